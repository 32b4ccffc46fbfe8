//! `cargo xtask scale`: how the many-body step scales with the number of contacts, on the
//! scene files of `scenes/scale/`.
//!
//! Each run loads a scene, sets its size, lets it settle (or run) for a given simulated time,
//! and then measures a window of steps: wall time per step split into detection, assembly and
//! solution, the solver's iterations and residual, the contacts, the largest penetration, the
//! kinetic energy and, for the resting column, the global force balance: the vertical
//! impulses of the contacts with the fixed walls and floor, summed and divided by Δt, against
//! the column's weight. The numbers go to `scale.json` and `scale.csv`, the figure to
//! `fig_scale.{svg,png,csv}`. The runs go one after the other, so that their timings do not
//! share the cores.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use moreau_lcp::fc2d::SiconosStorage;
use moreau_models::{AnyModel, Scene};
use moreau_stepper::{BodyContact, Mechanism, NO_BODY, Stepper};
use serde::Serialize;
use serde_json::Value;

use crate::frames::{Frame, Strip};
use crate::network;
use crate::plot::{Figure, Mark, Panel, Series};

/// The figure's file stem.
pub const STEM: &str = "fig_scale";

/// File stem of the force networks of the resting scenes.
pub const NETWORK_STEM: &str = "fig_scale_network";

/// One scene at one size.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    /// The scene, as named in the output (`disk-column`, `pyramid`, `granular-flow`).
    pub scene: &'static str,
    /// The scene file, relative to the workspace root.
    pub file: &'static str,
    /// `--set` overrides that give the size.
    pub set: Vec<(String, String)>,
    /// Simulated time before the measurement window (s).
    pub settle: f64,
    /// Steps in the measurement window.
    pub window: usize,
    /// Worker threads of rayon's pool (detection, assembly, islands): the scene settles on the
    /// first count, then the window is measured once per count in turn (each window continuing
    /// from the one before, the scene at rest), one result each.
    pub threads: Vec<usize>,
    /// How many times the windows of all thread counts are measured in turn (1, 2, 1, 2, ...
    /// for two counts), so that a slow phase of the machine does not decide their ratio; each
    /// count's result is its window of median time per step (the slower of the two middle
    /// ones for an even number).
    pub rounds: usize,
    /// Whether the scene should rest at the end (column, pyramid): then the force balance and
    /// the largest displacement are meaningful.
    pub resting: bool,
    /// Simulated time (s) of the positions from which the largest displacement is measured:
    /// after the first settling (the pyramid's boxes start 2 mm apart).
    pub reference: f64,
}

impl RunSpec {
    /// The scene and its size overrides, e.g. `disk-column fill.grain.count=1000`, and the
    /// threads when more than one.
    pub fn label(&self) -> String {
        let mut label = self.scene.to_owned();
        for (k, v) in &self.set {
            label.push_str(&format!(" {k}={v}"));
        }
        if self.threads != [1] {
            let counts: Vec<String> = self.threads.iter().map(usize::to_string).collect();
            label.push_str(&format!(" threads={}", counts.join(",")));
        }
        label
    }
}

/// What one run measured.
#[derive(Clone, Debug, Default, Serialize)]
pub struct RunResult {
    /// The scene's name.
    pub scene: String,
    /// The size overrides, as `key=value`.
    pub size: String,
    /// Worker threads.
    pub threads: usize,
    /// Bodies with coordinates.
    pub bodies: usize,
    /// Contacts with a normal impulse, mean over the window.
    pub contacts: f64,
    /// Detected contacts (closed or within the margin), mean over the window.
    pub detected: f64,
    /// Wall time per step over the window (ms).
    pub ms_per_step: f64,
    /// Of which detection (ms).
    pub ms_detection: f64,
    /// Of which assembly (ms).
    pub ms_assembly: f64,
    /// Of which the solution of the contact problems (ms).
    pub ms_solution: f64,
    /// Solver iterations per step, mean over the window (the worst island of each step).
    pub iterations: f64,
    /// The largest relative residual at exit over the window.
    pub residual: f64,
    /// Steps of the whole run (settling and window) taken with an island above the solvers'
    /// tolerance, as the scene's `inexact_residual` allows.
    pub inexact_steps: u64,
    /// Of which in the window.
    pub inexact_in_window: u64,
    /// The largest residual of those steps (0 when none).
    pub inexact_residual: f64,
    /// |Σ support reactions − weight| / weight at the last step (resting scenes), else NaN.
    pub force_balance_rel: f64,
    /// The largest penetration over the window (m).
    pub max_penetration: f64,
    /// Kinetic energy at the last step (J).
    pub kinetic_energy: f64,
    /// Height of the pile: highest minus lowest body origin (m).
    pub height: f64,
    /// The largest displacement of a body since the spec's reference time (m).
    pub max_displacement: f64,
    /// Wall time of the whole run, settling included (s).
    pub wall_seconds: f64,
    /// The force network of the last step of a resting run ([`crate::network::frame`]).
    #[serde(skip)]
    pub network: Option<Frame>,
}

/// The runs of the study; `quick` keeps those that take a few seconds.
pub fn specs(quick: bool) -> Vec<RunSpec> {
    let column = |n: usize, settle: f64, window: usize, threads: &[usize]| RunSpec {
        scene: "disk-column",
        file: "scenes/scale/disk-column.toml",
        set: vec![("fill.grain.count".into(), n.to_string())],
        settle,
        window,
        threads: threads.to_vec(),
        rounds: if threads.len() > 1 { 4 } else { 1 },
        resting: true,
        reference: 0.0,
    };
    let pyramid = |b: usize, time: f64| RunSpec {
        scene: "pyramid",
        file: "scenes/scale/pyramid.toml",
        set: vec![("fill.box.base".into(), b.to_string())],
        settle: time,
        window: 20,
        threads: vec![1],
        rounds: 1,
        resting: true,
        reference: 0.5,
    };
    let flow = |time: f64| RunSpec {
        scene: "granular-flow",
        file: "scenes/scale/granular-flow.toml",
        set: Vec::new(),
        settle: time,
        window: 20,
        threads: vec![1],
        rounds: 1,
        resting: false,
        reference: 0.0,
    };
    if quick {
        vec![column(100, 1.0, 20, &[1]), pyramid(10, 1.0), flow(0.1)]
    } else {
        vec![
            column(100, 2.0, 100, &[1]),
            column(300, 2.0, 100, &[1]),
            column(1000, 2.0, 50, &[1]),
            column(3000, 2.0, 50, &[1]),
            // About 10⁴ contacts: 313 rows, 7.8 m high.
            column(5000, 2.5, 100, &[1]),
            // 625 rows, 15.6 m high: the top row falls for about 1.8 s.
            column(10000, 3.0, 20, &[1, 2]),
            pyramid(10, 10.0),
            pyramid(20, 10.0),
            pyramid(50, 10.0),
            pyramid(100, 10.0),
            flow(2.0),
        ]
    }
}

/// The workspace root (the parent of `xtask/`).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().map(Path::to_path_buf).unwrap_or_default()
}

/// The vertical force of the fixed supports on the bodies over the step just taken: the
/// impulses P_N w_N + P_T w_T of every contact with one side without coordinates, summed on
/// the side with coordinates, over Δt. The contacts' directions are those of the step's
/// midpoint q_M = q_A + Δt/2 u_A, found again by the scene's own detection with the step's
/// active-set threshold `margin` (`StepperOptions::gap_tolerance`).
///
/// # Errors
/// When a contact that carried an impulse is not found again: the balance would leave it out.
fn support_force(
    model: &AnyModel,
    (q_a, u_a, t_a): (&[f64], &[f64], f64),
    dt: f64,
    margin: f64,
    impulses: &[(u64, f64, f64)],
    found: &mut Vec<BodyContact>,
) -> Result<f64> {
    let Some(bodies) = model.body_structure() else { return Ok(f64::NAN) };
    let mut q_m = Vec::new();
    let t_m = crate::contacts::midpoint(q_a, u_a, t_a, dt, &mut q_m);
    found.clear();
    bodies.detect(&q_m, t_m, margin, found);
    let mut force = 0.0;
    let mut k = 0;
    for &(id, p_n, p_t) in impulses {
        if p_n == 0.0 && p_t == 0.0 {
            continue;
        }
        while k < found.len() && found[k].id < id {
            k += 1;
        }
        let Some(point) = found.get(k).filter(|p| p.id == id) else {
            bail!(
                "contact {id} of the step ending at t = {:e} s, with impulses ({p_n:e}, {p_t:e}) \
                 N s, is not found again at the step's midpoint",
                t_a + dt
            );
        };
        for side in 0..2 {
            if point.bodies[side] != NO_BODY && point.bodies[1 - side] == NO_BODY {
                force += p_n * point.w_n[side][1] + p_t * point.w_t[side][1];
            }
        }
    }
    Ok(force / dt)
}

/// Runs one spec: one result per thread count. With `problems`, the largest island problem
/// of the first window's last step is written there in Siconos' FC2D format, as
/// `<scene>_<size>.dat`, for solving the same step problems with another solver.
///
/// # Errors
/// When the scene does not load or build, a step fails, or the problem cannot be written.
pub fn run_one(spec: &RunSpec, problems: Option<&Path>) -> Result<Vec<RunResult>> {
    let start = Instant::now();
    let path = root().join(spec.file);
    let mut scene =
        Scene::from_path(&path).with_context(|| format!("loading {}", path.display()))?;
    for (k, v) in &spec.set {
        scene.set(k, v).with_context(|| format!("{}: --set {k}={v}", spec.scene))?;
    }
    let mut stepper = scene.stepper().with_context(|| format!("building {}", spec.scene))?;
    if stepper.mechanism().body_structure().is_none() {
        bail!("{} does not detect its contacts at each step", spec.scene);
    }
    let pool = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .context("starting the worker threads")
    };
    let first = *spec.threads.first().context("a run needs a thread count")?;
    let settled = pool(first)?.install(|| settle(spec, &mut stepper))?;
    let mut windows: Vec<Vec<RunResult>> = vec![Vec::new(); spec.threads.len()];
    for round in 0..spec.rounds.max(1) {
        for (k, &threads) in spec.threads.iter().enumerate() {
            let r =
                pool(threads)?.install(|| measure(spec, threads, &mut stepper, &settled, start))?;
            if spec.rounds > 1 {
                eprintln!(
                    "scale: {} round {} ({threads} thread{}): {:.3} ms/step",
                    spec.label(),
                    round + 1,
                    if threads == 1 { "" } else { "s" },
                    r.ms_per_step
                );
            }
            if round == 0
                && k == 0
                && let Some(dir) = problems
            {
                write_problem(spec, &stepper, dir)?;
            }
            windows[k].push(r);
        }
    }
    Ok(windows.into_iter().filter_map(median_window).collect())
}

/// The window of median time per step, the slower of the two middle ones for an even number.
fn median_window(mut windows: Vec<RunResult>) -> Option<RunResult> {
    windows.sort_by(|a, b| a.ms_per_step.total_cmp(&b.ms_per_step));
    let middle = windows.len() / 2;
    windows.into_iter().nth(middle)
}

/// What the settling phase of a run leaves for its windows.
struct Settled {
    /// The positions from which the largest displacement is measured.
    q0: Vec<f64>,
    /// Steps taken with an island above the solvers' tolerance, and their largest residual.
    inexact_steps: u64,
    inexact_residual: f64,
}

/// Counts a step taken with an island above the solvers' tolerance; returns 1 for such a step.
fn count_inexact(info: Option<moreau_stepper::LcpInfo>, steps: &mut u64, largest: &mut f64) -> u64 {
    match info.and_then(|i| i.inexact()) {
        Some(residual) => {
            *steps += 1;
            *largest = largest.max(residual);
            1
        }
        None => 0,
    }
}

/// Steps the scene through its settling time; a settling that lasts more than 10 s of wall
/// time tells its progress on standard error at each tenth of it.
fn settle(spec: &RunSpec, stepper: &mut Stepper<AnyModel>) -> Result<Settled> {
    let dt = stepper.options().dt;
    let mut out = Settled { q0: stepper.q().to_vec(), inexact_steps: 0, inexact_residual: 0.0 };
    let settle_steps = (spec.settle / dt).round() as u64;
    let reference_step = (spec.reference / dt).round() as u64;
    let start = Instant::now();
    for k in 0..settle_steps {
        if k > 0 && k % (settle_steps / 10).max(1) == 0 && start.elapsed().as_secs() >= 10 {
            eprintln!(
                "scale: {}: settling, t = {:.3} of {} s after {:.0} s ({} inexact steps)",
                spec.label(),
                stepper.t(),
                spec.settle,
                start.elapsed().as_secs_f64(),
                out.inexact_steps
            );
        }
        if k == reference_step {
            out.q0.copy_from_slice(stepper.q());
        }
        let t = stepper.t();
        let report = stepper.step().with_context(|| format!("{} at t = {t}", spec.scene))?;
        count_inexact(report.lcp, &mut out.inexact_steps, &mut out.inexact_residual);
    }
    Ok(out)
}

/// Writes the largest island problem of the stepper's last step into `dir`.
fn write_problem(spec: &RunSpec, stepper: &Stepper<AnyModel>, dir: &Path) -> Result<()> {
    let Some(problem) = stepper.last_islands().max_by_key(|p| p.n_contacts()) else {
        return Ok(());
    };
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let size: Vec<&str> = spec.set.iter().map(|(_, v)| v.as_str()).collect();
    let name = if size.is_empty() {
        format!("{}.dat", spec.scene)
    } else {
        format!("{}_{}.dat", spec.scene, size.join("_"))
    };
    let path = dir.join(name);
    let file =
        std::fs::File::create(&path).with_context(|| format!("creating {}", path.display()))?;
    problem
        .to_owned()
        .write_siconos(std::io::BufWriter::new(file), SiconosStorage::SparseBlock)
        .with_context(|| format!("writing {}", path.display()))
}

/// Measures one window of steps on the current thread pool.
fn measure(
    spec: &RunSpec,
    threads: usize,
    stepper: &mut Stepper<AnyModel>,
    settled: &Settled,
    start: Instant,
) -> Result<RunResult> {
    let (dt, margin) = (stepper.options().dt, stepper.options().gap_tolerance);
    let q0 = &settled.q0;
    let bodies = q0.len() / 3;
    let (mut inexact_steps, mut inexact_residual) =
        (settled.inexact_steps, settled.inexact_residual);
    let mut r = RunResult {
        scene: spec.scene.to_owned(),
        size: spec.set.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(" "),
        threads,
        bodies,
        force_balance_rel: f64::NAN,
        ..RunResult::default()
    };
    let (mut wall, mut detection, mut assembly, mut solution) = (Duration::ZERO, 0.0, 0.0, 0.0);
    let mut iterations = 0usize;
    let mut found = Vec::new();
    for k in 0..spec.window {
        let (q_a, u_a, t_a) = (stepper.q().to_vec(), stepper.u().to_vec(), stepper.t());
        let t0 = Instant::now();
        let report = stepper.step().with_context(|| format!("{} at t = {t_a}", spec.scene))?;
        wall += t0.elapsed();
        let phases = report.times;
        detection += phases.detection.as_secs_f64();
        assembly += phases.assembly.as_secs_f64();
        solution += phases.solution.as_secs_f64();
        r.contacts += report.contacts.iter().filter(|c| c.p_n > 0.0).count() as f64;
        r.detected += report.contacts.len() as f64;
        r.inexact_in_window += count_inexact(report.lcp, &mut inexact_steps, &mut inexact_residual);
        if let Some(info) = report.lcp {
            iterations += info.iterations;
            r.residual = r.residual.max(info.residual);
        }
        r.max_penetration = r.max_penetration.max(report.penetration);
        if k + 1 == spec.window && spec.resting {
            let (ids, contacts) = (report.contact_ids.to_vec(), report.contacts.to_vec());
            let impulses: Vec<(u64, f64, f64)> =
                ids.iter().zip(&contacts).map(|(id, c)| (*id, c.p_n, c.p_t)).collect();
            let model = stepper.mechanism();
            let state = (q_a.as_slice(), u_a.as_slice(), t_a);
            let support = support_force(model, state, dt, margin, &impulses, &mut found)?;
            let weight = weight(model, &q_a);
            r.force_balance_rel = ((support - weight) / weight).abs();
            let caption = vec![format!("{} {}, t = {:.2} s", spec.scene, r.size, t_a + dt)];
            r.network = Some(network::frame(model, state, dt, margin, &ids, &contacts, caption)?);
        }
    }
    (r.inexact_steps, r.inexact_residual) = (inexact_steps, inexact_residual);
    let n = spec.window.max(1) as f64;
    r.ms_per_step = 1e3 * wall.as_secs_f64() / n;
    r.ms_detection = 1e3 * detection / n;
    r.ms_assembly = 1e3 * assembly / n;
    r.ms_solution = 1e3 * solution / n;
    r.iterations = iterations as f64 / n;
    r.contacts /= n;
    r.detected /= n;
    let (q, u) = (stepper.q(), stepper.u());
    r.kinetic_energy = match stepper.mechanism() {
        AnyModel::Declared(m) => m.kinetic_energy(q, u),
        _ => f64::NAN,
    };
    let ys = q.chunks_exact(3).map(|b| b[1]);
    let (lo, hi) =
        ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), y| (lo.min(y), hi.max(y)));
    r.height = if bodies > 0 { hi - lo } else { 0.0 };
    r.max_displacement = q
        .chunks_exact(3)
        .zip(q0.chunks_exact(3))
        .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
        .fold(0.0, f64::max);
    r.wall_seconds = start.elapsed().as_secs_f64();
    Ok(r)
}

/// The weight of the bodies: minus the vertical components of h at rest, which for the scale
/// scenes (gravity, no springs) are −m_k g.
fn weight(model: &AnyModel, q: &[f64]) -> f64 {
    let u = vec![0.0; q.len()];
    let mut h = vec![0.0; q.len()];
    model.forces(q, &u, 0.0, &mut h);
    -h.chunks_exact(3).map(|b| b[1]).sum::<f64>()
}

/// Runs every spec in order (one at a time, so that the timings do not share the cores),
/// writing the step problems into `problems` when given (see [`run_one`]). A run that fails
/// is reported with its error and the others go on.
pub fn run_all(specs: &[RunSpec], problems: Option<&Path>) -> Vec<Result<Vec<RunResult>, String>> {
    specs
        .iter()
        .map(|s| {
            let r = run_one(s, problems).map_err(|e| format!("{e:#}"));
            match &r {
                Ok(rs) => rs.iter().for_each(|r| {
                    eprintln!(
                        "scale: {} {} ({} thread{}): {} bodies, {:.0} contacts, {:.3} ms/step",
                        r.scene,
                        r.size,
                        r.threads,
                        if r.threads == 1 { "" } else { "s" },
                        r.bodies,
                        r.contacts,
                        r.ms_per_step
                    )
                }),
                Err(e) => eprintln!("scale: {} failed: {e}", s.scene),
            }
            r
        })
        .collect()
}

/// Least-squares slope of log10 y against log10 x over the positive pairs.
pub fn log_slope(x: &[f64], y: &[f64]) -> Option<f64> {
    let pts: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .filter(|(x, y)| **x > 0.0 && **y > 0.0)
        .map(|(x, y)| (x.log10(), y.log10()))
        .collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) =
        (pts.iter().map(|p| p.0).sum::<f64>() / n, pts.iter().map(|p| p.1).sum::<f64>() / n);
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// One cell of the table of runs, formatted for the CSV (full precision) or for Markdown.
enum Cell {
    Text(String),
    /// A number shown with this many decimals in Markdown.
    Fixed(f64, usize),
    /// A number shown in scientific notation in Markdown; NaN, a number that does not apply
    /// to the run (the force balance of a flow), is an empty CSV field and "—".
    Sci(f64),
}

impl Cell {
    fn csv(&self) -> String {
        match self {
            Cell::Text(t) => t.clone(),
            Cell::Sci(v) if v.is_nan() => String::new(),
            Cell::Fixed(v, _) | Cell::Sci(v) => format!("{v:e}"),
        }
    }

    fn markdown(&self) -> String {
        match self {
            Cell::Text(t) => t.clone(),
            Cell::Fixed(v, d) => format!("{v:.d$}"),
            Cell::Sci(v) if v.is_nan() => "—".to_owned(),
            Cell::Sci(v) => format!("{v:.1e}"),
        }
    }
}

/// The table's columns: CSV name, Markdown heading, and the cell of a run.
type Column = (&'static str, &'static str, fn(&RunResult) -> Cell);

const COLUMNS: &[Column] = &[
    ("scene", "scene", |r| Cell::Text(r.scene.clone())),
    ("size", "size", |r| Cell::Text(r.size.clone())),
    ("threads", "threads", |r| Cell::Text(r.threads.to_string())),
    ("bodies", "bodies", |r| Cell::Text(r.bodies.to_string())),
    ("contacts", "contacts", |r| Cell::Fixed(r.contacts, 0)),
    ("ms_per_step", "ms/step", |r| Cell::Fixed(r.ms_per_step, 3)),
    ("ms_detection", "detection", |r| Cell::Fixed(r.ms_detection, 3)),
    ("ms_assembly", "assembly", |r| Cell::Fixed(r.ms_assembly, 3)),
    ("ms_solution", "solution", |r| Cell::Fixed(r.ms_solution, 3)),
    ("iterations", "iterations", |r| Cell::Fixed(r.iterations, 1)),
    ("residual", "residual", |r| Cell::Sci(r.residual)),
    ("inexact_steps", "inexact steps", |r| Cell::Text(r.inexact_steps.to_string())),
    ("inexact_in_window", "of which in the window", |r| {
        Cell::Text(r.inexact_in_window.to_string())
    }),
    ("inexact_residual", "inexact residual", |r| Cell::Sci(r.inexact_residual)),
    ("force_balance_rel", "force balance", |r| Cell::Sci(r.force_balance_rel)),
    ("max_penetration", "penetration [m]", |r| Cell::Sci(r.max_penetration)),
    ("kinetic_energy", "kinetic energy [J]", |r| Cell::Sci(r.kinetic_energy)),
    ("height", "height [m]", |r| Cell::Sci(r.height)),
    ("max_displacement", "max displacement [m]", |r| Cell::Sci(r.max_displacement)),
];

/// What [`write()`] produced.
pub struct Written {
    /// Files written (names relative to the output folder).
    pub files: Vec<String>,
    /// The runs as JSON: one entry per run, the `scale` key of `summary.json`.
    pub json: Value,
    /// A Markdown table of the runs.
    pub markdown: String,
}

/// Writes `scale.json`, `scale.csv` and the figure into `out`.
///
/// # Errors
/// When a file cannot be written.
pub fn write(
    results: &[Result<Vec<RunResult>, String>],
    specs: &[RunSpec],
    out: &Path,
) -> Result<Written> {
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let ok: Vec<&RunResult> = results.iter().filter_map(|r| r.as_ref().ok()).flatten().collect();
    let entries: Vec<Value> = results
        .iter()
        .zip(specs)
        .flat_map(|(r, s)| match r {
            Ok(rs) => rs.iter().map(|r| serde_json::to_value(r).unwrap_or(Value::Null)).collect(),
            Err(e) => vec![serde_json::json!({"scene": s.scene, "error": e})],
        })
        .collect();
    let json = Value::Array(entries);
    let mut files = Vec::new();
    let path = out.join("scale.json");
    std::fs::write(&path, serde_json::to_string_pretty(&json)?)
        .with_context(|| format!("writing {}", path.display()))?;
    files.push("scale.json".to_owned());

    let mut csv = COLUMNS.iter().map(|c| c.0).collect::<Vec<_>>().join(",");
    csv.push('\n');
    let mut md = format!(
        "| {} |\n|---|---|{}\n",
        COLUMNS.iter().map(|c| c.1).collect::<Vec<_>>().join(" | "),
        "---:|".repeat(COLUMNS.len() - 2)
    );
    for r in &ok {
        let cells: Vec<Cell> = COLUMNS.iter().map(|c| (c.2)(r)).collect();
        csv.push_str(&cells.iter().map(Cell::csv).collect::<Vec<_>>().join(","));
        csv.push('\n');
        md.push_str(&format!(
            "| {} |\n",
            cells.iter().map(Cell::markdown).collect::<Vec<_>>().join(" | ")
        ));
    }
    for (r, s) in results.iter().zip(specs) {
        if let Err(e) = r {
            md.push_str(&format!("| {} | failed: {} |\n", s.scene, e.replace('|', "/")));
        }
    }
    let path = out.join("scale.csv");
    std::fs::write(&path, csv).with_context(|| format!("writing {}", path.display()))?;
    files.push("scale.csv".to_owned());

    let one_thread = |scene: &str| -> Vec<&RunResult> {
        ok.iter().copied().filter(|r| r.scene == scene && r.threads == 1).collect()
    };
    let column = one_thread("disk-column");
    let xs =
        |rs: &[&RunResult], f: fn(&RunResult) -> f64| rs.iter().map(|r| f(r)).collect::<Vec<_>>();
    let slope = log_slope(&xs(&column, |r| r.contacts), &xs(&column, |r| r.ms_per_step));
    let mut time = Panel::new(
        &match slope {
            Some(p) => format!("Time per step (disk column: slope {p:.2})"),
            None => "Time per step".to_owned(),
        },
        "log10 contacts",
        "log10 ms per step",
        "log10_contacts",
    );
    for (i, scene) in ["disk-column", "pyramid", "granular-flow"].into_iter().enumerate() {
        let rs = one_thread(scene);
        let x: Vec<f64> = rs.iter().map(|r| r.contacts.max(1.0).log10()).collect();
        let y: Vec<f64> = rs.iter().map(|r| r.ms_per_step.log10()).collect();
        if !x.is_empty() {
            time = time.with(
                Series::line(scene, &format!("log10_ms_{scene}"), x, y, i).with_mark(Mark::Points),
            );
        }
    }
    let iterations = Panel::new(
        "Solver iterations, resting disk column",
        "column height [m]",
        "iterations per step",
        "height",
    )
    .with(
        Series::line(
            "disk column",
            "iterations",
            xs(&column, |r| r.height),
            xs(&column, |r| r.iterations),
            0,
        )
        .with_mark(Mark::Points),
    );
    let balance =
        Panel::new("Force balance at rest", "log10 bodies", "log10 |R − W| / W", "log10_bodies")
            .with(
                Series::line(
                    "disk column",
                    "log10_force_balance",
                    column.iter().map(|r| (r.bodies as f64).log10()).collect(),
                    column.iter().map(|r| r.force_balance_rel.max(1e-17).log10()).collect(),
                    0,
                )
                .with_mark(Mark::Points),
            );
    let figure = Figure::new("Many-body steps: scaling", vec![time, iterations, balance], 3);
    let written = figure.write(out, STEM)?;
    files.extend(crate::reproduce::names(&written));
    // The force networks of the largest resting column and pyramid of at most 1,300 bodies.
    let networks: Vec<Frame> = ["disk-column", "pyramid"]
        .into_iter()
        .filter_map(|scene| {
            let largest = one_thread(scene).into_iter().filter(|r| r.bodies <= 1300);
            largest.max_by_key(|r| r.bodies)?.network.clone()
        })
        .collect();
    if !networks.is_empty() {
        let strip = Strip {
            title: "Force networks at rest (line width grows with the normal impulse)".into(),
            columns: networks.len(),
            frames: networks,
            cell_width: 420,
            cell_height: 420,
            window: None,
        };
        let written = strip.write_still(out, NETWORK_STEM)?;
        files.extend(crate::reproduce::names(&written));
    }
    Ok(Written { files, json, markdown: md })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_number_that_does_not_apply_is_left_blank() {
        let (nan, one) = (Cell::Sci(f64::NAN), Cell::Sci(1.5e-9));
        assert_eq!((nan.csv().as_str(), nan.markdown().as_str()), ("", "—"));
        assert_eq!((one.csv().as_str(), one.markdown().as_str()), ("1.5e-9", "1.5e-9"));
    }

    /// A disk of 2 kg at rest above a floor, its contacts detected: the scene's text with the
    /// disk's centre at `y` (m).
    fn disk_above_floor(y: f64) -> Scene {
        let text = format!(
            r#"
dt = 0.001
t_end = 0.01
gravity = [0.0, -9.81]
contact_set = "detected"
projection = false

[[bodies]]
name = "floor"
type = "fixed"
position = [0.0, 0.0]
shapes = [{{ type = "half_plane", point = [0.0, 0.0], normal = [0.0, 1.0] }}]

[[bodies]]
name = "disk"
type = "dynamic"
mass = 2.0
inertia = 0.01
position = [0.0, {y:e}]
shapes = [{{ type = "disk", center = [0.0, 0.0], radius = 0.1 }}]

[contacts_auto]
eps_n = 0.0
eps_t = 0.0
mu = 0.3
"#
        );
        Scene::from_toml_str(&text).expect("the scene reads")
    }

    /// One step from rest; the support force of that step, found again with the step's gap
    /// tolerance or with none, and the weight.
    fn support_after_one_step(y: f64, with_tolerance: bool) -> (Result<f64>, f64) {
        let mut stepper = disk_above_floor(y).stepper().expect("the scene builds");
        let (dt, tolerance) = (stepper.options().dt, stepper.options().gap_tolerance);
        let (q_a, u_a, t_a) = (stepper.q().to_vec(), stepper.u().to_vec(), stepper.t());
        let report = stepper.step().expect("the step is taken");
        let impulses: Vec<(u64, f64, f64)> = report
            .contact_ids
            .iter()
            .zip(report.contacts)
            .map(|(id, c)| (*id, c.p_n, c.p_t))
            .collect();
        assert_eq!(impulses.len(), 1, "the disk's one contact is in the step");
        let model = stepper.mechanism();
        let margin = if with_tolerance { tolerance } else { 0.0 };
        let state = (q_a.as_slice(), u_a.as_slice(), t_a);
        let support = support_force(model, state, dt, margin, &impulses, &mut Vec::new());
        (support, weight(model, &q_a))
    }

    #[test]
    fn the_rounds_of_a_thread_count_give_its_window_of_median_time() {
        let windows = |ms: &[f64]| {
            ms.iter().map(|&m| RunResult { ms_per_step: m, ..RunResult::default() }).collect()
        };
        let median = |ms: &[f64]| median_window(windows(ms)).map(|r| r.ms_per_step);
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[1.0, 4.0, 2.0, 3.0]), Some(3.0));
        assert_eq!(median(&[5.0]), Some(5.0));
        assert_eq!(median(&[]), None);
    }

    #[test]
    fn a_contact_open_within_the_gap_tolerance_carries_the_weight_in_the_force_balance() {
        // The disk rests half the active-set threshold above the floor: the step's problem
        // holds its contact (g_N <= gap_tolerance), whose impulse stops the fall, m g Δt.
        let probe = disk_above_floor(0.1).stepper().expect("the scene builds");
        let tolerance = probe.options().gap_tolerance;
        assert!(tolerance > 0.0, "a declared scene has a positive gap tolerance");
        let (support, weight) = support_after_one_step(0.1 + 0.5 * tolerance, true);
        let support = support.expect("the contact is found again with the step's threshold");
        assert!((weight - 2.0 * 9.81).abs() < 1e-12, "weight {weight}");
        assert!(((support - weight) / weight).abs() < 1e-12, "support {support}, weight {weight}");
        // Found again without that threshold, it would be left out of the balance: an error.
        let (missed, _) = support_after_one_step(0.1 + 0.5 * tolerance, false);
        let message = format!("{:#}", missed.expect_err("a contact with an impulse is missed"));
        assert!(message.contains("is not found again"), "{message}");
    }
}
