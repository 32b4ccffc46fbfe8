//! The stepper's error type.

use moreau_lcp::fc2d::Fc2d;
use moreau_lcp::{Lcp, LcpError, Status};
use moreau_setvalued::SetValuedError;

/// Everything that makes the stepper refuse its input or stop a run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum StepError {
    /// The time step is not finite and positive.
    #[error("time step dt = {dt} must be finite and > 0")]
    InvalidTimeStep {
        /// The rejected step (s).
        dt: f64,
    },
    /// A non-finite number in the state or in what the mechanism returned.
    #[error("non-finite {what} at index {index} (t = {t})")]
    NonFinite {
        /// Which quantity (`q`, `u`, `M`, `h`, `w_N`, ...).
        what: &'static str,
        /// Index of the first non-finite entry.
        index: usize,
        /// Time at which it was found (s).
        t: f64,
    },
    /// An entry of a closed contact's force direction that the mechanism's
    /// `ContactKinematics::contact` (or `contacts`, or `SharedWork::midpoint_contacts`) did not
    /// write. Every entry of w_N and w_T must be written, zeros included: the stepper reuses
    /// the buffers from contact to contact, and it fills them with a marker before each call
    /// so that an entry left alone is found instead of taking another contact's value.
    #[error(
        "{what}[{entry}] of contact {contact} was not written by the mechanism's contact \
         kinematics (t = {t}); every entry of w_N and w_T must be written, zeros included"
    )]
    Unwritten {
        /// Which force direction (`w_N` or `w_T`).
        what: &'static str,
        /// The contact, as an index into the mechanism's contacts.
        contact: usize,
        /// The coordinate of the entry left unwritten (0 to f − 1).
        entry: usize,
        /// Time of the midpoint at which the contact was evaluated (s).
        t: f64,
    },
    /// A vector or list of the wrong length.
    #[error("{what} has length {found}, expected {expected}")]
    Dimension {
        /// Which quantity.
        what: &'static str,
        /// The length the mechanism requires.
        expected: usize,
        /// The length given.
        found: usize,
    },
    /// The mass matrix is not symmetric positive definite.
    #[error("mass matrix M(q, t) is not symmetric positive definite at t = {t}: {reason}")]
    MassNotSpd {
        /// Time of the midpoint at which M was evaluated (s).
        t: f64,
        /// What failed (asymmetry or a non-positive pivot).
        reason: String,
    },
    /// The bilateral constraints cannot be kept: S = W_Bᵀ M⁻¹ W_B is zero (a joint links two
    /// bodies that cannot move), or constraints that repeat each other disagree (a mechanism
    /// its joints lock). Constraints that repeat each other and agree (a parallelogram with a
    /// third crank, a pin stated twice) are solved: S is then singular, and the step solves
    /// it with a ridge of 1e-10 of its largest diagonal entry, refined.
    #[error("bilateral constraints are redundant or singular at t = {t} (W_B' M^-1 W_B: {reason})")]
    RedundantConstraints {
        /// Time of the midpoint where they were evaluated (s).
        t: f64,
        /// Why the factorisation failed.
        reason: String,
    },
    /// The joints have come apart: their drift |g_B| at a step's midpoint exceeds 1e11 times
    /// the drift tolerance (a tenth of a declared mechanism's size; see
    /// `StepperOptions::joint_tolerance`). The step is too long for the joints' motion (a link
    /// that turns through a large angle per step), or the projection is off and the drift has
    /// built up; the run stops rather than go on with bodies that are no longer joined.
    #[error(
        "the joints have come apart at t = {t}: their largest drift |g_B| is {drift:e}, above \
         {limit:e}; take a shorter step or switch the projection on"
    )]
    JointsApart {
        /// Time of the midpoint (s).
        t: f64,
        /// The largest |g_B| at the midpoint (m or rad, as the constraints are written).
        drift: f64,
        /// The largest drift taken.
        limit: f64,
    },
    /// The correction of the positions onto the joints made their drift grow: W_B is not the
    /// derivative of g_B (a hand-derived mechanism's rows that disagree with its constraints),
    /// or the step is so long that the joints' directions turn through it.
    #[error(
        "the correction of the positions onto the joints at t = {t} took their largest drift \
         |g_B| from {before:e} to {after:e}: check that each row's W_B is the derivative of its \
         g_B, or take a shorter step"
    )]
    JointCorrectionDiverged {
        /// Time of the end of the step (s).
        t: f64,
        /// The largest |g_B| before the correction (m or rad, as the constraints are written).
        before: f64,
        /// The largest |g_B| after it.
        after: f64,
    },
    /// The active-set threshold is negative or not finite.
    #[error("gap tolerance {value} must be finite and >= 0")]
    InvalidGapTolerance {
        /// The rejected value (m).
        value: f64,
    },
    /// A tolerance of the projection (`projection_tolerance`, `joint_tolerance`) is negative
    /// or not finite.
    #[error("{name} {value} must be finite and >= 0")]
    InvalidTolerance {
        /// The option's name.
        name: &'static str,
        /// The rejected value.
        value: f64,
    },
    /// The residual up to which an inexact island is taken is negative, not finite or not
    /// below 1.
    #[error("inexact residual {value} must be finite, >= 0 and < 1")]
    InvalidInexactResidual {
        /// The rejected value.
        value: f64,
    },
    /// Impulses given to a restarted stepper that it cannot take
    /// ([`crate::Stepper::set_impulses`]).
    #[error("impulses: {reason}")]
    InvalidImpulses {
        /// What is wrong with them.
        reason: String,
    },
    /// The end time lies before the current time.
    #[error("end time {t_end} lies before the current time {t}")]
    EndBeforeStart {
        /// Current time (s).
        t: f64,
        /// Requested end time (s).
        t_end: f64,
    },
    /// The LCP of a step has no acceptable solution from the chosen solver.
    ///
    /// The instance is kept so that it can be written with `Lcp::write_siconos` and examined.
    #[error(
        "LCP of size {} failed at step {step} (t = {t}): solver status {status}",
        lcp.n()
    )]
    LcpFailed {
        /// Index of the failed step (0 for the first step of the stepper).
        step: u64,
        /// Start time t_A of the step (s).
        t: f64,
        /// Positions q_A at the start of the step.
        q: Vec<f64>,
        /// Velocities u_A at the start of the step.
        u: Vec<f64>,
        /// What the solver reported.
        status: Status,
        /// The LCP instance (A, b) of eq. 7.41.
        lcp: Box<Lcp>,
    },
    /// The contact problem of a step (its LCP, or an island's frictional-contact problem) has
    /// an entry beyond the range the solvers compute in (|x| ≤ 2^500 ≈ 3.3e150), so it is not
    /// solved. Its entries are w_Nᵀ M⁻¹ w_N, w_Tᵀ M⁻¹ w_N, ... and w_Nᵀ ũ + ŵ_N with
    /// ũ = u_A + M⁻¹ h Δt: a mass matrix that is nearly singular (an inertia of 1e-300 next to
    /// masses of order one), or forces, force directions or velocities far beyond the
    /// mechanism's scale. `source` names the entry in the solvers' terms (`M` and `q` of the
    /// LCP are the step's A and b, not the mechanism's mass matrix and coordinates).
    #[error(
        "the contact problem of step {step} (t = {t}) has an entry {value:e} beyond the \
         solvers' range of 3.3e150: M(q, t) is nearly singular or h, w_N, w_T or the velocities \
         are far beyond the mechanism's scale; check them, or write the mechanism in other units"
    )]
    ProblemOutOfRange {
        /// Index of the step (0 for the first step of the stepper).
        step: u64,
        /// Start time t_A of the step (s).
        t: f64,
        /// The entry out of range.
        value: f64,
        /// The solvers' refusal, naming the entry of the problem.
        #[source]
        source: LcpError,
    },
    /// A contact found by [`crate::BodyStructure::detect`] that the stepper cannot use.
    #[error("detected contact {index} (id {id}): {reason}")]
    InvalidContact {
        /// Its position in the detection's list.
        index: usize,
        /// Its identity.
        id: u64,
        /// What is wrong (a body that does not exist, identities out of order).
        reason: String,
    },
    /// The frictional-contact problem of one island of a step (mechanism with a
    /// [`crate::BodyStructure`]) has no acceptable solution from the chosen solver.
    ///
    /// The island's problem is kept so that it can be written with `Fc2d::write_siconos`
    /// and examined.
    #[error(
        "the contact problem of an island of {} contacts failed at step {step} (t = {t}): solver status {status}",
        problem.n_contacts()
    )]
    IslandFailed {
        /// Index of the failed step (0 for the first step of the stepper).
        step: u64,
        /// Start time t_A of the step (s).
        t: f64,
        /// Positions q_A at the start of the step.
        q: Vec<f64>,
        /// Velocities u_A at the start of the step.
        u: Vec<f64>,
        /// What the solver reported.
        status: Status,
        /// The island's problem: W by 2 × 2 blocks, q = b and μ of its contacts, in
        /// increasing order of identity.
        problem: Box<Fc2d>,
    },
    /// Invalid solver options or LCP input.
    #[error(transparent)]
    Lcp(#[from] LcpError),
    /// Invalid contact law.
    #[error(transparent)]
    Law(#[from] SetValuedError),
}
