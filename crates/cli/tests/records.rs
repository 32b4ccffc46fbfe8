//! What a record holds at the end of a run: every row recorded up to a failing or diverging
//! step reaches `OUT.partial`, and a thinned record still ends at t_end or at the step its
//! stop rule ended the run on.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, ensure};
use moreau_cli::simulate::{SimulateOptions, partial_path, run_scene, run_to_csv, scene};

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name)
}

/// A block of 1 kg hanging from a spring of the given stiffness, Δt = 0.01 s for 1 s: the
/// stability limit is k < 4 m / Δt² = 40,000 N/m.
const SPRING: &str = r#"
dt = 0.01
t_end = 1.0
gravity = [0.0, -9.81]

[[bodies]]
name = "block"
type = "dynamic"
mass = 1.0
inertia = 0.01
position = [0.0, -1.0]

[[forces]]
type = "spring"
name = "s"
body_a = "ground"
anchor_a = [0.0, 0.0]
body_b = "block"
anchor_b = [0.0, 0.0]
stiffness = 100.0
rest_length = 1.0
"#;

/// The times of the rows of a CSV record, after its header.
fn times(path: &Path) -> Result<Vec<f64>> {
    let text = std::fs::read_to_string(path).with_context(|| format!("{}", path.display()))?;
    text.lines()
        .skip(1)
        .map(|l| Ok(l.split(',').next().context("a time")?.parse::<f64>()?))
        .collect()
}

fn spring(dir: &Path, sets: &[&str]) -> Result<SimulateOptions> {
    let path = dir.join("spring.toml");
    std::fs::write(&path, SPRING)?;
    Ok(SimulateOptions {
        scene: Some(path),
        sets: sets.iter().map(|s| (*s).to_owned()).collect(),
        ..Default::default()
    })
}

#[test]
fn a_diverged_run_leaves_every_row_before_the_divergence() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("a.csv");
    // Below the stability limit but gaining energy: the guard stops it at step 69.
    let options = spring(dir.path(), &["forces.s.stiffness=39999"])?;
    let e = run_to_csv(&options, &out, &mut |_| {}).unwrap_err();
    let message = format!("{e:#}");
    ensure!(message.contains("diverged at step 69"), "{message}");
    ensure!(message.contains(&format!("the rows so far are in {}", partial_path(&out).display())));
    ensure!(!out.exists());
    let t = times(&partial_path(&out))?;
    // Row 0 and steps 0 to 68, the last at t = 0.69 s.
    ensure!(t.len() == 70, "{} rows", t.len());
    ensure!((t[69] - 0.69).abs() < 1e-12, "{t:?}");
    // Thinned, the rows up to the last kept one before the divergence.
    let options = spring(dir.path(), &["forces.s.stiffness=39999", "record_every=10"])?;
    run_to_csv(&options, &out, &mut |_| {}).unwrap_err();
    let t = times(&partial_path(&out))?;
    ensure!(t.len() == 7 && (t[6] - 0.6).abs() < 1e-12, "{t:?}");
    // Refused at the stability limit before the first step: row 0 is kept.
    let options = spring(dir.path(), &["forces.s.stiffness=40001"])?;
    let e = run_to_csv(&options, &out, &mut |_| {}).unwrap_err();
    ensure!(format!("{e:#}").contains("stability limit"), "{e:#}");
    ensure!(times(&partial_path(&out))? == [0.0]);
    Ok(())
}

#[test]
fn a_thinned_record_ends_at_the_stop_step_and_at_t_end() -> Result<()> {
    let dir = tempfile::tempdir()?;
    // The pendulum's stop rule is never met: the run ends at t_end = 3 s, 30,000 steps,
    // which 7 does not divide.
    let pendulum = |every: &str| SimulateOptions {
        scene: Some(scene_path("bodies/pendulum-wall.toml")),
        sets: vec![r#"stop_at={coordinate="bob.x", value=5.0}"#.into(), every.into()],
        ..Default::default()
    };
    let out = dir.path().join("b2.csv");
    let done = run_to_csv(&pendulum("record_every=7"), &out, &mut |_| {})?;
    let t = times(&out)?;
    ensure!(done.steps == 30_000 && t.len() as u64 == done.rows, "{} rows", t.len());
    // Rows at steps 0, 7, ..., 29,995 and 30,000.
    ensure!(t.len() == 1 + 30_000 / 7 + 1, "{} rows", t.len());
    ensure!(*t.last().context("a row")? == 3.0, "{:?}", &t[t.len() - 2..]);
    // Each row holds the state of its step: the last rows equal those of the full record.
    let full = run_scene(&scene(&pendulum("record_every=1"))?, u64::MAX)?.record;
    let thinned = run_scene(&scene(&pendulum("record_every=7"))?, u64::MAX)?.record;
    ensure!(thinned.t.last() == full.t.last());
    ensure!(thinned.q.last() == full.q.last());
    ensure!(thinned.q.get(thinned.len() - 2) == full.q.get(29_995));
    // The summed impulses of the last row are those of its steps, and all are kept.
    let sum = |r: &moreau_stepper::Record| -> f64 { r.joint_impulses.as_flat().iter().sum() };
    ensure!((sum(&full) - sum(&thinned)).abs() <= 1e-9 * sum(&full).abs().max(1.0));

    // The slider-crank stops at θ1 = 4π after 13,725 steps: its record ends there.
    let crank = |every: &str| SimulateOptions {
        model: Some("slider-crank".into()),
        sets: vec![every.into()],
        ..Default::default()
    };
    let out = dir.path().join("b.csv");
    let done = run_to_csv(&crank("record_every=1000"), &out, &mut |_| {})?;
    let t = times(&out)?;
    ensure!(done.steps == 13_725 && t.len() == 15, "{} steps, {} rows", done.steps, t.len());
    let full = run_scene(&scene(&crank("record_every=1"))?, u64::MAX)?.record;
    ensure!(t.last() == full.t.last(), "{:?} against {:?}", t.last(), full.t.last());
    Ok(())
}

/// The cells of a sweep's CSV after its header, without the columns `skip`.
fn sweep_rows(path: &Path, skip: &[&str]) -> Result<(Vec<String>, Vec<Vec<String>>)> {
    let mut r = csv::ReaderBuilder::new().comment(Some(b'#')).from_path(path)?;
    let h: Vec<String> = r.headers()?.iter().map(str::to_owned).collect();
    // The row's check covers the wall time too.
    let check = h.len() - 1;
    let keep: Vec<usize> =
        (0..h.len()).filter(|&i| i != check && !skip.contains(&h[i].as_str())).collect();
    let rows = r
        .records()
        .map(|rec| {
            let rec = rec?;
            Ok(keep.iter().map(|&i| rec[i].to_owned()).collect())
        })
        .collect::<Result<_>>()?;
    Ok((keep.iter().map(|&i| h[i].clone()).collect(), rows))
}

#[test]
fn key_numbers_do_not_depend_on_the_thinning() -> Result<()> {
    use moreau_cli::CliError;
    use moreau_cli::grid::Axis;
    use moreau_cli::sweep::{SweepOptions, run};
    let dir = tempfile::tempdir()?;
    // A report model's key numbers are read from every row: a thinned sweep is refused
    // before any file is written.
    let out = dir.path().join("c.csv");
    let axes = vec![Axis::parse("record_every=1,100")?];
    let e = run(&SweepOptions::new("ball", axes), &out).unwrap_err();
    let refused = e.chain().find_map(|c| c.downcast_ref::<CliError>());
    ensure!(matches!(refused, Some(CliError::KeysNeedEveryRow { record_every: 100, .. })), "{e:#}");
    ensure!(format!("{e:#}").contains("record_every = 100"), "{e:#}");
    ensure!(std::fs::read_dir(dir.path())?.next().is_none(), "files were written");
    // A declared mechanism's are the same whatever the thinning: the impacts from the
    // stepper's list, the final state and energies from the run's last step.
    let pendulum = SweepOptions {
        model: None,
        scene: Some(scene_path("bodies/pendulum-wall.toml")),
        ..SweepOptions::new("declared", vec![Axis::parse("record_every=1,10,3")?])
    };
    let out = dir.path().join("d.csv");
    let summary = run(&pendulum, &out)?;
    ensure!(summary.rows == 3 && summary.diverged == 0 && summary.failed == 0);
    let (h, rows) = sweep_rows(&out, &["member", "record_every", "wall_seconds"])?;
    ensure!(h.contains(&"hit.impacts".to_owned()) && h.contains(&"bob.x.end".to_owned()));
    ensure!(rows[0] == rows[1] && rows[0] == rows[2], "{h:?}\n{rows:?}");
    Ok(())
}
