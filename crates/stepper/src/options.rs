//! Options of the time-stepper: the step size h and the LCP solver.

use moreau_lcp::{LcpError, PgsOptions};
use serde::{Deserialize, Serialize};

/// Which LCP solver a step uses when contacts are closed.
///
/// Whatever the choice, a step whose LCP solution fails the residual test stops the run with
/// [`crate::StepError::LcpFailed`]; the choice trades robustness for speed, never correctness.
///
/// Read from a table such as `{ kind = "pgs", tolerance = 1e-10, omega = 1.0,
/// max_iterations = 10000 }`: a field the kind does not have is refused for every kind, and
/// PGS' settings must lie in their ranges (tolerance in (0, 1), ω in (0, 2), at least one
/// sweep).
#[derive(Clone, Copy, Debug, PartialEq, Default, Serialize, Deserialize)]
#[serde(try_from = "SolverTable", into = "SolverTable")]
#[non_exhaustive]
pub enum SolverChoice {
    /// The default: a single active contact in closed form (stick or slip either way, taken
    /// when the LCP's residual passes), otherwise the robust strategy of `moreau_lcp::Auto`:
    /// z = 0 when b ≥ 0, the complementary basis named by the previous step's impulses
    /// (solved directly, taken when its residual passes), Lemke, Lemke with other covering
    /// vectors, then enumeration for small problems. Steps with more than 24 closed contacts
    /// go to the equivalent frictional-contact problem instead, solved as an island of
    /// detected contacts is (`moreau_lcp::fc2d::Fc2dAuto`, block Gauss-Seidel warm-started
    /// from the previous impulses with exact solves of the clusters that stall; then
    /// nonsmooth Newton, the proximal point method and pivoting), whose cost grows with the
    /// contacts' couplings rather than as the cube of the LCP's size; so do steps whose LCP
    /// pivoting leaves unsolved (bodies whose masses differ by orders of magnitude).
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

/// The table form of [`SolverChoice`]. Its unit-like kinds are empty struct variants because
/// serde ignores unknown fields next to the tag of a unit variant.
#[derive(Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
enum SolverTable {
    Auto {},
    Lemke {},
    Pgs { tolerance: f64, omega: f64, max_iterations: usize },
    Enumeration {},
}

impl TryFrom<SolverTable> for SolverChoice {
    type Error = String;

    fn try_from(t: SolverTable) -> Result<Self, String> {
        Ok(match t {
            SolverTable::Auto {} => Self::Auto,
            SolverTable::Lemke {} => Self::Lemke,
            SolverTable::Enumeration {} => Self::Enumeration,
            SolverTable::Pgs { tolerance, omega, max_iterations } => {
                // The solver's own rules, so that a table is refused exactly when the
                // solver would refuse its options.
                PgsOptions::default()
                    .with_omega(omega)
                    .with_tolerance(tolerance)
                    .with_max_iterations(max_iterations)
                    .validate()
                    .map_err(|e| match e {
                        LcpError::InvalidOption { name, reason } => {
                            format!("solver.{name} {reason}")
                        }
                        e => e.to_string(),
                    })?;
                Self::Pgs { tolerance, omega, max_iterations }
            }
        })
    }
}

impl From<SolverChoice> for SolverTable {
    fn from(c: SolverChoice) -> Self {
        match c {
            SolverChoice::Auto => Self::Auto {},
            SolverChoice::Lemke => Self::Lemke {},
            SolverChoice::Enumeration => Self::Enumeration {},
            SolverChoice::Pgs { tolerance, omega, max_iterations } => {
                Self::Pgs { tolerance, omega, max_iterations }
            }
        }
    }
}

impl SolverChoice {
    /// Projected Gauss-Seidel with tolerance 1e-10, ω = 1 and 10 000 sweeps at most.
    pub fn pgs_default() -> Self {
        Self::Pgs { tolerance: 1e-10, omega: 1.0, max_iterations: 10_000 }
    }

    /// The short name that [`str::parse`] accepts (`auto`, `lemke`, `pgs`, `enum`).
    pub fn name(&self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Lemke => "lemke",
            Self::Pgs { .. } => "pgs",
            Self::Enumeration => "enum",
        }
    }
}

/// A solver name that is none of `auto`, `lemke`, `pgs`, `enum` (or `enumeration`).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown LCP solver '{name}'; accepted: auto, lemke, pgs, enum")]
pub struct UnknownSolver {
    /// The name given.
    pub name: String,
}

impl std::str::FromStr for SolverChoice {
    type Err = UnknownSolver;

    /// Parses a solver name: `auto`, `lemke`, `pgs` (with [`SolverChoice::pgs_default`]) or
    /// `enum`.
    fn from_str(name: &str) -> Result<Self, UnknownSolver> {
        match name {
            "auto" => Ok(Self::Auto),
            "lemke" => Ok(Self::Lemke),
            "pgs" => Ok(Self::pgs_default()),
            "enum" | "enumeration" => Ok(Self::Enumeration),
            other => Err(UnknownSolver { name: other.to_owned() }),
        }
    }
}

/// Options of a [`crate::Stepper`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[non_exhaustive]
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
    /// Default 0, the scheme exactly as written. After an LCP step that closes a contact at
    /// g_N = 0 (a body started at rest or sliding on its support), the next midpoint gap is
    /// zero only up to round-off (γ_N,E ≈ 1e-19 m/s, say); when it comes out positive, the
    /// contact drops out of one step and the body falls freely for Δt. No error says so: the
    /// body lands in the next step with an impact at γ_N,A = −g Δt, listed in
    /// `Record::impacts`, and rests g Δt² deep (1e-5 m at Δt = 1 ms), and a contact held by
    /// friction loses its grip for that step (a body pushed by F below μ m g slips
    /// F Δt² / m). A threshold of a few orders of magnitude above round-off in the
    /// mechanism's length unit (1e-12 m, say) keeps such contacts closed and changes nothing
    /// else; a declared mechanism's options give one relative to its size.
    #[serde(default)]
    pub gap_tolerance: f64,
    /// Project the end positions q_E back onto g_N ≥ 0 after each step (along M⁻¹ W_N, the
    /// smallest change in the kinetic metric, or for rigid bodies in maximal coordinates in
    /// the metric where every body weighs alike: see
    /// [`crate::Mechanism::maximal_coordinates`]), leaving the velocities alone. The scheme as
    /// written has none (default `false`); the penetration it leaves is O(Δt) per impact and
    /// can accumulate as drift where contacts stay closed over long runs, e.g. a slider in a
    /// clearance of micrometres.
    #[serde(default)]
    pub projection: bool,
    /// The penetration (in the mechanism's length unit) that the contact projection leaves
    /// alone: it runs only when some g_N(q_E) < −`projection_tolerance`. Default 0.
    ///
    /// Moving q_E without changing u_E disturbs contacts that rest (γ_N,E = 0 with ε_N = 0):
    /// the projection's linearised step leaves their gaps slightly positive, the next
    /// midpoint opens them, they fall back within a few steps, penetrate by O(g Δt²) and are
    /// projected again, so that a resting contact opens and closes every few steps. A
    /// tolerance above the penetration of a resting contact (g Δt², say) and far below any
    /// clearance lets resting contacts stay closed, as in the scheme without projection, and
    /// still removes the penetration of impacts and its drift.
    #[serde(default)]
    pub projection_tolerance: f64,
    /// The drift |g_B| of the bilateral constraints (in their unit, the mechanism's length
    /// unit for joints) that the correction of the positions after a step leaves alone.
    /// Default 0: 1e-12 max(1, ‖q‖∞), round-off of coordinates of order one or above in their
    /// unit. A mechanism much smaller than its length unit (a part of a millimetre in metres)
    /// needs a tolerance relative to its own size, which a declared mechanism gives (1e-12 of
    /// its size), so that it is corrected alike in any unit.
    #[serde(default)]
    pub joint_tolerance: f64,
    /// For a mechanism with a [`crate::BodyStructure`]: the natural residual
    /// (`moreau_lcp::fc2d::Fc2dResidual::natural`, dimensionless) up to which an island that
    /// the default solver's chain (or the chosen solver) leaves above its tolerance is still
    /// taken. Default 0: such an island ends the run with
    /// [`StepError::IslandFailed`](crate::StepError::IslandFailed).
    ///
    /// Dense frictional packings arrested by impacts (a column of grains while it settles)
    /// give problems where Gauss-Seidel's residual falls only as the inverse of its sweeps
    /// (about 1e-4 after 5,000 sweeps on 500 contacts at μ = 0.3) and Newton's method cycles.
    /// With a positive value, a large island is taken as soon as Gauss-Seidel has it at or
    /// below this residual and the reduction of its last 250 sweeps, kept up, would not reach
    /// the tolerance within the budget of 5,000 (so after 500 sweeps where the residual falls
    /// as the inverse of the sweeps), without Newton or pivoting; an island still above it
    /// after the budget goes through the whole chain. The step's [`LcpInfo`](crate::LcpInfo) then has status
    /// `IterationLimit` and its residual, and [`RunSummary`](crate::RunSummary) counts such
    /// steps. The residual is in the units of velocity and impulse, relative to the free
    /// velocities above 1 (m/s): 1e-4 leaves velocity errors of about 0.1 mm/s. An island
    /// whose heaviest body is far from 1 kg (its smallest normal diagonal entry of W outside
    /// 1/16 to 16) is solved with its impulses divided by the power of two that brings that
    /// entry near 1, so that its residual adds velocities to velocities.
    #[serde(default)]
    pub inexact_residual: f64,
}

impl StepperOptions {
    /// Options with time step `dt`, the default solver, no projection and every threshold at
    /// 0. For a mechanism whose contacts rest or slide, add a gap tolerance above round-off
    /// in its length unit: `StepperOptions::new(dt).with_gap_tolerance(1e-12)` (see
    /// [`Self::gap_tolerance`] for what its default of 0 does).
    pub fn new(dt: f64) -> Self {
        Self {
            dt,
            solver: SolverChoice::Auto,
            friction_rows_when_frictionless: false,
            gap_tolerance: 0.0,
            projection: false,
            projection_tolerance: 0.0,
            joint_tolerance: 0.0,
            inexact_residual: 0.0,
        }
    }

    /// The same options with a residual up to which an island left above the solvers'
    /// tolerance is taken (see [`Self::inexact_residual`]).
    pub fn with_inexact_residual(mut self, residual: f64) -> Self {
        self.inexact_residual = residual;
        self
    }

    /// The same options with an active-set threshold (see [`Self::gap_tolerance`]).
    pub fn with_gap_tolerance(mut self, gap_tolerance: f64) -> Self {
        self.gap_tolerance = gap_tolerance;
        self
    }

    /// The same options with or without the projection of the positions (see
    /// [`Self::projection`]).
    pub fn with_projection(mut self, projection: bool) -> Self {
        self.projection = projection;
        self
    }

    /// The same options with a penetration that the contact projection leaves alone (see
    /// [`Self::projection_tolerance`]).
    pub fn with_projection_tolerance(mut self, tolerance: f64) -> Self {
        self.projection_tolerance = tolerance;
        self
    }

    /// The same options with a drift of the bilateral constraints that the correction of the
    /// positions leaves alone (see [`Self::joint_tolerance`]).
    pub fn with_joint_tolerance(mut self, tolerance: f64) -> Self {
        self.joint_tolerance = tolerance;
        self
    }

    /// The same options with or without friction rows for frictionless contacts (see
    /// [`Self::friction_rows_when_frictionless`]).
    pub fn with_friction_rows_when_frictionless(mut self, rows: bool) -> Self {
        self.friction_rows_when_frictionless = rows;
        self
    }

    /// The same options with another solver.
    pub fn with_solver(mut self, solver: SolverChoice) -> Self {
        self.solver = solver;
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<SolverChoice, String> {
        #[derive(Deserialize)]
        struct S {
            solver: SolverChoice,
        }
        serde_json::from_str::<S>(text).map(|s| s.solver).map_err(|e| e.to_string())
    }

    #[test]
    fn solver_tables_are_read_strictly() {
        assert_eq!(read(r#"{"solver": {"kind": "lemke"}}"#), Ok(SolverChoice::Lemke));
        for kind in ["auto", "lemke", "enumeration"] {
            let e = read(&format!(r#"{{"solver": {{"kind": "{kind}", "max_pivots": 0}}}}"#))
                .expect_err(kind);
            assert!(e.contains("max_pivots"), "{e}");
        }
        let pgs = |t: f64, w: f64, n: usize| {
            read(&format!(
                r#"{{"solver": {{"kind": "pgs", "tolerance": {t}, "omega": {w}, "max_iterations": {n}}}}}"#
            ))
        };
        assert_eq!(
            pgs(1e-8, 1.2, 50),
            Ok(SolverChoice::Pgs { tolerance: 1e-8, omega: 1.2, max_iterations: 50 })
        );
        for (t, w, n, field) in [
            (1.0, 1.0, 10, "tolerance"),
            (0.0, 1.0, 10, "tolerance"),
            (1e-8, 2.0, 10, "omega"),
            (1e-8, 0.0, 10, "omega"),
            (1e-8, 1.0, 0, "max_iterations"),
        ] {
            let e = pgs(t, w, n).expect_err(field);
            assert!(e.contains(field), "{e}");
        }
        let e = read(r#"{"solver": {"kind": "pgs", "tolerance": 1e-8, "omega": 1, "max_iterations": 5, "x": 1}}"#)
            .expect_err("unknown field");
        assert!(e.contains('x'), "{e}");
    }
}
