//! Projected Gauss-Seidel with over-relaxation.
#![allow(non_snake_case)]

use serde::{Deserialize, Serialize};

use crate::error::rules;
use crate::solution::{check_warm_start, finish_row_major};
use crate::{LcpError, LcpRef, Method, Solution, Solver, Status};

/// Options of [`Pgs`]: the default, changed field by field with the `with_*` setters
/// (or by assigning the fields of a default value).
///
/// ```
/// use moreau_lcp::{Pgs, PgsOptions};
///
/// # fn main() -> Result<(), moreau_lcp::LcpError> {
/// let options = PgsOptions::default().with_omega(1.2).with_tolerance(1e-9);
/// assert_eq!((options.omega, options.tolerance), (1.2, 1e-9));
/// let solver = Pgs::new(options)?;
/// # let _ = solver;
/// # Ok(())
/// # }
/// ```
///
/// The struct is `#[non_exhaustive]`, so that fields added later keep their defaults in
/// callers' code; a struct literal does not compile outside this crate:
///
/// ```compile_fail,E0639
/// let options = moreau_lcp::PgsOptions { omega: 1.2, ..Default::default() };
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct PgsOptions {
    /// Relaxation factor ω in (0, 2) (dimensionless). Default 1.0 (plain Gauss-Seidel).
    pub omega: f64,
    /// Stop when [`Residual::natural`](crate::Residual::natural) and
    /// [`Residual::relative`](crate::Residual::relative) are both `<= tolerance`
    /// (dimensionless). Default 1e-10.
    pub tolerance: f64,
    /// Largest number of sweeps over all rows. Default 10000.
    pub max_iterations: usize,
}

with_setters!(PgsOptions {
    with_omega => omega: f64,
    with_tolerance => tolerance: f64,
    with_max_iterations => max_iterations: usize,
});

impl PgsOptions {
    /// Checks the options: `0 < omega < 2`, `0 < tolerance < 1` (z = 0 measures at most 1,
    /// so 1 or more would accept it whatever the problem), `max_iterations >= 1`.
    ///
    /// # Errors
    /// [`LcpError::InvalidOption`] naming the first field out of range.
    pub fn validate(&self) -> Result<(), LcpError> {
        rules::omega(self.omega)?;
        rules::relative_tolerance(self.tolerance)?;
        rules::count("max_iterations", self.max_iterations)
    }
}

impl Default for PgsOptions {
    fn default() -> Self {
        PgsOptions { omega: 1.0, tolerance: 1e-10, max_iterations: 10_000 }
    }
}

/// Projected Gauss-Seidel (PGS) with over-relaxation ω.
///
/// One sweep updates, for i = 1..n in turn and with the newest values of z,
///
/// `z_i <- max(0, z_i - ω (M z + q)_i / M_ii)`,
///
/// the exact minimisation of the quadratic `z'Mz/2 + q'z` over `z_i >= 0` for ω = 1.
/// After each sweep w = M z + q is recomputed and the sweep count is the iteration
/// count. The iterates converge for symmetric positive definite M and 0 < ω < 2, and for
/// M with positive diagonal that is strictly diagonally dominant by rows; for other M they
/// may not, and the status is then [`Status::IterationLimit`] (or
/// [`Status::NumericalFailure`] if they stop being finite, in which case the last finite
/// iterate is returned). A warm start z (projected onto z >= 0) is accepted; the default
/// start is z = 0.
///
/// **Precondition.** Every diagonal entry must be positive: the update divides by M_ii,
/// and with M_ii <= 0 the one-dimensional subproblem in z_i is unbounded or has no unique
/// minimiser. Such problems return [`LcpError::NonPositiveDiagonal`]; use
/// [`Lemke`](crate::Lemke). The friction LCP of the time-stepper has a zero block on its
/// diagonal and is therefore not for PGS.
///
/// # References
/// - R. W. Cottle, J.-S. Pang, R. E. Stone, The Linear Complementarity Problem, Academic
///   Press, 1992, §5.2.
/// - J. J. Moreau, Unilateral contact and dry friction in finite freedom dynamics, in
///   Nonsmooth Mechanics and Applications, CISM 302, Springer, 1988.
#[derive(Default)]
pub struct Pgs {
    options: PgsOptions,
    m_rows: Vec<f64>,
    q: Vec<f64>,
    inv_diag: Vec<f64>,
    backup: Vec<f64>,
}

impl Pgs {
    /// A solver with the given options.
    ///
    /// # Errors
    /// [`LcpError::InvalidOption`] when [`PgsOptions::validate`] refuses the options.
    pub fn new(options: PgsOptions) -> Result<Pgs, LcpError> {
        options.validate()?;
        Ok(Pgs { options, ..Pgs::default() })
    }

    /// The options in use.
    pub fn options(&self) -> &PgsOptions {
        &self.options
    }
}

impl Solver for Pgs {
    fn solve_into(
        &mut self,
        lcp: LcpRef<'_>,
        warm_start: Option<&[f64]>,
        out: &mut Solution,
    ) -> Result<(), LcpError> {
        let n = lcp.n();
        check_warm_start(n, warm_start)?;
        self.m_rows.resize(n * n, 0.0);
        self.q.resize(n, 0.0);
        self.inv_diag.resize(n, 0.0);
        self.backup.resize(n, 0.0);
        lcp.copy_m_row_major(&mut self.m_rows);
        lcp.copy_q(&mut self.q);
        for i in 0..n {
            let d = self.m_rows[i * n + i];
            if !(d > 0.0) {
                return Err(LcpError::NonPositiveDiagonal { index: i, value: d });
            }
            self.inv_diag[i] = 1.0 / d;
        }
        out.reset(n, Method::Pgs);
        if let Some(z) = warm_start {
            for (dst, src) in out.z.iter_mut().zip(z) {
                *dst = src.max(0.0);
            }
        }
        let PgsOptions { omega, tolerance, max_iterations } = self.options;
        let (m, q) = (&self.m_rows, &self.q);
        out.residual = finish_row_major(m, n, q, &out.z, &mut out.w);
        if out.residual.natural <= tolerance && out.residual.relative <= tolerance {
            out.status = Status::Solved;
            return Ok(());
        }
        out.status = Status::IterationLimit;
        for sweep in 1..=max_iterations {
            self.backup.copy_from_slice(&out.z);
            for i in 0..n {
                let row = &m[i * n..(i + 1) * n];
                let mut r = q[i];
                for (a, b) in row.iter().zip(out.z.iter()) {
                    r += a * b;
                }
                let zi = out.z[i];
                out.z[i] = (zi - omega * r * self.inv_diag[i]).max(0.0);
            }
            out.iterations = sweep;
            if out.z.iter().any(|v| !v.is_finite()) {
                out.z.copy_from_slice(&self.backup);
                out.residual = finish_row_major(m, n, q, &out.z, &mut out.w);
                out.status = Status::NumericalFailure;
                out.drop_non_finite(q);
                return Ok(());
            }
            out.residual = finish_row_major(m, n, q, &out.z, &mut out.w);
            if out.residual.natural <= tolerance && out.residual.relative <= tolerance {
                out.status = Status::Solved;
                return Ok(());
            }
        }
        out.drop_non_finite(q);
        Ok(())
    }
}
