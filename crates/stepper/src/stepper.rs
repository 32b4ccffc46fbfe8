//! Moreau's midpoint time-stepper (docs/theory.md, sections 4-6).
#![allow(non_snake_case)]

use faer::{ColRef, MatRef};
use moreau_kinematics::ContactPoint;
use moreau_lcp::fc2d::{Fc2d, Fc2dRef, Fc2dSolution, Fc2dSolver, Nsgs, NsgsOptions};
use moreau_lcp::{
    Auto, Enumeration, Lcp, LcpRef, Lemke, Method, Pgs, PgsOptions, Solution, Solver, Status,
};

use crate::dense::{Cholesky, dot, order, weigh_bodies_alike};
use crate::observer::{Observer, Recorder};
pub use crate::report::{
    ContactReport, ContactState, Impulses, LcpInfo, PhaseTimes, RunSummary, StepReport,
};
use crate::{Mechanism, Record, SolverChoice, StepError, StepperOptions};

mod checks;
mod islands;
mod joints;
mod solve;
mod sparse;
mod step;
pub(crate) use checks::check_state;
use checks::{
    LcpFailure, check_directions, check_finite, check_rheonomic, diagnose_non_finite,
    mark_unwritten,
};
use islands::{IslandSolver, Purpose};
use joints::Joints;
use solve::{
    FC2D_ROUTE_CONTACTS, Fc2dRoute, closed_form_residual, frictional_contact,
    one_contact_closed_form,
};
use sparse::BodyPath;

/// The LCP solver held by a stepper.
///
/// A stepper holds exactly one, built once, so the size difference between the variants (`Auto`
/// carries the workspaces of all its fallbacks) costs nothing worth an indirection on every solve.
#[allow(clippy::large_enum_variant)]
enum SolverImpl {
    Auto(Auto),
    Lemke(Lemke),
    Pgs(Pgs),
    Enumeration(Enumeration),
}

impl SolverImpl {
    fn new(choice: &SolverChoice) -> Result<Self, StepError> {
        Ok(match choice {
            SolverChoice::Auto => Self::Auto(Auto::default()),
            SolverChoice::Lemke => Self::Lemke(Lemke::default()),
            SolverChoice::Pgs { tolerance, omega, max_iterations } => Self::Pgs(Pgs::new(
                PgsOptions::default()
                    .with_omega(*omega)
                    .with_tolerance(*tolerance)
                    .with_max_iterations(*max_iterations),
            )?),
            SolverChoice::Enumeration => Self::Enumeration(Enumeration::default()),
        })
    }

    fn solve(
        &mut self,
        lcp: LcpRef<'_>,
        warm: Option<&[f64]>,
        out: &mut Solution,
    ) -> Result<(), moreau_lcp::LcpError> {
        match self {
            Self::Auto(s) => s.solve_into(lcp, warm, out),
            Self::Lemke(s) => s.solve_into(lcp, None, out),
            Self::Pgs(s) => s.solve_into(lcp, warm, out),
            Self::Enumeration(s) => s.solve_into(lcp, None, out),
        }
    }
}

/// Preallocated buffers of one step, sized for every contact closed at once.
struct Workspace {
    /// Midpoint positions q_M.
    q_m: Vec<f64>,
    /// End positions q_E before they are accepted.
    q_e: Vec<f64>,
    /// Normal gaps g_N(q_M, t_M) of all contacts.
    gaps: Vec<f64>,
    /// What the mechanism's `evaluate` keeps for its `midpoint_contacts` at q_M.
    memo: Vec<f64>,
    /// M(q_M, t_M), column-major.
    mass: Vec<f64>,
    /// h(q_M, u_A, t_M), then M⁻¹ h Δt.
    h: Vec<f64>,
    /// Impulse-free velocity ũ = u_A + M⁻¹ h Δt.
    u_free: Vec<f64>,
    /// Scratch vector of length f.
    tmp: Vec<f64>,
    /// u_A of the last step with an impulse (an LCP solved, or joints).
    u_start: Vec<f64>,
    /// q_A of the step, for a mechanism with joints and the projection on: the state that a
    /// correction refused with [`StepError::JointCorrectionDiverged`] gives back.
    q_start: Vec<f64>,
    /// ũ before the joints' impulses, for a mechanism with joints.
    u_unconstrained: Vec<f64>,
    /// The joints' impulses Λ_B of the last step, one per bilateral constraint.
    joint_impulses: Vec<f64>,
    chol: Cholesky,
    /// Whether `chol` holds the factor of a constant M.
    factored: bool,
    /// Indices of the active contacts.
    active: Vec<usize>,
    /// Positions in `active` of the active frictional contacts.
    frictional: Vec<usize>,
    /// μ of each contact in `frictional`, in its order.
    mu_f: Vec<f64>,
    /// The kinematics of the active contacts: their scalars, and w_N and w_T, one column
    /// of length f each.
    points: Vec<ContactPoint>,
    w_n: Vec<f64>,
    w_t: Vec<f64>,
    /// ŵ_N, ŵ_T and γ_NA, γ_TA of the active contacts.
    w_n_hat: Vec<f64>,
    w_t_hat: Vec<f64>,
    gamma_na: Vec<f64>,
    gamma_ta: Vec<f64>,
    /// Whether each active contact carried a normal impulse in the step before, for telling
    /// an impact from persistent contact.
    closed_before: Vec<bool>,
    /// M⁻¹(w_N − μ w_T) per active contact and M⁻¹ w_T per active frictional contact.
    y_n: Vec<f64>,
    x_t: Vec<f64>,
    /// The Delassus matrix G = [W_N W_T]ᵀ M⁻¹ [W_N W_T] for the nonsmooth Gauss-Seidel.
    g: Vec<f64>,
    /// The contact problem of the nonsmooth Gauss-Seidel: W by contact (rows N, T of each
    /// active contact, column-major), q and μ, the problem, its solver and solution.
    fc_w: Vec<f64>,
    fc_q: Vec<f64>,
    fc_mu: Vec<f64>,
    fc_warm: Vec<f64>,
    fc: Fc2d,
    nsgs: Option<Nsgs>,
    /// The default choice's solver of the contact problem (that of the islands of detected
    /// contacts): for many contacts, and where pivoting on eq. 7.41 fails. Built on its first
    /// use, which most mechanisms never make.
    fc_auto: Option<IslandSolver>,
    fc_solution: Fc2dSolution,
    /// The LCP (A column-major, b).
    a: Vec<f64>,
    b: Vec<f64>,
    /// Warm start for PGS and the previous impulses (P_N, P_R, ξ_L) of each contact.
    warm: Vec<f64>,
    prev: Vec<[f64; 3]>,
    solution: Solution,
    /// Size of the LCP the last step gave to a solver (0 when none).
    last_size: usize,
    /// Size of the last step's LCP (0 when no contact was closed) and how it was solved.
    lcp_size: usize,
    lcp_info: Option<LcpInfo>,
    /// Steps whose LCP needed a solver, since the stepper was made.
    lcp_solves: u64,
    /// The contacts whose reports hold an active contact (to be cleared next step).
    reported: Vec<usize>,
    /// The bilateral constraints (joints), evaluated at the midpoint.
    joints: Joints,
    /// The largest penetration max(0, −g_N) among the contacts at the last midpoint (m).
    penetration: f64,
    /// The largest |g_B| at the last midpoint (m or rad).
    joint_drift: f64,
    /// q_E as the midpoint rule gave it, before the position projection moved it, and
    /// whether the last step's projection moved it.
    q_unprojected: Vec<f64>,
    projected: bool,
    /// Buffers of the optional position projection.
    proj_active: Vec<usize>,
    proj_w: Vec<f64>,
    proj_x: Vec<f64>,
    proj_a: Vec<f64>,
    proj_b: Vec<f64>,
    proj_solver: Auto,
    proj_solution: Solution,
}

/// Moreau's midpoint time-stepper for a [`Mechanism`].
///
/// One step from t_A to t_E = t_A + Δt (docs/theory.md section 4):
/// 1. t_M = t_A + Δt/2, q_M = q_A + (Δt/2) u_A;
/// 2. M_M = M(q_M, t_M), h_M = h(q_M, u_A, t_M);
/// 3. the active set H = { i : g_N,i(q_M, t_M) ≤ 0 } (or ≤ [`StepperOptions::gap_tolerance`]);
/// 4. with H empty, u_E = u_A + M_M⁻¹ h_M Δt; otherwise the LCP of eq. 7.41 is assembled
///    for the contacts in H (one row per frictionless contact, three per frictional one),
///    solved, and u_E = u_A + M_M⁻¹(h_M Δt + W_N P_N + W_T P_T);
/// 5. q_E = q_M + (Δt/2) u_E.
///
/// M_M is factorised once per step (once per run when the mechanism says it is constant)
/// and nothing is allocated inside the step loop.
///
/// # References
/// - Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics.
/// - Glocker, Ch. (2001). Set-valued force laws.
/// - Flores, P. (2010). Application of the non-smooth dynamics approach to model and analyze
///   contact-impact events in rigid multibody systems using the LCP formulation.
pub struct Stepper<M: Mechanism> {
    mechanism: M,
    core: Core,
}

/// A stepper's state and workspace: everything but the mechanism, which the step borrows
/// beside it.
struct Core {
    options: StepperOptions,
    solver: SolverImpl,
    t0: f64,
    step: u64,
    t: f64,
    q: Vec<f64>,
    u: Vec<f64>,
    contacts: Vec<ContactReport>,
    /// The identities of the fixed contacts: their indices.
    contact_ids: Vec<u64>,
    ws: Workspace,
    /// The state of the many-body path, for a mechanism with a body structure.
    body: Option<Box<BodyPath>>,
}

/// The natural-map tolerance of the default choice's solver of many contacts: that of the
/// shared LCP residual with which the dense route accepts a solution.
const FC2D_TOLERANCE: f64 = 1e-10;

/// A step count as f64, through i64: the baseline x86-64 target converts signed integers in
/// one instruction and unsigned ones with a branch, and no run takes 2^63 steps.
#[inline(always)]
fn step_count_as_f64(k: u64) -> f64 {
    k as i64 as f64
}

impl<M: Mechanism> Stepper<M> {
    /// A stepper for `mechanism` starting from (q0, u0) at time t0.
    ///
    /// # Errors
    /// [`StepError::InvalidTimeStep`] for Δt not finite and positive,
    /// [`StepError::Dimension`] for state vectors or law lists of the wrong length,
    /// [`StepError::NonFinite`] for a non-finite state, and the solver's option errors. For a
    /// mechanism with a [`crate::BodyStructure`]: [`StepError::Dimension`] when f is not three
    /// times its number of bodies; for one that says [`Mechanism::maximal_coordinates`]: when f
    /// is not a multiple of three.
    pub fn new(
        mechanism: M,
        q0: &[f64],
        u0: &[f64],
        t0: f64,
        options: StepperOptions,
    ) -> Result<Self, StepError> {
        if !(options.dt > 0.0 && options.dt.is_finite()) {
            return Err(StepError::InvalidTimeStep { dt: options.dt });
        }
        if !(options.gap_tolerance >= 0.0 && options.gap_tolerance.is_finite()) {
            return Err(StepError::InvalidGapTolerance { value: options.gap_tolerance });
        }
        for (name, value) in [
            ("projection_tolerance", options.projection_tolerance),
            ("joint_tolerance", options.joint_tolerance),
        ] {
            if !(value >= 0.0 && value.is_finite()) {
                return Err(StepError::InvalidTolerance { name, value });
            }
        }
        if !(0.0..1.0).contains(&options.inexact_residual) {
            return Err(StepError::InvalidInexactResidual { value: options.inexact_residual });
        }
        let f = mechanism.num_coordinates();
        let body = match mechanism.body_structure() {
            Some(structure) => {
                let nb = structure.num_bodies();
                if f != 3 * nb {
                    return Err(StepError::Dimension {
                        what: "coordinates (three per body of the body structure)",
                        expected: 3 * nb,
                        found: f,
                    });
                }
                Some(Box::new(BodyPath::new(nb, mechanism.num_bilaterals())))
            }
            None if mechanism.maximal_coordinates() && !f.is_multiple_of(3) => {
                return Err(StepError::Dimension {
                    what: "coordinates (three per body: the mechanism says maximal_coordinates)",
                    expected: 3 * f.div_ceil(3),
                    found: f,
                });
            }
            None => None,
        };
        // The many-body path sizes its own buffers; the dense ones stay empty.
        let (fd, n) = if body.is_some() { (0, 0) } else { (f, mechanism.num_contacts()) };
        let laws = if body.is_some() { 0 } else { mechanism.laws().len() };
        for (what, len, expected) in [("q0", q0.len(), f), ("u0", u0.len(), f), ("laws", laws, n)] {
            if len != expected {
                return Err(StepError::Dimension { what, expected, found: len });
            }
        }
        if !t0.is_finite() {
            return Err(StepError::NonFinite { what: "t0", index: 0, t: t0 });
        }
        check_finite("q0", q0, t0)?;
        check_finite("u0", u0, t0)?;
        let solver = SolverImpl::new(&options.solver)?;
        let f = fd;
        let ws = Workspace {
            q_m: vec![0.0; f],
            q_e: vec![0.0; f],
            gaps: vec![0.0; n],
            memo: vec![0.0; mechanism.shared_work().map_or(0, |s| s.memo_len())],
            mass: vec![0.0; f * f],
            h: vec![0.0; f],
            u_free: vec![0.0; f],
            tmp: vec![0.0; f],
            u_start: vec![0.0; f],
            q_start: vec![0.0; if mechanism.num_bilaterals() > 0 { f } else { 0 }],
            q_unprojected: vec![0.0; if options.projection { f } else { 0 }],
            projected: false,
            u_unconstrained: vec![0.0; f],
            joint_impulses: vec![0.0; if body.is_some() { 0 } else { mechanism.num_bilaterals() }],
            chol: Cholesky::for_mass_matrix(f),
            factored: false,
            active: Vec::with_capacity(n),
            frictional: Vec::with_capacity(n),
            mu_f: vec![0.0; n],
            points: vec![ContactPoint::default(); n],
            w_n: vec![0.0; f * n],
            w_t: vec![0.0; f * n],
            w_n_hat: vec![0.0; n],
            w_t_hat: vec![0.0; n],
            gamma_na: vec![0.0; n],
            gamma_ta: vec![0.0; n],
            closed_before: vec![false; n],
            y_n: vec![0.0; f * n],
            x_t: vec![0.0; f * n],
            g: vec![0.0; 4 * n * n],
            fc_w: vec![0.0; 4 * n * n],
            fc_q: vec![0.0; 2 * n],
            fc_mu: vec![0.0; n],
            fc_warm: vec![0.0; 2 * n],
            fc: Fc2d::default(),
            nsgs: match &options.solver {
                SolverChoice::Pgs { tolerance, omega, max_iterations } => Some(Nsgs::new(
                    NsgsOptions::default()
                        .with_tolerance(*tolerance)
                        .with_omega(*omega)
                        .with_max_sweeps(*max_iterations),
                )?),
                _ => None,
            },
            fc_auto: None,
            fc_solution: Fc2dSolution::new(),
            a: vec![0.0; 9 * n * n],
            b: vec![0.0; 3 * n],
            warm: vec![0.0; 3 * n],
            prev: vec![[0.0; 3]; n],
            solution: Solution::new(),
            last_size: 0,
            lcp_size: 0,
            lcp_info: None,
            lcp_solves: 0,
            reported: Vec::with_capacity(n),
            joints: Joints::new(if body.is_some() { 0 } else { mechanism.num_bilaterals() }, f),
            penetration: 0.0,
            joint_drift: 0.0,
            proj_active: Vec::with_capacity(n),
            proj_w: vec![0.0; f * n],
            proj_x: vec![0.0; f * n],
            proj_a: vec![0.0; n * n],
            proj_b: vec![0.0; n],
            proj_solver: Auto::default(),
            proj_solution: Solution::new(),
        };
        Ok(Self {
            mechanism,
            core: Core {
                options,
                solver,
                t0,
                step: 0,
                t: t0,
                q: q0.to_vec(),
                u: u0.to_vec(),
                contacts: vec![ContactReport::default(); n],
                contact_ids: (0..n as u64).collect(),
                ws,
                body,
            },
        })
    }

    /// Current time t (s).
    pub fn t(&self) -> f64 {
        self.core.t
    }

    /// Current positions q.
    pub fn q(&self) -> &[f64] {
        &self.core.q
    }

    /// Current velocities u.
    pub fn u(&self) -> &[f64] {
        &self.core.u
    }

    /// The mechanism being integrated.
    pub fn mechanism(&self) -> &M {
        &self.mechanism
    }

    /// The options the stepper was built with.
    pub fn options(&self) -> &StepperOptions {
        &self.core.options
    }

    /// Number of steps taken so far.
    pub fn steps(&self) -> u64 {
        self.core.step
    }

    /// Restarts from state (q, u) at time t, forgetting the warm start.
    ///
    /// # Errors
    /// [`StepError::Dimension`] or [`StepError::NonFinite`] for a bad state.
    pub fn set_state(&mut self, t: f64, q: &[f64], u: &[f64]) -> Result<(), StepError> {
        check_state(self.core.q.len(), t, q, u)?;
        self.core.q.copy_from_slice(q);
        self.core.u.copy_from_slice(u);
        self.core.t0 = t;
        self.core.t = t;
        self.core.step = 0;
        self.core.ws.prev.fill([0.0; 3]);
        self.core.ws.joints.moved();
        if let Some(body) = &mut self.core.body {
            body.forget();
        }
        Ok(())
    }

    /// Takes `impulses` as those of the step that ended at the current state: the next step's
    /// warm start, and the contacts that were closed before it (so that a contact that goes on
    /// pressing is not reported as an impact). Call it after [`Self::set_state`] (which forgets
    /// them) or on a new stepper, with the impulses of the step that reached its state
    /// ([`Impulses::of`] its report): the run then goes on as the run that reached it. On the
    /// path of fixed contacts a contact's P_R = P_T + μ P_N is restored and its ξ_L (the
    /// Gauss-Seidel choice's warm start of the slip) starts at 0; its joints need no warm start.
    ///
    /// # Errors
    /// [`StepError::InvalidImpulses`] when the contacts' identities are not in increasing
    /// order (or, on the path of fixed contacts, not contact indices), a P_N is negative, a
    /// value is not finite, or `joints` is neither empty nor one per bilateral constraint; the
    /// impulses held before are then kept.
    pub fn set_impulses(&mut self, impulses: &Impulses) -> Result<(), StepError> {
        let invalid = |reason: String| Err(StepError::InvalidImpulses { reason });
        let n_b = self.mechanism.num_bilaterals();
        if !impulses.joints.is_empty() && impulses.joints.len() != n_b {
            return invalid(format!(
                "{} joint impulses for {n_b} bilateral constraints",
                impulses.joints.len()
            ));
        }
        if let Some(k) = impulses.joints.iter().position(|l| !l.is_finite()) {
            return invalid(format!("joint impulse {k} is {}", impulses.joints[k]));
        }
        let fixed = self.core.body.is_none();
        let n = self.core.contacts.len();
        for (k, &(id, p_n, p_t)) in impulses.contacts.iter().enumerate() {
            if !(p_n.is_finite() && p_t.is_finite()) {
                return invalid(format!("contact {id} has (P_N, P_T) = ({p_n}, {p_t})"));
            }
            if p_n < 0.0 {
                return invalid(format!("contact {id} has a negative P_N = {p_n}"));
            }
            if k > 0 && impulses.contacts[k - 1].0 >= id {
                return invalid(format!(
                    "contact {id} follows contact {}",
                    impulses.contacts[k - 1].0
                ));
            }
            if fixed && id >= n as u64 {
                return invalid(format!("contact {id} of a mechanism with {n} contacts"));
            }
        }
        match &mut self.core.body {
            Some(body) => body.set_impulses(impulses),
            None => {
                let laws = self.mechanism.laws();
                let prev = &mut self.core.ws.prev;
                prev.fill([0.0; 3]);
                for &(id, p_n, p_t) in &impulses.contacts {
                    let i = id as usize;
                    prev[i] = [p_n, p_t + laws[i].mu() * p_n, 0.0];
                }
            }
        }
        Ok(())
    }

    /// Takes one step of size Δt and reports it.
    ///
    /// # Errors
    /// [`StepError::MassNotSpd`] when M(q_M, t_M) is not SPD, [`StepError::NonFinite`] when the
    /// mechanism returns non-finite values or the state blows up, and
    /// [`StepError::LcpFailed`] (carrying the LCP instance) when the step's LCP has no
    /// acceptable solution ([`StepError::IslandFailed`] for an island of a mechanism with a
    /// [`crate::BodyStructure`], whose detected contacts may also be
    /// [`StepError::InvalidContact`]), [`StepError::JointsApart`] when the step's midpoint
    /// leaves the joints by a tenth of the mechanism's size, and
    /// [`StepError::JointCorrectionDiverged`] when the correction of the positions onto the
    /// joints makes their drift grow. The state is left at the start of the failed step.
    pub fn step(&mut self) -> Result<StepReport<'_>, StepError> {
        if self.core.body.is_some() {
            self.core.advance_bodies(&self.mechanism)?;
        } else {
            self.core.advance(&self.mechanism)?;
        }
        Ok(self.core.report())
    }

    /// The LCP (A, b) of eq. 7.41 that the last step assembled and gave to the solver, if it
    /// needed one (not when no contact was closed or the zero impulse solved it at once).
    /// Always `None` for a mechanism with a [`crate::BodyStructure`], whose steps pose
    /// frictional-contact problems by island instead (a failed one is kept in
    /// [`StepError::IslandFailed`]).
    pub fn last_lcp(&self) -> Option<LcpRef<'_>> {
        let s = self.core.ws.last_size;
        if s == 0 {
            return None;
        }
        LcpRef::new(
            MatRef::from_column_major_slice(&self.core.ws.a[..s * s], s, s),
            ColRef::from_slice(&self.core.ws.b[..s]),
        )
        .ok()
    }

    /// The planar frictional-contact problems of the islands that the last step of a
    /// mechanism with a [`crate::BodyStructure`] solved, in island order: each island's
    /// Delassus matrix W by 2 × 2 blocks, q = b and μ, its contacts in increasing order of
    /// identity. With the position projection on, these are the projection's normal-only
    /// problems (μ = 0), solved last. Empty for a mechanism without a body structure (see
    /// [`Stepper::last_lcp`]).
    ///
    /// For examining a step or solving it again elsewhere, for instance after
    /// `to_owned().write_siconos(..)` in Siconos' FC2D format.
    pub fn last_islands(&self) -> impl Iterator<Item = Fc2dRef<'_>> {
        self.core.body.iter().flat_map(|b| b.islands.problems())
    }

    /// Steps until t_end (the last step ends at it or less than Δt past it), calling
    /// `observer` after every step; stops early when the observer breaks. Once the run has
    /// ended without an error, [`Observer::finish`] is called with its last step's report.
    ///
    /// The number of steps is the nearest whole number of Δt in `t_end − t` (rounded up when
    /// it is not within 1e-6 Δt of one), and time is t_0 + kΔt, so no round-off accumulates.
    ///
    /// # Errors
    /// [`StepError::EndBeforeStart`] when t_end < t, and every error of [`Self::step`].
    pub fn run_until<O: Observer<M>>(
        &mut self,
        t_end: f64,
        observer: &mut O,
    ) -> Result<RunSummary, StepError> {
        if !t_end.is_finite() {
            return Err(StepError::NonFinite { what: "t_end", index: 0, t: t_end });
        }
        if t_end < self.core.t {
            return Err(StepError::EndBeforeStart { t: self.core.t, t_end });
        }
        let x = (t_end - self.core.t) / self.core.options.dt;
        let n = if (x - x.round()).abs() < 1e-6 { x.round() } else { x.ceil() } as u64;
        RunSteps { core: &mut self.core, mechanism: &self.mechanism, n, t_end, observer }.run()
    }

    /// Runs until t_end and records every step (row 0 is the current state).
    ///
    /// # Errors
    /// Every error of [`Self::run_until`]; the rows recorded before it are dropped with the
    /// record. To keep them, run a [`Recorder`] of your own with [`Self::run_until`]: its
    /// `record` holds every step up to the failed one.
    pub fn record_until(&mut self, t_end: f64) -> Result<Record, StepError> {
        let mut recorder = Recorder::new();
        recorder.push_initial(&self.mechanism, self.core.t, &self.core.q, &self.core.u);
        self.run_until(t_end, &mut recorder)?;
        Ok(recorder.record)
    }
}

/// The loop of [`Stepper::run_until`], the path and the order f chosen once.
struct RunSteps<'a, M, O> {
    core: &'a mut Core,
    mechanism: &'a M,
    n: u64,
    t_end: f64,
    observer: &'a mut O,
}

impl<M: Mechanism, O: Observer<M>> RunSteps<'_, M, O> {
    /// The one loop of [`Stepper::run_until`]: `n` calls of `advance`, each followed by the
    /// observer with the step's `report`. Each path passes its own step and report, so that
    /// the loop is compiled once per path with both inlined (on the path of fixed contacts,
    /// for a fixed number of coordinates).
    fn steps(
        self,
        mut advance: impl FnMut(&mut Core) -> Result<(), StepError>,
        report: impl Fn(&Core) -> StepReport<'_>,
    ) -> Result<RunSummary, StepError> {
        let RunSteps { core, mechanism, n, t_end, observer } = self;
        let solves_before = core.ws.lcp_solves;
        let mut steps = 0;
        let mut stopped = false;
        let (mut inexact_steps, mut inexact_residual) = (0, 0.0f64);
        for k in 0..n {
            advance(core)?;
            steps += 1;
            let r = report(core);
            if let Some(residual) = r.lcp.and_then(|info| info.inexact()) {
                inexact_steps += 1;
                inexact_residual = inexact_residual.max(residual);
            }
            stopped = observer.observe(mechanism, &r).is_break();
            // The last step's report, passed on once more: one report per step, so that the
            // loop keeps `report` inlined.
            if stopped || k + 1 == n {
                observer.finish(mechanism, &r);
            }
            if stopped {
                break;
            }
        }
        Ok(RunSummary {
            steps,
            lcp_solves: core.ws.lcp_solves - solves_before,
            inexact_steps,
            inexact_residual,
            t_end: core.t,
            stopped_early: stopped && core.t < t_end,
        })
    }

    /// Runs the loop compiled for the mechanism's path and, on the path of fixed contacts,
    /// for its number of coordinates.
    fn run(self) -> Result<RunSummary, StepError> {
        let mech = self.mechanism;
        if self.core.body.is_some() {
            return self.steps(|core| core.advance_bodies(mech), Core::report);
        }
        match self.core.q.len() {
            1 => self.steps(|core| core.advance_n::<M, 1>(mech), Core::dense_report),
            2 => self.steps(|core| core.advance_n::<M, 2>(mech), Core::dense_report),
            3 => self.steps(|core| core.advance_n::<M, 3>(mech), Core::dense_report),
            4 => self.steps(|core| core.advance_n::<M, 4>(mech), Core::dense_report),
            _ => self.steps(|core| core.advance_n::<M, 0>(mech), Core::dense_report),
        }
    }
}

/// The report of a contact of the step's problem from its impulses (P_N, P_T), its end
/// velocities γ = (γ_N, γ_T), its velocities γ_A at the step's start and whether it carried a
/// normal impulse at the step before. It is an impact when it carries a normal impulse,
/// approached (γ_N,A < 0) and was not closed before; it is open without a normal impulse,
/// sticking when γ_T is zero up to round-off relative to `scale` (the sum of the |w_T,i u_i|
/// that γ_T is made of), slipping otherwise.
#[inline(always)]
fn active_report(
    [p_n, p_t]: [f64; 2],
    [gamma_n, gamma_t]: [f64; 2],
    [gamma_n_a, gamma_t_a]: [f64; 2],
    closed_before: bool,
    scale: f64,
) -> ContactReport {
    let state = if p_n <= 0.0 {
        ContactState::Open
    } else if gamma_t.abs() <= 1e-9 * (1.0 + scale) {
        ContactState::Stick
    } else {
        ContactState::Slip
    };
    ContactReport {
        active: true,
        p_n,
        p_t,
        gamma_n,
        gamma_t,
        gamma_n_a,
        gamma_t_a,
        impact: p_n > 0.0 && gamma_n_a < 0.0 && !closed_before,
        state,
    }
}

#[allow(dead_code)]
fn _assert_send_sync() {
    fn is<T: Send + Sync>() {}
    is::<StepError>();
    is::<Core>();
}

impl<M: Mechanism> std::fmt::Debug for Stepper<M> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Stepper")
            .field("t", &self.core.t)
            .field("q", &self.core.q)
            .field("u", &self.core.u)
            .field("options", &self.core.options)
            .finish_non_exhaustive()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use moreau_kinematics::SplitMix64;
    use moreau_lcp::Enumeration;

    /// The LCP of eq. 7.41 for one contact with Delassus matrix G (2 × 2, SPD), μ and b.
    fn one_contact_lcp(g: [[f64; 2]; 2], mu: f64, b: [f64; 2]) -> (Vec<f64>, Vec<f64>) {
        let (nn, nt, tt) = (g[0][0], g[0][1], g[1][1]);
        // Rows (N; R; L), columns (P_N; P_R; ξ_L), column-major.
        let a = vec![nn - mu * nt, nt - mu * tt, 2.0 * mu, nt, tt, -1.0, 0.0, 1.0, 0.0];
        (a, vec![b[0], b[1], 0.0])
    }

    #[test]
    fn the_scalar_closed_form_residual_is_the_shared_relative_residual() {
        let mut rng = SplitMix64::new(11);
        for _ in 0..1000 {
            let a = 10f64.powf(rng.uniform(-6.0, 6.0));
            let b = -10f64.powf(rng.uniform(-6.0, 6.0));
            // The closed form's z, and neighbours a few roundings away.
            let z = -b / a * (1.0 + rng.uniform(-1e-12, 1e-12));
            let w = a * z + b;
            let shared = moreau_lcp::Residual::compute_column_major(1, &[a], &[b], &[z], &[w]);
            let ours = closed_form_residual(a, b, z);
            assert!(
                (ours - shared.relative).abs() <= 1e-15 * (1.0 + shared.relative),
                "{a} {b} {z}: {ours} {}",
                shared.relative
            );
        }
    }

    #[test]
    fn one_contact_closed_form_finds_an_lcp_solution_whenever_there_is_one() {
        let mut rng = SplitMix64::new(7);
        let (mut stick, mut forwards, mut backwards) = (0, 0, 0);
        for trial in 0..2000 {
            let (x, y, c) = (rng.uniform(0.2, 2.0), rng.uniform(0.2, 2.0), rng.uniform(-0.9, 0.9));
            let g = [[x, c * (x * y).sqrt()], [c * (x * y).sqrt(), y]];
            let mu = if trial % 10 == 0 { 0.0 } else { rng.uniform(0.0, 2.0) };
            let b = [rng.uniform(-2.0, -0.01), rng.uniform(-2.0, 2.0)];
            let (a, q) = one_contact_lcp(g, mu, b);
            let lcp = moreau_lcp::Lcp::from_column_major(3, &a, &q).unwrap();
            let all = Enumeration::default().solve_all(lcp.view()).unwrap();
            let prev = [0.0; 3];
            let mut out = Solution::new();
            let info = one_contact_closed_form(&a, &q, mu, prev, &mut out);
            if all.is_empty() {
                assert!(info.is_none(), "trial {trial}: no solution, yet closed form gave one");
                continue;
            }
            let info =
                info.unwrap_or_else(|| panic!("trial {trial}: {} solutions missed", all.len()));
            assert_eq!(info.method, Method::ClosedForm);
            let r = moreau_lcp::Residual::compute(lcp.view(), &out.z, &out.w);
            assert!(r.relative <= 1e-12, "trial {trial}: {r:?}");
            // (P_N, P_T) is what the velocities depend on: it must be one enumeration found.
            let p_t = out.z[1] - mu * out.z[0];
            assert!(
                all.iter().any(|s| {
                    (s.z[0] - out.z[0]).abs() <= 1e-9 * (1.0 + s.z[0].abs())
                        && (s.z[1] - mu * s.z[0] - p_t).abs() <= 1e-9 * (1.0 + p_t.abs())
                }),
                "trial {trial}: {:?} not among {:?}",
                out.z,
                all.iter().map(|s| s.z.clone()).collect::<Vec<_>>()
            );
            let xi_t = out.w[1] - out.z[2];
            if xi_t > 1e-12 {
                forwards += 1;
            } else if xi_t < -1e-12 {
                backwards += 1;
            } else {
                stick += 1;
            }
        }
        // Every case occurs in the sample.
        assert!(stick > 100 && forwards > 100 && backwards > 100, "{stick} {forwards} {backwards}");
    }
}
