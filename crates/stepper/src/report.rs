//! What a step reports: each contact's state, impulses and relative velocities, and how the
//! step's contact problem was solved.

use std::time::Duration;

use moreau_lcp::{Method, Status};

use crate::dense::{half_bilinear, half_quadratic};

/// Whether a contact is open, sticking or slipping at the end of a step.
///
/// The state describes the tangential velocity γ_T,E after the step, not the branch of the
/// friction law: under tangential restitution ε_T > 0, an impact that sticks in Newton's
/// tangential law (ξ_T = γ_T,E + ε_T γ_T,A = 0 with |P_T| < μ P_N) leaves the contact
/// with γ_T,E = −ε_T γ_T,A ≠ 0, reversing its sliding, and is reported as [`Self::Slip`].
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
    /// The solver's status: `Solved`, or, for a mechanism with a [`crate::BodyStructure`]
    /// whose options set [`crate::StepperOptions::inexact_residual`], the status of an island
    /// taken above the solvers' tolerance (`IterationLimit`). Other failures are errors.
    pub status: Status,
    /// Pivots or sweeps used.
    pub iterations: usize,
    /// The shared residual's scale-free acceptance measure (`moreau_lcp::Residual::relative`)
    /// of the accepted (P_N, P_R, ξ_L) on the step's LCP, whichever method produced it; 0 for
    /// the zero impulse of separating contacts, which solves the LCP exactly. For a mechanism
    /// with a [`crate::BodyStructure`] it is the same measure of the LCP of eq. 7.41 written
    /// for each island's (P_N, P_R = P_T + μ P_N, ξ_L), evaluated on the sparse blocks.
    ///
    /// An island's solvers accept by another measure, the natural residual of its planar
    /// frictional-contact problem (moreau-lcp's `Fc2dResidual`: 1e-10 against velocities of
    /// order 1), which is absolute where this one weighs each row against its own terms. A
    /// row whose terms are all small (a lightly loaded contact) can therefore read above the
    /// tolerance here on a step whose status is `Solved`: 2 of the 2,000 steps of the
    /// 600-grain flow (`scenes/scale/granular-flow.toml`) read 4.7e-5 and 1.6e-4.
    pub residual: f64,
}

impl LcpInfo {
    /// The residual of a step taken with an island above the solvers' tolerance (status other
    /// than `Solved`, as [`crate::StepperOptions::inexact_residual`] allows), `None` for a
    /// solved step: what [`RunSummary::inexact_steps`] counts.
    pub fn inexact(&self) -> Option<f64> {
        (self.status != Status::Solved).then_some(self.residual)
    }
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
    /// The contacts' reports: one per contact of the mechanism, in its order, on the path of
    /// fixed contacts; one per contact detected at the step's midpoint, in increasing order of
    /// identity, for a mechanism with a [`crate::BodyStructure`].
    pub contacts: &'a [ContactReport],
    /// The identity of each entry of `contacts`: the contact's index on the path of fixed
    /// contacts (0, 1, 2, ...), the [`crate::BodyContact::id`] the detection gave it for a
    /// mechanism with a [`crate::BodyStructure`].
    pub contact_ids: &'a [u64],
    /// Size of the LCP (0 when no contact was closed): one row per active frictionless
    /// contact, three per active frictional one. For a mechanism with a
    /// [`crate::BodyStructure`], the rows of the step's frictional-contact problems, two per
    /// detected contact.
    pub lcp_size: usize,
    /// How the LCP was solved, if there was one. For a mechanism with a
    /// [`crate::BodyStructure`], whose contacts are solved island by island, the worst island:
    /// the largest number of iterations and the largest residual, with the method of the island
    /// of largest residual.
    pub lcp: Option<LcpInfo>,
    /// The largest penetration max(0, −g_N) among the contacts at the step's midpoint q_M
    /// (m); 0 when none penetrates.
    pub penetration: f64,
    /// The largest |g_B| of the bilateral constraints at the step's midpoint q_M (m or rad):
    /// how far the positions have drifted off the joints; 0 without joints.
    pub joint_drift: f64,
    /// The end positions q_E as the midpoint rule gave them, before the position projection
    /// ([`crate::StepperOptions::projection`]) moved them to [`Self::q`]; `None` when the
    /// projection is off or left q_E as it was. The projection moves q alone: the energy it
    /// adds is [T + V](q, u_E, t_E) − [T + V](this, u_E, t_E), which
    /// [`crate::Record::cumulative_projection`] sums.
    pub q_unprojected: Option<&'a [f64]>,
    /// The joints' impulses Λ_B of the step, one per bilateral constraint in the order of
    /// [`crate::Mechanism::bilaterals`] (N s for a constraint on a distance, N m s on an
    /// angle; Λ_B / Δt is the mean reaction over the step), on the bodies as W_B Λ_B: the
    /// reactions of the joints. Empty without joints.
    pub joint_impulses: &'a [f64],
    /// The number of islands the step's problem split into, for a mechanism with a
    /// [`crate::BodyStructure`]: the connected components of the bodies linked by the step's
    /// contacts and joints (0 on the path of fixed contacts).
    pub islands: usize,
    /// The wall time of the step's phases, measured for a mechanism with a
    /// [`crate::BodyStructure`] (all zero otherwise).
    pub times: PhaseTimes,
    /// M_M (column-major, or by 3 × 3 blocks), the impulse-free velocity ũ (before the joints'
    /// impulses) and the velocity u_A at the step's start (read only when an impulse acted),
    /// for [`Self::impulse_dissipation`].
    pub(crate) mass: MassView<'a>,
    pub(crate) u_free: &'a [f64],
    pub(crate) u_start: &'a [f64],
}

/// The impulses of one step, by contact identity and by joint row: what a stepper keeps of
/// its last step, as the next step's warm start and to tell an impact (a contact closing
/// after a step without impulse) from persistent contact. Taken from a step's report
/// ([`Self::of`]) and given to a stepper restarted from that step's end state
/// ([`Stepper::set_impulses`](crate::Stepper::set_impulses)), they let the run go on as the
/// run that did not stop would: a settled pile restarted without them is solved from zero
/// impulses, which takes a large island many sweeps and reports its resting contacts as
/// impacts.
///
/// ```
/// use moreau_stepper::Impulses;
///
/// // Contact 3 pressed with P_N = 0.2 N s and sliding back with P_T = −0.05 N s.
/// let impulses = Impulses { contacts: vec![(3, 0.2, -0.05)], joints: vec![] };
/// assert_eq!(impulses.contacts[0].1, 0.2);
/// ```
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Impulses {
    /// The contacts that carried an impulse, as (identity, P_N, P_T) in N s and in increasing
    /// order of identity ([`StepReport::contact_ids`]: the index on the path of fixed
    /// contacts, the detection's identity on the many-body path). A contact not listed carried
    /// none.
    #[serde(default)]
    pub contacts: Vec<(u64, f64, f64)>,
    /// The joints' impulses Λ_B, one per bilateral constraint
    /// ([`StepReport::joint_impulses`]); empty to start the joints from zero.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joints: Vec<f64>,
}

impl Impulses {
    /// The impulses of the step that `report` describes: its contacts with a nonzero impulse
    /// (the zero impulse is what an unlisted contact has) and its joints' impulses.
    pub fn of(report: &StepReport<'_>) -> Self {
        let contacts = report
            .contact_ids
            .iter()
            .zip(report.contacts)
            .filter(|(_, c)| c.p_n != 0.0 || c.p_t != 0.0)
            .map(|(&id, c)| (id, c.p_n, c.p_t))
            .collect();
        Impulses { contacts, joints: report.joint_impulses.to_vec() }
    }

    /// Whether no contact and no joint carried an impulse.
    pub fn is_empty(&self) -> bool {
        self.contacts.is_empty() && self.joints.iter().all(|&l| l == 0.0)
    }
}

/// The wall time of the phases of one step of a mechanism with a [`crate::BodyStructure`],
/// for scaling studies.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhaseTimes {
    /// The detection of the contacts at the midpoint ([`crate::BodyStructure::detect`]).
    pub detection: Duration,
    /// The midpoint, the mass blocks and their inverses, h, ũ, the islands, the right-hand
    /// sides and the 2 × 2 blocks of W of every island.
    pub assembly: Duration,
    /// The islands' frictional-contact solves and the end velocities and positions.
    pub solution: Duration,
    /// The projection of the positions (detection at q_E included), when it is on.
    pub projection: Duration,
}

/// The mass matrix a step report holds.
#[derive(Clone, Copy, Debug)]
pub(crate) enum MassView<'a> {
    /// M, column-major f × f.
    Dense(&'a [f64]),
    /// One 3 × 3 block per body, column-major.
    Blocks(&'a [[f64; 9]]),
}

impl MassView<'_> {
    /// xᵀ M x / 2.
    pub(crate) fn half_quadratic(&self, x: &[f64]) -> f64 {
        match self {
            MassView::Dense(m) => half_quadratic(m, x.len(), x),
            MassView::Blocks(blocks) => {
                blocks.iter().zip(x.chunks_exact(3)).map(|(m, x)| half_quadratic(m, 3, x)).sum()
            }
        }
    }
}

impl StepReport<'_> {
    /// Energy removed by the impulses of the step (J): minus their work on the mechanism,
    /// −½ (W P)ᵀ (u_A + u_E) = ½ (ũ − u_E)ᵀ M_M (u_A + u_E), with ũ = u_A + M_M⁻¹h_M Δt the
    /// impulse-free velocity and W P = M_M (u_E − ũ) the impulses of the contacts and of the
    /// joints; zero when no impulse acted. Ideal joints do no work, but the midpoint rule's
    /// joints, held at the velocity level at q_M, do: what they remove is the scheme's error.
    ///
    /// The midpoint rule's change of kinetic energy, ½ (u_E − u_A)ᵀ M_M (u_E + u_A), is the
    /// work of h_M Δt over the step's displacement Δt (u_A + u_E)/2 = q_E − q_A plus this
    /// work of the impulses. So under constant forces (gravity), kinetic plus potential energy
    /// plus the sum of this quantity stays at its start to round-off, a contact at rest adds
    /// nothing (u_A = u_E = 0), and an impact adds ½ (1 − ε_N²) m γ_N,A² on a single contact
    /// without friction. Computed on demand: it costs one bilinear form.
    pub fn impulse_dissipation(&self) -> f64 {
        // Joints act at every step; contacts when they carry an impulse.
        let no_joints = self.joint_impulses.is_empty();
        if no_joints && self.contacts.iter().all(|c| c.p_n == 0.0 && c.p_t == 0.0) {
            return 0.0;
        }
        let (free, end, start) = (self.u_free, self.u, self.u_start);
        let x = |i: usize| free[i] - end[i];
        let y = |i: usize| start[i] + end[i];
        match self.mass {
            MassView::Dense(m) => half_bilinear(m, end.len(), x, y),
            MassView::Blocks(blocks) => blocks
                .iter()
                .enumerate()
                .map(|(b, m)| half_bilinear(m, 3, |i| x(3 * b + i), |j| y(3 * b + j)))
                .sum(),
        }
    }
}

/// What [`Stepper::run_until`](crate::Stepper::run_until) did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSummary {
    /// Steps taken.
    pub steps: u64,
    /// Steps whose LCP needed a solver (neither empty nor settled by the zero impulse).
    pub lcp_solves: u64,
    /// Steps taken with an island above the solvers' tolerance, as
    /// [`StepperOptions::inexact_residual`](crate::StepperOptions::inexact_residual) allows;
    /// always 0 without it.
    pub inexact_steps: u64,
    /// The largest [`LcpInfo::residual`] of those steps; 0 when there were none.
    pub inexact_residual: f64,
    /// Time reached (s).
    pub t_end: f64,
    /// Whether the observer stopped the run before `t_end`.
    pub stopped_early: bool,
}
