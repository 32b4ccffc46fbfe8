//! The cam with a flat-face follower: Figs 8.21 and 8.22.

use anyhow::{Result, bail};
use moreau_models::{AnyModel, CamParams, ModelKind, Role};
use serde_json::json;

use super::{Ctx, Entry, Output, focus, names};
use crate::analysis::ContactStateExt;
use crate::analysis::{self, EventKind};
use crate::frames::{Frame, Strip, frame, motion};
use crate::keys;
use crate::plot::{Figure, LegendAt, Mark, Panel, Series};
use crate::runs::{RunResult, RunSpec};

/// The cam run (Tab 8.5, Δt = 1e-4 s, three lobes).
pub(super) const MAIN: &str = "cam";

fn runs(_quick: bool) -> Vec<RunSpec> {
    vec![RunSpec::new(MAIN, ModelKind::Cam, &[("dt", "0.0001"), ("t_end", "0.15")])]
}

pub(super) fn entries() -> Vec<Entry> {
    vec![
        Entry {
            id: "Fig 8.21",
            stem: "fig08_21_cam",
            caption: "Cam with a translating flat-face follower (Tab 8.5: six lobes, ω = 20.94 rad/s, \
                      H = 17 mm, K_s = 240 N/mm, ε_N = 0.4, Δt = 1e-4 s), three lobe periods from the \
                      up-dead point: (a) follower displacement y with the cam lift s(t), (b) follower \
                      velocity v with the cam's ds/dt.",
            runs,
            draw: fig8_21,
        },
        Entry {
            id: "Fig 8.22",
            stem: "fig08_22_frames",
            caption: "Cam and follower during the first instants after the up-dead point: free fall, \
                      impact, rebounds and permanent contact (closed contact marked red). The animation \
                      (…_anim.svg) plays the first lobe period.",
            runs,
            draw: fig8_22,
        },
    ]
}

fn cam_params(run: &RunResult) -> Result<&CamParams> {
    match run.model() {
        AnyModel::Cam(c) => Ok(c.params()),
        _ => bail!("run {} is not a cam", run.spec.name),
    }
}

fn fig8_21(ctx: &Ctx<'_>, e: &Entry) -> Result<Output> {
    let run = ctx.run(MAIN)?;
    let p = cam_params(run)?;
    let t = run.record().t.clone();
    let y_mm: Vec<f64> = run.q(0).iter().map(|y| y * 1e3).collect();
    let s_mm: Vec<f64> = t.iter().map(|&t| p.lift(t) * 1e3).collect();
    let ds: Vec<f64> = t.iter().map(|&t| p.lift_rate(t)).collect();
    let fig = Figure::new(
        "Fig 8.21  Cam with flat-face follower",
        vec![
            Panel::new("(a) follower displacement", "t [s]", "y [mm]", "t")
                .with(Series::line("follower y", "y_mm", t.clone(), y_mm, 0))
                .with(
                    Series::line("cam lift s(t)", "s_mm", t.clone(), s_mm, 1)
                        .with_mark(Mark::Dashed),
                )
                .legend(LegendAt::LowerRight),
            Panel::new("(b) follower velocity", "t [s]", "v [m/s]", "t")
                .with(Series::line("follower v", "v", t.clone(), run.u(0), 0))
                .with(Series::line("cam ds/dt", "ds_dt", t, ds, 1).with_mark(Mark::Dashed))
                .legend(LegendAt::LowerRight),
        ],
        1,
    )
    .panel_size(1100, 380);
    let files = fig.write(ctx.out, e.stem)?;
    Ok(Output { files: names(&files), key_numbers: json!(keys::cam(run)), markdown: None })
}

fn fig8_22(ctx: &Ctx<'_>, e: &Entry) -> Result<Output> {
    let run = ctx.run(MAIN)?;
    let p = cam_params(run)?;
    let r = run.record();
    let period = p.lobe_period();
    let phase: Vec<_> = run.states().iter().map(|ph| ph[0]).collect();
    let gap: Vec<f64> = run.gaps().iter().map(|g| g[0]).collect();
    let gamma: Vec<f64> = run.gamma_pre().iter().map(|g| g[0]).collect();
    let lobe_rows = r.t.iter().take_while(|&&t| t < period).count().max(2);
    // Impacts, rebound apexes and the start of permanent contact in the first lobe.
    let hits: Vec<usize> = (1..lobe_rows)
        .filter(|&k| {
            analysis::classify(phase[k - 1], phase[k], gamma[k], run.impact_speed())
                == Some(EventKind::Impact)
        })
        .collect();
    let mut picks: Vec<(usize, String)> = vec![(0, "drop: free fall".to_owned())];
    if let Some(&h) = hits.first() {
        picks.push((h / 2, "free fall".to_owned()));
    }
    // The first three impacts with the apex of the rebound after each, then the last impact.
    for (j, &h) in hits.iter().enumerate() {
        if j >= 3 && j + 1 < hits.len() {
            continue;
        }
        picks.push((h, format!("impact {}", j + 1)));
        let next = hits.get(j + 1).copied().unwrap_or(lobe_rows);
        let flight: Vec<usize> = (h + 1..next).take_while(|&k| !phase[k].is_closed()).collect();
        if let Some(&apex) = flight.iter().max_by(|&&a, &&b| gap[a].total_cmp(&gap[b]))
            && j < 3
        {
            picks.push((apex, format!("rebound {} apex", j + 1)));
        }
    }
    let lobes = keys::cam(run).lobes;
    if let Some(tc) = lobes.first().and_then(|l| l.time_to_contact)
        && let Some(k) = r.t.iter().position(|&t| t >= tc)
    {
        picks.push((k, "permanent contact".to_owned()));
    }
    picks.sort_by_key(|(k, _)| *k);
    // Several labels on one row become one frame.
    let mut merged: Vec<(usize, String)> = Vec::new();
    for (k, what) in picks {
        match merged.last_mut() {
            Some((last, text)) if *last == k => {
                text.push_str(", ");
                text.push_str(&what);
            }
            _ => merged.push((k, what)),
        }
    }
    let picks = merged;
    let model = run.model();
    let frames: Vec<Frame> = picks
        .iter()
        .map(|(k, what)| {
            let caption = vec![
                format!("t = {:.1} ms", 1e3 * r.t[*k]),
                what.clone(),
                format!("g_N = {:.3} mm", 1e3 * gap[*k]),
            ];
            frame(model, r, *k, caption)
        })
        .collect();
    let last = picks.last().map_or(0.0, |(k, _)| r.t[*k]);
    // Zoom on the follower's face and the top of the cam: the follower's width, from below its
    // lowest face position to a little above its highest.
    let faces: Vec<[f64; 4]> = picks
        .iter()
        .filter_map(|(k, _)| {
            focus(
                &model.draw(&r.q[*k], r.t[*k]),
                &[Role::Cam, Role::Ground, Role::Guide, Role::ContactPoint],
            )
        })
        .collect();
    let window = faces
        .iter()
        .copied()
        .reduce(|a, b| [a[0].min(b[0]), a[1].min(b[1]), a[2].max(b[2]), a[3].max(b[3])])
        .map(|f| {
            let w = f[2] - f[0];
            let top = faces.iter().map(|g| g[1]).fold(f64::NEG_INFINITY, f64::max);
            [f[0] - 0.05 * w, f[1] - 0.35 * w, f[2] + 0.05 * w, top + 0.3 * w]
        });
    let strip = Strip {
        title: "Fig 8.22  Cam and follower after the up-dead point".to_owned(),
        columns: frames.len().min(5),
        frames,
        cell_width: 260,
        cell_height: 200,
        window,
    };
    let anim = motion(model, r, 0.0, period, 50);
    let files = strip.write(ctx.out, e.stem, &anim, 0.08)?;
    let rebound: Vec<f64> = lobes.first().map(|l| l.rebound_heights.clone()).unwrap_or_default();
    Ok(Output {
        files: names(&files),
        key_numbers: json!({
            "frames": picks.iter().map(|(k, w)| json!({"t": r.t[*k], "what": w})).collect::<Vec<_>>(),
            "impacts_first_lobe": hits.len(),
            "rebound_heights_first_lobe": rebound,
            "time_to_permanent_contact": lobes.first().and_then(|l| l.time_to_contact),
            "last_frame_time": last,
            "lobe_period": period,
            "lobes": lobes.len(),
            "impacts_per_lobe": lobes.iter().map(|l| l.impacts).collect::<Vec<_>>(),
        }),
        markdown: None,
    })
}
