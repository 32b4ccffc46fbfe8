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

use std::ops::Range;

use moreau_lcp::fc2d::{
    Fc2d, Fc2dAuto, Fc2dAutoOptions, Fc2dParts, Fc2dRef, Fc2dSolution, Fc2dSolver, LcpRoute,
    LcpRouteOptions, LcpRouteSolver, Newton, NewtonOptions, Nsgs, NsgsOptions, Proximal,
    ProximalOptions,
};
use moreau_lcp::{LcpError, Status};
use rayon::prelude::*;

use super::FC2D_TOLERANCE;
use crate::bodies::{BodyContact, NO_BODY};
use crate::stepper::StepError;
use crate::{LcpInfo, SolverChoice};

/// Contacts per batch above which a batch is closed: enough work that rayon's overhead does
/// not dominate a scene of many one-contact islands.
const BATCH_CONTACTS: usize = 256;

/// What the step knows of a detected contact besides its force directions: M⁻¹ w of each
/// side, the right-hand side b, γ_A, μ and the warm start.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct ContactWork {
    /// M_k⁻¹ w_N and M_k⁻¹ w_T restricted to the body of each side (zero for [`NO_BODY`]).
    pub(super) mw_n: [[f64; 3]; 2],
    pub(super) mw_t: [[f64; 3]; 2],
    /// b = (b_N, b_T) = W ᵀũ + ŵ + ε γ_A (docs/theory.md section 7).
    pub(super) b: [f64; 2],
    /// γ_N,A and γ_T,A.
    pub(super) gamma_a: [f64; 2],
    /// μ of the problem (the law's, 0 for a frictionless contact).
    pub(super) mu: f64,
    /// The impulses (P_N, P_T) found under the same identity in the step before, else zero.
    pub(super) warm: [f64; 2],
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

/// Islands of at most this many contacts are small: the default choice solves them with
/// unrelaxed Gauss-Seidel (whose exact local solution answers a one-contact island in one
/// sweep) to [`SMALL_TOLERANCE`], and by pivoting if that stalls.
const SMALL_ISLAND: usize = 8;

/// The Gauss-Seidel sweeps (cluster solves included) that the default choice gives a large
/// island before nonsmooth Newton takes over.
const LARGE_ISLAND_SWEEPS: usize = 5_000;

/// The Gauss-Seidel sweeps that follow each accepted Newton step of a large island: the step
/// carries the long-range correction, the sweeps settle the contacts whose case (stick or
/// slip, open or closed) it guessed wrong. On the settling disk column (N = 1000, islands
/// of 388 and 631 contacts) cold Newton with them needs 23 and 31 iterations to 1e-10.
const NEWTON_SMOOTHING_SWEEPS: usize = 20;

/// The past merits that the line search of a large island's Newton compares with: the
/// monotone rule stalls near 5e-5 on the settling column, where contacts at the boundary
/// of two cases flip from one iteration to the next.
const NEWTON_NONMONOTONE: usize = 10;

/// The Newton iterations the default choice gives a large island before the proximal
/// point method takes over: Newton either converges in a few dozen or cycles.
const NEWTON_ITERATIONS: usize = 50;

/// The largest island the default choice hands to pivoting (a dense solve of 3 n_c rows)
/// when Gauss-Seidel and Newton leave it unsolved.
const PIVOTING_ISLAND: usize = 300;

/// The natural-map tolerance of small islands, where it costs a few sweeps more.
const SMALL_TOLERANCE: f64 = 1e-13;

/// The solver of the islands' problems, from the stepper's [`SolverChoice`].
enum IslandSolver {
    /// The default choice: one `Fc2dAuto` for small islands and one for large ones, then,
    /// for the large islands that Gauss-Seidel and its cluster solves leave unsolved,
    /// nonsmooth Newton, the proximal point method, Gauss-Seidel resumed with the full
    /// budget from the proximal iterate, and pivoting.
    Auto(Box<([Fc2dAuto; 3], [Newton; 2], Proximal, LcpRoute)>),
    Nsgs(Nsgs),
    Lcp(LcpRoute),
}

impl IslandSolver {
    fn new(choice: &SolverChoice) -> Result<Self, LcpError> {
        Ok(match *choice {
            SolverChoice::Auto => Self::Auto(Box::new((
                [
                    Fc2dAuto::new(Fc2dAutoOptions {
                        tolerance: SMALL_TOLERANCE,
                        omega: 1.0,
                        ..Fc2dAutoOptions::default()
                    })?,
                    Fc2dAuto::new(Fc2dAutoOptions {
                        tolerance: FC2D_TOLERANCE,
                        max_sweeps: LARGE_ISLAND_SWEEPS,
                        ..Fc2dAutoOptions::default()
                    })?,
                    Fc2dAuto::new(Fc2dAutoOptions {
                        tolerance: FC2D_TOLERANCE,
                        ..Fc2dAutoOptions::default()
                    })?,
                ],
                {
                    let newton = |tolerance| {
                        Newton::new(NewtonOptions {
                            tolerance,
                            max_iterations: NEWTON_ITERATIONS,
                            smoothing_sweeps: NEWTON_SMOOTHING_SWEEPS,
                            nonmonotone: NEWTON_NONMONOTONE,
                            ..NewtonOptions::default()
                        })
                    };
                    [newton(FC2D_TOLERANCE)?, newton(SMALL_TOLERANCE)?]
                },
                Proximal::new(ProximalOptions {
                    tolerance: FC2D_TOLERANCE,
                    smoothing_sweeps: NEWTON_SMOOTHING_SWEEPS,
                    ..ProximalOptions::default()
                })?,
                LcpRoute::new(LcpRouteOptions {
                    tolerance: FC2D_TOLERANCE,
                    max_contacts: PIVOTING_ISLAND,
                    ..LcpRouteOptions::default()
                })?,
            ))),
            SolverChoice::Pgs { tolerance, omega, max_iterations } => {
                Self::Nsgs(Nsgs::new(NsgsOptions {
                    tolerance,
                    omega,
                    max_sweeps: max_iterations,
                    ..NsgsOptions::default()
                })?)
            }
            SolverChoice::Lemke | SolverChoice::Enumeration => {
                let solver = if matches!(choice, SolverChoice::Lemke) {
                    LcpRouteSolver::Lemke
                } else {
                    LcpRouteSolver::Enumeration
                };
                Self::Lcp(LcpRoute::new(LcpRouteOptions {
                    tolerance: FC2D_TOLERANCE,
                    solver,
                    ..LcpRouteOptions::default()
                })?)
            }
        })
    }

    /// Solves `problem` from `warm`; with `newton_first`, the default choice starts an island
    /// with joint groups by Newton.
    fn solve(
        &mut self,
        problem: Fc2dRef<'_>,
        warm: &[f64],
        newton_first: bool,
        out: &mut Fc2dSolution,
    ) -> Result<(), LcpError> {
        match self {
            Self::Auto(s) => {
                let (auto, [newton, joints], proximal, lcp) = &mut **s;
                if newton_first && problem.n_groups() > problem.n_contacts() {
                    // Joints couple their bodies stiffly (a chain's rows form a path whose W
                    // has a condition number growing as the square of its length), where
                    // Gauss-Seidel crawls; Newton solves the joints' rows exactly once it has
                    // the contacts' cases, and from the step before's impulses it usually has
                    // them. A cold start in a hyperstatic pile (the contact projection's) is
                    // better left to Gauss-Seidel, where Newton cycles. Its tolerance is that of
                    // small islands: the joints' correction asks for their drift to round-off.
                    joints.solve_into(problem, Some(warm), out)?;
                    if out.is_solved() {
                        return Ok(());
                    }
                }
                let k = usize::from(problem.n_groups() > SMALL_ISLAND);
                auto[k].solve_into(problem, Some(warm), out)?;
                if !out.is_solved() && k == 1 {
                    // Dense packings make W singular and their reactions indeterminate, where
                    // Gauss-Seidel can crawl; Newton's regularised steps, started cold and
                    // each followed by a few sweeps, then usually solve the island. Where
                    // Newton cycles between the cases of contacts at the boundary of two,
                    // the proximal point method's positive definite sub-problems do not;
                    // pivoting is the last resort of islands small enough for it.
                    newton.solve_into(problem, None, out)?;
                    if !out.is_solved() {
                        proximal.solve_into(problem, None, out)?;
                    }
                    if !out.is_solved() {
                        // The proximal iterate is close (1e-6 on an island of 986 contacts of
                        // the settling column, which Gauss-Seidel alone finishes in 37,800
                        // sweeps): Gauss-Seidel with the full budget finishes from it.
                        let start = std::mem::take(&mut out.r);
                        auto[2].solve_into(problem, Some(&start), out)?;
                    }
                    if !out.is_solved() && problem.n_groups() <= PIVOTING_ISLAND {
                        lcp.solve_into(problem, None, out)?;
                    }
                }
                Ok(())
            }
            Self::Nsgs(s) => s.solve_into(problem, Some(warm), out),
            Self::Lcp(s) => s.solve_into(problem, None, out),
        }
    }
}

/// Where one island's problem lies in its batch's buffers.
#[derive(Clone, Copy, Debug, Default)]
struct Slot {
    /// First contact of the island among the batch's contacts (the offset into `mu`).
    c_off: usize,
    /// Number of contacts.
    n: usize,
    /// Number of groups: contacts, then joint groups.
    groups: usize,
    /// First row of the island in the batch's rows (q, the warm start and r).
    row_off: usize,
    /// Number of rows.
    rows: usize,
    /// First entry of the island's row pointers in the batch's `row_ptr`, and of its group
    /// starts in `group_start`.
    rp_off: usize,
    /// Whether some b_N < 0 or a joint group is present, so that the island needs a solve.
    solve: bool,
}

/// A batch's concatenated island problems, borrowed apart from its solver.
#[derive(Clone, Copy)]
struct Buffers<'a> {
    block_off: &'a [usize],
    group_start: &'a [usize],
    row_ptr: &'a [usize],
    col: &'a [u32],
    blocks: &'a [[f64; 4]],
    q: &'a [f64],
    mu: &'a [f64],
}

impl<'a> Buffers<'a> {
    /// The problem of island `j` of the batch, at `slot`.
    fn problem(&self, j: usize, slot: &Slot) -> Result<Fc2dRef<'a>, LcpError> {
        let (c, n, groups) = (slot.c_off, slot.n, slot.groups);
        let b0 = self.block_off[j];
        let b1 = b0 + self.row_ptr[slot.rp_off + groups];
        let groups_of = slot.rp_off..slot.rp_off + groups + 1;
        Fc2dRef::from_parts(Fc2dParts {
            n_contacts: n,
            group_start: &self.group_start[groups_of.clone()],
            row_ptr: &self.row_ptr[groups_of],
            col: &self.col[b0..b1],
            blocks: &self.blocks[b0..b1],
            q: &self.q[slot.row_off..slot.row_off + slot.rows],
            mu: &self.mu[c..c + n],
        })
    }
}

/// Why an island's solve failed.
pub(super) enum IslandFailure {
    /// The problem or the warm start was refused, or the solver's options.
    Input(LcpError),
    /// The solver ended without a solution; the island's problem is kept to reproduce it.
    Status(Status, Box<Fc2d>),
}

/// A run of consecutive islands with its scratch and solver.
struct Batch {
    /// The islands of the batch.
    islands: Range<usize>,
    /// The links of the batch, a range of the step's island order.
    links: Range<usize>,
    slots: Vec<Slot>,
    /// The islands' problems, concatenated: group starts and row pointers relative to each
    /// island's first row and block, columns local to the island, blocks, q, μ and the warm
    /// start.
    group_start: Vec<usize>,
    row_ptr: Vec<usize>,
    col: Vec<u32>,
    blocks: Vec<[f64; 4]>,
    q: Vec<f64>,
    mu: Vec<f64>,
    warm: Vec<f64>,
    /// First block of each island in `blocks`.
    block_off: Vec<usize>,
    /// The (column, block) entries of one block row before they are sorted and merged.
    row: Vec<(u32, [f64; 4])>,
    solver: IslandSolver,
    solution: Fc2dSolution,
    /// The impulses of the batch's rows, in the batch's order: (P_N, P_T) of each contact,
    /// Λ_B of each joint row.
    r: Vec<f64>,
    /// Scratch of the LCP residual.
    sums: Vec<[f64; 4]>,
    /// The worst island's information, and the first failure.
    info: Option<LcpInfo>,
    failure: Option<IslandFailure>,
}

/// The read-only data of a step that the batches share.
struct Shared<'a> {
    contacts: &'a [BodyContact],
    joints: &'a [JointGroup],
    /// The work of each link: contacts, then joint groups.
    work: &'a [ContactWork],
    order: &'a [u32],
    island_start: &'a [usize],
    local: &'a [u32],
    body_start: &'a [usize],
    body_list: &'a [(u32, u8)],
}

impl Shared<'_> {
    /// The bodies of link `a` and its two rows' directions by side (w_N and w_T of a
    /// contact, the rows of a joint group).
    #[inline(always)]
    fn link(&self, a: usize) -> ([u32; 2], &[[f64; 3]; 2], &[[f64; 3]; 2]) {
        link(self.contacts, self.joints, a)
    }

    /// The number of rows of link `a`.
    #[inline(always)]
    fn rows(&self, a: usize) -> usize {
        let nc = self.contacts.len();
        if a < nc { 2 } else { self.joints[a - nc].rows }
    }
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

impl Batch {
    fn new(choice: &SolverChoice) -> Result<Self, LcpError> {
        Ok(Batch {
            islands: 0..0,
            links: 0..0,
            slots: Vec::new(),
            group_start: Vec::new(),
            row_ptr: Vec::new(),
            col: Vec::new(),
            blocks: Vec::new(),
            q: Vec::new(),
            mu: Vec::new(),
            warm: Vec::new(),
            block_off: Vec::new(),
            row: Vec::new(),
            solver: IslandSolver::new(choice)?,
            solution: Fc2dSolution::new(),
            r: Vec::new(),
            sums: Vec::new(),
            info: None,
            failure: None,
        })
    }

    /// Assembles the problem of every island of the batch: W_ij = Σ_k w_i,kᵀ M_k⁻¹ w_j,k
    /// over the bodies k that links i and j share, q = b, μ and the warm start.
    fn assemble(&mut self, s: &Shared<'_>) {
        self.slots.clear();
        self.group_start.clear();
        self.row_ptr.clear();
        self.col.clear();
        self.blocks.clear();
        self.block_off.clear();
        self.q.clear();
        self.mu.clear();
        self.warm.clear();
        let nc = s.contacts.len();
        for island in self.islands.clone() {
            let range = s.island_start[island]..s.island_start[island + 1];
            let mut slot = Slot {
                c_off: self.mu.len(),
                n: 0,
                groups: range.len(),
                row_off: self.q.len(),
                rows: 0,
                rp_off: self.row_ptr.len(),
                solve: false,
            };
            for k in range.clone() {
                let a = s.order[k] as usize;
                slot.n += usize::from(a < nc);
                slot.solve |= a >= nc || s.work[a].b[0] < 0.0;
            }
            let b0 = self.blocks.len();
            self.block_off.push(b0);
            self.row_ptr.push(0);
            self.group_start.push(0);
            for k in range {
                let a = s.order[k] as usize;
                let w = &s.work[a];
                let rows = s.rows(a);
                self.q.extend_from_slice(&w.b[..rows]);
                self.warm.extend_from_slice(&w.warm[..rows]);
                if a < nc {
                    self.mu.push(w.mu);
                }
                slot.rows += rows;
                if slot.solve {
                    self.block_row(s, a);
                } else {
                    // An island without a solve needs no blocks: its impulses are zero.
                    self.col.push((k - s.island_start[island]) as u32);
                    self.blocks.push([0.0; 4]);
                }
                self.row_ptr.push(self.blocks.len() - b0);
                self.group_start.push(slot.rows);
            }
            self.slots.push(slot);
        }
    }

    /// Appends the block row of link `a`: its blocks with every link sharing a body, by
    /// increasing local column, the contributions of two shared bodies added up. A joint
    /// group of one row has a zero second row and zero M⁻¹ of it, so its blocks' padding is
    /// zero as the problem's layout asks.
    fn block_row(&mut self, s: &Shared<'_>, a: usize) {
        let (bodies, w_0, w_1) = s.link(a);
        self.row.clear();
        for side in 0..2 {
            let k = bodies[side];
            if k == NO_BODY {
                continue;
            }
            let (wn, wt) = (&w_0[side], &w_1[side]);
            let k = k as usize;
            for &(c, sc) in &s.body_list[s.body_start[k]..s.body_start[k + 1]] {
                let wc = &s.work[c as usize];
                let (yn, yt) = (&wc.mw_n[sc as usize], &wc.mw_t[sc as usize]);
                self.row.push((
                    s.local[c as usize],
                    [dot3(wn, yn), dot3(wn, yt), dot3(wt, yn), dot3(wt, yt)],
                ));
            }
        }
        self.row.sort_unstable_by_key(|e| e.0);
        let mut last = u32::MAX;
        for &(c, b) in &self.row {
            if c == last {
                let dst = self.blocks.last_mut().expect("a block of this column was pushed");
                for (d, v) in dst.iter_mut().zip(b) {
                    *d += v;
                }
            } else {
                self.col.push(c);
                self.blocks.push(b);
                last = c;
            }
        }
    }

    /// The batch's buffers, borrowed apart from its solver.
    fn buffers(&self) -> Buffers<'_> {
        Buffers {
            block_off: &self.block_off,
            group_start: &self.group_start,
            row_ptr: &self.row_ptr,
            col: &self.col,
            blocks: &self.blocks,
            q: &self.q,
            mu: &self.mu,
        }
    }

    /// Solves the batch's islands in turn; the impulses go to `r`, the worst island's
    /// information to `info`, the first failure to `failure` (and the batch stops there).
    fn solve(&mut self, newton_first: bool) {
        self.info = None;
        self.failure = None;
        self.r.clear();
        self.r.resize(self.q.len(), 0.0);
        for (j, slot) in self.slots.iter().enumerate() {
            if !slot.solve {
                continue;
            }
            let rows = slot.row_off..slot.row_off + slot.rows;
            let buffers = Buffers {
                block_off: &self.block_off,
                group_start: &self.group_start,
                row_ptr: &self.row_ptr,
                col: &self.col,
                blocks: &self.blocks,
                q: &self.q,
                mu: &self.mu,
            };
            let problem = match buffers.problem(j, slot) {
                Ok(p) => p,
                Err(e) => {
                    self.failure = Some(IslandFailure::Input(e));
                    return;
                }
            };
            let warm = &self.warm[rows.clone()];
            if let Err(e) = self.solver.solve(problem, warm, newton_first, &mut self.solution) {
                self.failure = Some(IslandFailure::Input(e));
                return;
            }
            let out = &self.solution;
            if out.status != Status::Solved {
                self.failure =
                    Some(IslandFailure::Status(out.status, Box::new(problem.to_owned())));
                return;
            }
            self.r[rows].copy_from_slice(&out.r);
            let residual = lcp_residual(problem, &out.r, &mut self.sums);
            let info = LcpInfo {
                method: out.method,
                status: Status::Solved,
                iterations: out.iterations,
                residual,
            };
            self.info = Some(worse(self.info, info));
        }
    }
}

#[inline(always)]
fn dot3(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The worse of two islands' information: the largest iteration count, and the method and
/// residual of the island of largest residual.
fn worse(a: Option<LcpInfo>, b: LcpInfo) -> LcpInfo {
    match a {
        None => b,
        Some(a) => {
            let (m, r) = if b.residual > a.residual {
                (b.method, b.residual)
            } else {
                (a.method, a.residual)
            };
            LcpInfo {
                method: m,
                status: Status::Solved,
                iterations: a.iterations.max(b.iterations),
                residual: r,
            }
        }
    }
}

/// `moreau_lcp::Residual::relative` of the LCP of eq. 7.41 in z = (P_N; P_R; ξ_L) that an
/// island's frictional-contact solution r stands for, evaluated on the island's blocks: the
/// residual the dense path reports for the same step problem. As there, w = A z + b is
/// recomputed in the LCP's own terms, and ξ_L = max(0, −u_T) from the u_T so recomputed;
/// `sums` is scratch (Σ|A z| and A z + b of the rows N and R of each contact, then of each
/// bilateral row). The joint impulses Λ_B enter the contacts' rows as the given terms they
/// are on the dense path, and each bilateral row adds its equation W_B r + q_B = 0 as a row
/// with w = 0, whose violation |u_B| counts against the row's scale.
fn lcp_residual(problem: Fc2dRef<'_>, r: &[f64], sums: &mut Vec<[f64; 4]>) -> f64 {
    let parts = problem.parts();
    let n = parts.n_contacts;
    let (mu, q, gs) = (parts.mu, parts.q, parts.group_start);
    let groups = gs.len() - 1;
    // Rows N and R without ξ_L: the column of P_N,j carries W_·N − μ_j W_·T, that of
    // P_R,j = P_T,j + μ_j P_N,j carries W_·T, that of a bilateral group its rows' W_·B.
    sums.clear();
    for i in 0..groups {
        let (mut abs_0, mut abs_1) = (0.0, 0.0);
        let (mut sum_0, mut sum_1) =
            (q[gs[i]], if gs[i + 1] - gs[i] == 2 { q[gs[i] + 1] } else { 0.0 });
        let blocks = parts.row_ptr[i]..parts.row_ptr[i + 1];
        for (b, &j) in parts.blocks[blocks.clone()].iter().zip(&parts.col[blocks]) {
            let j = j as usize;
            let terms = if j < n {
                let (p_n, m) = (r[2 * j], mu[j]);
                let p_r = r[2 * j + 1] + m * p_n;
                [(b[0] - m * b[1]) * p_n, b[1] * p_r, (b[2] - m * b[3]) * p_n, b[3] * p_r]
            } else {
                let r_0 = r[gs[j]];
                let r_1 = if gs[j + 1] - gs[j] == 2 { r[gs[j] + 1] } else { 0.0 };
                [b[0] * r_0, b[1] * r_1, b[2] * r_0, b[3] * r_1]
            };
            for t in &terms[..2] {
                sum_0 += t;
                abs_0 += t.abs();
            }
            for t in &terms[2..] {
                sum_1 += t;
                abs_1 += t.abs();
            }
        }
        sums.push([sum_0, abs_0, sum_1, abs_1]);
    }
    let z = |i: usize| {
        let p_n = r[2 * i];
        [p_n, r[2 * i + 1] + mu[i] * p_n, (-sums[i][2]).max(0.0)]
    };
    let mut rows = moreau_lcp::ResidualRows::new((0..n).flat_map(z));
    for i in 0..n {
        let [p_n, p_r, xi_l] = z(i);
        let [sum_n, abs_n, sum_r, abs_r] = sums[i];
        rows.row(q[2 * i], p_n, sum_n, abs_n, sum_n);
        let w_r = sum_r + xi_l;
        rows.row(q[2 * i + 1], p_r, w_r, abs_r + xi_l, w_r);
        let (a, b) = (2.0 * mu[i] * p_n, -p_r);
        rows.row(0.0, xi_l, a + b, a.abs() + b.abs(), a + b);
    }
    for g in n..groups {
        let [sum_0, abs_0, sum_1, abs_1] = sums[g];
        rows.row(q[gs[g]], 0.0, 0.0, abs_0, sum_0);
        if gs[g + 1] - gs[g] == 2 {
            rows.row(q[gs[g] + 1], 0.0, 0.0, abs_1, sum_1);
        }
    }
    rows.finish().relative
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
        self.batches[..self.n_batches].iter().flat_map(move |b| {
            let buffers = b.buffers();
            b.slots
                .iter()
                .enumerate()
                .filter(|(_, slot)| slot.solve)
                .filter_map(move |(j, slot)| buffers.problem(j, slot).ok())
        })
    }

    /// Solves every island (the batches in parallel), writes the impulses into `r` and
    /// `r_joints` and returns the worst island's information (`None` when no island needed a
    /// solve). With `newton_first`, the default choice starts the islands with joints by
    /// Newton (a step's problem, warm-started, or the joints' correction, linear).
    pub(super) fn solve(&mut self, newton_first: bool) -> Result<Option<LcpInfo>, IslandFailure> {
        let batches = &mut self.batches[..self.n_batches];
        if batches.len() > 1 {
            batches.par_iter_mut().for_each(|b| b.solve(newton_first));
        } else {
            batches.iter_mut().for_each(|b| b.solve(newton_first));
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
