//! Scenes: a model's parameters, the step size, the stop rule and the solver, read from and
//! written to TOML, and run with the time-stepper.

use std::ops::ControlFlow;
use std::path::Path;
use std::time::Instant;

use moreau_stepper::{
    Observer, Record, Recorder, RunSummary, SolverChoice, StepReport, Stepper, StepperOptions,
    UnknownSolver,
};
use serde::{Deserialize, Serialize};

use crate::params::{finite, non_negative, positive, relation};
use crate::{
    AnyModel, BallParams, CamParams, ModelError, ModelKind, ModelParams, PainleveParams,
    SliderCrankIdealParams, SliderCrankParams, WoodpeckerParams,
};

fn one() -> usize {
    1
}

/// Stop a run once a coordinate reaches a value (for example the slider-crank's θ1 = 4π).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StopRule {
    /// Name of the coordinate, one of the model's coordinate names (`th1`, `y`, ...).
    pub coordinate: String,
    /// The value whose crossing ends the run; the step that reaches or passes it is the last.
    pub value: f64,
}

/// A simulation set-up: a model with its parameters, the step size, how long to run and
/// which LCP solver to use.
///
/// In TOML the scene's own keys come first and the model's parameters form the table
/// `[params]`, whose key `model` names the model (`ball`, `woodpecker`, `slider-crank`,
/// `slider-crank-ideal`, `cam`, `painleve`); nested tables such as `[params.init]` hold the
/// initial state:
///
/// ```toml
/// dt = 0.001          # time step Δt (s)
/// t_end = 10.0        # end time (s)
/// record_every = 1    # keep one step in n
/// solver = { kind = "auto" }
///
/// [params]
/// model = "ball"
/// m = 1.0
/// r = 0.1
/// g = 9.81
/// eps_n = 0.9
///
/// [params.init]
/// y0 = 1.0
/// v0 = 0.0
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Time step Δt (s), finite and > 0.
    pub dt: f64,
    /// End time (s); with a [`StopRule`] it is an upper bound on the run's length.
    pub t_end: f64,
    /// Keep one step in `record_every` in the [`Record`] (>= 1); default 1.
    #[serde(default = "one")]
    pub record_every: usize,
    /// The LCP solver; [`SolverChoice::Auto`] when omitted.
    #[serde(default)]
    pub solver: SolverChoice,
    /// An optional stop rule on a coordinate; none when omitted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop_at: Option<StopRule>,
    /// The model and its parameters (the table `[params]`).
    pub params: ModelParams,
}

/// The result of [`Scene::run`].
#[derive(Clone, Debug)]
pub struct Simulation {
    /// The recorded trajectory (row 0 is the initial state).
    pub record: Record,
    /// Wall-clock time of the run, from building the stepper to the last step (s).
    pub wall_seconds: f64,
    /// Steps taken.
    pub steps: u64,
    /// Steps whose LCP needed a solver.
    pub lcp_solves: u64,
    /// The model that was run.
    pub model: AnyModel,
}

/// Stops a run when a coordinate crosses a value, after passing the step to an inner observer.
struct StopObserver<'a, O> {
    inner: &'a mut O,
    index: usize,
    value: f64,
    start_below: bool,
}

impl<O: Observer<AnyModel>> Observer<AnyModel> for StopObserver<'_, O> {
    fn observe(&mut self, mechanism: &AnyModel, report: &StepReport<'_>) -> ControlFlow<()> {
        self.inner.observe(mechanism, report)?;
        let x = report.q[self.index];
        let crossed = if self.start_below { x >= self.value } else { x <= self.value };
        if crossed { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    }
}

impl Scene {
    /// The report's scene of a model: ball Δt = 1e-3 s for 10 s; woodpecker 1e-4 s for 1 s;
    /// slider-crank (both) 1e-5 s until θ1 = 4π (at most 1 s); cam 1e-4 s for 0.15 s (three
    /// lobes); Painlevé rod (μ = 0.3) 1e-3 s until it lies flat (φ = 0, at most 1.5 s). The
    /// solver is `auto`.
    pub fn report(kind: ModelKind) -> Scene {
        let (dt, t_end) = match kind {
            ModelKind::Ball => (1e-3, 10.0),
            ModelKind::Woodpecker => (1e-4, 1.0),
            ModelKind::SliderCrank | ModelKind::SliderCrankIdeal => (1e-5, 1.0),
            ModelKind::Cam => (1e-4, 0.15),
            ModelKind::Painleve => (1e-3, 1.5),
        };
        let stop_at = match kind {
            ModelKind::SliderCrank | ModelKind::SliderCrankIdeal => {
                Some(StopRule { coordinate: "th1".to_owned(), value: 4.0 * std::f64::consts::PI })
            }
            // The model has one contact, at the end that starts low: stop when the rod lies flat.
            ModelKind::Painleve => Some(StopRule { coordinate: "phi".to_owned(), value: 0.0 }),
            _ => None,
        };
        Scene {
            dt,
            t_end,
            record_every: 1,
            solver: SolverChoice::Auto,
            stop_at,
            params: ModelParams::report(kind),
        }
    }

    /// Which model the scene runs.
    pub fn kind(&self) -> ModelKind {
        self.params.kind()
    }

    /// Reads a scene from TOML text and validates it.
    ///
    /// # Errors
    /// [`ModelError::Parse`] with the TOML reader's message and the offending field for bad
    /// syntax, an unknown field or a wrong type; [`ModelError::InvalidParameter`] naming the
    /// field for a value out of range.
    pub fn from_toml_str(text: &str) -> Result<Scene, ModelError> {
        let scene: Scene = toml::from_str(text).map_err(|e| parse_error(text, &e))?;
        scene.validate()?;
        Ok(scene)
    }

    /// Reads a scene from a TOML file and validates it.
    ///
    /// # Errors
    /// [`ModelError::Io`] when the file cannot be read, and the errors of
    /// [`Self::from_toml_str`] (with the file's path).
    pub fn from_path(path: &Path) -> Result<Scene, ModelError> {
        let text = std::fs::read_to_string(path)
            .map_err(|source| ModelError::Io { path: path.to_owned(), source })?;
        Self::from_toml_str(&text).map_err(|e| match e {
            ModelError::Parse { field, message, .. } => {
                ModelError::Parse { path: Some(path.to_owned()), field, message }
            }
            other => other,
        })
    }

    /// The scene as TOML text that [`Self::from_toml_str`] reads back to an equal scene.
    pub fn to_toml_string(&self) -> String {
        toml::to_string(self)
            .unwrap_or_else(|e| format!("# the scene cannot be written as TOML: {e}\n"))
    }

    /// Checks the scene's own fields and builds the model once.
    ///
    /// # Errors
    /// [`ModelError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<(), ModelError> {
        positive("dt", self.dt)?;
        non_negative("t_end", self.t_end)?;
        if self.record_every == 0 {
            return Err(relation("record_every", 0.0, "must be at least 1"));
        }
        if let Some(stop) = &self.stop_at {
            finite("stop_at.value", stop.value)?;
            if !self.kind().coordinate_names().contains(&stop.coordinate.as_str()) {
                return Err(ModelError::BadValue {
                    key: "stop_at.coordinate".to_owned(),
                    value: stop.coordinate.clone(),
                    reason: format!(
                        "not a coordinate of {}; accepted: {}",
                        self.kind(),
                        self.kind().coordinate_names().join(", ")
                    ),
                });
            }
        }
        self.params.build().map(|_| ())
    }

    /// Validates the parameters and builds the model.
    ///
    /// # Errors
    /// The model's [`ModelError::InvalidParameter`] or [`ModelError::Law`].
    pub fn build(&self) -> Result<AnyModel, ModelError> {
        self.params.build()
    }

    /// The stepper's options: Δt and the solver.
    pub fn stepper_options(&self) -> StepperOptions {
        StepperOptions::new(self.dt).with_solver(self.solver)
    }

    /// A stepper at the model's initial state and t = 0, for stepping by hand.
    ///
    /// # Errors
    /// The errors of [`Self::build`] and of `Stepper::new`.
    pub fn stepper(&self) -> Result<Stepper<AnyModel>, ModelError> {
        let model = self.build()?;
        let (q0, u0) = model.initial_state();
        Ok(Stepper::new(model, &q0, &u0, 0.0, self.stepper_options())?)
    }

    /// Builds the model, runs it to the stop rule (or `t_end`) and records every
    /// `record_every`-th step; row 0 of the record is the initial state.
    ///
    /// # Errors
    /// The errors of [`Self::stepper`] and every [`moreau_stepper::StepError`] of the run.
    pub fn run(&self) -> Result<Simulation, ModelError> {
        let start = Instant::now();
        let mut stepper = self.stepper()?;
        let mut recorder = Recorder::every(self.record_every);
        recorder.push_initial(stepper.mechanism(), stepper.t(), stepper.q(), stepper.u());
        // The rows up to t_end, or a million when more (a stop rule may end the run early).
        let steps = (self.t_end - stepper.t()) / stepper.options().dt;
        let rows = (steps / self.record_every.max(1) as f64).ceil().clamp(0.0, 1e6);
        recorder.record.reserve(rows as usize + 1);
        let summary = self.drive(&mut stepper, &mut recorder)?;
        Ok(Simulation {
            record: recorder.record,
            wall_seconds: start.elapsed().as_secs_f64(),
            steps: summary.steps,
            lcp_solves: summary.lcp_solves,
            model: stepper.mechanism().clone(),
        })
    }

    /// Runs like [`Self::run`] but streams every step to `observer` instead of recording.
    ///
    /// # Errors
    /// As [`Self::run`].
    pub fn run_with<O: Observer<AnyModel>>(
        &self,
        observer: &mut O,
    ) -> Result<RunSummary, ModelError> {
        let mut stepper = self.stepper()?;
        self.drive(&mut stepper, observer)
    }

    /// Runs an existing stepper to the scene's stop rule or end time.
    ///
    /// # Errors
    /// Every [`moreau_stepper::StepError`] of the run.
    pub fn drive<O: Observer<AnyModel>>(
        &self,
        stepper: &mut Stepper<AnyModel>,
        observer: &mut O,
    ) -> Result<RunSummary, ModelError> {
        let summary = match &self.stop_at {
            Some(stop) => {
                let index = self
                    .kind()
                    .coordinate_names()
                    .iter()
                    .position(|n| *n == stop.coordinate)
                    .ok_or_else(|| ModelError::BadValue {
                        key: "stop_at.coordinate".to_owned(),
                        value: stop.coordinate.clone(),
                        reason: "not a coordinate of the model".to_owned(),
                    })?;
                let start_below = stepper.q()[index] < stop.value;
                let mut wrapped =
                    StopObserver { inner: observer, index, value: stop.value, start_below };
                stepper.run_until(self.t_end, &mut wrapped)?
            }
            None => stepper.run_until(self.t_end, observer)?,
        };
        Ok(summary)
    }

    /// Every key [`Self::set`] accepts: the scene's keys (`dt`, `t_end`, `record_every`,
    /// `solver`, ...) and then the model's parameters without the `params.` prefix (`m`,
    /// `eps_n`, `init.y0`, `beak.mu`, ...).
    pub fn keys(&self) -> Vec<String> {
        self.leaves().into_iter().map(|(display, _)| display).collect()
    }

    /// Leaves of the scene's TOML tree: (display key, full path).
    fn leaves(&self) -> Vec<(String, String)> {
        let mut out = Vec::new();
        let value = match toml::Value::try_from(self) {
            Ok(v) => v,
            Err(_) => return out,
        };
        let mut scene_keys = Vec::new();
        let mut param_keys = Vec::new();
        collect_leaves(&value, "", &mut |path| {
            if path == "params.model" || path == "solver.kind" {
                return;
            }
            match path.strip_prefix("params.") {
                Some(rest) => param_keys.push((rest.to_owned(), path.to_owned())),
                None => scene_keys.push((path.to_owned(), path.to_owned())),
            }
        });
        out.push(("solver".to_owned(), "solver".to_owned()));
        out.extend(scene_keys);
        out.extend(param_keys);
        out
    }

    /// The full dotted paths of the entries that [`Self::set`] with `key` changes: `solver`
    /// for `solver`, `params.init.y0` for `init.y0` or `y0`, and on the woodpecker
    /// `params.beak.mu`, `params.lower.mu` and `params.upper.mu` for `mu`. Two keys set the
    /// same entry exactly when their targets share a path.
    ///
    /// # Errors
    /// [`ModelError::UnknownKey`] listing the accepted keys.
    pub fn targets(&self, key: &str) -> Result<Vec<String>, ModelError> {
        if key == "solver" {
            return Ok(vec!["solver".to_owned()]);
        }
        let leaves = self.leaves();
        let short = key.strip_prefix("params.").unwrap_or(key);
        let exact: Vec<&String> =
            leaves.iter().filter(|(d, full)| d == short || full == key).map(|(_, f)| f).collect();
        let targets: Vec<&String> = if exact.is_empty() {
            let suffix = format!(".{short}");
            leaves.iter().filter(|(d, _)| d.ends_with(&suffix)).map(|(_, f)| f).collect()
        } else {
            exact
        };
        if targets.is_empty() || key.is_empty() {
            return Err(ModelError::UnknownKey { key: key.to_owned(), accepted: self.keys() });
        }
        Ok(targets.into_iter().cloned().collect())
    }

    /// Sets one value, as given on a command line by `--set key=value`.
    ///
    /// `key` is one of [`Self::keys`] (with or without the `params.` prefix) or a last part
    /// of one or more of them: `mu` on the woodpecker sets `beak.mu`, `lower.mu` and
    /// `upper.mu`; `v0` sets `init.v0`. `solver` takes a solver name (`auto`, `lemke`, `pgs`,
    /// `enum`). The value is parsed as the type the key already has, and the whole scene is
    /// validated again; on any error the scene is left unchanged.
    ///
    /// # Errors
    /// [`ModelError::UnknownKey`] listing the accepted keys; [`ModelError::BadValue`] naming the
    /// key when the value does not parse or is out of range.
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), ModelError> {
        let bad = |reason: String| ModelError::BadValue {
            key: key.to_owned(),
            value: value.to_owned(),
            reason,
        };
        if key == "solver" {
            self.solver = value.trim().parse().map_err(|e: UnknownSolver| bad(e.to_string()))?;
            return Ok(());
        }
        let targets = self.targets(key)?;
        let mut doc = toml::Value::try_from(&*self).map_err(|e| bad(e.to_string()))?;
        for path in &targets {
            let slot =
                leaf_mut(&mut doc, path).ok_or_else(|| bad(format!("no value at `{path}`")))?;
            *slot = parse_like(slot, value).map_err(bad)?;
        }
        let scene: Scene =
            doc.try_into().map_err(|e: toml::de::Error| bad(e.message().to_owned()))?;
        scene.validate().map_err(|e| bad(e.to_string()))?;
        *self = scene;
        Ok(())
    }
}

/// Calls `f` with the dotted path of every non-table value under `value`.
fn collect_leaves(value: &toml::Value, prefix: &str, f: &mut dyn FnMut(&str)) {
    match value {
        toml::Value::Table(table) => {
            for (k, v) in table {
                let path = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
                collect_leaves(v, &path, f);
            }
        }
        _ => f(prefix),
    }
}

fn leaf_mut<'a>(doc: &'a mut toml::Value, path: &str) -> Option<&'a mut toml::Value> {
    path.split('.').try_fold(doc, |v, k| v.as_table_mut()?.get_mut(k))
}

/// Parses `text` as a value of the same TOML type as `like`.
fn parse_like(like: &toml::Value, text: &str) -> Result<toml::Value, String> {
    let text = text.trim();
    match like {
        toml::Value::Float(_) | toml::Value::Integer(_)
            if matches!(like, toml::Value::Float(_)) =>
        {
            text.parse::<f64>()
                .map(toml::Value::Float)
                .map_err(|_| format!("expected a number, got `{text}`"))
        }
        toml::Value::Integer(_) => text
            .parse::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| format!("expected a whole number, got `{text}`")),
        toml::Value::Boolean(_) => text
            .parse::<bool>()
            .map(toml::Value::Boolean)
            .map_err(|_| format!("expected true or false, got `{text}`")),
        toml::Value::String(_) => Ok(toml::Value::String(text.to_owned())),
        other => Err(format!("cannot set a value of type {}", other.type_str())),
    }
}

/// Turns the TOML reader's error into a [`ModelError::Parse`] that names the field.
fn parse_error(text: &str, error: &toml::de::Error) -> ModelError {
    let located = error.span().and_then(|span| locate_key(text, span.start));
    if let Some(field) = located {
        return ModelError::Parse { path: None, field: Some(field), message: error.to_string() };
    }
    // Errors inside `[params]` come from a buffered, internally tagged enum and point at the
    // table header only; read the table again as the named model's parameters to find the key.
    if let Some((field, message)) = diagnose_params(text) {
        return ModelError::Parse {
            path: None,
            field: Some(field),
            message: format!("{}\n{message}", error.message()),
        };
    }
    ModelError::Parse { path: None, field: None, message: error.to_string() }
}

/// The dotted key written on the line that holds byte `offset`, with its table header.
fn locate_key(text: &str, offset: usize) -> Option<String> {
    let offset = offset.min(text.len());
    let line_start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let line = text[line_start..].lines().next().unwrap_or("").trim();
    if line.starts_with('[') || !line.contains('=') {
        return None;
    }
    let key = unquote(line.split('=').next()?.trim());
    let header = text[..line_start].lines().rev().map(str::trim).find(|l| l.starts_with('['));
    Some(match header {
        Some(h) => format!("{}.{key}", unquote(h.trim_matches(|c| c == '[' || c == ']').trim())),
        None => key,
    })
}

fn unquote(s: &str) -> String {
    s.split('.')
        .map(|p| p.trim().trim_matches('"').trim_matches('\''))
        .collect::<Vec<_>>()
        .join(".")
}

/// Reads `[params]` again as the named model's own parameter struct, whose errors carry
/// spans; returns the offending field and the reader's message.
fn diagnose_params(text: &str) -> Option<(String, String)> {
    let doc: toml::Table = toml::from_str(text).ok()?;
    let mut params = doc.get("params")?.as_table()?.clone();
    let kind: ModelKind = params.remove("model")?.as_str()?.parse().ok()?;
    let sub = toml::to_string(&params).ok()?;
    let error = match kind {
        ModelKind::Ball => toml::from_str::<BallParams>(&sub).err(),
        ModelKind::Woodpecker => toml::from_str::<WoodpeckerParams>(&sub).err(),
        ModelKind::SliderCrank => toml::from_str::<SliderCrankParams>(&sub).err(),
        ModelKind::SliderCrankIdeal => toml::from_str::<SliderCrankIdealParams>(&sub).err(),
        ModelKind::Cam => toml::from_str::<CamParams>(&sub).err(),
        ModelKind::Painleve => toml::from_str::<PainleveParams>(&sub).err(),
    }?;
    let message = error.message().to_owned();
    let field = match error.span().and_then(|s| locate_key(&sub, s.start)) {
        Some(f) => format!("params.{f}"),
        None => match unknown_field_name(&message) {
            Some(f) => format!("params.{f}"),
            None => "params".to_owned(),
        },
    };
    Some((field, message))
}

/// The name in "unknown field `name`, expected ...".
fn unknown_field_name(message: &str) -> Option<String> {
    let rest = message.strip_prefix("unknown field `")?;
    Some(rest[..rest.find('`')?].to_owned())
}
