//! The woodpecker toy: Figs 8.6 to 8.10.

use anyhow::{Context, Result};
use moreau_models::{AnyModel, ModelKind, Role};
use serde_json::json;

use super::{Ctx, Entry, Output, focus, follow, names};
use crate::analysis::ContactStateExt;
use crate::frames::{Frame, Strip, frame, motion_rows};
use crate::keys;
use crate::plot::{Figure, Panel, Series};
use crate::runs::{RunResult, RunSpec};
use moreau_stepper::ContactState;

/// The woodpecker run (Tab 8.3, Δt = 1e-4 s, 0–1 s).
pub(super) const MAIN: &str = "woodpecker";

fn runs(_quick: bool) -> Vec<RunSpec> {
    vec![RunSpec::new(MAIN, ModelKind::Woodpecker, &[("dt", "0.0001"), ("t_end", "1")])]
}

pub(super) fn entries() -> Vec<Entry> {
    vec![
        Entry {
            id: "Fig 8.6",
            stem: "fig08_06_sleeve",
            caption: "Woodpecker toy (Tab 8.3, Δt = 1e-4 s): (a) sleeve position y, (b) sleeve velocity v.",
            runs,
            draw: |ctx, e| {
                pair(
                    ctx,
                    e,
                    "Fig 8.6  Woodpecker: sleeve",
                    [
                        ("(a) sleeve position", "y [mm]", "y_mm", 0, 1e3),
                        ("(b) sleeve velocity", "v [m/s]", "v", 3, 1.0),
                    ],
                )
            },
        },
        Entry {
            id: "Fig 8.7",
            stem: "fig08_07_sleeve_angle",
            caption: "Woodpecker toy: (a) sleeve angle φ_M, (b) sleeve angular velocity ω_M.",
            runs,
            draw: |ctx, e| {
                pair(
                    ctx,
                    e,
                    "Fig 8.7  Woodpecker: sleeve rotation",
                    [
                        ("(a) sleeve angle", "φ_M [rad]", "phiM", 1, 1.0),
                        ("(b) sleeve angular velocity", "ω_M [rad/s]", "omegaM", 4, 1.0),
                    ],
                )
            },
        },
        Entry {
            id: "Fig 8.8",
            stem: "fig08_08_bird_angle",
            caption: "Woodpecker toy: (a) woodpecker angle φ_S, (b) woodpecker angular velocity ω_S.",
            runs,
            draw: |ctx, e| {
                pair(
                    ctx,
                    e,
                    "Fig 8.8  Woodpecker: body rotation",
                    [
                        ("(a) woodpecker angle", "φ_S [rad]", "phiS", 2, 1.0),
                        ("(b) woodpecker angular velocity", "ω_S [rad/s]", "omegaS", 5, 1.0),
                    ],
                )
            },
        },
        Entry {
            id: "Fig 8.9",
            stem: "fig08_09_phase",
            caption: "Woodpecker toy phase portraits: (a) sleeve ω_M vs φ_M, (b) woodpecker ω_S vs φ_S.",
            runs,
            draw: fig8_9,
        },
        Entry {
            id: "Fig 8.10",
            stem: "fig08_10_frames",
            caption: "Woodpecker toy over one period of the limit cycle: a frame at each change of the set \
                      of closed contacts and of stick/slip at contact 2 (lower sleeve edge); closed \
                      contacts are marked red. Contacts: 1 beak/pole, 2 lower sleeve edge, 3 upper \
                      sleeve edge. The animation (…_anim.svg) plays the same period.",
            runs,
            draw: fig8_10,
        },
    ]
}

/// Column `j` of the state (q then u), scaled.
fn state(run: &RunResult, j: usize, scale: f64) -> Vec<f64> {
    let f = run.record().q.width();
    let v = if j < f { run.q(j) } else { run.u(j - f) };
    v.into_iter().map(|x| x * scale).collect()
}

fn pair(
    ctx: &Ctx<'_>,
    e: &Entry,
    title: &str,
    panels: [(&str, &str, &str, usize, f64); 2],
) -> Result<Output> {
    let run = ctx.run(MAIN)?;
    let t = run.record().t.clone();
    let panels = panels
        .into_iter()
        .map(|(name, y_label, column, j, scale)| {
            Panel::new(name, "t [s]", y_label, "t").with(Series::line(
                "",
                column,
                t.clone(),
                state(run, j, scale),
                0,
            ))
        })
        .collect();
    let files = Figure::new(title, panels, 2).write(ctx.out, e.stem)?;
    Ok(Output { files: names(&files), key_numbers: json!(null), markdown: None })
}

fn fig8_9(ctx: &Ctx<'_>, e: &Entry) -> Result<Output> {
    let run = ctx.run(MAIN)?;
    let fig =
        Figure::new(
            "Fig 8.9  Woodpecker phase portraits",
            vec![
                Panel::new("(a) sleeve", "φ_M [rad]", "ω_M [rad/s]", "phiM").with(Series::line(
                    "",
                    "omegaM",
                    run.q(1),
                    run.u(1),
                    0,
                )),
                Panel::new("(b) woodpecker", "φ_S [rad]", "ω_S [rad/s]", "phiS")
                    .with(Series::line("", "omegaS", run.q(2), run.u(2), 1)),
            ],
            2,
        );
    let files = fig.write(ctx.out, e.stem)?;
    Ok(Output { files: names(&files), key_numbers: json!(keys::woodpecker(run)), markdown: None })
}

/// The 0-based listed index of the lower sleeve edge (contact 2 of the full model).
fn lower_edge(model: &AnyModel) -> Option<usize> {
    match model {
        AnyModel::Woodpecker(w) => w.contact_ids().iter().position(|&k| k == 1),
        _ => None,
    }
}

fn state_line(phase: &[ContactState]) -> String {
    phase
        .iter()
        .enumerate()
        .map(|(i, p)| format!("{} {}", i + 1, p.name()))
        .collect::<Vec<_>>()
        .join(" · ")
}

fn fig8_10(ctx: &Ctx<'_>, e: &Entry) -> Result<Output> {
    let run = ctx.run(MAIN)?;
    let k = keys::woodpecker(run);
    let cycle = k.cycle.as_ref().context("no limit cycle found in the woodpecker run")?;
    let r = run.record();
    let phases = run.states();
    let model = run.model();
    let lower = lower_edge(model);
    let closed = |k: usize| -> Vec<bool> { phases[k].iter().map(|p| p.is_closed()).collect() };
    let all_events = keys::events(run);
    // Rows at which the closed set or contact 2's stick/slip changes, within one period.
    let mut rows = vec![cycle.start_row];
    for row in cycle.start_row + 1..cycle.end_row {
        let set_changed = closed(row) != closed(row - 1);
        let lower_changed = lower.is_some_and(|i| phases[row][i] != phases[row - 1][i]);
        if set_changed || lower_changed {
            rows.push(row);
        }
    }
    let anim_rows = motion_rows(r, cycle.start, cycle.end, 48);
    let focus_of = |row: usize| {
        focus(&model.draw(&r.q[row], r.t[row]), &[Role::Pole]).unwrap_or([-0.01, -0.01, 0.01, 0.01])
    };
    let all_focus: Vec<[f64; 4]> =
        rows.iter().chain(&anim_rows).map(|&row| focus_of(row)).collect();
    let windows = follow(&all_focus, 0.12);
    let frames: Vec<Frame> = rows
        .iter()
        .zip(&windows)
        .map(|(&row, &window)| {
            let what: Vec<String> = all_events
                .iter()
                .filter(|ev| ev.row == row)
                .map(|ev| format!("{}: {}", ev.contact, ev.kind.name()))
                .collect();
            let caption = vec![
                format!("t = {:.4} s (+{:.1} ms)", r.t[row], 1e3 * (r.t[row] - cycle.start)),
                state_line(&phases[row]),
                if what.is_empty() { String::new() } else { what.join(", ") },
            ];
            Frame { window: Some(window), ..frame(model, r, row, caption) }
        })
        .collect();
    let strip = Strip {
        title: format!(
            "Fig 8.10  Woodpecker: one period of the limit cycle (T = {:.4} s)",
            cycle.period
        ),
        columns: frames.len().min(8),
        frames,
        cell_width: 220,
        cell_height: 260,
        window: None,
    };
    let anim: Vec<Frame> = anim_rows
        .iter()
        .zip(&windows[rows.len()..])
        .map(|(&row, &window)| {
            let caption = vec![format!("t = {:.4} s", r.t[row]), state_line(&phases[row])];
            Frame { window: Some(window), ..frame(model, r, row, caption) }
        })
        .collect();
    let files = strip.write(ctx.out, e.stem, &anim, cycle.period * 20.0 / 48.0)?;
    let frame_rows: Vec<serde_json::Value> =
        rows.iter().map(|&row| json!({"t": r.t[row], "state": state_line(&phases[row])})).collect();
    Ok(Output {
        files: names(&files),
        key_numbers: json!({"period": cycle.period, "descent_speed": k.descent_speed,
            "events": k.events, "frames": frame_rows}),
        markdown: None,
    })
}
