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

use crate::bodies::{
    AutoContacts, BodySpec, ContactSet, ContactSpec, FillSpec, ForceSpec, JointSpec, SystemSpec,
};
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
/// A scene file has one of two forms. For a model of the report, the scene's own keys come
/// first and the model's parameters form the table `[params]`, whose key `model` names the
/// model (`ball`, `woodpecker`, `slider-crank`, `slider-crank-ideal`, `cam`, `painleve`);
/// nested tables such as `[params.init]` hold the initial state:
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
///
/// A declared mechanism ([`crate::bodies::SystemSpec`]) has no `[params]`: the scene's keys
/// are followed by `gravity`, `contact_set` (`"fixed"` by default, or `"detected"`: see
/// [`crate::bodies::ContactSet`]) and the arrays of tables `[[bodies]]`, `[[fill]]`
/// (generated bodies, [`crate::bodies::FillSpec`]), `[[joints]]`, `[[forces]]`,
/// `[[contacts]]` and the table `[contacts_auto]`; `projection` defaults to `true` there:
///
/// ```toml
/// dt = 0.001
/// t_end = 2.0
/// gravity = [0.0, -9.81]   # m/s²
///
/// [[bodies]]
/// name = "rod"
/// type = "dynamic"
/// mass = 1.0               # kg
/// inertia = 0.0833333      # kg m², about the origin (here the centre of mass)
/// position = [0.5, 0.0]    # m
///
/// [[joints]]
/// type = "revolute"
/// name = "hinge"
/// body_a = "ground"
/// anchor_a = [0.0, 0.0]
/// body_b = "rod"
/// anchor_b = [-0.5, 0.0]
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Time step Δt (s), finite and > 0.
    pub dt: f64,
    /// End time (s); with a [`StopRule`] it is an upper bound on the run's length.
    pub t_end: f64,
    /// Keep one step in `record_every` in the [`Record`] (>= 1); default 1.
    pub record_every: usize,
    /// The LCP solver; [`SolverChoice::Auto`] when omitted.
    pub solver: SolverChoice,
    /// An optional stop rule on a coordinate; none when omitted.
    pub stop_at: Option<StopRule>,
    /// Project the positions back onto the joints and onto g_N >= 0 after each step
    /// (`StepperOptions::projection`); default `false` for the report's models, `true` for
    /// declared mechanisms.
    pub projection: bool,
    /// The model and its parameters (the table `[params]`, or the declaration).
    pub params: ModelParams,
}

fn yes() -> bool {
    true
}

fn is_false(b: &bool) -> bool {
    !*b
}

fn is_true(b: &bool) -> bool {
    *b
}

/// A report model's scene as written in TOML.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct BuiltinFile {
    dt: f64,
    t_end: f64,
    #[serde(default = "one")]
    record_every: usize,
    #[serde(default)]
    solver: SolverChoice,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    stop_at: Option<StopRule>,
    #[serde(default, skip_serializing_if = "is_false")]
    projection: bool,
    params: ModelParams,
}

/// A declared mechanism's scene as written in TOML: the scene's keys and the declaration's.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct DeclaredFile {
    dt: f64,
    t_end: f64,
    #[serde(default = "one")]
    record_every: usize,
    #[serde(default)]
    solver: SolverChoice,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    stop_at: Option<StopRule>,
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    projection: bool,
    gravity: [f64; 2],
    bodies: Vec<BodySpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    joints: Vec<JointSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    forces: Vec<ForceSpec>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    contacts: Vec<ContactSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    contacts_auto: Option<AutoContacts>,
    #[serde(default, skip_serializing_if = "ContactSet::is_fixed")]
    contact_set: ContactSet,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    fill: Vec<FillSpec>,
}

impl From<BuiltinFile> for Scene {
    fn from(f: BuiltinFile) -> Self {
        Scene {
            dt: f.dt,
            t_end: f.t_end,
            record_every: f.record_every,
            solver: f.solver,
            stop_at: f.stop_at,
            projection: f.projection,
            params: f.params,
        }
    }
}

impl From<DeclaredFile> for Scene {
    fn from(f: DeclaredFile) -> Self {
        let spec = SystemSpec {
            gravity: f.gravity,
            bodies: f.bodies,
            joints: f.joints,
            forces: f.forces,
            contacts: f.contacts,
            contacts_auto: f.contacts_auto,
            contact_set: f.contact_set,
            fill: f.fill,
        };
        Scene {
            dt: f.dt,
            t_end: f.t_end,
            record_every: f.record_every,
            solver: f.solver,
            stop_at: f.stop_at,
            projection: f.projection,
            params: ModelParams::Declared(Box::new(spec)),
        }
    }
}

impl Serialize for Scene {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match &self.params {
            ModelParams::Declared(spec) => DeclaredFile {
                dt: self.dt,
                t_end: self.t_end,
                record_every: self.record_every,
                solver: self.solver,
                stop_at: self.stop_at.clone(),
                projection: self.projection,
                gravity: spec.gravity,
                bodies: spec.bodies.clone(),
                joints: spec.joints.clone(),
                forces: spec.forces.clone(),
                contacts: spec.contacts.clone(),
                contacts_auto: spec.contacts_auto.clone(),
                contact_set: spec.contact_set,
                fill: spec.fill.clone(),
            }
            .serialize(serializer),
            params => BuiltinFile {
                dt: self.dt,
                t_end: self.t_end,
                record_every: self.record_every,
                solver: self.solver,
                stop_at: self.stop_at.clone(),
                projection: self.projection,
                params: params.clone(),
            }
            .serialize(serializer),
        }
    }
}

impl<'de> Deserialize<'de> for Scene {
    /// Reads either form: with a `params` table the report model's, otherwise the declared.
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let value = toml::Value::deserialize(deserializer)?;
        if value.get("params").is_some() {
            BuiltinFile::deserialize(value).map(Scene::from).map_err(D::Error::custom)
        } else {
            DeclaredFile::deserialize(value).map(Scene::from).map_err(D::Error::custom)
        }
    }
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
            ModelKind::Declared => (1e-3, 2.0),
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
            projection: kind == ModelKind::Declared,
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
        let table: toml::Table = toml::from_str(text).map_err(|e| parse_error(text, &e))?;
        // Each form is read from the text itself, so that the reader's errors keep their
        // positions in the file.
        let scene: Scene = if table.contains_key("params") {
            toml::from_str::<BuiltinFile>(text).map_err(|e| parse_error(text, &e))?.into()
        } else {
            toml::from_str::<DeclaredFile>(text)
                .map_err(|e| declared_parse_error(text, &table, &e))?
                .into()
        };
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
        let model = self.params.build()?;
        if let Some(stop) = &self.stop_at {
            finite("stop_at.value", stop.value)?;
            let names = model.coordinate_names();
            if names.position(&stop.coordinate).is_none() {
                return Err(ModelError::BadValue {
                    key: "stop_at.coordinate".to_owned(),
                    value: stop.coordinate.clone(),
                    reason: format!(
                        "not a coordinate of {}; accepted: {}",
                        self.kind(),
                        names.to_vec().join(", ")
                    ),
                });
            }
        }
        Ok(())
    }

    /// Validates the parameters and builds the model.
    ///
    /// # Errors
    /// The model's [`ModelError::InvalidParameter`] or [`ModelError::Law`].
    pub fn build(&self) -> Result<AnyModel, ModelError> {
        self.params.build()
    }

    /// The stepper's options: Δt, the solver and the projection; a declared mechanism stepped
    /// with the projection gets its projection tolerance
    /// ([`crate::bodies::Multibody::projection_tolerance`]), which keeps resting contacts
    /// closed.
    pub fn stepper_options(&self) -> StepperOptions {
        let options =
            StepperOptions::new(self.dt).with_solver(self.solver).with_projection(self.projection);
        match &self.params {
            ModelParams::Declared(spec) if self.projection => match spec.build() {
                Ok(m) => options.with_projection_tolerance(m.projection_tolerance()),
                // The build's error surfaces where the scene is built.
                Err(_) => options,
            },
            _ => options,
        }
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
                let index =
                    stepper.mechanism().coordinate_names().position(&stop.coordinate).ok_or_else(
                        || ModelError::BadValue {
                            key: "stop_at.coordinate".to_owned(),
                            value: stop.coordinate.clone(),
                            reason: "not a coordinate of the model".to_owned(),
                        },
                    )?;
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
        if !targets.is_empty() && !key.is_empty() {
            return Ok(targets.into_iter().cloned().collect());
        }
        // A path into an array (`bodies.block.position.1`) or to an optional field that the
        // scene leaves at its default (`bodies.block.angle`) is not among the leaves; it is
        // accepted when everything up to its last part exists.
        if self.kind() == ModelKind::Declared
            && let Ok(mut doc) = toml::Value::try_from(self)
            && let (parent, last) = key.rsplit_once('.').unwrap_or(("", key))
            && let Some(container) = leaf_mut(&mut doc, parent)
            && (container.is_table() || (container.is_array() && last.parse::<usize>().is_ok()))
        {
            return Ok(vec![key.to_owned()]);
        }
        Err(ModelError::UnknownKey { key: key.to_owned(), accepted: self.keys() })
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
            match leaf_mut(&mut doc, path) {
                Some(slot) => *slot = parse_like(slot, value).map_err(bad)?,
                None => {
                    let (parent, last) = path.rsplit_once('.').unwrap_or(("", path));
                    let table = leaf_mut(&mut doc, parent)
                        .and_then(toml::Value::as_table_mut)
                        .ok_or_else(|| bad(format!("no value at `{path}`")))?;
                    table.insert(last.to_owned(), parse_any(value));
                }
            }
        }
        let scene: Scene =
            doc.try_into().map_err(|e: toml::de::Error| bad(e.message().to_owned()))?;
        scene.validate().map_err(|e| bad(e.to_string()))?;
        *self = scene;
        Ok(())
    }
}

/// Calls `f` with the dotted path of every value under `value` that is neither a table nor
/// an array of tables; the elements of an array of tables are named by their `name` field,
/// or by their index when they have none.
fn collect_leaves(value: &toml::Value, prefix: &str, f: &mut dyn FnMut(&str)) {
    let join = |k: &str| if prefix.is_empty() { k.to_owned() } else { format!("{prefix}.{k}") };
    match value {
        toml::Value::Table(table) => {
            for (k, v) in table {
                collect_leaves(v, &join(k), f);
            }
        }
        toml::Value::Array(items) if !items.is_empty() && items.iter().all(|v| v.is_table()) => {
            for (i, item) in items.iter().enumerate() {
                let name = item.get("name").and_then(toml::Value::as_str);
                collect_leaves(item, &join(&name.map_or_else(|| i.to_string(), str::to_owned)), f);
            }
        }
        _ => f(prefix),
    }
}

/// The value at a dotted path: table keys, and for arrays an index or (arrays of tables) the
/// `name` of an element.
fn leaf_mut<'a>(doc: &'a mut toml::Value, path: &str) -> Option<&'a mut toml::Value> {
    if path.is_empty() {
        return Some(doc);
    }
    path.split('.').try_fold(doc, |v, k| match v {
        toml::Value::Table(t) => t.get_mut(k),
        toml::Value::Array(items) => match k.parse::<usize>() {
            Ok(i) => items.get_mut(i),
            Err(_) => items.iter_mut().find(|e| e.get("name").and_then(|n| n.as_str()) == Some(k)),
        },
        _ => None,
    })
}

/// Parses a value given for a key the scene does not write (an optional field at its
/// default): a TOML value (`2`, `[0, 1]`, `true`, `{ kind = "linear", ... }`), or else the text
/// as a string.
fn parse_any(text: &str) -> toml::Value {
    let text = text.trim();
    toml::from_str::<toml::Table>(&format!("v = {text}"))
        .ok()
        .and_then(|mut t| t.remove("v"))
        .unwrap_or_else(|| toml::Value::String(text.to_owned()))
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
        toml::Value::Array(_) | toml::Value::Table(_) => {
            let value = parse_any(text);
            if value.type_str() == like.type_str() {
                Ok(value)
            } else {
                Err(format!("expected {} such as [0.0, 1.0], got `{text}`", like.type_str()))
            }
        }
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
        ModelKind::Declared => None,
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

/// Turns the TOML reader's error on a declared scene into a [`ModelError::Parse`] that names
/// the field by its `--set` path: each element of the arrays of tables is read again alone to
/// find the one at fault (the reader's positions name the array, not the element, and the
/// tagged tables of joints and forces lose them).
fn declared_parse_error(text: &str, table: &toml::Table, error: &toml::de::Error) -> ModelError {
    fn first_error<T: serde::de::DeserializeOwned>(
        table: &toml::Table,
        key: &str,
    ) -> Option<(String, String)> {
        let items = table.get(key)?.as_array()?;
        items.iter().enumerate().find_map(|(i, item)| {
            let e = T::deserialize(item.clone()).err()?;
            let name = item.get("name").and_then(toml::Value::as_str);
            let element = name.map_or_else(|| i.to_string(), str::to_owned);
            let message = e.message().to_owned();
            let field = match unknown_field_name(&message) {
                Some(f) => format!("{key}.{element}.{f}"),
                None => format!("{key}.{element}"),
            };
            Some((field, message))
        })
    }
    let found = first_error::<BodySpec>(table, "bodies")
        .or_else(|| first_error::<JointSpec>(table, "joints"))
        .or_else(|| first_error::<ForceSpec>(table, "forces"))
        .or_else(|| first_error::<ContactSpec>(table, "contacts"))
        .or_else(|| first_error::<FillSpec>(table, "fill"));
    match found {
        Some((field, message)) => ModelError::Parse {
            path: None,
            field: Some(field),
            message: format!("{}\n{message}", error.message()),
        },
        // An error outside the arrays of tables keeps the reader's position.
        None => ModelError::Parse {
            path: None,
            field: error.span().and_then(|span| locate_key(text, span.start)),
            message: error.to_string(),
        },
    }
}
