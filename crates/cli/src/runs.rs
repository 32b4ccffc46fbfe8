//! Simulation runs: a scene with overrides, its result, and the per-row quantities the
//! analysis needs (contact phases, approach velocities, gaps).

use anyhow::{Context, Result};
use moreau_kinematics::ContactKinematics;
use moreau_models::{AnyModel, ModelKind, ModelParams, Scene, Simulation};
use moreau_stepper::{ContactState, Record};

use serde::Serialize;

use crate::analysis::ContactStateExt;

/// One simulation run as a report lists it.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct RunInfo {
    /// Name of the run (e.g. `ball_e0.9_dt1e-3`).
    pub name: String,
    /// Model name (`ball`, `woodpecker`, ...).
    pub model: String,
    /// Time step Δt (s).
    pub dt: f64,
    /// End time (s).
    pub t_end: f64,
    /// LCP solver name.
    pub solver: String,
    /// Every model parameter as (dotted key, value).
    pub parameters: Vec<(String, String)>,
    /// Wall-clock time of the run (s).
    pub wall_seconds: f64,
    /// Steps taken.
    pub steps: u64,
    /// Steps that needed an LCP solver.
    pub lcp_solves: u64,
}

/// A named simulation: a model's report scene with `key=value` overrides.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSpec {
    /// Name of the run inside a reproduction.
    pub name: String,
    /// The model.
    pub kind: ModelKind,
    /// Overrides applied with `Scene::set`, in order.
    pub sets: Vec<(String, String)>,
}

impl RunSpec {
    /// A run of `kind` named `name` with overrides given as `(key, value)` pairs.
    pub fn new(name: &str, kind: ModelKind, sets: &[(&str, &str)]) -> Self {
        Self {
            name: name.to_owned(),
            kind,
            sets: sets.iter().map(|(k, v)| ((*k).to_owned(), (*v).to_owned())).collect(),
        }
    }

    /// The scene: the model's report scene with the overrides.
    ///
    /// # Errors
    /// When an override names an unknown key or has a bad value.
    pub fn scene(&self) -> Result<Scene> {
        let mut scene = Scene::report(self.kind);
        for (k, v) in &self.sets {
            scene.set(k, v).with_context(|| format!("run {}: --set {k}={v}", self.name))?;
        }
        Ok(scene)
    }

    /// Builds the scene and runs it under the guards (see [`crate::guard`]) with the default
    /// step limit.
    ///
    /// # Errors
    /// When the scene is invalid, its step plan is refused, or the run fails or diverges.
    pub fn execute(&self) -> Result<RunResult> {
        let scene = self.scene()?;
        let sim = crate::simulate::run_scene(&scene, crate::guard::DEFAULT_MAX_STEPS)
            .with_context(|| format!("run {}", self.name))?;
        let info = run_info(&self.name, &scene, &sim);
        Ok(RunResult { spec: self.clone(), scene, sim, info })
    }
}

/// A finished run.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// What was run.
    pub spec: RunSpec,
    /// The scene that was run.
    pub scene: Scene,
    /// The stepper's record and costs.
    pub sim: Simulation,
    /// The run as the report lists it.
    pub info: RunInfo,
}

impl RunResult {
    /// The record.
    pub fn record(&self) -> &Record {
        &self.sim.record
    }

    /// The model that was run.
    pub fn model(&self) -> &AnyModel {
        &self.sim.model
    }

    /// Column `j` of the coordinates q over all rows.
    pub fn q(&self, j: usize) -> Vec<f64> {
        self.sim.record.q.column(j).collect()
    }

    /// Column `j` of the velocities u over all rows.
    pub fn u(&self, j: usize) -> Vec<f64> {
        self.sim.record.u.column(j).collect()
    }

    /// Normal impulses P_N of contact `i` over all rows.
    pub fn p_n(&self, i: usize) -> Vec<f64> {
        self.sim.record.p_n.column(i).collect()
    }

    /// Contact states per row.
    pub fn states(&self) -> Vec<Vec<ContactState>> {
        self.sim.record.state.iter().map(<[ContactState]>::to_vec).collect()
    }

    /// Approach velocities γ_N⁻ per row (see [`gamma_pre`]).
    pub fn gamma_pre(&self) -> Vec<Vec<f64>> {
        gamma_pre(&self.sim.model, &self.sim.record)
    }

    /// Gaps g_N per row and contact.
    pub fn gaps(&self) -> Vec<Vec<f64>> {
        gaps(&self.sim.model, &self.sim.record)
    }

    /// Threshold on γ_N⁻ that tells an impact from a soft closing: five times the velocity
    /// gravity adds in one step, 5 g Δt, with the scene's own g. For the slider-crank, whose
    /// contacts chatter (close and reopen every few steps at a few mm/s while the slider is
    /// pressed against a surface), at least 2 % of the largest approach speed of the run.
    pub fn impact_speed(&self) -> f64 {
        let base = 5.0 * gravity(&self.scene).abs() * self.scene.dt;
        if self.spec.kind != ModelKind::SliderCrank {
            return base;
        }
        let phases = self.states();
        let gamma = self.gamma_pre();
        let mut largest: f64 = 0.0;
        for k in 1..phases.len() {
            for (i, p) in phases[k].iter().enumerate() {
                if p.is_closed() && !phases[k - 1][i].is_closed() {
                    largest = largest.max(-gamma[k][i]);
                }
            }
        }
        base.max(0.02 * largest)
    }
}

/// Normal relative velocity γ_N⁻ = w_Nᵀ u + ŵ_N of each contact at the start of the step that
/// ends at row k (from row k − 1); row 0 gets zeros.
pub fn gamma_pre(model: &AnyModel, record: &Record) -> Vec<Vec<f64>> {
    let f = model.num_coordinates();
    let n = model.num_contacts();
    let mut w_n = vec![0.0; f];
    let mut w_t = vec![0.0; f];
    let mut out = vec![vec![0.0; n]; record.len()];
    for k in 1..record.len() {
        let (q, u, t) = (&record.q[k - 1], &record.u[k - 1], record.t[k - 1]);
        for i in 0..n {
            let c = model.contact(i, q, t, &mut w_n, &mut w_t);
            out[k][i] = w_n.iter().zip(u).map(|(a, b)| a * b).sum::<f64>() + c.w_n_hat;
        }
    }
    out
}

/// Gaps g_N(q_k, t_k) per row and contact.
pub fn gaps(model: &AnyModel, record: &Record) -> Vec<Vec<f64>> {
    let n = model.num_contacts();
    record
        .q
        .iter()
        .zip(&record.t)
        .map(|(q, &t)| (0..n).map(|i| model.normal_gap(i, q, t)).collect())
        .collect()
}

/// The scene's gravitational acceleration g (m/s²): its parameter `g`, which every report
/// model has, or the magnitude of a declared mechanism's `gravity`; 0 for a model without
/// one.
pub fn gravity(scene: &Scene) -> f64 {
    if let ModelParams::Declared(spec) = &scene.params {
        return spec.gravity[0].hypot(spec.gravity[1]);
    }
    parameters(scene)
        .into_iter()
        .find(|(k, _)| k == "g")
        .and_then(|(_, v)| v.parse().ok())
        .unwrap_or(0.0)
}

/// Every leaf of a TOML value as (dotted key, text); the elements of an array of tables are
/// named by their `name` (or their index), as `--set` names them (`bodies.bob.mass`).
fn toml_leaves(value: &toml::Value, prefix: &str, out: &mut Vec<(String, String)>) {
    let join = |k: &str| if prefix.is_empty() { k.to_owned() } else { format!("{prefix}.{k}") };
    match value {
        toml::Value::Table(t) => {
            for (k, v) in t {
                toml_leaves(v, &join(k), out);
            }
        }
        toml::Value::Array(items) if !items.is_empty() && items.iter().all(|v| v.is_table()) => {
            for (i, item) in items.iter().enumerate() {
                let name = item.get("name").and_then(toml::Value::as_str);
                toml_leaves(item, &join(&name.map_or_else(|| i.to_string(), str::to_owned)), out);
            }
        }
        toml::Value::String(s) => out.push((prefix.to_owned(), s.clone())),
        other => out.push((prefix.to_owned(), other.to_string())),
    }
}

/// The model parameters of a scene as (dotted key, text), without the model's name; a
/// declared mechanism's declaration by its `--set` paths (`gravity`, `bodies.bob.mass`, ...).
pub fn parameters(scene: &Scene) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let value = match &scene.params {
        ModelParams::Declared(spec) => toml::Value::try_from(spec.as_ref()),
        params => toml::Value::try_from(params),
    };
    if let Ok(v) = value {
        toml_leaves(&v, "", &mut out);
    }
    out.retain(|(k, _)| k != "model");
    if let Some(stop) = &scene.stop_at {
        out.push(("stop when".to_owned(), format!("{} = {}", stop.coordinate, stop.value)));
    }
    out
}

/// The report's description of a run.
pub fn run_info(name: &str, scene: &Scene, sim: &Simulation) -> RunInfo {
    RunInfo {
        name: name.to_owned(),
        model: scene.kind().name().to_owned(),
        dt: scene.dt,
        t_end: sim.record.t.last().copied().unwrap_or(0.0),
        solver: scene.solver.name().to_owned(),
        parameters: parameters(scene),
        wall_seconds: sim.wall_seconds,
        steps: sim.steps,
        lcp_solves: sim.lcp_solves,
    }
}

// Runs are built and collected across rayon's worker threads.
const _: fn() = || {
    fn is<T: Send + Sync>() {}
    is::<RunSpec>();
    is::<RunResult>();
};
