//! `cargo xtask frames`: pictures of any scene, a report model's or a declared mechanism's: a
//! strip of frames at chosen instants (SVG and PNG) and an animated SVG of the whole run.
//!
//! The scene runs under the `moreau` command's guards (the same run as `simulate`), and its
//! frames are drawn by [`crate::frames::frame`] like the report's strips.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail, ensure};
use clap::Args;
use moreau_models::AnyModel;
use moreau_stepper::{ContactState, Record};

use crate::frames::{Frame, Strip, closed_in_row, detected_contacts, frame, motion, motion_rows};
use crate::network;
use crate::runs::RunResult;
use crate::simulate::{self, SimulateOptions};

/// Frames of the strip when neither `--times` nor `--count` is given.
pub const DEFAULT_COUNT: usize = 6;

/// Frames of the animation.
pub const ANIMATION_FRAMES: usize = 60;

/// Most frames of a strip (17 rows of six): a larger strip would be an image of gigabytes.
pub const MAX_FRAMES: usize = 100;

/// Why `frames` refuses the strip's instants.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum FramesError {
    /// `--times` was given no instant.
    NoTimes,
    /// `--count 0`.
    ZeroCount,
    /// More evenly spaced frames than the record has rows to draw them from.
    CountAboveRows {
        /// Frames asked for.
        count: usize,
        /// Rows of the record.
        rows: usize,
    },
    /// More frames than a strip holds.
    TooManyFrames {
        /// Frames asked for.
        frames: usize,
        /// The option that asked for them: `--times` or `--count`.
        option: &'static str,
    },
    /// An instant that is not finite or lies outside the run's rows.
    OutsideRun {
        /// The instant (s).
        t: f64,
        /// Time of the run's first row (s).
        first: f64,
        /// Time of the run's last row (s).
        last: f64,
        /// The scene's end time (s); above `last` when a stop rule ended the run earlier.
        t_end: f64,
    },
    /// An instant not later than the one before it.
    NotIncreasing {
        /// The earlier instant in the list (s).
        before: f64,
        /// The instant that follows it (s).
        t: f64,
    },
    /// Two instants drawn from the same row of the record, which would give two equal frames.
    SameRow {
        /// The first instant (s).
        before: f64,
        /// The second (s).
        t: f64,
        /// Time of the row both fall on (s).
        row_t: f64,
        /// The spacing of the record's rows (s): `record_every` Δt.
        spacing: f64,
    },
}

impl std::fmt::Display for FramesError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Self::NoTimes => write!(f, "--times: no instant given"),
            Self::ZeroCount => write!(f, "--count must be at least 1"),
            Self::CountAboveRows { count, rows } => write!(
                f,
                "--count {count}: the record has {rows} rows, too few for {count} distinct \
                 evenly spaced frames; lower the count or record_every"
            ),
            Self::TooManyFrames { frames, option } => {
                write!(
                    f,
                    "{frames} frames asked for ({option}): a strip holds at most {MAX_FRAMES}"
                )
            }
            Self::OutsideRun { t, first, last, t_end } => {
                write!(f, "--times: t = {t} s lies outside the run ({first} to {last} s)")?;
                if last < t_end {
                    write!(f, ", which its stop rule ended before t_end = {t_end} s")?;
                }
                Ok(())
            }
            Self::NotIncreasing { before, t } => write!(
                f,
                "--times: t = {t} s follows t = {before} s; give the instants in increasing \
                 order, each once"
            ),
            Self::SameRow { before, t, row_t, spacing } => write!(
                f,
                "--times: t = {before} s and t = {t} s are both drawn from the row at t = {row_t} s \
                 (the record keeps a row every {spacing} s)"
            ),
        }
    }
}

impl std::error::Error for FramesError {}

/// Arguments of `frames`.
#[derive(Args, Clone, Debug)]
pub struct FramesArgs {
    /// Model (ball, woodpecker, ...); optional with --scene, which names the model or
    /// declares the mechanism.
    pub model: Option<String>,
    /// Scene file (TOML): a report model's or a declared mechanism's.
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Override a scene key: --set key=value (repeatable; each entry once; in order, the
    /// scene validated once all are applied).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub sets: Vec<String>,
    /// Instants of the strip's frames (s), comma-separated, increasing, within the run (at most
    /// 100), each drawn from its own row of the record.
    #[arg(long, value_delimiter = ',', conflicts_with = "count", allow_hyphen_values = true)]
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
/// (the animation) into the output folder, after removing those of an earlier run; returns
/// their paths.
///
/// # Errors
/// The errors of the run (as `simulate`: no model, a model that disagrees with the scene file,
/// unknown keys, a refused step plan, divergence); the instants' [`FramesError`]s (see
/// [`rows`]); an unwritable output (refused before the run).
pub fn run(args: &FramesArgs) -> Result<Vec<PathBuf>> {
    crate::reproduce::writable(&args.out).context("--out")?;
    // Pictures of an earlier run of the scene are removed first, so that a run that fails
    // leaves none to be taken for its own.
    let stem = stem(args);
    for name in [format!("{stem}.svg"), format!("{stem}.png"), format!("{stem}_anim.svg")] {
        let path = args.out.join(name);
        if path.is_file() {
            std::fs::remove_file(&path).with_context(|| format!("removing {}", path.display()))?;
        }
    }
    let options = SimulateOptions {
        model: args.model.clone(),
        scene: args.scene.clone(),
        sets: args.sets.clone(),
        ..SimulateOptions::default()
    };
    let result = simulate::run(&options)?;
    let rows = rows(&result, args.times.as_deref(), args.count)?;
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
/// A [`FramesError`]: no time; a time that is not finite or lies outside the run; times not
/// in increasing order or two on the same row; a count of zero or too large for the record's
/// rows; more than [`MAX_FRAMES`] frames.
pub fn rows(result: &RunResult, times: Option<&[f64]>, count: Option<usize>) -> Result<Vec<usize>> {
    let frames = times.map_or(count.unwrap_or(DEFAULT_COUNT), <[f64]>::len);
    let option = if times.is_some() { "--times" } else { "--count" };
    if frames > MAX_FRAMES {
        return Err(FramesError::TooManyFrames { frames, option }.into());
    }
    let t = &result.record().t;
    let (first, last) = match (t.first(), t.last()) {
        (Some(&a), Some(&b)) => (a, b),
        _ => bail!("the run has no rows"),
    };
    let t_end = result.scene.t_end;
    // The row at or after s, or the one before it when that is nearer.
    let nearest = |s: f64| {
        let k = t.partition_point(|&tk| tk < s).min(t.len() - 1);
        if k > 0 && (s - t[k - 1]).abs() < (t[k] - s).abs() { k - 1 } else { k }
    };
    match times {
        Some([]) => Err(FramesError::NoTimes.into()),
        Some(times) => {
            let slack = 1e-9 * (last - first).abs().max(result.scene.dt);
            let mut rows: Vec<usize> = Vec::with_capacity(times.len());
            for (j, &s) in times.iter().enumerate() {
                if !(s.is_finite() && s >= first - slack && s <= last + slack) {
                    return Err(FramesError::OutsideRun { t: s, first, last, t_end }.into());
                }
                let k = nearest(s);
                if j > 0 {
                    let before = times[j - 1];
                    if s <= before {
                        return Err(FramesError::NotIncreasing { before, t: s }.into());
                    }
                    if rows[j - 1] == k {
                        let spacing = result.scene.dt * result.scene.record_every.max(1) as f64;
                        let row_t = t[k];
                        return Err(FramesError::SameRow { before, t: s, row_t, spacing }.into());
                    }
                }
                rows.push(k);
            }
            Ok(rows)
        }
        None => {
            let n = count.unwrap_or(DEFAULT_COUNT);
            if n == 0 {
                return Err(FramesError::ZeroCount.into());
            }
            let step = if n == 1 { 0.0 } else { (last - first) / (n - 1) as f64 };
            let rows: Vec<usize> = (0..n).map(|j| nearest(first + step * j as f64)).collect();
            if rows.windows(2).any(|w| w[0] == w[1]) {
                return Err(FramesError::CountAboveRows { count: n, rows: t.len() }.into());
            }
            Ok(rows)
        }
    }
}

/// A caption line of the contacts closed in a row, at most three named: `stick` or `slip`
/// for a contact still closed at the row's end, `impact` for one that closed within the row and
/// opened again (an impact with rebound), `closed` in row 0, before any step.
fn contacts_line(names: &[String], closed: &[bool], states: &[ContactState], row: usize) -> String {
    let closed: Vec<String> = names
        .iter()
        .zip(closed)
        .enumerate()
        .filter(|(_, (_, c))| **c)
        .map(|(i, (n, _))| {
            let what = match states.get(i) {
                _ if row == 0 => "closed",
                Some(ContactState::Stick) => "stick",
                Some(ContactState::Slip) => "slip",
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

/// The caption line of the contacts closed in row `row`: those of the record's contact list
/// ([`contacts_line`]), or, for a mechanism whose contacts are detected at each step, how many
/// the detection finds closed at the row's state.
fn row_contacts_line(model: &AnyModel, r: &Record, row: usize) -> String {
    match detected_contacts(model, &r.q[row], r.t[row]) {
        Some(points) if points.is_empty() => "contacts open".to_owned(),
        Some(points) if points.len() == 1 => "1 contact closed".to_owned(),
        Some(points) => format!("{} contacts closed", points.len()),
        None => {
            let states = r.state.get(row).unwrap_or(&[]);
            let closed = closed_in_row(model, r, row);
            contacts_line(&model.contact_names(), &closed, states, row)
        }
    }
}

/// The strip of a run at `rows`, titled after `name`: each frame captioned with its time and
/// the contacts closed in its row.
pub fn strip(result: &RunResult, name: &str, rows: &[usize]) -> Strip {
    let (model, r) = (result.model(), result.record());
    let frames: Vec<Frame> = rows
        .iter()
        .map(|&k| {
            let caption = vec![format!("t = {:.4} s", r.t[k]), row_contacts_line(model, r, k)];
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
