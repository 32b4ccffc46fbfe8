//! `tradeoff --quick` end to end: the files, their columns, one row per run and error measure,
//! and the ball's errors against the closed form.

use std::path::Path;

use anyhow::{Context, Result, ensure};
use xtask::tradeoff::{Options, Solver, metrics, run, studies};

fn read(path: &Path) -> Result<(Vec<String>, Vec<csv::StringRecord>)> {
    let mut r = csv::Reader::from_path(path).with_context(|| format!("{}", path.display()))?;
    let header = r.headers()?.iter().map(str::to_owned).collect();
    let rows = r.records().collect::<Result<Vec<_>, _>>()?;
    Ok((header, rows))
}

#[test]
fn quick_tradeoff_writes_the_table_figures_and_orders() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let summary = run(&Options { out: dir.path().to_owned(), quick: true, jobs: Some(2) })?;
    let expected = [
        "figS1_speed_accuracy.svg",
        "figS1_speed_accuracy.png",
        "figS1_speed_accuracy.csv",
        "figS2_error_vs_dt.svg",
        "figS2_error_vs_dt.png",
        "figS2_error_vs_dt.csv",
        "tradeoff.csv",
        "tradeoff.md",
    ];
    ensure!(summary.files == expected, "{:?}", summary.files);
    for f in expected {
        let len = std::fs::metadata(dir.path().join(f))?.len();
        ensure!(len > 500, "{f} has {len} bytes");
    }

    let (header, rows) = read(&dir.path().join("tradeoff.csv"))?;
    ensure!(
        header
            == [
                "model",
                "solver",
                "dt",
                "metric",
                "steps",
                "lcp_solves",
                "wall_s",
                "steps_per_s",
                "lcp_solves_per_s",
                "error",
                "unit",
                "status"
            ],
        "{header:?}"
    );
    // One row per run and error measure, then one per error measure of each reference.
    let count: usize = studies(true)
        .iter()
        .map(|s| {
            let m = metrics(s.kind).len();
            s.solvers.len() * s.steps.len() * m + if s.reference.is_some() { m } else { 0 }
        })
        .sum();
    ensure!(rows.len() == count, "{} rows, expected {count}", rows.len());
    for r in &rows {
        let status = &r[11];
        ensure!(
            ["ok", "failed: ", "not measured: ", "diverged: ", "reference: "]
                .iter()
                .any(|p| status.starts_with(p)),
            "status {status}"
        );
        if status == "ok" {
            let e: f64 = r[9].parse()?;
            ensure!(e.is_finite() && e >= 0.0, "{r:?}");
        }
    }

    // The ball against the closed form, Auto solver: impact times within 5 Δt of t_k and
    // shrinking with Δt; the first free fall exact to round-off (the midpoint rule integrates
    // constant gravity exactly).
    let ball = |metric: &str| -> Result<Vec<(f64, f64)>> {
        rows.iter()
            .filter(|r| &r[0] == "ball" && &r[1] == "auto" && &r[3] == metric)
            .map(|r| Ok((r[2].parse()?, r[9].parse()?)))
            .collect()
    };
    let times = ball("impact times")?;
    ensure!(times.len() == 4, "{times:?}");
    for w in times.windows(2) {
        ensure!(w[1].1 < w[0].1, "impact-time error does not shrink: {times:?}");
    }
    for (dt, e) in &times {
        ensure!(*e <= 5.0 * dt, "impact times: {e} at Δt = {dt}");
    }
    for (_, e) in ball("free fall")? {
        ensure!(e < 1e-12, "free fall error {e}");
    }
    // Every solver gives the ball the same impact times (a scalar LCP).
    let lemke: Vec<&csv::StringRecord> = rows
        .iter()
        .filter(|r| &r[0] == "ball" && r[1] == Solver::Lemke.label() && &r[3] == "impact times")
        .collect();
    ensure!(
        lemke.iter().map(|r| r[9].parse::<f64>().unwrap_or(f64::NAN)).eq(times.iter().map(|t| t.1))
    );

    let (h1, _) = read(&dir.path().join("figS1_speed_accuracy.csv"))?;
    ensure!(h1 == ["model", "metric", "unit", "solver", "dt", "wall_s", "error"], "{h1:?}");
    let (h2, fig2) = read(&dir.path().join("figS2_error_vs_dt.csv"))?;
    ensure!(h2 == ["model", "metric", "unit", "series", "dt", "error"], "{h2:?}");
    ensure!(fig2.iter().any(|r| &r[0] == "ball" && r[3].starts_with("fit p = ")));
    ensure!(fig2.iter().any(|r| &r[0] == "woodpecker" && &r[3] == "reference"));

    // Observed orders: first order for the ball's impact times; the free fall has none.
    let md = std::fs::read_to_string(dir.path().join("tradeoff.md"))?;
    let line = md
        .lines()
        .find(|l| l.starts_with("| ball | impact times | s | global | auto |"))
        .context("order row of the ball")?;
    let p: f64 = line.trim_end_matches(" |").rsplit("| ").next().context("order")?.parse()?;
    ensure!((0.7..1.3).contains(&p), "ball order {p}");
    ensure!(md.contains("| ball | free fall | m | impact-free | auto | — | 0 | — (errors ≤"));
    ensure!(md.contains("Step size for an error target"));
    Ok(())
}

/// A run that a typed error stops is listed as failed and counted in the study's error; a
/// reference that fails leaves the model's errors unmeasured and fails the study too.
#[test]
fn failed_runs_are_listed_and_end_the_study_in_an_error() -> Result<()> {
    let mut ball = studies(true)[0].clone();
    ball.steps = vec![1e-2];
    // PGS refuses a tolerance outside (0, 1).
    ball.solvers = vec![Solver::Auto, Solver::Pgs { tolerance: 2.0 }];
    let results = xtask::tradeoff::run_studies(&[ball]);
    let failed = xtask::tradeoff::failed_runs(&results);
    ensure!(failed.len() == 1 && failed[0].starts_with("ball pgs 2e0 Δt = 1e-2 s: "), "{failed:?}");
    let message = format!("{:#}", xtask::tradeoff::check_runs(&results).expect_err("a failure"));
    ensure!(message.contains("1 of 2 runs of the speed/accuracy study failed"), "{message}");

    let mut cam = studies(true)[4].clone();
    ensure!(cam.label() == "cam");
    (cam.steps, cam.solvers) = (vec![1e-2], vec![Solver::Auto]);
    // A mass the model refuses: the reference, the run at h_ref/2 and the run fail.
    cam.sets = vec![("m".into(), "-1".into())];
    let results = xtask::tradeoff::run_studies(&[cam]);
    let failed = xtask::tradeoff::failed_runs(&results);
    ensure!(failed.len() == 3 && failed[0].starts_with("cam auto Δt = 3e-5 s: "), "{failed:?}");
    let message = format!("{:#}", xtask::tradeoff::check_runs(&results).expect_err("a failure"));
    ensure!(message.contains("3 of 3 runs of the speed/accuracy study failed"), "{message}");
    Ok(())
}
