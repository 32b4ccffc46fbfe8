//! `cargo xtask frames`: pictures of any scene, a report model's or a declared mechanism's: a
//! strip of frames at chosen instants (SVG and PNG) and an animated SVG of the whole run.
//!
//! The scene runs under the `moreau` command's guards (the same run as `simulate`), and its
//! frames are drawn by [`crate::frames::frame`] like the report's strips.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail, ensure};
use clap::Args;
use moreau_stepper::ContactState;

use crate::frames::{Frame, Strip, frame, motion, motion_rows};
use crate::network;
use crate::runs::RunResult;
use crate::simulate::{self, SimulateOptions};

/// Frames of the strip when neither `--times` nor `--count` is given.
pub const DEFAULT_COUNT: usize = 6;

/// Frames of the animation.
pub const ANIMATION_FRAMES: usize = 60;

/// Most frames of a strip (17 rows of six): a larger strip would be an image of gigabytes.
pub const MAX_FRAMES: usize = 100;

/// Arguments of `frames`.
#[derive(Args, Clone, Debug)]
pub struct FramesArgs {
    /// Model (ball, woodpecker, ...); optional with --scene, which names the model or
    /// declares the mechanism.
    pub model: Option<String>,
    /// Scene file (TOML): a report model's or a declared mechanism's.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Override a scene key: --set key=value (repeatable; each entry once).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Instants of the strip's frames (s), comma-separated, within the run (at most 100).
    #[arg(long, value_delimiter = ',', conflicts_with = "count")]
    pub times: Option<Vec<f64>>,
    /// Number of the strip's frames, evenly spaced from t = 0 to the end of the run
    /// (default 6, at most 100).
    #[arg(long)]
    pub count: Option<usize>,
    /// Output folder (created when missing).
    #[arg(long, default_value = "target/frames")]
    pub out: PathBuf,
    /// Draw the strip's and the animation's frames as force networks (declared scenes): each
    /// contact of the step ending at the frame's row a line between the bodies' centres of
    /// mass, as wide as its normal impulse.
    #[arg(long)]
    pub forces: bool,
}

impl FramesArgs {
    /// Runs `frames`, printing the files written.
    ///
    /// # Errors
    /// As [`run`].
    pub fn run(self) -> Result<()> {
        let files = run(&self)?;
        for f in &files {
            println!("wrote {}", f.display());
        }
        Ok(())
    }
}

/// The file stem of the pictures: the scene file's stem, or the model's name.
fn stem(args: &FramesArgs) -> String {
    args.scene
        .as_deref()
        .and_then(Path::file_stem)
        .map(|s| s.to_string_lossy().into_owned())
        .or_else(|| args.model.clone())
        .unwrap_or_else(|| "scene".to_owned())
}

/// Runs the scene and writes `<stem>.svg`, `<stem>.png` (the strip) and `<stem>_anim.svg`
/// (the animation) into the output folder; returns their paths.
///
/// # Errors
/// The errors of the run (as `simulate`: no model, a model that disagrees with the scene file,
/// unknown keys, a refused step plan, divergence); a time outside the run or not finite, a
/// count of zero, more than [`MAX_FRAMES`] frames; an unwritable output (refused before the
/// run).
pub fn run(args: &FramesArgs) -> Result<Vec<PathBuf>> {
    crate::reproduce::writable(&args.out).context("--out")?;
    let options = SimulateOptions {
        model: args.model.clone(),
        scene: args.scene.clone(),
        sets: args.sets.clone(),
        ..SimulateOptions::default()
    };
    let result = simulate::run(&options)?;
    let rows = rows(&result, args.times.as_deref(), args.count)?;
    let stem = stem(args);
    let mut strip = strip(&result, &stem, &rows);
    let r = result.record();
    let end = r.t.last().copied().unwrap_or(0.0);
    let anim = if args.forces {
        // The strip's and the animation's networks from one second run; the animation keeps
        // one window for all its frames.
        let moving = motion_rows(r, 0.0, end, ANIMATION_FRAMES);
        let mut all = networks(&result, &[rows.as_slice(), moving.as_slice()].concat())?;
        let anim: Vec<Frame> = all.split_off(rows.len());
        strip.frames = all;
        strip.title = format!("{} (force networks)", strip.title);
        anim.into_iter().map(|f| Frame { window: None, ..f }).collect()
    } else {
        motion(result.model(), r, 0.0, end, ANIMATION_FRAMES)
    };
    // The animation plays in real time, within 1/25 s and 1/2 s a frame.
    let frame_seconds = (end / (ANIMATION_FRAMES - 1) as f64).clamp(0.04, 0.5);
    strip.write(&args.out, &stem, &anim, frame_seconds)
}

/// The force networks of the steps that end at the record's `rows`, from a second run of the
/// scene (bit for bit the first): row k > 0 ends step k · record_every − 1, and the last row
/// the run's last step (which a stop rule may end between two thinned rows); row 0, the
/// initial state, shows the bodies alone.
///
/// # Errors
/// A scene that does not declare its bodies; a row whose step ends at another time than the
/// row's; a failed step.
pub fn networks(result: &RunResult, rows: &[usize]) -> Result<Vec<Frame>> {
    let (scene, r) = (&result.scene, result.record());
    let every = scene.record_every.max(1) as u64;
    let last_row = r.len().saturating_sub(1);
    let step_of = |k: usize| {
        (k > 0).then(|| if k == last_row { result.sim.steps - 1 } else { k as u64 * every - 1 })
    };
    let mut stepper = scene.stepper()?;
    let (dt, margin) = (stepper.options().dt, stepper.options().gap_tolerance);
    let caption = |t: f64, carrying: usize| {
        vec![format!("t = {t:.4} s"), format!("{carrying} contacts carry an impulse")]
    };
    // Row 0 (in the strip and the animation alike) is drawn once.
    let initial = if rows.contains(&0) {
        let state = (stepper.q(), stepper.u(), stepper.t());
        let mechanism = stepper.mechanism();
        Some(network::frame(mechanism, state, 0.0, margin, &[], &[], caption(r.t[0], 0))?)
    } else {
        None
    };
    let mut frames: Vec<Option<Frame>> =
        rows.iter().map(|&k| if k == 0 { initial.clone() } else { None }).collect();
    let last = rows.iter().filter_map(|&k| step_of(k)).max();
    for s in 0..last.map_or(0, |l| l + 1) {
        let wanted: Vec<usize> = (0..rows.len()).filter(|&i| step_of(rows[i]) == Some(s)).collect();
        // The step's start, kept only for a step that is drawn.
        let start =
            (!wanted.is_empty()).then(|| (stepper.q().to_vec(), stepper.u().to_vec(), stepper.t()));
        let report = stepper.step()?;
        let Some((q_a, u_a, t_a)) = start else { continue };
        let (ids, contacts) = (report.contact_ids.to_vec(), report.contacts.to_vec());
        let t = report.t;
        let carrying = contacts.iter().filter(|c| c.p_n > 0.0).count();
        for i in wanted {
            let row_t = r.t[rows[i]];
            ensure!(
                (t - row_t).abs() <= 1e-6 * dt,
                "row {} at t = {row_t} s is not the end of step {s} (t = {t} s)",
                rows[i]
            );
            let state = (q_a.as_slice(), u_a.as_slice(), t_a);
            let model = stepper.mechanism();
            frames[i] = Some(network::frame(
                model,
                state,
                dt,
                margin,
                &ids,
                &contacts,
                caption(row_t, carrying),
            )?);
        }
    }
    frames.into_iter().map(|f| f.context("a row without its step")).collect()
}

/// The rows of the strip: the row nearest each of `times`, or `count` rows evenly spaced
/// over the run ([`DEFAULT_COUNT`] when neither is given).
///
/// # Errors
/// A time that is not finite or lies outside the run; a count of zero; more than
/// [`MAX_FRAMES`] frames.
pub fn rows(result: &RunResult, times: Option<&[f64]>, count: Option<usize>) -> Result<Vec<usize>> {
    let frames = times.map_or(count.unwrap_or(DEFAULT_COUNT), <[f64]>::len);
    ensure!(
        frames <= MAX_FRAMES,
        "{frames} frames asked for ({}): a strip holds at most {MAX_FRAMES}",
        if times.is_some() { "--times" } else { "--count" }
    );
    let t = &result.record().t;
    let (first, last) = match (t.first(), t.last()) {
        (Some(&a), Some(&b)) => (a, b),
        _ => bail!("the run has no rows"),
    };
    let times: Vec<f64> = match times {
        Some(times) => {
            for &s in times {
                ensure!(
                    s.is_finite() && s >= first && s <= last + 1e-9,
                    "--times: t = {s} s lies outside the run (0 to {last} s)"
                );
            }
            times.to_vec()
        }
        None => {
            let n = count.unwrap_or(DEFAULT_COUNT);
            ensure!(n > 0, "--count must be at least 1");
            let step = if n == 1 { 0.0 } else { (last - first) / (n - 1) as f64 };
            (0..n).map(|j| first + step * j as f64).collect()
        }
    };
    Ok(times
        .iter()
        .map(|&s| {
            // The first row at or after s, or the one before it when that is nearer.
            let k = t.partition_point(|&tk| tk < s).min(t.len() - 1);
            if k > 0 && (s - t[k - 1]).abs() < (t[k] - s).abs() { k - 1 } else { k }
        })
        .collect())
}

/// A caption line of the contacts closed in a row, at most three named: `stick` or `slip`
/// for a contact still closed at the row's end, `impact` for one that closed within the row and
/// opened again (an impact with rebound).
fn contacts_line(names: &[String], active: &[bool], states: &[ContactState]) -> String {
    let closed: Vec<String> = names
        .iter()
        .zip(active)
        .zip(states)
        .filter(|((_, a), s)| **a || **s != ContactState::Open)
        .map(|((n, _), s)| {
            let what = match s {
                ContactState::Stick => "stick",
                ContactState::Slip => "slip",
                _ => "impact",
            };
            format!("{n} {what}")
        })
        .collect();
    match closed.len() {
        0 => "contacts open".to_owned(),
        1..=3 => closed.join(" · "),
        n => format!("{} · +{} more closed", closed[..3].join(" · "), n - 3),
    }
}

/// The strip of a run at `rows`, titled after `name`: each frame captioned with its time and
/// the contacts closed in its row.
pub fn strip(result: &RunResult, name: &str, rows: &[usize]) -> Strip {
    let (model, r) = (result.model(), result.record());
    let names = model.contact_names();
    let frames: Vec<Frame> = rows
        .iter()
        .map(|&k| {
            let (active, states) = (r.active.get(k).unwrap_or(&[]), r.state.get(k).unwrap_or(&[]));
            let line = contacts_line(&names, active, states);
            let caption = vec![format!("t = {:.4} s", r.t[k]), line];
            frame(model, r, k, caption)
        })
        .collect();
    Strip {
        title: format!("{name} ({}, Δt = {:e} s)", model.kind(), result.scene.dt),
        columns: frames.len().clamp(1, 6),
        frames,
        cell_width: 240,
        cell_height: 240,
        window: None,
    }
}
