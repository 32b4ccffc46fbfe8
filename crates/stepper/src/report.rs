//! What a step reports: each contact's state, impulses and relative velocities, and how the
//! step's contact problem was solved.

use moreau_lcp::{Method, Status};

use crate::dense::half_quadratic;

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
    /// Normal relative velocity γ_N,E = w_Nᵀ u_E + ŵ_N after the step, with w_N and ŵ_N at
    /// (q_M, t_M) (only meaningful when active).
    pub gamma_n: f64,
    /// Tangential relative velocity γ_T,E after the step (only meaningful when active).
    pub gamma_t: f64,
    /// Normal relative velocity γ_N,A = w_Nᵀ u_A + ŵ_N before the step, the velocity Newton's
    /// law acts on, with w_N and ŵ_N at (q_M, t_M) (only meaningful when active).
    pub gamma_n_a: f64,
    /// Tangential relative velocity γ_T,A before the step, with w_T and ŵ_T at (q_M, t_M)
    /// (only meaningful when active).
    pub gamma_t_a: f64,
    /// Whether the step was an impact at this contact: the contact closed (P_N > 0) after a
    /// step in which it carried no impulse, approaching with γ_N,A < 0. Persistent contact is
    /// not an impact, however γ_N,A rounds; a soft closing (γ_N,A of the order of the speed the
    /// smooth forces give in one step) is, and `gamma_n_a` tells the two apart.
    pub impact: bool,
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
    /// The shared residual's scale-free acceptance measure (`moreau_lcp::Residual::relative`)
    /// of the accepted (P_N, P_R, ξ_L) on the step's LCP, whichever method produced it; 0 for
    /// the zero impulse of separating contacts, which solves the LCP exactly.
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
    /// The largest penetration max(0, −g_N) among the contacts at the step's midpoint q_M
    /// (m); 0 when none penetrates.
    pub penetration: f64,
    /// The largest |g_B| of the bilateral constraints at the step's midpoint q_M (m or rad):
    /// how far the positions have drifted off the joints; 0 without joints.
    pub joint_drift: f64,
    /// M_M, column-major, and the impulse-free velocity ũ, for [`Self::impulse_dissipation`].
    pub(crate) mass: &'a [f64],
    pub(crate) u_free: &'a [f64],
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

/// What [`Stepper::run_until`](crate::Stepper::run_until) did.
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
