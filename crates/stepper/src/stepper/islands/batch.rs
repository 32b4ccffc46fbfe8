//! The batches of islands: each island's problem assembled into a batch's buffers (the 2 × 2
//! blocks of its Delassus matrix, q, μ and the warm start), solved, and measured by the LCP
//! residual the dense path reports.

use std::ops::Range;

use moreau_lcp::fc2d::{Fc2d, Fc2dParts, Fc2dRef, Fc2dSolution};
use moreau_lcp::{LcpError, ResidualRows, Status};

use super::solver::IslandSolver;
use rayon::prelude::*;

use super::{CHUNK_LINKS, ContactWork, JointGroup, Purpose, fill, for_chunks, in_parallel, link};
use crate::LcpInfo;
use crate::SolverChoice;
use crate::bodies::{BodyContact, NO_BODY};

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
    /// The power of two c by which W is multiplied and the impulses divided for the solve
    /// ([`units`]); 1 when the island is solved as assembled.
    scale: f64,
}

/// The largest |log₂| of the island's smallest normal diagonal entry of W for which it is
/// solved as assembled: about bodies of 1/16 to 16 kg (in the units of their declaration).
const UNSCALED_EXPONENT: f64 = 4.0;

/// The power of two c for an island whose smallest diagonal entry of W on a contact's normal
/// row (or a joint group's first row) is `smallest`: 2^−e with e the exponent nearest log₂
/// of it, or 1 when |e| ≤ [`UNSCALED_EXPONENT`] (or the entry is not positive and finite).
///
/// The solvers accept an iterate by the natural residual, which adds impulses and velocities
/// (moreau-lcp's `Fc2dResidual`) against an absolute tolerance. On bodies much heavier than
/// their unit of mass the impulses are orders of magnitude above the velocities, and their
/// round-off alone exceeds the tolerance: a box of 5,000 t tumbling onto a floor stopped on
/// an island of one contact at the iteration limit. Solving c W r̃ + q = u for r̃ = r / c
/// brings the impulses of the island's heaviest body (smallest entry) to the velocities'
/// magnitude, and those of lighter bodies below it. Scaled by its lightest body instead
/// (largest entry 117, c = 1/128), an island of 6 contacts of a pile of boxes, a capsule and
/// a disk of 0.03 to 0.24 kg, which pivoting solves to 8e-17 as assembled, could not be
/// solved to 1e-13 any more.
/// The factor is a power of two, so that c W r̃ is W r to the bit and the solution comes
/// back exactly as r = c r̃; the iterates are those of the problem as assembled, scaled, and
/// only the point where the solver accepts one depends on the units.
fn units(smallest: f64) -> f64 {
    if !(smallest > 0.0 && smallest.is_finite()) {
        return 1.0;
    }
    let e = smallest.log2().round();
    if e.abs() <= UNSCALED_EXPONENT { 1.0 } else { (-e).exp2() }
}

/// A batch's island problems, concatenated: group starts and row pointers relative to each
/// island's first row and block, columns local to the island, blocks, q, μ and the warm start.
#[derive(Default)]
struct Problems {
    slots: Vec<Slot>,
    group_start: Vec<usize>,
    row_ptr: Vec<usize>,
    col: Vec<u32>,
    blocks: Vec<[f64; 4]>,
    q: Vec<f64>,
    mu: Vec<f64>,
    warm: Vec<f64>,
    /// First block of each island in `blocks`.
    block_off: Vec<usize>,
}

impl Problems {
    fn clear(&mut self) {
        self.slots.clear();
        self.group_start.clear();
        self.row_ptr.clear();
        self.col.clear();
        self.blocks.clear();
        self.q.clear();
        self.mu.clear();
        self.warm.clear();
        self.block_off.clear();
    }

    /// The problem of island `j` of the batch.
    fn problem(&self, j: usize) -> Result<Fc2dRef<'_>, LcpError> {
        let slot = &self.slots[j];
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
pub(in crate::stepper) enum IslandFailure {
    /// The problem or the warm start was refused, or the solver's options.
    Input(LcpError),
    /// The solver ended without a solution; the island's problem is kept to reproduce it.
    Status(Status, Box<Fc2d>),
}

/// A run of consecutive islands with its scratch and solver.
pub(super) struct Batch {
    /// The islands of the batch.
    pub(super) islands: Range<usize>,
    /// The links of the batch, a range of the step's island order.
    pub(super) links: Range<usize>,
    /// The islands' problems.
    problems: Problems,
    solver: IslandSolver,
    solution: Fc2dSolution,
    /// The impulses of the batch's rows, in the batch's order: (P_N, P_T) of each contact,
    /// Λ_B of each joint row.
    pub(super) r: Vec<f64>,
    /// Scratch of the LCP residual.
    sums: Vec<[f64; 4]>,
    /// c W and the warm start divided by c of an island solved in its own units ([`units`]).
    scaled_blocks: Vec<[f64; 4]>,
    scaled_warm: Vec<f64>,
    /// The worst island's information, and the first failure.
    pub(super) info: Option<LcpInfo>,
    pub(super) failure: Option<IslandFailure>,
}

/// The read-only data of a step that the batches share.
pub(super) struct Shared<'a> {
    pub(super) contacts: &'a [BodyContact],
    pub(super) joints: &'a [JointGroup],
    /// The work of each link: contacts, then joint groups.
    pub(super) work: &'a [ContactWork],
    pub(super) order: &'a [u32],
    pub(super) island_start: &'a [usize],
    pub(super) local: &'a [u32],
    pub(super) body_start: &'a [usize],
    pub(super) body_list: &'a [(u32, u8)],
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

impl Batch {
    pub(super) fn new(choice: &SolverChoice) -> Result<Self, LcpError> {
        Ok(Batch {
            islands: 0..0,
            links: 0..0,
            problems: Problems::default(),
            solver: IslandSolver::new(choice)?,
            solution: Fc2dSolution::new(),
            r: Vec::new(),
            sums: Vec::new(),
            scaled_blocks: Vec::new(),
            scaled_warm: Vec::new(),
            info: None,
            failure: None,
        })
    }

    /// Assembles the problem of every island of the batch: W_ij = Σ_k w_i,kᵀ M_k⁻¹ w_j,k
    /// over the bodies k that links i and j share, q = b, μ and the warm start.
    pub(super) fn assemble(&mut self, s: &Shared<'_>) {
        let p = &mut self.problems;
        p.clear();
        let nc = s.contacts.len();
        for island in self.islands.clone() {
            let range = s.island_start[island]..s.island_start[island + 1];
            let mut slot = Slot {
                c_off: p.mu.len(),
                n: 0,
                groups: range.len(),
                row_off: p.q.len(),
                rows: 0,
                rp_off: p.row_ptr.len(),
                solve: false,
                scale: 1.0,
            };
            let mut smallest = f64::INFINITY;
            for k in range.clone() {
                let a = s.order[k] as usize;
                slot.n += usize::from(a < nc);
                slot.solve |= a >= nc || s.work[a].b[0] < 0.0;
                smallest = smallest.min(s.work[a].diagonal);
            }
            slot.scale = units(smallest);
            let b0 = p.blocks.len();
            p.block_off.push(b0);
            p.row_ptr.push(0);
            p.group_start.push(0);
            for k in range.clone() {
                let a = s.order[k] as usize;
                let w = &s.work[a];
                let rows = s.rows(a);
                p.q.extend_from_slice(&w.b[..rows]);
                p.warm.extend_from_slice(&w.warm[..rows]);
                if a < nc {
                    p.mu.push(w.mu);
                }
                slot.rows += rows;
                p.group_start.push(slot.rows);
            }
            if !slot.solve {
                // An island without a solve needs no blocks: its impulses are zero.
                for k in range.clone() {
                    p.col.push((k - range.start) as u32);
                    p.blocks.push([0.0; 4]);
                    p.row_ptr.push(p.blocks.len() - b0);
                }
            } else if in_parallel(range.len()) {
                // A large island: each block row's length first (the links of its bodies
                // counted once), then the rows written in parallel straight into their places.
                let first_row = p.row_ptr.len();
                let order = &s.order[range];
                p.row_ptr.par_extend(
                    order.par_iter().with_min_len(CHUNK_LINKS).map(|&a| row_len(s, a as usize)),
                );
                let start = p.blocks.len() - b0;
                let mut end = start;
                for e in &mut p.row_ptr[first_row..] {
                    end += *e;
                    *e = end;
                }
                let first = p.blocks.len();
                p.col.par_extend(rayon::iter::repeat_n(0, end - start));
                p.blocks.par_extend(rayon::iter::repeat_n([0.0; 4], end - start));
                let ends = &p.row_ptr[first_row..];
                write_rows(s, order, ends, start, &mut p.col[first..], &mut p.blocks[first..]);
            } else {
                for k in range {
                    block_row(s, s.order[k] as usize, |c, b| {
                        p.col.push(c);
                        p.blocks.push(b);
                    });
                    p.row_ptr.push(p.blocks.len() - b0);
                }
            }
            p.slots.push(slot);
        }
    }

    /// The problems of the batch's islands that need a solve, in island order.
    pub(super) fn problems(&self) -> impl Iterator<Item = Fc2dRef<'_>> {
        let p = &self.problems;
        (0..p.slots.len()).filter(|&j| p.slots[j].solve).filter_map(|j| p.problem(j).ok())
    }

    /// Solves the batch's islands in turn; the impulses go to `r`, the worst island's
    /// information to `info`, the first failure to `failure` (and the batch stops there).
    /// An island the solvers leave above their tolerance is taken when its natural residual
    /// is at most the purpose's inexact residual (its information then says so), else it is
    /// the batch's failure.
    pub(super) fn solve(&mut self, purpose: Purpose) {
        self.info = None;
        self.failure = None;
        fill(&mut self.r, self.problems.q.len(), 0.0);
        for (j, slot) in self.problems.slots.iter().enumerate() {
            if !slot.solve {
                continue;
            }
            let rows = slot.row_off..slot.row_off + slot.rows;
            let problem = match self.problems.problem(j) {
                Ok(p) => p,
                Err(e) => {
                    self.failure = Some(IslandFailure::Input(e));
                    return;
                }
            };
            let warm = &self.problems.warm[rows.clone()];
            let c = slot.scale;
            let solved = if c == 1.0 {
                self.solver.solve(problem, warm, purpose, &mut self.solution)
            } else {
                let parts = problem.parts();
                self.scaled_blocks.clear();
                self.scaled_blocks.extend(parts.blocks.iter().map(|b| b.map(|v| c * v)));
                self.scaled_warm.clear();
                self.scaled_warm.extend(warm.iter().map(|v| v / c));
                let scaled =
                    Fc2dRef::from_parts(Fc2dParts { blocks: &self.scaled_blocks, ..parts });
                let solved = scaled.and_then(|scaled| {
                    self.solver.solve(scaled, &self.scaled_warm, purpose, &mut self.solution)
                });
                self.solution.r.iter_mut().for_each(|r| *r *= c);
                solved
            };
            let taken = match solved {
                Ok(taken) => taken,
                Err(e) => {
                    self.failure = Some(IslandFailure::Input(e));
                    return;
                }
            };
            let out = &self.solution;
            if !taken {
                self.failure =
                    Some(IslandFailure::Status(out.status, Box::new(problem.to_owned())));
                return;
            }
            self.r[rows].copy_from_slice(&out.r);
            let residual = lcp_residual(problem, &out.r, &mut self.sums);
            let info = LcpInfo {
                method: out.method,
                status: out.status,
                iterations: out.iterations,
                residual,
            };
            self.info = Some(worse(self.info, info));
        }
    }
}

/// Writes the block rows of `links` into `col` and `blocks`, which hold exactly those rows;
/// `ends` are the rows' ends and `start` the first row's start (relative to the island's
/// first block). The halves of more than [`CHUNK_LINKS`] links go through `rayon::join`.
fn write_rows(
    s: &Shared<'_>,
    links: &[u32],
    ends: &[usize],
    start: usize,
    col: &mut [u32],
    blocks: &mut [[f64; 4]],
) {
    if links.len() <= CHUNK_LINKS {
        let mut k = 0;
        for &a in links {
            block_row(s, a as usize, |c, b| {
                col[k] = c;
                blocks[k] = b;
                k += 1;
            });
        }
        debug_assert_eq!(k, col.len(), "the rows' lengths were counted");
        return;
    }
    let mid = links.len() / 2;
    let split = ends[mid - 1] - start;
    let (col_a, col_b) = col.split_at_mut(split);
    let (blocks_a, blocks_b) = blocks.split_at_mut(split);
    rayon::join(
        || write_rows(s, &links[..mid], &ends[..mid], start, col_a, blocks_a),
        || write_rows(s, &links[mid..], &ends[mid..], ends[mid - 1], col_b, blocks_b),
    );
}

/// The links acting on side `side` of link `a`, as (link, side), in link order (hence in
/// the order of their local columns: an island lists its links in link order).
#[inline(always)]
fn side_links<'a>(s: &Shared<'a>, bodies: [u32; 2], side: usize) -> &'a [(u32, u8)] {
    match bodies[side] {
        NO_BODY => &[],
        k => &s.body_list[s.body_start[k as usize]..s.body_start[k as usize + 1]],
    }
}

/// The number of blocks of the block row of link `a`: the links of its two bodies, a link on
/// both (a contact between the same two bodies, `a` itself among them) counted once.
fn row_len(s: &Shared<'_>, a: usize) -> usize {
    let bodies = s.link(a).0;
    let (l0, l1) = (side_links(s, bodies, 0), side_links(s, bodies, 1));
    let (mut i, mut j, mut shared) = (0, 0, 0);
    while i < l0.len() && j < l1.len() {
        let (x, y) = (l0[i].0, l1[j].0);
        shared += usize::from(x == y);
        i += usize::from(x <= y);
        j += usize::from(y <= x);
    }
    l0.len() + l1.len() - shared
}

/// Gives the block row of link `a` to `emit(column, block)` by increasing local column: its
/// blocks with every link sharing a body, the lists of its two bodies merged, and a link on
/// both bodies given once with the two bodies' contributions added up. A joint group of one
/// row has a zero second row and zero M⁻¹ of it, so its blocks' padding is zero as the
/// problem's layout asks.
#[inline(always)]
fn block_row(s: &Shared<'_>, a: usize, mut emit: impl FnMut(u32, [f64; 4])) {
    let (bodies, w_0, w_1) = s.link(a);
    let (l0, l1) = (side_links(s, bodies, 0), side_links(s, bodies, 1));
    let block = |side: usize, &(c, sc): &(u32, u8)| {
        let wc = &s.work[c as usize];
        let (yn, yt) = (&wc.mw_n[sc as usize], &wc.mw_t[sc as usize]);
        let (wn, wt) = (&w_0[side], &w_1[side]);
        [dot3(wn, yn), dot3(wn, yt), dot3(wt, yn), dot3(wt, yt)]
    };
    let (mut i, mut j) = (0, 0);
    while i < l0.len() || j < l1.len() {
        let x = l0.get(i).map_or(u32::MAX, |e| e.0);
        let y = l1.get(j).map_or(u32::MAX, |e| e.0);
        if x < y {
            emit(s.local[x as usize], block(0, &l0[i]));
            i += 1;
        } else if y < x {
            emit(s.local[y as usize], block(1, &l1[j]));
            j += 1;
        } else {
            let (b0, b1) = (block(0, &l0[i]), block(1, &l1[j]));
            emit(s.local[x as usize], [b0[0] + b1[0], b0[1] + b1[1], b0[2] + b1[2], b0[3] + b1[3]]);
            i += 1;
            j += 1;
        }
    }
}

#[inline(always)]
fn dot3(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The worse of two islands' information: the largest iteration count, the method and
/// residual of the island of largest residual, and a status other than `Solved` if either has
/// one (an island taken above the solvers' tolerance).
pub(super) fn worse(a: Option<LcpInfo>, b: LcpInfo) -> LcpInfo {
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
                status: if a.status == Status::Solved { b.status } else { a.status },
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
    // Each group's sums from its own block row: in chunks on rayon's pool for a large island,
    // the same bits either way.
    fill(sums, groups, [0.0; 4]);
    for_chunks(sums, |first, chunk| {
        for (k, out) in chunk.iter_mut().enumerate() {
            let i = first + k;
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
            *out = [sum_0, abs_0, sum_1, abs_1];
        }
    });
    let sums = &*sums;
    let z = |i: usize| {
        let p_n = r[2 * i];
        [p_n, r[2 * i + 1] + mu[i] * p_n, (-sums[i][2]).max(0.0)]
    };
    // The rows of group g: N, R and L of a contact, the rows of a bilateral group.
    let group_rows = |mut rows: ResidualRows, g: usize| {
        if g < n {
            let [p_n, p_r, xi_l] = z(g);
            let [sum_n, abs_n, sum_r, abs_r] = sums[g];
            rows.row(q[2 * g], p_n, sum_n, abs_n, sum_n);
            let w_r = sum_r + xi_l;
            rows.row(q[2 * g + 1], p_r, w_r, abs_r + xi_l, w_r);
            let (a, b) = (2.0 * mu[g] * p_n, -p_r);
            rows.row(0.0, xi_l, a + b, a.abs() + b.abs(), a + b);
        } else {
            let [sum_0, abs_0, sum_1, abs_1] = sums[g];
            rows.row(q[gs[g]], 0.0, 0.0, abs_0, sum_0);
            if gs[g + 1] - gs[g] == 2 {
                rows.row(q[gs[g] + 1], 0.0, 0.0, abs_1, sum_1);
            }
        }
        rows
    };
    // Every quantity of the residual is a maximum: in chunks on rayon's pool for a large
    // island, the same bits either way.
    let rows = if in_parallel(groups) {
        let z_max = (0..n)
            .into_par_iter()
            .with_min_len(CHUNK_LINKS)
            .map(|i| z(i).iter().fold(0.0f64, |m, v| m.max(v.abs())))
            .reduce(|| 0.0, f64::max);
        let fresh = ResidualRows::new([z_max]);
        (0..groups)
            .into_par_iter()
            .with_min_len(CHUNK_LINKS)
            .fold(|| fresh.clone(), group_rows)
            .reduce(
                || fresh.clone(),
                |mut a, b| {
                    a.merge(&b);
                    a
                },
            )
    } else {
        (0..groups).fold(ResidualRows::new((0..n).flat_map(z)), group_rows)
    };
    rows.finish().relative
}
