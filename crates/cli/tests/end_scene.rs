//! `simulate --end-scene FILE` writes the run's end state as a scene that starts there: the
//! pendulum run in two halves against one run of the whole, a sweep started from the end
//! state, and no file from a run that does not succeed.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, ensure};
use moreau_cli::grid::Axis;
use moreau_cli::simulate::{SimulateOptions, run_to_csv};
use moreau_cli::sweep::{SweepOptions, run as sweep};
use moreau_models::Scene;

fn pendulum() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies/pendulum-wall.toml")
}

/// The header and the rows of a record, as numbers.
fn record(path: &Path) -> Result<(Vec<String>, Vec<Vec<f64>>)> {
    let mut r = csv::ReaderBuilder::new().comment(Some(b'#')).from_path(path)?;
    let header = r.headers()?.iter().map(str::to_owned).collect();
    let rows = r
        .records()
        .map(|row| row?.iter().map(|x| x.parse::<f64>().map_err(Into::into)).collect())
        .collect::<Result<_>>()?;
    Ok((header, rows))
}

fn options(scene: PathBuf, tf: f64, end_scene: Option<PathBuf>) -> SimulateOptions {
    SimulateOptions { scene: Some(scene), tf: Some(tf), end_scene, ..SimulateOptions::default() }
}

#[test]
fn the_end_scene_continues_the_run() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let (first, second, whole) =
        (dir.path().join("first.csv"), dir.path().join("second.csv"), dir.path().join("whole.csv"));
    let end = dir.path().join("end.toml");
    // The bob falls for 0.3 s, then 0.3 s more, through its impact on the wall at 0.50 s.
    run_to_csv(&options(pendulum(), 0.3, Some(end.clone())), &first, &mut |_| {})?;
    let next = Scene::from_path(&end)?;
    ensure!((next.t_start, next.t_end) == (0.3, 0.6), "{} to {}", next.t_start, next.t_end);
    run_to_csv(&options(end.clone(), 0.6, None), &second, &mut |_| {})?;
    run_to_csv(&options(pendulum(), 0.6, None), &whole, &mut |_| {})?;
    let (h, a) = record(&first)?;
    let (h2, b) = record(&second)?;
    let (_, c) = record(&whole)?;
    ensure!(h == h2, "the continued run has the same columns");
    // Its first row is the first run's last, at t = 0.3 s.
    let (last, start) = (a.last().context("rows")?, &b[0]);
    ensure!(start[0] == 0.3, "starts at {}", start[0]);
    let x = h.iter().position(|c| c == "bob.x").context("bob.x")?;
    let vx = h.iter().position(|c| c == "bob.vx").context("bob.vx")?;
    ensure!(start[x] == last[x] && start[vx] == last[vx], "{start:?} against {last:?}");
    // Its rows are those of the run of the whole from 0.3 s on: the same times and states to
    // round-off, the impact included.
    let from = c.iter().position(|row| row[0] == 0.3).context("a row at 0.3 s")?;
    ensure!(c.len() - from == b.len(), "{} rows against {}", b.len(), c.len() - from);
    let p_n = h.iter().position(|c| c == "hit.PN").context("hit.PN")?;
    ensure!(b.iter().any(|row| row[p_n] > 0.0), "the bob strikes the wall in the second half");
    for (r, s) in b.iter().zip(&c[from..]) {
        // n Δt from 0.3 s and from 0 round differently in the last bit.
        ensure!((r[0] - s[0]).abs() <= 1e-12, "row at {} against {}", r[0], s[0]);
        for j in [x, vx, p_n] {
            ensure!(
                (r[j] - s[j]).abs() <= 1e-9,
                "{} at t = {}: {} against {}",
                h[j],
                r[0],
                r[j],
                s[j]
            );
        }
    }
    Ok(())
}

#[test]
fn a_sweep_starts_from_the_end_state() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let end = dir.path().join("end.toml");
    run_to_csv(
        &options(pendulum(), 0.3, Some(end.clone())),
        &dir.path().join("a.csv"),
        &mut |_| {},
    )?;
    let first_impacts = |scene: &Path, out: &Path| -> Result<Vec<f64>> {
        let axes = vec![Axis::parse("contacts.hit.eps_n=0.5,0.8")?, Axis::parse("t_end=0.6")?];
        let summary = sweep(&SweepOptions::scene(scene, axes), out)?;
        ensure!((summary.rows, summary.failed, summary.diverged) == (2, 0, 0));
        let part = moreau_cli::parts::read_part(out, false)?;
        let t = part.columns.iter().position(|c| c == "hit.first_impact_t").context("column")?;
        part.rows.iter().map(|(_, row)| Ok(row[t].parse::<f64>()?)).collect()
    };
    // The members start at 0.3 s, not at 0: they strike the wall when the sweep from rest
    // does, at 0.50 s.
    let continued = first_impacts(&end, &dir.path().join("continued.csv"))?;
    let from_rest = first_impacts(&pendulum(), &dir.path().join("from-rest.csv"))?;
    for (a, b) in continued.iter().zip(&from_rest) {
        ensure!((a - b).abs() <= 1e-12 && (0.49..0.52).contains(a), "first impact {a}, {b}");
    }
    Ok(())
}

#[test]
fn a_run_that_does_not_succeed_writes_no_end_scene() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let end = dir.path().join("end.toml");
    let out = dir.path().join("out.csv");
    // 0.30005 s is not a whole number of steps of 1e-4 s: refused before the first step.
    let e = run_to_csv(&options(pendulum(), 0.30005, Some(end.clone())), &out, &mut |_| {});
    ensure!(e.is_err() && !end.exists(), "{e:?}");
    // The command line's option, and the end scene may not be the record itself.
    let run = |args: &[&str]| Command::new(env!("CARGO_BIN_EXE_moreau")).args(args).output();
    let scene = pendulum();
    let scene = scene.to_str().context("UTF-8")?;
    let (out_s, end_s) = (out.to_str().context("UTF-8")?, end.to_str().context("UTF-8")?);
    let same =
        run(&["simulate", "--scene", scene, "--tf", "0.1", "--out", out_s, "--end-scene", out_s])?;
    ensure!(!same.status.success(), "the record and the end scene are one file");
    let ok =
        run(&["simulate", "--scene", scene, "--tf", "0.1", "--out", out_s, "--end-scene", end_s])?;
    ensure!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    ensure!(Scene::from_path(&end)?.t_start == 0.1);
    Ok(())
}

fn pyramid() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/scale/pyramid.toml")
}

#[test]
fn a_settled_pile_goes_on_from_its_end_scene_as_the_run_of_the_whole() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let end = dir.path().join("end.toml");
    let base = |tf: f64, end_scene: Option<PathBuf>| SimulateOptions {
        sets: vec!["fill.box.base=3".to_owned(), "record_every=10".to_owned()],
        ..options(pyramid(), tf, end_scene)
    };
    // Six boxes land on the floor and on each other, and rest by t = 0.3 s.
    run_to_csv(&base(0.3, Some(end.clone())), &dir.path().join("a.csv"), &mut |_| {})?;
    let text = std::fs::read_to_string(&end)?;
    let next = Scene::from_toml_str(&text)?;
    let impulses = next.impulses.as_ref().context("the end scene holds its last impulses")?;
    // Each of the five boxes on a box or the floor presses at two corners.
    ensure!(impulses.contacts.len() >= 10, "{impulses:?}");
    let second = dir.path().join("second.csv");
    run_to_csv(&options(end.clone(), 0.5, None), &second, &mut |_| {})?;
    let whole = dir.path().join("whole.csv");
    run_to_csv(&base(0.5, None), &whole, &mut |_| {})?;
    let (h, b) = record(&second)?;
    let (_, c) = record(&whole)?;
    let from = c.iter().position(|row| row[0] == 0.3).context("a row at 0.3 s")?;
    ensure!(c.len() - from == b.len(), "{} rows against {}", b.len(), c.len() - from);
    // Bit for bit but the times, which n Δt from 0.3 s and from 0 round differently, and
    // the energy dissipated and the projection's, which each run counts from its own start.
    let dissipated = h.iter().position(|c| c == "dissipated").context("dissipated")?;
    let projected = h.iter().position(|c| c == "projected").context("projected")?;
    for (r, s) in b.iter().zip(&c[from..]) {
        ensure!((r[0] - s[0]).abs() <= 1e-12, "row at {} against {}", r[0], s[0]);
        for j in (1..h.len()).filter(|&j| j != dissipated && j != projected) {
            ensure!(r[j] == s[j], "{} at t = {}: {} against {}", h[j], r[0], r[j], s[j]);
        }
        for k in [dissipated, projected] {
            let since = s[k] - c[from][k];
            ensure!((r[k] - since).abs() <= 1e-12, "{} {}, {since}", h[k], r[k]);
        }
    }
    // Without them the first step starts cold and finds other bits.
    let mut cold = next.clone();
    cold.impulses = None;
    let cold_path = dir.path().join("cold.toml");
    std::fs::write(&cold_path, cold.to_toml_string()?)?;
    let cold_csv = dir.path().join("cold.csv");
    run_to_csv(&options(cold_path, 0.5, None), &cold_csv, &mut |_| {})?;
    let (_, d) = record(&cold_csv)?;
    let apart = d.iter().zip(&b).any(|(r, s)| r[1..] != s[1..]);
    ensure!(apart, "a cold start gives the same record");
    Ok(())
}

#[test]
fn impulses_the_mechanism_cannot_take_are_refused_by_name() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let end = dir.path().join("end.toml");
    let first = dir.path().join("a.csv");
    run_to_csv(&options(pendulum(), 0.3, Some(end.clone())), &first, &mut |_| {})?;
    let mut scene = Scene::from_path(&end)?;
    // The revolute joint has two rows: three impulses do not fit it.
    let impulses = scene.impulses.get_or_insert_with(Default::default);
    ensure!(impulses.joints.len() == 2, "the hinge holds the swinging bob: {impulses:?}");
    impulses.joints.push(0.0);
    // Named row by row, the scene file cannot hold the third.
    let e = scene.to_toml_string().expect_err("no third row to name");
    ensure!(e.to_string().contains("3 joint impulses for the mechanism's 2 joint rows"), "{e}");
    // Given as plain numbers, row by row, the stepper refuses them.
    let bad = dir.path().join("bad.toml");
    std::fs::write(&bad, toml::to_string(&scene)?)?;
    let e = run_to_csv(&options(bad, 0.6, None), &dir.path().join("b.csv"), &mut |_| {})
        .expect_err("three joint impulses for two rows");
    ensure!(format!("{e:#}").contains("impulses: 3 joint impulses for 2 bilateral"), "{e:#}");
    Ok(())
}
