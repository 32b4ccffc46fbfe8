//! `cargo xtask simulate`: run one model and write its record as CSV.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use moreau_models::{ModelKind, Scene};

use crate::runs::{RunResult, RunSpec, run_info};

/// What to simulate.
#[derive(Clone, Debug, Default)]
pub struct SimulateOptions {
    /// Model name (`ball`, `woodpecker`, `slider-crank`, `slider-crank-ideal`, `cam`,
    /// `painleve`).
    pub model: String,
    /// A scene file to start from instead of the model's report scene.
    pub scene: Option<PathBuf>,
    /// `key=value` overrides, applied in order.
    pub sets: Vec<String>,
    /// Time step Δt (s), overriding the scene's.
    pub dt: Option<f64>,
    /// End time (s), overriding the scene's.
    pub tf: Option<f64>,
    /// Solver name (`auto`, `lemke`, `pgs`, `enum`).
    pub solver: Option<String>,
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

/// The scene of the options: the scene file or the model's report scene, with overrides.
///
/// # Errors
/// Unknown model, unreadable scene, a scene of another model, unknown keys or bad values.
pub fn scene(options: &SimulateOptions) -> Result<Scene> {
    let kind = parse_model(&options.model)?;
    let mut scene = match &options.scene {
        Some(path) => Scene::from_path(path)?,
        None => Scene::report(kind),
    };
    if scene.kind() != kind {
        bail!("the scene file describes model '{}', not '{}'", scene.kind(), kind);
    }
    let mut sets: Vec<(String, String)> = Vec::new();
    if let Some(dt) = options.dt {
        sets.push(("dt".into(), dt.to_string()));
    }
    if let Some(tf) = options.tf {
        sets.push(("t_end".into(), tf.to_string()));
    }
    if let Some(solver) = &options.solver {
        sets.push(("solver".into(), solver.clone()));
    }
    for s in &options.sets {
        sets.push(parse_set(s)?);
    }
    for (k, v) in &sets {
        scene.set(k, v).with_context(|| format!("--set {k}={v}"))?;
    }
    Ok(scene)
}

/// Runs the options' scene.
///
/// # Errors
/// As [`scene`], and when the run fails.
pub fn run(options: &SimulateOptions) -> Result<RunResult> {
    let scene = scene(options)?;
    let sim = scene.run()?;
    let spec = RunSpec { name: "simulate".into(), kind: scene.kind(), sets: Vec::new() };
    let info = run_info(&spec.name, &scene, &sim);
    Ok(RunResult { spec, scene, sim, info })
}

/// The CSV header of a record: `t`, the coordinate and velocity names, `PN1, PT1, ...` and
/// `A1, ...`.
pub fn header(run: &RunResult) -> Vec<String> {
    let model = run.model();
    let n = model.contact_names().len();
    let mut h = vec!["t".to_owned()];
    h.extend(model.coordinate_names().iter().map(|s| (*s).to_owned()));
    h.extend(model.velocity_names().iter().map(|s| (*s).to_owned()));
    for i in 1..=n {
        h.push(format!("PN{i}"));
        h.push(format!("PT{i}"));
    }
    h.extend((1..=n).map(|i| format!("A{i}")));
    h
}

/// Writes the record of `run` as CSV.
///
/// # Errors
/// When the file cannot be written.
pub fn write_record(run: &RunResult, path: &Path) -> Result<()> {
    let r = run.record();
    let mut w =
        csv::Writer::from_path(path).with_context(|| format!("creating {}", path.display()))?;
    w.write_record(header(run))?;
    for k in 0..r.len() {
        let mut row = vec![r.t[k].to_string()];
        row.extend(r.q[k].iter().map(f64::to_string));
        row.extend(r.u[k].iter().map(f64::to_string));
        for (p_n, p_t) in r.p_n[k].iter().zip(&r.p_t[k]) {
            row.push(p_n.to_string());
            row.push(p_t.to_string());
        }
        row.extend(r.active[k].iter().map(|&a| if a { "1".to_owned() } else { "0".to_owned() }));
        w.write_record(&row)?;
    }
    w.flush()?;
    Ok(())
}
