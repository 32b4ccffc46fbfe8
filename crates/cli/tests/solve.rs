//! `solve`: problems read from Siconos' formats, told apart, solved by each solver to a
//! planted solution or checked against the problem, and the refusals.

use std::path::{Path, PathBuf};

use anyhow::Result;
use moreau_cli::CliError;
use moreau_cli::solve::{FC2D_SOLVERS, LCP_SOLVERS, Problem, read, run, solve};
use moreau_lcp::fc2d::{Fc2d, Fc2dResidual};
use moreau_lcp::{Lcp, Status};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../lcp/tests/data/moreau").join(name)
}

fn cli_error(e: &anyhow::Error) -> Option<&CliError> {
    e.chain().find_map(|c| c.downcast_ref::<CliError>())
}

/// The rows of a CSV file of numbers, after its header.
fn numbers(path: &Path) -> Result<(String, Vec<Vec<f64>>)> {
    let text = std::fs::read_to_string(path)?;
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default().to_owned();
    let rows = lines
        .map(|l| l.split(',').map(|x| Ok(x.parse::<f64>()?)).collect::<Result<Vec<f64>>>())
        .collect::<Result<_>>()?;
    Ok((header, rows))
}

#[test]
fn every_lcp_solver_finds_a_planted_solution() -> Result<()> {
    // M symmetric positive definite, z* = (1, 0, 2), w* = (0, 3, 0): q = w* - M z*.
    let m = [[4.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 2.0]];
    let (z, w) = ([1.0, 0.0, 2.0], [0.0, 3.0, 0.0]);
    let q: Vec<f64> = (0..3).map(|i| w[i] - (0..3).map(|j| m[i][j] * z[j]).sum::<f64>()).collect();
    let rows: Vec<Vec<f64>> = m.iter().map(|r| r.to_vec()).collect();
    let dir = tempfile::tempdir()?;
    let file = dir.path().join("planted.dat");
    Lcp::from_rows(&rows, &q)?.write_siconos(std::fs::File::create(&file)?)?;
    for solver in LCP_SOLVERS {
        let out = dir.path().join(format!("{solver}.csv"));
        let s = run(&file, None, Some(solver), Some(1e-12), Some(&out))?;
        assert_eq!((s.kind, s.size, s.status), ("lcp", 3, Status::Solved), "{solver}");
        let (header, rows) = numbers(&out)?;
        assert_eq!(header, "i,z,w");
        for (i, row) in rows.iter().enumerate() {
            assert_eq!(row[0], i as f64);
            assert!(
                (row[1] - z[i]).abs() < 1e-9 && (row[2] - w[i]).abs() < 1e-9,
                "{solver}: {row:?}"
            );
        }
    }
    Ok(())
}

#[test]
fn every_contact_solver_answers_for_the_solution_it_writes() -> Result<()> {
    // The island of a stack of boxes of 0.2 and 2e5 kg in turn (moreau-lcp's test data), which
    // pivoting alone leaves 5.7e-6 off.
    let file = data("stack_mass_ratio_island.dat");
    let Problem::Fc2d(problem) = read(&file, None)? else { panic!("an FC2D file") };
    let dir = tempfile::tempdir()?;
    let mut solved = 0;
    for solver in FC2D_SOLVERS {
        let out = dir.path().join(format!("{solver}.csv"));
        let result = run(&file, None, Some(solver), Some(1e-10), Some(&out));
        let written = match &result {
            Ok(s) => {
                assert_eq!(s.status, Status::Solved);
                solved += 1;
                out.clone()
            }
            Err(e) => {
                let Some(CliError::NotSolved { partial: Some(p), .. }) = cli_error(e) else {
                    panic!("{solver}: {e:#}");
                };
                assert!(!out.exists());
                p.clone()
            }
        };
        // The written reactions give the reported residual again, and u = W r + q.
        let (header, rows) = numbers(&written)?;
        assert_eq!(header, "contact,r_n,r_t,u_n,u_t");
        let r: Vec<f64> = rows.iter().flat_map(|row| [row[1], row[2]]).collect();
        let mut u = vec![0.0; problem.n_rows()];
        let again = Fc2dResidual::compute(problem.view(), &r, &mut u);
        let reported = match &result {
            Ok(s) => s.residual,
            Err(e) => match cli_error(e) {
                Some(CliError::NotSolved { residual, .. }) => *residual,
                _ => unreachable!(),
            },
        };
        assert!((again.natural - reported).abs() <= 1e-12 + 1e-9 * reported, "{solver}");
        for (row, u) in rows.iter().zip(u.chunks(2)) {
            assert!((row[3] - u[0]).abs() <= 1e-9 && (row[4] - u[1]).abs() <= 1e-9, "{solver}");
        }
    }
    // The default chain and the LCP route (through its polish) solve it.
    assert!(solved >= 2, "{solved} solvers");
    assert_eq!(solve(&Problem::Fc2d(problem), None, Some(1e-10))?.status, Status::Solved);
    Ok(())
}

#[test]
fn the_kind_of_problem_is_told_from_the_file_or_given() -> Result<()> {
    let lcp = data("stack_mass_ratio_lcp.dat");
    let fc2d = data("stack_mass_ratio_island.dat");
    assert!(matches!(read(&lcp, None)?, Problem::Lcp(ref p) if p.n() == 27));
    assert!(matches!(read(&fc2d, None)?, Problem::Fc2d(ref p) if p.n_contacts() == 10));
    assert!(matches!(read(&fc2d, Some("fc2d"))?, Problem::Fc2d(_)));
    let e = read(&lcp, Some("fc2d")).unwrap_err();
    assert!(matches!(cli_error(&e), Some(CliError::Problem { .. })), "{e:#}");
    assert!(format!("{e:#}").contains("is not an FC2D file"));
    let e = read(&lcp, Some("qp")).unwrap_err();
    assert!(matches!(cli_error(&e), Some(CliError::UnknownProblemKind { .. })), "{e:#}");
    // A file of neither kind names both readers' complaints.
    let dir = tempfile::tempdir()?;
    let bad = dir.path().join("bad.dat");
    std::fs::write(&bad, "3\n1 2\n")?;
    let e = read(&bad, None).unwrap_err();
    let message = format!("{e:#}");
    assert!(
        message.contains("is not an LCP file (")
            && message.contains(", nor an FC2D file (")
            && message.contains(", nor a GFC2D file ("),
        "{message}"
    );
    let e = read(&dir.path().join("missing.dat"), None).unwrap_err();
    assert!(format!("{e:#}").contains("cannot be read"));
    // An FC2D problem read back equals the one written.
    let again = Fc2d::read_siconos(std::fs::File::open(&fc2d)?)?;
    assert_eq!(read(&fc2d, None)?, Problem::Fc2d(again));
    Ok(())
}

#[test]
fn a_global_problem_is_solved_through_its_reduction() -> Result<()> {
    // A granular flow on a wall from Siconos' collection (moreau-lcp's test data): 69
    // contacts, M and H given. Reduced on reading, it is the same problem as the one
    // moreau-lcp's reader and reduction give, and its solution reaches the tolerance.
    let file = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../lcp/tests/data/siconos/fc2d/gfc2d_granularflowonwall_00069_00350.dat");
    let Problem::Gfc2d(reduced) = read(&file, None)? else { panic!("a GFC2D file") };
    let global = moreau_lcp::fc2d::Gfc2d::read_siconos(std::fs::File::open(&file)?)?;
    assert_eq!(reduced, global.reduce()?.problem);
    assert_eq!((reduced.n_contacts(), global.n_contacts()), (69, 69));
    assert!(matches!(read(&file, Some("gfc2d"))?, Problem::Gfc2d(_)));
    let e = read(&file, Some("fc2d")).unwrap_err();
    assert!(format!("{e:#}").contains("is not an FC2D file"), "{e:#}");
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("r.csv");
    let s = run(&file, None, None, Some(1e-8), Some(&out))?;
    assert_eq!((s.kind, s.size, s.status), ("gfc2d", global.n_contacts(), Status::Solved));
    let (header, rows) = numbers(&out)?;
    assert_eq!(header, "contact,r_n,r_t,u_n,u_t");
    let r: Vec<f64> = rows.iter().flat_map(|row| [row[1], row[2]]).collect();
    assert!(r.iter().any(|&r| r > 0.0));
    let mut u = vec![0.0; reduced.n_rows()];
    assert!(Fc2dResidual::compute(reduced.view(), &r, &mut u).natural <= 1e-8);
    Ok(())
}

#[test]
fn a_solver_of_the_other_kind_or_a_bad_tolerance_is_refused() {
    let lcp = data("stack_mass_ratio_lcp.dat");
    let e = run(&lcp, None, Some("nsgs"), None, None).unwrap_err();
    let Some(CliError::UnknownSolver { kind, accepted, .. }) = cli_error(&e) else {
        panic!("{e:#}");
    };
    assert_eq!((*kind, accepted.as_str()), ("lcp", "auto, lemke, pgs, enum"));
    let island = data("stack_mass_ratio_island.dat");
    let e = run(&island, None, Some("lemke"), None, None).unwrap_err();
    assert!(matches!(cli_error(&e), Some(CliError::UnknownSolver { kind: "fc2d", .. })));
    for tolerance in [0.0, -1.0, f64::NAN] {
        assert!(run(&island, None, None, Some(tolerance), None).is_err(), "{tolerance}");
    }
    // A tolerance of 1 or more, which a contact solver's own options take, is refused for
    // every solver as a scene's is, naming the option.
    for (problem, solver) in [(&island, "nsgs"), (&island, "auto"), (&lcp, "pgs")] {
        for tolerance in [1.0, 2.0, f64::INFINITY, f64::NAN] {
            let e = run(problem, None, Some(solver), Some(tolerance), None).unwrap_err();
            assert!(matches!(cli_error(&e), Some(CliError::BadTolerance { .. })), "{e:#}");
            assert!(e.to_string().starts_with("--tolerance "), "{e:#}");
        }
    }
    let e =
        run(&island, None, None, None, Some(Path::new(env!("CARGO_MANIFEST_DIR")))).unwrap_err();
    assert!(matches!(cli_error(&e), Some(CliError::Output { .. })), "{e:#}");
}

#[test]
fn an_lcp_without_solution_is_an_error_with_its_certificate() -> Result<()> {
    // A 1 × 1 LCP with M = -1 and q = -1: w = -z - 1 < 0 for every z >= 0.
    let dir = tempfile::tempdir()?;
    let file = dir.path().join("none.dat");
    Lcp::from_rows(&[vec![-1.0]], &[-1.0])?.write_siconos(std::fs::File::create(&file)?)?;
    let out = dir.path().join("z.csv");
    let e = run(&file, None, Some("auto"), None, Some(&out)).unwrap_err();
    let Some(CliError::NotSolved { status, partial, .. }) = cli_error(&e) else {
        panic!("{e:#}");
    };
    assert_eq!(*status, Status::NoSolution);
    assert!(!out.exists() && partial.as_ref().is_some_and(|p| p.exists()));
    Ok(())
}

#[test]
fn a_solve_that_succeeds_removes_the_last_iterate_of_an_earlier_one() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let file = dir.path().join("p.dat");
    Lcp::from_rows(&[vec![2.0]], &[-2.0])?.write_siconos(std::fs::File::create(&file)?)?;
    let out = dir.path().join("ex.csv");
    let partial = dir.path().join("ex.csv.partial");
    std::fs::write(&partial, "i,z,w\n0,0.5,-1\n")?;
    let s = run(&file, None, Some("lemke"), None, Some(&out))?;
    assert_eq!(s.status, Status::Solved);
    assert!(!partial.exists(), "the earlier last iterate is left");
    let (header, rows) = numbers(&out)?;
    assert_eq!((header.as_str(), rows), ("i,z,w", vec![vec![0.0, 1.0, 0.0]]));
    Ok(())
}

#[test]
fn a_problem_followed_by_data_is_refused_naming_the_line() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let siconos = Path::new(env!("CARGO_MANIFEST_DIR")).join("../lcp/tests/data/siconos");
    // An LCP of 2 rows (its q on line 8), then three numbers that its size leaves out.
    let lcp = dir.path().join("lcp.dat");
    let text = std::fs::read_to_string(siconos.join("lcp/lcp_deudeu.dat"))?;
    std::fs::write(&lcp, format!("{text}\n7 8 9\n"))?;
    // An FC2D problem of 2 contacts, then a second μ.
    let fc2d = dir.path().join("fc2d.dat");
    let text = std::fs::read_to_string(siconos.join("fc2d/FC2D_SliderCrankLagrangian00000.dat"))?;
    let mu_line = text.lines().count();
    std::fs::write(&fc2d, format!("{text}0.3 0.3\n"))?;
    for (file, kind, line, found, after) in [
        (&lcp, None, 9, "7", "q"),
        (&lcp, Some("lcp"), 9, "7", "q"),
        (&fc2d, None, mu_line + 1, "0.3", "μ"),
    ] {
        let e = read(file, kind).expect_err("data after the problem");
        let text = format!("{e:#}");
        anyhow::ensure!(
            matches!(cli_error(&e), Some(CliError::TrailingData { line: l, found: f, after: a, .. })
                if *l == line && f == found && *a == after),
            "{text}"
        );
        anyhow::ensure!(text.contains(&format!("'{found}' on line {line}, after its {after}")));
    }
    // Through the command: exit status 1 and the line on stderr.
    let o =
        std::process::Command::new(env!("CARGO_BIN_EXE_moreau")).arg("solve").arg(&lcp).output()?;
    let stderr = String::from_utf8_lossy(&o.stderr);
    anyhow::ensure!(o.status.code() == Some(1), "{stderr}");
    anyhow::ensure!(
        stderr.contains("is an LCP file followed by unexpected data '7' on line 9"),
        "{stderr}"
    );
    // Siconos' comments after an LCP, and the flag after an FC2D problem, are read as before.
    for name in
        ["lcp/lcp_CPS_1.dat", "lcp/lcp_exp_murty.dat", "fc2d/FrictionContactProblem00031.dat"]
    {
        read(&siconos.join(name), None)?;
    }
    Ok(())
}

#[test]
fn a_problem_file_cut_inside_its_last_number_is_refused() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let siconos = Path::new(env!("CARGO_MANIFEST_DIR")).join("../lcp/tests/data/siconos");
    // The FC2D problem's last line holds its two μ = 1.000000000000000020816682e-02; cut in
    // the second after `1.`, the file used to be solved with μ = 1 for that contact.
    let text = std::fs::read_to_string(siconos.join("fc2d/FC2D_SliderCrankLagrangian00000.dat"))?;
    let whole = text.trim_end();
    let last = whole.rfind(char::is_whitespace).map_or(0, |k| k + 1);
    assert_eq!(&whole[last..], "1.000000000000000020816682e-02");
    let cut = dir.path().join("cut.dat");
    std::fs::write(&cut, &whole[..last + 2])?;
    let lines = whole.lines().count();
    let e = read(&cut, None).expect_err("a file cut inside a number");
    let text = format!("{e:#}");
    anyhow::ensure!(matches!(cli_error(&e), Some(CliError::Problem { .. })), "{text}");
    anyhow::ensure!(
        text.contains(&format!("ends inside its last number '1.' on line {lines}")),
        "{text}"
    );
    // As an FC2D file too, and through the command: exit status 1, nothing solved.
    anyhow::ensure!(read(&cut, Some("fc2d")).is_err());
    let o =
        std::process::Command::new(env!("CARGO_BIN_EXE_moreau")).arg("solve").arg(&cut).output()?;
    let stderr = String::from_utf8_lossy(&o.stderr);
    anyhow::ensure!(o.status.code() == Some(1) && o.stdout.is_empty(), "{stderr}");
    anyhow::ensure!(stderr.contains("the file looks cut off"), "{stderr}");
    // The whole file, and Siconos' files that end with a space after their last number, read.
    let Problem::Fc2d(p) = read(&siconos.join("fc2d/FC2D_SliderCrankLagrangian00000.dat"), None)?
    else {
        panic!("an FC2D file")
    };
    assert_eq!(p.mu(), [0.01, 0.01]);
    assert!(!std::fs::read_to_string(siconos.join("lcp/lcp_mmc.dat"))?.ends_with('\n'));
    let Problem::Lcp(lcp) = read(&siconos.join("lcp/lcp_mmc.dat"), None)? else {
        panic!("an LCP file")
    };
    assert_eq!(lcp.n(), 26);
    Ok(())
}

#[test]
fn a_solve_that_misses_its_tolerance_removes_the_solution_of_an_earlier_one() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let (good, none) = (dir.path().join("good.dat"), dir.path().join("none.dat"));
    Lcp::from_rows(&[vec![2.0]], &[-2.0])?.write_siconos(std::fs::File::create(&good)?)?;
    Lcp::from_rows(&[vec![-1.0]], &[-1.0])?.write_siconos(std::fs::File::create(&none)?)?;
    let out = dir.path().join("z.csv");
    run(&good, None, None, None, Some(&out))?;
    assert_eq!(numbers(&out)?.1, vec![vec![0.0, 1.0, 0.0]]);
    // The second problem has no solution: its last iterate goes to z.csv.partial, and the
    // first problem's z = 1 no longer stands in z.csv for it.
    let e = run(&none, None, None, None, Some(&out)).unwrap_err();
    let Some(CliError::NotSolved { status, partial: Some(partial), .. }) = cli_error(&e) else {
        panic!("{e:#}");
    };
    assert_eq!(*status, Status::NoSolution);
    assert!(!out.exists(), "z.csv of the earlier solve is left");
    assert_eq!(numbers(partial)?.1, vec![vec![0.0, 0.0, -1.0]]);
    Ok(())
}

#[test]
fn a_residual_met_at_round_off_is_reported_above_the_tolerance() -> Result<()> {
    // The island of boxes of 0.2 and 2e5 kg: the LCP route ends at a natural residual of
    // 1.7e-11, which its solver accepts at the round-off of the solution, above 1e-12.
    let file = data("stack_mass_ratio_island.dat");
    let s = solve(&read(&file, None)?, Some("lcp-route"), Some(1e-12))?;
    assert_eq!((s.status, s.tolerance), (Status::Solved, 1e-12));
    assert!(s.residual > 1e-12 && s.residual <= s.round_off, "{s:?}");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_moreau"))
        .args(["solve", "--solver", "lcp-route", "--tolerance", "1e-12"])
        .arg(&file)
        .output()?;
    let stdout = String::from_utf8_lossy(&o.stdout);
    anyhow::ensure!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    anyhow::ensure!(
        stdout.contains(&format!(
            "residual {:.3e} (above the tolerance 1e-12, within the round-off {:.3e}",
            s.residual, s.round_off
        )),
        "{stdout}"
    );
    // Met to the tolerance itself, the line says nothing more.
    let s = solve(&read(&file, None)?, Some("lcp-route"), Some(1e-8))?;
    assert!(s.residual <= 1e-8 && s.round_off == 0.0, "{s:?}");
    Ok(())
}
