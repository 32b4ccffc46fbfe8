//! The proximal point method for planar frictional contact, its sub-problems solved by
//! nonsmooth Newton: the robust route for dense packings whose W is singular.

use serde::{Deserialize, Serialize};

use super::residual::project_cone;
use super::solution::check_warm_start;
use super::{Fc2dParts, Fc2dRef, Fc2dResidual, Fc2dSolution, Fc2dSolver, Newton, NewtonOptions};
use crate::error::rules;
use crate::{LcpError, Method, Status};

/// Options of [`Proximal`]: the default, changed field by field with the `with_*` setters
/// (or by assigning the fields of a default value).
///
/// ```
/// use moreau_lcp::fc2d::{Proximal, ProximalOptions};
///
/// # fn main() -> Result<(), moreau_lcp::LcpError> {
/// let options = ProximalOptions::default().with_tolerance(1e-10).with_max_outer(50);
/// assert_eq!((options.tolerance, options.max_outer), (1e-10, 50));
/// let solver = Proximal::new(options)?;
/// # let _ = solver;
/// # Ok(())
/// # }
/// ```
///
/// The struct is `#[non_exhaustive]`, so that fields added later keep their defaults in
/// callers' code; a struct literal does not compile outside this crate:
///
/// ```compile_fail,E0639
/// let options = moreau_lcp::fc2d::ProximalOptions { tolerance: 1e-10, ..Default::default() };
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct ProximalOptions {
    /// Accept r when `natural <= max(tolerance, round_off)` ([`Fc2dResidual::meets`]).
    /// Default 1e-8.
    pub tolerance: f64,
    /// Largest number of proximal (outer) iterations. Default 300.
    pub max_outer: usize,
    /// Newton iterations allowed to each sub-problem. Default 15.
    pub inner_iterations: usize,
    /// Gauss-Seidel sweeps after each accepted Newton step of a sub-problem
    /// ([`NewtonOptions::smoothing_sweeps`]). Default 20.
    pub smoothing_sweeps: usize,
    /// Past merits the sub-problems' line search compares with
    /// ([`NewtonOptions::nonmonotone`]). Default 10.
    pub nonmonotone: usize,
    /// The first proximal weight α (dimensionless): `η_i = α W_NN,ii` for both rows of
    /// contact i (`α W_bb` for a bilateral row). Default 1e-2.
    pub initial_weight: f64,
    /// Factor in (0, 1) applied to α after a successful outer iteration. Default 0.3.
    pub shrink: f64,
    /// Factor > 1 applied to α after a failed one. Default 10.
    pub grow: f64,
}

with_setters!(ProximalOptions {
    with_tolerance => tolerance: f64,
    with_max_outer => max_outer: usize,
    with_inner_iterations => inner_iterations: usize,
    with_smoothing_sweeps => smoothing_sweeps: usize,
    with_nonmonotone => nonmonotone: usize,
    with_initial_weight => initial_weight: f64,
    with_shrink => shrink: f64,
    with_grow => grow: f64,
});

impl Default for ProximalOptions {
    fn default() -> Self {
        ProximalOptions {
            tolerance: 1e-8,
            max_outer: 300,
            inner_iterations: 15,
            smoothing_sweeps: 20,
            nonmonotone: 10,
            initial_weight: 1e-2,
            shrink: 0.3,
            grow: 10.0,
        }
    }
}

/// Smallest proximal weight α: below it the sub-problem is as singular as the problem.
const MIN_WEIGHT: f64 = 1e-12;

/// Largest proximal weight α: above it a sub-problem barely moves r.
const MAX_WEIGHT: f64 = 1e4;

/// The proximal point method (Rockafellar 1976) on the planar frictional-contact problem,
/// each sub-problem solved by [`Newton`].
///
/// From r_k, the sub-problem is the same contact problem with W and q replaced by
///
/// ```text
/// W_η = W + η,   q_η = q - η r_k     (η = diag(η_i), η_i = α W_NN,ii)
/// ```
///
/// that is, u = W r + q + η (r - r_k): a regularised problem whose W_η is positive
/// definite, so that its reactions are unique and Newton's Jacobian is regular even when W
/// is singular (more contact rows than degrees of freedom in a dense packing, where Newton
/// on the problem itself crawls or cycles). Its solution r_{k+1} satisfies the problem's
/// laws up to the term η (r_{k+1} - r_k), which vanishes as the iterates settle. Each
/// sub-problem is started from r_k. An outer iteration whose sub-problem is solved, or
/// whose result lowers the problem's residual, is accepted and α shrinks (the steps get
/// longer, the convergence faster); otherwise r_k is kept and α grows (the sub-problem
/// gets easier). The solve ends [`Status::Solved`] when the shared [`Fc2dResidual`] of
/// r_k is within the tolerance, [`Status::IterationLimit`] after `max_outer` outer
/// iterations. [`Fc2dSolution::iterations`] counts the Newton iterations of all
/// sub-problems.
///
/// A warm start gives r_0 (default 0). Each outer iteration copies W's blocks (their
/// diagonal shifted); the sub-problems share one Newton workspace, whose symbolic
/// analysis is made once per problem.
///
/// # References
/// - R. T. Rockafellar, Monotone operators and the proximal point algorithm, SIAM
///   Journal on Control and Optimization 14 (1976) 877-898.
/// - V. Acary, M. Brémond, O. Huber, On solving contact problems with Coulomb friction:
///   formulations and numerical comparisons, in Advanced Topics in Nonsmooth Dynamics,
///   Springer, 2018, 375-457.
pub struct Proximal {
    options: ProximalOptions,
    newton: Newton,
    inner: Fc2dSolution,
    blocks: Vec<[f64; 4]>,
    q: Vec<f64>,
    /// W's diagonal entry per row (W_NN,ii for both rows of a contact).
    scale: Vec<f64>,
    r: Vec<f64>,
    u: Vec<f64>,
}

impl std::fmt::Debug for Proximal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Proximal").field("options", &self.options).finish_non_exhaustive()
    }
}

impl Default for Proximal {
    fn default() -> Self {
        Proximal::new(ProximalOptions::default()).expect("the default options are valid")
    }
}

impl Proximal {
    /// A solver with the given options.
    ///
    /// # Errors
    /// [`LcpError::InvalidOption`] unless `tolerance` is finite and > 0, `max_outer`,
    /// `inner_iterations` and `nonmonotone` are >= 1, `1e-12 <= initial_weight <= 1e4`, `0 < shrink < 1`
    /// and `grow > 1`.
    pub fn new(options: ProximalOptions) -> Result<Proximal, LcpError> {
        rules::tolerance(options.tolerance)?;
        rules::count("max_outer", options.max_outer)?;
        rules::count("inner_iterations", options.inner_iterations)?;
        if !(MIN_WEIGHT..=MAX_WEIGHT).contains(&options.initial_weight) {
            return Err(rules::invalid("initial_weight", "must be in [1e-12, 1e4]"));
        }
        if !(options.shrink > 0.0 && options.shrink < 1.0) {
            return Err(rules::invalid("shrink", "must be in (0, 1)"));
        }
        if !(options.grow > 1.0 && options.grow.is_finite()) {
            return Err(rules::invalid("grow", "must be finite and > 1"));
        }
        // The sub-problems are solved well below the tolerance, so that the proximal
        // term, not the inner error, is what is left of the problem's residual.
        let newton = Newton::new(NewtonOptions {
            tolerance: 0.01 * options.tolerance,
            max_iterations: options.inner_iterations,
            smoothing_sweeps: options.smoothing_sweeps,
            nonmonotone: options.nonmonotone,
            ..Default::default()
        })?;
        Ok(Proximal {
            options,
            newton,
            inner: Fc2dSolution::new(),
            blocks: Vec::new(),
            q: Vec::new(),
            scale: Vec::new(),
            r: Vec::new(),
            u: Vec::new(),
        })
    }

    /// The options.
    pub fn options(&self) -> &ProximalOptions {
        &self.options
    }
}

impl Fc2dSolver for Proximal {
    fn solve_into(
        &mut self,
        problem: Fc2dRef<'_>,
        warm_start: Option<&[f64]>,
        out: &mut Fc2dSolution,
    ) -> Result<(), LcpError> {
        check_warm_start(problem, warm_start)?;
        let n = problem.n_rows();
        let tolerance = self.options.tolerance;
        out.reset(n, Method::ProximalNewton);
        if problem.n_groups() == 0 {
            out.method = Method::Trivial;
            out.certify(problem, tolerance, Status::NumericalFailure);
            return Ok(());
        }
        let p = problem.parts();
        let gs = p.group_start;
        self.scale.clear();
        self.scale.resize(n, 0.0);
        for g in 0..problem.n_groups() {
            let k = (p.row_ptr[g]..p.row_ptr[g + 1])
                .find(|&k| p.col[k] as usize == g)
                .expect("a validated problem stores every diagonal block");
            let block = p.blocks[k];
            for (row, s) in (gs[g]..gs[g + 1]).zip([block[0], block[3]]) {
                // A contact's tangential row takes the normal entry, so that η keeps the
                // cone's shape (η_N = η_T); a zero entry gets a unit weight.
                let w = if g < p.n_contacts { block[0] } else { s };
                self.scale[row] = if w > 0.0 { w } else { 1.0 };
            }
        }
        self.r.clear();
        if let Some(w) = warm_start {
            self.r.extend_from_slice(w);
        } else {
            self.r.resize(n, 0.0);
        }
        for (i, &mu) in problem.mu().iter().enumerate() {
            let (a, b) = project_cone(self.r[2 * i], self.r[2 * i + 1], mu);
            self.r[2 * i] = a;
            self.r[2 * i + 1] = b;
        }
        self.u.clear();
        self.u.resize(n, 0.0);
        let mut best = Fc2dResidual::compute(problem, &self.r, &mut self.u);
        let mut iterations = 0;
        let mut alpha = self.options.initial_weight;
        let mut status = Status::IterationLimit;
        for _ in 0..self.options.max_outer {
            self.blocks.clear();
            self.blocks.extend_from_slice(p.blocks);
            for g in 0..problem.n_groups() {
                for k in p.row_ptr[g]..p.row_ptr[g + 1] {
                    if p.col[k] as usize == g {
                        self.blocks[k][0] += alpha * self.scale[gs[g]];
                        if gs[g + 1] - gs[g] == 2 {
                            self.blocks[k][3] += alpha * self.scale[gs[g] + 1];
                        }
                    }
                }
            }
            self.q.clear();
            self.q.extend((0..n).map(|i| p.q[i] - alpha * self.scale[i] * self.r[i]));
            // A sub-problem beyond the range of a valid problem (q − η r_k from a warm start
            // far out, such as r = 1e300) is the method's failure, not the caller's input.
            let Ok(sub) = Fc2dRef::from_parts(Fc2dParts { blocks: &self.blocks, q: &self.q, ..p })
            else {
                status = Status::NumericalFailure;
                break;
            };
            self.newton.solve_into(sub, Some(&self.r), &mut self.inner)?;
            iterations += self.inner.iterations;
            let trial = Fc2dResidual::compute(problem, &self.inner.r, &mut self.u);
            if !trial.natural.is_finite() {
                status = Status::NumericalFailure;
                break;
            }
            if self.inner.status == Status::Solved || trial.natural < best.natural {
                self.r.copy_from_slice(&self.inner.r);
                best = trial;
                alpha = (alpha * self.options.shrink).max(MIN_WEIGHT);
            } else {
                alpha = (alpha * self.options.grow).min(MAX_WEIGHT);
            }
            if best.meets(tolerance) {
                break;
            }
        }
        out.r.clear();
        out.r.extend_from_slice(&self.r);
        out.method = Method::ProximalNewton;
        out.lcp_method = None;
        out.iterations = iterations;
        out.certify(problem, tolerance, status);
        Ok(())
    }
}
