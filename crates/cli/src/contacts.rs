//! The contacts file of `simulate --contacts FILE`: every contact in the active set of the
//! steps the record keeps, located on its bodies, for force networks and contact statistics.
//!
//! One CSV row per active contact of each recorded step (one step in `record_every`, and the
//! run's last step, as the record keeps them), in the step's order of identity:
//!
//! | column | meaning |
//! |---|---|
//! | `t` | end time t_E of the step (s), the record row's `t` |
//! | `id` | the contact's identity: its index in the contact list with the fixed contact set, the detection's identity (two shapes and a feature, the same while they touch) with the detected one |
//! | `body_a`, `body_b` | the bodies of its two sides, by name |
//! | `xa`, `ya`, `xb`, `yb` | the points on body a's and body b's surfaces at the step's midpoint q_M (m) |
//! | `nx`, `ny` | the unit normal from a towards b at q_M |
//! | `gap` | g_N(q_M, t_M) (m), ≤ the stepper's gap tolerance for an active contact |
//! | `PN`, `PT` | the impulses of this one step (N s; the mean force over the step is P/Δt) |
//! | `gamma_n`, `gamma_t` | the relative velocities γ_N,E and γ_T,E after the step (m/s) |
//! | `state` | `open`, `stick` or `slip` |
//! | `impact` | 1 when the step was an impact at the contact, else 0 |
//!
//! Unlike the record's `PN` and `PT` columns, which sum the impulses of the steps between two
//! rows, the contacts file shows the one step that ends at each row: contacts come and go
//! between rows. The points and normal are those the step's problem was written for: the
//! contacts are found again at q_M = q_A + Δt/2 u_A, t_M = t_A + Δt/2 (the step's own
//! arithmetic), with the scene's gap tolerance as the margin.

use std::io::Write;

use anyhow::Result;
use moreau_models::bodies::{LocatedContact, Multibody};
use moreau_stepper::{ContactState, StepReport};

use crate::error::CliError;
use crate::number;
use crate::output::csv_record;

/// The midpoint of the step from (q_A, u_A, t_A) with step `dt`: q_M = q_A + Δt/2 u_A into
/// `q_m` and t_M = t_A + Δt/2 returned, in the stepper's own arithmetic, so to the bit.
pub fn midpoint(q_a: &[f64], u_a: &[f64], t_a: f64, dt: f64, q_m: &mut Vec<f64>) -> f64 {
    let half = 0.5 * dt;
    q_m.clear();
    q_m.extend(q_a.iter().zip(u_a).map(|(q, u)| q + half * u));
    t_a + half
}

/// The contact `id` of the step that ends at `t_e`, located at the step's midpoint
/// (`q_m`, `t_m`) with the step's active-set `margin` ([`Multibody::locate_contact`]).
///
/// # Errors
/// [`CliError::ContactNotLocated`] when the midpoint does not give it again.
pub fn locate(
    model: &Multibody,
    id: u64,
    (q_m, t_m): (&[f64], f64),
    margin: f64,
    t_e: f64,
) -> Result<LocatedContact, CliError> {
    model.locate_contact(id, q_m, t_m, margin).ok_or(CliError::ContactNotLocated { id, t: t_e })
}

/// The header of a contacts file.
pub const HEADER: &str =
    "t,id,body_a,body_b,xa,ya,xb,yb,nx,ny,gap,PN,PT,gamma_n,gamma_t,state,impact";

/// Writes the located contacts of the recorded steps of a run of a declared mechanism.
pub(crate) struct ContactLog<W: Write> {
    out: W,
    /// One step in `every` is recorded.
    every: u64,
    dt: f64,
    margin: f64,
    /// The bodies' names as CSV fields (quoted when they hold a comma, a quote or a line end).
    names: Vec<String>,
    /// q_A, u_A and t_A of the next recorded step: the state the step before it ended at.
    q_a: Vec<f64>,
    u_a: Vec<f64>,
    t_a: f64,
    /// The start (q_A, u_A, t_A) of the step last observed, kept when the run may end on a
    /// step the thinning skips (a stop rule), for [`Self::finish_step`].
    last_start: Option<(Vec<f64>, Vec<f64>, f64)>,
    q_m: Vec<f64>,
    /// Rows written.
    pub(crate) rows: u64,
}

impl<W: Write> ContactLog<W> {
    /// A log of `model` run from (q0, u0) at t0, recording one step in `every`, with the
    /// stepper's step `dt` and gap tolerance `margin`; writes the header. With `stops_early`
    /// (a stop rule may end the run on a step the thinning skips) it keeps each step's start,
    /// so that [`Self::finish_step`] can write the run's last step as the record does.
    pub(crate) fn new(
        model: &Multibody,
        (q0, u0, t0): (Vec<f64>, Vec<f64>, f64),
        every: usize,
        (dt, margin): (f64, f64),
        stops_early: bool,
        mut out: W,
    ) -> Result<Self> {
        writeln!(out, "{HEADER}")?;
        let names =
            model.body_names().into_iter().map(|n| csv_record([n])).collect::<Result<_, _>>()?;
        let q_m = Vec::with_capacity(q0.len());
        Ok(Self {
            out,
            every: every.max(1) as u64,
            dt,
            margin,
            names,
            last_start: stops_early.then(|| (q0.clone(), u0.clone(), t0)),
            q_a: q0,
            u_a: u0,
            t_a: t0,
            q_m,
            rows: 0,
        })
    }

    /// Writes the active contacts of the step of `report` when the record keeps it, at time
    /// `t` (the record row's), and takes the step's end state as the next step's start when
    /// the record keeps the next step.
    ///
    /// # Errors
    /// [`CliError::ContactNotLocated`] for a contact the step reported that its midpoint does
    /// not give again; an unwritable file.
    pub(crate) fn observe(
        &mut self,
        model: &Multibody,
        report: &StepReport<'_>,
        t: f64,
    ) -> Result<()> {
        if (report.step + 1).is_multiple_of(self.every) {
            let t_m = midpoint(&self.q_a, &self.u_a, self.t_a, self.dt, &mut self.q_m);
            self.write_step(model, report, t_m, t)?;
        }
        if let Some((q, u, t_a)) = &mut self.last_start {
            // Every step's start is kept: this step's for `finish_step`, the next one's in q_a.
            std::mem::swap(q, &mut self.q_a);
            std::mem::swap(u, &mut self.u_a);
            *t_a = self.t_a;
            self.q_a.copy_from_slice(report.q);
            self.u_a.copy_from_slice(report.u);
            self.t_a = report.t;
        } else if (report.step + 2).is_multiple_of(self.every) {
            // The next step's start is needed only when the record keeps that step.
            self.q_a.copy_from_slice(report.q);
            self.u_a.copy_from_slice(report.u);
            self.t_a = report.t;
        }
        Ok(())
    }

    /// Writes the active contacts of the last step of the run, `last`, at time `t` when the
    /// thinning skipped it, as the record writes its row ([`moreau_stepper::Observer::finish`]).
    ///
    /// # Errors
    /// As [`Self::observe`].
    pub(crate) fn finish_step(
        &mut self,
        model: &Multibody,
        last: &StepReport<'_>,
        t: f64,
    ) -> Result<()> {
        if (last.step + 1).is_multiple_of(self.every) {
            return Ok(());
        }
        let Some((q_a, u_a, t_a)) = &self.last_start else { return Ok(()) };
        let t_m = midpoint(q_a, u_a, *t_a, self.dt, &mut self.q_m);
        self.write_step(model, last, t_m, t)
    }

    /// Writes the active contacts of the step of `report`, located at its midpoint (`q_m`,
    /// `t_m`), at time `t`.
    fn write_step(
        &mut self,
        model: &Multibody,
        report: &StepReport<'_>,
        t_m: f64,
        t: f64,
    ) -> Result<()> {
        for (c, &id) in report.contacts.iter().zip(report.contact_ids) {
            if !c.active {
                continue;
            }
            let located = locate(model, id, (&self.q_m, t_m), self.margin, report.t)?;
            let g = located.geometry;
            let state = match c.state {
                ContactState::Open => "open",
                ContactState::Stick => "stick",
                ContactState::Slip => "slip",
            };
            number::write(&mut self.out, t)?;
            write!(
                self.out,
                ",{id},{},{}",
                self.names[located.bodies[0]], self.names[located.bodies[1]]
            )?;
            for x in [
                g.point_a[0],
                g.point_a[1],
                g.point_b[0],
                g.point_b[1],
                g.normal[0],
                g.normal[1],
                g.gap,
                c.p_n,
                c.p_t,
                c.gamma_n,
                c.gamma_t,
            ] {
                number::write_next(&mut self.out, x)?;
            }
            writeln!(self.out, ",{state},{}", u8::from(c.impact))?;
            self.rows += 1;
        }
        Ok(())
    }

    /// Flushes the file and returns its writer.
    pub(crate) fn finish(mut self) -> Result<W> {
        self.out.flush()?;
        Ok(self.out)
    }
}
