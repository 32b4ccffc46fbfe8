//! The project's own figure on the speed/accuracy trade: error against wall time for each
//! model, LCP solver and time step.

use anyhow::Result;
use moreau_models::{ModelKind, ModelParams};
use serde_json::json;

use super::{Ctx, Entry, Output, names};
use crate::analysis::BallClosedForm;
use crate::keys;
use crate::plot::{Figure, LegendAt, Mark, Panel, Series};
use crate::runs::{RunResult, RunSpec};

pub(super) fn entries() -> Vec<Entry> {
    vec![Entry {
        id: "Speed/accuracy",
        stem: "figS1_speed_accuracy",
        caption: "Speed against accuracy: error of each run against wall time, per model, LCP solver \
                  (auto, lemke, pgs) and time step (points, finest step at the right). Errors: ball, \
                  largest |y − y_exact| over 0–2 s against the closed form; woodpecker, relative error \
                  of the limit-cycle period; slider-crank, relative error of the time of two crank \
                  revolutions; cam, largest |y − y_ref| over three lobes. References: the closed form, \
                  or the auto solver with a much smaller step. Wall times are measured and vary \
                  between machines and runs.",
        runs: specs,
        draw: fig,
    }]
}

struct Study {
    kind: ModelKind,
    label: &'static str,
    t_end: Option<&'static str>,
    steps: &'static [&'static str],
    reference: Option<&'static str>,
}

fn studies(quick: bool) -> Vec<Study> {
    if quick {
        vec![
            Study {
                kind: ModelKind::Ball,
                label: "ball",
                t_end: Some("2"),
                steps: &["0.01", "0.001"],
                reference: None,
            },
            Study {
                kind: ModelKind::Woodpecker,
                label: "woodpecker",
                t_end: Some("0.6"),
                steps: &["0.0002", "0.0001"],
                reference: Some("0.00005"),
            },
            Study {
                kind: ModelKind::SliderCrank,
                label: "slider-crank",
                t_end: None,
                steps: &["0.00004", "0.00002"],
                reference: Some("0.00001"),
            },
            Study {
                kind: ModelKind::Cam,
                label: "cam",
                t_end: Some("0.15"),
                steps: &["0.0004", "0.0001"],
                reference: Some("0.00005"),
            },
        ]
    } else {
        vec![
            Study {
                kind: ModelKind::Ball,
                label: "ball",
                t_end: Some("2"),
                steps: &["0.025", "0.01", "0.004", "0.001", "0.0004"],
                reference: None,
            },
            Study {
                kind: ModelKind::Woodpecker,
                label: "woodpecker",
                t_end: Some("1"),
                steps: &["0.0004", "0.0002", "0.0001", "0.00005"],
                reference: Some("0.00002"),
            },
            Study {
                kind: ModelKind::SliderCrank,
                label: "slider-crank",
                t_end: None,
                steps: &["0.00004", "0.00002", "0.00001", "0.000005"],
                reference: Some("0.000001"),
            },
            Study {
                kind: ModelKind::Cam,
                label: "cam",
                t_end: Some("0.15"),
                steps: &["0.0004", "0.0002", "0.0001", "0.00005"],
                reference: Some("0.00001"),
            },
        ]
    }
}

fn solvers(quick: bool) -> &'static [&'static str] {
    if quick { &["auto", "lemke"] } else { &["auto", "lemke", "pgs"] }
}

fn name(label: &str, solver: &str, dt: &str) -> String {
    format!("speed_{label}_{solver}_dt{dt}")
}

fn ref_name(label: &str) -> String {
    format!("speed_{label}_reference")
}

fn spec(study: &Study, name: String, solver: &str, dt: &str) -> RunSpec {
    let mut sets = vec![("dt".to_owned(), dt.to_owned()), ("solver".to_owned(), solver.to_owned())];
    if let Some(t) = study.t_end {
        sets.push(("t_end".to_owned(), t.to_owned()));
    }
    RunSpec { name, kind: study.kind, sets }
}

fn specs(quick: bool) -> Vec<RunSpec> {
    let mut out = Vec::new();
    for s in studies(quick) {
        if let Some(dt) = s.reference {
            out.push(spec(&s, ref_name(s.label), "auto", dt));
        }
        for solver in solvers(quick) {
            for dt in s.steps {
                out.push(spec(&s, name(s.label, solver, dt), solver, dt));
            }
        }
    }
    out
}

/// Largest |y − y_exact| of a ball run over the record, against the closed-form bounces.
fn ball_error(run: &RunResult) -> Option<f64> {
    let ModelParams::Ball(p) = &run.scene.params else { return None };
    let cf = BallClosedForm::new(p.init.y0, p.r, p.g, p.eps_n);
    let times = cf.impact_times(64);
    let exact = |t: f64| -> f64 {
        match times.iter().rposition(|&ti| ti <= t) {
            None => p.init.y0 - 0.5 * p.g * t * t,
            Some(j) => {
                let v = cf.v1 * p.eps_n.powi(j as i32 + 1);
                let s = t - times[j];
                p.r + v * s - 0.5 * p.g * s * s
            }
        }
    };
    let r = run.record();
    Some(
        r.t.iter()
            .zip(&r.q)
            .filter(|(t, _)| **t < cf.t_inf)
            .map(|(&t, q)| (q[0] - exact(t)).abs())
            .fold(0.0, f64::max),
    )
}

/// Linear interpolation of (t, y) at `t`.
fn interpolate(t: &[f64], y: &[f64], at: f64) -> f64 {
    let k = t.partition_point(|&x| x < at);
    if k == 0 {
        return y[0];
    }
    if k >= t.len() {
        return y[t.len() - 1];
    }
    let w = (at - t[k - 1]) / (t[k] - t[k - 1]);
    y[k - 1] + w * (y[k] - y[k - 1])
}

fn error(kind: ModelKind, run: &RunResult, reference: Option<&RunResult>) -> Option<f64> {
    match kind {
        ModelKind::Ball => ball_error(run),
        ModelKind::Woodpecker => {
            let t = keys::woodpecker(run).cycle?.period;
            let t_ref = keys::woodpecker(reference?).cycle?.period;
            Some(((t - t_ref) / t_ref).abs())
        }
        ModelKind::SliderCrank => {
            let d = keys::slider(run).duration;
            let d_ref = keys::slider(reference?).duration;
            Some(((d - d_ref) / d_ref).abs())
        }
        _ => {
            let reference = reference?;
            let (tr, yr) = (&reference.record().t, reference.q(0));
            let r = run.record();
            Some(
                r.t.iter()
                    .zip(&r.q)
                    .map(|(&t, q)| (q[0] - interpolate(tr, &yr, t)).abs())
                    .fold(0.0, f64::max),
            )
        }
    }
}

fn fig(ctx: &Ctx<'_>, e: &Entry) -> Result<Output> {
    let mut panels = Vec::new();
    let mut rows = Vec::new();
    for (p, study) in studies(ctx.quick).iter().enumerate() {
        let reference = study.reference.and_then(|_| ctx.try_run(&ref_name(study.label)).ok());
        let unit = match study.kind {
            ModelKind::Woodpecker | ModelKind::SliderCrank => "relative error [-]",
            _ => "error [m]",
        };
        let title = format!("({}) {}", ["a", "b", "c", "d"][p], study.label);
        let mut panel =
            Panel::new(&title, "log10 wall time [s]", &format!("log10 {unit}"), "log10_wall")
                .legend(LegendAt::UpperRight);
        for (j, solver) in solvers(ctx.quick).iter().enumerate() {
            let (mut xs, mut ys) = (Vec::new(), Vec::new());
            for dt in study.steps {
                let n = name(study.label, solver, dt);
                match ctx.try_run(&n) {
                    Ok(run) => {
                        let err = error(study.kind, run, reference);
                        let wall = run.sim.wall_seconds;
                        if let Some(err) = err.filter(|e| *e > 0.0) {
                            xs.push(wall.max(1e-6).log10());
                            ys.push(err.log10());
                        }
                        rows.push(
                            json!({"model": study.label, "solver": solver, "dt": run.scene.dt,
                            "steps": run.sim.steps, "lcp_solves": run.sim.lcp_solves,
                            "wall_seconds": wall, "error": err}),
                        );
                    }
                    Err(msg) => rows.push(
                        json!({"model": study.label, "solver": solver, "dt": dt, "failed": msg}),
                    ),
                }
            }
            let column = format!("log10_error_{}_{solver}", study.label);
            panel.series.push(
                Series::line(solver, &column, xs.clone(), ys.clone(), j).with_mark(Mark::Dashed),
            );
            panel.series.push(
                Series::line("", &format!("{column}_points"), xs, ys, j)
                    .with_mark(Mark::Points)
                    .not_data(),
            );
        }
        panels.push(panel);
    }
    let fig = Figure::new(
        "Speed against accuracy: error vs wall time per model, solver and Δt",
        panels,
        2,
    );
    let files = fig.write(ctx.out, e.stem)?;
    let md = {
        let mut s = String::from(
            "| model | solver | Δt [s] | steps | LCP solves | wall time [s] | error |\n|---|---|---:|---:|---:|---:|---:|\n",
        );
        for r in &rows {
            if r.get("failed").is_some() {
                s.push_str(&format!(
                    "| {} | {} | {} | failed: {} | | | |\n",
                    r["model"].as_str().unwrap_or(""),
                    r["solver"].as_str().unwrap_or(""),
                    r["dt"],
                    r["failed"].as_str().unwrap_or("")
                ));
            } else {
                s.push_str(&format!(
                    "| {} | {} | {} | {} | {} | {:.4} | {} |\n",
                    r["model"].as_str().unwrap_or(""),
                    r["solver"].as_str().unwrap_or(""),
                    r["dt"],
                    r["steps"],
                    r["lcp_solves"],
                    r["wall_seconds"].as_f64().unwrap_or(f64::NAN),
                    r["error"].as_f64().map_or("—".to_owned(), |e| format!("{e:.3e}"))
                ));
            }
        }
        s
    };
    Ok(Output { files: names(&files), key_numbers: json!(rows), markdown: Some(md) })
}
