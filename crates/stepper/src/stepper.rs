//! Moreau's midpoint time-stepper (EQUATIONS.md, sections 4-6).
#![allow(non_snake_case)]

use faer::{ColRef, MatRef};
use moreau_kinematics::ContactPoint;
use moreau_lcp::fc2d::{Fc2d, Fc2dSolution, Fc2dSolver, Nsgs, NsgsOptions};
use moreau_lcp::{
    Auto, Enumeration, Lcp, LcpRef, Lemke, Method, Pgs, PgsOptions, Solution, Solver, Status,
};

use crate::dense::{Cholesky, dot, half_quadratic, order};
use crate::observer::{Observer, Recorder};
use crate::{ConcreteOp, Mechanism, Record, SolverChoice, StepError, StepperOptions};

/// Whether a contact is open, sticking or slipping at the end of a step.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "snake_case")]
pub enum ContactState {
    /// No normal impulse: the contact is open or separating (P_N = 0).
    #[default]
    Open,
    /// P_N > 0 and the tangential velocity γ_T after the step vanishes.
    Stick,
    /// P_N > 0 and γ_T ≠ 0 after the step.
    Slip,
}

/// What happened at one contact during a step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactReport {
    /// Whether the contact was in the active set H (g_N(q_M, t_M) ≤ 0).
    pub active: bool,
    /// Normal impulse P_N over the step (zero when not active).
    pub p_n: f64,
    /// Tangential impulse P_T over the step (zero when not active or frictionless).
    pub p_t: f64,
    /// Normal relative velocity γ_N after the step (only meaningful when active).
    pub gamma_n: f64,
    /// Tangential relative velocity γ_T after the step (only meaningful when active).
    pub gamma_t: f64,
    /// Open, sticking or slipping.
    pub state: ContactState,
}

/// How a step's LCP was solved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LcpInfo {
    /// The method that produced the accepted solution.
    pub method: Method,
    /// The solver's status (always `Solved` in a report: failures are errors).
    pub status: Status,
    /// Pivots or sweeps used.
    pub iterations: usize,
    /// The largest entry of the shared residual of `moreau_lcp::Residual`; for a single
    /// frictionless contact solved in closed form, the equation error |A P_N + b| (z = −b/A
    /// with A > 0 > b needs no check).
    pub residual: f64,
}

/// The outcome of one step, borrowed from the stepper until the next step.
#[derive(Clone, Copy, Debug)]
pub struct StepReport<'a> {
    /// Index of this step since the stepper was created (0 for the first).
    pub step: u64,
    /// End time t_E of the step (s).
    pub t: f64,
    /// End positions q_E.
    pub q: &'a [f64],
    /// End velocities u_E.
    pub u: &'a [f64],
    /// One report per contact of the mechanism.
    pub contacts: &'a [ContactReport],
    /// Size of the LCP (0 when no contact was closed): one row per active frictionless
    /// contact, three per active frictional one.
    pub lcp_size: usize,
    /// How the LCP was solved, if there was one.
    pub lcp: Option<LcpInfo>,
    /// M_M, column-major, and the impulse-free velocity ũ, for [`Self::impulse_dissipation`].
    mass: &'a [f64],
    u_free: &'a [f64],
}

impl StepReport<'_> {
    /// Kinetic energy removed by the impulses of the step, ½ũᵀM_Mũ − ½u_EᵀM_Mu_E with
    /// ũ = u_A + M_M⁻¹h_M Δt the impulse-free velocity (J); zero when no impulse acted.
    /// Computed on demand: it costs two quadratic forms.
    pub fn impulse_dissipation(&self) -> f64 {
        if self.contacts.iter().all(|c| c.p_n == 0.0 && c.p_t == 0.0) {
            return 0.0;
        }
        let f = self.u.len();
        half_quadratic(self.mass, f, self.u_free) - half_quadratic(self.mass, f, self.u)
    }
}

/// What [`Stepper::run_until`] did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSummary {
    /// Steps taken.
    pub steps: u64,
    /// Steps whose LCP needed a solver (neither empty nor settled by the zero impulse).
    pub lcp_solves: u64,
    /// Time reached (s).
    pub t_end: f64,
    /// Whether the observer stopped the run before `t_end`.
    pub stopped_early: bool,
}

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
            SolverChoice::Pgs { tolerance, omega, max_iterations } => {
                Self::Pgs(Pgs::new(PgsOptions {
                    omega: *omega,
                    tolerance: *tolerance,
                    max_iterations: *max_iterations,
                })?)
            }
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
/// One step from t_A to t_E = t_A + Δt (EQUATIONS.md section 4):
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

/// A stepper's state and workspace: everything but the mechanism, so that the step loop can
/// be compiled for the concrete mechanism that [`Mechanism::with_concrete`] names.
struct Core {
    options: StepperOptions,
    solver: SolverImpl,
    t0: f64,
    step: u64,
    t: f64,
    q: Vec<f64>,
    u: Vec<f64>,
    contacts: Vec<ContactReport>,
    ws: Workspace,
}

/// A step count as f64, through i64: the baseline x86-64 target converts signed integers in
/// one instruction and unsigned ones with a branch, and no run takes 2^63 steps.
#[inline(always)]
fn step_count_as_f64(k: u64) -> f64 {
    k as i64 as f64
}

#[inline(always)]
fn check_finite(what: &'static str, v: &[f64], t: f64) -> Result<(), StepError> {
    if v.iter().all(|x| x.is_finite()) {
        return Ok(());
    }
    let index = v.iter().position(|x| !x.is_finite()).unwrap_or(0);
    Err(StepError::NonFinite { what, index, t })
}

/// (t, q, u) as a state of a mechanism of f coordinates: q and u of f entries each (else
/// [`StepError::Dimension`]), t, q and u finite (else [`StepError::NonFinite`], t first).
pub(crate) fn check_state(f: usize, t: f64, q: &[f64], u: &[f64]) -> Result<(), StepError> {
    for (what, len) in [("q", q.len()), ("u", u.len())] {
        if len != f {
            return Err(StepError::Dimension { what, expected: f, found: len });
        }
    }
    if !t.is_finite() {
        return Err(StepError::NonFinite { what: "t", index: 0, t });
    }
    check_finite("q", q, t)?;
    check_finite("u", u, t)
}

/// A contact's force directions w_N and w_T must be finite; the error names the first entry
/// that is not (w_N's entries first, then w_T's).
#[inline(always)]
fn check_directions(w_n: &[f64], w_t: &[f64]) -> Result<(), LcpFailure> {
    match w_n.iter().chain(w_t).position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(index) => Err(LcpFailure::NonFinite { what: "w_N/w_T", index }),
    }
}

/// Names the first non-finite value among h, u_E and q_E of a step (in that order); `Ok` when
/// all are finite after all.
#[cold]
#[inline(never)]
fn diagnose_non_finite(h: &[f64], u: &[f64], q: &[f64], t: f64) -> Result<(), StepError> {
    check_finite("h", h, t)?;
    check_finite("u", u, t)?;
    check_finite("q", q, t)
}

impl<M: Mechanism> Stepper<M> {
    /// A stepper for `mechanism` starting from (q0, u0) at time t0.
    ///
    /// # Errors
    /// [`StepError::InvalidTimeStep`] for Δt not finite and positive,
    /// [`StepError::Dimension`] for state vectors or law lists of the wrong length,
    /// [`StepError::NonFinite`] for a non-finite state, and the solver's option errors.
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
        let f = mechanism.num_coordinates();
        let n = mechanism.num_contacts();
        for (what, len, expected) in
            [("q0", q0.len(), f), ("u0", u0.len(), f), ("laws", mechanism.laws().len(), n)]
        {
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
        let ws = Workspace {
            q_m: vec![0.0; f],
            q_e: vec![0.0; f],
            gaps: vec![0.0; n],
            memo: vec![0.0; mechanism.memo_len()],
            mass: vec![0.0; f * f],
            h: vec![0.0; f],
            u_free: vec![0.0; f],
            tmp: vec![0.0; f],
            chol: Cholesky::new(f),
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
            y_n: vec![0.0; f * n],
            x_t: vec![0.0; f * n],
            g: vec![0.0; 4 * n * n],
            fc_w: vec![0.0; 4 * n * n],
            fc_q: vec![0.0; 2 * n],
            fc_mu: vec![0.0; n],
            fc_warm: vec![0.0; 2 * n],
            fc: Fc2d::default(),
            nsgs: match &options.solver {
                SolverChoice::Pgs { tolerance, omega, max_iterations } => {
                    Some(Nsgs::new(NsgsOptions {
                        tolerance: *tolerance,
                        omega: *omega,
                        max_sweeps: *max_iterations,
                        ..NsgsOptions::default()
                    })?)
                }
                _ => None,
            },
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
                ws,
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
        Ok(())
    }

    /// Takes one step of size Δt and reports it.
    ///
    /// # Errors
    /// [`StepError::MassNotSpd`] when M(q_M, t_M) is not SPD, [`StepError::NonFinite`] when the
    /// mechanism returns non-finite values or the state blows up, and
    /// [`StepError::LcpFailed`] (carrying the LCP instance) when the step's LCP has no
    /// acceptable solution. The state is left at the start of the failed step.
    pub fn step(&mut self) -> Result<StepReport<'_>, StepError> {
        self.mechanism.with_concrete(Advance { core: &mut self.core })?;
        Ok(self.core.report())
    }

    /// The LCP (A, b) of eq. 7.41 that the last step assembled and gave to the solver, if it
    /// needed one (not when no contact was closed or the zero impulse solved it at once).
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

    /// Steps until t_end (the last step may end up to Δt/2 past it), calling `observer` after
    /// every step; stops early when the observer breaks.
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
        let run = RunSteps { core: &mut self.core, outer: &self.mechanism, n, t_end, observer };
        self.mechanism.with_concrete(run)
    }

    /// Runs until t_end and records every step (row 0 is the current state).
    ///
    /// # Errors
    /// Every error of [`Self::run_until`].
    pub fn record_until(&mut self, t_end: f64) -> Result<Record, StepError> {
        let mut recorder = Recorder::new();
        recorder.push_initial(&self.mechanism, self.core.t, &self.core.q, &self.core.u);
        self.run_until(t_end, &mut recorder)?;
        Ok(recorder.record)
    }
}

impl Core {
    /// The report of the step just taken.
    fn report(&self) -> StepReport<'_> {
        StepReport {
            step: self.step - 1,
            t: self.t,
            q: &self.q,
            u: &self.u,
            contacts: &self.contacts,
            lcp_size: self.ws.lcp_size,
            // Set only by steps with contacts.
            lcp: if self.ws.lcp_size > 0 { self.ws.lcp_info } else { None },
            mass: &self.ws.mass,
            u_free: &self.ws.u_free,
        }
    }

    /// The body of [`Stepper::step`]: updates (t, q, u) and the contact reports.
    fn advance<K: Mechanism>(&mut self, mech: &K) -> Result<(), StepError> {
        match self.q.len() {
            1 => self.advance_n::<K, 1>(mech),
            2 => self.advance_n::<K, 2>(mech),
            3 => self.advance_n::<K, 3>(mech),
            4 => self.advance_n::<K, 4>(mech),
            _ => self.advance_n::<K, 0>(mech),
        }
    }

    /// [`Self::advance`] for f = N coordinates (`N > 0`: the small mechanisms, whose loops over
    /// the coordinates then have constant bounds) or any f (`N = 0`).
    #[inline(always)]
    fn advance_n<K: Mechanism, const N: usize>(&mut self, mech: &K) -> Result<(), StepError> {
        let f = order::<N>(self.q.len());
        let dt = self.options.dt;
        let half = 0.5 * dt;
        let t_m = self.t + half;
        let ws = &mut self.ws;

        for ((q_m, q), u) in ws.q_m[..f].iter_mut().zip(&self.q[..f]).zip(&self.u[..f]) {
            *q_m = q + half * u;
        }
        let new_mass = !(ws.factored && mech.constant_mass_matrix());
        let mass = new_mass.then_some(&mut ws.mass[..f * f]);
        mech.evaluate(
            &ws.q_m[..f],
            &self.u[..f],
            t_m,
            mass,
            &mut ws.h[..f],
            &mut ws.gaps,
            &mut ws.memo,
        );
        if new_mass {
            check_finite("M", &ws.mass[..f * f], t_m)?;
            ws.chol
                .factor::<N>(&ws.mass)
                .map_err(|e| StepError::MassNotSpd { t: t_m, reason: e.to_string() })?;
            ws.factored = true;
        }
        // A non-finite h gives a non-finite ũ, which the check of u_E below reports as h.
        ws.chol.solve_scaled_add::<N>(&mut ws.h[..f], dt, &self.u[..f], &mut ws.u_free[..f]);

        ws.last_size = 0;
        ws.active.clear();
        let mut poison = 0.0;
        for (i, &g) in ws.gaps.iter().enumerate() {
            // x · 0 is 0 for a finite x and NaN otherwise: one test after the loop.
            poison += g * 0.0;
            if g <= self.options.gap_tolerance {
                ws.active.push(i);
            }
        }
        if poison != 0.0 {
            check_finite("h", &ws.h, t_m)?;
            check_finite("g_N", &ws.gaps, t_m)?;
        }

        // Steps without contacts, closed now or in the step before, skip what follows out of
        // line.
        let contacts = !(ws.active.is_empty() && ws.reported.is_empty());
        if contacts {
            self.solve_contacts::<K, N>(mech, t_m)?;
        } else {
            self.ws.lcp_size = 0;
        }
        let ws = &mut self.ws;
        let lcp_size = ws.lcp_size;
        let u_new = if lcp_size > 0 { &mut ws.tmp } else { &mut ws.u_free };
        // q_E and u_E, with one test for non-finite values in both; the cold path names the
        // culprit. A non-finite h gives a non-finite ũ, so it is caught here too.
        let mut poison = 0.0;
        for ((q_e, q_m), u) in ws.q_e[..f].iter_mut().zip(&ws.q_m[..f]).zip(&u_new[..f]) {
            *q_e = q_m + half * u;
            poison += *q_e * 0.0 + *u * 0.0;
        }
        if poison != 0.0 {
            diagnose_non_finite(&ws.h, u_new, &ws.q_e, t_m)?;
        }
        if N == 0 {
            // q_A and u_A are not needed any more: swap the buffers rather than copy.
            std::mem::swap(&mut self.u, u_new);
            std::mem::swap(&mut self.q, &mut ws.q_e);
        } else {
            // A few entries cost less to copy than the buffers do to swap.
            self.u[..f].copy_from_slice(&u_new[..f]);
            self.q[..f].copy_from_slice(&ws.q_e[..f]);
        }

        if contacts {
            self.report_contacts::<K, N>(mech);
        }

        if self.options.projection {
            let t_e = self.t0 + step_count_as_f64(self.step + 1) * dt;
            self.project(mech, t_e)?;
        }

        self.step += 1;
        self.t = self.t0 + step_count_as_f64(self.step) * dt;
        Ok(())
    }

    /// The contact part of a step before u_E: clears the previous step's contact reports
    /// and, when contacts are closed, solves their LCP (u_E into `ws.tmp`). Sets the step's
    /// LCP size and information.
    #[inline(never)]
    fn solve_contacts<K: Mechanism, const N: usize>(
        &mut self,
        mech: &K,
        t_m: f64,
    ) -> Result<(), StepError> {
        let ws = &mut self.ws;
        for &i in &ws.reported {
            self.contacts[i] = ContactReport::default();
        }
        ws.reported.clear();
        ws.lcp_size = 0;
        ws.lcp_info = None;
        if !ws.active.is_empty() {
            check_finite("h", &ws.h[..order::<N>(ws.h.len())], t_m)?;
            let (size, solved) =
                Self::contact_step::<K, N>(mech, &self.options, &mut self.solver, ws, &self.u, t_m)
                    .map_err(|e| self.lcp_error(e))?;
            let ws = &mut self.ws;
            ws.lcp_size = size;
            ws.lcp_info = Some(solved);
            if solved.method != Method::Trivial {
                ws.lcp_solves += 1;
            }
        }
        Ok(())
    }

    /// The contact reports of a step from its end velocities; forgets the impulses of the
    /// contacts that have opened.
    #[inline(never)]
    fn report_contacts<K: Mechanism, const N: usize>(&mut self, mech: &K) {
        let f = order::<N>(self.q.len());
        let ws = &mut self.ws;
        let laws = mech.laws();
        let u = &self.u[..f];
        for (a, &i) in ws.active.iter().enumerate() {
            let w_n = &ws.w_n[a * f..][..f];
            let w_t = &ws.w_t[a * f..][..f];
            let gamma_n = dot(w_n, u) + ws.w_n_hat[a];
            let gamma_t = dot(w_t, u) + ws.w_t_hat[a];
            let [p_n, p_r, _] = ws.prev[i];
            let mu = laws[i].mu();
            // P_T = P_R − μ P_N (section 5); P_R is zero for a contact without friction rows.
            let p_t = p_r - mu * p_n;
            let scale: f64 = w_t.iter().zip(u).map(|(w, u)| (w * u).abs()).sum();
            let state = if p_n <= 0.0 {
                ContactState::Open
            } else if gamma_t.abs() <= 1e-9 * (1.0 + scale) {
                ContactState::Stick
            } else {
                ContactState::Slip
            };
            self.contacts[i] = ContactReport { active: true, p_n, p_t, gamma_n, gamma_t, state };
            ws.reported.push(i);
        }
        for (i, c) in self.contacts.iter().enumerate() {
            if !c.active {
                ws.prev[i] = [0.0; 3];
            }
        }
    }

    /// Moves q_E back onto the admissible set g_N(q, t_E) ≥ 0 along M⁻¹ W_N:
    /// q_E ← q_E + M⁻¹ W_N λ with 0 ≤ λ ⊥ W_Nᵀ M⁻¹ W_N λ + g_N ≥ 0 over all contacts, when
    /// one penetrates, repeated (at most four times) while the linearisation leaves some
    /// penetration. Velocities are not changed, so kinetic energy is not changed.
    fn project<K: Mechanism>(&mut self, mech: &K, t_e: f64) -> Result<(), StepError> {
        let f = self.q.len();
        let ws = &mut self.ws;
        for _ in 0..4 {
            // Every contact enters the projection LCP once one penetrates: pushing a corner
            // out can push its neighbour on the same face in, and complementarity keeps the
            // open ones (g_N > 0) free of impulse.
            ws.proj_active.clear();
            let mut penetrating = false;
            mech.normal_gaps(&self.q, t_e, &mut ws.proj_b);
            for (i, &g) in ws.proj_b.iter().enumerate() {
                if !g.is_finite() {
                    return Err(StepError::NonFinite { what: "g_N", index: i, t: t_e });
                }
                penetrating |= g < 0.0;
                ws.proj_active.push(i);
            }
            let k = ws.proj_active.len();
            if !penetrating {
                break;
            }
            for (a, &i) in ws.proj_active.iter().enumerate() {
                let (w_n, x) = (&mut ws.proj_w[a * f..][..f], &mut ws.proj_x[a * f..][..f]);
                mech.contact(i, &self.q, t_e, w_n, &mut ws.tmp);
                x.copy_from_slice(w_n);
                ws.chol.solve(x);
            }
            for c in 0..k {
                for r in 0..k {
                    ws.proj_a[r + c * k] = dot(&ws.proj_w[r * f..][..f], &ws.proj_x[c * f..][..f]);
                }
            }
            let lcp = LcpRef::new(
                MatRef::from_column_major_slice(&ws.proj_a[..k * k], k, k),
                ColRef::from_slice(&ws.proj_b[..k]),
            )?;
            ws.proj_solver.solve_into(lcp, None, &mut ws.proj_solution)?;
            if ws.proj_solution.status != Status::Solved {
                // A projection that cannot be computed leaves q_E as the scheme gave it.
                break;
            }
            for (c, lambda) in ws.proj_solution.z.iter().enumerate() {
                for (q, x) in self.q.iter_mut().zip(&ws.proj_x[c * f..][..f]) {
                    *q += x * lambda.max(0.0);
                }
            }
        }
        check_finite("q", &self.q, t_e)
    }

    /// Assembles and solves the LCP of the active contacts; writes u_E into `ws.tmp` and the
    /// impulses (P_N, P_R, ξ_L) into `ws.prev`. Returns the LCP size and how it was solved.
    fn contact_step<K: Mechanism, const N: usize>(
        mech: &K,
        options: &StepperOptions,
        solver: &mut SolverImpl,
        ws: &mut Workspace,
        u_a: &[f64],
        t_m: f64,
    ) -> Result<(usize, LcpInfo), LcpFailure> {
        let f = order::<N>(u_a.len());
        let u_a = &u_a[..f];
        let laws = mech.laws();
        if let [i] = ws.active[..]
            && !(laws[i].is_frictional() || options.friction_rows_when_frictionless)
            && matches!(options.solver, SolverChoice::Auto)
            && let Some(done) = Self::one_frictionless_contact::<K, N>(mech, ws, u_a, t_m, i)?
        {
            return Ok(done);
        }
        ws.frictional.clear();
        let na = ws.active.len();
        mech.midpoint_contacts(
            &ws.active,
            &ws.q_m,
            t_m,
            &ws.memo,
            &mut ws.w_n[..na * f],
            &mut ws.w_t[..na * f],
            &mut ws.points[..na],
        );
        // γ_A, and b = W' ũ + ŵ + ε γ_A (eq. 7.41 with W' M⁻¹ h Δt + γ_A = W' ũ + ŵ): rows N
        // of all contacts, rows R of the frictional ones; rows L are zero.
        let u_free = &ws.u_free[..f];
        let mut all_separating = true;
        let mut poison = 0.0;
        for (a, &i) in ws.active.iter().enumerate() {
            let law = laws[i];
            let (w_n, w_t) = (&ws.w_n[a * f..][..f], &ws.w_t[a * f..][..f]);
            // x · 0 is 0 for a finite x and NaN otherwise: one test after the loop.
            for (n_j, t_j) in w_n.iter().zip(w_t) {
                poison += n_j * 0.0 + t_j * 0.0;
            }
            let point = ws.points[a];
            ws.w_n_hat[a] = point.w_n_hat;
            ws.w_t_hat[a] = point.w_t_hat;
            let gamma_n = dot(w_n, u_a) + point.w_n_hat;
            let gamma_t = dot(w_t, u_a) + point.w_t_hat;
            ws.gamma_na[a] = gamma_n;
            ws.gamma_ta[a] = gamma_t;
            let b_n = dot(w_n, u_free) + point.w_n_hat + law.eps_n() * gamma_n;
            ws.b[a] = b_n;
            all_separating &= b_n >= 0.0;
            if law.is_frictional() || options.friction_rows_when_frictionless {
                let k = ws.frictional.len();
                ws.b[na + k] = dot(w_t, u_free) + point.w_t_hat + law.eps_t() * gamma_t;
                ws.mu_f[k] = law.mu();
                ws.frictional.push(a);
            }
        }
        if poison != 0.0 {
            for a in 0..na {
                check_directions(&ws.w_n[a * f..][..f], &ws.w_t[a * f..][..f])?;
            }
        }
        let nf = ws.frictional.len();
        let s = na + 2 * nf;
        ws.b[na + nf..s].fill(0.0);

        if all_separating {
            // The zero-impulse solution: P_N = P_R = 0, ξ_L = max(0, −b_R).
            ws.tmp.copy_from_slice(&ws.u_free);
            for &i in ws.active.iter() {
                ws.prev[i] = [0.0; 3];
            }
            for (k, &a) in ws.frictional.iter().enumerate() {
                ws.prev[ws.active[a]][2] = (-ws.b[na + k]).max(0.0);
            }
            let info = LcpInfo {
                method: Method::Trivial,
                status: Status::Solved,
                iterations: 0,
                residual: 0.0,
            };
            return Ok((s, info));
        }

        // Columns M⁻¹ w_T of the frictional contacts and M⁻¹ (w_N − μ w_T) of all.
        for (k, &a) in ws.frictional.iter().enumerate() {
            ws.chol.solve_into::<N>(&ws.w_t[a * f..][..f], &mut ws.x_t[k * f..][..f]);
        }
        let mut k = 0;
        for a in 0..na {
            let y = &mut ws.y_n[a * f..][..f];
            ws.chol.solve_into::<N>(&ws.w_n[a * f..][..f], y);
            if k < nf && ws.frictional[k] == a {
                let mu = ws.mu_f[k];
                for (yj, xj) in y.iter_mut().zip(&ws.x_t[k * f..][..f]) {
                    *yj -= mu * xj;
                }
                k += 1;
            }
        }

        // A of eq. 7.41, column-major, rows (N; R; L), columns (P_N; P_R; ξ_L).
        let A = &mut ws.a[..s * s];
        A.fill(0.0);
        for c in 0..na {
            let y = &ws.y_n[c * f..][..f];
            for r in 0..na {
                A[r + c * s] = dot(&ws.w_n[r * f..][..f], y);
            }
            for (k, &r) in ws.frictional.iter().enumerate() {
                A[na + k + c * s] = dot(&ws.w_t[r * f..][..f], y);
            }
        }
        for (l, &c) in ws.frictional.iter().enumerate() {
            let x = &ws.x_t[l * f..][..f];
            let col = na + l;
            for r in 0..na {
                A[r + col * s] = dot(&ws.w_n[r * f..][..f], x);
            }
            for (k, &r) in ws.frictional.iter().enumerate() {
                A[na + k + col * s] = dot(&ws.w_t[r * f..][..f], x);
            }
            A[na + nf + l + col * s] = -1.0;
            A[na + l + (na + nf + l) * s] = 1.0;
            A[na + nf + l + c * s] = 2.0 * ws.mu_f[l];
        }

        ws.last_size = s;
        let one_contact = na == 1 && nf == 1 && matches!(options.solver, SolverChoice::Auto);
        let solved = if one_contact
            && let Some(info) = one_contact_closed_form(
                &ws.a[..s * s],
                &ws.b[..s],
                laws[ws.active[0]].mu(),
                ws.prev[ws.active[0]],
                &mut ws.solution,
            ) {
            info
        } else if let (SolverChoice::Pgs { .. }, true) = (&options.solver, nf > 0) {
            // The LCP of eq. 7.41 has zeros on the diagonal of its ξ_L block, where projected
            // Gauss-Seidel cannot pivot; it is run on the equivalent contact problem instead.
            let info = nonsmooth_gauss_seidel(ws, laws)?;
            if info.status != Status::Solved {
                return Err(LcpFailure::Status(info.status));
            }
            info
        } else {
            let lcp = LcpRef::from_column_major(s, &ws.a[..s * s], &ws.b[..s])
                .map_err(LcpFailure::Input)?;
            // The previous step's (P_N, P_R, ξ_L) of each contact: PGS starts from them and
            // Auto first tries the complementary basis they name.
            let warm = if matches!(options.solver, SolverChoice::Pgs { .. } | SolverChoice::Auto) {
                for (a, &i) in ws.active.iter().enumerate() {
                    ws.warm[a] = ws.prev[i][0];
                }
                for (k, &a) in ws.frictional.iter().enumerate() {
                    let [_, p_r, xi_l] = ws.prev[ws.active[a]];
                    ws.warm[na + k] = p_r;
                    ws.warm[na + nf + k] = xi_l;
                }
                Some(&ws.warm[..s])
            } else {
                None
            };
            solver.solve(lcp, warm, &mut ws.solution).map_err(LcpFailure::Solver)?;
            if ws.solution.status != Status::Solved {
                return Err(LcpFailure::Status(ws.solution.status));
            }
            LcpInfo {
                method: ws.solution.method,
                status: ws.solution.status,
                iterations: ws.solution.iterations,
                residual: ws.solution.residual.max(),
            }
        };

        // u_E = ũ + M⁻¹(w_N − μ w_T) P_N + M⁻¹ w_T P_R (eq. 7.36).
        let z = &ws.solution.z;
        ws.tmp.copy_from_slice(&ws.u_free);
        for a in 0..na {
            let p_n = z[a].max(0.0);
            ws.prev[ws.active[a]] = [p_n, 0.0, 0.0];
            if p_n != 0.0 {
                for (u, y) in ws.tmp.iter_mut().zip(&ws.y_n[a * f..][..f]) {
                    *u += y * p_n;
                }
            }
        }
        for (k, &a) in ws.frictional.iter().enumerate() {
            let p_r = z[na + k].max(0.0);
            let i = ws.active[a];
            ws.prev[i][1] = p_r;
            ws.prev[i][2] = z[na + nf + k].max(0.0);
            if p_r != 0.0 {
                for (u, x) in ws.tmp.iter_mut().zip(&ws.x_t[k * f..][..f]) {
                    *u += x * p_r;
                }
            }
        }
        Ok((s, solved))
    }

    /// [`Self::contact_step`] for one active frictionless contact i with the default solver,
    /// without the general assembly: the LCP is the scalar A P_N + b ≥ 0, P_N ≥ 0 with
    /// A = w_Nᵀ M⁻¹ w_N and b = w_Nᵀ ũ + ŵ_N + ε_N γ_NA, so P_N = 0 when b ≥ 0 and
    /// P_N = −b/A otherwise; u_E = ũ + M⁻¹ w_N P_N. `None` (nothing written that the general
    /// path needs) when A is not positive or −b/A is not finite.
    #[inline(always)]
    fn one_frictionless_contact<K: Mechanism, const N: usize>(
        mech: &K,
        ws: &mut Workspace,
        u_a: &[f64],
        t_m: f64,
        i: usize,
    ) -> Result<Option<(usize, LcpInfo)>, LcpFailure> {
        let f = order::<N>(u_a.len());
        let u_a = &u_a[..f];
        let (w_n, w_t) = (&mut ws.w_n[..f], &mut ws.w_t[..f]);
        let point = mech.contact(i, &ws.q_m, t_m, w_n, w_t);
        check_directions(w_n, w_t)?;
        ws.w_n_hat[0] = point.w_n_hat;
        ws.w_t_hat[0] = point.w_t_hat;
        let gamma_na = dot(w_n, u_a) + point.w_n_hat;
        let u_free = &ws.u_free[..f];
        let b = dot(w_n, u_free) + point.w_n_hat + mech.laws()[i].eps_n() * gamma_na;
        ws.b[0] = b;
        let u_e = &mut ws.tmp[..f];
        if b >= 0.0 {
            u_e.copy_from_slice(u_free);
            ws.prev[i] = [0.0; 3];
            let info = LcpInfo {
                method: Method::Trivial,
                status: Status::Solved,
                iterations: 0,
                residual: 0.0,
            };
            return Ok(Some((1, info)));
        }
        let y = &mut ws.y_n[..f];
        ws.chol.solve_into::<N>(w_n, y);
        let a = dot(w_n, y);
        let p_n = -b / a;
        if !(a > 0.0 && p_n.is_finite()) {
            return Ok(None);
        }
        ws.a[0] = a;
        ws.last_size = 1;
        for ((u_e, u), y) in u_e.iter_mut().zip(u_free).zip(y.iter()) {
            *u_e = u + y * p_n;
        }
        ws.prev[i] = [p_n, 0.0, 0.0];
        // z = −b/A and w = A z + b are each one rounding from exact: the equation error is
        // the residual.
        let info = LcpInfo {
            method: Method::ClosedForm,
            status: Status::Solved,
            iterations: 0,
            residual: (a * p_n + b).abs(),
        };
        Ok(Some((1, info)))
    }

    /// Turns a failure of the contact step into the public error, with the LCP instance.
    fn lcp_error(&self, failure: LcpFailure) -> StepError {
        let t = self.t;
        match failure {
            LcpFailure::NonFinite { what, index } => StepError::NonFinite { what, index, t },
            // Finite M, h and W give a finite LCP unless the state has grown past the range
            // of f64 in between: report that as the state it is.
            LcpFailure::Input(moreau_lcp::LcpError::NonFinite { .. }) => {
                StepError::NonFinite { what: "LCP (A, b): the state has diverged", index: 0, t }
            }
            LcpFailure::Input(e) | LcpFailure::Solver(e) => StepError::Lcp(e),
            LcpFailure::Status(status) => {
                let na = self.ws.active.len();
                let s = na + 2 * self.ws.frictional.len();
                let lcp =
                    Lcp::from_column_major(s, &self.ws.a[..s * s], &self.ws.b[..s]).map(Box::new);
                match lcp {
                    Ok(lcp) => StepError::LcpFailed {
                        step: self.step,
                        t,
                        q: self.q.clone(),
                        u: self.u.clone(),
                        status,
                        lcp,
                    },
                    Err(e) => StepError::Lcp(e),
                }
            }
        }
    }

    /// The loop of [`Stepper::run_until`]: `n` steps of [`Self::advance_n`] with `mech`, the
    /// concrete mechanism behind `outer`, which the observer sees.
    fn run_steps<K: Mechanism, M: Mechanism, const N: usize, O: Observer<M>>(
        &mut self,
        mech: &K,
        outer: &M,
        n: u64,
        t_end: f64,
        observer: &mut O,
    ) -> Result<RunSummary, StepError> {
        let solves_before = self.ws.lcp_solves;
        let mut steps = 0;
        let mut stopped = false;
        for _ in 0..n {
            self.advance_n::<K, N>(mech)?;
            steps += 1;
            if observer.observe(outer, &self.report()).is_break() {
                stopped = true;
                break;
            }
        }
        Ok(RunSummary {
            steps,
            lcp_solves: self.ws.lcp_solves - solves_before,
            t_end: self.t,
            stopped_early: stopped && self.t < t_end,
        })
    }
}

/// One step of a [`Core`] with the concrete mechanism.
struct Advance<'a> {
    core: &'a mut Core,
}

impl ConcreteOp for Advance<'_> {
    type Output = Result<(), StepError>;
    fn run<K: Mechanism>(self, mechanism: &K) -> Self::Output {
        self.core.advance(mechanism)
    }
}

/// The loop of [`Stepper::run_until`] with the concrete mechanism, the order f chosen once.
struct RunSteps<'a, M, O> {
    core: &'a mut Core,
    outer: &'a M,
    n: u64,
    t_end: f64,
    observer: &'a mut O,
}

impl<M: Mechanism, O: Observer<M>> ConcreteOp for RunSteps<'_, M, O> {
    type Output = Result<RunSummary, StepError>;
    fn run<K: Mechanism>(self, mech: &K) -> Self::Output {
        let RunSteps { core, outer, n, t_end, observer } = self;
        match core.q.len() {
            1 => core.run_steps::<K, M, 1, O>(mech, outer, n, t_end, observer),
            2 => core.run_steps::<K, M, 2, O>(mech, outer, n, t_end, observer),
            3 => core.run_steps::<K, M, 3, O>(mech, outer, n, t_end, observer),
            4 => core.run_steps::<K, M, 4, O>(mech, outer, n, t_end, observer),
            _ => core.run_steps::<K, M, 0, O>(mech, outer, n, t_end, observer),
        }
    }
}

/// Relative residual up to which a closed-form solution is accepted (that of the LCP
/// solvers' default).
const CLOSED_FORM_TOLERANCE: f64 = 1e-9;

/// The cases of one active contact's LCP (EQUATIONS.md section 5 with n = 1), in the order
/// they are tried.
#[derive(Clone, Copy, PartialEq)]
enum Mode {
    /// ξ_T = 0 with |P_T| ≤ μ P_N: (P_N, P_R) from the 2 × 2 system, ξ_L = 0.
    Stick,
    /// ξ_T > 0: P_T = −μ P_N (P_R = 0, ξ_L = 0).
    SlidePositive,
    /// ξ_T < 0: P_T = +μ P_N (P_L = 0, so P_R = 2μ P_N; ξ_L = −ξ_T).
    SlideNegative,
}

/// Solves the LCP of a single active frictional contact (three rows, x = (P_N, P_R, ξ_L)) in
/// closed form, as the time-stepper's default solver does (a frictionless one takes
/// `Stepper::one_frictionless_contact`). With b_N < 0 the contact carries an impulse, and one
/// of stick, slip forwards and slip backwards holds; they are tried starting with the previous
/// step's case, the one that holds on most steps (should several hold, it is also the one
/// kept, as with Auto's warm basis). The z found is accepted only when the shared residual
/// passes [`CLOSED_FORM_TOLERANCE`]; otherwise `None`, and the caller runs the general solver.
fn one_contact_closed_form(
    A: &[f64],
    b: &[f64],
    mu: f64,
    prev: [f64; 3],
    out: &mut Solution,
) -> Option<LcpInfo> {
    const S: usize = 3;
    let (A, b): (&[f64; S * S], &[f64; S]) = (A.try_into().ok()?, b.try_into().ok()?);
    // A is column-major: A[r + 3 c].
    let (a00, a10, a01, a11) = (A[0], A[1], A[3], A[4]);
    let [p_n, p_r, xi_l] = prev;
    let first = if p_n > 0.0 && xi_l > 0.0 {
        Mode::SlideNegative
    } else if p_n > 0.0 && p_r == 0.0 {
        Mode::SlidePositive
    } else {
        Mode::Stick
    };
    let others = [Mode::Stick, Mode::SlidePositive, Mode::SlideNegative];
    let mut order = std::iter::once(first).chain(others.into_iter().filter(|&m| m != first));
    // Comparisons with NaN are false: a singular case yields no candidate.
    let found = order.find_map(|mode| match mode {
        Mode::Stick => {
            let det = a00 * a11 - a01 * a10;
            let p_n = (a01 * b[1] - a11 * b[0]) / det;
            let p_r = (a10 * b[0] - a00 * b[1]) / det;
            (p_n >= 0.0 && p_r >= 0.0 && 2.0 * mu * p_n - p_r >= 0.0).then_some([p_n, p_r, 0.0])
        }
        Mode::SlidePositive => {
            let p_n = -b[0] / a00;
            (p_n >= 0.0 && a10 * p_n + b[1] >= 0.0).then_some([p_n, 0.0, 0.0])
        }
        Mode::SlideNegative => {
            let p_n = -b[0] / (a00 + 2.0 * mu * a01);
            let xi_l = -(a10 * p_n + 2.0 * mu * a11 * p_n + b[1]);
            (p_n >= 0.0 && xi_l >= 0.0).then_some([p_n, 2.0 * mu * p_n, xi_l])
        }
    })?;
    let (z, w) = (&mut out.z, &mut out.w);
    z.clear();
    z.extend_from_slice(&found);
    w.clear();
    for r in 0..S {
        w.push(b[r] + (0..S).map(|c| A[r + c * S] * z[c]).sum::<f64>());
    }
    let residual = moreau_lcp::Residual::compute_column_major(S, A, b, z, w);
    (residual.relative <= CLOSED_FORM_TOLERANCE).then(|| LcpInfo {
        method: Method::ClosedForm,
        status: Status::Solved,
        iterations: 0,
        residual: residual.max(),
    })
}

/// The nonsmooth Gauss-Seidel of `moreau_lcp` on the contact problem in (P_N, P_T),
/// equivalent to the LCP of eq. 7.41: W is the Delassus matrix G = [W_N W_T]ᵀ M⁻¹ [W_N W_T]
/// ordered by contact, q = (b_N, b_R) and μ per contact; a frictionless contact gets μ = 0
/// and a tangential row of its own scale coupled to nothing, which keeps its P_T at zero.
/// Warm-started from the previous step's impulses. Writes z = (P_N; P_R; ξ_L) of eq. 7.41
/// into `ws.solution.z` and checks it with the LCP's own residual.
fn nonsmooth_gauss_seidel(
    ws: &mut Workspace,
    laws: &[moreau_setvalued::ContactLaw],
) -> Result<LcpInfo, LcpFailure> {
    let f = ws.q_m.len();
    let na = ws.active.len();
    let nf = ws.frictional.len();
    let m = na + nf;
    let s = na + 2 * nf;
    // M⁻¹ w_N = y_N + μ x_T for frictional contacts, y_N otherwise.
    let column = |ws: &Workspace, c: usize, out: &mut [f64]| {
        if c < na {
            out.copy_from_slice(&ws.y_n[c * f..][..f]);
            if let Some(k) = ws.frictional.iter().position(|&a| a == c) {
                let mu = laws[ws.active[c]].mu();
                for (o, x) in out.iter_mut().zip(&ws.x_t[k * f..][..f]) {
                    *o += mu * x;
                }
            }
        } else {
            let k = c - na;
            out.copy_from_slice(&ws.x_t[k * f..][..f]);
        }
    };
    let row = |ws: &Workspace, r: usize| -> std::ops::Range<usize> {
        let a = if r < na { r } else { ws.frictional[r - na] };
        a * f..(a + 1) * f
    };
    let mut x = std::mem::take(&mut ws.tmp);
    for c in 0..m {
        column(ws, c, &mut x);
        for r in 0..m {
            let w = if r < na { &ws.w_n[row(ws, r)] } else { &ws.w_t[row(ws, r)] };
            ws.g[r + c * m] = dot(w, &x);
        }
    }
    ws.tmp = x;
    // The row (and column) of G of each contact's tangential impulse, if it has one.
    let g = &ws.g[..m * m];
    let tangent = |a: usize| ws.frictional.iter().position(|&c| c == a).map(|k| na + k);
    let n = 2 * na;
    let w = &mut ws.fc_w[..n * n];
    w.fill(0.0);
    for a in 0..na {
        let (ra, ta) = (a, tangent(a));
        for c in 0..na {
            let (rc, tc) = (c, tangent(c));
            w[2 * a + 2 * c * n] = g[ra + rc * m];
            if let Some(tc) = tc {
                w[2 * a + (2 * c + 1) * n] = g[ra + tc * m];
            }
            if let Some(ta) = ta {
                w[2 * a + 1 + 2 * c * n] = g[ta + rc * m];
                if let Some(tc) = tc {
                    w[2 * a + 1 + (2 * c + 1) * n] = g[ta + tc * m];
                }
            }
        }
        let law = laws[ws.active[a]];
        let [p_n, p_r, _] = ws.prev[ws.active[a]];
        ws.fc_q[2 * a] = ws.b[a];
        ws.fc_warm[2 * a] = p_n;
        match ta {
            Some(t) => {
                ws.fc_q[2 * a + 1] = ws.b[t];
                ws.fc_mu[a] = law.mu();
                ws.fc_warm[2 * a + 1] = p_r - law.mu() * p_n;
            }
            None => {
                let d = g[a + a * m];
                w[2 * a + 1 + (2 * a + 1) * n] = if d > 0.0 { d } else { 1.0 };
                ws.fc_q[2 * a + 1] = 0.0;
                ws.fc_mu[a] = 0.0;
                ws.fc_warm[2 * a + 1] = 0.0;
            }
        }
    }
    ws.fc
        .set_dense(MatRef::from_column_major_slice(w, n, n), &ws.fc_q[..n], &ws.fc_mu[..na])
        .map_err(LcpFailure::Input)?;
    let nsgs = ws.nsgs.as_mut().expect("a stepper with the Gauss-Seidel choice holds its solver");
    nsgs.solve_into(ws.fc.view(), Some(&ws.fc_warm[..n]), &mut ws.fc_solution)
        .map_err(LcpFailure::Solver)?;
    // z = (P_N; P_R = P_T + μ P_N; ξ_L = max(0, −ξ_T)) of eq. 7.41, and its residual.
    let (r, u) = (&ws.fc_solution.r, &ws.fc_solution.u);
    let z = &mut ws.solution.z;
    z.clear();
    z.resize(s, 0.0);
    for a in 0..na {
        z[a] = r[2 * a];
    }
    for (k, &a) in ws.frictional.iter().enumerate() {
        z[na + k] = r[2 * a + 1] + ws.fc_mu[a] * r[2 * a];
        z[na + nf + k] = (-u[2 * a + 1]).max(0.0);
    }
    let w = &mut ws.solution.w;
    w.clear();
    w.resize(s, 0.0);
    for r in 0..s {
        let mut v = ws.b[r];
        for c in 0..s {
            v += ws.a[r + c * s] * z[c];
        }
        w[r] = v;
    }
    let lcp = LcpRef::new(
        MatRef::from_column_major_slice(&ws.a[..s * s], s, s),
        ColRef::from_slice(&ws.b[..s]),
    );
    let residual = match lcp {
        Ok(lcp) => moreau_lcp::Residual::compute(lcp, z, w).max(),
        Err(_) => f64::INFINITY,
    };
    Ok(LcpInfo {
        method: Method::Nsgs,
        status: ws.fc_solution.status,
        iterations: ws.fc_solution.iterations,
        residual,
    })
}

/// Internal failure of a contact step, turned into a [`StepError`] with context.
enum LcpFailure {
    NonFinite { what: &'static str, index: usize },
    Input(moreau_lcp::LcpError),
    Solver(moreau_lcp::LcpError),
    Status(Status),
}

#[allow(dead_code)]
fn _assert_send_sync() {
    fn is<T: Send + Sync>() {}
    is::<StepError>();
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
