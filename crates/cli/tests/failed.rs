//! A run that stops on a step problem its solver leaves unsolved writes that problem in
//! Siconos' format, the same problem the stepper's error holds, and says where; a sweep writes
//! one per failed member.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result};
use moreau_cli::failed::failed_problem_path;
use moreau_cli::grid::Axis;
use moreau_cli::simulate::{SimulateOptions, run_to_csv, scene};
use moreau_cli::sweep::{SweepOptions, run};
use moreau_lcp::fc2d::{Fc2d, Fc2dAuto, Fc2dAutoOptions, Fc2dSolver, LcpRoute};
use moreau_lcp::{Enumeration, Lcp, Status};
use moreau_models::ModelError;
use moreau_stepper::StepError;

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name)
}

/// The pile of three disks with its contacts detected, solved by Gauss-Seidel allowed
/// `sweeps` sweeps to 1e-14.
fn pile(sweeps: u32) -> SimulateOptions {
    SimulateOptions {
        scene: Some(scene_path("bodies/stack.toml")),
        sets: vec![
            "solver=pgs".into(),
            format!("solver.max_iterations={sweeps}"),
            "solver.tolerance=1e-14".into(),
        ],
        ..Default::default()
    }
}

#[test]
fn an_island_left_unsolved_is_written_as_the_stepper_holds_it() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("pile.csv");
    let failed = failed_problem_path(&out);
    assert_eq!(failed, dir.path().join("pile.csv.failed.dat"));
    let e = run_to_csv(&pile(1), &out, &mut |_| {}).unwrap_err();
    let message = format!("{e:#}");
    assert!(message.contains(&format!("is in {}, in Siconos' FC2D format", failed.display())));
    assert!(!out.exists() && failed.exists());

    // The file holds the island the stepper stopped on, number for number.
    let error = scene(&pile(1))?.run().unwrap_err();
    let ModelError::Step(StepError::IslandFailed { problem, step, status, .. }) = error else {
        panic!("expected an island's failure, got {error}");
    };
    assert_eq!(status, Status::IterationLimit);
    assert!(message.contains(&format!("of step {step} ({} contacts)", problem.n_contacts())));
    let written = Fc2d::read_siconos(std::fs::File::open(&failed)?)?;
    assert_eq!(written, *problem);
    // It is a problem with a solution, which the default solver finds.
    let solved = Fc2dAuto::default().solve(&written)?;
    assert_eq!(solved.status, Status::Solved);
    assert!(solved.residual.natural <= 1e-8, "{:?}", solved.residual);

    // A later run of the same output that succeeds does not leave the old problem beside it.
    run_to_csv(&pile(100_000), &out, &mut |_| {})?;
    assert!(out.exists() && !failed.exists());
    Ok(())
}

#[test]
fn an_island_with_a_joint_is_written_as_its_contacts_alone() -> Result<()> {
    // The pendulum striking a wall, its contact detected: the bob's island holds the wall
    // contact and the hinge's two bilateral rows, which Siconos' FC2D format cannot hold.
    let options = SimulateOptions {
        scene: Some(scene_path("bodies/pendulum-wall.toml")),
        sets: vec![
            "contact_set=detected".into(),
            "solver=pgs".into(),
            "solver.max_iterations=1".into(),
            "solver.tolerance=1e-14".into(),
        ],
        ..Default::default()
    };
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("pendulum.csv");
    let e = run_to_csv(&options, &out, &mut |_| {}).unwrap_err();
    assert!(
        format!("{e:#}").contains(
            "(1 contacts, its 2 bilateral rows (joints) eliminated by their Schur complement)"
        ),
        "{e:#}"
    );
    let written = Fc2d::read_siconos(std::fs::File::open(failed_problem_path(&out))?)?;
    let error = scene(&options)?.run().unwrap_err();
    let ModelError::Step(StepError::IslandFailed { problem, .. }) = error else {
        panic!("expected an island's failure, got {error}");
    };
    assert_eq!(problem.view().n_bilateral(), 2);
    assert_eq!(written, problem.view().without_bilateral()?);
    // The contact's reaction is the same solved alone as with the joint's rows.
    let tight = Fc2dAutoOptions::default().with_tolerance(1e-13);
    let alone = Fc2dAuto::new(tight)?.solve(&written)?;
    let whole = LcpRoute::default().solve(&problem)?;
    assert_eq!((alone.status, whole.status), (Status::Solved, Status::Solved));
    assert!(alone.r[0] > 0.0, "{:?}", alone.r);
    for k in 0..2 {
        assert!((alone.r[k] - whole.r[k]).abs() <= 1e-12 * alone.r[0], "{alone:?} vs {whole:?}");
    }
    Ok(())
}

#[test]
fn a_step_lcp_without_solution_is_written_with_its_step() -> Result<()> {
    // The woodpecker variant with a longer beak arm, μ = 1.84 and ε_T = 0.69 at the beak,
    // whose LCP of eq. 7.41 has no solution at step 142 (tests/extremes/drift.rs), run with
    // Lemke's method.
    let dt = 0.000_111_591_849_423_313_29;
    let sets = [
        ("params.l_m", 0.01 * 1.473_838_299_104_488),
        ("params.l_g", 0.015 * 0.557_909_627_367_138_9),
        ("params.l_s", 0.0201 * 1.838_218_654_034_367_5),
        ("params.j_s", 7e-7 * 0.984_603_404_592_709_3),
        ("params.beak.eps_n", 0.0),
        ("params.beak.eps_t", 0.692_339_004_153_656_7),
        ("params.beak.mu", 1.839_702_639_234_597),
        ("params.lower.mu", 0.758_367_251_504_570_5),
        ("params.upper.mu", 0.0),
        ("dt", dt),
        ("t_end", 300.0 * dt),
    ];
    let mut sets: Vec<String> = sets.iter().map(|(k, v)| format!("{k}={v}")).collect();
    sets.push("solver=lemke".into());
    let options =
        SimulateOptions { scene: Some(scene_path("woodpecker.toml")), sets, ..Default::default() };
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("w.csv");
    let e = run_to_csv(&options, &out, &mut |_| {}).unwrap_err();
    let failed = failed_problem_path(&out);
    let message = format!("{e:#}");
    assert!(
        message.contains(&format!(
            "the LCP of step 142 (6 rows) is in {}, in Siconos' LCP format",
            failed.display()
        )),
        "{message}"
    );
    let lcp = Lcp::read_siconos(std::fs::File::open(&failed)?)?;
    assert_eq!(lcp.n(), 6);
    assert!(Enumeration::default().solve_all(lcp.view())?.is_empty());
    Ok(())
}

#[test]
fn a_sweep_writes_the_problem_of_each_failed_member() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("sweep.csv");
    let axes = vec![
        Axis::parse("solver=pgs")?,
        Axis::parse("solver.max_iterations=1,100000")?,
        Axis::parse("solver.tolerance=1e-14")?,
    ];
    let summary = run(&SweepOptions::scene(&scene_path("bodies/stack.toml"), axes), &out)?;
    assert_eq!((summary.rows, summary.failed), (2, 1));
    let member = |i: u32| failed_problem_path(&dir.path().join(format!("sweep.csv.member-{i}")));
    assert!(!member(1).exists());
    let written = Fc2d::read_siconos(std::fs::File::open(member(0))?)?;
    assert!(written.n_contacts() > 0);
    let text = std::fs::read_to_string(&out)?;
    let row = text.lines().find(|l| l.starts_with("0,")).context("member 0's row")?;
    assert!(row.contains(&format!("{}", member(0).display())), "{row}");
    // The command ends in an error once every row is written, and so does a resumed run
    // that finds the finished part with its failed member.
    let scene = scene_path("bodies/stack.toml");
    let args = |out: &Path| {
        let sets = ["solver=pgs", "solver.max_iterations=1,100000", "solver.tolerance=1e-14"];
        let mut args = vec!["sweep".to_owned(), "--scene".into(), scene.display().to_string()];
        args.extend(sets.iter().flat_map(|s| ["--set".to_owned(), (*s).to_owned()]));
        args.extend(["--out".to_owned(), out.display().to_string()]);
        args
    };
    let fresh = dir.path().join("fresh.csv");
    for (out, resume) in [(&fresh, false), (&out, true)] {
        let mut command = Command::new(env!("CARGO_BIN_EXE_moreau"));
        command.args(args(out));
        if resume {
            command.arg("--resume");
        }
        let run = command.output()?;
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{stderr}");
        assert!(stderr.contains("0 members diverged and 1 failed of the 2"), "{stderr}");
        let rows = std::fs::read_to_string(out)?;
        assert_eq!(rows.lines().filter(|l| l.starts_with("0,") || l.starts_with("1,")).count(), 2);
    }
    Ok(())
}
