//! The robust default for planar frictional contact: the LCP route for small problems,
//! nonsmooth Gauss-Seidel beyond, and exact solves of the clusters where it stalls.

use serde::{Deserialize, Serialize};

use super::residual::natural_map;
use super::solution::check_warm_start;
use super::{
    Fc2dParts, Fc2dRef, Fc2dResidual, Fc2dSolution, Fc2dSolver, LcpRoute, LcpRouteOptions, Newton,
    NewtonOptions, Nsgs, NsgsOptions,
};
use crate::error::rules;
use crate::{LcpError, Method, Status};

/// Options of [`Fc2dAuto`]: the default, changed field by field with the `with_*` setters
/// (or by assigning the fields of a default value).
///
/// ```
/// use moreau_lcp::fc2d::{Fc2dAuto, Fc2dAutoOptions};
///
/// # fn main() -> Result<(), moreau_lcp::LcpError> {
/// let options = Fc2dAutoOptions::default().with_tolerance(1e-10).with_max_sweeps(500);
/// assert_eq!((options.tolerance, options.max_sweeps), (1e-10, 500));
/// let solver = Fc2dAuto::new(options)?;
/// # let _ = solver;
/// # Ok(())
/// # }
/// ```
///
/// The struct is `#[non_exhaustive]`, so that fields added later keep their defaults in
/// callers' code; a struct literal does not compile outside this crate:
///
/// ```compile_fail,E0639
/// let options = moreau_lcp::fc2d::Fc2dAutoOptions { tolerance: 1e-10, ..Default::default() };
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct Fc2dAutoOptions {
    /// Accept r when `natural <= max(tolerance, round_off)` ([`Fc2dResidual::meets`]).
    /// Default 1e-8.
    pub tolerance: f64,
    /// Problems with at most this many contacts go to the [`LcpRoute`] when the first
    /// window of Gauss-Seidel sweeps does not solve them. Default 100 (a dense pivoting
    /// solve of 300 rows, tens of milliseconds).
    pub lcp_max_contacts: usize,
    /// Largest total number of Gauss-Seidel sweeps. Default 100,000.
    pub max_sweeps: usize,
    /// Gauss-Seidel sweeps between two progress checks. Default 50.
    pub window: usize,
    /// A window that divides the residual by less than this factor (> 1) counts as a
    /// stall and triggers the cluster solves. Default 2.
    pub stall_factor: f64,
    /// Rings of neighbours (contacts sharing a block of W) added around the contacts
    /// whose local residual is too large. Default 2.
    pub cluster_depth: usize,
    /// Largest cluster handed to the LCP route; larger ones are cut to their contacts
    /// nearest the offending ones. Default 300.
    pub max_cluster_contacts: usize,
    /// Largest cluster handed to the LCP route (a dense pivoting solve of 3 n_c rows);
    /// larger clusters go to Newton directly. Default 100.
    pub cluster_lcp_contacts: usize,
    /// Largest number of rounds of cluster solves (rounds skipped because too many
    /// contacts are off are not counted). Default 20.
    pub max_rounds: usize,
    /// Relaxation factor ω of the Gauss-Seidel sweeps, in (0, 2). Default 1.4: on
    /// Siconos' granular problems it halves the sweeps of ω = 1 (220 instead of 505 to
    /// 1e-4 on 2,020 contacts, 300 instead of 627 on 7,002), while ω = 1.6 diverges on
    /// 7,002 contacts. On a few weakly coupled contacts over-relaxation costs sweeps instead:
    /// a single contact, which ω = 1 solves in one sweep (and certifies in a second), takes
    /// 22 sweeps to 1e-8 at ω = 1.4, its error multiplied by −0.4 each sweep; the stepper
    /// solves its small islands at ω = 1.
    pub omega: f64,
}

with_setters!(Fc2dAutoOptions {
    with_tolerance => tolerance: f64,
    with_lcp_max_contacts => lcp_max_contacts: usize,
    with_max_sweeps => max_sweeps: usize,
    with_window => window: usize,
    with_stall_factor => stall_factor: f64,
    with_cluster_depth => cluster_depth: usize,
    with_max_cluster_contacts => max_cluster_contacts: usize,
    with_cluster_lcp_contacts => cluster_lcp_contacts: usize,
    with_max_rounds => max_rounds: usize,
    with_omega => omega: f64,
});

impl Default for Fc2dAutoOptions {
    fn default() -> Self {
        Fc2dAutoOptions {
            tolerance: 1e-8,
            lcp_max_contacts: 100,
            max_sweeps: 100_000,
            window: 50,
            stall_factor: 2.0,
            cluster_depth: 2,
            max_cluster_contacts: 300,
            cluster_lcp_contacts: 100,
            max_rounds: 20,
            omega: 1.4,
        }
    }
}

/// The robust default solver of planar frictional-contact problems; every exit is
/// certified by the shared residual and [`Fc2dSolution::method`] names the method that
/// produced r.
///
/// 1. [`Nsgs`] (over-relaxed by `omega`) runs a first window of `window` sweeps. When it
///    reaches the tolerance, that is the answer ([`Method::Nsgs`]): most problems end
///    here, at a cost of a few nanoseconds per stored block and sweep.
/// 2. A problem of at most `lcp_max_contacts` contacts that is not solved yet goes to
///    the exact [`LcpRoute`] (a dense pivoting solve of 3 n_c rows, whose cost grows as
///    n_c³). If it ends [`Status::Solved`], that is the answer ([`Method::LcpRoute`]); if
///    it ends [`Status::NoSolution`] (enumeration proved that the problem has none), so is
///    that, with the LCP route's r and pivots, rather than the sweeps that could not end.
/// 3. Otherwise Gauss-Seidel resumes by windows, each warm-started from the last. When a
///    window divides the residual by less than `stall_factor` and at most
///    `max_cluster_contacts` groups are still off (their local natural map above the
///    tolerance), Gauss-Seidel is taken to be stalled on a few clusters of strongly
///    coupled contacts while the rest has converged (in a dense packing, where W is
///    nearly singular). The offending groups are grown by `cluster_depth` rings of
///    neighbours through W's block graph into connected clusters, and each cluster's
///    problem with the other reactions frozen,
///    `u_C = W_CC r_C + (q_C + Σ_{j∉C} W_Cj r_j)`, is solved exactly: by the
///    [`LcpRoute`] up to `cluster_lcp_contacts` contacts, else (or when that solution is
///    rejected) by [`Newton`] from the current reactions. A cluster's solution is kept
///    only when it lowers the largest local residual over the cluster and its
///    neighbours: a nearly singular W_CC has distant solutions that would disturb the
///    surroundings more than they help. An exact cluster solution is a fixed point of
///    the Gauss-Seidel sweep on its contacts, so the following sweeps only spread its
///    effect. When the tolerance is reached after a kept cluster solution, the method is
///    [`Method::NsgsClusters`] (and [`Fc2dSolution::lcp_method`] the LCP solver's
///    method when the last kept cluster was solved by pivoting).
///
/// Otherwise the solve ends [`Status::IterationLimit`] when the sweep budget is spent first,
/// [`Status::NumericalFailure`] on non-finite iterates. [`Fc2dSolution::iterations`]
/// counts the Gauss-Seidel sweeps.
///
/// A warm start is handed to Gauss-Seidel (the LCP route cannot use one). Repeated
/// solves that end in Gauss-Seidel allocate nothing once warm; the LCP route and the
/// cluster solves build dense matrices or sparse patterns and allocate.
pub struct Fc2dAuto {
    options: Fc2dAutoOptions,
    lcp: LcpRoute,
    nsgs: Nsgs,
    cluster_lcp: LcpRoute,
    cluster_newton: Newton,
    clusters: Clusters,
    sub_out: Fc2dSolution,
}

impl std::fmt::Debug for Fc2dAuto {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fc2dAuto").field("options", &self.options).finish_non_exhaustive()
    }
}

impl Default for Fc2dAuto {
    fn default() -> Self {
        Fc2dAuto::new(Fc2dAutoOptions::default()).expect("the default options are valid")
    }
}

/// Buffers of the cluster search and of one cluster's sub-problem.
#[derive(Default)]
struct Clusters {
    /// Ring (distance) of each group from an offending contact, `u32::MAX` if none.
    ring: Vec<u32>,
    /// Local index of each group in the current cluster, `u32::MAX` if outside.
    local: Vec<u32>,
    /// Breadth-first queue.
    queue: Vec<usize>,
    /// Members of the current cluster, sorted.
    members: Vec<usize>,
    /// Whether a group was already put in a cluster this round.
    taken: Vec<bool>,
    /// The groups whose velocity a cluster changes, and their marks.
    affected: Vec<usize>,
    in_affected: Vec<bool>,
    /// The reactions of a cluster before its solve.
    saved: Vec<f64>,
    group_start: Vec<usize>,
    row_ptr: Vec<usize>,
    col: Vec<u32>,
    blocks: Vec<[f64; 4]>,
    q: Vec<f64>,
    mu: Vec<f64>,
}

impl Fc2dAuto {
    /// A solver with the given options.
    ///
    /// # Errors
    /// [`LcpError::InvalidOption`] unless `tolerance` is finite and > 0, `max_sweeps`,
    /// `window` and `max_cluster_contacts` are >= 1, `stall_factor > 1` and
    /// `0 < omega < 2`.
    pub fn new(options: Fc2dAutoOptions) -> Result<Fc2dAuto, LcpError> {
        rules::tolerance(options.tolerance)?;
        rules::count("max_sweeps", options.max_sweeps)?;
        rules::count("window", options.window)?;
        if !(options.stall_factor > 1.0) {
            return Err(rules::invalid("stall_factor", "must be > 1"));
        }
        rules::count("max_cluster_contacts", options.max_cluster_contacts)?;
        let lcp = LcpRoute::new(LcpRouteOptions {
            tolerance: options.tolerance,
            max_contacts: options.lcp_max_contacts,
            ..Default::default()
        })?;
        let nsgs = Nsgs::new(NsgsOptions {
            tolerance: options.tolerance,
            max_sweeps: options.window.min(options.max_sweeps),
            omega: options.omega,
            ..Default::default()
        })?;
        // A cluster is solved well below the tolerance, so that its boundary is what is
        // left to Gauss-Seidel.
        let cluster_lcp = LcpRoute::new(LcpRouteOptions {
            tolerance: 0.01 * options.tolerance,
            max_contacts: options.cluster_lcp_contacts,
            ..Default::default()
        })?;
        let cluster_newton = Newton::new(NewtonOptions {
            tolerance: 0.01 * options.tolerance,
            max_iterations: 30,
            ..Default::default()
        })?;
        Ok(Fc2dAuto {
            options,
            lcp,
            nsgs,
            cluster_lcp,
            cluster_newton,
            clusters: Clusters::default(),
            sub_out: Fc2dSolution::new(),
        })
    }

    /// The options.
    pub fn options(&self) -> &Fc2dAutoOptions {
        &self.options
    }

    /// One round of cluster solves around the contacts whose local residual exceeds
    /// `threshold` (absolute); `out.r` is updated in place and `out.u` recomputed.
    /// Returns the number of clusters whose solution was kept, or `None` when there are
    /// too many offending groups for a few small clusters (nothing was tried).
    fn solve_clusters(
        &mut self,
        problem: Fc2dRef<'_>,
        threshold: f64,
        out: &mut Fc2dSolution,
    ) -> Result<Option<usize>, LcpError> {
        let p = problem.parts();
        let groups = problem.n_groups();
        let n_c = p.n_contacts;
        let gs = p.group_start;
        let c = &mut self.clusters;
        c.ring.clear();
        c.ring.resize(groups, u32::MAX);
        c.local.clear();
        c.local.resize(groups, u32::MAX);
        c.taken.clear();
        c.taken.resize(groups, false);
        c.in_affected.clear();
        c.in_affected.resize(groups, false);
        c.queue.clear();
        for g in 0..groups {
            let error = if g < n_c {
                let (e0, e1) = natural_map(
                    out.r[2 * g],
                    out.r[2 * g + 1],
                    out.u[2 * g],
                    out.u[2 * g + 1],
                    p.mu[g],
                );
                (e0 * e0 + e1 * e1).sqrt()
            } else {
                out.u[gs[g]..gs[g + 1]].iter().fold(0.0f64, |m, v| m.max(v.abs()))
            };
            if error > threshold {
                c.ring[g] = 0;
                c.queue.push(g);
            }
        }
        if c.queue.len() > self.options.max_cluster_contacts {
            // Too many offending groups for a few small clusters: Gauss-Seidel has not
            // converged outside them yet.
            return Ok(None);
        }
        // Rings of neighbours, breadth first from all offending groups at once.
        let mut head = 0;
        while head < c.queue.len() {
            let g = c.queue[head];
            head += 1;
            let next = c.ring[g] + 1;
            if next as usize > self.options.cluster_depth {
                continue;
            }
            for &j in &p.col[p.row_ptr[g]..p.row_ptr[g + 1]] {
                let j = j as usize;
                if c.ring[j] == u32::MAX {
                    c.ring[j] = next;
                    c.queue.push(j);
                }
            }
        }
        let marked = c.queue.len();
        let mut solved = 0;
        for start in 0..marked {
            let seed = self.clusters.queue[start];
            if self.clusters.taken[seed] || self.clusters.ring[seed] != 0 {
                continue;
            }
            self.gather_cluster(problem, seed);
            if self.solve_cluster(problem, out)? {
                solved += 1;
            }
        }
        problem.velocity(&out.r, &mut out.u);
        Ok(Some(solved))
    }

    /// Collects the marked groups connected to `seed` (nearest rings first, at most
    /// `max_cluster_contacts` contacts) into `members`, sorted.
    fn gather_cluster(&mut self, problem: Fc2dRef<'_>, seed: usize) {
        let p = problem.parts();
        let c = &mut self.clusters;
        let marked = c.queue.len();
        c.members.clear();
        c.members.push(seed);
        c.taken[seed] = true;
        let mut contacts = usize::from(seed < p.n_contacts);
        let mut head = 0;
        while head < c.members.len() {
            let g = c.members[head];
            head += 1;
            for &j in &p.col[p.row_ptr[g]..p.row_ptr[g + 1]] {
                let j = j as usize;
                if c.ring[j] == u32::MAX || c.taken[j] {
                    continue;
                }
                if j < p.n_contacts {
                    if contacts >= self.options.max_cluster_contacts {
                        continue;
                    }
                    contacts += 1;
                }
                c.taken[j] = true;
                c.members.push(j);
            }
        }
        debug_assert!(c.members.len() <= marked);
        c.members.sort_unstable();
    }

    /// Solves the sub-problem of `members` with the other reactions frozen, first by the
    /// LCP route, then, if that fails or its solution is rejected, by Newton from the
    /// current reactions. A solution is kept only when it lowers the largest local
    /// residual over the cluster and its neighbours. `out.u` must be W r + q on entry and
    /// is kept so. Returns whether a solution was kept.
    fn solve_cluster(
        &mut self,
        problem: Fc2dRef<'_>,
        out: &mut Fc2dSolution,
    ) -> Result<bool, LcpError> {
        let p = problem.parts();
        let gs = p.group_start;
        let c = &mut self.clusters;
        for (l, &g) in c.members.iter().enumerate() {
            c.local[g] = l as u32;
        }
        c.group_start.clear();
        c.group_start.push(0);
        c.row_ptr.clear();
        c.row_ptr.push(0);
        c.col.clear();
        c.blocks.clear();
        c.q.clear();
        c.mu.clear();
        c.saved.clear();
        let mut n_contacts = 0;
        for &g in &c.members {
            let rows = gs[g + 1] - gs[g];
            if g < p.n_contacts {
                n_contacts += 1;
                c.mu.push(p.mu[g]);
            }
            c.group_start.push(c.group_start.last().copied().unwrap_or(0) + rows);
            c.saved.extend_from_slice(&out.r[gs[g]..gs[g + 1]]);
            // q of the sub-problem: u_g minus the cluster's own contribution.
            let mut v = [out.u[gs[g]], if rows == 2 { out.u[gs[g] + 1] } else { 0.0 }];
            for k in p.row_ptr[g]..p.row_ptr[g + 1] {
                let j = p.col[k] as usize;
                if c.local[j] == u32::MAX {
                    continue;
                }
                let b = &p.blocks[k];
                let r0 = out.r[gs[j]];
                let r1 = if gs[j + 1] - gs[j] == 2 { out.r[gs[j] + 1] } else { 0.0 };
                v[0] -= b[0] * r0 + b[1] * r1;
                v[1] -= b[2] * r0 + b[3] * r1;
                c.col.push(c.local[j]);
                c.blocks.push(*b);
            }
            c.q.extend_from_slice(&v[..rows]);
            c.row_ptr.push(c.col.len());
        }
        for &g in &c.members {
            c.local[g] = u32::MAX;
        }
        // The groups whose velocity the cluster's reactions change: its members and
        // their neighbours (W's block pattern is symmetric for W = H M⁻¹ Hᵀ; the final
        // residual is computed in full anyway).
        c.affected.clear();
        for &g in &c.members {
            for &j in &p.col[p.row_ptr[g]..p.row_ptr[g + 1]] {
                let j = j as usize;
                if !c.in_affected[j] {
                    c.in_affected[j] = true;
                    c.affected.push(j);
                }
            }
        }
        for &g in &c.affected {
            c.in_affected[g] = false;
        }
        let before = local_error(problem, &c.affected, &out.r, &out.u);
        // A cluster whose frozen surroundings push its q beyond the range of a valid problem
        // (reactions far out) is not solved: the sweeps go on.
        let Ok(sub) = Fc2dRef::from_parts(Fc2dParts {
            n_contacts,
            group_start: &c.group_start,
            row_ptr: &c.row_ptr,
            col: &c.col,
            blocks: &c.blocks,
            q: &c.q,
            mu: &c.mu,
        }) else {
            return Ok(false);
        };
        for attempt in [Method::LcpRoute, Method::Newton] {
            let sub_out = &mut self.sub_out;
            if attempt == Method::LcpRoute {
                self.cluster_lcp.solve_into(sub, None, sub_out)?;
            } else {
                self.cluster_newton.solve_into(sub, Some(&c.saved), sub_out)?;
            }
            if sub_out.status != Status::Solved {
                continue;
            }
            for (l, &g) in c.members.iter().enumerate() {
                let rows = gs[g]..gs[g + 1];
                let local = c.group_start[l]..c.group_start[l + 1];
                out.r[rows].copy_from_slice(&sub_out.r[local]);
            }
            update_velocity(problem, &c.affected, &out.r, &mut out.u);
            if local_error(problem, &c.affected, &out.r, &out.u) <= before {
                out.lcp_method = sub_out.lcp_method;
                return Ok(true);
            }
            // The cluster's exact solution disturbs its surroundings more than it helps
            // (a singular W_CC has other solutions): back to the old reactions.
            for (l, &g) in c.members.iter().enumerate() {
                let rows = gs[g]..gs[g + 1];
                let local = c.group_start[l]..c.group_start[l + 1];
                out.r[rows].copy_from_slice(&c.saved[local]);
            }
            update_velocity(problem, &c.affected, &out.r, &mut out.u);
        }
        Ok(false)
    }
}

/// The largest local natural map (contacts) or violation (bilateral groups) over `groups`.
fn local_error(problem: Fc2dRef<'_>, groups: &[usize], r: &[f64], u: &[f64]) -> f64 {
    let p = problem.parts();
    let gs = p.group_start;
    let mut error = 0.0f64;
    for &g in groups {
        if g < p.n_contacts {
            let (e0, e1) = natural_map(r[2 * g], r[2 * g + 1], u[2 * g], u[2 * g + 1], p.mu[g]);
            error = error.max((e0 * e0 + e1 * e1).sqrt());
        } else {
            error = u[gs[g]..gs[g + 1]].iter().fold(error, |m, v| m.max(v.abs()));
        }
    }
    error
}

/// Recomputes `u_g = Σ_j W_gj r_j + q_g` for the given groups.
fn update_velocity(problem: Fc2dRef<'_>, groups: &[usize], r: &[f64], u: &mut [f64]) {
    let p = problem.parts();
    let gs = p.group_start;
    for &g in groups {
        let two = gs[g + 1] - gs[g] == 2;
        let [u0, u1] =
            problem.row_product(g, r, [p.q[gs[g]], if two { p.q[gs[g] + 1] } else { 0.0 }]);
        u[gs[g]] = u0;
        if two {
            u[gs[g] + 1] = u1;
        }
    }
}

impl Fc2dSolver for Fc2dAuto {
    fn solve_into(
        &mut self,
        problem: Fc2dRef<'_>,
        warm_start: Option<&[f64]>,
        out: &mut Fc2dSolution,
    ) -> Result<(), LcpError> {
        check_warm_start(problem, warm_start)?;
        let tolerance = self.options.tolerance;
        let scale = problem.q_norm_inf().max(1.0);
        self.nsgs.solve_into(problem, warm_start, out)?;
        if out.status != Status::IterationLimit {
            return Ok(());
        }
        let mut sweeps = out.iterations;
        if out.status == Status::IterationLimit
            && problem.n_contacts() <= self.options.lcp_max_contacts
        {
            // Gauss-Seidel did not finish in its first window: the certified route, with
            // Gauss-Seidel's iterate kept to resume from if it fails.
            self.sub_out.r.clear();
            self.sub_out.r.extend_from_slice(&out.r);
            self.lcp.solve_into(problem, None, out)?;
            // Solved, or proved to have no solution by enumeration: no sweep can do better.
            if out.status == Status::Solved || out.status == Status::NoSolution {
                return Ok(());
            }
            out.r.clear();
            out.r.extend_from_slice(&self.sub_out.r);
            out.method = Method::Nsgs;
            out.lcp_method = None;
            out.certify(problem, tolerance, Status::IterationLimit);
        }
        let mut rounds = 0;
        let mut last = f64::INFINITY;
        let mut method = Method::Nsgs;
        let mut lcp_method = None;
        while out.status == Status::IterationLimit && sweeps < self.options.max_sweeps {
            let stalled = out.residual.natural * self.options.stall_factor > last;
            if stalled && rounds < self.options.max_rounds {
                let threshold = tolerance * scale;
                if let Some(kept) = self.solve_clusters(problem, threshold, out)? {
                    rounds += 1;
                    if kept > 0 {
                        method = Method::NsgsClusters;
                        lcp_method = out.lcp_method;
                    }
                }
                out.residual = Fc2dResidual::of_velocity(problem, &out.r, &out.u, tolerance);
                if out.residual.meets(tolerance) {
                    out.certify(problem, tolerance, Status::IterationLimit);
                    break;
                }
            }
            last = out.residual.natural;
            std::mem::swap(&mut self.sub_out.r, &mut out.r);
            self.nsgs.solve_into(problem, Some(&self.sub_out.r), out)?;
            sweeps += out.iterations;
        }
        out.method = method;
        out.lcp_method = lcp_method;
        out.iterations = sweeps;
        if out.status == Status::Solved || out.status == Status::NumericalFailure {
            return Ok(());
        }
        out.certify(problem, tolerance, Status::IterationLimit);
        Ok(())
    }
}
