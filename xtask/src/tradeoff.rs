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
//! A run that stops with a typed error is listed as `failed: <reason>`, and the study, once
//! every file is written, ends in an error that counts such runs ([`check_runs`]).
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

mod errors;
use errors::{ball_errors, reference_errors};
mod measure;
mod report;
pub use errors::*;
pub use measure::*;
pub use report::*;

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
        ModelKind::Declared => &[],
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

/// Runs `cargo xtask tradeoff`.
///
/// # Errors
/// When the output folder cannot be written or a figure cannot be drawn; when a run failed,
/// once every file is written ([`check_runs`]).
pub fn run(options: &Options) -> Result<Summary> {
    let start = Instant::now();
    crate::reproduce::writable(&options.out).context("--out")?;
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
    check_runs(&results)?;
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
