//! `cargo xtask sweep`: the Cartesian product of parameter values, run in parallel, one CSV
//! row of key numbers per member.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, ensure};
use moreau_models::{ModelKind, Scene};
use rayon::prelude::*;

use crate::grid::{Axis, Progress, Shard, product};
use crate::keys;
use crate::runs::{RunResult, RunSpec, run_info};
use crate::simulate::parse_model;

/// What to sweep.
#[derive(Clone, Debug)]
pub struct SweepOptions {
    /// Model name.
    pub model: String,
    /// A scene file to start from instead of the model's report scene.
    pub scene: Option<PathBuf>,
    /// The swept parameters (`key=v1,v2,...`).
    pub axes: Vec<Axis>,
    /// Run only this part of the members.
    pub shard: Option<Shard>,
}

/// The CSV header of a sweep: `member`, `members`, the swept keys, the model's key numbers,
/// `steps`, `lcp_solves`, `wall_seconds`, `error`.
pub fn header(kind: ModelKind, axes: &[Axis]) -> Vec<String> {
    let mut h = vec!["member".to_owned(), "members".to_owned()];
    h.extend(axes.iter().map(|a| a.key.clone()));
    h.extend(keys::columns(kind).iter().map(|s| (*s).to_owned()));
    h.extend(["steps", "lcp_solves", "wall_seconds", "error"].map(str::to_owned));
    h
}

fn cell(x: Option<f64>) -> String {
    match x {
        Some(v) if v.is_finite() => v.to_string(),
        _ => String::new(),
    }
}

/// Runs the sweep and writes the CSV to `out`; returns the number of rows written.
///
/// Every member's scene is built first, so a bad key or value fails before any run. Members
/// run in parallel; rows are written in member order. A member whose run fails gets a row
/// with its error message and empty numbers.
///
/// # Errors
/// Unknown model, bad scene, unknown keys or bad values, or an unwritable output.
pub fn run(options: &SweepOptions, out: &Path) -> Result<usize> {
    let kind = parse_model(&options.model)?;
    let base = match &options.scene {
        Some(path) => Scene::from_path(path)?,
        None => Scene::report(kind),
    };
    ensure!(
        base.kind() == kind,
        "the scene file describes model '{}', not '{}'",
        base.kind(),
        kind
    );
    let members = product(&options.axes);
    let total = members.len();
    let selected: Vec<usize> =
        (0..total).filter(|&i| options.shard.is_none_or(|s| s.contains(i))).collect();
    let scenes: Vec<Scene> = selected
        .iter()
        .map(|&i| {
            let mut scene = base.clone();
            for (k, v) in &members[i] {
                scene.set(k, v).with_context(|| format!("member {i}: --set {k}={v}"))?;
            }
            Ok(scene)
        })
        .collect::<Result<_>>()?;
    faer::set_global_parallelism(faer::Par::Seq);
    let progress = Progress::new(selected.len(), &format!("sweep {kind}"));
    let rows: Vec<Vec<String>> = selected
        .par_iter()
        .zip(scenes.par_iter())
        .map(|(&i, scene)| {
            let mut row = vec![i.to_string(), total.to_string()];
            row.extend(members[i].iter().map(|(_, v)| v.clone()));
            match scene.run() {
                Ok(sim) => {
                    let spec =
                        RunSpec { name: format!("member {i}"), kind, sets: members[i].clone() };
                    let info = run_info(&spec.name, scene, &sim);
                    let result = RunResult { spec, scene: scene.clone(), sim, info };
                    row.extend(keys::row(&result).into_iter().map(cell));
                    row.push(result.sim.steps.to_string());
                    row.push(result.sim.lcp_solves.to_string());
                    row.push(format!("{:.6}", result.sim.wall_seconds));
                    row.push(String::new());
                }
                Err(e) => {
                    row.extend(keys::columns(kind).iter().map(|_| String::new()));
                    row.extend([String::new(), String::new(), String::new(), e.to_string()]);
                }
            }
            progress.tick(&format!("member {i}"));
            row
        })
        .collect();
    progress.finish();
    let mut w =
        csv::Writer::from_path(out).with_context(|| format!("creating {}", out.display()))?;
    w.write_record(header(kind, &options.axes))?;
    for row in &rows {
        w.write_record(row)?;
    }
    w.flush()?;
    Ok(rows.len())
}
