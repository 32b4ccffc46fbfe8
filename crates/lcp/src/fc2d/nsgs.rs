//! Nonsmooth block Gauss-Seidel (NSGS) for planar frictional contact.

use serde::{Deserialize, Serialize};

use super::local::{solve_bilateral, solve_contact};
use super::residual::{natural_map, project_cone};
use super::solution::check_warm_start;
use super::{Fc2dRef, Fc2dSolution, Fc2dSolver};
use crate::error::rules;
use crate::{LcpError, Method, Status};

/// Options of [`Nsgs`]: the default, changed field by field with the `with_*` setters
/// (or by assigning the fields of a default value).
///
/// ```
/// use moreau_lcp::fc2d::{Nsgs, NsgsOptions};
///
/// # fn main() -> Result<(), moreau_lcp::LcpError> {
/// let options = NsgsOptions::default().with_tolerance(1e-10).with_omega(1.2);
/// assert_eq!((options.tolerance, options.omega), (1e-10, 1.2));
/// let solver = Nsgs::new(options)?;
/// # let _ = solver;
/// # Ok(())
/// # }
/// ```
///
/// The struct is `#[non_exhaustive]`, so that fields added later keep their defaults in
/// callers' code; a struct literal does not compile outside this crate:
///
/// ```compile_fail,E0639
/// let options = moreau_lcp::fc2d::NsgsOptions { tolerance: 1e-10, ..Default::default() };
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct NsgsOptions {
    /// Accept r when `natural <= max(tolerance, round_off)`
    /// ([`Fc2dResidual::meets`](super::Fc2dResidual::meets); natural is in the units of r
    /// and u, relative to q when `‖q‖∞ > 1`). Default 1e-8.
    pub tolerance: f64,
    /// Largest number of sweeps over all contacts and bilateral groups. Default 10,000.
    pub max_sweeps: usize,
    /// Relaxation factor ω in (0, 2) (dimensionless): each group's reaction becomes
    /// `ω r_local + (1 - ω) r_old`, projected back onto the cone for a contact. Default 1.
    pub omega: f64,
    /// Keep [`Fc2dResidual::natural`](super::Fc2dResidual::natural) after every sweep in [`Fc2dSolution::history`]
    /// (which costs one product with W per sweep). Default false.
    pub keep_history: bool,
}

with_setters!(NsgsOptions {
    with_tolerance => tolerance: f64,
    with_max_sweeps => max_sweeps: usize,
    with_omega => omega: f64,
    with_keep_history => keep_history: bool,
});

impl NsgsOptions {
    /// Checks the options: `0 < omega < 2`, `tolerance` finite and > 0, `max_sweeps >= 1`.
    ///
    /// # Errors
    /// [`LcpError::InvalidOption`] naming the first field out of range.
    pub fn validate(&self) -> Result<(), LcpError> {
        rules::omega(self.omega)?;
        rules::tolerance(self.tolerance)?;
        rules::count("max_sweeps", self.max_sweeps)
    }
}

impl Default for NsgsOptions {
    fn default() -> Self {
        NsgsOptions { tolerance: 1e-8, max_sweeps: 10_000, omega: 1.0, keep_history: false }
    }
}

/// The first sweep after which [`Nsgs`] checks the true residual at every power of two,
/// whatever the lagged residual says.
const FIRST_SCHEDULED_CHECK: usize = 64;

/// Nonsmooth block Gauss-Seidel (Moreau 1988, Jean 1999): sweeps over the contacts and
/// bilateral groups in order, solving each group's local problem exactly with the newest
/// reactions of the others.
///
/// For group i with diagonal block W_ii, the velocity the other groups produce is
/// `v_i = q_i + Σ_{j≠i} W_ij r_j`, and the local problem `u_i = W_ii r_i + v_i` with
/// Signorini's and Coulomb's laws (or `u_i = 0` for a bilateral group) is solved in closed
/// form: open, stick, or slip in either direction (see the crate documentation). The
/// local solver needs neither a regular nor an exactly symmetric block.
///
/// **Stopping.** While sweeping, each group's natural map is evaluated at its reaction
/// before the update, with the velocity of the current mixed iterate: a lagged residual
/// that costs a few flops per group. When its maximum, scaled as
/// [`Fc2dResidual::natural`](super::Fc2dResidual::natural), falls to the tolerance, the true residual of the new
/// iterate is computed; the solve ends [`Status::Solved`] only when that is within the
/// tolerance. The lagged residual cannot fall below the round-off of the iterate
/// ([`Fc2dResidual::round_off`](super::Fc2dResidual::round_off)), so the true residual is
/// also computed after sweeps 64, 128, 256, ..., and after any sweep whose lagged residual
/// is below the round-off measured by such a check: a tolerance below round-off is then
/// met at round-off ([`Fc2dResidual::meets`](super::Fc2dResidual::meets)) by sweep
/// max(64, 2 s) when s sweeps reach it, not after `max_sweeps`. The sweep limit ends it with
/// [`Status::IterationLimit`], non-finite
/// iterates with [`Status::NumericalFailure`] (a lagged residual that overflows at a finite
/// iterate only postpones the test to the next sweep).
///
/// **Convergence.** Coulomb's law is not associated, so no convergence is guaranteed even
/// for a positive definite W: the iterates can settle into a cycle (two contacts, both
/// slipping, can alternate between two points for ever), which the status reports as
/// [`Status::IterationLimit`]. Under-relaxation (`omega < 1`) damps such cycles at the cost
/// of slower sweeps; [`Fc2dAuto`](super::Fc2dAuto) hands the contacts where Gauss-Seidel
/// stalls to pivoting instead.
///
/// A warm start gives the initial r (the cone does not need to hold; contacts are
/// projected onto it); the default start is r = 0. The workspace is reused: repeated
/// solves of problems of the same size allocate nothing.
///
/// # References
/// - J. J. Moreau, Unilateral contact and dry friction in finite freedom dynamics, CISM
///   Courses and Lectures 302, Springer, 1988.
/// - M. Jean, The non-smooth contact dynamics method, Computer Methods in Applied
///   Mechanics and Engineering 177 (1999) 235-257.
/// - V. Acary, B. Brogliato, Numerical Methods for Nonsmooth Dynamical Systems, Springer,
///   2008, §13.
#[derive(Clone, Debug, Default)]
pub struct Nsgs {
    options: NsgsOptions,
    /// Reactions, two entries per group (the second is zero for one-row groups).
    x: Vec<f64>,
    /// q in the same layout.
    q: Vec<f64>,
}

impl Nsgs {
    /// A solver with the given options.
    ///
    /// # Errors
    /// [`LcpError::InvalidOption`] unless `0 < omega < 2`, `tolerance` is finite and > 0
    /// and `max_sweeps >= 1`.
    pub fn new(options: NsgsOptions) -> Result<Nsgs, LcpError> {
        options.validate()?;
        Ok(Nsgs { options, x: Vec::new(), q: Vec::new() })
    }

    /// The options.
    pub fn options(&self) -> &NsgsOptions {
        &self.options
    }

    /// One sweep over all groups; returns the largest lagged local residual.
    fn sweep(&mut self, problem: Fc2dRef<'_>) -> f64 {
        let parts = problem.parts();
        let n_c = parts.n_contacts;
        let omega = self.options.omega;
        // Pairs: one bounds check per block instead of two.
        let (x, _) = self.x.as_chunks_mut::<2>();
        let (q, _) = self.q.as_chunks::<2>();
        // Squared norms for the contacts (a square root per contact would cost more than
        // its blocks), plain values for the bilateral rows.
        let mut lagged_sq = 0.0f64;
        let mut lagged_bilateral = 0.0f64;
        for g in 0..problem.n_groups() {
            let (start, end) = (parts.row_ptr[g], parts.row_ptr[g + 1]);
            let [mut v0, mut v1] = q[g];
            let mut diagonal = &[0.0; 4];
            for (b, &j) in parts.blocks[start..end].iter().zip(&parts.col[start..end]) {
                let j = j as usize;
                let [x0, x1] = x[j];
                v0 += b[0] * x0 + b[1] * x1;
                v1 += b[2] * x0 + b[3] * x1;
                if j == g {
                    diagonal = b;
                }
            }
            let d = diagonal;
            let [old0, old1] = x[g];
            // (v0, v1) is u_g at the current iterate; remove the group's own part.
            let (u0, u1) = (v0, v1);
            v0 -= d[0] * old0 + d[1] * old1;
            v1 -= d[2] * old0 + d[3] * old1;
            x[g] = if g < n_c {
                let mu = parts.mu[g];
                let (e0, e1) = natural_map(old0, old1, u0, u1, mu);
                lagged_sq = lagged_sq.max(e0 * e0 + e1 * e1);
                let (r0, r1) = solve_contact(d, v0, v1, mu);
                if omega == 1.0 {
                    [r0, r1]
                } else {
                    let (a, b) = project_cone(
                        omega * r0 + (1.0 - omega) * old0,
                        omega * r1 + (1.0 - omega) * old1,
                        mu,
                    );
                    [a, b]
                }
            } else {
                let rows = parts.group_start[g + 1] - parts.group_start[g];
                let e = if rows == 2 { u0.abs().max(u1.abs()) } else { u0.abs() };
                lagged_bilateral = lagged_bilateral.max(e);
                let (r0, r1) = solve_bilateral(d, (v0, v1), rows, (old0, old1));
                [omega * r0 + (1.0 - omega) * old0, omega * r1 + (1.0 - omega) * old1]
            };
        }
        lagged_sq.sqrt().max(lagged_bilateral)
    }

    /// Copies the padded iterate into r (problem layout) and certifies it.
    fn finish(&self, problem: Fc2dRef<'_>, out: &mut Fc2dSolution, otherwise: Status) {
        let gs = problem.parts().group_start;
        for g in 0..problem.n_groups() {
            out.r[gs[g]] = self.x[2 * g];
            if gs[g + 1] - gs[g] == 2 {
                out.r[gs[g] + 1] = self.x[2 * g + 1];
            }
        }
        out.certify(problem, self.options.tolerance, otherwise);
    }
}

impl Fc2dSolver for Nsgs {
    fn solve_into(
        &mut self,
        problem: Fc2dRef<'_>,
        warm_start: Option<&[f64]>,
        out: &mut Fc2dSolution,
    ) -> Result<(), LcpError> {
        check_warm_start(problem, warm_start)?;
        let groups = problem.n_groups();
        let gs = problem.parts().group_start;
        let mu = problem.mu();
        out.reset(problem.n_rows(), Method::Nsgs);
        self.x.clear();
        self.x.resize(2 * groups, 0.0);
        self.q.clear();
        self.q.resize(2 * groups, 0.0);
        for g in 0..groups {
            for (k, row) in (gs[g]..gs[g + 1]).enumerate() {
                self.q[2 * g + k] = problem.q()[row];
                if let Some(w) = warm_start {
                    self.x[2 * g + k] = w[row];
                }
            }
            if g < problem.n_contacts() {
                let (a, b) = project_cone(self.x[2 * g], self.x[2 * g + 1], mu[g]);
                self.x[2 * g] = a;
                self.x[2 * g + 1] = b;
            }
        }
        if groups == 0 {
            out.method = Method::Trivial;
            out.certify(problem, self.options.tolerance, Status::NumericalFailure);
            return Ok(());
        }
        let scale = problem.q_norm_inf().max(1.0);
        let tolerance = self.options.tolerance;
        // The round-off of the last full check that missed the tolerance (0 before one): a
        // lagged residual below it may be met at round-off, so it is checked in full too.
        let mut floor = 0.0f64;
        for sweep in 1..=self.options.max_sweeps {
            let lagged = self.sweep(problem) / scale;
            out.iterations = sweep;
            if !self.x.iter().all(|v| v.is_finite()) {
                self.finish(problem, out, Status::NumericalFailure);
                out.status = Status::NumericalFailure;
                return Ok(());
            }
            // A lagged residual beyond f64's range with a finite iterate (measured at a start
            // such as r = 1e300, whose natural map squares past f64's range) is no test of
            // the new iterate: it fails `lagged <= tolerance` and the sweeps go on.
            // A tolerance below what floating point resolves at r is never reached by the
            // lagged residual; the full checks at sweeps 64, 128, 256, ... find such an r
            // solved at round-off (at most 3 % more work than the sweeps themselves).
            let scheduled = sweep >= FIRST_SCHEDULED_CHECK && sweep.is_power_of_two();
            if self.options.keep_history
                || lagged <= tolerance.max(floor)
                || scheduled
                || sweep == self.options.max_sweeps
            {
                self.finish(problem, out, Status::IterationLimit);
                floor = floor.max(out.residual.round_off);
                if self.options.keep_history {
                    out.history.push(out.residual.natural);
                }
                if out.status == Status::Solved || out.status == Status::NumericalFailure {
                    return Ok(());
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn options_are_checked() {
        for (options, name) in [
            (NsgsOptions { omega: 2.0, ..Default::default() }, "omega"),
            (NsgsOptions { tolerance: 0.0, ..Default::default() }, "tolerance"),
            (NsgsOptions { max_sweeps: 0, ..Default::default() }, "max_sweeps"),
        ] {
            assert!(
                matches!(Nsgs::new(options), Err(LcpError::InvalidOption { name: n, .. }) if n == name)
            );
        }
        let json = r#"{"tolerance": 1e-6, "omega": 1.2}"#;
        let o: NsgsOptions = serde_json::from_str(json).unwrap();
        assert_eq!((o.tolerance, o.omega, o.max_sweeps), (1e-6, 1.2, 10_000));
        assert!(serde_json::from_str::<NsgsOptions>(r#"{"tolerence": 1e-6}"#).is_err());
    }
}
