//! The project's own speed/accuracy study in the report: the figures and tables of
//! [`crate::tradeoff`] (`cargo xtask tradeoff`), in quick form under `--quick`.

use anyhow::Result;

use super::{Ctx, Entry, Output};
use crate::tradeoff;

pub(super) fn entries() -> Vec<Entry> {
    vec![Entry {
        id: "Speed and accuracy",
        stem: tradeoff::WALL_STEM,
        caption: "Speed against accuracy for each model, LCP solver (Lemke, Auto, PGS at \
                  tolerances 1e-4, 1e-8, 1e-12) and step size Δt (1e-2 s down to 1e-6 s; 1e-2 s to \
                  3e-4 s under --quick). First figure: headline error against wall time, one series \
                  per solver, the Auto runs labelled by Δt. Second figure: the same errors against \
                  Δt with the least-squares order p fitted over the finest Auto runs, and the \
                  reference's own error (run at h_ref against h_ref/2). Errors: ball against the \
                  closed form (ε_N = 0.7), the other models against a reference run at h_ref = 1e-7 s \
                  (3e-5 s under --quick). Runs that diverge are listed in the table, not plotted. \
                  Wall times are measured (best of up to five repeats for runs under 20 ms) while \
                  other runs share the cores; they vary between machines and runs. Everything else \
                  is deterministic.",
        runs: |_| Vec::new(),
        draw: fig,
    }]
}

fn fig(ctx: &Ctx<'_>, _e: &Entry) -> Result<Output> {
    let results = tradeoff::run_studies(&tradeoff::studies(ctx.quick));
    let command = if ctx.quick { "cargo xtask reproduce --quick" } else { "cargo xtask reproduce" };
    let written = tradeoff::write(&results, ctx.out, command)?;
    tradeoff::check_runs(&results)?;
    Ok(Output {
        files: written.files,
        key_numbers: written.key_numbers,
        markdown: Some(written.markdown),
    })
}
