//! `cargo xtask`: reproduce the report and run the speed/accuracy study; `simulate`, `sweep`,
//! `merge` and `solve` run the `moreau` command's code; `frames` draws any scene.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use moreau_cli::cli::{self, MergeArgs, SimulateArgs, SolveArgs, SweepArgs};
use xtask::scene_frames::FramesArgs;
use xtask::{reproduce, scale, tradeoff};

#[derive(Parser)]
#[command(name = "xtask", about = "Moreau's task runner", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Regenerate every figure and table of the report, summary.json and report.html.
    Reproduce {
        /// Output folder.
        #[arg(long, default_value = "target/reproduce")]
        out: PathBuf,
        /// A smaller speed/accuracy study (step sizes down to 3e-4 s, references at 3e-5 s); the
        /// report's figures are the same as in a full run (for CI).
        #[arg(long)]
        quick: bool,
        /// Worker threads, at least 1 (default: one per core).
        #[arg(long, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..))]
        jobs: Option<usize>,
    },
    /// Run one model or scene file and write its record as CSV (the `moreau simulate` command).
    Simulate(SimulateArgs),
    /// Run a parameter sweep; one CSV row per member (the `moreau sweep` command).
    Sweep(SweepArgs),
    /// Error against cost for each model, step size and LCP solver: figures, table, orders.
    Tradeoff {
        /// Output folder.
        #[arg(long, default_value = "target/tradeoff")]
        out: PathBuf,
        /// Four step sizes from 1e-2 to 3e-4 s and a coarser reference (a few seconds).
        #[arg(long)]
        quick: bool,
        /// Worker threads, at least 1 (default: one per core).
        #[arg(long, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..))]
        jobs: Option<usize>,
    },
    /// How the many-body step scales: time per step, iterations and force balance on the scale
    /// scenes, from 10² to 10⁴ bodies.
    Scale {
        /// Output folder.
        #[arg(long, default_value = "target/scale")]
        out: PathBuf,
        /// Only the small sizes.
        #[arg(long)]
        quick: bool,
        /// Also write each run's largest island problem of its last step into this folder, in
        /// Siconos' FC2D format (for `crates/lcp/siconos/compare_fc2d.sh`).
        #[arg(long)]
        problems: Option<PathBuf>,
        /// Only the runs with this word in their label (scene, size overrides, thread
        /// counts), e.g. `pyramid` or `fill.grain.count=1000` (not the 10,000-disk run).
        #[arg(long)]
        only: Option<String>,
    },
    /// Join the CSV parts of a sharded sweep (the `moreau merge` command).
    Merge(MergeArgs),
    /// Solve one LCP or planar frictional-contact problem from a file in Siconos' format (the
    /// `moreau solve` command).
    Solve(SolveArgs),
    /// Pictures of any scene: a strip of frames (SVG, PNG) and an animated SVG of the run.
    Frames(FramesArgs),
}

fn main() -> ExitCode {
    match run(Cli::parse().command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(command: Command) -> Result<()> {
    match command {
        Command::Reproduce { out, quick, jobs } => {
            let summary = reproduce::run(&reproduce::Options { out: out.clone(), quick, jobs })?;
            println!(
                "wrote {} files to {} in {:.1} s (the report's simulations {:.3} s of CPU, \
                 besides the speed/accuracy and scaling studies)",
                summary.files,
                out.display(),
                summary.total_seconds,
                summary.simulation_seconds
            );
        }
        Command::Simulate(args) => cli::Command::Simulate(args).run()?,
        Command::Sweep(args) => cli::Command::Sweep(args).run()?,
        Command::Tradeoff { out, quick, jobs } => {
            let summary = tradeoff::run(&tradeoff::Options { out: out.clone(), quick, jobs })?;
            println!(
                "wrote {} files to {} in {:.1} s (simulations {:.1} s of CPU)",
                summary.files.len(),
                out.display(),
                summary.total_seconds,
                summary.simulation_seconds
            );
        }
        Command::Scale { out, quick, problems, only } => {
            // The outputs are checked before the runs, which take minutes to hours.
            reproduce::writable(&out).context("--out")?;
            if let Some(dir) = &problems {
                reproduce::writable(dir).context("--problems")?;
            }
            let mut specs = scale::specs(quick);
            if let Some(only) = &only {
                specs.retain(|s| s.label().split_whitespace().any(|w| w == only));
                if specs.is_empty() {
                    anyhow::bail!("no run of the scaling study matches {only:?}");
                }
            }
            let results = scale::run_all(&specs, problems.as_deref());
            let written = scale::write(&results, &specs, &out)?;
            println!("wrote {} files to {}", written.files.len(), out.display());
            println!("{}", written.markdown);
            let failed = results.iter().filter(|r| r.is_err()).count();
            if failed > 0 {
                anyhow::bail!(
                    "{failed} of {} runs failed (listed above and in scale.json)",
                    specs.len()
                );
            }
        }
        Command::Merge(args) => cli::Command::Merge(args).run()?,
        Command::Solve(args) => cli::Command::Solve(args).run()?,
        Command::Frames(args) => args.run()?,
    }
    Ok(())
}
