//! The contact problem of a step of a mechanism with a [`BodyStructure`], island by island:
//! the islands (connected components of the bodies linked by contacts and joints), the 2 × 2
//! blocks W_ij = w_iᵀ M⁻¹ w_j of each island's Delassus matrix, and the islands' solves by
//! moreau-lcp's planar frictional-contact solvers, in parallel.
//!
//! Contacts and joint groups are the island's links: link a < n_c is detected contact a, link
//! n_c + g is joint group g. An island's problem lists its contacts first (two rows each), then
//! its joint groups as bilateral groups of one or two rows, as moreau-lcp's layout asks.
//!
//! Islands are grouped into batches of consecutive islands; each batch owns its scratch and
//! its solver and solves its islands one after the other, so that the result of an island
//! depends on its own data only and is bit-identical for any number of threads.

mod batch;
mod solver;

use moreau_lcp::LcpError;
use moreau_lcp::fc2d::Fc2dRef;
use rayon::prelude::*;

pub(super) use self::batch::IslandFailure;
use self::batch::{Batch, Shared, worse};
pub(super) use self::solver::IslandSolver;
use crate::bodies::{BodyContact, NO_BODY};
use crate::stepper::StepError;
use crate::{LcpInfo, SolverChoice};

/// Contacts per batch above which a batch is closed: enough work that rayon's overhead does
/// not dominate a scene of many one-contact islands.
const BATCH_CONTACTS: usize = 256;

/// Links per chunk of the per-link work of one large island (force directions, right-hand
/// sides, block rows) run in parallel: enough work per rayon task that its overhead is small.
pub(super) const CHUNK_LINKS: usize = 512;

/// Links above which the per-link work runs in chunks on rayon's current pool: below it (and
/// on a pool of one thread) the tasks cost more than they save.
pub(super) const PARALLEL_LINKS: usize = 2048;

/// Whether `n` links' per-link work runs in chunks in parallel.
pub(super) fn in_parallel(n: usize) -> bool {
    n > PARALLEL_LINKS && rayon::current_num_threads() > 1
}

/// Runs `op` on consecutive chunks of [`CHUNK_LINKS`] items, each with the index of its first
/// item, in parallel when [`in_parallel`] says so, else on the whole slice at once. An item's
/// result must depend on its own data only, so that it is the same, bit for bit, either way.
pub(super) fn for_chunks<T: Send>(items: &mut [T], op: impl Fn(usize, &mut [T]) + Sync) {
    if in_parallel(items.len()) {
        items
            .par_chunks_mut(CHUNK_LINKS)
            .enumerate()
            .for_each(|(k, chunk)| op(k * CHUNK_LINKS, chunk));
    } else {
        op(0, items);
    }
}

/// Sets `v` to `n` copies of `value`, written in chunks in parallel when [`in_parallel`] says
/// so.
pub(super) fn fill<T: Clone + Send + Sync>(v: &mut Vec<T>, n: usize, value: T) {
    v.clear();
    if in_parallel(n) {
        v.par_extend(rayon::iter::repeat_n(value, n).with_min_len(CHUNK_LINKS));
    } else {
        v.resize(n, value);
    }
}

/// What the step knows of a detected contact besides its force directions: M⁻¹ w of each
/// side, the right-hand side b, γ_A, μ and the warm start.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct ContactWork {
    /// M_k⁻¹ w_N and M_k⁻¹ w_T restricted to the body of each side (zero for [`NO_BODY`]).
    pub(super) mw_n: [[f64; 3]; 2],
    pub(super) mw_t: [[f64; 3]; 2],
    /// b = (b_N, b_T) = W ᵀũ + ŵ + ε γ_A (docs/theory.md section 10).
    pub(super) b: [f64; 2],
    /// γ_N,A and γ_T,A.
    pub(super) gamma_a: [f64; 2],
    /// μ of the problem (the law's, 0 for a frictionless contact).
    pub(super) mu: f64,
    /// The impulses (P_N, P_T) found under the same identity in the step before, else zero.
    pub(super) warm: [f64; 2],
    /// The diagonal entry of W of the link's first row, w_Nᵀ M⁻¹ w_N of a contact (1/kg for
    /// bodies of mass properties in kg), which sets the units its island is solved in.
    pub(super) diagonal: f64,
}

/// One group of at most two consecutive bilateral rows on the same two bodies: a bilateral
/// group of the island's problem.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct JointGroup {
    /// The two bodies of the rows, [`NO_BODY`] for a side without coordinates.
    pub(super) bodies: [u32; 2],
    /// w_B of the group's first and second row restricted to each body (the second zero in a
    /// group of one row): `w[row][side]`.
    pub(super) w: [[[f64; 3]; 2]; 2],
    /// g_B and ŵ_B of each row (zero for a missing second row).
    pub(super) g: [f64; 2],
    pub(super) w_hat: [f64; 2],
    /// The number of rows, 1 or 2.
    pub(super) rows: usize,
}

/// Groups the bilateral rows: consecutive rows on the same two bodies two by two (a revolute
/// joint's rows together, a weld's three as two and one), any other row alone.
///
/// # Errors
/// [`StepError::NonFinite`] for a non-finite row, [`StepError::RedundantConstraints`] for a
/// row on no body with coordinates, whose constraint nothing can keep.
pub(super) fn group_rows(
    rows: &[crate::BodyBilateral],
    t: f64,
    out: &mut Vec<JointGroup>,
) -> Result<(), StepError> {
    out.clear();
    for (i, r) in rows.iter().enumerate() {
        let p = r.point;
        let finite = p.g.is_finite() && p.w_hat.is_finite();
        if !finite || r.w.iter().flatten().any(|v| !v.is_finite()) {
            return Err(StepError::NonFinite { what: "bilateral constraint", index: i, t });
        }
        if r.bodies == [NO_BODY; 2] {
            return Err(StepError::RedundantConstraints {
                t,
                reason: format!("row {i} acts on no body with coordinates"),
            });
        }
        match out.last_mut() {
            Some(g) if g.rows == 1 && g.bodies == r.bodies => {
                g.w[1] = r.w;
                g.g[1] = p.g;
                g.w_hat[1] = p.w_hat;
                g.rows = 2;
            }
            _ => out.push(JointGroup {
                bodies: r.bodies,
                w: [r.w, [[0.0; 3]; 2]],
                g: [p.g, 0.0],
                w_hat: [p.w_hat, 0.0],
                rows: 1,
            }),
        }
    }
    Ok(())
}

/// The bodies of link `a` (a contact when `a < contacts.len()`, else a joint group) and its two
/// rows' directions by side.
#[inline(always)]
pub(super) fn link<'a>(
    contacts: &'a [BodyContact],
    joints: &'a [JointGroup],
    a: usize,
) -> ([u32; 2], &'a [[f64; 3]; 2], &'a [[f64; 3]; 2]) {
    match contacts.get(a) {
        Some(c) => (c.bodies, &c.w_n, &c.w_t),
        None => {
            let g = &joints[a - contacts.len()];
            (g.bodies, &g.w[0], &g.w[1])
        }
    }
}

/// What the islands' problems are solved for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Purpose {
    /// The step's impulses. An island that the solvers leave above their tolerance is taken
    /// when its natural residual is at most `inexact` (see `StepperOptions::inexact_residual`).
    Step {
        /// The largest natural residual of an island taken inexact; 0 for none.
        inexact: f64,
    },
    /// The joints' correction after the step, the contacts that carried an impulse held.
    JointCorrection,
    /// The contacts' projection out of penetration (normal rows, frictionless).
    ContactProjection,
}

impl Purpose {
    /// The residual up to which an island is taken inexact.
    fn inexact(self) -> f64 {
        match self {
            Purpose::Step { inexact } => inexact,
            _ => 0.0,
        }
    }
}

/// The islands of a step and the batches that solve them.
#[derive(Default)]
pub(super) struct Islands {
    /// Union-find parent of each body.
    parent: Vec<u32>,
    /// The island of each root body, `u32::MAX` before it is numbered.
    label: Vec<u32>,
    /// The island of each link.
    island_of: Vec<u32>,
    /// The links by island (each island's contacts in detection order, then its joint groups)
    /// and each island's start.
    pub(super) order: Vec<u32>,
    pub(super) island_start: Vec<usize>,
    /// Each link's index within its island.
    local: Vec<u32>,
    /// The links acting on each body (link, side), by body.
    body_start: Vec<usize>,
    body_list: Vec<(u32, u8)>,
    batches: Vec<Batch>,
    n_batches: usize,
    /// The impulses (P_N, P_T) of each contact, in detection order.
    pub(super) r: Vec<[f64; 2]>,
    /// The impulses Λ_B of each joint group's rows (zero for a missing second row).
    pub(super) r_joints: Vec<[f64; 2]>,
    /// The number of rows of each joint group of the last split.
    joint_rows: Vec<usize>,
}

fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let p = parent[x as usize];
        parent[x as usize] = parent[p as usize];
        x = p;
    }
    x
}

impl Islands {
    /// Splits the contacts and joint groups into islands over `num_bodies` bodies: bodies
    /// linked by a contact or a joint belong to the same island, a side without coordinates
    /// links nothing. Islands are numbered by their first link (contacts first, then joint
    /// groups), each island's contacts kept in detection order and followed by its joint
    /// groups in row order.
    pub(super) fn split(
        &mut self,
        num_bodies: usize,
        contacts: &[BodyContact],
        joints: &[JointGroup],
    ) {
        let nc = contacts.len();
        let nl = nc + joints.len();
        let bodies_of = |a: usize| link(contacts, joints, a).0;
        self.parent.clear();
        self.parent.extend(0..num_bodies as u32);
        for l in 0..nl {
            let [a, b] = bodies_of(l);
            if a != NO_BODY && b != NO_BODY {
                let (ra, rb) = (find(&mut self.parent, a), find(&mut self.parent, b));
                // The smaller root wins, so that the forest does not depend on the order of
                // the unions' arguments.
                let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
                self.parent[hi as usize] = lo;
            }
        }
        self.label.clear();
        self.label.resize(num_bodies, u32::MAX);
        self.island_of.clear();
        let mut islands = 0u32;
        for l in 0..nl {
            let bodies = bodies_of(l);
            let body = if bodies[0] != NO_BODY { bodies[0] } else { bodies[1] };
            let island = if body == NO_BODY {
                // A link between two sides without coordinates is an island of its own.
                islands += 1;
                islands - 1
            } else {
                let root = find(&mut self.parent, body) as usize;
                if self.label[root] == u32::MAX {
                    self.label[root] = islands;
                    islands += 1;
                }
                self.label[root]
            };
            self.island_of.push(island);
        }
        // A counting sort by island keeps each island's contacts in detection order.
        let n_islands = islands as usize;
        self.island_start.clear();
        self.island_start.resize(n_islands + 1, 0);
        for &i in &self.island_of {
            self.island_start[i as usize + 1] += 1;
        }
        for i in 0..n_islands {
            self.island_start[i + 1] += self.island_start[i];
        }
        self.order.clear();
        self.order.resize(nl, 0);
        self.local.clear();
        self.local.resize(nl, 0);
        // `label` is reused as the next free position of each island.
        self.label.clear();
        self.label.extend(self.island_start[..n_islands].iter().map(|&s| s as u32));
        for (c, &i) in self.island_of.iter().enumerate() {
            let pos = self.label[i as usize];
            self.order[pos as usize] = c as u32;
            self.local[c] = pos - self.island_start[i as usize] as u32;
            self.label[i as usize] += 1;
        }
        // The links of each body.
        self.body_start.clear();
        self.body_start.resize(num_bodies + 1, 0);
        for l in 0..nl {
            for &k in &bodies_of(l) {
                if k != NO_BODY {
                    self.body_start[k as usize + 1] += 1;
                }
            }
        }
        for k in 0..num_bodies {
            self.body_start[k + 1] += self.body_start[k];
        }
        self.body_list.clear();
        self.body_list.resize(self.body_start[num_bodies], (0, 0));
        self.parent.clear();
        self.parent.extend(self.body_start[..num_bodies].iter().map(|&s| s as u32));
        for a in 0..nl {
            for (side, &k) in bodies_of(a).iter().enumerate() {
                if k != NO_BODY {
                    let pos = &mut self.parent[k as usize];
                    self.body_list[*pos as usize] = (a as u32, side as u8);
                    *pos += 1;
                }
            }
        }
        self.r.clear();
        self.r.resize(nc, [0.0; 2]);
        self.r_joints.clear();
        self.r_joints.resize(joints.len(), [0.0; 2]);
        self.joint_rows.clear();
        self.joint_rows.extend(joints.iter().map(|g| g.rows));
    }

    /// The links acting on body `k` in the last split, as (link, side), in link order.
    pub(super) fn links_of(&self, k: usize) -> &[(u32, u8)] {
        &self.body_list[self.body_start[k]..self.body_start[k + 1]]
    }

    /// The number of islands of the last split.
    pub(super) fn count(&self) -> usize {
        self.island_start.len().saturating_sub(1)
    }

    /// Groups the islands into batches and assembles every island's problem (in parallel
    /// when there are several batches); `work` holds the contacts' then the joint groups'.
    pub(super) fn assemble(
        &mut self,
        contacts: &[BodyContact],
        joints: &[JointGroup],
        work: &[ContactWork],
        choice: &SolverChoice,
    ) -> Result<(), LcpError> {
        let n_islands = self.count();
        self.n_batches = 0;
        let mut island = 0;
        while island < n_islands {
            let start = island;
            while island < n_islands
                && self.island_start[island] - self.island_start[start] < BATCH_CONTACTS
            {
                island += 1;
            }
            if self.n_batches == self.batches.len() {
                self.batches.push(Batch::new(choice)?);
            }
            let batch = &mut self.batches[self.n_batches];
            batch.islands = start..island;
            batch.links = self.island_start[start]..self.island_start[island];
            self.n_batches += 1;
        }
        let shared = Shared {
            contacts,
            joints,
            work,
            order: &self.order,
            island_start: &self.island_start,
            local: &self.local,
            body_start: &self.body_start,
            body_list: &self.body_list,
        };
        let batches = &mut self.batches[..self.n_batches];
        if batches.len() > 1 {
            batches.par_iter_mut().for_each(|b| b.assemble(&shared));
        } else {
            batches.iter_mut().for_each(|b| b.assemble(&shared));
        }
        Ok(())
    }

    /// The problems of the last assembled islands that needed a solve, batch by batch in
    /// island order.
    pub(super) fn problems(&self) -> impl Iterator<Item = Fc2dRef<'_>> {
        self.batches[..self.n_batches].iter().flat_map(Batch::problems)
    }

    /// Solves every island (the batches in parallel) for `purpose`, writes the impulses into
    /// `r` and `r_joints` and returns the worst island's information (`None` when no island
    /// needed a solve).
    pub(super) fn solve(&mut self, purpose: Purpose) -> Result<Option<LcpInfo>, IslandFailure> {
        let batches = &mut self.batches[..self.n_batches];
        if batches.len() > 1 {
            batches.par_iter_mut().for_each(|b| b.solve(purpose));
        } else {
            batches.iter_mut().for_each(|b| b.solve(purpose));
        }
        let nc = self.r.len();
        let mut info = None;
        for b in &mut self.batches[..self.n_batches] {
            if let Some(f) = b.failure.take() {
                return Err(f);
            }
            let mut row = 0;
            for pos in b.links.clone() {
                let a = self.order[pos] as usize;
                if a < nc {
                    self.r[a] = [b.r[row], b.r[row + 1]];
                    row += 2;
                } else {
                    let g = a - nc;
                    let rows = self.joint_rows[g];
                    self.r_joints[g] = [b.r[row], if rows == 2 { b.r[row + 1] } else { 0.0 }];
                    row += rows;
                }
            }
            if let Some(i) = b.info {
                info = Some(worse(info, i));
            }
        }
        Ok(info)
    }
}
