//! The study's outputs: the table rows, the markdown report, the solver costs and the
//! step-size choices, the key numbers and the figures.

use super::*;

/// One row of the table: a run and one of its error measures.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Row {
    /// Model name.
    pub model: String,
    /// Solver label.
    pub solver: String,
    /// Step h (s).
    pub dt: f64,
    /// Error measure.
    pub metric: String,
    /// Steps taken.
    pub steps: u64,
    /// LCP solves.
    pub lcp_solves: u64,
    /// Measured wall time (s).
    pub wall_s: f64,
    /// Steps per second.
    pub steps_per_s: f64,
    /// LCP solves per second.
    pub lcp_solves_per_s: f64,
    /// The error, when measured.
    pub error: Option<f64>,
    /// Unit of the error.
    pub unit: String,
    /// `ok`, `reference`, `failed: <reason>` or `not measured: <reason>`.
    pub status: String,
}

fn status_of(m: &Measurement, e: &Result<f64, String>) -> String {
    match (&m.outcome, e) {
        (Err(reason), _) => format!("failed: {reason}"),
        (Ok(o), _) if o.diverged() => {
            format!("diverged: the state grew to {:.1e}", o.max_state)
        }
        (Ok(_), Ok(_)) => "ok".to_owned(),
        (Ok(_), Err(why)) => format!("not measured: {why}"),
    }
}

/// The table rows of all studies: every run and metric, then each reference (h_ref, its error
/// against the run at h_ref/2).
pub fn rows(results: &[StudyResult]) -> Vec<Row> {
    let mut out = Vec::new();
    let row =
        |r: &StudyResult, m: &Measurement, metric: &Metric, e: &Result<f64, String>, status| Row {
            model: r.study.label().to_owned(),
            solver: m.solver.label(),
            dt: m.dt,
            metric: metric.name.to_owned(),
            steps: m.steps,
            lcp_solves: m.lcp_solves,
            wall_s: m.wall_seconds,
            steps_per_s: m.steps_per_second(),
            lcp_solves_per_s: m.lcp_solves_per_second(),
            error: e.as_ref().ok().copied(),
            unit: metric.unit.to_owned(),
            status,
        };
    for r in results {
        for (m, errs) in r.runs.iter().zip(&r.errors) {
            for (metric, e) in r.metrics().iter().zip(errs) {
                out.push(row(r, m, metric, e, status_of(m, e)));
            }
        }
        if let Some((href, half)) = &r.reference {
            for (metric, e) in r.metrics().iter().zip(&r.reference_error) {
                let status = match e {
                    Ok(_) => format!("reference: against h_ref/2 = {:e} s", half.dt),
                    Err(why) => format!("reference: not measured: {why}"),
                };
                out.push(row(r, href, metric, e, status));
            }
        }
    }
    out
}

/// A number for tables: three significant digits in scientific notation.
fn sci(x: f64) -> String {
    if x == 0.0 { "0".to_owned() } else { format!("{x:.2e}") }
}

fn md_cell(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// The Markdown of the study: observed orders, the reference's convergence and one row per
/// run (headline error, the other errors in the last column).
pub fn markdown(results: &[StudyResult]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Observed order p of convergence: least-squares slope of log10 error against log10 Δt \
         over the finest {FIT_POINTS} runs of one solver whose errors lie above round-off \
         ({ROUND_OFF:e}) and above {REFERENCE_MARGIN}× the reference's own error; diverged runs \
         are left out.\n"
    );
    let _ =
        writeln!(s, "| model | error | unit | phase | solver | Δt range [s] | points | order p |");
    let _ = writeln!(s, "|---|---|---|---|---|---|---:|---:|");
    for r in results {
        for o in &r.orders {
            let (range, points, p) = match &o.fit {
                Ok(f) => (
                    format!("{:e} – {:e}", f.dt_min, f.dt_max),
                    f.points.to_string(),
                    format!("{:.2}", f.order),
                ),
                Err(why) => ("—".to_owned(), "0".to_owned(), format!("— ({why})")),
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {range} | {points} | {} |",
                r.study.label(),
                o.metric.name,
                o.metric.unit,
                o.metric.stretch.name(),
                o.solver,
                md_cell(&p)
            );
        }
    }
    let _ = writeln!(
        s,
        "\nReference runs (Auto solver) and their own error: the run at h_ref/2 against the run \
         at h_ref.\n"
    );
    let _ = writeln!(
        s,
        "| model | h_ref [s] | error | difference h_ref vs h_ref/2 | unit | steps | wall [s] |"
    );
    let _ = writeln!(s, "|---|---:|---|---:|---|---:|---:|");
    for r in results {
        match &r.reference {
            Some((href, _)) => {
                for (metric, e) in r.metrics().iter().zip(&r.reference_error) {
                    let v = match e {
                        Ok(x) => sci(*x),
                        Err(why) => format!("— ({})", md_cell(why)),
                    };
                    let _ = writeln!(
                        s,
                        "| {} | {:e} | {} | {v} | {} | {} | {:.2} |",
                        r.study.label(),
                        href.dt,
                        metric.name,
                        metric.unit,
                        href.steps,
                        href.wall_seconds
                    );
                }
            }
            None => {
                let _ = writeln!(s, "| {} | closed form | | | | | |", r.study.label());
            }
        }
    }
    s.push_str(&choices(results));
    s.push_str(&costs_markdown(results));
    let _ = writeln!(
        s,
        "\nRuns: cost and error. Wall times are measured (they vary between machines and runs); \
         steps, LCP solves and errors are deterministic.\n"
    );
    let _ = writeln!(
        s,
        "| model | solver | Δt [s] | steps | LCP solves | wall [s] | steps/s | LCP solves/s | error | unit | status | other errors |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|---:|---:|---|---|---|");
    for r in results {
        let ms = r.metrics();
        for (m, errs) in r.runs.iter().zip(&r.errors) {
            let head = &errs[0];
            let others: Vec<String> = ms
                .iter()
                .zip(errs)
                .skip(1)
                .map(|(metric, e)| match e {
                    Ok(x) => format!("{}: {} {}", metric.name, sci(*x), metric.unit),
                    Err(_) if m.outcome.is_err() => format!("{}: —", metric.name),
                    Err(why) => format!("{}: — ({why})", metric.name),
                })
                .collect();
            let _ = writeln!(
                s,
                "| {} | {} | {:e} | {} | {} | {:.2e} | {:.2e} | {:.2e} | {} | {} | {} | {} |",
                r.study.label(),
                m.solver.label(),
                m.dt,
                m.steps,
                m.lcp_solves,
                m.wall_seconds,
                m.steps_per_second(),
                m.lcp_solves_per_second(),
                head.as_ref().map_or("—".to_owned(), |x| sci(*x)),
                ms[0].unit,
                md_cell(&status_of(m, head)),
                md_cell(&others.join("; "))
            );
        }
    }
    s
}

/// One choice of step and solver for an error target.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Choice {
    /// Model name.
    pub model: String,
    /// The headline error measure.
    pub metric: String,
    /// Unit of the error.
    pub unit: String,
    /// Error target (a power of ten).
    pub target: f64,
    /// Largest step h whose Auto run meets the target (s).
    pub dt: f64,
    /// Error of that run.
    pub error: f64,
    /// Wall time of that run (s).
    pub wall_s: f64,
    /// The fastest solver meeting the target at that step, and its wall time (s).
    pub fastest: (String, f64),
}

/// The cost and accuracy of one solver on one model.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SolverCost {
    /// Model name.
    pub model: String,
    /// Solver label.
    pub solver: String,
    /// Runs that finished (not failed, not diverged) and runs in all.
    pub finished: (usize, usize),
    /// Steps per second over the finished runs of at least 1000 steps (total steps over total
    /// wall time).
    pub steps_per_s: Option<f64>,
    /// LCP solves per second over the same runs.
    pub lcp_solves_per_s: Option<f64>,
    /// Smallest and largest ratio of the headline error to the fitted solver's at the same
    /// step, over steps where that error lies above the floor.
    pub error_ratio: Option<(f64, f64)>,
}

/// Cost and accuracy of each solver on each model.
pub fn solver_costs(results: &[StudyResult]) -> Vec<SolverCost> {
    let mut out = Vec::new();
    for r in results {
        let fitted = r.fitted_solver();
        let floor = r.floor(0);
        let reference: Vec<(f64, f64)> =
            headline(r, fitted).into_iter().map(|p| (p.0, p.2)).filter(|p| p.1 > floor).collect();
        for &solver in &r.study.solvers {
            let runs: Vec<&Measurement> = r.runs.iter().filter(|m| m.solver == solver).collect();
            let finished: Vec<&&Measurement> =
                runs.iter().filter(|m| m.outcome.is_ok() && !m.diverged()).collect();
            let long: Vec<&&&Measurement> = finished.iter().filter(|m| m.steps >= 1000).collect();
            let wall: f64 = long.iter().map(|m| m.wall_seconds).sum();
            let rate = |count: u64| (wall > 0.0).then(|| count as f64 / wall);
            let ratios = headline(r, solver)
                .into_iter()
                .filter_map(|p| reference.iter().find(|q| q.0 == p.0).map(|q| p.2 / q.1));
            out.push(SolverCost {
                model: r.study.label().to_owned(),
                solver: solver.label(),
                finished: (finished.len(), runs.len()),
                steps_per_s: rate(long.iter().map(|m| m.steps).sum()),
                lcp_solves_per_s: rate(long.iter().map(|m| m.lcp_solves).sum()),
                error_ratio: analysis::range(ratios),
            });
        }
    }
    out
}

fn costs_markdown(results: &[StudyResult]) -> String {
    let mut s = String::from(
        "\nCost of each solver: steps and LCP solves per second of wall time over its finished \
         runs of at least 1000 steps, and its headline error relative to the Auto solver's at the \
         same Δt.\n\n\
         | model | solver | runs neither failed nor diverged | steps/s | LCP solves/s | error / Auto error |\n\
         |---|---|---:|---:|---:|---|\n",
    );
    let opt = |x: Option<f64>| x.map_or("—".to_owned(), |v| format!("{v:.2e}"));
    for c in solver_costs(results) {
        let ratio = c.error_ratio.map_or("—".to_owned(), |(lo, hi)| format!("{lo:.3} – {hi:.3}"));
        let _ = writeln!(
            s,
            "| {} | {} | {} of {} | {} | {} | {ratio} |",
            c.model,
            c.solver,
            c.finished.0,
            c.finished.1,
            opt(c.steps_per_s),
            opt(c.lcp_solves_per_s)
        );
    }
    s
}

/// For each model and each power of ten between its largest and smallest headline error:
/// the largest step whose Auto run meets it, and the fastest solver meeting it at that step.
pub fn choose(results: &[StudyResult]) -> Vec<Choice> {
    let mut out = Vec::new();
    for r in results {
        let metric = &r.metrics()[0];
        let fitted = r.fitted_solver();
        let floor = r.floor(0);
        let auto: Vec<(f64, f64, f64)> =
            headline(r, fitted).into_iter().filter(|p| p.2 > floor).collect();
        let Some((lo, hi)) = analysis::range(auto.iter().map(|p| p.2)) else { continue };
        let (top, bottom) = (hi.log10().floor() as i32, lo.log10().ceil() as i32);
        for k in (bottom..=top).rev() {
            let target = 10f64.powi(k);
            let best = auto.iter().filter(|p| p.2 <= target).max_by(|a, b| a.0.total_cmp(&b.0));
            let Some(&(dt, wall, error)) = best else { continue };
            let fastest = r
                .study
                .solvers
                .iter()
                .flat_map(|&solver| headline(r, solver).into_iter().map(move |p| (solver, p)))
                .filter(|(_, p)| p.0 == dt && p.2 <= target)
                .min_by(|a, b| a.1.1.total_cmp(&b.1.1))
                .map_or((fitted.label(), wall), |(solver, p)| (solver.label(), p.1));
            out.push(Choice {
                model: r.study.label().to_owned(),
                metric: metric.name.to_owned(),
                unit: metric.unit.to_owned(),
                target,
                dt,
                error,
                wall_s: wall,
                fastest,
            });
        }
    }
    out
}

fn choices(results: &[StudyResult]) -> String {
    let mut s = String::from(
        "\nStep size for an error target: the largest Δt whose Auto run meets it (headline \
         error), and the fastest solver meeting it at that Δt.\n\n\
         | model | error | target | largest Δt [s] | error at Δt | auto wall [s] | fastest solver | its wall [s] |\n\
         |---|---|---:|---:|---:|---:|---|---:|\n",
    );
    for c in choose(results) {
        let _ = writeln!(
            s,
            "| {} | {} | {:e} {} | {:e} | {} | {:.2e} | {} | {:.2e} |",
            c.model,
            c.metric,
            c.target,
            if c.unit == "-" { "(relative)" } else { c.unit.as_str() },
            c.dt,
            sci(c.error),
            c.wall_s,
            c.fastest.0,
            c.fastest.1
        );
    }
    s
}

/// Key numbers: observed orders and the references' own errors.
pub fn key_numbers(results: &[StudyResult]) -> Value {
    let mut orders = serde_json::Map::new();
    let mut references = serde_json::Map::new();
    for r in results {
        for (o, e) in r.orders.iter().zip(&r.reference_error) {
            let key = format!("{} {}", r.study.label(), o.metric.name);
            orders.insert(
                key.clone(),
                match &o.fit {
                    Ok(f) => json!(f.order),
                    Err(why) => json!(why),
                },
            );
            if let Some((h, _)) = &r.reference {
                references.insert(
                    key,
                    json!({"h_ref": h.dt, "difference": e.as_ref().ok(), "unit": o.metric.unit}),
                );
            }
        }
    }
    json!({"observed_order": orders, "reference_error": references})
}

/// The stem of the error-against-wall-time figure.
pub const WALL_STEM: &str = "figS1_speed_accuracy";
/// The stem of the error-against-step figure.
pub const DT_STEM: &str = "figS2_error_vs_dt";

fn panel_title(p: usize, r: &StudyResult) -> String {
    let m = &r.metrics()[0];
    let letter = (b'a' + (p % 26) as u8) as char;
    format!("({letter}) {}: {} [{}]", r.study.label(), m.name, m.unit)
}

fn solver_mark(solver: Solver) -> Mark {
    if solver == Solver::Lemke { Mark::Rings } else { Mark::Points }
}

/// The headline errors of one solver's runs: (Δt, wall time, error) of the runs with a
/// positive error.
fn headline(r: &StudyResult, solver: Solver) -> Vec<(f64, f64, f64)> {
    r.runs
        .iter()
        .zip(&r.errors)
        .filter(|(m, _)| m.solver == solver && !m.diverged())
        .filter_map(|(m, e)| match e[0] {
            Ok(x) if x > 0.0 => Some((m.dt, m.wall_seconds, x)),
            _ => None,
        })
        .collect()
}

/// Writes the two figures (SVG, PNG and a CSV of the plotted points each).
fn write_figures(results: &[StudyResult], out: &Path) -> Result<Vec<PathBuf>> {
    let mut wall_panels = Vec::new();
    let mut dt_panels = Vec::new();
    let mut wall_csv = csv::Writer::from_path(out.join(format!("{WALL_STEM}.csv")))?;
    wall_csv.write_record(["model", "metric", "unit", "solver", "dt", "wall_s", "error"])?;
    let mut dt_csv = csv::Writer::from_path(out.join(format!("{DT_STEM}.csv")))?;
    dt_csv.write_record(["model", "metric", "unit", "series", "dt", "error"])?;
    for (p, r) in results.iter().enumerate() {
        let metric = &r.metrics()[0];
        let title = panel_title(p, r);
        let mut wall = Panel::new(
            &title,
            "log10 wall time [s]",
            &format!("log10 error [{}]", metric.unit),
            "log10_wall",
        )
        .legend(LegendAt::UpperRight)
        .headroom(0.3);
        let mut by_dt = Panel::new(
            &title,
            "log10 Δt [s]",
            &format!("log10 error [{}]", metric.unit),
            "log10_dt",
        )
        .legend(LegendAt::UpperLeft)
        .headroom(0.45);
        for (j, &solver) in r.study.solvers.iter().enumerate() {
            let points = headline(r, solver);
            let label = solver.label();
            for &(dt, w, e) in &points {
                wall_csv.write_record([
                    r.study.label(),
                    metric.name,
                    metric.unit,
                    &label,
                    &format!("{dt:e}"),
                    &format!("{w}"),
                    &format!("{e}"),
                ])?;
                dt_csv.write_record([
                    r.study.label(),
                    metric.name,
                    metric.unit,
                    &label,
                    &format!("{dt:e}"),
                    &format!("{e}"),
                ])?;
            }
            let xs: Vec<f64> = points.iter().map(|p| p.1.max(1e-7).log10()).collect();
            let hs: Vec<f64> = points.iter().map(|p| p.0.log10()).collect();
            let ys: Vec<f64> = points.iter().map(|p| p.2.log10()).collect();
            let column = format!("{}_{}", r.study.label(), label.replace(' ', "_"));
            let mut dots = Series::line("", &column, xs.clone(), ys.clone(), j)
                .with_mark(solver_mark(solver))
                .not_data();
            if solver == Solver::Auto {
                dots =
                    dots.with_point_labels(points.iter().map(|p| format!("{:e}", p.0)).collect());
            }
            wall.series
                .push(Series::line(&label, &column, xs, ys.clone(), j).with_mark(Mark::Dashed));
            wall.series.push(dots);
            by_dt.series.push(
                Series::line(&label, &column, hs.clone(), ys.clone(), j).with_mark(Mark::Dashed),
            );
            by_dt.series.push(
                Series::line("", &column, hs, ys, j).with_mark(solver_mark(solver)).not_data(),
            );
        }
        if let Some(Ok(fit)) = r.orders.first().map(|o| &o.fit) {
            let ends = [fit.dt_min, fit.dt_max];
            by_dt.series.push(Series::line(
                &format!("fit ({}): p = {:.2}", r.orders[0].solver, fit.order),
                "fit",
                ends.iter().map(|h| h.log10()).collect(),
                ends.iter().map(|h| fit.at(*h).log10()).collect(),
                6,
            ));
            for h in ends {
                dt_csv.write_record([
                    r.study.label(),
                    metric.name,
                    metric.unit,
                    &format!("fit p = {}", fit.order),
                    &format!("{h:e}"),
                    &format!("{}", fit.at(h)),
                ])?;
            }
        }
        if let (Some((href, _)), Some(Ok(e))) = (&r.reference, r.reference_error.first())
            && *e > 0.0
        {
            let lo = href.dt.log10();
            let hi = r.study.steps.first().copied().unwrap_or(href.dt).log10();
            by_dt.series.push(
                Series::line(
                    "reference h_ref vs h_ref/2",
                    "reference",
                    vec![lo, hi],
                    vec![e.log10(); 2],
                    7,
                )
                .with_mark(Mark::Dashed),
            );
            by_dt.series.push(
                Series::line("", "reference_point", vec![lo], vec![e.log10()], 7)
                    .with_mark(Mark::Rings)
                    .not_data(),
            );
            dt_csv.write_record([
                r.study.label(),
                metric.name,
                metric.unit,
                "reference",
                &format!("{:e}", href.dt),
                &format!("{e}"),
            ])?;
        }
        wall_panels.push(wall);
        dt_panels.push(by_dt);
    }
    wall_csv.flush()?;
    dt_csv.flush()?;
    let mut files = Vec::new();
    for (stem, title, panels) in [
        (
            WALL_STEM,
            "Error against wall time per model and LCP solver (points: Δt of the auto runs)",
            wall_panels,
        ),
        (
            DT_STEM,
            "Error against step size Δt per model and LCP solver, with the fitted order",
            dt_panels,
        ),
    ] {
        let fig = Figure::new(title, panels, 2);
        let svg = out.join(format!("{stem}.svg"));
        let png = out.join(format!("{stem}.png"));
        fig.write_svg(&svg)?;
        fig.write_png(&png)?;
        files.extend([svg, png, out.join(format!("{stem}.csv"))]);
    }
    Ok(files)
}

/// Writes `tradeoff.csv` (one row per run and error measure).
fn write_table(results: &[StudyResult], path: &Path) -> Result<()> {
    let mut w =
        csv::Writer::from_path(path).with_context(|| format!("creating {}", path.display()))?;
    w.write_record([
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
        "status",
    ])?;
    for r in rows(results) {
        w.write_record([
            r.model,
            r.solver,
            format!("{:e}", r.dt),
            r.metric,
            r.steps.to_string(),
            r.lcp_solves.to_string(),
            format!("{}", r.wall_s),
            format!("{}", r.steps_per_s),
            format!("{}", r.lcp_solves_per_s),
            r.error.map_or(String::new(), |e| format!("{e}")),
            r.unit,
            r.status,
        ])?;
    }
    w.flush()?;
    Ok(())
}

/// What [`write()`] produced.
#[derive(Clone, Debug, Default)]
pub struct Written {
    /// Files written (names relative to the output folder).
    pub files: Vec<String>,
    /// The Markdown of the study (orders, references, runs), without a title.
    pub markdown: String,
    /// Key numbers (observed orders, reference errors).
    pub key_numbers: Value,
}

/// Writes the figures, `tradeoff.csv` and `tradeoff.md` into `out`; `command` is the command
/// line named in `tradeoff.md`.
///
/// # Errors
/// When a file cannot be written or a figure cannot be drawn.
pub fn write(results: &[StudyResult], out: &Path, command: &str) -> Result<Written> {
    let mut paths = write_figures(results, out)?;
    let csv = out.join("tradeoff.csv");
    write_table(results, &csv)?;
    paths.push(csv);
    let md = markdown(results);
    let descriptions: String = results
        .iter()
        .flat_map(|r| {
            r.metrics().iter().map(move |m| {
                format!("- {} — {} [{}]: {}.\n", r.study.label(), m.name, m.unit, m.description)
            })
        })
        .collect();
    let text = format!(
        "# Speed and accuracy\n\nGenerated by `{command}`. Each model runs its report scene \
         (the ball with ε_N = 0.7 for 3 s) at each step size Δt with each LCP solver. Errors:\n\n\
         {descriptions}\n{md}"
    );
    let path = out.join("tradeoff.md");
    std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
    paths.push(path);
    let files = crate::reproduce::names(&paths);
    Ok(Written { files, markdown: md, key_numbers: key_numbers(results) })
}

/// The runs that a typed error stopped, references included, each as `model solver Δt:
/// reason`. A diverged run is a result of the study (the step is beyond the stability
/// limit), not a failure.
pub fn failed_runs(results: &[StudyResult]) -> Vec<String> {
    results
        .iter()
        .flat_map(|r| {
            let references = r.reference.iter().flat_map(|(a, b)| [a, b]);
            references.chain(&r.runs).filter_map(move |m| {
                let reason = m.outcome.as_ref().err()?;
                Some(format!(
                    "{} {} Δt = {:e} s: {reason}",
                    r.study.label(),
                    m.solver.label(),
                    m.dt
                ))
            })
        })
        .collect()
}

/// Ends in an error that counts and names the failed runs ([`failed_runs`]), if any.
///
/// # Errors
/// When a run of the study failed.
pub fn check_runs(results: &[StudyResult]) -> Result<()> {
    let failed = failed_runs(results);
    let all: usize =
        results.iter().map(|r| r.runs.len() + 2 * usize::from(r.reference.is_some())).sum();
    if let Some(first) = failed.first() {
        anyhow::bail!(
            "{} of {all} runs of the speed/accuracy study failed (listed as failed in \
             tradeoff.csv), the first: {first}",
            failed.len()
        );
    }
    Ok(())
}
