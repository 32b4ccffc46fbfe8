//! `reproduce --quick` end to end: every file of docs/figures.md, the plotted columns, the key
//! numbers against the closed forms, and the same CSVs whatever the number of threads.

use std::collections::BTreeSet;
use std::path::Path;

use anyhow::{Context, Result, ensure};
use serde_json::Value;
use xtask::reproduce::{Options, run};

/// Every figure and table docs/figures.md lists, as the file stems `reproduce` writes.
const PLOTS: [&str; 15] = [
    "fig03_02_laws",
    "figI_02_scalar_lcp",
    "fig08_02_ball",
    "fig08_03_ball_dt",
    "fig08_06_sleeve",
    "fig08_07_sleeve_angle",
    "fig08_08_bird_angle",
    "fig08_09_phase",
    "fig08_10_frames",
    "fig08_15_corners",
    "fig08_16_speeds",
    "fig08_17_corner1_eps",
    "fig08_18_portraits_eps",
    "fig08_21_cam",
    "fig08_22_frames",
];

fn header(path: &Path) -> Result<Vec<String>> {
    let mut r = csv::Reader::from_path(path).with_context(|| format!("{}", path.display()))?;
    Ok(r.headers()?.iter().map(str::to_owned).collect())
}

fn has_columns(dir: &Path, file: &str, columns: &[&str]) -> Result<()> {
    let h = header(&dir.join(file))?;
    for c in columns {
        ensure!(h.iter().any(|x| x == c), "{file} lacks column {c}; has {h:?}");
    }
    Ok(())
}

fn number(v: &Value, path: &str) -> Result<f64> {
    path.split('.')
        .try_fold(v, |v, k| v.get(k))
        .and_then(Value::as_f64)
        .with_context(|| format!("summary.json has no number at {path}"))
}

fn check_outputs(dir: &Path) -> Result<()> {
    for stem in PLOTS {
        for ext in ["svg", "png"] {
            let p = dir.join(format!("{stem}.{ext}"));
            ensure!(
                std::fs::metadata(&p).map(|m| m.len() > 1000).unwrap_or(false),
                "missing or tiny {}",
                p.display()
            );
        }
        let frames = stem.ends_with("_frames");
        let data = dir.join(format!("{stem}{}", if frames { "_anim.svg" } else { ".csv" }));
        ensure!(data.exists(), "missing {}", data.display());
    }
    for f in [
        "table8_2.csv",
        "table8_2.md",
        "summary.json",
        "report.html",
        "report.md",
        "figS1_speed_accuracy.csv",
        "figS1_speed_accuracy.png",
        "figS2_error_vs_dt.csv",
        "figS2_error_vs_dt.png",
        "tradeoff.csv",
        "tradeoff.md",
        "fig_scale.svg",
        "fig_scale.png",
        "fig_scale.csv",
        "fig_scale_network.svg",
        "fig_scale_network.png",
        "scale.csv",
        "scale.json",
    ] {
        ensure!(dir.join(f).exists(), "missing {f}");
    }
    // The speed/accuracy section: its table and observed orders are in the report.
    let report = std::fs::read_to_string(dir.join("report.md"))?;
    ensure!(report.contains("## Speed and accuracy"), "report.md lacks the speed/accuracy section");
    ensure!(
        report.contains("| ball | impact times | s | global | auto |"),
        "no order for the ball"
    );
    // The CSVs hold the plotted series.
    has_columns(
        dir,
        "fig08_02_ball.csv",
        &["t", "y", "v", "Lambda_N", "E_potential", "E_kinetic", "E_total"],
    )?;
    has_columns(
        dir,
        "fig08_03_ball_dt.csv",
        &["y_dt1e-3", "y_dt2.5e-2", "v_dt1e-3", "Lambda_N_dt2.5e-2"],
    )?;
    has_columns(dir, "fig08_06_sleeve.csv", &["t", "y_mm", "v"])?;
    has_columns(dir, "fig08_09_phase.csv", &["phiM", "omegaM", "phiS", "omegaS"])?;
    has_columns(dir, "fig08_15_corners.csv", &["revolutions", "Y1", "Y2", "Y3", "Y4"])?;
    has_columns(
        dir,
        "fig08_16_speeds.csv",
        &["w1_clearance", "w1_ideal", "w2_clearance", "w2_ideal", "X", "Y"],
    )?;
    has_columns(dir, "fig08_17_corner1_eps.csv", &["Y1_e0.1", "Y1_e0.4", "Y1_e0.6", "Y1_e0.9"])?;
    has_columns(dir, "fig08_18_portraits_eps.csv", &["X_e0.1", "Y_e0.9"])?;
    has_columns(dir, "fig08_21_cam.csv", &["t", "y_mm", "s_mm", "v", "ds_dt"])?;
    has_columns(dir, "fig03_02_laws.csv", &["g_N", "lambda_N", "gamma_T", "lambda_T"])?;
    has_columns(dir, "figI_02_scalar_lcp.csv", &["y_line_a", "y_solution_c"])?;
    has_columns(
        dir,
        "table8_2.csv",
        &["t", "y", "v", "t_M", "q_M", "M_M", "h_M", "g_N(q_M)", "b", "Lambda_N", "xi_N"],
    )?;

    // The report embeds every figure.
    let html = std::fs::read_to_string(dir.join("report.html"))?;
    ensure!(
        html.matches("data:image/png;base64,").count() >= PLOTS.len(),
        "report.html lacks images"
    );
    ensure!(html.contains("Table 8.2") && html.contains("wall time"));

    // Key numbers against the closed forms.
    let s: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json"))?)?;
    // The scaling study: one entry per run with the documented fields; the resting column
    // carries its weight.
    let runs = s["scale"].as_array().context("summary.json has no scale array")?;
    ensure!(runs.len() >= 3, "{} scaling runs", runs.len());
    for run in runs {
        for key in
            ["bodies", "contacts", "ms_per_step", "iterations", "residual", "max_penetration"]
        {
            ensure!(number(run, key)? >= 0.0, "scale entry {run} has a negative {key}");
        }
        ensure!(run["scene"].is_string() && run.get("force_balance_rel").is_some(), "{run}");
    }
    let column = runs.iter().find(|r| r["scene"] == "disk-column").context("no disk column")?;
    let balance = number(column, "force_balance_rel")?;
    ensure!(balance < 1e-8, "the resting column's reactions against its weight: {balance:e}");
    ensure!(report.contains("## Scaling"), "report.md lacks the scaling section");
    let ball = &s["key_numbers"]["ball"];
    let dt = number(ball, "dt")?;
    // Each model's key numbers come with the costs of their run: 10 s at Δt = 1 ms.
    ensure!(number(ball, "steps")? == 10_000.0, "{ball}");
    ensure!(number(ball, "lcp_solves")? > 0.0 && number(ball, "wall_seconds")? > 0.0, "{ball}");
    let top: BTreeSet<&str> =
        s.as_object().context("an object")?.keys().map(String::as_str).collect();
    let documented = [
        "generator",
        "quick",
        "key_numbers",
        "scale",
        "figures",
        "runs",
        "simulation_seconds",
        "total_seconds",
    ];
    ensure!(top == documented.into_iter().collect(), "summary.json's keys: {top:?}");
    let t1 = number(ball, "key_numbers.first_impact.t")?;
    let t1_exact = (2.0 * 0.9f64 / 9.81).sqrt();
    ensure!((t1 - t1_exact).abs() <= dt, "first impact {t1} vs closed form {t1_exact}");
    ensure!((number(ball, "key_numbers.closed_form.t1")? - t1_exact).abs() < 1e-12);
    let v1 = (2.0 * 9.81 * 0.9f64).sqrt();
    let v_pre = number(ball, "key_numbers.first_impact.v_pre")?;
    let v_post = number(ball, "key_numbers.first_impact.v_post")?;
    // Within the speed gained or lost over one step.
    ensure!((v_pre + v1).abs() <= 9.81 * dt, "v_pre {v_pre} vs {}", -v1);
    ensure!((v_post - 0.9 * v1).abs() <= 2.0 * 9.81 * dt, "v_post {v_post} vs {}", 0.9 * v1);
    // The ball rests once its flights are shorter than a step: within dt/(1 − ε_N) + dt of
    // the accumulation time, and not after it.
    let rest = number(ball, "key_numbers.rest_time")?;
    let t_inf = t1_exact * 1.9 / 0.1;
    ensure!(rest <= t_inf + dt && rest >= t_inf - (dt / 0.1 + dt), "rest {rest} vs t_inf {t_inf}");
    // The woodpecker settles on a limit cycle of period 0.1461 s (within 1 %) and descends.
    let wood = &s["key_numbers"]["woodpecker"]["key_numbers"];
    let period = number(wood, "cycle.period")?;
    ensure!((period - 0.1461).abs() <= 0.01 * 0.1461, "woodpecker period {period} vs 0.1461 s");
    ensure!(number(wood, "descent_speed")? > 0.0);
    // Two crank revolutions for each restitution coefficient.
    let slider = s["key_numbers"]["slider_crank"].as_array().context("slider runs")?;
    ensure!(slider.len() == 4);
    for run in slider {
        let revs = number(run, "key_numbers.revolutions")?;
        ensure!((revs - 2.0).abs() < 0.01, "revolutions {revs}");
    }
    Ok(())
}

/// The rows of a CSV without the given columns (measured wall times and the rates derived
/// from them), which must all be there.
fn without_columns(path: &Path, measured: &[&str]) -> Result<Vec<Vec<String>>> {
    let mut r = csv::Reader::from_path(path)?;
    let h: Vec<String> = r.headers()?.iter().map(str::to_owned).collect();
    let keep: Vec<usize> = (0..h.len()).filter(|&i| !measured.contains(&h[i].as_str())).collect();
    ensure!(keep.len() + measured.len() == h.len(), "{} lacks {measured:?}", path.display());
    let mut rows = vec![keep.iter().map(|&i| h[i].clone()).collect()];
    for rec in r.records() {
        let rec = rec?;
        rows.push(keep.iter().map(|&i| rec[i].to_owned()).collect());
    }
    Ok(rows)
}

fn csv_files(dir: &Path) -> Result<BTreeSet<String>> {
    let mut names = BTreeSet::new();
    for entry in std::fs::read_dir(dir)? {
        let name = entry?.file_name().to_string_lossy().into_owned();
        if name.ends_with(".csv") {
            names.insert(name);
        }
    }
    Ok(names)
}

#[test]
fn quick_reproduction_is_complete_and_independent_of_the_thread_count() -> Result<()> {
    let one = tempfile::tempdir()?;
    let two = tempfile::tempdir()?;
    run(&Options { out: one.path().to_owned(), quick: true, jobs: Some(1) })?;
    run(&Options { out: two.path().to_owned(), quick: true, jobs: Some(2) })?;
    check_outputs(two.path())?;
    let names = csv_files(one.path())?;
    ensure!(names == csv_files(two.path())?);
    for name in &names {
        // The speed/accuracy and scaling figures plot measured wall times, which differ
        // between runs; their tables are compared without them.
        if name.starts_with("figS1") || name.starts_with("fig_scale") {
            continue;
        }
        let measured: &[&str] = match name.as_str() {
            "tradeoff.csv" => &["wall_s", "steps_per_s", "lcp_solves_per_s"],
            "scale.csv" => &["ms_per_step", "ms_detection", "ms_assembly", "ms_solution"],
            _ => &[],
        };
        if !measured.is_empty() {
            let a = without_columns(&one.path().join(name), measured)?;
            ensure!(a == without_columns(&two.path().join(name), measured)?, "{name} differs");
            continue;
        }
        let a = std::fs::read(one.path().join(name))?;
        let b = std::fs::read(two.path().join(name))?;
        ensure!(a == b, "{name} differs between 1 and 2 threads");
    }
    Ok(())
}

/// A figure that cannot be written fails the reproduction, naming the figure, and leaves no
/// summary or report: neither its own nor that of an earlier reproduction into the folder.
#[test]
fn a_failed_figure_leaves_no_report() -> Result<()> {
    let dir = tempfile::tempdir()?;
    for name in ["summary.json", "report.html", "report.md"] {
        std::fs::write(dir.path().join(name), "an earlier reproduction")?;
    }
    // A folder where Fig 8.2's PNG goes.
    std::fs::create_dir(dir.path().join("fig08_02_ball.png"))?;
    let err = run(&Options { out: dir.path().to_owned(), quick: true, jobs: Some(2) })
        .expect_err("Fig 8.2 cannot be written");
    let message = format!("{err:#}");
    ensure!(message.contains("1 of 18 figures and tables failed"), "{message}");
    ensure!(message.contains("Fig 8.2 (fig08_02_ball)"), "{message}");
    for name in ["summary.json", "report.html", "report.md"] {
        ensure!(!dir.path().join(name).exists(), "{name} is left from an earlier reproduction");
    }
    // The other figures are drawn.
    ensure!(dir.path().join("fig08_03_ball_dt.png").exists());
    Ok(())
}
