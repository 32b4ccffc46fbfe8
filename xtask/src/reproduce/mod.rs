//! `cargo xtask reproduce`: every figure and table of the report from the project's own
//! simulations.
//!
//! Figures are entries of one registry table ([`registry`]): an identifier, a file stem, a
//! caption, the runs the figure needs and the function that draws it. The runs of all entries
//! are collected (each name once), run in parallel, and the figures are then drawn in
//! parallel; results are collected in registry order, so the output does not depend on the
//! number of threads.

mod ball;
mod cam;
mod laws;
mod scale;
mod slider;
mod tradeoff;
mod woodpecker;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, anyhow, bail};
use moreau_models::{Drawing, Role};
use rayon::prelude::*;
use serde_json::{Value, json};

use crate::keys;
use crate::report::{FigureReport, Report, RunInfo};
use crate::runs::{RunResult, RunSpec};

/// Options of a reproduction.
#[derive(Clone, Debug)]
pub struct Options {
    /// Output folder (created when missing).
    pub out: PathBuf,
    /// Shorter horizons and fewer runs.
    pub quick: bool,
    /// Worker threads; one per core when `None`.
    pub jobs: Option<usize>,
}

/// What a reproduction did.
#[derive(Clone, Debug)]
pub struct Summary {
    /// Number of files written.
    pub files: usize,
    /// Wall time of the whole reproduction (s).
    pub total_seconds: f64,
    /// Sum of the wall times of the simulations (s).
    pub simulation_seconds: f64,
    /// The figures as reported.
    pub figures: Vec<FigureReport>,
}

/// What drawing a figure produced.
#[derive(Clone, Debug, Default)]
pub struct Output {
    /// Files written (names relative to the output folder).
    pub files: Vec<String>,
    /// Key numbers shown with the figure.
    pub key_numbers: Value,
    /// A Markdown table shown in the report.
    pub markdown: Option<String>,
}

/// One figure or table of the registry.
pub struct Entry {
    /// Identifier as in the source, e.g. `Fig 8.2`.
    pub id: &'static str,
    /// File stem, e.g. `fig08_02_ball`.
    pub stem: &'static str,
    /// Caption.
    pub caption: &'static str,
    /// The runs the figure needs (depends on `quick`).
    pub runs: fn(bool) -> Vec<RunSpec>,
    /// Draws the figure into the output folder.
    pub draw: fn(&Ctx<'_>, &Entry) -> Result<Output>,
}

/// What a figure function sees: the output folder and the finished runs.
pub struct Ctx<'a> {
    /// Output folder.
    pub out: &'a Path,
    /// Whether this is a quick reproduction.
    pub quick: bool,
    runs: &'a BTreeMap<String, Result<RunResult, String>>,
}

impl Ctx<'_> {
    /// The finished run called `name`.
    ///
    /// # Errors
    /// When the run failed or does not exist.
    pub fn run(&self, name: &str) -> Result<&RunResult> {
        match self.runs.get(name) {
            Some(Ok(r)) => Ok(r),
            Some(Err(e)) => Err(anyhow!("run {name} failed: {e}")),
            None => Err(anyhow!("no run called {name}")),
        }
    }

    /// The run called `name`, or its error message.
    pub fn try_run(&self, name: &str) -> Result<&RunResult, String> {
        match self.runs.get(name) {
            Some(Ok(r)) => Ok(r),
            Some(Err(e)) => Err(e.clone()),
            None => Err(format!("no run called {name}")),
        }
    }
}

/// File names (relative) of written paths.
pub(crate) fn names(paths: &[PathBuf]) -> Vec<String> {
    paths.iter().filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned())).collect()
}

/// The registry: every figure and table of the report, in the report's order.
pub fn registry() -> Vec<Entry> {
    let mut entries = Vec::new();
    entries.extend(laws::entries());
    entries.extend(ball::entries());
    entries.extend(woodpecker::entries());
    entries.extend(slider::entries());
    entries.extend(cam::entries());
    entries.extend(tradeoff::entries());
    entries.extend(scale::entries());
    entries
}

/// Makes sure `dir` is a folder that files can be written into: creates it when missing and
/// writes and removes a probe file, so that a bad output is refused before any run.
///
/// # Errors
/// When `dir` is a file, lies under a file, or cannot be created or written.
pub fn writable(dir: &Path) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        bail!("{} is a file, not a folder", dir.display());
    }
    std::fs::create_dir_all(dir)
        .with_context(|| format!("creating the folder {}", dir.display()))?;
    let probe = dir.join(".xtask-write-probe");
    std::fs::write(&probe, b"").with_context(|| format!("writing into {}", dir.display()))?;
    std::fs::remove_file(&probe).with_context(|| format!("writing into {}", dir.display()))?;
    Ok(())
}

/// The files written once every figure is drawn, in this order.
pub const REPORT_FILES: [&str; 3] = ["summary.json", "report.html", "report.md"];

/// Runs the reproduction.
///
/// # Errors
/// When the output folder cannot be written, a run that a figure needs fails, or drawing
/// fails; then `summary.json`, `report.html` and `report.md` are not written (those of an
/// earlier reproduction into the folder are removed first).
pub fn run(options: &Options) -> Result<Summary> {
    let start = Instant::now();
    writable(&options.out).context("--out")?;
    // The report of an earlier reproduction into the same folder goes first: a reproduction
    // that fails leaves no report that looks complete.
    for name in REPORT_FILES {
        let path = options.out.join(name);
        if path.exists() {
            std::fs::remove_file(&path).with_context(|| format!("removing {}", path.display()))?;
        }
    }
    faer::set_global_parallelism(faer::Par::Seq);
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(jobs) = options.jobs {
        builder = builder.num_threads(jobs.max(1));
    }
    let pool = builder.build().context("starting the worker threads")?;
    pool.install(|| reproduce(options, start))
}

fn reproduce(options: &Options, start: Instant) -> Result<Summary> {
    let entries = registry();
    // The union of the runs, each name once, in registry order.
    let mut specs: Vec<RunSpec> = Vec::new();
    for e in &entries {
        for spec in (e.runs)(options.quick) {
            match specs.iter().find(|s| s.name == spec.name) {
                Some(existing) if *existing != spec => {
                    bail!("run {} is defined twice with different settings", spec.name)
                }
                Some(_) => {}
                None => specs.push(spec),
            }
        }
    }
    let progress = crate::grid::Progress::new(specs.len(), "simulations");
    let results: Vec<Result<RunResult, String>> = specs
        .par_iter()
        .map(|spec| {
            let r = spec.execute().map_err(|e| format!("{e:#}"));
            progress.tick(&spec.name);
            r
        })
        .collect();
    progress.finish();
    let simulation_seconds: f64 =
        results.iter().filter_map(|r| r.as_ref().ok()).map(|r| r.sim.wall_seconds).sum();
    let runs: BTreeMap<String, Result<RunResult, String>> =
        specs.iter().map(|s| s.name.clone()).zip(results).collect();
    let ctx = Ctx { out: &options.out, quick: options.quick, runs: &runs };

    let drawn: Vec<Result<(Output, f64)>> = entries
        .par_iter()
        .map(|e| {
            let t0 = Instant::now();
            let out = (e.draw)(&ctx, e).with_context(|| format!("{} ({})", e.id, e.stem))?;
            Ok((out, t0.elapsed().as_secs_f64()))
        })
        .collect();
    let mut figures = Vec::new();
    let mut failures = Vec::new();
    for (e, d) in entries.iter().zip(drawn) {
        let (out, seconds) = match d {
            Ok(d) => d,
            Err(err) => {
                failures.push(format!("{err:#}"));
                continue;
            }
        };
        figures.push(FigureReport {
            id: e.id.to_owned(),
            stem: e.stem.to_owned(),
            caption: e.caption.to_owned(),
            files: out.files,
            runs: (e.runs)(options.quick).into_iter().map(|s| s.name).collect(),
            key_numbers: out.key_numbers,
            markdown: out.markdown,
            draw_seconds: seconds,
        });
    }
    if !failures.is_empty() {
        bail!(
            "{} of {} figures and tables failed, and no summary.json or report was written:\n{}",
            failures.len(),
            entries.len(),
            failures.join("\n")
        );
    }

    let infos: Vec<RunInfo> = specs
        .iter()
        .filter_map(|s| runs.get(&s.name).and_then(|r| r.as_ref().ok()).map(|r| r.info.clone()))
        .collect();
    // Each model's key numbers with its run's parameters, Δt, solver, steps, LCP solves and
    // wall time.
    let with_costs = |run: &RunResult| -> Value {
        let mut v = keys::summary(run);
        if let Value::Object(map) = &mut v {
            map.insert("steps".into(), json!(run.info.steps));
            map.insert("lcp_solves".into(), json!(run.info.lcp_solves));
            map.insert("wall_seconds".into(), json!(run.info.wall_seconds));
        }
        v
    };
    let model_keys = |names: &[&str]| -> Value {
        let list: Vec<Value> =
            names.iter().filter_map(|n| ctx.run(n).ok()).map(with_costs).collect();
        if list.len() == 1 {
            list.into_iter().next().unwrap_or(Value::Null)
        } else {
            Value::Array(list)
        }
    };
    let key_numbers = json!({
        "ball": model_keys(&[ball::MAIN]),
        "ball_time_steps": model_keys(&ball::DT_RUNS),
        "woodpecker": model_keys(&[woodpecker::MAIN]),
        "slider_crank": model_keys(&slider::EPS_RUNS),
        "slider_crank_ideal": model_keys(&[slider::IDEAL]),
        "cam": model_keys(&[cam::MAIN]),
    });
    let scale_runs = figures
        .iter()
        .find(|f| f.stem == crate::scale::STEM)
        .map_or(Value::Null, |f| f.key_numbers.clone());
    let total_seconds = start.elapsed().as_secs_f64();
    let summary = json!({
        "generator": "cargo xtask reproduce",
        "quick": options.quick,
        "key_numbers": key_numbers,
        "scale": scale_runs,
        "figures": figures.iter().map(|f| json!({
            "id": f.id, "stem": f.stem, "caption": f.caption, "files": f.files,
            "runs": f.runs, "key_numbers": f.key_numbers,
        })).collect::<Vec<_>>(),
        "runs": infos,
        "simulation_seconds": simulation_seconds,
        "total_seconds": total_seconds,
    });
    let path = options.out.join("summary.json");
    std::fs::write(&path, serde_json::to_string_pretty(&summary)?)
        .with_context(|| format!("writing {}", path.display()))?;
    let preamble = format!(
        "Every figure and table below was regenerated by `cargo xtask reproduce{}` from the \
         project's own simulations (Moreau's midpoint time-stepping with an LCP per step). \
         Simulations ran in parallel; their wall times are listed with each run.",
        if options.quick { " --quick" } else { "" }
    );
    let report = Report {
        title: "Moreau: reproduction of the report's figures and tables",
        preamble: &preamble,
        figures: &figures,
        runs: &infos,
        total_seconds,
    };
    report.write(&options.out)?;
    let files = figures.iter().map(|f| f.files.len()).sum::<usize>() + 3;
    Ok(Summary { files, total_seconds, simulation_seconds, figures })
}

/// Bounds [x0, y0, x1, y1] of the elements of a drawing whose role is not in `skip`.
pub(crate) fn focus(drawing: &Drawing, skip: &[Role]) -> Option<[f64; 4]> {
    let mut b: Option<[f64; 4]> = None;
    let mut add = |x0: f64, y0: f64, x1: f64, y1: f64| {
        b = Some(match b {
            None => [x0, y0, x1, y1],
            Some(o) => [o[0].min(x0), o[1].min(y0), o[2].max(x1), o[3].max(y1)],
        });
    };
    for l in drawing.polylines.iter().filter(|l| !skip.contains(&l.role)) {
        for p in &l.points {
            add(p[0], p[1], p[0], p[1]);
        }
    }
    for c in drawing.circles.iter().filter(|c| !skip.contains(&c.role)) {
        add(
            c.center[0] - c.radius,
            c.center[1] - c.radius,
            c.center[0] + c.radius,
            c.center[1] + c.radius,
        );
    }
    b
}

/// Windows of one common size (the largest focus, padded by `pad` of its size) centred on each
/// focus: a camera that follows the mechanism.
pub(crate) fn follow(focus: &[[f64; 4]], pad: f64) -> Vec<[f64; 4]> {
    let w = focus.iter().map(|f| f[2] - f[0]).fold(0.0, f64::max) * (1.0 + 2.0 * pad);
    let h = focus.iter().map(|f| f[3] - f[1]).fold(0.0, f64::max) * (1.0 + 2.0 * pad);
    focus
        .iter()
        .map(|f| {
            let (cx, cy) = (0.5 * (f[0] + f[2]), 0.5 * (f[1] + f[3]));
            [cx - 0.5 * w, cy - 0.5 * h, cx + 0.5 * w, cy + 0.5 * h]
        })
        .collect()
}
