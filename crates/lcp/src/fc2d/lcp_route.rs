//! The exact LCP reformulation of the planar frictional-contact problem.
#![allow(non_snake_case)]

use serde::{Deserialize, Serialize};

use super::solution::check_warm_start;
use super::{Fc2d, Fc2dRef, Fc2dSolution, Fc2dSolver, Newton, NewtonOptions};
use crate::dense::Lu;
use crate::error::rules;
use crate::{Auto, Enumeration, LcpError, LcpRef, Lemke, Method, Solution, Solver, Status};

/// Which LCP solver the [`LcpRoute`] hands the reformulated problem to.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum LcpRouteSolver {
    /// [`Auto`] with its default options (Lemke with other covering vectors, then
    /// enumeration up to its size guard).
    #[default]
    Auto,
    /// [`Lemke`] with its default options.
    Lemke,
    /// [`Enumeration`] with its default options (3 n_c up to its size guard).
    Enumeration,
}

/// Options of [`LcpRoute`]: the default, changed field by field with the `with_*` setters
/// (or by assigning the fields of a default value).
///
/// ```
/// use moreau_lcp::fc2d::{LcpRoute, LcpRouteOptions};
///
/// # fn main() -> Result<(), moreau_lcp::LcpError> {
/// let options = LcpRouteOptions::default().with_tolerance(1e-10).with_max_contacts(50);
/// assert_eq!((options.tolerance, options.max_contacts), (1e-10, 50));
/// let solver = LcpRoute::new(options)?;
/// # let _ = solver;
/// # Ok(())
/// # }
/// ```
///
/// The struct is `#[non_exhaustive]`, so that fields added later keep their defaults in
/// callers' code; a struct literal does not compile outside this crate:
///
/// ```compile_fail,E0639
/// let options = moreau_lcp::fc2d::LcpRouteOptions { tolerance: 1e-10, ..Default::default() };
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct LcpRouteOptions {
    /// Accept r when [`Fc2dResidual::natural`](super::Fc2dResidual::natural) is
    /// `<= tolerance`. Default 1e-8.
    pub tolerance: f64,
    /// Problems with more contacts are not attempted ([`Status::TooLarge`]): the LCP is
    /// dense, of size 3 n_c, and a pivoting solve costs about (3 n_c)³ operations.
    /// Default 150.
    pub max_contacts: usize,
    /// The LCP solver. Default [`LcpRouteSolver::Auto`].
    pub solver: LcpRouteSolver,
    /// Largest number of [`Newton`] iterations that finish pivoting's candidate when it misses
    /// the tolerance (0: none). Default 20.
    pub polish_iterations: usize,
}

with_setters!(LcpRouteOptions {
    with_tolerance => tolerance: f64,
    with_max_contacts => max_contacts: usize,
    with_solver => solver: LcpRouteSolver,
    with_polish_iterations => polish_iterations: usize,
});

impl Default for LcpRouteOptions {
    fn default() -> Self {
        LcpRouteOptions {
            tolerance: 1e-8,
            max_contacts: 150,
            solver: LcpRouteSolver::Auto,
            polish_iterations: 20,
        }
    }
}

/// The certified path for small problems: the planar frictional-contact problem written
/// exactly as an LCP and solved by pivoting.
///
/// Coulomb's law is split with `r_R = r_T + μ r_N >= 0`, `r_L = μ r_N - r_T >= 0` and
/// `u_T = ξ_R - ξ_L`, as in the step LCP of Moreau's midpoint method:
///
/// ```text
/// z = (r_N; r_R; ξ_L),   w = (u_N; ξ_R; r_L),   w = A z + b,   0 <= z ⊥ w >= 0,
///
/// A = [ W_NN - W_NT μ   W_NT   0 ]      b = [ q_N ]
///     [ W_TN - W_TT μ   W_TT   I ]          [ q_T ]
///     [ 2 μ             -I     0 ]          [ 0   ]
/// ```
///
/// (μ the diagonal matrix of the friction coefficients). Bilateral rows are eliminated
/// first by their Schur complement: with `W_bb λ = -(W_bc r_c + q_b)`, the contacts see
/// `W_cc - W_cb W_bb⁻¹ W_bc` and `q_c - W_cb W_bb⁻¹ q_b`; a singular W_bb (redundant
/// constraints, a pivot of W_bb's LU below 1e-13 of its column) ends the solve with
/// [`Status::NumericalFailure`].
///
/// The LCP's solution is mapped back to `r_T = r_R - μ r_N`, λ and u = W r + q, and
/// judged by the FC2D residual. [`Status::NoSolution`] is reported only when the LCP
/// solver's enumeration proved that the LCP has none; problems above `max_contacts`
/// return [`Status::TooLarge`] without a solve, and those whose LCP has an entry beyond
/// the range the LCP solvers compute in ([`MAX_ENTRY`](crate::MAX_ENTRY), as 2 μ for
/// μ = `MAX_ENTRY` is) end at r = 0 with [`Status::NumericalFailure`] unless r = 0 solves them. Warm starts are not used. The
/// elimination, the LCP and its solver work on buffers kept from one solve to the next:
/// once the sizes have been seen, a solve does not allocate.
///
/// **Polish.** Pivoting on an ill-conditioned basis can end a few digits short of the
/// tolerance: where the masses of bodies in contact differ by orders of magnitude, the
/// entries of the LCP's matrix span as many, and round-off in the basis' factorisation is
/// amplified by the reactions' size. Such a candidate usually has every contact's case
/// (separating, sticking, slipping) right, and on that piece Coulomb's law is linear: one
/// [`Newton`] step from it solves the problem. So when the candidate misses the tolerance,
/// Newton (at most `polish_iterations` iterations) starts from it, and the better of the two
/// by the natural residual is returned; [`Fc2dSolution::iterations`] then counts the pivots
/// and the Newton iterations, and the method stays [`Method::LcpRoute`].
pub struct LcpRoute {
    options: LcpRouteOptions,
    /// Newton's solver of the polish (`None` when `polish_iterations` is 0).
    polish: Option<Newton>,
    /// Pivoting's candidate while the polish runs.
    candidate: Fc2dSolution,
    solution: Solution,
    reduced: Reduced,
    /// The LCP's M (column-major, 3 n_c × 3 n_c) and q.
    a: Vec<f64>,
    b: Vec<f64>,
    /// The LCP solver, kept with its workspace.
    pivoting: Box<dyn Solver + Send + Sync>,
}

impl Default for LcpRoute {
    fn default() -> Self {
        LcpRoute::new(LcpRouteOptions::default()).expect("the default options are valid")
    }
}

impl LcpRoute {
    /// A solver with the given options.
    ///
    /// # Errors
    /// [`LcpError::InvalidOption`] unless `tolerance` is finite and > 0.
    pub fn new(options: LcpRouteOptions) -> Result<LcpRoute, LcpError> {
        rules::tolerance(options.tolerance)?;
        let polish = match options.polish_iterations {
            0 => None,
            max_iterations => Some(Newton::new(NewtonOptions {
                tolerance: options.tolerance,
                max_iterations,
                ..NewtonOptions::default()
            })?),
        };
        let pivoting: Box<dyn Solver + Send + Sync> = match options.solver {
            LcpRouteSolver::Auto => Box::new(Auto::default()),
            LcpRouteSolver::Lemke => Box::new(Lemke::default()),
            LcpRouteSolver::Enumeration => Box::new(Enumeration::default()),
        };
        Ok(LcpRoute {
            options,
            polish,
            candidate: Fc2dSolution::new(),
            solution: Solution::new(),
            reduced: Reduced::default(),
            a: Vec::new(),
            b: Vec::new(),
            pivoting,
        })
    }

    /// The options.
    pub fn options(&self) -> &LcpRouteOptions {
        &self.options
    }
}

/// The contacts' W and q after the elimination of the bilateral rows, and the map from
/// contact reactions to multipliers: `λ = G r_c + g`; all column-major, with the dense W
/// and the LU of W_bb they come from.
#[derive(Default)]
struct Reduced {
    /// The problem's W (n × n).
    dense: Vec<f64>,
    /// `W_cc - W_cb W_bb⁻¹ W_bc` (2 n_c × 2 n_c).
    w: Vec<f64>,
    /// `q_c - W_cb W_bb⁻¹ q_b`.
    q: Vec<f64>,
    /// `G = -W_bb⁻¹ W_bc` (n_b × 2 n_c) and `g = -W_bb⁻¹ q_b`.
    g_mat: Vec<f64>,
    g_vec: Vec<f64>,
    lu: Lu,
}

impl Reduced {
    /// Eliminates `problem`'s bilateral rows; false when W_bb is numerically singular or
    /// the result is not finite.
    fn eliminate(&mut self, problem: Fc2dRef<'_>) -> bool {
        let n = problem.n_rows();
        let nc2 = 2 * problem.n_contacts();
        let nb = n - nc2;
        problem.dense_into(&mut self.dense);
        let dense = &self.dense;
        let q = problem.q();
        self.g_mat.clear();
        self.g_mat.resize(nb * nc2, 0.0);
        self.g_vec.clear();
        self.g_vec.resize(nb, 0.0);
        if nb > 0 {
            if !self.lu.factor_with(nb, |i, j| dense[nc2 + i + (nc2 + j) * n]) {
                return false;
            }
            for j in 0..nc2 {
                let column = &mut self.g_mat[j * nb..][..nb];
                for (i, x) in column.iter_mut().enumerate() {
                    *x = -dense[nc2 + i + j * n];
                }
                self.lu.solve(column);
            }
            for (i, x) in self.g_vec.iter_mut().enumerate() {
                *x = -q[nc2 + i];
            }
            self.lu.solve(&mut self.g_vec);
            let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
            if !finite(&self.g_mat) || !finite(&self.g_vec) {
                return false;
            }
        }
        self.w.clear();
        self.w.resize(nc2 * nc2, 0.0);
        for j in 0..nc2 {
            let g = &self.g_mat[j * nb..][..nb];
            for i in 0..nc2 {
                let coupled: f64 =
                    g.iter().enumerate().map(|(k, x)| dense[i + (nc2 + k) * n] * x).sum();
                self.w[i + j * nc2] = dense[i + j * n] + coupled;
            }
        }
        self.q.clear();
        self.q.extend((0..nc2).map(|i| {
            let coupled: f64 =
                self.g_vec.iter().enumerate().map(|(k, x)| dense[i + (nc2 + k) * n] * x).sum();
            q[i] + coupled
        }));
        true
    }
}

impl Fc2dRef<'_> {
    /// The equivalent problem of the contacts alone: the bilateral rows eliminated by their
    /// Schur complement, as [`LcpRoute`] does, with `W_cc - W_cb W_bb⁻¹ W_bc` (dense) and
    /// `q_c - W_cb W_bb⁻¹ q_b`. Its solutions are this problem's contact reactions, the
    /// multipliers following as `λ = -W_bb⁻¹ (W_bc r_c + q_b)`. A problem with bilateral rows
    /// can thus be written in Siconos' FC2D format, which has none; one without comes back
    /// with the same W, q and μ. The result is dense: 4 n_c² entries of W.
    ///
    /// # Errors
    /// [`LcpError::Structure`] when W_bb is numerically singular (redundant constraints, a
    /// pivot of its LU below 1e-13 of its column) or the result is not finite.
    pub fn without_bilateral(&self) -> Result<Fc2d, LcpError> {
        let mut reduced = Reduced::default();
        if !reduced.eliminate(*self) {
            return Err(LcpError::Structure(
                "the bilateral rows cannot be eliminated: W_bb is singular or the result is not \
                 finite"
                    .into(),
            ));
        }
        let nc2 = 2 * self.n_contacts();
        Fc2d::from_dense(
            faer::MatRef::from_column_major_slice(&reduced.w, nc2, nc2),
            &reduced.q,
            self.mu(),
        )
    }
}

impl Fc2dSolver for LcpRoute {
    fn solve_into(
        &mut self,
        problem: Fc2dRef<'_>,
        warm_start: Option<&[f64]>,
        out: &mut Fc2dSolution,
    ) -> Result<(), LcpError> {
        check_warm_start(problem, warm_start)?;
        let tolerance = self.options.tolerance;
        out.reset(problem.n_rows(), Method::LcpRoute);
        let n_c = problem.n_contacts();
        if n_c > self.options.max_contacts
            || (self.options.solver == LcpRouteSolver::Enumeration
                && 3 * n_c > crate::EnumerationOptions::default().max_n)
        {
            out.residual = super::Fc2dResidual::compute(problem, &out.r, &mut out.u);
            out.status = Status::TooLarge;
            return Ok(());
        }
        if !self.reduced.eliminate(problem) {
            out.certify(problem, tolerance, Status::NumericalFailure);
            out.status = Status::NumericalFailure;
            return Ok(());
        }
        let reduced = &self.reduced;
        let mu = problem.mu();
        let nc2 = 2 * n_c;
        let lcp_status = if n_c == 0 {
            out.lcp_method = Some(Method::Trivial);
            Status::Solved
        } else {
            let W = |i: usize, j: usize| reduced.w[i + j * nc2];
            let m = 3 * n_c;
            let A = &mut self.a;
            A.clear();
            A.resize(m * m, 0.0);
            for i in 0..n_c {
                for k in 0..n_c {
                    let (nn, nt) = (W(2 * i, 2 * k), W(2 * i, 2 * k + 1));
                    let (tn, tt) = (W(2 * i + 1, 2 * k), W(2 * i + 1, 2 * k + 1));
                    A[i + k * m] = nn - nt * mu[k];
                    A[i + (n_c + k) * m] = nt;
                    A[n_c + i + k * m] = tn - tt * mu[k];
                    A[n_c + i + (n_c + k) * m] = tt;
                }
                A[n_c + i + (2 * n_c + i) * m] = 1.0;
                A[2 * n_c + i + i * m] = 2.0 * mu[i];
                A[2 * n_c + i + (n_c + i) * m] = -1.0;
            }
            self.b.clear();
            self.b.extend((0..m).map(|k| {
                if k < n_c {
                    reduced.q[2 * k]
                } else if k < 2 * n_c {
                    reduced.q[2 * (k - n_c) + 1]
                } else {
                    0.0
                }
            }));
            let Ok(lcp) = LcpRef::from_column_major(m, &self.a, &self.b) else {
                // The problem is valid but its LCP is not: an entry beyond the range the LCP
                // solvers compute in (a μ or a W so large that W_TN - W_TT μ passes
                // `MAX_ENTRY`, or an elimination that overflowed). No pivoting: r = 0 is
                // judged as it stands.
                out.certify(problem, tolerance, Status::NumericalFailure);
                return Ok(());
            };
            let sol = &mut self.solution;
            self.pivoting.solve_into(lcp, None, sol)?;
            out.lcp_method = Some(sol.method);
            out.iterations = sol.iterations;
            for i in 0..n_c {
                let r_n = sol.z[i];
                out.r[2 * i] = r_n;
                // A contact whose ξ_L the basis takes (its w_L = 2 μ P_N - P_R is 0 there)
                // slides, with P_T = μ P_N on the cone's edge exactly; P_R - μ P_N would carry
                // the solve's error on P_R, relative to P_N's own size when P_N is small.
                let l = 2 * n_c + i;
                out.r[2 * i + 1] =
                    if sol.z[l] > sol.w[l] { mu[i] * r_n } else { sol.z[n_c + i] - mu[i] * r_n };
            }
            sol.status
        };
        let nb = reduced.g_vec.len();
        for (b, g) in reduced.g_vec.iter().enumerate() {
            let mut lambda = *g;
            for j in 0..nc2 {
                lambda += reduced.g_mat[b + j * nb] * out.r[j];
            }
            out.r[nc2 + b] = lambda;
        }
        let otherwise = match lcp_status {
            Status::Solved => Status::NumericalFailure,
            other => other,
        };
        out.certify(problem, tolerance, otherwise);
        if let Some(newton) = &mut self.polish
            && !out.is_solved()
            && lcp_status != Status::NoSolution
            && out.r.iter().all(|v| v.is_finite())
        {
            let candidate = &mut self.candidate;
            std::mem::swap(candidate, out);
            newton.solve_into(problem, Some(&candidate.r), out)?;
            if out.residual.natural <= candidate.residual.natural {
                out.method = Method::LcpRoute;
                out.lcp_method = candidate.lcp_method;
                out.iterations += candidate.iterations;
            } else {
                std::mem::swap(candidate, out);
            }
        }
        Ok(())
    }
}
