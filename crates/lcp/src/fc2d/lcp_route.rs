//! The exact LCP reformulation of the planar frictional-contact problem.
#![allow(non_snake_case)]

use faer::Mat;
use faer::linalg::solvers::{DenseSolveCore, Solve};
use serde::{Deserialize, Serialize};

use super::solution::check_warm_start;
use super::{Fc2dRef, Fc2dSolution, Fc2dSolver};
use crate::error::rules;
use crate::{Auto, Enumeration, Lcp, LcpError, Lemke, Method, Solution, Solver, Status};

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

/// Options of [`LcpRoute`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
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
}

impl Default for LcpRouteOptions {
    fn default() -> Self {
        LcpRouteOptions { tolerance: 1e-8, max_contacts: 150, solver: LcpRouteSolver::Auto }
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
/// constraints) ends the solve with [`Status::NumericalFailure`].
///
/// The LCP's solution is mapped back to `r_T = r_R - μ r_N`, λ and u = W r + q, and
/// judged by the FC2D residual. [`Status::NoSolution`] is reported only when the LCP
/// solver's enumeration proved that the LCP has none; problems above `max_contacts`
/// return [`Status::TooLarge`] without a solve. Warm starts are not used.
#[derive(Default)]
pub struct LcpRoute {
    options: LcpRouteOptions,
    solution: Solution,
}

impl LcpRoute {
    /// A solver with the given options.
    ///
    /// # Errors
    /// [`LcpError::InvalidOption`] unless `tolerance` is finite and > 0.
    pub fn new(options: LcpRouteOptions) -> Result<LcpRoute, LcpError> {
        rules::tolerance(options.tolerance)?;
        Ok(LcpRoute { options, solution: Solution::new() })
    }

    /// The options.
    pub fn options(&self) -> &LcpRouteOptions {
        &self.options
    }
}

/// The contacts' W and q after the elimination of the bilateral rows, and the map from
/// contact reactions to multipliers: `λ = G r_c + g`.
struct Reduced {
    w: Mat<f64>,
    q: Vec<f64>,
    g_mat: Mat<f64>,
    g_vec: Vec<f64>,
}

fn eliminate_bilateral(problem: Fc2dRef<'_>) -> Option<Reduced> {
    let n = problem.n_rows();
    let nc2 = 2 * problem.n_contacts();
    let nb = n - nc2;
    let dense = problem.to_dense();
    let W = Mat::from_fn(n, n, |i, j| dense[i + j * n]);
    let q = problem.q();
    if nb == 0 {
        return Some(Reduced { w: W, q: q.to_vec(), g_mat: Mat::zeros(0, nc2), g_vec: Vec::new() });
    }
    let W_bb = W.as_ref().submatrix(nc2, nc2, nb, nb);
    let W_bc = W.as_ref().submatrix(nc2, 0, nb, nc2);
    let W_cb = W.as_ref().submatrix(0, nc2, nc2, nb);
    let lu = W_bb.full_piv_lu();
    let inverse = lu.inverse();
    // A rank-deficient W_bb leaves λ undetermined: recognised by the inverse failing to
    // reproduce the identity.
    let check = &inverse * W_bb;
    let defect = (0..nb)
        .flat_map(|i| (0..nb).map(move |j| (i, j)))
        .map(|(i, j)| (check[(i, j)] - if i == j { 1.0 } else { 0.0 }).abs())
        .fold(0.0f64, f64::max);
    if !(defect <= 1e-8) {
        return None;
    }
    let g_mat = -(&inverse * W_bc);
    let q_b = Mat::from_fn(nb, 1, |i, _| q[nc2 + i]);
    let g_col = -lu.solve(&q_b);
    let w = W.as_ref().submatrix(0, 0, nc2, nc2) + W_cb * &g_mat;
    let w_g = W_cb * &g_col;
    let reduced_q = (0..nc2).map(|i| q[i] + w_g[(i, 0)]).collect();
    Some(Reduced { w, q: reduced_q, g_mat, g_vec: (0..nb).map(|i| g_col[(i, 0)]).collect() })
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
        let Some(reduced) = eliminate_bilateral(problem) else {
            out.certify(problem, tolerance, Status::NumericalFailure);
            out.status = Status::NumericalFailure;
            return Ok(());
        };
        let mu = problem.mu();
        let lcp_status = if n_c == 0 {
            out.lcp_method = Some(Method::Trivial);
            Status::Solved
        } else {
            let W = &reduced.w;
            let m = 3 * n_c;
            let mut A = Mat::<f64>::zeros(m, m);
            for i in 0..n_c {
                for k in 0..n_c {
                    let (nn, nt) = (W[(2 * i, 2 * k)], W[(2 * i, 2 * k + 1)]);
                    let (tn, tt) = (W[(2 * i + 1, 2 * k)], W[(2 * i + 1, 2 * k + 1)]);
                    A[(i, k)] = nn - nt * mu[k];
                    A[(i, n_c + k)] = nt;
                    A[(n_c + i, k)] = tn - tt * mu[k];
                    A[(n_c + i, n_c + k)] = tt;
                }
                A[(n_c + i, 2 * n_c + i)] = 1.0;
                A[(2 * n_c + i, i)] = 2.0 * mu[i];
                A[(2 * n_c + i, n_c + i)] = -1.0;
            }
            let b = faer::Col::from_fn(m, |k| {
                if k < n_c {
                    reduced.q[2 * k]
                } else if k < 2 * n_c {
                    reduced.q[2 * (k - n_c) + 1]
                } else {
                    0.0
                }
            });
            let lcp = Lcp::new(A, b)?;
            let sol = &mut self.solution;
            match self.options.solver {
                LcpRouteSolver::Auto => Auto::default().solve_into(lcp.view(), None, sol)?,
                LcpRouteSolver::Lemke => Lemke::default().solve_into(lcp.view(), None, sol)?,
                LcpRouteSolver::Enumeration => {
                    Enumeration::default().solve_into(lcp.view(), None, sol)?
                }
            }
            out.lcp_method = Some(sol.method);
            out.iterations = sol.iterations;
            for i in 0..n_c {
                let r_n = sol.z[i];
                out.r[2 * i] = r_n;
                out.r[2 * i + 1] = sol.z[n_c + i] - mu[i] * r_n;
            }
            sol.status
        };
        let nc2 = 2 * n_c;
        for (b, g) in reduced.g_vec.iter().enumerate() {
            let mut lambda = *g;
            for j in 0..nc2 {
                lambda += reduced.g_mat[(b, j)] * out.r[j];
            }
            out.r[nc2 + b] = lambda;
        }
        let otherwise = match lcp_status {
            Status::Solved => Status::NumericalFailure,
            other => other,
        };
        out.certify(problem, tolerance, otherwise);
        Ok(())
    }
}
