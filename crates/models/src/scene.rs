//! Scenes: a model's parameters, the step size, the stop rule and the solver, read from and
//! written to TOML, and run with the time-stepper.
//!
//! This module holds the scene and its runs; `file` reads and writes the two forms of a
//! scene file and names the field at fault in a reader's error, `set` lists and changes
//! single values by their dotted keys (`--set key=value`), and `tree` finds where such a key
//! lies in the scene's tree, with the fields each table takes.

mod continued;
mod file;
mod labels;
mod set;
mod tree;

pub use set::SceneEdit;

use std::ops::ControlFlow;
use std::path::Path;
use std::time::Instant;

use moreau_stepper::{
    Impulses, Mechanism, Observer, Record, Recorder, RunSummary, SolverChoice, StepReport, Stepper,
    StepperOptions,
};
use serde::{Deserialize, Serialize};

use crate::bodies::Multibody;
use crate::params::{finite, non_negative, positive, relation};
use crate::registry::dispatch;
use crate::{AnyModel, ModelError, ModelKind, ModelParams};
use file::{BuiltinFile, DeclaredFile, declared_parse_error, parse_error};

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
/// `[[contacts]]` and the table `[contacts_auto]`; `projection` defaults to `true` there, and
/// `inexact_residual` (0 by default) lets a scene of detected contacts take islands that the
/// solvers leave above their tolerance ([`Scene::inexact_residual`]). Either form may end
/// with the table `[impulses]` of a scene written at the end of a run ([`Scene::impulses`]):
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
    /// Start time t₀ (s), finite; default 0 (key `t_start`). The initial state is the state at
    /// t₀, where a run starts and the driven bodies' motions, the loads' functions of time and
    /// the motors take up; a scene written at the end of a run ([`Self::continued`]) starts
    /// at that run's end.
    pub t_start: f64,
    /// End time (s), at least `t_start`; with a [`StopRule`] it is an upper bound on the run's
    /// length.
    pub t_end: f64,
    /// Keep one step in `record_every` in the [`Record`] (>= 1), and the run's last step
    /// (at t_end or the stop rule's step) whatever the thinning; default 1.
    pub record_every: usize,
    /// The LCP solver; [`SolverChoice::Auto`] when omitted.
    pub solver: SolverChoice,
    /// An optional stop rule on a coordinate; none when omitted.
    pub stop_at: Option<StopRule>,
    /// Project the positions back onto the joints and onto g_N >= 0 after each step
    /// (`StepperOptions::projection`); default `false` for the report's models, `true` for
    /// declared mechanisms.
    pub projection: bool,
    /// The natural residual up to which an island of detected contacts that the solvers leave
    /// above their tolerance is still taken, and counted (`StepperOptions::inexact_residual`;
    /// key `inexact_residual`, dimensionless); default 0, which ends the run on such an island
    /// instead. Only the many-body path (`contact_set = "detected"`) has islands.
    pub inexact_residual: f64,
    /// The model and its parameters (the table `[params]`, or the declaration).
    pub params: ModelParams,
    /// The impulses of the step that reached the initial state, by contact identity
    /// ([`Impulses`]), taken as the first step's warm start and as the contacts closed before
    /// it ([`Stepper::set_impulses`]); `None` (the default) starts from zero impulses. A scene
    /// written at the end of a run has them, so that a settled pile goes on resting without
    /// a cold start.
    ///
    /// In a scene file they are the table `[impulses]`: `contacts`, each `[contact, P_N, P_T]`
    /// in N s, and `joints`, each `[row, Λ_B]`. A declared mechanism's contact is named by its
    /// two shapes and the pair's feature, `"<body>.<shape>/<body>.<shape>/<feature>"`, or by
    /// its slot's name on the fixed contact set, and a joint row as the record names it
    /// (`"hinge.Lx"`): read, the names find each contact's identity in the mechanism as the
    /// file declares it, so that bodies added or removed before others keep every contact's
    /// impulses its own. A report model's contacts, and a declared mechanism's given as
    /// numbers, are identities as they stand (and its joints' plain numbers Λ_B row by row).
    pub impulses: Option<Impulses>,
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
    /// Steps taken with an island above the solvers' tolerance (see
    /// [`Scene::inexact_residual`]), and the largest LCP residual among them (0 when none).
    pub inexact_steps: u64,
    /// See `inexact_steps`.
    pub inexact_residual: f64,
    /// The impulses of the last step (the scene's own for a run of no steps): with the
    /// record's last state, the start of a continued run ([`Scene::continued`]).
    pub impulses: Option<Impulses>,
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

impl<M, O: Observer<M>> Observer<M> for StopObserver<'_, O> {
    fn observe(&mut self, mechanism: &M, report: &StepReport<'_>) -> ControlFlow<()> {
        self.inner.observe(mechanism, report)?;
        let x = report.q[self.index];
        let crossed = if self.start_below { x >= self.value } else { x <= self.value };
        if crossed { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
    }

    fn finish(&mut self, mechanism: &M, last: &StepReport<'_>) {
        self.inner.finish(mechanism, last);
    }
}

/// Shows an observer of scene-built models the [`AnyModel`] whose inner model a stepper of
/// the model's own type steps.
struct AsAnyModel<'a, O> {
    model: &'a AnyModel,
    inner: &'a mut O,
}

impl<M, O: Observer<AnyModel>> Observer<M> for AsAnyModel<'_, O> {
    fn observe(&mut self, _: &M, report: &StepReport<'_>) -> ControlFlow<()> {
        self.inner.observe(self.model, report)
    }

    fn finish(&mut self, _: &M, last: &StepReport<'_>) {
        self.inner.finish(self.model, last);
    }
}

/// Runs `stepper` until `t_end`, or until the coordinate `index` crosses `value` when `stop`
/// is `Some((index, value))`.
fn run_to_end<M: Mechanism, O: Observer<M>>(
    stepper: &mut Stepper<M>,
    stop: Option<(usize, f64)>,
    t_end: f64,
    observer: &mut O,
) -> Result<RunSummary, ModelError> {
    Ok(match stop {
        Some((index, value)) => {
            let start_below = stepper.q()[index] < value;
            let mut wrapped = StopObserver { inner: observer, index, value, start_below };
            stepper.run_until(t_end, &mut wrapped)?
        }
        None => stepper.run_until(t_end, observer)?,
    })
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
            t_start: 0.0,
            t_end,
            record_every: 1,
            solver: SolverChoice::Auto,
            stop_at,
            projection: kind == ModelKind::Declared,
            inexact_residual: 0.0,
            params: ModelParams::report(kind),
            impulses: None,
        }
    }

    /// The scene of the declared mechanism `spec` (a [`crate::bodies::MultibodyBuilder`]'s
    /// [`spec`](crate::bodies::MultibodyBuilder::spec), or a declaration read elsewhere),
    /// stepped by Δt = `dt` (s) from t = 0 to `t_end` (s), with a scene file's defaults for
    /// the rest: every step recorded, the `auto` solver, the position projection on, no stop
    /// rule, no start impulses.
    ///
    /// ```
    /// # fn main() -> Result<(), Box<dyn std::error::Error>> {
    /// use moreau_models::Scene;
    /// use moreau_models::bodies::{BodySpec, JointSpec, MultibodyBuilder};
    ///
    /// let mut builder = MultibodyBuilder::new([0.0, -9.81]);
    /// builder.add_body(BodySpec::dynamic("bob", 1.0, 1e-6, [0.5, 0.0], 0.0));
    /// builder.add_joint(JointSpec::revolute("hinge", "ground", [0.0, 0.0], "bob", [-0.5, 0.0]));
    /// let scene = Scene::declared(builder.spec().clone(), 1e-3, 0.1);
    /// let run = scene.run()?;
    /// assert_eq!(run.steps, 100);
    /// // The same scene as a file: `moreau simulate --scene pendulum.toml` runs it.
    /// assert_eq!(Scene::from_toml_str(&scene.to_toml_string()?)?, scene);
    /// # Ok(())
    /// # }
    /// ```
    pub fn declared(spec: crate::bodies::SystemSpec, dt: f64, t_end: f64) -> Scene {
        Scene {
            dt,
            t_end,
            params: ModelParams::Declared(Box::new(spec)),
            ..Scene::report(ModelKind::Declared)
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
    /// field for a value out of range; [`ModelError::BadValue`] (key `impulses.contacts.<k>`
    /// or `impulses.joints.<k>`) for an impulse whose name the declared mechanism does not
    /// have (see [`Self::impulses`]).
    pub fn from_toml_str(text: &str) -> Result<Scene, ModelError> {
        let table: toml::Table = toml::from_str(text).map_err(|e| parse_error(text, &e))?;
        if table.is_empty() {
            return Err(ModelError::Parse {
                path: None,
                field: None,
                message: "the scene is empty: it needs dt and t_end, and either [params] with \
                          a model or the bodies of a declared mechanism (scenes/ has examples)"
                    .to_owned(),
            });
        }
        // Each form is read from the text itself, so that the reader's errors keep their
        // positions in the file, and then from its table: the text's reader takes the first
        // entries of a longer array for a field of fixed length (a position of three numbers),
        // which the table's reader refuses, as under `--set`.
        let value = || toml::Value::Table(table.clone());
        let scene: Scene = if table.contains_key("params") {
            let file = toml::from_str::<BuiltinFile>(text).map_err(|e| parse_error(text, &e))?;
            BuiltinFile::deserialize(value()).map_err(|e| parse_error(text, &e))?;
            file.into()
        } else {
            let file = toml::from_str::<DeclaredFile>(text)
                .map_err(|e| declared_parse_error(text, &table, &e))?;
            DeclaredFile::deserialize(value())
                .map_err(|e| declared_parse_error(text, &table, &e))?;
            file.into_scene()?
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
            .map_err(|cause| ModelError::Io { path: path.to_owned(), cause })?;
        Self::from_toml_str(&text).map_err(|e| match e {
            ModelError::Parse { field, message, .. } => {
                ModelError::Parse { path: Some(path.to_owned()), field, message }
            }
            other => other,
        })
    }

    /// The scene as TOML text that [`Self::from_toml_str`] reads back to an equal scene. The
    /// table `[impulses]` comes last, its contacts and joint rows one per line, a declared
    /// mechanism's by name (see [`Self::impulses`]).
    ///
    /// # Errors
    /// [`ModelError::Unwritable`] for a scene that TOML cannot hold (an impulse's contact
    /// identity above TOML's largest integer) and for a declared mechanism's impulses that name
    /// no contact or joint row of it; the errors of [`Self::build`] for a declared mechanism
    /// with impulses, whose names are taken from it.
    pub fn to_toml_string(&self) -> Result<String, ModelError> {
        file::to_toml(self)
    }

    /// Checks the scene's own fields and builds the model once.
    ///
    /// # Errors
    /// [`ModelError::InvalidParameter`] naming the field.
    pub fn validate(&self) -> Result<(), ModelError> {
        positive("dt", self.dt)?;
        finite("t_start", self.t_start)?;
        if self.t_start == 0.0 {
            non_negative("t_end", self.t_end)?;
        } else if !(self.t_end >= self.t_start) {
            return Err(relation(
                "t_end",
                self.t_end,
                &format!("must be finite and >= t_start = {}", self.t_start),
            ));
        }
        if self.record_every == 0 {
            return Err(relation("record_every", 0.0, "must be at least 1"));
        }
        // The stepper's own rule (`StepperOptions::inexact_residual`), checked before a run
        // starts rather than at its first step.
        if !(0.0..1.0).contains(&self.inexact_residual) {
            return Err(relation(
                "inexact_residual",
                self.inexact_residual,
                "must lie in [0, 1): a natural residual up to which an island is taken",
            ));
        }
        let model = self.build()?;
        if let Some(stop) = &self.stop_at {
            finite("stop_at.value", stop.value)?;
            let names = model.coordinate_names();
            if names.position(&stop.coordinate).is_none() {
                return Err(ModelError::BadValue {
                    key: "stop_at.coordinate".to_owned(),
                    value: stop.coordinate.clone(),
                    reason: format!(
                        "not a coordinate of {}; accepted: {}",
                        match self.kind() {
                            ModelKind::Declared => "the declared mechanism".to_owned(),
                            kind => format!("the model `{kind}`"),
                        },
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
        self.params.build_at(self.t_start)
    }

    /// The stepper's options: Δt, the solver and the projection. A declared mechanism gets its
    /// gap tolerance ([`crate::bodies::Multibody::gap_tolerance`]), which keeps resting
    /// contacts closed whatever round-off leaves in their gaps, and, stepped with the
    /// projection, its projection tolerance
    /// ([`crate::bodies::Multibody::projection_tolerance`]) and joint tolerance
    /// ([`crate::bodies::Multibody::joint_tolerance`]), all relative to its size.
    pub fn stepper_options(&self) -> StepperOptions {
        match &self.params {
            // The build's error surfaces where the scene is built.
            ModelParams::Declared(spec) => {
                self.options_of(spec.build_at(self.t_start).ok().as_ref())
            }
            _ => self.options_of(None),
        }
    }

    /// [`Self::stepper_options`] with the declared mechanism built already, if the scene
    /// declares one.
    fn options_of(&self, declared: Option<&Multibody>) -> StepperOptions {
        let options = StepperOptions::new(self.dt)
            .with_solver(self.solver)
            .with_projection(self.projection)
            .with_inexact_residual(self.inexact_residual);
        let Some(m) = declared else { return options };
        let own = m.stepper_options(self.dt);
        let options = options.with_gap_tolerance(own.gap_tolerance);
        if self.projection {
            options
                .with_projection_tolerance(own.projection_tolerance)
                .with_joint_tolerance(own.joint_tolerance)
        } else {
            options
        }
    }

    /// [`Self::stepper_options`] for the scene's `model`, built already.
    fn options_for(&self, model: &AnyModel) -> StepperOptions {
        match model {
            AnyModel::Declared(m) => self.options_of(Some(m)),
            _ => self.options_of(None),
        }
    }

    /// A stepper at the model's initial state and t = t_start, for stepping by hand.
    ///
    /// # Errors
    /// The errors of [`Self::build`] and of `Stepper::new`.
    pub fn stepper(&self) -> Result<Stepper<AnyModel>, ModelError> {
        let model = self.build()?;
        let (q0, u0) = model.initial_state();
        let options = self.options_for(&model);
        let mut stepper = Stepper::new(model, &q0, &u0, self.t_start, options)?;
        if let Some(impulses) = &self.impulses {
            stepper.set_impulses(impulses)?;
        }
        Ok(stepper)
    }

    /// Builds the model, runs it to the stop rule (or `t_end`) and records every
    /// `record_every`-th step and the last; row 0 of the record is the initial state.
    ///
    /// The run steps the model's own type (a [`Stepper`] of [`crate::Ball`], say), so that a
    /// scene-built model costs what the concrete type costs.
    ///
    /// It stops on the stepper's errors only (a state that is not finite, an island no solver
    /// solves): the `moreau` command's guards against a run that diverges while staying finite
    /// (energy growth, states beyond their bounds, contacts sunk deeper than the bodies'
    /// sizes, bodies carried through thin shapes) are `moreau_cli::guard::run_guarded`, which
    /// runs a scene under them.
    ///
    /// # Errors
    /// The errors of [`Self::stepper`] and every [`moreau_stepper::StepError`] of the run.
    pub fn run(&self) -> Result<Simulation, ModelError> {
        let start = Instant::now();
        let model = self.build()?;
        let (q0, u0) = model.initial_state();
        let mut recorder = Recorder::every(self.record_every);
        recorder.push_initial(&model, self.t_start, &q0, &u0);
        // The rows up to t_end, or a million when more (a stop rule may end the run early).
        let steps = (self.t_end - self.t_start) / self.dt;
        let rows = (steps / self.record_every.max(1) as f64).ceil().clamp(0.0, 1e6);
        recorder.record.reserve(rows as usize + 1);
        let summary = self.run_model(&model, &mut recorder)?;
        let impulses = recorder.last_impulses().cloned().or_else(|| self.impulses.clone());
        Ok(Simulation {
            record: recorder.record,
            wall_seconds: start.elapsed().as_secs_f64(),
            steps: summary.steps,
            lcp_solves: summary.lcp_solves,
            inexact_steps: summary.inexact_steps,
            inexact_residual: summary.inexact_residual,
            impulses,
            model,
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
        let model = self.build()?;
        self.run_model(&model, observer)
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
        let stop = self.stop(stepper.mechanism())?;
        run_to_end(stepper, stop, self.t_end, observer)
    }

    /// Runs a stepper of `model`'s own type from its initial state at t_start to the stop rule
    /// or end time, showing `observer` the scene-built `model`.
    fn run_model<O: Observer<AnyModel>>(
        &self,
        model: &AnyModel,
        observer: &mut O,
    ) -> Result<RunSummary, ModelError> {
        let stop = self.stop(model)?;
        let (q0, u0) = model.initial_state();
        let options = self.options_for(model);
        let mut shown = AsAnyModel { model, inner: observer };
        dispatch!(model, m => {
            let mut stepper = Stepper::new(m.clone(), &q0, &u0, self.t_start, options)?;
            if let Some(impulses) = &self.impulses {
                stepper.set_impulses(impulses)?;
            }
            run_to_end(&mut stepper, stop, self.t_end, &mut shown)
        })
    }

    /// The index of the stop rule's coordinate in `model` and the rule's value.
    fn stop(&self, model: &AnyModel) -> Result<Option<(usize, f64)>, ModelError> {
        let Some(stop) = &self.stop_at else { return Ok(None) };
        let index = model.coordinate_names().position(&stop.coordinate).ok_or_else(|| {
            ModelError::BadValue {
                key: "stop_at.coordinate".to_owned(),
                value: stop.coordinate.clone(),
                reason: "not a coordinate of the model".to_owned(),
            }
        })?;
        Ok(Some((index, stop.value)))
    }
}
