//! `cargo xtask tradeoff`: what a step size h = Δt and an LCP solver cost and what they buy.
//!
//! For each model (bouncing ball, woodpecker, slider-crank with and without clearance, cam,
//! Painlevé's rod) the study runs the report's scene at step sizes h from 1e-2 s down to
//! 1e-6 s with each LCP solver (Lemke, Auto, projected Gauss-Seidel at tolerances 1e-4, 1e-8
//! and 1e-12), and measures
//!
//! - the cost: wall time, steps, LCP solves, steps per second and LCP solves per second;
//! - the error in the model's own units: against the closed form for the ball (impact times
//!   t_k, apex heights, the rest time against t_∞ = t_1 (1 + ε_N)/(1 − ε_N), the first free
//!   fall), and against a reference run at a much smaller step h_ref (Auto solver) for the
//!   others (states at fixed times, the woodpecker's period, impact instants). The reference's
//!   own error is estimated by the difference between runs at h_ref and h_ref/2;
//! - the observed order of convergence p, the least-squares slope of log error against log h
//!   ([`fit_order`]), in impact-free phases and globally.
//!
//! A run that stops with a typed error is a result: it is listed as `failed: <reason>`.
//!
//! Runs stream their steps through an observer that keeps only what the errors need (states
//! at sample times, contact transitions), so runs of millions of steps need little memory.
//! Everything written is deterministic except the wall times, which are measured.
//!
//! # References
//! - Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics.
//! - Flores, P. (2010). Application of the non-smooth dynamics approach to model and analyze
//!   contact-impact events in rigid multibody systems using the LCP formulation.

use std::fmt::Write as _;
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use moreau_kinematics::ContactKinematics;
use moreau_lcp::Method;
use moreau_models::{AnyModel, ModelKind, ModelParams, Scene};
use moreau_stepper::{ContactState, Observer, SolverChoice, StepReport};
use rayon::prelude::*;
use serde::Serialize;
use serde_json::{Value, json};

use crate::analysis::{self, BallClosedForm, ContactEvent, ContactStateExt, EventKind};
use crate::plot::{Figure, LegendAt, Mark, Panel, Series};

/// Options of `cargo xtask tradeoff`.
#[derive(Clone, Debug)]
pub struct Options {
    /// Output folder (created when missing).
    pub out: PathBuf,
    /// Fewer and larger step sizes and a coarser reference (a few seconds in all).
    pub quick: bool,
    /// Worker threads; one per core when `None`.
    pub jobs: Option<usize>,
}

/// What `cargo xtask tradeoff` did.
#[derive(Clone, Debug)]
pub struct Summary {
    /// Files written (names relative to the output folder).
    pub files: Vec<String>,
    /// Wall time of the whole study (s).
    pub total_seconds: f64,
    /// Sum of the wall times of the simulations (s).
    pub simulation_seconds: f64,
}

/// Number of impacts, apexes or impact instants compared.
const EVENTS_COMPARED: usize = 5;
/// Errors at or below this are round-off, not discretisation error.
const ROUND_OFF: f64 = 1e-10;
/// A point is limited by the reference when its error is below this multiple of the
/// reference's own error.
const REFERENCE_MARGIN: f64 = 3.0;
/// A run whose |q| or |u| exceeds this has diverged (the step is beyond the stability limit).
const DIVERGED: f64 = 1e6;
/// Runs shorter than this (s) are repeated, up to [`REPEATS`] times in all, and the shortest
/// wall time is kept: one short run is mostly timer and scheduling noise.
const SHORT_RUN: f64 = 0.02;
/// Largest number of timed repetitions of a short run.
const REPEATS: usize = 5;
/// The order is fitted over at most this many of the finest usable steps (the asymptotic
/// range).
const FIT_POINTS: usize = 5;

/// An LCP solver of the study.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum Solver {
    /// Lemke's complementary pivoting.
    Lemke,
    /// The robust strategy: trivial solution, Lemke, other covering vectors, enumeration.
    Auto,
    /// Projected Gauss-Seidel with ω = 1, at most 10 000 sweeps per step, warm-started.
    Pgs {
        /// Tolerance on the scaled natural residual ‖min(z, w)‖∞ (dimensionless).
        tolerance: f64,
    },
}

impl Solver {
    /// The solvers of the full study: Lemke, Auto, PGS at 1e-4, 1e-8 and 1e-12.
    pub fn all() -> Vec<Solver> {
        vec![
            Solver::Lemke,
            Solver::Auto,
            Solver::Pgs { tolerance: 1e-4 },
            Solver::Pgs { tolerance: 1e-8 },
            Solver::Pgs { tolerance: 1e-12 },
        ]
    }

    /// Short name: `lemke`, `auto`, `pgs 1e-4`, ...
    pub fn label(self) -> String {
        match self {
            Solver::Lemke => "lemke".to_owned(),
            Solver::Auto => "auto".to_owned(),
            Solver::Pgs { tolerance } => format!("pgs {tolerance:e}"),
        }
    }

    /// The stepper's solver choice.
    pub fn choice(self) -> SolverChoice {
        match self {
            Solver::Lemke => SolverChoice::Lemke,
            Solver::Auto => SolverChoice::Auto,
            Solver::Pgs { tolerance } => {
                SolverChoice::Pgs { tolerance, omega: 1.0, max_iterations: 10_000 }
            }
        }
    }
}

/// Whether an error measures an impact-free phase or the whole run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stretch {
    /// Smooth motion only (no contact closes).
    ImpactFree,
    /// The whole run, impacts included.
    Global,
}

impl Stretch {
    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Stretch::ImpactFree => "impact-free",
            Stretch::Global => "global",
        }
    }
}

/// One error measure of a model.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Metric {
    /// Short name, e.g. `impact times`.
    pub name: &'static str,
    /// Unit of the error, e.g. `s`, `m`, `rad/s`, `-` (relative).
    pub unit: &'static str,
    /// Impact-free phase or whole run.
    pub stretch: Stretch,
    /// What is compared with what.
    pub description: &'static str,
}

/// The error measures of a model, the headline measure first.
pub fn metrics(kind: ModelKind) -> &'static [Metric] {
    const fn m(
        name: &'static str,
        unit: &'static str,
        stretch: Stretch,
        description: &'static str,
    ) -> Metric {
        Metric { name, unit, stretch, description }
    }
    const BALL: [Metric; 4] = [
        m(
            "impact times",
            "s",
            Stretch::Global,
            "largest |t_k − t_k,exact| over the first 5 impacts (t_k: midpoint of the impact step)",
        ),
        m(
            "apex heights",
            "m",
            Stretch::Global,
            "largest |y_max − (R + (ε_N^k v1)²/2g)| over the first 5 flights",
        ),
        m("rest time", "s", Stretch::Global, "|t_rest − t_∞|, t_∞ = t1 (1 + ε_N)/(1 − ε_N)"),
        m(
            "free fall",
            "m",
            Stretch::ImpactFree,
            "largest |y − (y0 − g t²/2)| at t = 0.03, 0.06, ... before the first impact",
        ),
    ];
    const WOODPECKER: [Metric; 3] = [
        m(
            "period",
            "-",
            Stretch::Global,
            "|T − T_ref|/T_ref of the limit-cycle period (beak impacts)",
        ),
        m(
            "beak impacts",
            "s",
            Stretch::Global,
            "largest |t_k − t_k,ref| over the first 5 beak impacts",
        ),
        m(
            "sleeve height",
            "m",
            Stretch::Global,
            "largest |y − y_ref| at t = 0.03, 0.06, ..., 0.99",
        ),
    ];
    const SLIDER: [Metric; 3] = [
        m(
            "crank speed",
            "rad/s",
            Stretch::Global,
            "largest |ω1 − ω1,ref| at t = 0.03, 0.06, 0.09, 0.12",
        ),
        m(
            "impact instants",
            "s",
            Stretch::Global,
            "largest |t_k − t_k,ref| over the first 5 steps in which a corner is hit",
        ),
        m("two revolutions", "s", Stretch::Global, "|T − T_ref| of the time to θ1 = 4π"),
    ];
    const IDEAL: [Metric; 1] = [m(
        "crank speed",
        "rad/s",
        Stretch::ImpactFree,
        "largest |ω1 − ω1,ref| at t = 0.03, 0.06, 0.09, 0.12 (no contacts)",
    )];
    const CAM: [Metric; 2] = [
        m("follower height", "m", Stretch::Global, "largest |y − y_ref| at t = 0.03, ..., 0.15"),
        m(
            "impact instants",
            "s",
            Stretch::Global,
            "largest |t_k − t_k,ref| over the first 5 impacts",
        ),
    ];
    const PAINLEVE: [Metric; 2] = [
        m("time to lie flat", "s", Stretch::Global, "|t_flat − t_flat,ref| (φ reaches 0)"),
        m("rod angle", "rad", Stretch::Global, "largest |φ − φ_ref| at t = 0.03, ..., 0.6"),
    ];
    match kind {
        ModelKind::Ball => &BALL,
        ModelKind::Woodpecker => &WOODPECKER,
        ModelKind::SliderCrank => &SLIDER,
        ModelKind::SliderCrankIdeal => &IDEAL,
        ModelKind::Cam => &CAM,
        ModelKind::Painleve => &PAINLEVE,
    }
}

/// One model of the study: its scene, step sizes, solvers and reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Study {
    /// The model (its report scene is the starting point).
    pub kind: ModelKind,
    /// Overrides applied with `Scene::set` before Δt and the solver.
    pub sets: Vec<(String, String)>,
    /// Step sizes h (s), largest first.
    pub steps: Vec<f64>,
    /// LCP solvers.
    pub solvers: Vec<Solver>,
    /// Step h_ref of the reference run (Auto solver; also run at h_ref/2 to estimate its own
    /// error); `None` when the error is taken against a closed form.
    pub reference: Option<f64>,
    /// Times at which the state is compared (s).
    pub sample_times: Vec<f64>,
}

/// Step sizes of the full study, three per decade down to 1e-6 s.
const LADDER: [f64; 9] = [1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 3e-6, 1e-6];
/// Step sizes of the quick study.
const QUICK_LADDER: [f64; 4] = [1e-2, 3e-3, 1e-3, 3e-4];

/// Sample times 0.03 k, k = 1..=count: whole multiples of every step of the ladders.
fn every_30ms(count: usize) -> Vec<f64> {
    (1..=count).map(|k| 0.03 * k as f64).collect()
}

impl Study {
    /// A study of `kind` at the given steps with all solvers.
    fn new(kind: ModelKind, steps: &[f64], reference: Option<f64>, samples: usize) -> Self {
        Self {
            kind,
            sets: Vec::new(),
            steps: steps.to_vec(),
            solvers: Solver::all(),
            reference,
            sample_times: every_30ms(samples),
        }
    }

    /// The model's name.
    pub fn label(&self) -> &'static str {
        self.kind.name()
    }

    /// The scene at step `dt` with `solver`.
    ///
    /// # Errors
    /// When an override or the step is rejected.
    pub fn scene(&self, dt: f64, solver: Solver) -> Result<Scene> {
        let mut scene = Scene::report(self.kind);
        for (k, v) in &self.sets {
            scene.set(k, v).with_context(|| format!("{}: --set {k}={v}", self.label()))?;
        }
        scene.dt = dt;
        scene.solver = solver.choice();
        scene.validate().with_context(|| format!("{} at Δt = {dt}", self.label()))?;
        Ok(scene)
    }
}

/// The studies of `cargo xtask tradeoff` (quick: four step sizes from 1e-2 to 3e-4 s and a
/// reference at 3e-5 s).
///
/// The ball drops with ε_N = 0.7 (rest at t_∞ = 2.43 s) for 3 s; the other models run their
/// report scenes. The ideal slider-crank has no contacts, so it is run with one solver.
pub fn studies(quick: bool) -> Vec<Study> {
    let (steps, h_ref): (&[f64], f64) = if quick { (&QUICK_LADDER, 3e-5) } else { (&LADDER, 1e-7) };
    let mut ball = Study::new(ModelKind::Ball, steps, None, 14);
    ball.sets = vec![("eps_n".into(), "0.7".into()), ("t_end".into(), "3".into())];
    let mut ideal = Study::new(ModelKind::SliderCrankIdeal, steps, Some(h_ref), 4);
    ideal.solvers = vec![Solver::Auto];
    vec![
        ball,
        Study::new(ModelKind::Woodpecker, steps, Some(h_ref), 33),
        Study::new(ModelKind::SliderCrank, steps, Some(h_ref), 4),
        ideal,
        Study::new(ModelKind::Cam, steps, Some(h_ref), 5),
        Study::new(ModelKind::Painleve, steps, Some(h_ref), 20),
    ]
}

/// The state at one sample time, interpolated linearly between the ends of the step that
/// contains it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sample {
    /// Sample time (s).
    pub t: f64,
    /// Coordinates q.
    pub q: Vec<f64>,
    /// Velocities u.
    pub u: Vec<f64>,
}

/// A change of a contact's state at the end of a step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Transition {
    /// Step number, from 1 (the row of a full record).
    pub row: usize,
    /// End time of the step (s).
    pub t: f64,
    /// Contact index, from 0.
    pub contact: usize,
    /// State before the step.
    pub from: ContactState,
    /// State after the step.
    pub to: ContactState,
    /// Normal relative velocity γ_N⁻ = w_Nᵀ u_A + ŵ_N at the start of the step (m/s); only
    /// computed when the contact closes, zero otherwise.
    pub gamma_pre: f64,
}

/// What a run leaves for the error measures.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Observation {
    /// Step Δt (s).
    pub dt: f64,
    /// The scene's gravitational acceleration g (m/s²), for the impact threshold 5 g Δt.
    pub g: f64,
    /// Time reached (s).
    pub t_end: f64,
    /// Whether the scene's stop rule ended the run before its end time.
    pub stopped_early: bool,
    /// States at the sample times reached.
    pub samples: Vec<Sample>,
    /// Contact state changes.
    pub transitions: Vec<Transition>,
    /// Largest `q[0]` in each flight between closings of contact 0 (the ball's apexes).
    pub apexes: Vec<f64>,
    /// Midpoint time of the first step of the final run of steps with P_N > 0 at contact 0,
    /// if that run lasts at least 10 steps to the end (the ball's rest time, s).
    pub rest_time: Option<f64>,
    /// When the scene's stop rule was met: the time at which its coordinate crosses the
    /// stop value, interpolated linearly within the step (s).
    pub crossing: Option<f64>,
    /// Largest |q_i| or |u_i| over the run.
    pub max_state: f64,
}

impl Observation {
    /// Contact events (analysis' classification): a closing is an impact when
    /// γ_N⁻ < −`impact_speed`.
    pub fn events(&self, impact_speed: f64) -> Vec<ContactEvent> {
        self.transitions
            .iter()
            .filter_map(|tr| {
                let kind = analysis::classify(tr.from, tr.to, tr.gamma_pre, impact_speed)?;
                Some(ContactEvent {
                    row: tr.row,
                    t: tr.t,
                    contact: tr.contact + 1,
                    kind,
                    after: tr.to,
                })
            })
            .collect()
    }

    /// Midpoint times of the steps in which one of `contacts` closes with γ_N⁻ <
    /// −`impact_speed` (several contacts hit in one step count once).
    pub fn impact_instants(&self, contacts: &[usize], impact_speed: f64) -> Vec<f64> {
        let mut rows: Vec<(usize, f64)> = self
            .transitions
            .iter()
            .filter(|tr| {
                contacts.contains(&tr.contact)
                    && analysis::classify(tr.from, tr.to, tr.gamma_pre, impact_speed)
                        == Some(EventKind::Impact)
            })
            .map(|tr| (tr.row, tr.t - 0.5 * self.dt))
            .collect();
        rows.dedup_by_key(|r| r.0);
        rows.into_iter().map(|r| r.1).collect()
    }

    /// Whether the state left every physical bound (|q| or |u| above 1e6).
    pub fn diverged(&self) -> bool {
        !(self.max_state <= DIVERGED)
    }

    /// Largest approach speed −γ_N⁻ of any closing (m/s).
    pub fn largest_approach(&self) -> f64 {
        self.transitions
            .iter()
            .filter(|tr| !tr.from.is_closed() && tr.to.is_closed())
            .map(|tr| -tr.gamma_pre)
            .fold(0.0, f64::max)
    }
}

/// The streaming observer of a run.
struct Probe {
    dt: f64,
    sample_times: Vec<f64>,
    track_apexes: bool,
    obs: Observation,
    steps: u64,
    lcp_solves: u64,
    prev_t: f64,
    prev_q: Vec<f64>,
    prev_u: Vec<f64>,
    prev_phase: Vec<ContactState>,
    w_n: Vec<f64>,
    w_t: Vec<f64>,
    flight_top: Option<f64>,
    closed_run: Option<(f64, usize)>,
    stop: Option<(usize, f64)>,
}

impl Probe {
    fn new(scene: &Scene, model: &AnyModel, sample_times: &[f64]) -> Self {
        let (q, u) = model.initial_state();
        let dt = scene.dt;
        let stop = scene.stop_at.as_ref().and_then(|s| {
            let index = scene.kind().coordinate_names().iter().position(|n| *n == s.coordinate)?;
            Some((index, s.value))
        });
        let f = q.len();
        Self {
            dt,
            sample_times: sample_times.to_vec(),
            track_apexes: scene.kind() == ModelKind::Ball,
            obs: Observation { dt, g: crate::runs::gravity(scene), ..Observation::default() },
            steps: 0,
            lcp_solves: 0,
            prev_t: 0.0,
            prev_q: q,
            prev_u: u,
            prev_phase: vec![ContactState::Open; model.num_contacts()],
            w_n: vec![0.0; f],
            w_t: vec![0.0; f],
            flight_top: None,
            closed_run: None,
            stop,
        }
    }

    fn finish(mut self, t_end: f64, stopped_early: bool) -> Observation {
        self.obs.t_end = t_end;
        self.obs.stopped_early = stopped_early;
        self.obs.rest_time = self.closed_run.filter(|(_, n)| *n >= 10).map(|(t, _)| t);
        if !stopped_early {
            self.obs.crossing = None;
        }
        self.obs
    }
}

impl Observer<AnyModel> for Probe {
    fn observe(&mut self, model: &AnyModel, r: &StepReport<'_>) -> ControlFlow<()> {
        self.steps += 1;
        if r.lcp.is_some_and(|l| l.method != Method::Trivial) {
            self.lcp_solves += 1;
        }
        let row = self.steps as usize;
        for x in r.q.iter().chain(r.u) {
            self.obs.max_state = self.obs.max_state.max(x.abs());
        }
        if let Some((i, value)) = self.stop {
            let (a, b) = (self.prev_q[i] - value, r.q[i] - value);
            if self.obs.crossing.is_none() && a != 0.0 && (a < 0.0) != (b < 0.0) {
                self.obs.crossing = Some(self.prev_t + (r.t - self.prev_t) * a / (a - b));
            }
        }
        while let Some(&ts) = self.sample_times.get(self.obs.samples.len()) {
            if ts > r.t {
                break;
            }
            let span = r.t - self.prev_t;
            let w = if span > 0.0 { ((ts - self.prev_t) / span).clamp(0.0, 1.0) } else { 1.0 };
            let mix = |a: &[f64], b: &[f64]| -> Vec<f64> {
                a.iter().zip(b).map(|(a, b)| a + w * (b - a)).collect()
            };
            let sample = Sample { t: ts, q: mix(&self.prev_q, r.q), u: mix(&self.prev_u, r.u) };
            self.obs.samples.push(sample);
        }
        for (i, c) in r.contacts.iter().enumerate() {
            let phase = c.state;
            let before = self.prev_phase[i];
            if phase == before {
                continue;
            }
            let gamma_pre = if !before.is_closed() && phase.is_closed() {
                let point =
                    model.contact(i, &self.prev_q, self.prev_t, &mut self.w_n, &mut self.w_t);
                self.w_n.iter().zip(&self.prev_u).map(|(a, b)| a * b).sum::<f64>() + point.w_n_hat
            } else {
                0.0
            };
            self.obs.transitions.push(Transition {
                row,
                t: r.t,
                contact: i,
                from: before,
                to: phase,
                gamma_pre,
            });
            self.prev_phase[i] = phase;
            if i == 0
                && self.track_apexes
                && !before.is_closed()
                && let Some(top) = self.flight_top.take()
            {
                self.obs.apexes.push(top);
            }
        }
        if let Some(c) = r.contacts.first() {
            if self.track_apexes && c.state == ContactState::Open && !r.q.is_empty() {
                if let Some(top) = self.flight_top.as_mut() {
                    *top = top.max(r.q[0]);
                } else if !self.obs.transitions.is_empty() {
                    self.flight_top = Some(r.q[0]);
                }
            }
            self.closed_run = if c.p_n > 0.0 {
                match self.closed_run {
                    Some((t, n)) => Some((t, n + 1)),
                    None => Some((r.t - 0.5 * self.dt, 1)),
                }
            } else {
                None
            };
        }
        self.prev_t = r.t;
        self.prev_q.copy_from_slice(r.q);
        self.prev_u.copy_from_slice(r.u);
        ControlFlow::Continue(())
    }
}

/// One run of the study: its cost and what it observed, or why it failed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Measurement {
    /// The LCP solver.
    pub solver: Solver,
    /// Step h (s).
    pub dt: f64,
    /// Steps taken (up to the failure, if any).
    pub steps: u64,
    /// Steps whose LCP needed a solver.
    pub lcp_solves: u64,
    /// Measured wall time of the run (s).
    pub wall_seconds: f64,
    /// What the run observed, or the typed error that stopped it.
    pub outcome: Result<Observation, String>,
}

impl Measurement {
    /// Whether the run finished with a state beyond every physical bound.
    pub fn diverged(&self) -> bool {
        self.outcome.as_ref().is_ok_and(Observation::diverged)
    }

    /// Steps per second of wall time.
    pub fn steps_per_second(&self) -> f64 {
        self.steps as f64 / self.wall_seconds.max(1e-9)
    }

    /// LCP solves per second of wall time.
    pub fn lcp_solves_per_second(&self) -> f64 {
        self.lcp_solves as f64 / self.wall_seconds.max(1e-9)
    }
}

/// Runs `study` at step `dt` with `solver`.
pub fn measure(study: &Study, dt: f64, solver: Solver) -> Measurement {
    let failed = |reason: String| Measurement {
        solver,
        dt,
        steps: 0,
        lcp_solves: 0,
        wall_seconds: 0.0,
        outcome: Err(reason),
    };
    let scene = match study.scene(dt, solver) {
        Ok(s) => s,
        Err(e) => return failed(format!("{e:#}")),
    };
    let model = match scene.build() {
        Ok(m) => m,
        Err(e) => return failed(e.to_string()),
    };
    let mut probe = Probe::new(&scene, &model, &study.sample_times);
    let start = Instant::now();
    let result = scene.run_with(&mut probe);
    let mut wall_seconds = start.elapsed().as_secs_f64();
    let (steps, lcp_solves) = (probe.steps, probe.lcp_solves);
    let mut spent = wall_seconds;
    for _ in 1..REPEATS {
        if result.is_err() || spent >= SHORT_RUN {
            break;
        }
        let mut again = Probe::new(&scene, &model, &study.sample_times);
        let start = Instant::now();
        let repeat = scene.run_with(&mut again);
        let wall = start.elapsed().as_secs_f64();
        if repeat.is_err() {
            break;
        }
        wall_seconds = wall_seconds.min(wall);
        spent += wall;
    }
    let outcome = match result {
        Ok(summary) => Ok(probe.finish(summary.t_end, summary.stopped_early)),
        Err(e) => Err(format!("{:#}", anyhow::Error::from(e))),
    };
    Measurement { solver, dt, steps, lcp_solves, wall_seconds, outcome }
}

/// Largest `|values[k] − reference[k]|` over the first `count` entries of `reference`.
///
/// # Errors
/// When the reference is empty or `values` has fewer entries than are compared (a missed
/// impact, say).
pub fn paired_error(values: &[f64], reference: &[f64], count: usize) -> Result<f64, String> {
    let k = count.min(reference.len());
    if k == 0 {
        return Err("nothing to compare with".to_owned());
    }
    if values.len() < k {
        return Err(format!("{} of the {k} events compared were found", values.len()));
    }
    let worst =
        values[..k].iter().zip(&reference[..k]).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
    if worst.is_finite() { Ok(worst) } else { Err("non-finite value".to_owned()) }
}

/// Largest distance from each of the first `count` reference instants to the nearest instant
/// of the run (extra events of the run are not penalised; a missed one is, by its distance to
/// the next).
///
/// # Errors
/// When the reference or the run has no instants.
pub fn nearest_error(values: &[f64], reference: &[f64], count: usize) -> Result<f64, String> {
    let k = count.min(reference.len());
    if k == 0 {
        return Err("nothing to compare with".to_owned());
    }
    if values.is_empty() {
        return Err("no events in the run".to_owned());
    }
    let worst = reference[..k]
        .iter()
        .map(|r| values.iter().map(|v| (v - r).abs()).fold(f64::INFINITY, f64::min))
        .fold(0.0, f64::max);
    if worst.is_finite() { Ok(worst) } else { Err("non-finite value".to_owned()) }
}

/// Largest |pick(run) − pick(reference)| over the reference's samples.
///
/// # Errors
/// When the reference has no samples or the run ended before one of them.
pub fn sampled_error(
    run: &[Sample],
    reference: &[Sample],
    pick: impl Fn(&Sample) -> f64,
) -> Result<f64, String> {
    if reference.is_empty() {
        return Err("the reference has no samples".to_owned());
    }
    if run.len() < reference.len() {
        return Err(format!("the run ended before t = {}", reference[run.len()].t));
    }
    let worst =
        run.iter().zip(reference).map(|(a, b)| (pick(a) - pick(b)).abs()).fold(0.0, f64::max);
    if worst.is_finite() { Ok(worst) } else { Err("non-finite state".to_owned()) }
}

/// Relative error |x − x_ref|/|x_ref|.
///
/// # Errors
/// When x_ref is zero or a value is not finite.
pub fn relative_error(x: f64, x_ref: f64) -> Result<f64, String> {
    let e = ((x - x_ref) / x_ref).abs();
    if e.is_finite() { Ok(e) } else { Err(format!("cannot compare {x} with {x_ref}")) }
}

/// Apex heights R + (ε_N^k v1)²/(2g), k = 1..=count, of the closed-form ball (m).
pub fn ball_apexes(cf: &BallClosedForm, r: f64, count: usize) -> Vec<f64> {
    (1..=count).map(|k| r + (cf.eps_n.powi(k as i32) * cf.v1).powi(2) / (2.0 * cf.g)).collect()
}

/// Errors of a ball run against the closed form, one per [`metrics`] entry.
fn ball_errors(params: &ModelParams, obs: &Observation) -> Vec<Result<f64, String>> {
    let ModelParams::Ball(p) = params else {
        return vec![Err("not a ball".to_owned()); 4];
    };
    if p.init.v0 != 0.0 {
        return vec![Err("the closed form needs a drop from rest".to_owned()); 4];
    }
    let cf = BallClosedForm::new(p.init.y0, p.r, p.g, p.eps_n);
    let impacts = obs.impact_instants(&[0], 5.0 * p.g * obs.dt);
    let times = nearest_error(&impacts, &cf.impact_times(EVENTS_COMPARED), EVENTS_COMPARED);
    let apexes =
        paired_error(&obs.apexes, &ball_apexes(&cf, p.r, EVENTS_COMPARED), EVENTS_COMPARED);
    let rest = obs
        .rest_time
        .map(|t| (t - cf.t_inf).abs())
        .ok_or_else(|| "the ball is not at rest by the end of the run".to_owned());
    let before: Vec<&Sample> = obs.samples.iter().filter(|s| s.t + obs.dt < cf.t1).collect();
    let fall = if before.is_empty() {
        Err("no sample before the first impact".to_owned())
    } else {
        Ok(before
            .iter()
            .map(|s| (s.q[0] - (p.init.y0 - 0.5 * p.g * s.t * s.t)).abs())
            .fold(0.0, f64::max))
    };
    vec![times, apexes, rest, fall]
}

/// Errors of a run against a reference run, one per [`metrics`] entry.
fn reference_errors(
    kind: ModelKind,
    obs: &Observation,
    r: &Observation,
) -> Vec<Result<f64, String>> {
    let speed = |o: &Observation| 5.0 * o.g.abs() * o.dt;
    let stop_time = |o: &Observation, what: &str| {
        o.crossing.ok_or_else(|| format!("{what} by the end of the run"))
    };
    match kind {
        ModelKind::Woodpecker => {
            let period = |o: &Observation| {
                analysis::limit_cycle(&o.events(speed(o)), 1)
                    .map(|c| c.period)
                    .ok_or_else(|| "no limit cycle found".to_owned())
            };
            vec![
                period(obs).and_then(|t| relative_error(t, period(r)?)),
                nearest_error(
                    &obs.impact_instants(&[0], speed(obs)),
                    &r.impact_instants(&[0], speed(r)),
                    EVENTS_COMPARED,
                ),
                sampled_error(&obs.samples, &r.samples, |s| s.q[0]),
            ]
        }
        ModelKind::SliderCrank => {
            // Corners chatter at a few mm/s while the slider is pressed against the guide:
            // an impact needs at least 2 % of the largest approach speed of the run.
            let impacts = |o: &Observation| {
                let threshold = speed(o).max(0.02 * o.largest_approach());
                o.impact_instants(&[0, 1, 2, 3], threshold)
            };
            let two_revolutions = |o: &Observation| stop_time(o, "θ1 does not reach 4π");
            vec![
                sampled_error(&obs.samples, &r.samples, |s| s.u[0]),
                nearest_error(&impacts(obs), &impacts(r), EVENTS_COMPARED),
                two_revolutions(obs).and_then(|t| Ok((t - two_revolutions(r)?).abs())),
            ]
        }
        ModelKind::SliderCrankIdeal => vec![sampled_error(&obs.samples, &r.samples, |s| s.u[0])],
        ModelKind::Cam => vec![
            sampled_error(&obs.samples, &r.samples, |s| s.q[0]),
            nearest_error(
                &obs.impact_instants(&[0], speed(obs)),
                &r.impact_instants(&[0], speed(r)),
                EVENTS_COMPARED,
            ),
        ],
        ModelKind::Painleve => {
            let flat = |o: &Observation| stop_time(o, "the rod does not lie flat");
            vec![
                flat(obs).and_then(|t| Ok((t - flat(r)?).abs())),
                sampled_error(&obs.samples, &r.samples, |s| s.q[2]),
            ]
        }
        ModelKind::Ball => vec![Err("the ball is compared with its closed form".to_owned()); 4],
    }
}

/// A least-squares fit log10 e = log10 C + p log10 h.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OrderFit {
    /// Observed order p (slope).
    pub order: f64,
    /// log10 C (intercept).
    pub log10_constant: f64,
    /// Points fitted.
    pub points: usize,
    /// Smallest step fitted (s).
    pub dt_min: f64,
    /// Largest step fitted (s).
    pub dt_max: f64,
}

impl OrderFit {
    /// The fitted error C h^p at step `dt`.
    pub fn at(&self, dt: f64) -> f64 {
        10f64.powf(self.log10_constant + self.order * dt.log10())
    }
}

/// Least-squares slope of log10 error against log10 h over the points with a finite, positive
/// step and error; `None` with fewer than two such points or a single step size.
///
/// # Example
/// ```
/// // e = 0.5 h² at h = 1e-2 and 1e-3: order 2.
/// let fit = xtask::tradeoff::fit_order(&[1e-2, 1e-3], &[5e-5, 5e-7]).expect("two points");
/// assert!((fit.order - 2.0).abs() < 1e-12);
/// assert!((fit.at(1e-4) - 5e-9).abs() < 1e-20);
/// ```
pub fn fit_order(dt: &[f64], error: &[f64]) -> Option<OrderFit> {
    let points: Vec<(f64, f64)> = dt
        .iter()
        .zip(error)
        .filter(|(h, e)| h.is_finite() && e.is_finite() && **h > 0.0 && **e > 0.0)
        .map(|(h, e)| (h.log10(), e.log10()))
        .collect();
    let n = points.len();
    if n < 2 {
        return None;
    }
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n as f64;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n as f64;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if !(sxx > 0.0) {
        return None;
    }
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let order = sxy / sxx;
    let used = dt
        .iter()
        .zip(error)
        .filter(|(h, e)| h.is_finite() && e.is_finite() && **h > 0.0 && **e > 0.0)
        .map(|(h, _)| *h);
    let (lo, hi) =
        used.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), h| (lo.min(h), hi.max(h)));
    Some(OrderFit { order, log10_constant: my - order * mx, points: n, dt_min: lo, dt_max: hi })
}

/// The observed order of one error measure.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Order {
    /// The measure.
    pub metric: Metric,
    /// Solver whose runs were fitted.
    pub solver: String,
    /// The fit, or why there is none.
    pub fit: Result<OrderFit, String>,
    /// Largest error of the fitted runs at or below the floor (round-off or the reference's
    /// own error), when some were left out.
    pub floor: Option<f64>,
}

/// The results of one study.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyResult {
    /// The study.
    pub study: Study,
    /// Every (solver, step) run, solvers outermost.
    pub runs: Vec<Measurement>,
    /// The errors of each run, one per [`metrics`] entry.
    pub errors: Vec<Vec<Result<f64, String>>>,
    /// The reference runs at h_ref and h_ref/2.
    pub reference: Option<(Measurement, Measurement)>,
    /// The reference's own error: the run at h_ref/2 against the run at h_ref, per metric.
    pub reference_error: Vec<Result<f64, String>>,
    /// The observed orders, per metric.
    pub orders: Vec<Order>,
}

impl StudyResult {
    /// The metrics of the study's model.
    pub fn metrics(&self) -> &'static [Metric] {
        metrics(self.study.kind)
    }

    /// The solver whose runs the orders and choices use: Auto when studied.
    pub fn fitted_solver(&self) -> Solver {
        fitted_solver(&self.study)
    }

    /// Errors of metric `k` at or below this are round-off or within the reference's own
    /// error: they measure nothing about the step.
    pub fn floor(&self, k: usize) -> f64 {
        floor(&self.study, &self.reference_error, k)
    }
}

fn fitted_solver(study: &Study) -> Solver {
    if study.solvers.contains(&Solver::Auto) { Solver::Auto } else { study.solvers[0] }
}

fn floor(study: &Study, reference_error: &[Result<f64, String>], k: usize) -> f64 {
    match reference_error.get(k) {
        Some(Ok(e)) if study.reference.is_some() => (REFERENCE_MARGIN * e).max(ROUND_OFF),
        _ => ROUND_OFF,
    }
}

/// Errors of `obs` for `study`: against the closed form (ball) or `reference`.
fn evaluate(
    study: &Study,
    obs: &Observation,
    reference: Option<&Result<Observation, String>>,
) -> Vec<Result<f64, String>> {
    let n = metrics(study.kind).len();
    if study.kind == ModelKind::Ball {
        return match study.scene(1e-3, Solver::Auto) {
            Ok(scene) => ball_errors(&scene.params, obs),
            Err(e) => vec![Err(format!("{e:#}")); n],
        };
    }
    match reference {
        Some(Ok(r)) => reference_errors(study.kind, obs, r),
        Some(Err(e)) => vec![Err(format!("the reference run failed: {e}")); n],
        None => vec![Err("no reference run".to_owned()); n],
    }
}

/// Runs every study (in the current rayon pool, largest runs first) and evaluates the errors
/// and observed orders.
pub fn run_studies(studies: &[Study]) -> Vec<StudyResult> {
    // Jobs: (study, step, solver); references are the Auto solver at h_ref and h_ref/2.
    let mut jobs: Vec<(usize, f64, Solver)> = Vec::new();
    for (i, s) in studies.iter().enumerate() {
        if let Some(h) = s.reference {
            jobs.push((i, h, Solver::Auto));
            jobs.push((i, 0.5 * h, Solver::Auto));
        }
        for &solver in &s.solvers {
            for &dt in &s.steps {
                jobs.push((i, dt, solver));
            }
        }
    }
    let cost =
        |&(i, dt, _): &(usize, f64, Solver)| -> f64 { Scene::report(studies[i].kind).t_end / dt };
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by(|&a, &b| cost(&jobs[b]).total_cmp(&cost(&jobs[a])));
    let progress = crate::grid::Progress::new(jobs.len(), "tradeoff runs");
    let measured: Vec<(usize, Measurement)> = order
        .par_iter()
        .with_max_len(1)
        .map(|&j| {
            let (i, dt, solver) = jobs[j];
            let m = measure(&studies[i], dt, solver);
            progress.tick(&format!("{} {} Δt = {dt:e}", studies[i].label(), solver.label()));
            (j, m)
        })
        .collect();
    progress.finish();
    let mut by_job: Vec<Option<Measurement>> = vec![None; jobs.len()];
    for (j, m) in measured {
        by_job[j] = Some(m);
    }
    let mut results = Vec::new();
    let mut next = by_job.into_iter().flatten();
    for s in studies {
        let reference = match s.reference {
            Some(_) => match (next.next(), next.next()) {
                (Some(a), Some(b)) => Some((a, b)),
                _ => None,
            },
            None => None,
        };
        let runs: Vec<Measurement> =
            (0..s.solvers.len() * s.steps.len()).filter_map(|_| next.next()).collect();
        results.push(evaluate_study(s, runs, reference));
    }
    results
}

fn evaluate_study(
    study: &Study,
    runs: Vec<Measurement>,
    reference: Option<(Measurement, Measurement)>,
) -> StudyResult {
    let ms = metrics(study.kind);
    let reference_error = match &reference {
        Some((r, half)) => match &half.outcome {
            Ok(h) => evaluate(study, h, Some(&r.outcome)),
            Err(e) => vec![Err(format!("the run at h_ref/2 failed: {e}")); ms.len()],
        },
        None => vec![Err("closed form".to_owned()); ms.len()],
    };
    let errors: Vec<Vec<Result<f64, String>>> = runs
        .iter()
        .map(|m| match &m.outcome {
            Ok(obs) => evaluate(study, obs, reference.as_ref().map(|(r, _)| &r.outcome)),
            Err(e) => vec![Err(format!("failed: {e}")); ms.len()],
        })
        .collect();
    let fitted = fitted_solver(study);
    let orders = ms
        .iter()
        .enumerate()
        .map(|(k, metric)| {
            let floor = floor(study, &reference_error, k);
            let (mut usable, mut below) = (Vec::new(), None::<f64>);
            for (m, e) in runs.iter().zip(&errors) {
                if m.solver != fitted || m.diverged() {
                    continue;
                }
                if let Some(Ok(e)) = e.get(k) {
                    if *e > floor {
                        usable.push((m.dt, *e));
                    } else {
                        below = Some(below.map_or(*e, |b| b.max(*e)));
                    }
                }
            }
            // The asymptotic range: the finest usable steps.
            usable.sort_by(|a, b| a.0.total_cmp(&b.0));
            usable.truncate(FIT_POINTS);
            let (dts, errs): (Vec<f64>, Vec<f64>) = usable.into_iter().unzip();
            let fit = fit_order(&dts, &errs).ok_or_else(|| match below {
                Some(b) if floor > ROUND_OFF => format!(
                    "errors down to {b:.1e} {} reach the reference's own error",
                    metric.unit
                ),
                Some(b) => format!("errors ≤ {b:.1e} {}: round-off only", metric.unit),
                None => "fewer than two measured errors".to_owned(),
            });
            Order { metric: *metric, solver: fitted.label(), fit, floor: below }
        })
        .collect();
    StudyResult { study: study.clone(), runs, errors, reference, reference_error, orders }
}

/// One row of the table: a run and one of its error measures.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    /// Model name.
    pub model: String,
    /// Solver label.
    pub solver: String,
    /// Step h (s).
    pub dt: f64,
    /// Error measure.
    pub metric: String,
    /// Steps taken.
    pub steps: u64,
    /// LCP solves.
    pub lcp_solves: u64,
    /// Measured wall time (s).
    pub wall_s: f64,
    /// Steps per second.
    pub steps_per_s: f64,
    /// LCP solves per second.
    pub lcp_solves_per_s: f64,
    /// The error, when measured.
    pub error: Option<f64>,
    /// Unit of the error.
    pub unit: String,
    /// `ok`, `reference`, `failed: <reason>` or `not measured: <reason>`.
    pub status: String,
}

fn status_of(m: &Measurement, e: &Result<f64, String>) -> String {
    match (&m.outcome, e) {
        (Err(reason), _) => format!("failed: {reason}"),
        (Ok(o), _) if o.diverged() => {
            format!("diverged: the state grew to {:.1e}", o.max_state)
        }
        (Ok(_), Ok(_)) => "ok".to_owned(),
        (Ok(_), Err(why)) => format!("not measured: {why}"),
    }
}

/// The table rows of all studies: every run and metric, then each reference (h_ref, its error
/// against the run at h_ref/2).
pub fn rows(results: &[StudyResult]) -> Vec<Row> {
    let mut out = Vec::new();
    let row =
        |r: &StudyResult, m: &Measurement, metric: &Metric, e: &Result<f64, String>, status| Row {
            model: r.study.label().to_owned(),
            solver: m.solver.label(),
            dt: m.dt,
            metric: metric.name.to_owned(),
            steps: m.steps,
            lcp_solves: m.lcp_solves,
            wall_s: m.wall_seconds,
            steps_per_s: m.steps_per_second(),
            lcp_solves_per_s: m.lcp_solves_per_second(),
            error: e.as_ref().ok().copied(),
            unit: metric.unit.to_owned(),
            status,
        };
    for r in results {
        for (m, errs) in r.runs.iter().zip(&r.errors) {
            for (metric, e) in r.metrics().iter().zip(errs) {
                out.push(row(r, m, metric, e, status_of(m, e)));
            }
        }
        if let Some((href, half)) = &r.reference {
            for (metric, e) in r.metrics().iter().zip(&r.reference_error) {
                let status = match e {
                    Ok(_) => format!("reference: against h_ref/2 = {:e} s", half.dt),
                    Err(why) => format!("reference: not measured: {why}"),
                };
                out.push(row(r, href, metric, e, status));
            }
        }
    }
    out
}

/// A number for tables: three significant digits in scientific notation.
fn sci(x: f64) -> String {
    if x == 0.0 { "0".to_owned() } else { format!("{x:.2e}") }
}

fn md_cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// The Markdown of the study: observed orders, the reference's convergence and one row per
/// run (headline error, the other errors in the last column).
pub fn markdown(results: &[StudyResult]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Observed order p of convergence: least-squares slope of log10 error against log10 Δt \
         over the finest {FIT_POINTS} runs of one solver whose errors lie above round-off \
         ({ROUND_OFF:e}) and above {REFERENCE_MARGIN}× the reference's own error; diverged runs \
         are left out.\n"
    );
    let _ =
        writeln!(s, "| model | error | unit | phase | solver | Δt range [s] | points | order p |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---:|---:|");
    for r in results {
        for o in &r.orders {
            let (range, points, p) = match &o.fit {
                Ok(f) => (
                    format!("{:e} – {:e}", f.dt_min, f.dt_max),
                    f.points.to_string(),
                    format!("{:.2}", f.order),
                ),
                Err(why) => ("—".to_owned(), "0".to_owned(), format!("— ({why})")),
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {range} | {points} | {} |",
                r.study.label(),
                o.metric.name,
                o.metric.unit,
                o.metric.stretch.name(),
                o.solver,
                md_cell(&p)
            );
        }
    }
    let _ = writeln!(
        s,
        "\nReference runs (Auto solver) and their own error: the run at h_ref/2 against the run \
         at h_ref.\n"
    );
    let _ = writeln!(
        s,
        "| model | h_ref [s] | error | difference h_ref vs h_ref/2 | unit | steps | wall [s] |"
    );
    let _ = writeln!(s, "|---|---:|---|---:|---|---:|---:|");
    for r in results {
        match &r.reference {
            Some((href, _)) => {
                for (metric, e) in r.metrics().iter().zip(&r.reference_error) {
                    let v = match e {
                        Ok(x) => sci(*x),
                        Err(why) => format!("— ({})", md_cell(why)),
                    };
                    let _ = writeln!(
                        s,
                        "| {} | {:e} | {} | {v} | {} | {} | {:.2} |",
                        r.study.label(),
                        href.dt,
                        metric.name,
                        metric.unit,
                        href.steps,
                        href.wall_seconds
                    );
                }
            }
            None => {
                let _ = writeln!(s, "| {} | closed form | | | | | |", r.study.label());
            }
        }
    }
    s.push_str(&choices(results));
    s.push_str(&costs_markdown(results));
    let _ = writeln!(
        s,
        "\nRuns: cost and error. Wall times are measured (they vary between machines and runs); \
         steps, LCP solves and errors are deterministic.\n"
    );
    let _ = writeln!(
        s,
        "| model | solver | Δt [s] | steps | LCP solves | wall [s] | steps/s | LCP solves/s | error | unit | status | other errors |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|---:|---:|---|---|---|");
    for r in results {
        let ms = r.metrics();
        for (m, errs) in r.runs.iter().zip(&r.errors) {
            let head = &errs[0];
            let others: Vec<String> = ms
                .iter()
                .zip(errs)
                .skip(1)
                .map(|(metric, e)| match e {
                    Ok(x) => format!("{}: {} {}", metric.name, sci(*x), metric.unit),
                    Err(_) if m.outcome.is_err() => format!("{}: —", metric.name),
                    Err(why) => format!("{}: — ({why})", metric.name),
                })
                .collect();
            let _ = writeln!(
                s,
                "| {} | {} | {:e} | {} | {} | {:.2e} | {:.2e} | {:.2e} | {} | {} | {} | {} |",
                r.study.label(),
                m.solver.label(),
                m.dt,
                m.steps,
                m.lcp_solves,
                m.wall_seconds,
                m.steps_per_second(),
                m.lcp_solves_per_second(),
                head.as_ref().map_or("—".to_owned(), |x| sci(*x)),
                ms[0].unit,
                md_cell(&status_of(m, head)),
                md_cell(&others.join("; "))
            );
        }
    }
    s
}

/// One choice of step and solver for an error target.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Choice {
    /// Model name.
    pub model: String,
    /// The headline error measure.
    pub metric: String,
    /// Unit of the error.
    pub unit: String,
    /// Error target (a power of ten).
    pub target: f64,
    /// Largest step h whose Auto run meets the target (s).
    pub dt: f64,
    /// Error of that run.
    pub error: f64,
    /// Wall time of that run (s).
    pub wall_s: f64,
    /// The fastest solver meeting the target at that step, and its wall time (s).
    pub fastest: (String, f64),
}

/// The cost and accuracy of one solver on one model.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SolverCost {
    /// Model name.
    pub model: String,
    /// Solver label.
    pub solver: String,
    /// Runs that finished (not failed, not diverged) and runs in all.
    pub finished: (usize, usize),
    /// Steps per second over the finished runs of at least 1000 steps (total steps over total
    /// wall time).
    pub steps_per_s: Option<f64>,
    /// LCP solves per second over the same runs.
    pub lcp_solves_per_s: Option<f64>,
    /// Smallest and largest ratio of the headline error to the fitted solver's at the same
    /// step, over steps where that error lies above the floor.
    pub error_ratio: Option<(f64, f64)>,
}

/// Cost and accuracy of each solver on each model.
pub fn solver_costs(results: &[StudyResult]) -> Vec<SolverCost> {
    let mut out = Vec::new();
    for r in results {
        let fitted = r.fitted_solver();
        let floor = r.floor(0);
        let reference: Vec<(f64, f64)> =
            headline(r, fitted).into_iter().map(|p| (p.0, p.2)).filter(|p| p.1 > floor).collect();
        for &solver in &r.study.solvers {
            let runs: Vec<&Measurement> = r.runs.iter().filter(|m| m.solver == solver).collect();
            let finished: Vec<&&Measurement> =
                runs.iter().filter(|m| m.outcome.is_ok() && !m.diverged()).collect();
            let long: Vec<&&&Measurement> = finished.iter().filter(|m| m.steps >= 1000).collect();
            let wall: f64 = long.iter().map(|m| m.wall_seconds).sum();
            let rate = |count: u64| (wall > 0.0).then(|| count as f64 / wall);
            let ratios = headline(r, solver)
                .into_iter()
                .filter_map(|p| reference.iter().find(|q| q.0 == p.0).map(|q| p.2 / q.1));
            out.push(SolverCost {
                model: r.study.label().to_owned(),
                solver: solver.label(),
                finished: (finished.len(), runs.len()),
                steps_per_s: rate(long.iter().map(|m| m.steps).sum()),
                lcp_solves_per_s: rate(long.iter().map(|m| m.lcp_solves).sum()),
                error_ratio: analysis::range(ratios),
            });
        }
    }
    out
}

fn costs_markdown(results: &[StudyResult]) -> String {
    let mut s = String::from(
        "\nCost of each solver: steps and LCP solves per second of wall time over its finished \
         runs of at least 1000 steps, and its headline error relative to the Auto solver's at the \
         same Δt.\n\n\
         | model | solver | runs neither failed nor diverged | steps/s | LCP solves/s | error / Auto error |\n\
         |---|---|---:|---:|---:|---|\n",
    );
    let opt = |x: Option<f64>| x.map_or("—".to_owned(), |v| format!("{v:.2e}"));
    for c in solver_costs(results) {
        let ratio = c.error_ratio.map_or("—".to_owned(), |(lo, hi)| format!("{lo:.3} – {hi:.3}"));
        let _ = writeln!(
            s,
            "| {} | {} | {} of {} | {} | {} | {ratio} |",
            c.model,
            c.solver,
            c.finished.0,
            c.finished.1,
            opt(c.steps_per_s),
            opt(c.lcp_solves_per_s)
        );
    }
    s
}

/// For each model and each power of ten between its largest and smallest headline error:
/// the largest step whose Auto run meets it, and the fastest solver meeting it at that step.
pub fn choose(results: &[StudyResult]) -> Vec<Choice> {
    let mut out = Vec::new();
    for r in results {
        let metric = &r.metrics()[0];
        let fitted = r.fitted_solver();
        let floor = r.floor(0);
        let auto: Vec<(f64, f64, f64)> =
            headline(r, fitted).into_iter().filter(|p| p.2 > floor).collect();
        let Some((lo, hi)) = analysis::range(auto.iter().map(|p| p.2)) else { continue };
        let (top, bottom) = (hi.log10().floor() as i32, lo.log10().ceil() as i32);
        for k in (bottom..=top).rev() {
            let target = 10f64.powi(k);
            let best = auto.iter().filter(|p| p.2 <= target).max_by(|a, b| a.0.total_cmp(&b.0));
            let Some(&(dt, wall, error)) = best else { continue };
            let fastest = r
                .study
                .solvers
                .iter()
                .flat_map(|&solver| headline(r, solver).into_iter().map(move |p| (solver, p)))
                .filter(|(_, p)| p.0 == dt && p.2 <= target)
                .min_by(|a, b| a.1.1.total_cmp(&b.1.1))
                .map_or((fitted.label(), wall), |(solver, p)| (solver.label(), p.1));
            out.push(Choice {
                model: r.study.label().to_owned(),
                metric: metric.name.to_owned(),
                unit: metric.unit.to_owned(),
                target,
                dt,
                error,
                wall_s: wall,
                fastest,
            });
        }
    }
    out
}

fn choices(results: &[StudyResult]) -> String {
    let mut s = String::from(
        "\nStep size for an error target: the largest Δt whose Auto run meets it (headline \
         error), and the fastest solver meeting it at that Δt.\n\n\
         | model | error | target | largest Δt [s] | error at Δt | auto wall [s] | fastest solver | its wall [s] |\n\
         |---|---|---:|---:|---:|---:|---|---:|\n",
    );
    for c in choose(results) {
        let _ = writeln!(
            s,
            "| {} | {} | {:e} {} | {:e} | {} | {:.2e} | {} | {:.2e} |",
            c.model,
            c.metric,
            c.target,
            if c.unit == "-" { "(relative)" } else { c.unit.as_str() },
            c.dt,
            sci(c.error),
            c.wall_s,
            c.fastest.0,
            c.fastest.1
        );
    }
    s
}

/// Key numbers: observed orders and the references' own errors.
pub fn key_numbers(results: &[StudyResult]) -> Value {
    let mut orders = serde_json::Map::new();
    let mut references = serde_json::Map::new();
    for r in results {
        for (o, e) in r.orders.iter().zip(&r.reference_error) {
            let key = format!("{} {}", r.study.label(), o.metric.name);
            orders.insert(
                key.clone(),
                match &o.fit {
                    Ok(f) => json!(f.order),
                    Err(why) => json!(why),
                },
            );
            if let Some((h, _)) = &r.reference {
                references.insert(
                    key,
                    json!({"h_ref": h.dt, "difference": e.as_ref().ok(), "unit": o.metric.unit}),
                );
            }
        }
    }
    json!({"observed_order": orders, "reference_error": references})
}

/// The stem of the error-against-wall-time figure.
pub const WALL_STEM: &str = "figS1_speed_accuracy";
/// The stem of the error-against-step figure.
pub const DT_STEM: &str = "figS2_error_vs_dt";

fn panel_title(p: usize, r: &StudyResult) -> String {
    let m = &r.metrics()[0];
    let letter = (b'a' + (p % 26) as u8) as char;
    format!("({letter}) {}: {} [{}]", r.study.label(), m.name, m.unit)
}

fn solver_mark(solver: Solver) -> Mark {
    if solver == Solver::Lemke { Mark::Rings } else { Mark::Points }
}

/// The headline errors of one solver's runs: (Δt, wall time, error) of the runs with a
/// positive error.
fn headline(r: &StudyResult, solver: Solver) -> Vec<(f64, f64, f64)> {
    r.runs
        .iter()
        .zip(&r.errors)
        .filter(|(m, _)| m.solver == solver && !m.diverged())
        .filter_map(|(m, e)| match e[0] {
            Ok(x) if x > 0.0 => Some((m.dt, m.wall_seconds, x)),
            _ => None,
        })
        .collect()
}

/// Writes the two figures (SVG, PNG and a CSV of the plotted points each).
fn write_figures(results: &[StudyResult], out: &Path) -> Result<Vec<PathBuf>> {
    let mut wall_panels = Vec::new();
    let mut dt_panels = Vec::new();
    let mut wall_csv = csv::Writer::from_path(out.join(format!("{WALL_STEM}.csv")))?;
    wall_csv.write_record(["model", "metric", "unit", "solver", "dt", "wall_s", "error"])?;
    let mut dt_csv = csv::Writer::from_path(out.join(format!("{DT_STEM}.csv")))?;
    dt_csv.write_record(["model", "metric", "unit", "series", "dt", "error"])?;
    for (p, r) in results.iter().enumerate() {
        let metric = &r.metrics()[0];
        let title = panel_title(p, r);
        let mut wall = Panel::new(
            &title,
            "log10 wall time [s]",
            &format!("log10 error [{}]", metric.unit),
            "log10_wall",
        )
        .legend(LegendAt::UpperRight)
        .headroom(0.3);
        let mut by_dt = Panel::new(
            &title,
            "log10 Δt [s]",
            &format!("log10 error [{}]", metric.unit),
            "log10_dt",
        )
        .legend(LegendAt::UpperLeft)
        .headroom(0.45);
        for (j, &solver) in r.study.solvers.iter().enumerate() {
            let points = headline(r, solver);
            let label = solver.label();
            for &(dt, w, e) in &points {
                wall_csv.write_record([
                    r.study.label(),
                    metric.name,
                    metric.unit,
                    &label,
                    &format!("{dt:e}"),
                    &format!("{w}"),
                    &format!("{e}"),
                ])?;
                dt_csv.write_record([
                    r.study.label(),
                    metric.name,
                    metric.unit,
                    &label,
                    &format!("{dt:e}"),
                    &format!("{e}"),
                ])?;
            }
            let xs: Vec<f64> = points.iter().map(|p| p.1.max(1e-7).log10()).collect();
            let hs: Vec<f64> = points.iter().map(|p| p.0.log10()).collect();
            let ys: Vec<f64> = points.iter().map(|p| p.2.log10()).collect();
            let column = format!("{}_{}", r.study.label(), label.replace(' ', "_"));
            let mut dots = Series::line("", &column, xs.clone(), ys.clone(), j)
                .with_mark(solver_mark(solver))
                .not_data();
            if solver == Solver::Auto {
                dots =
                    dots.with_point_labels(points.iter().map(|p| format!("{:e}", p.0)).collect());
            }
            wall.series
                .push(Series::line(&label, &column, xs, ys.clone(), j).with_mark(Mark::Dashed));
            wall.series.push(dots);
            by_dt.series.push(
                Series::line(&label, &column, hs.clone(), ys.clone(), j).with_mark(Mark::Dashed),
            );
            by_dt.series.push(
                Series::line("", &column, hs, ys, j).with_mark(solver_mark(solver)).not_data(),
            );
        }
        if let Some(Ok(fit)) = r.orders.first().map(|o| &o.fit) {
            let ends = [fit.dt_min, fit.dt_max];
            by_dt.series.push(Series::line(
                &format!("fit ({}): p = {:.2}", r.orders[0].solver, fit.order),
                "fit",
                ends.iter().map(|h| h.log10()).collect(),
                ends.iter().map(|h| fit.at(*h).log10()).collect(),
                6,
            ));
            for h in ends {
                dt_csv.write_record([
                    r.study.label(),
                    metric.name,
                    metric.unit,
                    &format!("fit p = {}", fit.order),
                    &format!("{h:e}"),
                    &format!("{}", fit.at(h)),
                ])?;
            }
        }
        if let (Some((href, _)), Some(Ok(e))) = (&r.reference, r.reference_error.first())
            && *e > 0.0
        {
            let lo = href.dt.log10();
            let hi = r.study.steps.first().copied().unwrap_or(href.dt).log10();
            by_dt.series.push(
                Series::line(
                    "reference h_ref vs h_ref/2",
                    "reference",
                    vec![lo, hi],
                    vec![e.log10(); 2],
                    7,
                )
                .with_mark(Mark::Dashed),
            );
            by_dt.series.push(
                Series::line("", "reference_point", vec![lo], vec![e.log10()], 7)
                    .with_mark(Mark::Rings)
                    .not_data(),
            );
            dt_csv.write_record([
                r.study.label(),
                metric.name,
                metric.unit,
                "reference",
                &format!("{:e}", href.dt),
                &format!("{e}"),
            ])?;
        }
        wall_panels.push(wall);
        dt_panels.push(by_dt);
    }
    wall_csv.flush()?;
    dt_csv.flush()?;
    let mut files = Vec::new();
    for (stem, title, panels) in [
        (
            WALL_STEM,
            "Error against wall time per model and LCP solver (points: Δt of the auto runs)",
            wall_panels,
        ),
        (
            DT_STEM,
            "Error against step size Δt per model and LCP solver, with the fitted order",
            dt_panels,
        ),
    ] {
        let fig = Figure::new(title, panels, 2);
        let svg = out.join(format!("{stem}.svg"));
        let png = out.join(format!("{stem}.png"));
        fig.write_svg(&svg)?;
        fig.write_png(&png)?;
        files.extend([svg, png, out.join(format!("{stem}.csv"))]);
    }
    Ok(files)
}

/// Writes `tradeoff.csv` (one row per run and error measure).
fn write_table(results: &[StudyResult], path: &Path) -> Result<()> {
    let mut w =
        csv::Writer::from_path(path).with_context(|| format!("creating {}", path.display()))?;
    w.write_record([
        "model",
        "solver",
        "dt",
        "metric",
        "steps",
        "lcp_solves",
        "wall_s",
        "steps_per_s",
        "lcp_solves_per_s",
        "error",
        "unit",
        "status",
    ])?;
    for r in rows(results) {
        w.write_record([
            r.model,
            r.solver,
            format!("{:e}", r.dt),
            r.metric,
            r.steps.to_string(),
            r.lcp_solves.to_string(),
            format!("{}", r.wall_s),
            format!("{}", r.steps_per_s),
            format!("{}", r.lcp_solves_per_s),
            r.error.map_or(String::new(), |e| format!("{e}")),
            r.unit,
            r.status,
        ])?;
    }
    w.flush()?;
    Ok(())
}

/// What [`write()`] produced.
#[derive(Clone, Debug, Default)]
pub struct Written {
    /// Files written (names relative to the output folder).
    pub files: Vec<String>,
    /// The Markdown of the study (orders, references, runs), without a title.
    pub markdown: String,
    /// Key numbers (observed orders, reference errors).
    pub key_numbers: Value,
}

/// Writes the figures, `tradeoff.csv` and `tradeoff.md` into `out`; `command` is the command
/// line named in `tradeoff.md`.
///
/// # Errors
/// When a file cannot be written or a figure cannot be drawn.
pub fn write(results: &[StudyResult], out: &Path, command: &str) -> Result<Written> {
    let mut paths = write_figures(results, out)?;
    let csv = out.join("tradeoff.csv");
    write_table(results, &csv)?;
    paths.push(csv);
    let md = markdown(results);
    let descriptions: String = results
        .iter()
        .flat_map(|r| {
            r.metrics().iter().map(move |m| {
                format!("- {} — {} [{}]: {}.\n", r.study.label(), m.name, m.unit, m.description)
            })
        })
        .collect();
    let text = format!(
        "# Speed and accuracy\n\nGenerated by `{command}`. Each model runs its report scene \
         (the ball with ε_N = 0.7 for 3 s) at each step size Δt with each LCP solver. Errors:\n\n\
         {descriptions}\n{md}"
    );
    let path = out.join("tradeoff.md");
    std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
    paths.push(path);
    let files = crate::reproduce::names(&paths);
    Ok(Written { files, markdown: md, key_numbers: key_numbers(results) })
}

/// Runs `cargo xtask tradeoff`.
///
/// # Errors
/// When the output folder cannot be written or a figure cannot be drawn. Failed runs are
/// results, not errors.
pub fn run(options: &Options) -> Result<Summary> {
    let start = Instant::now();
    std::fs::create_dir_all(&options.out)
        .with_context(|| format!("creating {}", options.out.display()))?;
    faer::set_global_parallelism(faer::Par::Seq);
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(jobs) = options.jobs {
        builder = builder.num_threads(jobs.max(1));
    }
    let pool = builder.build().context("starting the worker threads")?;
    let results = pool.install(|| run_studies(&studies(options.quick)));
    let command =
        if options.quick { "cargo xtask tradeoff --quick" } else { "cargo xtask tradeoff" };
    let written = write(&results, &options.out, command)?;
    let simulation_seconds = results
        .iter()
        .flat_map(|r| r.runs.iter().chain(r.reference.iter().flat_map(|(a, b)| [a, b])))
        .map(|m| m.wall_seconds)
        .sum();
    Ok(Summary {
        files: written.files,
        total_seconds: start.elapsed().as_secs_f64(),
        simulation_seconds,
    })
}

// Studies and their runs are built and collected across rayon's worker threads.
const _: fn() = || {
    fn is<T: Send + Sync>() {}
    is::<Study>();
    is::<Measurement>();
    is::<StudyResult>();
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_fit_recovers_planted_slopes() {
        let dt = [1e-2, 3e-3, 1e-3, 3e-4, 1e-4];
        for (c, p) in [(3.0, 1.0), (0.5, 2.0), (7.0, 0.5)] {
            let e: Vec<f64> = dt.iter().map(|h: &f64| c * h.powf(p)).collect();
            let fit = fit_order(&dt, &e).expect("fit");
            assert!((fit.order - p).abs() < 1e-12, "{} vs {p}", fit.order);
            assert!((fit.log10_constant - c.log10()).abs() < 1e-10);
            assert_eq!(fit.points, 5);
            assert!((fit.dt_min - 1e-4).abs() < 1e-16 && (fit.dt_max - 1e-2).abs() < 1e-14);
            assert!((fit.at(1e-3) - c * 1e-3f64.powf(p)).abs() < 1e-9 * c * 1e-3f64.powf(p));
        }
    }

    #[test]
    fn order_fit_with_alternating_noise_and_rejected_points() {
        // Factors 1.1 and 1/1.1 alternate: the slope moves by a bounded amount.
        let dt = [1e-2, 1e-3, 1e-4, 1e-5];
        let e: Vec<f64> = dt
            .iter()
            .enumerate()
            .map(|(k, h)| 2.0 * h * if k % 2 == 0 { 1.1 } else { 1.0 / 1.1 })
            .collect();
        let fit = fit_order(&dt, &e).expect("fit");
        // Exact least squares on logs: x = −2, −3, −4, −5; noise ±log10(1.1) alternating.
        let d = 1.1f64.log10();
        // Deviations of x from its mean: 1.5, 0.5, −0.5, −1.5; Σ dx² = 5.
        let expected = 1.0 + (1.5 * d + 0.5 * -d + -0.5 * d + -1.5 * -d) / 5.0;
        assert!((fit.order - expected).abs() < 1e-12, "{} vs {expected}", fit.order);
        // Zero, negative and non-finite errors are left out; one point or one step is no fit.
        assert!(fit_order(&[1e-2, 1e-3], &[1e-3, 0.0]).is_none());
        assert!(fit_order(&[1e-2, 1e-2], &[1e-3, 2e-3]).is_none());
        assert!(fit_order(&[1e-2, 1e-3, 1e-4], &[f64::NAN, -1.0, 1e-5]).is_none());
        let fit = fit_order(&[1e-2, 1e-3, 1e-4], &[1e-2, f64::INFINITY, 1e-6]).expect("fit");
        assert!((fit.order - 2.0).abs() < 1e-12 && fit.points == 2);
    }

    #[test]
    fn paired_and_sampled_errors() {
        assert_eq!(paired_error(&[1.0, 2.5, 3.0], &[1.0, 2.0, 3.2], 5), Ok(0.5));
        assert_eq!(paired_error(&[1.0, 2.0, 9.0], &[1.0, 2.0, 3.0], 2), Ok(0.0));
        assert!(paired_error(&[1.0], &[1.0, 2.0], 5).unwrap_err().contains("1 of the 2"));
        assert!(paired_error(&[1.0], &[], 5).is_err());
        // Nearest instants: extra events of the run do not count, a missed one does.
        let e = nearest_error(&[0.9, 1.5, 2.125, 3.0], &[1.0, 2.0, 3.0], 5).expect("e");
        assert!((e - 0.125).abs() < 1e-15, "{e}");
        assert!((nearest_error(&[1.0, 3.0], &[1.0, 2.0, 3.0], 5).expect("e") - 1.0).abs() < 1e-15);
        assert!(nearest_error(&[], &[1.0], 5).is_err());
        assert!(nearest_error(&[1.0], &[], 5).is_err());
        let s = |t: f64, y: f64| Sample { t, q: vec![y], u: vec![-y] };
        let reference = [s(0.1, 1.0), s(0.2, 2.0)];
        assert_eq!(sampled_error(&[s(0.1, 1.25), s(0.2, 1.5)], &reference, |x| x.q[0]), Ok(0.5));
        assert_eq!(sampled_error(&[s(0.1, 1.25), s(0.2, 1.5)], &reference, |x| x.u[0]), Ok(0.5));
        let e = sampled_error(&[s(0.1, 1.0)], &reference, |x| x.q[0]).unwrap_err();
        assert!(e.contains("0.2"), "{e}");
        assert_eq!(relative_error(1.02, 1.0).map(|e| (e - 0.02).abs() < 1e-15), Ok(true));
        assert!(relative_error(1.0, 0.0).is_err());
    }

    /// The closed-form ball observed exactly: every error is zero; shifted impact times and
    /// apexes give the shift.
    #[test]
    fn ball_errors_against_the_closed_form() {
        let scene = studies(true)[0].scene(1e-3, Solver::Auto).expect("scene");
        let ModelParams::Ball(p) = &scene.params else { panic!("ball") };
        let cf = BallClosedForm::new(p.init.y0, p.r, p.g, p.eps_n);
        assert!((cf.t_inf - cf.t1 * 1.7 / 0.3).abs() < 1e-12);
        let dt = 1e-3;
        let times = cf.impact_times(6);
        let mut obs = Observation { dt, rest_time: Some(cf.t_inf + 2e-3), ..Default::default() };
        for (k, &t) in times.iter().enumerate() {
            obs.transitions.push(Transition {
                row: k * 10 + 1,
                t: t + 0.5 * dt + if k == 2 { 4e-4 } else { 0.0 },
                contact: 0,
                from: ContactState::Open,
                to: ContactState::Stick,
                gamma_pre: -1.0,
            });
        }
        obs.apexes = ball_apexes(&cf, p.r, 6);
        obs.apexes[1] -= 3e-4;
        obs.samples = (1..=14)
            .map(|k| {
                let t = 0.03 * k as f64;
                Sample { t, q: vec![p.init.y0 - 0.5 * p.g * t * t], u: vec![-p.g * t] }
            })
            .collect();
        let e = ball_errors(&scene.params, &obs);
        let close =
            |r: &Result<f64, String>, x: f64| r.as_ref().is_ok_and(|v| (v - x).abs() < 1e-12);
        assert!(close(&e[0], 4e-4), "{:?}", e[0]);
        assert!(close(&e[1], 3e-4), "{:?}", e[1]);
        assert!(close(&e[2], 2e-3), "{:?}", e[2]);
        assert!(close(&e[3], 0.0), "{:?}", e[3]);
        // The first apex after impact 1 of a drop from 1 m with R = 0.1 m: R + 0.49 H.
        assert!((obs.apexes[0] - (0.1 + 0.49 * 0.9)).abs() < 1e-12);
        // Slow closings (γ_N⁻ above −5 g Δt) are not impacts: the fifth impact is missed, and
        // its distance to the nearest impact found (the fourth) is the error.
        obs.transitions[4].gamma_pre = -1e-3;
        obs.transitions[5].gamma_pre = -1e-3;
        let e = ball_errors(&scene.params, &obs);
        assert!(close(&e[0], times[4] - times[3]), "{:?}", e[0]);
        // Too few apexes cannot be compared.
        obs.apexes.truncate(3);
        let e = ball_errors(&scene.params, &obs);
        assert!(e[1].as_ref().unwrap_err().contains("3 of the 5"), "{:?}", e[1]);
    }

    /// A free fall run by the stepper: the midpoint rule integrates constant gravity exactly,
    /// and the probe's samples and impacts match the closed form.
    #[test]
    fn probe_on_the_ball_matches_the_closed_form() {
        let study = &studies(true)[0];
        let m = measure(study, 1e-3, Solver::Auto);
        let obs = m.outcome.as_ref().expect("run");
        assert_eq!(m.steps, 3000);
        assert_eq!(obs.samples.len(), 14);
        let e = ball_errors(&study.scene(1e-3, Solver::Auto).expect("scene").params, obs);
        assert!(e[3].as_ref().is_ok_and(|v| *v < 1e-12), "{:?}", e[3]);
        // First impact within the step: |t_M − t1| ≤ Δt.
        assert!(e[0].as_ref().is_ok_and(|v| *v <= 5e-3), "{:?}", e[0]);
        assert!((obs.impact_instants(&[0], 0.05)[0] - (1.8f64 / 9.81).sqrt()).abs() <= 1e-3);
        let rest = obs.rest_time.expect("rests");
        assert!((rest - 0.4284 * 1.7 / 0.3).abs() < 0.05, "{rest}");
    }
}
