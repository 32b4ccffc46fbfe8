//! The result of a planar frictional-contact solve and the trait of its solvers.

use serde::{Deserialize, Serialize};

use super::residual::project_cone;
use super::{Fc2d, Fc2dRef, Fc2dResidual};
use crate::{LcpError, Method, Status};

/// The result of a planar frictional-contact solve.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fc2dSolution {
    /// How the solve ended; [`Status::Solved`] only when `residual.natural` is at or below
    /// the solver's tolerance.
    pub status: Status,
    /// Which method produced r.
    pub method: Method,
    /// For a solve through the LCP reformulation, the LCP solver's own method.
    pub lcp_method: Option<Method>,
    /// Reactions (impulses) r, one entry per row: `(r_N, r_T)` per contact, then the
    /// multipliers of the bilateral rows.
    pub r: Vec<f64>,
    /// Velocities u = W r + q, recomputed from r.
    pub u: Vec<f64>,
    /// The work done: Gauss-Seidel sweeps ([`Nsgs`](super::Nsgs), and
    /// [`Fc2dAuto`](super::Fc2dAuto) in total over its windows), Newton iterations
    /// ([`Newton`](super::Newton), and the inner Newton iterations of
    /// [`Proximal`](super::Proximal) summed over its outer ones), or pivots
    /// ([`LcpRoute`](super::LcpRoute), plus the iterations of its Newton polish when one ran).
    pub iterations: usize,
    /// The residual of r; [`Fc2dResidual::INFINITE`] until a solver has measured r.
    pub residual: Fc2dResidual,
    /// `residual.natural` after each sweep, when the solver's options ask for it.
    pub history: Vec<f64>,
}

impl Default for Fc2dSolution {
    fn default() -> Self {
        Self::new()
    }
}

impl Fc2dSolution {
    /// An empty solution with status [`Status::NumericalFailure`] and the residual
    /// [`Fc2dResidual::INFINITE`] (nothing measured yet meets no tolerance), to be filled by
    /// [`Fc2dSolver::solve_into`].
    pub fn new() -> Self {
        Fc2dSolution {
            status: Status::NumericalFailure,
            method: Method::Nsgs,
            lcp_method: None,
            r: Vec::new(),
            u: Vec::new(),
            iterations: 0,
            residual: Fc2dResidual::INFINITE,
            history: Vec::new(),
        }
    }

    /// `true` when the status is [`Status::Solved`].
    pub fn is_solved(&self) -> bool {
        self.status == Status::Solved
    }

    /// Sizes r and u for `rows` rows (reusing their capacity) and resets the rest.
    pub(crate) fn reset(&mut self, rows: usize, method: Method) {
        self.status = Status::NumericalFailure;
        self.method = method;
        self.lcp_method = None;
        self.r.clear();
        self.r.resize(rows, 0.0);
        self.u.clear();
        self.u.resize(rows, 0.0);
        self.iterations = 0;
        self.residual = Fc2dResidual::INFINITE;
        self.history.clear();
    }

    /// Projects each contact's r onto its cone, recomputes u and the residual from r, and
    /// sets the status: `Solved` when the residual is within `tolerance` (or its round-off,
    /// [`Fc2dResidual::meets`]), else `otherwise`.
    ///
    /// The projection leaves an iterate of the cones unchanged, bit for bit; it removes the
    /// round-off of solvers that work in other variables (the LCP route's P_R = P_T + μ P_N
    /// can give P_N = 0 with |P_T| ~ 1e-19), which the natural map accepts but which puts r
    /// outside the cone that Coulomb's law requires exactly.
    pub(crate) fn certify(&mut self, problem: Fc2dRef<'_>, tolerance: f64, otherwise: Status) {
        let gs = problem.parts().group_start;
        for (i, &mu) in problem.mu().iter().enumerate() {
            let k = gs[i];
            (self.r[k], self.r[k + 1]) = project_cone(self.r[k], self.r[k + 1], mu);
        }
        problem.velocity(&self.r, &mut self.u);
        self.residual = Fc2dResidual::of_velocity(problem, &self.r, &self.u, tolerance);
        self.status = if self.residual.meets(tolerance) {
            Status::Solved
        } else if self.residual.natural.is_finite() {
            otherwise
        } else {
            Status::NumericalFailure
        };
    }
}

/// A solver of planar frictional-contact problems.
pub trait Fc2dSolver {
    /// Solves `problem` into `out`, reusing its buffers and the solver's workspace. A warm
    /// start gives initial reactions r (one entry per row); solvers that cannot use one
    /// ignore it.
    ///
    /// # Errors
    /// Invalid options or a warm start of the wrong length or with non-finite entries.
    /// Not converging is a [`Status`], not an error.
    fn solve_into(
        &mut self,
        problem: Fc2dRef<'_>,
        warm_start: Option<&[f64]>,
        out: &mut Fc2dSolution,
    ) -> Result<(), LcpError>;

    /// Solves an owned problem from a cold start.
    ///
    /// # Errors
    /// As [`Fc2dSolver::solve_into`].
    fn solve(&mut self, problem: &Fc2d) -> Result<Fc2dSolution, LcpError> {
        let mut out = Fc2dSolution::new();
        self.solve_into(problem.view(), None, &mut out)?;
        Ok(out)
    }
}

/// Checks a warm start's length and entries.
pub(crate) fn check_warm_start(problem: Fc2dRef<'_>, warm: Option<&[f64]>) -> Result<(), LcpError> {
    if let Some(w) = warm {
        if w.len() != problem.n_rows() {
            return Err(LcpError::WarmStartLength { expected: problem.n_rows(), found: w.len() });
        }
        if let Some(i) = w.iter().position(|v| !v.is_finite()) {
            return Err(LcpError::NonFinite { what: "warm start", index: (i, 0) });
        }
    }
    Ok(())
}
