//! Fig 3.2 (Signorini's and Coulomb's laws from `Upr` and `Sgn`) and Fig I.2 (the scalar LCP
//! in its four sign cases, solved by enumeration).

use anyhow::Result;
use moreau_lcp::{Enumeration, Lcp};
use moreau_setvalued::{coulomb_graph, signorini_graph};
use serde_json::json;

use super::{Ctx, Entry, Output, names};
use crate::plot::{Figure, LegendAt, Mark, Panel, Series};

pub(super) fn entries() -> Vec<Entry> {
    vec![
        Entry {
            id: "Fig 3.2",
            stem: "fig03_02_laws",
            caption: "Set-valued force laws sampled from the project's Upr and Sgn: (a) Signorini's law, \
                      g_N ≥ 0, λ_N ≥ 0, g_N λ_N = 0 (−λ_N ∈ Upr(g_N)); (b) Coulomb's law, \
                      −λ_T ∈ μλ_N Sgn(γ_T) with μ = 0.3 and λ_N = 1 N.",
            runs: |_| Vec::new(),
            draw: fig3_2,
        },
        Entry {
            id: "Fig I.2",
            stem: "figI_02_scalar_lcp",
            caption: "The scalar LCP y = a x + b, 0 ≤ y ⊥ x ≥ 0, for the four sign cases of (a, b): the \
                      line, the complementarity corner, and every solution found by the project's \
                      enumeration solver (rings).",
            runs: |_| Vec::new(),
            draw: fig_i2,
        },
    ]
}

/// Friction coefficient and normal force of the drawn Coulomb law.
const MU: f64 = 0.3;
const LAMBDA_N: f64 = 1.0;

fn fig3_2(ctx: &Ctx<'_>, e: &Entry) -> Result<Output> {
    let sig = signorini_graph(1.0, 1.0, 201)?;
    let cou = coulomb_graph(MU, LAMBDA_N, -1.0, 1.0, 201)?;
    let (gx, gy): (Vec<f64>, Vec<f64>) = sig.into_iter().unzip();
    let (cx, cy): (Vec<f64>, Vec<f64>) = cou.into_iter().unzip();
    let b = MU * LAMBDA_N;
    let fig = Figure::new(
        "Fig 3.2  Set-valued force laws",
        vec![
            Panel::new(
                "(a) Signorini: −λ_N ∈ Upr(g_N)",
                "gap g_N [m]",
                "normal force λ_N [N]",
                "g_N",
            )
            .with(
                Series::line("graph of Signorini's law", "lambda_N", gx, gy, 0)
                    .with_mark(Mark::ThickLine),
            )
            .x_range(-1.0, 1.0)
            .y_range(-0.2, 1.0),
            Panel::new(
                "(b) Coulomb: −λ_T ∈ μλ_N Sgn(γ_T)",
                "sliding velocity γ_T [m/s]",
                "friction force λ_T [N]",
                "gamma_T",
            )
            .with(
                Series::line("graph of Coulomb's law", "lambda_T", cx, cy, 1)
                    .with_mark(Mark::ThickLine),
            )
            .with(
                Series::line("±μλ_N", "", vec![-1.0, 1.0], vec![b, b], 7)
                    .with_mark(Mark::Dashed)
                    .not_data(),
            )
            .with(
                Series::line("", "", vec![-1.0, 1.0], vec![-b, -b], 7)
                    .with_mark(Mark::Dashed)
                    .not_data(),
            )
            .x_range(-1.0, 1.0)
            .y_range(-0.5, 0.5),
        ],
        2,
    );
    let files = fig.write(ctx.out, e.stem)?;
    Ok(Output {
        files: names(&files),
        key_numbers: json!({"mu": MU, "lambda_N": LAMBDA_N, "friction_bound": b}),
        markdown: None,
    })
}

fn fig_i2(ctx: &Ctx<'_>, e: &Entry) -> Result<Output> {
    let cases = [
        ("(a) a > 0, b > 0", 1.0, 1.0),
        ("(b) a > 0, b < 0", 1.0, -1.0),
        ("(c) a < 0, b > 0", -1.0, 1.0),
        ("(d) a < 0, b < 0", -1.0, -1.0),
    ];
    let mut panels = Vec::new();
    let mut numbers = serde_json::Map::new();
    let mut solver = Enumeration::default();
    for (j, (title, a, b)) in cases.into_iter().enumerate() {
        let lcp = Lcp::from_rows(&[vec![a]], &[b])?;
        let solutions = solver.solve_all(lcp.view())?;
        let xs: Vec<f64> = solutions.iter().map(|s| s.z[0]).collect();
        let ys: Vec<f64> = solutions.iter().map(|s| s.w[0]).collect();
        let verdict = match solutions.len() {
            0 => "no solution".to_owned(),
            1 => "unique solution".to_owned(),
            n => format!("{n} solutions"),
        };
        let line_x = vec![-0.5, 2.0];
        let line_y: Vec<f64> = line_x.iter().map(|x| a * x + b).collect();
        let tag = ["a", "b", "c", "d"][j];
        panels.push(
            Panel::new(&format!("{title}: {verdict}"), "x [-]", "y [-]", &format!("x_{tag}"))
                .with(Series::line(&line_label(a, b), &format!("y_line_{tag}"), line_x, line_y, 0))
                .with(
                    Series::line(
                        "0 ≤ y ⊥ x ≥ 0",
                        &format!("corner_{tag}"),
                        vec![0.0, 0.0, 2.0],
                        vec![2.0, 0.0, 0.0],
                        7,
                    )
                    .with_mark(Mark::ThickLine),
                )
                .with(
                    Series::line(
                        "solutions (enumeration)",
                        &format!("y_solution_{tag}"),
                        xs.clone(),
                        ys.clone(),
                        1,
                    )
                    .with_mark(Mark::Rings),
                )
                .x_range(-0.5, 2.0)
                .y_range(-1.6, 2.0)
                .legend(LegendAt::UpperRight),
        );
        numbers.insert(
            tag.to_owned(),
            json!({"a": a, "b": b, "solutions": solutions.len(), "x": xs, "y": ys}),
        );
    }
    let fig = Figure::new("Fig I.2  The scalar LCP y = a x + b, 0 ≤ y ⊥ x ≥ 0", panels, 2);
    let files = fig.write(ctx.out, e.stem)?;
    Ok(Output { files: names(&files), key_numbers: json!(numbers), markdown: None })
}

/// "y = x + 1", "y = −x − 1", ... for the legend.
fn line_label(a: f64, b: f64) -> String {
    let slope = match a {
        1.0 => "x".to_owned(),
        -1.0 => "−x".to_owned(),
        a if a < 0.0 => format!("−{} x", -a),
        a => format!("{a} x"),
    };
    let sign = if b < 0.0 { "−" } else { "+" };
    format!("y = {slope} {sign} {}", b.abs())
}
