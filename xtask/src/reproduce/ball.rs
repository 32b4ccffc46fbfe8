//! The bouncing ball: Fig 8.2, Table 8.2 and Fig 8.3.

use anyhow::{Context, Result, bail};
use moreau_models::{ModelKind, ModelParams};
use serde_json::json;

use super::{Ctx, Entry, Output, names};
use crate::keys;
use crate::plot::{Figure, LegendAt, Mark, Panel, Series};
use crate::runs::{RunResult, RunSpec};
use crate::table::Table;

/// The run of Fig 8.2 and Table 8.2 (Tab 8.1: ε_N = 0.9, Δt = 1 ms, 10 s).
pub(super) const MAIN: &str = "ball";
/// The runs of Fig 8.3 (ε_N = 0.7, Δt = 1 ms and 25 ms, 3 s).
pub(super) const DT_RUNS: [&str; 2] = ["ball_e0.7_dt1e-3", "ball_e0.7_dt2.5e-2"];

fn main_run(_quick: bool) -> Vec<RunSpec> {
    vec![RunSpec::new(MAIN, ModelKind::Ball, &[("eps_n", "0.9"), ("dt", "0.001"), ("t_end", "10")])]
}

fn dt_runs(_quick: bool) -> Vec<RunSpec> {
    vec![
        RunSpec::new(
            DT_RUNS[0],
            ModelKind::Ball,
            &[("eps_n", "0.7"), ("dt", "0.001"), ("t_end", "3")],
        ),
        RunSpec::new(
            DT_RUNS[1],
            ModelKind::Ball,
            &[("eps_n", "0.7"), ("dt", "0.025"), ("t_end", "3")],
        ),
    ]
}

pub(super) fn entries() -> Vec<Entry> {
    vec![
        Entry {
            id: "Fig 8.2",
            stem: "fig08_02_ball",
            caption: "Bouncing ball, Tab 8.1 parameters (m = 1 kg, R = 0.1 m, y0 = 1 m, ε_N = 0.9, \
                      Δt = 0.001 s), 0–10 s: (a) height y of the centre, (b) velocity v, (c) normal \
                      impulse Λ_N of each step, (d) potential, kinetic and total energy.",
            runs: main_run,
            draw: fig8_2,
        },
        Entry {
            id: "Table 8.2",
            stem: "table8_2",
            caption: "Step-by-step record of the bouncing ball around its first impact (ε_N = 0.9, \
                      Δt = 0.001 s): state at the start of each step (t, y, v), midpoint quantities \
                      (t_M, q_M, M_M, h_M, g_N(q_M)), the LCP constant b = (1 + ε_N) v_A − g Δt, the \
                      impulse Λ_N and ξ_N = A Λ_N + b with A = 1/m. Rows: t = 0 and seven steps \
                      either side of the impact step.",
            runs: main_run,
            draw: table8_2,
        },
        Entry {
            id: "Fig 8.3",
            stem: "fig08_03_ball_dt",
            caption: "Bouncing ball with ε_N = 0.7 and two time steps, Δt = 0.001 s and Δt = 0.025 s, \
                      0–3 s: (a) position, (b) velocity, (c) impulse per step.",
            runs: dt_runs,
            draw: fig8_3,
        },
    ]
}

fn fig8_2(ctx: &Ctx<'_>, e: &Entry) -> Result<Output> {
    let run = ctx.run(MAIN)?;
    let r = run.record();
    let t = r.t.clone();
    let fig = Figure::new(
        "Fig 8.2  Bouncing ball (ε_N = 0.9, Δt = 0.001 s)",
        vec![
            Panel::new("(a) position", "t [s]", "y [m]", "t").with(Series::line(
                "",
                "y",
                t.clone(),
                run.q(0),
                0,
            )),
            Panel::new("(b) velocity", "t [s]", "v [m/s]", "t").with(Series::line(
                "",
                "v",
                t.clone(),
                run.u(0),
                0,
            )),
            Panel::new("(c) impulse", "t [s]", "Λ_N [kg m/s]", "t").with(Series::line(
                "",
                "Lambda_N",
                t.clone(),
                run.p_n(0),
                0,
            )),
            Panel::new("(d) energy", "t [s]", "E [J]", "t")
                .with(Series::line("potential", "E_potential", t.clone(), r.potential.clone(), 0))
                .with(Series::line("kinetic", "E_kinetic", t.clone(), r.kinetic.clone(), 1))
                .with(
                    Series::line("total", "E_total", t, r.total_energy(), 6)
                        .with_mark(Mark::Dashed),
                ),
        ],
        2,
    );
    let files = fig.write(ctx.out, e.stem)?;
    Ok(Output { files: names(&files), key_numbers: json!(keys::ball(run)), markdown: None })
}

/// The rows of Table 8.2: step s goes from row s to row s + 1 of the record.
pub(crate) fn table_rows(run: &RunResult, either_side: usize) -> Result<Table> {
    let ModelParams::Ball(p) = &run.scene.params else { bail!("Table 8.2 needs a ball run") };
    let r = run.record();
    let dt = run.scene.dt;
    let first =
        (1..r.len()).find(|&k| r.p_n[k][0] > 0.0).context("the ball never hits the floor")?;
    let impact_step = first - 1;
    let mut steps = vec![0];
    let lo = impact_step.saturating_sub(either_side).max(1);
    let hi = (impact_step + either_side).min(r.len() - 2);
    steps.extend(lo..=hi);
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 12];
    for s in steps {
        let (t_a, y_a, v_a) = (r.t[s], r.q[s][0], r.u[s][0]);
        let t_m = t_a + 0.5 * dt;
        let q_m = y_a + 0.5 * dt * v_a;
        let g_n = q_m - p.r;
        let b = (1.0 + p.eps_n) * v_a - p.g * dt;
        let lambda = r.p_n[s + 1][0];
        let xi = lambda / p.m + b;
        let active = g_n <= 0.0;
        let row = [
            t_a,
            y_a,
            v_a,
            t_m,
            q_m,
            p.m,
            -p.m * p.g,
            g_n,
            if active { 1.0 } else { 0.0 },
            b,
            lambda,
            xi,
        ];
        for (c, v) in cols.iter_mut().zip(row) {
            c.push(v);
        }
    }
    let headers =
        ["t", "y", "v", "t_M", "q_M", "M_M", "h_M", "g_N(q_M)", "active", "b", "Lambda_N", "xi_N"];
    let mut table = Table::default();
    for (h, c) in headers.iter().zip(cols) {
        table.push_column(h, c);
    }
    Ok(table)
}

fn table8_2(ctx: &Ctx<'_>, e: &Entry) -> Result<Output> {
    let run = ctx.run(MAIN)?;
    let table = table_rows(run, 7)?;
    let csv = ctx.out.join(format!("{}.csv", e.stem));
    table.write_csv(&csv)?;
    let md = markdown(&table);
    let md_path = ctx.out.join(format!("{}.md", e.stem));
    let text = format!(
        "# Table 8.2  Bouncing ball around the first impact\n\n{}\n\n{md}\n\
         b is the LCP constant (the column the report heads w_NM); active = 1 when g_N(q_M) ≤ 0 and \
         the contact enters the LCP; ξ_N = Λ_N/m + b. Here b and ξ_N are shown for the steps in \
         the LCP only; the CSV has them for every step.\n",
        e.caption
    );
    std::fs::write(&md_path, text)?;
    let k = keys::ball(run);
    Ok(Output {
        files: vec![format!("{}.csv", e.stem), format!("{}.md", e.stem)],
        key_numbers: json!({"first_impact": k.first_impact, "closed_form": k.closed_form}),
        markdown: Some(md),
    })
}

/// Table 8.2 as Markdown; b and ξ_N are left blank for steps whose contact is not in the LCP.
fn markdown(table: &Table) -> String {
    let headers = table.headers();
    let col = |name: &str| table.column(name).unwrap_or(&[]);
    let active = col("active");
    let mut s = format!("| {} |\n|{}\n", headers.join(" | "), "---:|".repeat(headers.len()));
    for r in 0..table.rows() {
        let on = active.get(r).is_some_and(|&a| a > 0.5);
        let cells: Vec<String> = headers
            .iter()
            .map(|h| {
                let x = col(h).get(r).copied().unwrap_or(f64::NAN);
                match *h {
                    "active" => format!("{x:.0}"),
                    "M_M" | "h_M" => format!("{x:.2}"),
                    "b" | "xi_N" if !on => "—".to_owned(),
                    _ => format!("{x:.6}"),
                }
            })
            .collect();
        s.push_str(&format!("| {} |\n", cells.join(" | ")));
    }
    s
}

fn fig8_3(ctx: &Ctx<'_>, e: &Entry) -> Result<Output> {
    let fine = ctx.run(DT_RUNS[0])?;
    let coarse = ctx.run(DT_RUNS[1])?;
    let mut panels = vec![
        Panel::new("(a) position", "t [s]", "y [m]", "t"),
        Panel::new("(b) velocity", "t [s]", "v [m/s]", "t"),
        Panel::new("(c) impulse", "t [s]", "Λ_N [kg m/s]", "t"),
    ];
    for (j, (run, label, tag)) in
        [(fine, "Δt = 0.001 s", "dt1e-3"), (coarse, "Δt = 0.025 s", "dt2.5e-2")]
            .into_iter()
            .enumerate()
    {
        let t = run.record().t.clone();
        let mark = if j == 0 { Mark::Line } else { Mark::Dashed };
        let data = [run.q(0), run.u(0), run.p_n(0)];
        for ((panel, y), name) in panels.iter_mut().zip(data).zip(["y", "v", "Lambda_N"]) {
            panel.series.push(
                Series::line(label, &format!("{name}_{tag}"), t.clone(), y, j).with_mark(mark),
            );
        }
    }
    panels[2].legend = LegendAt::UpperRight;
    let fig = Figure::new("Fig 8.3  Bouncing ball, ε_N = 0.7, two time steps", panels, 3)
        .panel_size(560, 420);
    let files = fig.write(ctx.out, e.stem)?;
    Ok(Output {
        files: names(&files),
        key_numbers: json!({"dt_0.001": keys::ball(fine), "dt_0.025": keys::ball(coarse)}),
        markdown: None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_rows_satisfy_the_scalar_lcp() -> Result<()> {
        let run = RunSpec::new("t", ModelKind::Ball, &[("t_end", "0.6")]).execute()?;
        let table = table_rows(&run, 3)?;
        assert_eq!(table.rows(), 1 + 7);
        let col = |n: &str| table.column(n).map(<[f64]>::to_vec).context(n.to_owned());
        let (t, v, active, b, lambda, xi) =
            (col("t")?, col("v")?, col("active")?, col("b")?, col("Lambda_N")?, col("xi_N")?);
        assert_eq!(t[0], 0.0);
        // One active step: the impact, with Λ_N = −b/A (A = 1/m = 1) and ξ_N = 0, so that
        // v_E = −ε_N v_A: the next row's v.
        let k = active.iter().position(|&a| a > 0.5).context("an active step")?;
        assert_eq!(active.iter().filter(|&&a| a > 0.5).count(), 1);
        assert!((lambda[k] + b[k]).abs() < 1e-12 && xi[k].abs() < 1e-12);
        assert!((v[k + 1] + 0.9 * v[k]).abs() < 1e-12, "{} vs {}", v[k + 1], -0.9 * v[k]);
        // The impact is the step that contains t1 = sqrt(2H/g).
        let t1 = (1.8f64 / 9.81).sqrt();
        assert!(t[k] <= t1 + 1e-3 && t1 <= t[k] + 2e-3, "{} vs {t1}", t[k]);
        let md = markdown(&table);
        assert_eq!(md.lines().count(), 2 + 8);
        assert_eq!(md.matches('—').count(), 2 * 7);
        Ok(())
    }
}
