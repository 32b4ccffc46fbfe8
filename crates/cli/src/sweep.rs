//! `moreau sweep`: the Cartesian product of parameter values, run in parallel under the
//! guards, one CSV row of key numbers per member, written as each member finishes.

use std::collections::{BTreeSet, HashSet};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use anyhow::{Context, Result};
use moreau_models::{AnyModel, ModelError, Scene};
use rayon::prelude::*;

use crate::error::CliError;
use crate::failed::{self, failed_problem_path};
use crate::grid::{self, Axis, Grid, Progress, Shard};
use crate::guard::{self, DEFAULT_MAX_STEPS};
use crate::keys;
use crate::number;
use crate::output::{self, Output, OutputLock, suffixed};
use crate::parts::{self, PartHeader, fnv64, row_check};
use crate::runs::{RunResult, RunSpec, run_info};
use crate::simulate::{apply_sets, base_scene, check_record_every, run_scene};

/// The most members one run of a sweep (its shard) may hold: a larger run is refused before
/// anything is checked or run ([`CliError::SweepTooLarge`]), and is split with `--shard`.
/// Each member's scene is checked before the first runs, and the rows are read back and
/// sorted in memory at the end: 10⁶ members of the ball take 1.5 GB there.
pub const MAX_MEMBERS: u64 = 1_000_000;

/// Members checked at once, in parallel, before the first runs.
const CHECK_CHUNK: usize = 4096;

/// What to sweep.
#[derive(Clone, Debug)]
pub struct SweepOptions {
    /// Model name; `None` to take the model from the scene file. When both are given they
    /// must agree.
    pub model: Option<String>,
    /// A scene file to start from instead of the model's report scene: a report model's or a
    /// declared mechanism's.
    pub scene: Option<PathBuf>,
    /// The swept parameters (`key=v1,v2,...`), each scene entry at most once.
    pub axes: Vec<Axis>,
    /// A CSV file listing members ([`grid::members_file_axes`]): its columns come before
    /// `axes` in the product, its rows outermost.
    pub members: Option<PathBuf>,
    /// Run only this part of the members.
    pub shard: Option<Shard>,
    /// The largest number of steps of a member; [`DEFAULT_MAX_STEPS`] when `None`.
    pub max_steps: Option<u64>,
    /// Continue the unfinished run `<out>.partial` of the same sweep instead of starting anew.
    pub resume: bool,
}

impl SweepOptions {
    /// A sweep of `model` over `axes`, all members, default limits, not resumed.
    pub fn new(model: &str, axes: Vec<Axis>) -> Self {
        Self {
            model: Some(model.to_owned()),
            scene: None,
            axes,
            members: None,
            shard: None,
            max_steps: None,
            resume: false,
        }
    }

    /// A sweep of the scene file `scene` (a report model's or a declared mechanism's) over
    /// `axes`, all members, default limits, not resumed.
    pub fn scene(scene: &Path, axes: Vec<Axis>) -> Self {
        Self {
            model: None,
            scene: Some(scene.to_owned()),
            axes,
            members: None,
            shard: None,
            max_steps: None,
            resume: false,
        }
    }
}

/// The CSV columns of a sweep: `member`, `members`, the swept keys as given (`eps_n`,
/// `bodies.block.mass`, ...), the model's key numbers ([`keys::columns_of`]), `steps`,
/// `lcp_solves`, `inexact_steps` (steps taken with an island above the solvers' tolerance, as
/// the scene's `inexact_residual` allows), `wall_seconds`, `status`, `error` and the row's
/// `check`.
pub fn header(model: &AnyModel, axes: &[Axis]) -> Vec<String> {
    let mut h = vec!["member".to_owned(), "members".to_owned()];
    h.extend(axes.iter().map(|a| a.key.clone()));
    h.extend(keys::columns_of(model));
    h.extend(
        ["steps", "lcp_solves", "inexact_steps", "wall_seconds", "status", "error", "check"]
            .map(str::to_owned),
    );
    h
}

/// A key number's cell: empty when it is not defined or not finite.
fn cell(x: Option<f64>) -> String {
    match x {
        Some(v) if v.is_finite() => number::text(v),
        _ => String::new(),
    }
}

/// A wall time's cell: to the microsecond.
fn seconds(s: f64) -> String {
    number::text((s * 1e6).round() / 1e6)
}

/// The id of a sweep: a hash of the model, the base scene, the axes, the step limit and the
/// program's version (see [`parts`]).
///
/// # Errors
/// [`Scene::to_toml_string`]'s, for a base scene that TOML cannot hold.
pub fn sweep_id(base: &Scene, axes: &[Axis], max_steps: u64) -> Result<String, ModelError> {
    let mut text = format!(
        "format {}\nmoreau {}\nmodel {}\nmax_steps {max_steps}\n{}\n",
        parts::FORMAT,
        env!("CARGO_PKG_VERSION"),
        base.kind(),
        base.to_toml_string()?
    );
    for a in axes {
        text.push_str(&format!("axis {}\n", a.text()));
    }
    Ok(format!("{:016x}", fnv64(text.as_bytes())))
}

/// What a sweep did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub struct SweepSummary {
    /// Rows in the output (members of the shard).
    pub rows: u64,
    /// Members run now (the others were finished by an earlier run and kept).
    pub ran: u64,
    /// Members of the output the divergence guard stopped (`status` `diverged`), whether run
    /// now or kept from an earlier run.
    pub diverged: u64,
    /// Members of the output whose run failed otherwise (`status` `failed`).
    pub failed: u64,
    /// Whether the output held this sweep's finished part already (with `resume`): nothing
    /// was left to run, and the file was left as it was.
    pub finished_before: bool,
    /// Whether resuming dropped the unfinished part's damaged last line (a row cut off while
    /// it was written, or altered since), whose member was run again.
    pub dropped_damaged_row: bool,
}

impl SweepSummary {
    /// The summary of the finished rows of a part with `columns`, of which `ran` were run
    /// now.
    pub(crate) fn of_rows(columns: &[String], rows: &[Vec<String>], ran: u64) -> Self {
        let status = columns.iter().position(|c| c == "status");
        let count = |s: &str| {
            rows.iter().filter(|r| status.and_then(|k| r.get(k)).is_some_and(|v| v == s)).count()
                as u64
        };
        SweepSummary {
            rows: rows.len() as u64,
            ran,
            diverged: count("diverged"),
            failed: count("failed"),
            finished_before: false,
            dropped_damaged_row: false,
        }
    }

    /// Ok when no member of the output diverged or failed; otherwise
    /// [`CliError::MembersFailed`] for the output `out` (whose rows are all written).
    pub(crate) fn members_ok(&self, out: PathBuf) -> Result<(), CliError> {
        if self.diverged + self.failed == 0 {
            return Ok(());
        }
        Err(CliError::MembersFailed {
            out,
            rows: self.rows,
            diverged: self.diverged,
            failed: self.failed,
        })
    }
}

/// Builds member `i`'s scene and checks its step plan.
fn member_scene(base: &Scene, grid: &Grid, i: u64, max_steps: u64) -> Result<Scene> {
    let mut scene = base.clone();
    apply_sets(&mut scene, &grid.member(i)).with_context(|| format!("member {i}"))?;
    let steps = guard::plan_steps(&scene, max_steps).with_context(|| format!("member {i}"))?;
    check_record_every(&scene, steps).with_context(|| format!("member {i}"))?;
    keys::check_thinning(&scene).with_context(|| format!("member {i}"))?;
    Ok(scene)
}

/// Runs one member and returns its row (without the check); `columns` are the key-number
/// columns of the base scene. A declared member whose bodies or contacts differ from the base
/// scene's (a `fill.<name>.count` swept, say) fills the columns it shares with it by name
/// ([`aligned`]) and leaves the others empty, so that no number moves under another name. A
/// member that stops on a step problem writes it to `<out>.member-<i>.failed.dat`
/// ([`failed::with_failed_problem`]), and its error says so.
fn member_row(
    scene: &Scene,
    columns: &[String],
    grid: &Grid,
    i: u64,
    max_steps: u64,
    out: &Path,
) -> Vec<String> {
    let kind = scene.kind();
    let mut row = vec![i.to_string(), grid.len().to_string()];
    row.extend(grid.member(i).into_iter().map(|(_, v)| v));
    let start = Instant::now();
    let empty = |row: &mut Vec<String>| row.extend(columns.iter().map(|_| String::new()));
    let numbers = || -> Result<Vec<String>> {
        let sim = run_scene(scene, max_steps)?;
        let spec = RunSpec { name: format!("member {i}"), kind, sets: grid.member(i) };
        let info = run_info(&spec.name, scene, &sim);
        let result = RunResult { spec, scene: scene.clone(), sim, info };
        let own = keys::columns_of(result.model());
        let values = aligned(columns, &own, keys::row(&result));
        let mut cells: Vec<String> = values.into_iter().map(cell).collect();
        cells.push(result.sim.steps.to_string());
        cells.push(result.sim.lcp_solves.to_string());
        cells.push(result.sim.inexact_steps.to_string());
        cells.push(seconds(result.sim.wall_seconds));
        cells.extend(["ok".to_owned(), String::new()]);
        Ok(cells)
    };
    match unwound(numbers) {
        Ok(cells) => row.extend(cells),
        Err(e) => {
            let status = match e.downcast_ref::<CliError>() {
                Some(CliError::Diverged { .. }) => "diverged",
                _ => "failed",
            };
            let member = suffixed(out, &format!(".member-{i}"));
            let e = failed::with_failed_problem(e, &failed_problem_path(&member));
            empty(&mut row);
            row.extend([String::new(), String::new(), String::new()]);
            row.push(seconds(start.elapsed().as_secs_f64()));
            row.extend([status.to_owned(), format!("{e:#}")]);
        }
    }
    row
}

/// A member's key numbers `values`, under its own columns `own`, placed under the base scene's
/// `columns`: as they are when the columns are the same, else by name, a column the member
/// does not have left empty and a member's column the base scene does not have left out.
fn aligned(columns: &[String], own: &[String], values: Vec<Option<f64>>) -> Vec<Option<f64>> {
    if own == columns {
        return values;
    }
    let by_name: std::collections::HashMap<&str, Option<f64>> =
        own.iter().map(String::as_str).zip(values).collect();
    columns.iter().map(|c| by_name.get(c.as_str()).copied().flatten()).collect()
}

/// The result of `run`, or, if it panics, an error that carries the panic's message: the
/// member's row then records the failure and the sweep goes on with the other members.
fn unwound<T>(run: impl FnOnce() -> Result<T>) -> Result<T> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(run)).unwrap_or_else(|payload| {
        let message = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "no message".into());
        Err(anyhow::anyhow!(
            "the member's run stopped on an internal error (a panic: {message}); its other \
             numbers are not known"
        ))
    })
}

/// Why the existing `partial` of a sweep `identity` run without `--resume` is not written
/// over: an unfinished run of this sweep, which `--resume` continues, or a file that it would
/// not continue (another sweep's or shard's unfinished run, or not a sweep's at all).
fn partial_reason(partial: &Path, identity: &PartHeader) -> String {
    let first = std::fs::File::open(partial).ok().and_then(|f| {
        let mut line = String::new();
        std::io::BufRead::read_line(&mut std::io::BufReader::new(f), &mut line).ok()?;
        Some(line)
    });
    let first = first.unwrap_or_default();
    match PartHeader::parse(first.trim_end_matches(['\n', '\r'])) {
        Ok(h) if h == *identity => {
            "holds an unfinished run of this sweep; pass --resume to continue it, or remove it"
                .into()
        }
        Ok(h) => format!(
            "holds an unfinished run of another sweep or shard ({}), which --resume would not \
             continue; remove it, or give another --out",
            h.line()
        ),
        Err(_) => "is not an unfinished run of a sweep (an earlier `simulate` of this output?); \
                   remove it, or give another --out"
            .into(),
    }
}

/// Runs the sweep (or its shard) and writes the CSV part to `out`.
///
/// Before any run: `out` must not be the scene file nor an existing file other than a regular
/// file (a symbolic link is written through to its file, see [`output`]), the keys must be
/// distinct (aliases included), every selected member's scene must build and plan its steps,
/// no other run may hold `<out>.lock`, and `<out>.partial` must be writable. The run holds
/// `<out>.lock` until it ends. Members then run in parallel, each row appended to
/// `<out>.partial` and flushed as its member finishes, so that an interrupted sweep keeps its
/// finished members; with `resume` such a file of the same sweep is continued without running
/// its members again (a row cut off by the interruption is run again), and a finished `out`
/// of the same sweep is left as it is ([`SweepSummary::finished_before`]), while one of
/// another sweep is refused. A run of more than [`MAX_MEMBERS`] members is refused first. On a
/// terminal, a progress bar shows the members checked and then those run; elsewhere nothing
/// is shown. A sweep that starts anew removes the
/// `<out>.member-<i>.failed.dat` files of an earlier one. At the end the rows are written
/// sorted by member to `<out>.tmp`, which is renamed over `out` once written in full (a sweep
/// killed or stopped by a full disk then leaves the former `out` as it was), and
/// `<out>.partial` is removed; a resumed `<out>.partial` is rewritten in the same way. A
/// member whose run diverges or fails (a panic of its run included) keeps its row, with its
/// status and error and empty numbers, and the other members run on. The members are enumerated lazily, never listed.
///
/// # Errors
/// [`CliError::SweepTooLarge`] for a run of more than [`MAX_MEMBERS`] members; unknown
/// model, bad scene, a key given twice, unknown keys or bad values, a member whose
/// step plan is refused, a member of a report model with `record_every` > 1, whose key
/// numbers need every row ([`CliError::KeysNeedEveryRow`]), an unfinished run at `<out>.partial` without `resume` (or of another
/// sweep), with `resume` a finished `out` of another sweep ([`CliError::MixedParts`]), an
/// output that is the scene file or not a regular file ([`CliError::Output`]) or that another
/// run holds ([`CliError::Locked`]), an unwritable output.
pub fn run(options: &SweepOptions, out: &Path) -> Result<SweepSummary> {
    run_with_warnings(options, out, &mut |w| eprintln!("warning: {w}"))
}

/// [`run`] with the warnings about the members' initial gaps passed to `warn` (each distinct
/// warning once, with the first member that has it).
///
/// # Errors
/// As [`run`].
pub fn run_with_warnings(
    options: &SweepOptions,
    out: &Path,
    warn: &mut dyn FnMut(&str),
) -> Result<SweepSummary> {
    // The output: not the scene file, not a file other than a regular one.
    let out_file = Output::new(out)?;
    let inputs: Vec<&Path> =
        options.scene.iter().chain(&options.members).map(PathBuf::as_path).collect();
    output::check_distinct(&inputs, &[&out_file])?;
    let base = base_scene(options.model.as_deref(), options.scene.as_deref())?;
    let kind = base.kind();
    let max_steps = options.max_steps.unwrap_or(DEFAULT_MAX_STEPS);
    let mut axes = match &options.members {
        Some(path) => grid::members_file_axes(path)?,
        None => Vec::new(),
    };
    axes.extend(options.axes.iter().cloned());
    let grid = Grid::new(axes)?;
    let shard = options.shard.unwrap_or(Shard::all());
    let members = shard.count(grid.len());
    if members > MAX_MEMBERS {
        return Err(CliError::SweepTooLarge {
            members,
            total: grid.len(),
            limit: MAX_MEMBERS,
            shards: grid.len().div_ceil(MAX_MEMBERS),
        }
        .into());
    }
    // Member 0 first, so that a repeated or unknown key is refused whatever the shard.
    if !grid.is_empty() {
        member_scene(&base, &grid, 0, max_steps)?;
    }
    let base_model = base.build()?;
    let key_columns = keys::columns_of(&base_model);
    // Every member, in parallel by chunks, the first refusal and the warnings in member order.
    let mut warned = BTreeSet::new();
    let checking = Progress::on_terminal(members as usize, &format!("checking sweep {kind}"));
    let mut to_check = shard.members(grid.len());
    loop {
        let chunk: Vec<u64> = to_check.by_ref().take(CHECK_CHUNK).collect();
        if chunk.is_empty() {
            break;
        }
        let checked: Vec<Result<Vec<String>>> = chunk
            .par_iter()
            .map(|&i| {
                let scene = member_scene(&base, &grid, i, max_steps)?;
                let model = scene.build()?;
                let mut warnings = guard::gap_warnings(&model, scene.t_start, scene.projection);
                if keys::columns_of(&model) != key_columns {
                    warnings.push(
                        "its bodies or contacts differ from the base scene's: its row gives the \
                         key numbers it shares with the base scene, by name, and leaves the \
                         others empty"
                            .to_owned(),
                    );
                }
                checking.tick("");
                Ok(warnings)
            })
            .collect();
        for (i, warnings) in chunk.into_iter().zip(checked) {
            for w in warnings? {
                if warned.len() < 20 && warned.insert(w.clone()) {
                    warn(&format!("member {i}: {w}"));
                }
            }
        }
    }
    checking.clear();
    let identity = PartHeader {
        id: sweep_id(&base, grid.axes(), max_steps)?,
        model: kind.name().to_owned(),
        members: grid.len(),
        shard,
        version: env!("CARGO_PKG_VERSION").to_owned(),
    };
    let columns = header(&base_model, grid.axes());
    let _lock = OutputLock::acquire(&out_file)?;
    let target = out_file.target();
    let partial = out_file.partial();
    if options.resume && !partial.exists() && target.exists() {
        // A finished part of this sweep needs nothing more; one of another sweep is kept.
        let part = parts::read_part(target, false)?;
        if part.header != identity || part.columns != columns {
            return Err(CliError::MixedParts {
                part: out.to_owned(),
                reason: format!(
                    "is a finished run of another sweep or shard ({}), not of this one ({}); \
                     --resume continues this sweep only: give another --out, or leave out \
                     --resume to run this sweep over it",
                    part.header.line(),
                    identity.line()
                ),
            }
            .into());
        }
        let rows = part.rows.len() as u64;
        let members = shard.count(grid.len());
        if rows != members {
            return Err(CliError::MixedParts {
                part: out.to_owned(),
                reason: format!(
                    "holds {rows} rows where this sweep's shard has {members} members; leave \
                     out --resume to run the sweep over it"
                ),
            }
            .into());
        }
        let rows: Vec<Vec<String>> = part.rows.into_iter().map(|(_, r)| r).collect();
        return Ok(SweepSummary {
            finished_before: true,
            ..SweepSummary::of_rows(&columns, &rows, 0)
        });
    }
    let mut kept: Vec<Vec<String>> = Vec::new();
    let mut dropped_damaged_row = false;
    if partial.exists() {
        if !options.resume {
            let reason = partial_reason(&partial, &identity);
            return Err(CliError::Output { path: partial, reason }.into());
        }
        let part = parts::read_part(&partial, true)?;
        if part.header != identity || part.columns != columns {
            return Err(CliError::MixedParts {
                part: partial,
                reason: format!(
                    "is an unfinished run of another sweep or shard ({}), not of this one ({})",
                    part.header.line(),
                    identity.line()
                ),
            }
            .into());
        }
        dropped_damaged_row = part.dropped_tail;
        kept = part.rows.into_iter().map(|(_, r)| r).collect();
    } else {
        // The problems an earlier sweep's members stopped on are not this sweep's.
        output::remove_stale_member_problems(&out_file)?;
    }
    let done: HashSet<u64> = kept.iter().filter_map(|r| r[0].parse().ok()).collect();
    parts::write_part(&partial, &identity, &columns, &kept)?;
    let file = std::fs::OpenOptions::new()
        .append(true)
        .open(&partial)
        .with_context(|| format!("opening {}", partial.display()))?;
    let writer = Mutex::new(csv::Writer::from_writer(file));
    let todo = shard.count(grid.len()) - done.len() as u64;
    faer::set_global_parallelism(faer::Par::Seq);
    let progress = Progress::on_terminal(todo as usize, &format!("sweep {kind}"));
    let ran = Mutex::new(0u64);
    let failure: Mutex<Option<anyhow::Error>> = Mutex::new(None);
    (0..shard.count(grid.len())).into_par_iter().for_each(|j| {
        let i = shard.k as u64 - 1 + j * shard.n as u64;
        if done.contains(&i) {
            return;
        }
        let row = member_scene(&base, &grid, i, max_steps).map(|scene| {
            let mut row = member_row(&scene, &key_columns, &grid, i, max_steps, target);
            row.push(row_check(&row));
            row
        });
        let written = row.and_then(|row| {
            let mut w = writer.lock().unwrap_or_else(|e| e.into_inner());
            w.write_record(&row)?;
            w.flush()?;
            *ran.lock().unwrap_or_else(|e| e.into_inner()) += 1;
            Ok(())
        });
        if let Err(e) = written {
            failure.lock().unwrap_or_else(|p| p.into_inner()).get_or_insert(e);
        }
        progress.tick(&format!("member {i}"));
    });
    progress.finish();
    drop(writer);
    if let Some(e) = failure.into_inner().unwrap_or_else(|p| p.into_inner()) {
        return Err(e.context(format!("the finished members are in {}", partial.display())));
    }
    // The finished part, sorted by member, replaces the unfinished one.
    let part = parts::read_part(&partial, false)?;
    let mut rows = part.rows;
    rows.sort_by_key(|(i, _)| *i);
    let rows: Vec<Vec<String>> = rows.into_iter().map(|(_, r)| r).collect();
    anyhow::ensure!(
        rows.len() as u64 == shard.count(grid.len()),
        "{} holds {} rows where the shard has {} members",
        partial.display(),
        rows.len(),
        shard.count(grid.len())
    );
    parts::write_part(target, &identity, &columns, &rows)?;
    std::fs::remove_file(&partial).with_context(|| format!("removing {}", partial.display()))?;
    let ran = ran.into_inner().unwrap_or_else(|p| p.into_inner());
    Ok(SweepSummary { dropped_damaged_row, ..SweepSummary::of_rows(&columns, &rows, ran) })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run that panics becomes an error carrying the panic's message, whether the payload
    /// is a literal or a formatted string; a run that returns is passed through.
    #[test]
    fn a_panicking_run_becomes_an_error_with_its_message() {
        let literal = unwound::<()>(|| panic!("index out of bounds")).unwrap_err();
        assert!(format!("{literal:#}").contains("a panic: index out of bounds"), "{literal:#}");
        let formatted = unwound::<()>(|| panic!("row {} of {}", 7, 3)).unwrap_err();
        assert!(format!("{formatted:#}").contains("a panic: row 7 of 3"), "{formatted:#}");
        assert_eq!(unwound(|| Ok(42)).unwrap(), 42);
        let failed = unwound::<()>(|| anyhow::bail!("diverged")).unwrap_err();
        assert_eq!(format!("{failed:#}"), "diverged");
    }
}
