//! Options of the time-stepper: the step size h and the LCP solver.

use serde::{Deserialize, Serialize};

use crate::StepError;

/// Which LCP solver a step uses when contacts are closed.
///
/// Whatever the choice, a step whose LCP solution fails the residual test stops the run with
/// [`StepError::LcpFailed`]; the choice trades robustness for speed, never correctness.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum SolverChoice {
    /// The default: a single active contact in closed form (stick or slip either way, taken
    /// when the LCP's residual passes), otherwise the robust strategy of `moreau_lcp::Auto`:
    /// z = 0 when b ≥ 0, the complementary basis named by the previous step's impulses
    /// (solved directly, taken when its residual passes), Lemke, Lemke with other covering
    /// vectors, then enumeration for small problems.
    #[default]
    Auto,
    /// Lemke's complementary pivoting alone.
    Lemke,
    /// Gauss-Seidel, warm-started from the previous step's impulses: projected Gauss-Seidel
    /// on the normal LCP when no active contact has friction, else the nonsmooth block
    /// Gauss-Seidel of `moreau_lcp::fc2d::Nsgs` on the step's contact problem.
    Pgs {
        /// Tolerance on the scaled natural residual: ‖min(z, w)‖∞ of the normal LCP, or
        /// `Fc2dResidual::natural` of the contact problem (dimensionless).
        tolerance: f64,
        /// Over-relaxation factor ω in (0, 2).
        omega: f64,
        /// Largest number of sweeps per step.
        max_iterations: usize,
    },
    /// Enumeration of all complementary bases (for tiny problems only).
    Enumeration,
}

impl SolverChoice {
    /// Projected Gauss-Seidel with tolerance 1e-10, ω = 1 and 10 000 sweeps at most.
    pub fn pgs_default() -> Self {
        Self::Pgs { tolerance: 1e-10, omega: 1.0, max_iterations: 10_000 }
    }

    /// Parses a solver name: `auto`, `lemke`, `pgs` (with [`Self::pgs_default`]) or `enum`.
    ///
    /// # Errors
    /// [`StepError::UnknownSolver`] naming the accepted values.
    pub fn parse(name: &str) -> Result<Self, StepError> {
        match name {
            "auto" => Ok(Self::Auto),
            "lemke" => Ok(Self::Lemke),
            "pgs" => Ok(Self::pgs_default()),
            "enum" | "enumeration" => Ok(Self::Enumeration),
            other => Err(StepError::UnknownSolver { name: other.to_owned() }),
        }
    }

    /// The short name accepted by [`Self::parse`].
    pub fn name(&self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Lemke => "lemke",
            Self::Pgs { .. } => "pgs",
            Self::Enumeration => "enum",
        }
    }
}

/// Options of a [`crate::Stepper`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StepperOptions {
    /// Time step Δt (s); must be finite and positive.
    pub dt: f64,
    /// The LCP solver; [`SolverChoice::Auto`] by default.
    #[serde(default)]
    pub solver: SolverChoice,
    /// Give frictionless contacts (μ = 0) the two friction rows too, so that the LCP has
    /// three rows per active contact. The velocities are the same either way (the rows force
    /// P_R = P_L = 0); this exists to verify that and to compare with codes that always
    /// assemble them. Default `false`: a frictionless contact has only its normal row.
    #[serde(default)]
    pub friction_rows_when_frictionless: bool,
    /// Active-set threshold (m): contact i enters the LCP when g_N,i(q_M, t_M) ≤ this value.
    /// Default 0, the scheme exactly as written. After an LCP step that closes a contact, the
    /// next midpoint gap is zero only up to round-off (γ_N,E ≈ 1e-19 m/s, say); when it comes
    /// out positive, the contact drops out of one step and the body falls freely for Δt,
    /// which shifts a resting or sliding body by about g Δt²/2. A threshold of a few orders of
    /// magnitude above round-off in the mechanism's length unit (1e-12 m, say) keeps such
    /// contacts closed and changes nothing else.
    #[serde(default)]
    pub gap_tolerance: f64,
    /// Project the end positions q_E back onto g_N ≥ 0 after each step (along M⁻¹ W_N, the
    /// smallest change in the kinetic metric), leaving the velocities alone. The scheme as
    /// written has none (default `false`); the penetration it leaves is O(Δt) per impact and
    /// can accumulate as drift where contacts stay closed over long runs, e.g. a slider in a
    /// clearance of micrometres.
    #[serde(default)]
    pub projection: bool,
}

impl StepperOptions {
    /// Options with time step `dt` and the default solver.
    pub fn new(dt: f64) -> Self {
        Self {
            dt,
            solver: SolverChoice::Auto,
            friction_rows_when_frictionless: false,
            gap_tolerance: 0.0,
            projection: false,
        }
    }

    /// The same options with an active-set threshold (see [`Self::gap_tolerance`]).
    pub fn with_gap_tolerance(mut self, gap_tolerance: f64) -> Self {
        self.gap_tolerance = gap_tolerance;
        self
    }

    /// The same options with another solver.
    pub fn with_solver(mut self, solver: SolverChoice) -> Self {
        self.solver = solver;
        self
    }
}
