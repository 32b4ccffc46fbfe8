//! Sweeps, shards and merging, and `simulate`'s CSV and error messages.

use std::path::Path;

use anyhow::{Context, Result, ensure};
use moreau_cli::grid::{Axis, Shard};
use moreau_cli::parts::merge;
use moreau_cli::simulate::{SimulateOptions, write_record};
use moreau_cli::sweep::{SweepOptions, run};

fn options(shard: Option<Shard>) -> Result<SweepOptions> {
    let axes = vec![
        Axis::parse("eps_n=0.5,0.7,0.9")?,
        Axis::parse("dt=0.001,0.002")?,
        Axis::parse("t_end=2")?,
    ];
    Ok(SweepOptions { shard, ..SweepOptions::new("ball", axes) })
}

/// The CSV without the measured wall time.
fn without_wall_time(path: &Path) -> Result<Vec<Vec<String>>> {
    let mut r = csv::ReaderBuilder::new().comment(Some(b'#')).from_path(path)?;
    let h: Vec<String> = r.headers()?.iter().map(str::to_owned).collect();
    let wall = h.iter().position(|c| c == "wall_seconds").context("wall_seconds column")?;
    // The check covers the wall time too.
    let check = h.len() - 1;
    let keep = |i: &usize| *i != wall && *i != check;
    let mut rows =
        vec![h.iter().enumerate().filter(|(i, _)| keep(i)).map(|(_, c)| c.clone()).collect()];
    for rec in r.records() {
        let rec = rec?;
        rows.push(
            rec.iter().enumerate().filter(|(i, _)| keep(i)).map(|(_, c)| c.to_owned()).collect(),
        );
    }
    Ok(rows)
}

#[test]
fn sharded_sweep_merges_to_the_unsharded_one() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let all = dir.path().join("all.csv");
    assert_eq!(run(&options(None)?, &all)?.rows, 6);
    let mut parts = Vec::new();
    for k in 1..=4 {
        let p = dir.path().join(format!("part{k}.csv"));
        run(&options(Some(Shard::parse(&format!("{k}/4"))?))?, &p)?;
        parts.push(p);
    }
    let merged = dir.path().join("merged.csv");
    assert_eq!(merge(&merged, &parts)?, 6);
    let a = without_wall_time(&all)?;
    assert_eq!(a, without_wall_time(&merged)?);
    // Header, then members 0..6 in order with their parameter values and key numbers.
    assert_eq!(a[0][..5], ["member", "members", "eps_n", "dt", "t_end"]);
    assert!(a[0].contains(&"rest_time".to_owned()) && a[0].contains(&"first_impact_t".to_owned()));
    assert_eq!(a[1][..4], ["0", "6", "0.5", "0.001"]);
    assert_eq!(a[6][..4], ["5", "6", "0.9", "0.002"]);
    // The ball's first impact is at t1 = sqrt(2 · 0.9 / 9.81) within one step for every member.
    let col = a[0].iter().position(|c| c == "first_impact_t").context("column")?;
    for (row, dt) in a[1..].iter().zip([0.001, 0.002, 0.001, 0.002, 0.001, 0.002]) {
        let t: f64 = row[col].parse()?;
        assert!((t - (1.8f64 / 9.81).sqrt()).abs() <= dt, "{t}");
    }
    // Leaving a part out is caught.
    let e = merge(&merged, &parts[..3]).unwrap_err().to_string();
    assert!(e.contains("missing") && e.contains('3'), "{e}");
    // The merged file names the sweep of its parts; the status of every member is ok.
    let text = std::fs::read_to_string(&merged)?;
    let first = std::fs::read_to_string(&parts[0])?;
    let id = |t: &str| t.lines().next().map(|l| l.split("; ").nth(1).map(str::to_owned));
    assert_eq!(id(&text), id(&first));
    assert!(text.lines().next().is_some_and(|l| l.contains("shard 1/1")));
    let status = a[0].iter().position(|c| c == "status").context("status")?;
    assert!(a[1..].iter().all(|r| r[status] == "ok"));
    Ok(())
}

#[test]
fn sweep_rejects_unknown_keys_before_running() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let mut o = options(None)?;
    o.axes.push(Axis::parse("no_such_key=1")?);
    let e = format!("{:#}", run(&o, &dir.path().join("x.csv")).unwrap_err());
    ensure!(e.contains("no_such_key") && e.contains("eps_n"), "{e}");
    Ok(())
}

#[test]
fn simulate_writes_named_columns() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let o = SimulateOptions {
        model: Some("woodpecker".into()),
        tf: Some(0.01),
        sets: vec!["beak.eps_n=0.4".into()],
        ..SimulateOptions::default()
    };
    let result = moreau_cli::simulate::run(&o)?;
    let path = dir.path().join("w.csv");
    write_record(&result, &path)?;
    let mut r = csv::Reader::from_path(&path)?;
    let h: Vec<String> = r.headers()?.iter().map(str::to_owned).collect();
    assert_eq!(
        h,
        [
            "t",
            "y",
            "phiM",
            "phiS",
            "v",
            "omegaM",
            "omegaS",
            "PN1",
            "PT1",
            "PN2",
            "PT2",
            "PN3",
            "PT3",
            "A1",
            "A2",
            "A3",
            "T",
            "V",
            "dissipated",
            "projected"
        ]
    );
    let rows: Vec<csv::StringRecord> = r.records().collect::<Result<_, _>>()?;
    // Row 0 and one row per step of 1e-4 s.
    assert_eq!(rows.len(), 101);
    assert_eq!(&rows[0][0], "0");
    assert_eq!(&rows[100][0], "0.01");
    // Contact 2 is closed at t = 0 (g_N2 < 0) and carries an impulse in the first step.
    assert_eq!(&rows[1][14], "1");
    assert!(rows[1][9].parse::<f64>()? > 0.0);
    Ok(())
}

#[test]
fn simulate_errors_list_what_is_accepted() {
    let bad_model =
        SimulateOptions { model: Some("pendulum".into()), ..SimulateOptions::default() };
    let e = format!("{:#}", moreau_cli::simulate::run(&bad_model).unwrap_err());
    assert!(e.contains("slider-crank") && e.contains("woodpecker"), "{e}");
    let bad_key = SimulateOptions {
        model: Some("ball".into()),
        sets: vec!["mass=2".into()],
        ..SimulateOptions::default()
    };
    let e = format!("{:#}", moreau_cli::simulate::run(&bad_key).unwrap_err());
    assert!(e.contains("mass") && e.contains("eps_n") && e.contains("init.y0"), "{e}");
    let bad_value = SimulateOptions {
        model: Some("ball".into()),
        sets: vec!["eps_n=1.5".into()],
        ..SimulateOptions::default()
    };
    let e = format!("{:#}", moreau_cli::simulate::run(&bad_value).unwrap_err());
    assert!(e.contains("eps_n"), "{e}");
    let bad_solver = SimulateOptions {
        model: Some("ball".into()),
        solver: Some("newton".into()),
        ..SimulateOptions::default()
    };
    let e = format!("{:#}", moreau_cli::simulate::run(&bad_solver).unwrap_err());
    assert!(e.contains("lemke") && e.contains("pgs"), "{e}");
}

#[test]
fn the_declared_ball_gives_its_first_impact_at_the_report_models_time() -> Result<()> {
    // Both key numbers are the impact step's midpoint t_M, the report's 0.4285 s (Table 8.2)
    // at Δt = 1e-3 s: the declared ball is the hand model to the bit.
    let dir = tempfile::tempdir()?;
    let scene =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies/ball.toml");
    let mut times = Vec::new();
    for (options, column) in [
        (SweepOptions::new("ball", vec![Axis::parse("t_end=0.5")?]), "first_impact_t"),
        (SweepOptions::scene(&scene, vec![Axis::parse("t_end=0.5")?]), "floor.first_impact_t"),
    ] {
        let out = dir.path().join(format!("{}.csv", times.len()));
        run(&options, &out)?;
        let part = moreau_cli::parts::read_part(&out, false)?;
        let col = part.columns.iter().position(|c| c == column).context("column")?;
        times.push(part.rows[0].1[col].parse::<f64>()?);
    }
    assert_eq!(times[0], times[1]);
    assert!((times[0] - 0.4285).abs() < 1e-12, "{}", times[0]);
    Ok(())
}

/// `key=v1,...` with `n` distinct values from `first` by `step`.
fn axis(key: &str, n: usize, first: f64, step: f64) -> String {
    let values: Vec<String> = (0..n).map(|i| format!("{}", first + step * i as f64)).collect();
    format!("{key}={}", values.join(","))
}

#[test]
fn a_sweep_too_large_for_one_run_is_refused_before_anything_is_done() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("huge.csv");
    // 10^9 members: the command answers at once, where it used to check them for hours.
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_moreau"))
        .args(["sweep", "ball", "--set", &axis("eps_n", 1000, 0.1, 1e-4)])
        .args(["--set", &axis("init.y0", 1000, 1.0, 1e-3), "--set"])
        .arg(axis("t_end", 1000, 0.01, 0.01))
        .arg("--out")
        .arg(&out)
        .stderr(std::process::Stdio::piped())
        .spawn()?;
    let start = std::time::Instant::now();
    while child.try_wait()?.is_none() {
        if start.elapsed().as_secs() > 30 {
            child.kill()?;
            child.wait()?;
            anyhow::bail!("a sweep of 10^9 members was not refused within 30 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let o = child.wait_with_output()?;
    let stderr = String::from_utf8_lossy(&o.stderr);
    ensure!(o.status.code() == Some(1), "{stderr}");
    ensure!(stderr.contains("holds 1000000000 members"), "{stderr}");
    ensure!(stderr.contains("split it with --shard K/N, N >= 1000"), "{stderr}");
    ensure!(std::fs::read_dir(dir.path())?.next().is_none(), "it left files");
    // Typed, counting the members of the run: 1001 x 1000 members are too many for one run.
    let axes = vec![
        Axis::parse(&axis("eps_n", 1001, 0.1, 1e-4))?,
        Axis::parse(&axis("t_end", 1000, 0.01, 0.01))?,
    ];
    let e = run(&SweepOptions::new("ball", axes), &out).expect_err("too large");
    let too_large = e.chain().find_map(|c| c.downcast_ref::<moreau_cli::CliError>());
    ensure!(
        matches!(
            too_large,
            Some(moreau_cli::CliError::SweepTooLarge {
                members: 1_001_000,
                total: 1_001_000,
                limit: 1_000_000,
                shards: 2
            })
        ),
        "{e:#}"
    );
    Ok(())
}

#[test]
fn a_sweep_shows_its_progress_on_a_terminal_only() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("k.csv");
    let args = ["sweep", "ball", "--set", "eps_n=0.5,0.7", "--set", "t_end=0.05", "--out"];
    // Standard error is a pipe: no line per member.
    let o =
        std::process::Command::new(env!("CARGO_BIN_EXE_moreau")).args(args).arg(&out).output()?;
    let stderr = String::from_utf8_lossy(&o.stderr);
    ensure!(o.status.success() && stderr.is_empty(), "{stderr}");
    // On a terminal (`script` gives the command one), a bar counts the members.
    let command = format!("{} {} {}", env!("CARGO_BIN_EXE_moreau"), args.join(" "), out.display());
    match std::process::Command::new("script").args(["-qec", &command, "/dev/null"]).output() {
        Ok(o) if o.status.success() => {
            let screen = String::from_utf8_lossy(&o.stdout);
            ensure!(screen.contains("sweep ball") && screen.contains("2/2"), "{screen}");
        }
        _ => println!("script is not available: the terminal is not tried"),
    }
    Ok(())
}

/// A sweep over the number of grains of a declared column (20 and 100, the file's own): the
/// rows keep the base scene's columns, the member of 20 grains fills those of its grains with
/// the end of its own run (the same numbers as `simulate` of that scene) and leaves those of
/// grains 20 to 99 empty; the member of 100 fills all. Both end `ok`, where a member whose
/// bodies differed from the base scene's failed.
#[test]
fn a_sweep_over_the_number_of_bodies_fills_the_columns_it_shares_by_name() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/scale/disk-column.toml");
    let out = dir.path().join("count.csv");
    let axes = vec![Axis::parse("fill.grain.count=20,100")?, Axis::parse("t_end=0.02")?];
    let summary = run(&SweepOptions::scene(&scene, axes), &out)?;
    ensure!((summary.rows, summary.failed, summary.diverged) == (2, 0, 0), "{summary:?}");
    let part = moreau_cli::parts::read_part(&out, false)?;
    let col = |name: &str| part.columns.iter().position(|c| c == name).context(name.to_owned());
    let cell =
        |row: usize, name: &str| -> Result<String> { Ok(part.rows[row].1[col(name)?].clone()) };
    for row in 0..2 {
        ensure!(cell(row, "status")? == "ok", "member {row}: {}", cell(row, "error")?);
    }
    let alone = moreau_cli::simulate::run(&SimulateOptions {
        scene: Some(scene.clone()),
        sets: vec!["fill.grain.count=20".into(), "t_end=0.02".into()],
        ..SimulateOptions::default()
    })?;
    let record = alone.record();
    let names = alone.model().coordinate_names();
    let last = record.q.last().context("a row")?;
    for (name, q) in names.iter().zip(last) {
        let value: f64 = cell(0, &format!("{name}.end"))?.parse()?;
        ensure!(value == *q, "{name}: {value} in the sweep, {q} alone");
    }
    ensure!(names.len() == 60, "{} coordinates", names.len());
    for g in [20, 57, 99] {
        ensure!(cell(0, &format!("grain{g}.y.end"))?.is_empty());
        ensure!(!cell(1, &format!("grain{g}.y.end"))?.is_empty());
    }
    Ok(())
}

#[test]
fn a_members_file_sweeps_its_rows_as_linked_axes_would() -> Result<()> {
    // The pendulum released from 0.3 and 0.5 rad: the bob's position and the hinge's anchor on
    // it vary together, each row of the file one release, times two restitutions of the wall.
    let dir = tempfile::tempdir()?;
    let scene =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies/pendulum-wall.toml");
    let releases = [0.3f64, 0.5];
    let position = |a: f64| format!("[{},{}]", -a.sin(), -a.cos());
    let anchor = |a: f64| format!("[{},{}]", a.sin(), a.cos());
    let mut text =
        "# releases of the bob\nbodies.bob.position,joints.hinge.anchor_b,t_end\n".to_owned();
    for a in releases {
        text.push_str(&format!("\"{}\",\"{}\", 0.5\n", position(a), anchor(a)));
    }
    let members = dir.path().join("releases.csv");
    std::fs::write(&members, text)?;
    let eps = Axis::parse("contacts.hit.eps_n=0.2,0.8")?;
    let from_file = dir.path().join("file.csv");
    let options = SweepOptions {
        members: Some(members.clone()),
        ..SweepOptions::scene(&scene, vec![eps.clone()])
    };
    assert_eq!(run(&options, &from_file)?.rows, 4);
    let join = |f: &dyn Fn(f64) -> String| releases.map(f).join(",");
    let linked = vec![
        Axis::parse(&format!("bodies.bob.position={}", join(&position)))?,
        Axis::parse(&format!("+joints.hinge.anchor_b={}", join(&anchor)))?,
        Axis::parse("+t_end=0.5,0.5")?,
        eps,
    ];
    let from_sets = dir.path().join("sets.csv");
    assert_eq!(run(&SweepOptions::scene(&scene, linked), &from_sets)?.rows, 4);
    let (a, b) = (without_wall_time(&from_file)?, without_wall_time(&from_sets)?);
    assert_eq!(a, b);
    assert_eq!(
        a[0][2..6],
        ["bodies.bob.position", "joints.hinge.anchor_b", "t_end", "contacts.hit.eps_n"]
    );
    assert_eq!(a[3][2..6], [position(0.5), anchor(0.5), "0.5".into(), "0.2".into()]);
    // The file is an input: the sweep does not write over it.
    let e = run(&options, &members).unwrap_err();
    ensure!(format!("{e:#}").contains("is the input"), "{e:#}");
    ensure!(std::fs::read_to_string(&members)?.starts_with("# releases"), "the file is kept");
    // A key of the file also given by --set is one entry set twice.
    let twice = SweepOptions {
        members: Some(members),
        ..SweepOptions::scene(&scene, vec![Axis::parse("t_end=1")?])
    };
    let e = run(&twice, &dir.path().join("twice.csv")).unwrap_err();
    ensure!(format!("{e:#}").contains("give each key once"), "{e:#}");
    Ok(())
}
