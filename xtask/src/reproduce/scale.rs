//! The many-body scaling study in the report: the quick runs of [`crate::scale`]
//! (`cargo xtask scale --quick`), whose entries are also the `scale` key of `summary.json`.

use anyhow::{Result, bail};

use super::{Ctx, Entry, Output};
use crate::scale;

pub(super) fn entries() -> Vec<Entry> {
    vec![Entry {
        id: "Scaling",
        stem: scale::STEM,
        caption: "How the many-body step scales (the quick runs of cargo xtask scale, the same \
                  under --quick and in a full reproduction): the scale scenes' disk column, box \
                  pyramid and granular flow, contacts detected at each step and solved island by \
                  island. Left: wall time per step against the contacts that carry an impulse \
                  (log-log, with the least-squares slope of the disk column). Middle: solver \
                  iterations per step against the height of the resting column. Right: the \
                  resting column's support reactions against its weight. Below: the force networks \
                  of the resting column and pyramid, each contact of the last step a line from \
                  centre of mass to centre of mass (or to the floor), its width growing with \
                  the normal impulse. Wall times are measured while the report's other figures \
                  are drawn on the other cores; cargo xtask scale measures them alone.",
        runs: |_| Vec::new(),
        draw: fig,
    }]
}

fn fig(ctx: &Ctx<'_>, _e: &Entry) -> Result<Output> {
    let specs = scale::specs(true);
    let results = scale::run_all(&specs, None);
    let written = scale::write(&results, &specs, ctx.out)?;
    let failed: Vec<&String> = results.iter().filter_map(|r| r.as_ref().err()).collect();
    if !failed.is_empty() {
        bail!("{} of {} scaling runs failed: {}", failed.len(), specs.len(), failed[0]);
    }
    Ok(Output { files: written.files, key_numbers: written.json, markdown: Some(written.markdown) })
}
