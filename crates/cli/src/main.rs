//! `moreau`: run a model to CSV, run parameter sweeps and merge their parts.

use std::process::ExitCode;

use clap::Parser;
use moreau_cli::cli::Command;

#[derive(Parser)]
#[command(
    name = "moreau",
    about = "Non-smooth rigid multibody simulations: runs and sweeps",
    version
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

fn main() -> ExitCode {
    match Cli::parse().command.run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
