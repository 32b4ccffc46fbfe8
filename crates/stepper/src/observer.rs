//! Streaming results: the [`Observer`] trait and the [`Recorder`] that keeps a [`Record`].

use std::ops::ControlFlow;

use serde::{Deserialize, Serialize};

use crate::dense::half_quadratic;
use crate::report::MassView;
use crate::{ContactReport, ContactState, Impulses, Mechanism, Rows, StepReport};

/// Receives every step of a run; returning [`ControlFlow::Break`] stops the run after it.
///
/// Closures `FnMut(&StepReport) -> ControlFlow<()>` are observers too (with the default
/// [`Observer::finish`], which does nothing), and so is `()`, which keeps nothing:
/// `stepper.run_until(t_end, &mut ())?` only advances the state.
pub trait Observer<M: ?Sized> {
    /// Called after each step with the mechanism and the step's report.
    fn observe(&mut self, mechanism: &M, report: &StepReport<'_>) -> ControlFlow<()>;

    /// Called once when a run of [`crate::Stepper::run_until`] has ended without an error,
    /// with the report of its last step, the one `observe` was last called with: after the
    /// step that reached t_end, or after the step on which `observe` returned
    /// [`ControlFlow::Break`]. Not called for a run of no steps, nor after a failed step (the
    /// run then returns the error). Does nothing by default; a [`Recorder`] writes the last
    /// step's row here when its thinning skipped it. An observer that wraps another passes
    /// the call on when its inner observer saw that step.
    fn finish(&mut self, mechanism: &M, last: &StepReport<'_>) {
        let _ = (mechanism, last);
    }
}

impl<M: ?Sized, F: FnMut(&StepReport<'_>) -> ControlFlow<()>> Observer<M> for F {
    fn observe(&mut self, _mechanism: &M, report: &StepReport<'_>) -> ControlFlow<()> {
        self(report)
    }
}

impl<M: ?Sized> Observer<M> for () {
    fn observe(&mut self, _mechanism: &M, _report: &StepReport<'_>) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// One impact of a run: a step in which a contact closed with Newton's law acting on a
/// negative normal relative velocity (see [`ContactReport::impact`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Impact {
    /// Index of the step since the stepper was created (see [`StepReport::step`]).
    pub step: u64,
    /// End time t_E of the impact step (s); the step spans (t_E − Δt, t_E].
    pub t: f64,
    /// The contact, as an index into the mechanism's contacts (0-based); for a mechanism with
    /// a [`crate::BodyStructure`], the contact's identity ([`crate::BodyContact::id`]).
    pub contact: usize,
    /// Normal relative velocity before the step, γ_N,A < 0 (m/s, or rad/s for an angular
    /// gap).
    pub gamma_n_before: f64,
    /// Normal relative velocity after the step, γ_N,E; for a single contact without friction
    /// and a constant w_N, −ε_N γ_N,A.
    pub gamma_n_after: f64,
    /// Normal impulse P_N of the step (N s).
    pub p_n: f64,
    /// Tangential impulse P_T of the step (N s).
    pub p_t: f64,
}

/// A recorded trajectory: one row per kept step, and every impact.
///
/// Row `k` holds the state at `t[k]`; the impulses and activity of row `k` are those of the
/// steps since the previous row (summed when rows are thinned with [`Recorder::every`]). Row 0
/// is the state the run started from, with zero impulses. The last row of a run of
/// [`crate::Stepper::run_until`] is its last step, thinned rows or not (see
/// [`Observer::finish`]): a run of 10 steps kept one in 4 has rows at steps 0, 4, 8 and 10.
/// [`Record::impacts`] lists every impact of every step, thinned rows or not.
///
/// For a mechanism with a [`crate::BodyStructure`], whose contacts come and go, the rows keep
/// the bodies' q and u, the energies and the solver's numbers, and the per-contact columns
/// (`p_n`, `p_t`, `active`, `state`) have no entries; the impacts are listed by contact
/// identity. An observer of [`StepReport::contacts`] and [`StepReport::contact_ids`] sees every
/// contact of every step.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Record {
    /// Time t (s).
    pub t: Vec<f64>,
    /// Generalised coordinates q.
    pub q: Rows<f64>,
    /// Generalised velocities u.
    pub u: Rows<f64>,
    /// Normal impulses P_N per contact (zero when open).
    pub p_n: Rows<f64>,
    /// Tangential impulses P_T per contact (zero when open or frictionless).
    pub p_t: Rows<f64>,
    /// Whether each contact was in the active set (g_N(q_M) ≤ 0).
    pub active: Rows<bool>,
    /// Open, sticking or slipping, per contact, at the end of the row's last step.
    pub state: Rows<ContactState>,
    /// The joints' impulses Λ_B per bilateral constraint, in the order of
    /// [`crate::Mechanism::bilaterals`] ([`StepReport::joint_impulses`]), summed over the
    /// row's steps (zero in row 0); no entries without joints.
    #[serde(default)]
    pub joint_impulses: Rows<f64>,
    /// Size of the row's last LCP (0 when no contact was closed).
    pub lcp_size: Vec<usize>,
    /// Iterations or pivots of the row's last LCP solve.
    pub iterations: Vec<usize>,
    /// Kinetic energy uᵀ M u / 2 (J).
    pub kinetic: Vec<f64>,
    /// Potential energy V(q, t) (J); zero when the mechanism defines none.
    pub potential: Vec<f64>,
    /// Energy removed by the impulses of contacts and joints and by the dampers from the
    /// recorder's first row up to this row (J): the sum of [`StepReport::impulse_dissipation`]
    /// and of the dampers' work taken out of each step (see [`Mechanism::damping_forces`],
    /// counted from [`Recorder::push_initial`]); cumulative, 0 at row 0. The energy removed by
    /// the steps of row k is `cumulative_dissipation[k] − cumulative_dissipation[k − 1]`.
    /// Under constant smooth forces (gravity) and linear dampers, kinetic + potential +
    /// cumulative dissipation minus [`Self::cumulative_projection`] stays at its initial
    /// value to round-off, under other conservative forces to within the scheme's error. Work
    /// done by drives and applied loads is not counted.
    pub cumulative_dissipation: Vec<f64>,
    /// Energy the position projection ([`crate::StepperOptions::projection`]) added from the
    /// recorder's first row up to this row (J): over the steps whose projection moved q_E,
    /// the sum of [T + V](q_E, u_E, t_E) − [T + V](q_E before the projection, u_E, t_E)
    /// ([`StepReport::q_unprojected`]). The projection moves q alone; pushing a body out of
    /// the floor against gravity adds energy, which this counts. Cumulative, 0 at row 0 and
    /// without the projection.
    #[serde(default)]
    pub cumulative_projection: Vec<f64>,
    /// Every impact, in the order of the steps (see [`ContactReport::impact`]): the steps in
    /// which a contact closed with a negative normal relative velocity γ_N,A. A closing at a
    /// speed below what the smooth forces give in a step or two (γ_N,A of the order of
    /// g Δt) is a soft closing by the scheme's measure, still listed: filter on
    /// [`Impact::gamma_n_before`] to keep the hard ones.
    #[serde(default)]
    pub impacts: Vec<Impact>,
}

impl Record {
    /// Empties the record's rows and makes its tables `f` (q, u), `n` (the contacts) and
    /// `n_b` (the joints' rows) wide; impacts already listed (by the step that writes the first row) are kept.
    fn set_widths(&mut self, f: usize, n: usize, n_b: usize) {
        *self = Self {
            impacts: std::mem::take(&mut self.impacts),
            q: Rows::new(f),
            u: Rows::new(f),
            p_n: Rows::new(n),
            p_t: Rows::new(n),
            active: Rows::new(n),
            state: Rows::new(n),
            joint_impulses: Rows::new(n_b),
            ..Self::default()
        };
    }

    /// Reserves room for `additional` more rows in every column, so that a run of known
    /// length grows no buffer. The tables of q, u and the contacts take their widths from
    /// the first row, so reserve after it for them to be reserved too.
    pub fn reserve(&mut self, additional: usize) {
        for v in [
            &mut self.t,
            &mut self.kinetic,
            &mut self.potential,
            &mut self.cumulative_dissipation,
            &mut self.cumulative_projection,
        ] {
            v.reserve(additional);
        }
        self.lcp_size.reserve(additional);
        self.iterations.reserve(additional);
        for v in [&mut self.q, &mut self.u, &mut self.p_n, &mut self.p_t, &mut self.joint_impulses]
        {
            v.reserve(additional);
        }
        self.active.reserve(additional);
        self.state.reserve(additional);
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether the record has no rows.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Total energy (kinetic plus potential) per row (J).
    pub fn total_energy(&self) -> Vec<f64> {
        self.kinetic.iter().zip(&self.potential).map(|(k, v)| k + v).collect()
    }

    /// The impacts at contact `contact` (0-based), in the order of the steps.
    pub fn impacts_at(&self, contact: usize) -> impl Iterator<Item = &Impact> + '_ {
        self.impacts.iter().filter(move |i| i.contact == contact)
    }
}

/// An [`Observer`] that keeps every `n`-th step in a [`Record`], and the last step of each
/// run of [`crate::Stepper::run_until`] ([`Observer::finish`]), so that a thinned record
/// still ends at t_end or at the step that stopped the run.
///
/// The record's tables take their widths (f coordinates, n contacts) from its first row, so
/// one recorder serves runs of one mechanism.
///
/// # Panics
/// When it is given a row of another mechanism's size after the first row.
#[derive(Clone, Debug)]
pub struct Recorder {
    /// What has been recorded so far.
    pub record: Record,
    every: usize,
    pending: usize,
    mass: Vec<f64>,
    /// The mass blocks of a mechanism with a body structure.
    blocks: Vec<[f64; 9]>,
    sum_p_n: Vec<f64>,
    sum_p_t: Vec<f64>,
    any_active: Vec<bool>,
    /// The joints' impulses summed since the last row.
    sum_joints: Vec<f64>,
    /// The contacts' states of the row being written.
    states: Vec<ContactState>,
    /// Energy removed by the impulses and the dampers since the first row (J).
    sum_dissipated: f64,
    /// Energy added by the position projection since the first row (J).
    sum_projected: f64,
    /// For a mechanism with dampers, the state the observed step starts from and buffers for
    /// their work; `None` otherwise.
    damped: Option<Damped>,
    /// The impulses of the run's last step, once it has finished.
    last_impulses: Option<Impulses>,
}

impl Default for Recorder {
    fn default() -> Self {
        Self::new()
    }
}

impl Recorder {
    /// A recorder that keeps every step.
    pub fn new() -> Self {
        Self::every(1)
    }

    /// A recorder that keeps one step in `n` (`n = 0` is taken as 1), summing the impulses
    /// of the steps in between (impacts are all kept), and the last step of a run.
    pub fn every(n: usize) -> Self {
        Self {
            record: Record::default(),
            every: n.max(1),
            pending: 0,
            mass: Vec::new(),
            blocks: Vec::new(),
            sum_p_n: Vec::new(),
            sum_p_t: Vec::new(),
            any_active: Vec::new(),
            sum_joints: Vec::new(),
            states: Vec::new(),
            sum_dissipated: 0.0,
            sum_projected: 0.0,
            damped: None,
            last_impulses: None,
        }
    }

    /// The impulses of the last step of the run that last finished on this recorder
    /// ([`Impulses::of`] its report): with the record's last state, what a run continued from
    /// there starts with ([`crate::Stepper::set_impulses`]). `None` before a run has finished
    /// (a run of no steps finishes none).
    pub fn last_impulses(&self) -> Option<&Impulses> {
        self.last_impulses.as_ref()
    }

    /// Records the state a run starts from, as row 0 with zero impulses.
    pub fn push_initial<M: Mechanism + ?Sized>(
        &mut self,
        mechanism: &M,
        t: f64,
        q: &[f64],
        u: &[f64],
    ) {
        let n = if mechanism.body_structure().is_some() { 0 } else { mechanism.num_contacts() };
        self.resize(n);
        self.sum_joints.clear();
        self.sum_joints.resize(mechanism.num_bilaterals(), 0.0);
        let contacts = vec![ContactReport::default(); n];
        self.push_row(mechanism, t, q, u, &contacts, 0, 0);
        let mut h_d = vec![0.0; q.len()];
        self.damped = mechanism.damping_forces(q, u, t, &mut h_d).then(|| Damped {
            t,
            q: q.to_vec(),
            u: u.to_vec(),
            q_mid: vec![0.0; q.len()],
            h_d,
        });
    }

    fn resize(&mut self, n: usize) {
        if self.sum_p_n.len() != n {
            self.sum_p_n = vec![0.0; n];
            self.sum_p_t = vec![0.0; n];
            self.any_active = vec![false; n];
        }
    }

    /// The kinetic energy ½ uᵀ M(q, t) u.
    fn kinetic<M: Mechanism + ?Sized>(
        &mut self,
        mechanism: &M,
        q: &[f64],
        u: &[f64],
        t: f64,
    ) -> f64 {
        match mechanism.body_structure() {
            Some(structure) => {
                self.blocks.resize(structure.num_bodies(), [0.0; 9]);
                structure.mass_blocks(q, t, &mut self.blocks);
                MassView::Blocks(&self.blocks).half_quadratic(u)
            }
            None => {
                let f = q.len();
                self.mass.resize(f * f, 0.0);
                mechanism.mass_matrix(q, t, &mut self.mass);
                half_quadratic(&self.mass, f, u)
            }
        }
    }

    /// T + V at (q, u, t), V taken as 0 where the mechanism defines none.
    fn energy<M: Mechanism + ?Sized>(
        &mut self,
        mechanism: &M,
        q: &[f64],
        u: &[f64],
        t: f64,
    ) -> f64 {
        self.kinetic(mechanism, q, u, t) + mechanism.potential_energy(q, t).unwrap_or(0.0)
    }

    fn push_row<M: Mechanism + ?Sized>(
        &mut self,
        mechanism: &M,
        t: f64,
        q: &[f64],
        u: &[f64],
        contacts: &[ContactReport],
        lcp_size: usize,
        iterations: usize,
    ) {
        let kinetic = self.kinetic(mechanism, q, u, t);
        let r = &mut self.record;
        if r.is_empty() {
            r.set_widths(q.len(), self.sum_p_n.len(), self.sum_joints.len());
        }
        r.t.push(t);
        r.q.push(q);
        r.u.push(u);
        r.p_n.push(&self.sum_p_n);
        r.p_t.push(&self.sum_p_t);
        r.active.push(&self.any_active);
        r.joint_impulses.push(&self.sum_joints);
        self.states.clear();
        if self.sum_p_n.is_empty() {
            // Contacts recorded by identity are not kept per row.
        } else {
            self.states.extend(contacts.iter().map(|c| c.state));
        }
        r.state.push(&self.states);
        r.lcp_size.push(lcp_size);
        r.iterations.push(iterations);
        r.kinetic.push(kinetic);
        r.potential.push(mechanism.potential_energy(q, t).unwrap_or(0.0));
        r.cumulative_dissipation.push(self.sum_dissipated);
        r.cumulative_projection.push(self.sum_projected);
        self.sum_p_n.fill(0.0);
        self.sum_p_t.fill(0.0);
        self.any_active.fill(false);
        self.sum_joints.fill(0.0);
    }
}

/// The start (t_A, q_A, u_A) of the step a [`Recorder`] observes next, for the dampers' work.
#[derive(Clone, Debug)]
struct Damped {
    t: f64,
    q: Vec<f64>,
    u: Vec<f64>,
    q_mid: Vec<f64>,
    h_d: Vec<f64>,
}

impl Damped {
    /// The energy the dampers took out of the step `report` ends, −(Δt/2) h_Dᵀ (u_A + u_E)
    /// with h_D at the midpoint (q_M, u_A, t_M), where the step evaluates h: the part of the
    /// midpoint rule's change of kinetic energy, ½ (u_E − u_A)ᵀ M (u_E + u_A), that the
    /// dampers did; then the step's end becomes the next one's start.
    fn step<M: Mechanism + ?Sized>(&mut self, mechanism: &M, report: &StepReport<'_>) -> f64 {
        let half = 0.5 * (report.t - self.t);
        for ((m, q), u) in self.q_mid.iter_mut().zip(&self.q).zip(&self.u) {
            *m = q + half * u;
        }
        self.h_d.fill(0.0);
        mechanism.damping_forces(&self.q_mid, &self.u, self.t + half, &mut self.h_d);
        let work: f64 =
            self.h_d.iter().zip(&self.u).zip(report.u).map(|((h, a), e)| h * (a + e)).sum();
        self.t = report.t;
        self.q.copy_from_slice(report.q);
        self.u.copy_from_slice(report.u);
        -half * work
    }
}

impl<M: Mechanism + ?Sized> Observer<M> for Recorder {
    fn observe(&mut self, mechanism: &M, report: &StepReport<'_>) -> ControlFlow<()> {
        let by_id = mechanism.body_structure().is_some();
        self.resize(if by_id { 0 } else { report.contacts.len() });
        for (i, c) in report.contacts.iter().enumerate() {
            if !by_id {
                self.sum_p_n[i] += c.p_n;
                self.sum_p_t[i] += c.p_t;
                self.any_active[i] |= c.active;
            }
            if c.impact {
                self.record.impacts.push(Impact {
                    step: report.step,
                    t: report.t,
                    contact: if by_id { report.contact_ids[i] as usize } else { i },
                    gamma_n_before: c.gamma_n_a,
                    gamma_n_after: c.gamma_n,
                    p_n: c.p_n,
                    p_t: c.p_t,
                });
            }
        }
        if self.sum_joints.len() != report.joint_impulses.len() {
            self.sum_joints = vec![0.0; report.joint_impulses.len()];
        }
        for (s, l) in self.sum_joints.iter_mut().zip(report.joint_impulses) {
            *s += l;
        }
        self.sum_dissipated += report.impulse_dissipation();
        if let Some(d) = &mut self.damped {
            self.sum_dissipated += d.step(mechanism, report);
        }
        if let Some(q_unprojected) = report.q_unprojected {
            let (u, t) = (report.u, report.t);
            self.sum_projected += self.energy(mechanism, report.q, u, t)
                - self.energy(mechanism, q_unprojected, u, t);
        }
        self.pending += 1;
        if self.pending >= self.every {
            self.push_step(mechanism, report);
        }
        ControlFlow::Continue(())
    }

    /// Writes the last step's row when the thinning skipped it, with the impulses summed
    /// since the last row.
    fn finish(&mut self, mechanism: &M, last: &StepReport<'_>) {
        if self.pending > 0 {
            self.push_step(mechanism, last);
        }
        self.last_impulses = Some(Impulses::of(last));
    }
}

impl Recorder {
    /// Writes the row of the step of `report`, with the sums of the steps since the last row.
    fn push_step<M: Mechanism + ?Sized>(&mut self, mechanism: &M, report: &StepReport<'_>) {
        self.pending = 0;
        let iterations = report.lcp.map_or(0, |l| l.iterations);
        self.push_row(
            mechanism,
            report.t,
            report.q,
            report.u,
            report.contacts,
            report.lcp_size,
            iterations,
        );
    }
}

#[allow(dead_code)]
fn _assert_send_sync() {
    fn is<T: Send + Sync>() {}
    is::<Record>();
    is::<Impact>();
    is::<Recorder>();
}
