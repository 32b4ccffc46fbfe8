//! The slider-crank with a translational clearance joint: Figs 8.15 to 8.18.

use anyhow::{Result, bail};
use moreau_models::{AnyModel, ModelKind, SliderCrank, SliderCrankIdeal};
use serde_json::json;

use super::{Ctx, Entry, Output, names};
use crate::keys;
use crate::plot::{Figure, LegendAt, Mark, Panel, Series};
use crate::runs::{RunResult, RunSpec};

/// The restitution sweep of Figs 8.17/8.18; ε_N = 0.4 is the run of Figs 8.15/8.16.
pub(super) const EPS_RUNS: [&str; 4] = ["slider_e0.1", "slider_e0.4", "slider_e0.6", "slider_e0.9"];
const EPS: [&str; 4] = ["0.1", "0.4", "0.6", "0.9"];
/// The ideal joint.
pub(super) const IDEAL: &str = "slider_ideal";

fn eps_runs(_quick: bool) -> Vec<RunSpec> {
    EPS_RUNS
        .iter()
        .zip(EPS)
        .map(|(name, e)| RunSpec::new(name, ModelKind::SliderCrank, &[("eps_n", e)]))
        .collect()
}

fn main_runs(quick: bool) -> Vec<RunSpec> {
    let mut v: Vec<RunSpec> =
        eps_runs(quick).into_iter().filter(|s| s.name == EPS_RUNS[1]).collect();
    v.push(RunSpec::new(IDEAL, ModelKind::SliderCrankIdeal, &[]));
    v
}

pub(super) fn entries() -> Vec<Entry> {
    vec![
        Entry {
            id: "Fig 8.15",
            stem: "fig08_15_corners",
            caption: "Slider-crank with a translational clearance joint (Tab 8.4, ε_N = 0.4, μ = 0.01, \
                      c = 1 mm, Δt = 1e-5 s), two crank revolutions: normalised vertical position of \
                      slider corners 1–4, Y_i = (y_i − y_i,centred)/(c/2) (+1: touching the upper guide \
                      surface, −1: the lower one).",
            runs: main_runs,
            draw: fig8_15,
        },
        Entry {
            id: "Fig 8.16",
            stem: "fig08_16_speeds",
            caption: "Slider-crank, clearance joint (ε_N = 0.4) against the ideal joint: (a) crank speed, \
                      (b) connecting-rod speed, (c) connecting-rod portrait (speed vs angle), (d) slider \
                      portrait: normalised Y = y3/(c/2) against X = (x3 − l2)/l1 of the slider centre.",
            runs: main_runs,
            draw: fig8_16,
        },
        Entry {
            id: "Fig 8.17",
            stem: "fig08_17_corner1_eps",
            caption: "Slider-crank: normalised vertical motion of corner 1 for ε_N = 0.1, 0.4, 0.6 and 0.9 \
                      (runs of the restitution sweep, in parallel).",
            runs: eps_runs,
            draw: fig8_17,
        },
        Entry {
            id: "Fig 8.18",
            stem: "fig08_18_portraits_eps",
            caption: "Slider-crank: slider portraits (normalised Y vs X of the slider centre inside the \
                      clearance) for ε_N = 0.1, 0.4, 0.6 and 0.9.",
            runs: eps_runs,
            draw: fig8_18,
        },
    ]
}

fn clearance(run: &RunResult) -> Result<&SliderCrank> {
    match run.model() {
        AnyModel::SliderCrank(m) => Ok(m),
        _ => bail!("run {} is not a slider-crank with clearance", run.spec.name),
    }
}

fn ideal_model(run: &RunResult) -> Result<&SliderCrankIdeal> {
    match run.model() {
        AnyModel::SliderCrankIdeal(m) => Ok(m),
        _ => bail!("run {} is not an ideal slider-crank", run.spec.name),
    }
}

/// The crank's revolutions θ1 / 2π along the run, which must have reached the two
/// revolutions the figures show (a run cut short by its t_end would draw fewer).
fn revolutions(run: &RunResult) -> Result<Vec<f64>> {
    let revs: Vec<f64> = run.q(0).into_iter().map(|th| th / std::f64::consts::TAU).collect();
    let last = revs.last().copied().unwrap_or(0.0);
    if !(last >= 2.0) {
        bail!(
            "run {} ended at t = {} s after {last:.4} crank revolutions, short of the 2 its \
             figures show",
            run.spec.name,
            run.record().t.last().copied().unwrap_or(0.0)
        );
    }
    Ok(revs)
}

fn corner(run: &RunResult, k: usize) -> Result<Vec<f64>> {
    let m = clearance(run)?;
    Ok(run.record().q.iter().map(|q| m.normalized_corner(k, q)).collect())
}

fn portrait(run: &RunResult) -> Result<(Vec<f64>, Vec<f64>)> {
    let m = clearance(run)?;
    Ok(run.record().q.iter().map(|q| m.slider_portrait(q)).map(|p| (p[0], p[1])).unzip())
}

fn fig8_15(ctx: &Ctx<'_>, e: &Entry) -> Result<Output> {
    let run = ctx.run(EPS_RUNS[1])?;
    let revs = revolutions(run)?;
    let mut panels = Vec::new();
    for k in 0..4 {
        let title = format!("({}) corner {}", ["a", "b", "c", "d"][k], k + 1);
        panels.push(
            Panel::new(&title, "crank revolutions [-]", &format!("Y{} [-]", k + 1), "revolutions")
                .with(Series::line("", &format!("Y{}", k + 1), revs.clone(), corner(run, k)?, k)),
        );
    }
    let fig =
        Figure::new("Fig 8.15  Slider-crank: normalised corner motion (ε_N = 0.4)", panels, 2);
    let files = fig.write(ctx.out, e.stem)?;
    Ok(Output { files: names(&files), key_numbers: json!(keys::slider(run)), markdown: None })
}

fn fig8_16(ctx: &Ctx<'_>, e: &Entry) -> Result<Output> {
    let run = ctx.run(EPS_RUNS[1])?;
    let ideal = ctx.run(IDEAL)?;
    let im = ideal_model(ideal)?;
    let revs = revolutions(run)?;
    let irevs = revolutions(ideal)?;
    let ith1 = ideal.q(0);
    let iw1 = ideal.u(0);
    let ideal_rod_speed: Vec<f64> =
        ith1.iter().zip(&iw1).map(|(&th, &w)| im.rod_speed(th, w)).collect();
    let ideal_rod_angle: Vec<f64> = ith1.iter().map(|&th| im.rod_angle(th)).collect();
    let (px, py) = portrait(run)?;
    let fig = Figure::new(
        "Fig 8.16  Slider-crank: clearance joint (ε_N = 0.4) and ideal joint",
        vec![
            Panel::new("(a) crank speed", "crank revolutions [-]", "ω1 [rad/s]", "revolutions")
                .with(Series::line("clearance joint", "w1_clearance", revs.clone(), run.u(0), 0))
                .with(
                    Series::line("ideal joint", "w1_ideal", irevs.clone(), iw1.clone(), 1)
                        .with_mark(Mark::Dashed),
                )
                .headroom(0.3),
            Panel::new(
                "(b) connecting-rod speed",
                "crank revolutions [-]",
                "ω2 [rad/s]",
                "revolutions",
            )
            .with(Series::line("clearance joint", "w2_clearance", revs, run.u(1), 0))
            .with(
                Series::line("ideal joint", "w2_ideal", irevs, ideal_rod_speed.clone(), 1)
                    .with_mark(Mark::Dashed),
            )
            .headroom(0.3),
            Panel::new("(c) connecting-rod portrait", "θ2 [rad]", "ω2 [rad/s]", "th2")
                .with(Series::line(
                    "clearance joint",
                    "w2_clearance_portrait",
                    run.q(1),
                    run.u(1),
                    0,
                ))
                .with(
                    Series::line(
                        "ideal joint",
                        "w2_ideal_portrait",
                        ideal_rod_angle,
                        ideal_rod_speed,
                        1,
                    )
                    .with_mark(Mark::Dashed),
                )
                .headroom(0.3),
            Panel::new("(d) slider portrait", "X = (x3 − l2)/l1 [-]", "Y = y3/(c/2) [-]", "X")
                .with(Series::line("", "Y", px, py, 0)),
        ],
        2,
    );
    let files = fig.write(ctx.out, e.stem)?;
    Ok(Output {
        files: names(&files),
        key_numbers: json!({"clearance": keys::slider(run), "ideal": keys::ideal(ideal)}),
        markdown: None,
    })
}

fn fig8_17(ctx: &Ctx<'_>, e: &Entry) -> Result<Output> {
    let mut panels = Vec::new();
    let mut numbers = Vec::new();
    for (j, (name, eps)) in EPS_RUNS.iter().zip(EPS).enumerate() {
        let run = ctx.run(name)?;
        let title = format!("({}) ε_N = {eps}", ["a", "b", "c", "d"][j]);
        panels.push(
            Panel::new(&title, "crank revolutions [-]", "Y1 [-]", &format!("revolutions_e{eps}"))
                .with(Series::line(
                    "",
                    &format!("Y1_e{eps}"),
                    revolutions(run)?,
                    corner(run, 0)?,
                    j,
                ))
                .legend(LegendAt::None),
        );
        numbers.push(keys::slider(run));
    }
    let fig = Figure::new(
        "Fig 8.17  Slider-crank: corner 1 for four restitution coefficients",
        panels,
        2,
    );
    let files = fig.write(ctx.out, e.stem)?;
    Ok(Output { files: names(&files), key_numbers: json!(numbers), markdown: None })
}

fn fig8_18(ctx: &Ctx<'_>, e: &Entry) -> Result<Output> {
    let mut panels = Vec::new();
    let mut numbers = Vec::new();
    for (j, (name, eps)) in EPS_RUNS.iter().zip(EPS).enumerate() {
        let run = ctx.run(name)?;
        revolutions(run)?;
        let (px, py) = portrait(run)?;
        let title = format!("({}) ε_N = {eps}", ["a", "b", "c", "d"][j]);
        panels.push(
            Panel::new(&title, "X = (x3 − l2)/l1 [-]", "Y = y3/(c/2) [-]", &format!("X_e{eps}"))
                .with(Series::line("", &format!("Y_e{eps}"), px, py, j)),
        );
        numbers.push(keys::slider(run));
    }
    let fig = Figure::new(
        "Fig 8.18  Slider-crank: slider portraits for four restitution coefficients",
        panels,
        2,
    );
    let files = fig.write(ctx.out, e.stem)?;
    Ok(Output { files: names(&files), key_numbers: json!(numbers), markdown: None })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_short_of_two_revolutions_is_refused() -> Result<()> {
        // The crank turns at about 150 rad/s: 0.02 s is about half a revolution.
        let short =
            RunSpec::new("short", ModelKind::SliderCrankIdeal, &[("t_end", "0.02")]).execute()?;
        let err = revolutions(&short).unwrap_err().to_string();
        assert!(
            err.contains("run short ended at t = 0.02") && err.contains("short of the 2"),
            "{err}"
        );
        let full = RunSpec::new("full", ModelKind::SliderCrankIdeal, &[]).execute()?;
        let revs = revolutions(&full)?;
        assert!((2.0..2.01).contains(revs.last().unwrap()), "{:?}", revs.last());
        Ok(())
    }
}
