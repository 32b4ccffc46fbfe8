//! `cargo xtask`: reproduce the report, simulate one model, run and merge parameter sweeps.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use xtask::grid::{Axis, Shard};
use xtask::{reproduce, simulate, sweep, tradeoff};

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
        /// Shorter horizons and fewer runs (for CI).
        #[arg(long)]
        quick: bool,
        /// Worker threads (default: one per core).
        #[arg(long)]
        jobs: Option<usize>,
    },
    /// Run one model and write its record as CSV.
    Simulate {
        /// Model: ball, woodpecker, slider-crank, slider-crank-ideal, cam, painleve.
        model: String,
        /// Scene file (TOML) to start from instead of the report's scene.
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Override a scene key: --set key=value (repeatable).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        sets: Vec<String>,
        /// Time step Δt (s).
        #[arg(long)]
        dt: Option<f64>,
        /// End time (s).
        #[arg(long)]
        tf: Option<f64>,
        /// LCP solver: auto, lemke, pgs or enum.
        #[arg(long)]
        solver: Option<String>,
        /// Output CSV file.
        #[arg(long)]
        out: PathBuf,
    },
    /// Run the Cartesian product of parameter values in parallel; one CSV row per member.
    Sweep {
        /// Model: ball, woodpecker, slider-crank, slider-crank-ideal, cam, painleve.
        model: String,
        /// Swept key and its values: --set key=v1,v2,... (repeatable).
        #[arg(long = "set", value_name = "KEY=V1,V2,...")]
        sets: Vec<String>,
        /// Scene file (TOML) to start from instead of the report's scene.
        #[arg(long)]
        scene: Option<PathBuf>,
        /// Run only part K of N (members i with i mod N = K − 1).
        #[arg(long, value_name = "K/N")]
        shard: Option<String>,
        /// Output CSV file.
        #[arg(long)]
        out: PathBuf,
    },
    /// Error against cost for each model, step size and LCP solver: figures, table, orders.
    Tradeoff {
        /// Output folder.
        #[arg(long, default_value = "target/tradeoff")]
        out: PathBuf,
        /// Four step sizes from 1e-2 to 3e-4 s and a coarser reference (a few seconds).
        #[arg(long)]
        quick: bool,
        /// Worker threads (default: one per core).
        #[arg(long)]
        jobs: Option<usize>,
    },
    /// Join the CSV parts of a sharded sweep, sorted by member.
    Merge {
        /// Output CSV file.
        out: PathBuf,
        /// The parts.
        #[arg(required = true)]
        parts: Vec<PathBuf>,
    },
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
                "wrote {} files to {} in {:.1} s (simulations {:.1} s of CPU)",
                summary.files,
                out.display(),
                summary.total_seconds,
                summary.simulation_seconds
            );
        }
        Command::Simulate { model, scene, sets, dt, tf, solver, out } => {
            let options = simulate::SimulateOptions { model, scene, sets, dt, tf, solver };
            let run = simulate::run(&options)?;
            simulate::write_record(&run, &out)?;
            println!(
                "{}: {} steps, {} LCP solves, {:.3} s; wrote {} rows to {}",
                run.spec.kind,
                run.sim.steps,
                run.sim.lcp_solves,
                run.sim.wall_seconds,
                run.record().len(),
                out.display()
            );
        }
        Command::Sweep { model, sets, scene, shard, out } => {
            let axes = sets.iter().map(|s| Axis::parse(s)).collect::<Result<Vec<_>>>()?;
            let shard = shard.as_deref().map(Shard::parse).transpose()?;
            let rows = sweep::run(&sweep::SweepOptions { model, scene, axes, shard }, &out)
                .context("sweep")?;
            println!("wrote {rows} members to {}", out.display());
        }
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
        Command::Merge { out, parts } => {
            let rows = xtask::grid::merge(&out, &parts)?;
            println!("merged {rows} members into {}", out.display());
        }
    }
    Ok(())
}
