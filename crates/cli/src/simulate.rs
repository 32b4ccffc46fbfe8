//! `moreau simulate`: run one model under the guards and stream its record to CSV.

use std::fs::File;
use std::io::{BufWriter, IsTerminal, Write};
use std::ops::ControlFlow;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use moreau_models::{AnyModel, ModelKind, Scene, Simulation};
use moreau_stepper::{Impulses, Mechanism, Observer, Record, Recorder, StepReport};

use crate::contacts::ContactLog;
use crate::error::CliError;
use crate::failed::{self, failed_problem_path};
use crate::guard::{self, DEFAULT_MAX_STEPS};
use crate::number;
pub use crate::output::partial_path;
use crate::output::{self, Output, OutputLock, csv_record};
use crate::runs::{RunResult, RunSpec, run_info};

/// What to simulate.
#[derive(Clone, Debug, Default)]
pub struct SimulateOptions {
    /// Model name (`ball`, `woodpecker`, `slider-crank`, `slider-crank-ideal`, `cam`,
    /// `painleve`); `None` to take the model from the scene file. When both are given they
    /// must agree.
    pub model: Option<String>,
    /// A scene file to start from instead of the model's report scene: a report model's
    /// (with `[params]`) or a declared mechanism's (with `[[bodies]]`).
    pub scene: Option<PathBuf>,
    /// `key=value` overrides; each scene entry may be set once.
    pub sets: Vec<String>,
    /// Time step Δt (s), overriding the scene's.
    pub dt: Option<f64>,
    /// End time (s), overriding the scene's.
    pub tf: Option<f64>,
    /// Solver name (`auto`, `lemke`, `pgs`, `enum`).
    pub solver: Option<String>,
    /// The largest number of steps allowed; [`DEFAULT_MAX_STEPS`] when `None`.
    pub max_steps: Option<u64>,
    /// A file to write the located contacts of the recorded steps to (declared mechanisms
    /// only; see [`crate::contacts`]), written as `<file>.partial` until the run succeeds.
    pub contacts: Option<PathBuf>,
    /// A scene file to write the run's end state to, as the scene continued from it
    /// ([`Scene::continued`]): its `t_start` the run's last time, its initial state the last
    /// step's q and u. Written once the run has succeeded, and only then.
    pub end_scene: Option<PathBuf>,
}

impl SimulateOptions {
    /// The step limit in force.
    pub fn step_limit(&self) -> u64 {
        self.max_steps.unwrap_or(DEFAULT_MAX_STEPS)
    }
}

/// Parses `key=value`.
///
/// # Errors
/// When there is no `=` or the key is empty.
pub fn parse_set(text: &str) -> Result<(String, String)> {
    match text.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_owned(), v.trim().to_owned())),
        _ => bail!("expected key=value, got '{text}'"),
    }
}

/// The model named `name`.
///
/// # Errors
/// An unknown name, with the accepted names.
pub fn parse_model(name: &str) -> Result<ModelKind> {
    Ok(name.parse::<ModelKind>()?)
}

/// The scene to start from: the scene file when one is given (a report model's or a declared
/// mechanism's), otherwise the named model's report scene.
///
/// # Errors
/// [`CliError::NoModel`] when neither is given; [`CliError::ModelMismatch`] when both are and
/// the file describes another model; an unknown model name; an unreadable or invalid scene
/// file (the models' error, naming the field).
pub fn base_scene(model: Option<&str>, scene: Option<&Path>) -> Result<Scene> {
    match (model, scene) {
        (None, None) => {
            Err(CliError::NoModel { accepted: ModelKind::ALL.map(ModelKind::name).join(", ") }
                .into())
        }
        (Some(name), None) => Ok(Scene::report(parse_model(name)?)),
        (given, Some(path)) => {
            let scene = Scene::from_path(path)?;
            if let Some(name) = given
                && name != scene.kind().name()
            {
                // An unknown name is refused as such before the disagreement is reported.
                parse_model(name)?;
                return Err(CliError::ModelMismatch {
                    given: name.to_owned(),
                    path: path.to_owned(),
                    in_scene: scene.kind().name().to_owned(),
                }
                .into());
            }
            Ok(scene)
        }
    }
}

/// Applies `key=value` overrides to a scene in order, refusing a key that sets an entry an
/// earlier key set, aliases included (`y0` and `init.y0`; `mu` and `beak.mu` on the
/// woodpecker; `bodies.1.mass` and `bodies.sleeve.mass` when the second body is `sleeve`),
/// or a part of it (`gravity` and `gravity.1`). Each key is resolved on the scene as the
/// earlier overrides left it, so that `solver=pgs` followed by `solver.tolerance=1e-8` works:
/// the solver's name chooses its kind, whose fields a later key may then set.
///
/// # Errors
/// [`CliError::RepeatedKey`] naming both keys and the entry; [`moreau_models::ModelError::UnknownKey`] for a
/// key the scene does not have, with the keys of the level where it leaves the scene's and
/// the nearest of them; a bad value (naming the override); a scene the overrides leave
/// invalid, naming the override after which it became so. Overrides that are valid only
/// together are taken: the scene is validated once all are applied.
pub fn apply_sets(scene: &mut Scene, sets: &[(String, String)]) -> Result<()> {
    apply_labelled(scene, sets.iter().map(|(k, v)| (k.as_str(), k.as_str(), v.as_str())))
}

/// [`apply_sets`] with each override's name for the messages (`--dt` for the key `dt`).
fn apply_labelled<'a>(
    scene: &mut Scene,
    sets: impl IntoIterator<Item = (&'a str, &'a str, &'a str)>,
) -> Result<()> {
    // Whether setting `later` after `earlier` changes what `earlier` set: the same entry, a
    // part of it or a whole it is part of; a field of the solver after its name does not.
    let overlap = |earlier: &str, later: &str| {
        let under = |part: &str, whole: &str| {
            part.strip_prefix(whole).is_some_and(|rest| rest.starts_with('.'))
        };
        earlier == later || under(earlier, later) || (under(later, earlier) && earlier != "solver")
    };
    // The option as the user typed it: `--dt NaN`, or `--set dt=NaN`.
    let typed = |label: &str, key: &str, value: &str| {
        if label == key { format!("--set {key}={value}") } else { format!("{label} {value}") }
    };
    let mut seen: Vec<(&str, Vec<String>)> = Vec::new();
    let mut typed_all = Vec::new();
    let mut edit = scene.clone().edit();
    for (label, key, value) in sets {
        let typed = || typed(label, key, value);
        let targets = edit.scene().targets(key).with_context(typed)?;
        for (first, earlier) in &seen {
            let repeated =
                targets.iter().find_map(|t| earlier.iter().find(|e| overlap(e, t)).map(|e| (t, e)));
            if let Some((entry, before)) = repeated {
                // The whole of the two, which both set.
                let entry = if entry.len() <= before.len() { entry } else { before };
                return Err(CliError::RepeatedKey {
                    first: (*first).to_owned(),
                    second: label.to_owned(),
                    entry: entry.clone(),
                }
                .into());
            }
        }
        edit.set(key, value).with_context(typed)?;
        seen.push((label, targets));
        typed_all.push(typed());
    }
    // Overrides that are only valid together (a body moved with the anchor that holds it)
    // are taken together; a scene they leave invalid is refused at the override after which
    // it became so.
    let since = edit.invalid_since();
    *scene = edit.finish().map_err(|e| {
        let e = anyhow::Error::from(e);
        match since {
            Some(i) => e.context(typed_all[i].clone()),
            None => e,
        }
    })?;
    Ok(())
}

/// The scene of the options: the scene file or the model's report scene, with overrides.
///
/// # Errors
/// As [`base_scene`]; a key given twice, unknown keys or bad values.
pub fn scene(options: &SimulateOptions) -> Result<Scene> {
    let mut scene = base_scene(options.model.as_deref(), options.scene.as_deref())?;
    let (dt, tf) = (options.dt.map(|v| v.to_string()), options.tf.map(|v| v.to_string()));
    let options_sets =
        [("--dt", "dt", &dt), ("--tf", "t_end", &tf), ("--solver", "solver", &options.solver)];
    let given: Vec<(String, String)> =
        options.sets.iter().map(|s| parse_set(s)).collect::<Result<_>>()?;
    let sets = options_sets
        .into_iter()
        .filter_map(|(label, key, value)| value.as_deref().map(|v| (label, key, v)))
        .chain(given.iter().map(|(k, v)| (k.as_str(), k.as_str(), v.as_str())));
    apply_labelled(&mut scene, sets)?;
    Ok(scene)
}

/// Checks that thinning the record keeps its rows evenly spaced up to t_end: `record_every`
/// must divide the planned steps unless a stop rule may end the run earlier. Whatever the
/// thinning, the recorder keeps a run's last step ([`moreau_stepper::Observer::finish`]), so
/// that a run its stop rule ends still has its last row at the stop step.
///
/// # Errors
/// When it does not divide them.
pub fn check_record_every(scene: &Scene, steps: u64) -> Result<()> {
    let every = scene.record_every.max(1) as u64;
    if scene.stop_at.is_none() && !steps.is_multiple_of(every) {
        bail!(
            "record_every = {every} does not divide the {steps} steps: the rows would not be \
             evenly spaced up to t_end = {}",
            scene.t_end
        );
    }
    Ok(())
}

/// The time of the row of step `step` that ends at the stepper's time `t`: t_end after the
/// last planned step (step index `planned − 1`), whose n Δt differs from t_end by round-off
/// only, since t_end is a whole number of steps; `t` otherwise.
fn row_time(t: f64, step: u64, planned: u64, scene: &Scene) -> f64 {
    if step + 1 == planned && (t - scene.t_end).abs() <= 1e-6 * scene.dt { scene.t_end } else { t }
}

/// Sets the last row's time to t_end after the last planned step ([`row_time`]).
fn end_at_t_end(record: &mut Record, step: u64, planned: u64, scene: &Scene) {
    if let Some(t) = record.t.last_mut() {
        *t = row_time(*t, step, planned, scene);
    }
}

/// Runs a scene under the guards (see [`guard::run_guarded`]) and keeps its record in memory.
///
/// # Errors
/// The errors of [`guard::run_guarded`] and [`check_record_every`].
pub fn run_scene(scene: &Scene, max_steps: u64) -> Result<Simulation> {
    let start = Instant::now();
    let model = scene.build()?;
    let planned = guard::plan_steps(scene, max_steps)?;
    check_record_every(scene, planned)?;
    let mut recorder = Recorder::every(scene.record_every);
    let (q0, u0) = model.initial_state();
    recorder.push_initial(&model, scene.t_start, &q0, &u0);
    recorder.record.reserve((planned / scene.record_every.max(1) as u64).min(1 << 20) as usize);
    let run = guard::run_guarded(scene, &model, max_steps, &mut recorder)?;
    end_at_t_end(&mut recorder.record, run.summary.steps.saturating_sub(1), planned, scene);
    Ok(Simulation {
        record: std::mem::take(&mut recorder.record),
        wall_seconds: start.elapsed().as_secs_f64(),
        steps: run.summary.steps,
        lcp_solves: run.summary.lcp_solves,
        inexact_steps: run.summary.inexact_steps,
        inexact_residual: run.summary.inexact_residual,
        impulses: recorder.last_impulses().cloned().or_else(|| scene.impulses.clone()),
        model,
    })
}

/// Runs the options' scene under the guards and keeps the record in memory.
///
/// # Errors
/// As [`scene`] and [`run_scene`].
pub fn run(options: &SimulateOptions) -> Result<RunResult> {
    let scene = scene(options)?;
    let sim = run_scene(&scene, options.step_limit())?;
    let spec = RunSpec { name: "simulate".into(), kind: scene.kind(), sets: Vec::new() };
    let info = run_info(&spec.name, &scene, &sim);
    Ok(RunResult { spec, scene, sim, info })
}

/// The CSV header of a record of `model`: `t`, the coordinate and velocity names, then
/// each contact's impulses and whether it was active in the row.
///
/// A report model's contacts are numbered (`PN1, PT1, PN2, PT2, ...`, then `A1, A2, ...`); a
/// declared mechanism's columns are named after its bodies and contacts: `<body>.x`,
/// `<body>.y`, `<body>.theta` for each dynamic body in declaration order, then `<body>.vx`,
/// `<body>.vy`, `<body>.omega`, then `<contact>.PN, <contact>.PT` for each contact and
/// `<contact>.active` for each contact, in the order of the contact list. Last come the
/// joints' impulses Λ_B summed over the row's steps, one per bilateral constraint: named
/// after the joints for a declared mechanism (`<joint>.Lx`, `<joint>.Ly`, `<joint>.Ltheta`,
/// `<joint>.Ln`, see `Multibody::bilateral_names`), `L1, L2, ...` otherwise. The last
/// four columns are the energies at the row (J, or the scene's units of energy): `T`, the
/// kinetic energy ½ uᵀ M u; `V`, the potential energy of gravity and springs; `dissipated`,
/// the energy the impulses of contacts and joints and the dampers removed since row 0
/// (`Record::cumulative_dissipation`); and `projected`, the energy the position projection's
/// moves of q added since row 0 (`Record::cumulative_projection`): under gravity and
/// dampers, T + V + dissipated − projected stays at its row-0 value to round-off.
pub fn header(model: &AnyModel) -> Vec<String> {
    let mut h = vec!["t".to_owned()];
    h.extend(model.coordinate_names().iter().map(str::to_owned));
    h.extend(model.velocity_names().iter().map(str::to_owned));
    if model.kind() == ModelKind::Declared {
        let names = model.contact_names();
        for c in &names {
            h.push(format!("{c}.PN"));
            h.push(format!("{c}.PT"));
        }
        h.extend(names.iter().map(|c| format!("{c}.active")));
    } else {
        let n = model.contact_names().len();
        for i in 1..=n {
            h.push(format!("PN{i}"));
            h.push(format!("PT{i}"));
        }
        h.extend((1..=n).map(|i| format!("A{i}")));
    }
    // The joints' impulses, summed over the row's steps like the contacts'.
    match model {
        AnyModel::Declared(m) => h.extend(m.bilateral_names()),
        _ => h.extend((1..=model.num_bilaterals()).map(|i| format!("L{i}"))),
    }
    h.extend(["T", "V", "dissipated", "projected"].map(str::to_owned));
    h
}

/// Writes rows `rows` of a record as CSV lines (numbers as [`number`] writes them).
fn write_rows(w: &mut impl Write, r: &Record, rows: std::ops::Range<usize>) -> Result<()> {
    for k in rows {
        number::write(w, r.t[k])?;
        let (q, u) = (r.q.get(k).unwrap_or(&[]), r.u.get(k).unwrap_or(&[]));
        for &x in q.iter().chain(u) {
            number::write_next(w, x)?;
        }
        let (p_n, p_t) = (r.p_n.get(k).unwrap_or(&[]), r.p_t.get(k).unwrap_or(&[]));
        for (&a, &b) in p_n.iter().zip(p_t) {
            number::write_next(w, a)?;
            number::write_next(w, b)?;
        }
        for &a in r.active.get(k).unwrap_or(&[]) {
            write!(w, ",{}", u8::from(a))?;
        }
        for &x in r.joint_impulses.get(k).unwrap_or(&[]) {
            number::write_next(w, x)?;
        }
        let projected = r.cumulative_projection.get(k).copied().unwrap_or(0.0);
        for x in [r.kinetic[k], r.potential[k], r.cumulative_dissipation[k], projected] {
            number::write_next(w, x)?;
        }
        writeln!(w)?;
    }
    Ok(())
}

/// Writes the record of `run` as CSV.
///
/// # Errors
/// When the file cannot be written.
pub fn write_record(run: &RunResult, path: &Path) -> Result<()> {
    let file = File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut w = BufWriter::new(file);
    writeln!(w, "{}", csv_record(header(run.model()))?)?;
    write_rows(&mut w, run.record(), 0..run.record().len())?;
    w.flush()?;
    Ok(())
}

/// Rows kept in memory before they are written.
const BATCH: usize = 4096;

/// An observer that thins steps with the stepper's [`Recorder`] and writes its rows to a
/// CSV file in batches, so that memory stays bounded whatever the length of the run.
struct Streamer<W: Write> {
    recorder: Recorder,
    planned: u64,
    scene: Scene,
    out: W,
    rows: u64,
    /// The contacts file, when one was asked for.
    contacts: Option<ContactLog<W>>,
    error: Option<anyhow::Error>,
    bar: Option<indicatif::ProgressBar>,
    /// The last step's end state, at t_end exactly after the last planned step.
    end: Option<EndState>,
}

/// A run's end state: the last step's t, q and u, and its impulses.
struct EndState {
    t: f64,
    q: Vec<f64>,
    u: Vec<f64>,
    impulses: Impulses,
}

impl<W: Write> Streamer<W> {
    fn drain(&mut self) -> Result<()> {
        let r = &self.recorder.record;
        write_rows(&mut self.out, r, 0..r.len())?;
        self.rows += r.len() as u64;
        // The recorder takes the widths of its tables from its next row again.
        self.recorder.record = Record::default();
        Ok(())
    }
}

impl<W: Write> Observer<AnyModel> for Streamer<W> {
    fn observe(&mut self, model: &AnyModel, report: &StepReport<'_>) -> ControlFlow<()> {
        let _ = self.recorder.observe(model, report);
        end_at_t_end(&mut self.recorder.record, report.step, self.planned, &self.scene);
        if let (Some(log), AnyModel::Declared(m)) = (&mut self.contacts, model) {
            let t = row_time(report.t, report.step, self.planned, &self.scene);
            if let Err(e) = log.observe(m, report, t) {
                self.error = Some(e);
                return ControlFlow::Break(());
            }
        }
        if let Some(bar) = &self.bar
            && report.step.is_multiple_of(4096)
        {
            bar.set_position(report.step);
        }
        if self.recorder.record.len() >= BATCH
            && let Err(e) = self.drain()
        {
            self.error = Some(e);
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    }

    /// The run's last step: its row when the thinning skipped it, and its contacts.
    fn finish(&mut self, model: &AnyModel, last: &StepReport<'_>) {
        let t = row_time(last.t, last.step, self.planned, &self.scene);
        let (q, u, impulses) = (last.q.to_vec(), last.u.to_vec(), Impulses::of(last));
        self.end = Some(EndState { t, q, u, impulses });
        self.recorder.finish(model, last);
        end_at_t_end(&mut self.recorder.record, last.step, self.planned, &self.scene);
        if let (Some(log), AnyModel::Declared(m)) = (&mut self.contacts, model) {
            let t = row_time(last.t, last.step, self.planned, &self.scene);
            if let Err(e) = log.finish_step(m, last, t)
                && self.error.is_none()
            {
                self.error = Some(e);
            }
        }
    }
}

/// What [`run_to_csv`] did.
#[derive(Clone, Debug)]
pub struct Simulated {
    /// The scene that was run.
    pub scene: Scene,
    /// Steps taken.
    pub steps: u64,
    /// Steps whose LCP needed a solver.
    pub lcp_solves: u64,
    /// Steps taken with an island above the solvers' tolerance (the scene's
    /// `inexact_residual`), and the largest LCP residual among them.
    pub inexact_steps: u64,
    /// See `inexact_steps`; 0 when there were none.
    pub inexact_residual: f64,
    /// Rows written (row 0 is the initial state).
    pub rows: u64,
    /// Rows written to the contacts file, when one was asked for.
    pub contact_rows: Option<u64>,
    /// Wall-clock time (s).
    pub wall_seconds: f64,
    /// Warnings about the initial gaps (see [`guard::gap_warnings`]).
    pub warnings: Vec<String>,
}

/// Runs the options' scene under the guards and streams its record to `out` as CSV.
///
/// The outputs are checked first ([`output`]): neither `out` nor the contacts file may be the
/// scene file or each other, nor an existing file that is not a regular file; a symbolic link
/// is written through to its file; each is locked (`<out>.lock`) while the run writes it. The
/// scene and its step plan are checked before the lock is taken (a refused scene leaves no
/// file), and `<out>.partial` is created before the first step; the rows go there in batches of a few thousand, and the file is renamed to `out`
/// once the run has ended at t_end (or its stop rule). A run that fails or diverges leaves
/// `<out>.partial` for inspection and no `out` (an `out` of an earlier run is removed, and so
/// is the contacts file's); one that stops on a step problem that its
/// solver leaves unsolved writes that problem to `<out>.failed.dat` as well
/// ([`failed::with_failed_problem`]). `warn` receives the warnings about the
/// initial gaps before the run. With [`SimulateOptions::contacts`], the located contacts of
/// the recorded steps go to that file in the same way ([`crate::contacts`]).
///
/// # Errors
/// As [`scene`] and [`guard::run_guarded`]; an unwritable output;
/// [`CliError::ContactsOfReportModel`] for a contacts file of a report model;
/// [`CliError::Output`] for an output that is the scene file, a contacts file that is the
/// output itself, or an output that is not a regular file; [`CliError::Locked`] for an output
/// that another run holds.
pub fn run_to_csv(
    options: &SimulateOptions,
    out: &Path,
    warn: &mut dyn FnMut(&str),
) -> Result<Simulated> {
    let start = Instant::now();
    let out_file = Output::new(out)?;
    let contacts_file = options.contacts.as_deref().map(Output::new).transpose()?;
    let end_file = options.end_scene.as_deref().map(Output::new).transpose()?;
    let inputs: Vec<&Path> = options.scene.iter().map(PathBuf::as_path).collect();
    let outputs: Vec<&Output> = [Some(&out_file), contacts_file.as_ref(), end_file.as_ref()]
        .into_iter()
        .flatten()
        .collect();
    output::check_distinct(&inputs, &outputs)?;
    // The scene is checked before any file is touched, its lock included.
    let scene = scene(options)?;
    let model = scene.build()?;
    let planned = guard::plan_steps(&scene, options.step_limit())?;
    check_record_every(&scene, planned)?;
    let _locks =
        outputs.iter().map(|o| OutputLock::acquire(o)).collect::<Result<Vec<_>, CliError>>()?;
    // The contacts file's path and its `.partial`, and its log.
    let (contacts_files, log) = match (&contacts_file, &model) {
        (None, _) => (None, None),
        (Some(file), AnyModel::Declared(m)) => {
            let (partial, w) = file.create_partial()?;
            let margin = m.gap_tolerance();
            let stops_early = scene.stop_at.is_some();
            let (q0, u0) = m.initial_state();
            let log = ContactLog::new(
                m,
                (q0, u0, scene.t_start),
                scene.record_every,
                (scene.dt, margin),
                stops_early,
                w,
            )?;
            (Some((file, partial)), Some(log))
        }
        (Some(_), other) => {
            return Err(
                CliError::ContactsOfReportModel { model: other.kind().name().into() }.into()
            );
        }
    };
    let (partial, mut out_w) = out_file.create_partial()?;
    // The problem an earlier run of the same output stopped on is not this run's.
    let failed_path = failed_problem_path(out_file.target());
    output::remove_stale(&failed_path)?;
    let warnings = guard::gap_warnings(&model, scene.t_start, scene.projection);
    for w in &warnings {
        warn(w);
    }
    writeln!(out_w, "{}", csv_record(header(&model))?)?;
    let mut recorder = Recorder::every(scene.record_every);
    let (q0, u0) = model.initial_state();
    recorder.push_initial(&model, scene.t_start, &q0, &u0);
    let bar = (std::io::stderr().is_terminal() && planned >= 100_000).then(|| {
        let bar = indicatif::ProgressBar::new(planned);
        if let Ok(style) = indicatif::ProgressStyle::with_template(
            "{msg} [{bar:40}] {pos}/{len} steps ({elapsed}, eta {eta})",
        ) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_message(format!("simulate {}", scene.kind()));
        bar
    });
    let mut streamer = Streamer {
        recorder,
        planned,
        scene: scene.clone(),
        out: out_w,
        rows: 0,
        contacts: log,
        error: None,
        bar,
        end: None,
    };
    let run = guard::run_guarded(&scene, &model, options.step_limit(), &mut streamer);
    if let Some(bar) = &streamer.bar {
        bar.finish_and_clear();
    }
    if let Some(e) = streamer.error.take() {
        return Err(e.context(format!("writing {}", partial.display())));
    }
    // The rows recorded so far reach the file whether the run succeeded or not.
    let written = streamer
        .drain()
        .and_then(|()| Ok(streamer.out.flush()?))
        .with_context(|| format!("writing {}", partial.display()));
    // A failed run leaves its rows in the partial files only: an `out` (or contacts file) of
    // an earlier run that succeeded does not describe this one. A removal that fails is told
    // with the run's error rather than in its place.
    let remove_former = || {
        let contacts = contacts_files.as_ref().map(|(file, _)| file.target());
        [Some(out_file.target()), contacts]
            .into_iter()
            .flatten()
            .filter_map(|path| output::remove_stale(path).err())
            .map(|e| format!("; {e}"))
            .collect::<String>()
    };
    let run = match (run, written) {
        (Ok(run), Ok(())) => run,
        (Ok(_), Err(e)) => return Err(e),
        (Err(e), Ok(())) => {
            let note = remove_former();
            return Err(failed::with_failed_problem(e, &failed_path)
                .context(format!("the rows so far are in {}{note}", partial.display())));
        }
        (Err(e), Err(w)) => {
            let note = remove_former();
            return Err(failed::with_failed_problem(e, &failed_path).context(format!(
                "the rows so far could not all be written to {} ({w:#}){note}",
                partial.display()
            )));
        }
    };
    let contact_rows = streamer.contacts.as_ref().map(|log| log.rows);
    if let (Some(log), Some((file, partial))) = (streamer.contacts.take(), &contacts_files) {
        file.publish_written(partial, log.finish()?)?;
    }
    if let Some(file) = &end_file {
        write_end_scene(&scene, streamer.end.take(), &model, file)?;
    }
    out_file.publish_written(&partial, streamer.out)?;
    Ok(Simulated {
        scene,
        steps: run.summary.steps,
        lcp_solves: run.summary.lcp_solves,
        inexact_steps: run.summary.inexact_steps,
        inexact_residual: run.summary.inexact_residual,
        rows: streamer.rows,
        contact_rows,
        wall_seconds: start.elapsed().as_secs_f64(),
        warnings,
    })
}

/// Writes the scene continued from the run's end state `end` (its last step's t, q, u and
/// impulses; the initial state and the scene's impulses for a run of no steps) to `file`,
/// whole or not at all.
///
/// # Errors
/// The errors of [`Scene::continued`]; a scene that TOML cannot hold; an unwritable file.
fn write_end_scene(
    scene: &Scene,
    end: Option<EndState>,
    model: &AnyModel,
    file: &Output,
) -> Result<()> {
    let (t, q, u, impulses) = match end {
        Some(EndState { t, q, u, impulses }) => (t, q, u, Some(impulses)),
        None => {
            let (q0, u0) = model.initial_state();
            (scene.t_start, q0, u0, scene.impulses.clone())
        }
    };
    let next = scene.continued(t, &q, &u, impulses.filter(|i| !i.is_empty()))?;
    let text = next.to_toml_string()?;
    let (partial, mut w) = file.create_partial()?;
    writeln!(
        w,
        "# The end state of a run at t = {t} s, continued: run it for as long again, or \
         change t_end. The impulses of its last step, by contact, start it warm.\n\
         {text}"
    )
    .with_context(|| format!("writing {}", partial.display()))?;
    file.publish_written(&partial, w)?;
    Ok(())
}
