//! The `moreau` command: run any scene to CSV (one of the reference report's models, or a
//! mechanism declared in a scene file), run parameter sweeps in parallel (sharded over machines
//! if need be) and merge their parts, with guards that keep a run from passing off a
//! meaningless result or losing data.
//!
//! **For**: users who simulate the models and scene files of `moreau-models` from the command
//! line or a job script (`cargo install --path crates/cli`, then `moreau simulate|sweep|merge`,
//! with a model name or `--scene FILE`, and `moreau solve` for a step problem), and programs
//! that want the same runs, key numbers and sweep files as a library ([`simulate`], [`sweep`],
//! [`parts`], [`keys`], [`analysis`], [`solve`]).
//! **Not for**: figures and the reproduction report (the repository's `cargo xtask reproduce`
//! and `cargo xtask frames`), or hand-derived mechanisms that no scene file can hold (run them
//! with `moreau-stepper` directly).
//!
//! What a run guarantees ([`guard`]): Δt ≤ t_end, t_end a whole number of steps and the last
//! row at t_end, at most [`guard::DEFAULT_MAX_STEPS`] steps unless asked for, a stop with a
//! typed [`CliError::Diverged`] naming the cause and the step when Δt exceeds the stability
//! limit, the energy of a mechanism without drives grows, the state explodes, or a body is
//! carried through what it should strike (a contact sinks deeper than its size); warnings
//! about penetrating or touching initial gaps. A declared mechanism written in other units
//! (micrometres and milligrams, kilometres and kilotonnes) is guarded in its own
//! ([`guard::Scales`]). A declared mechanism's contacts can be written
//! too, located on their bodies ([`contacts`]: the force network of a pile at each recorded
//! step). Records stream to disk in batches; sweep rows are written as members finish, each
//! sweep part names its sweep, and [`parts::merge`] refuses mixed, incomplete or damaged sets.
//! Numbers go to CSV in the shortest text that reads back exactly, with an exponent when that
//! is shorter ([`number`]). Outputs ([`output`]) are written through a symbolic link to its
//! file, never over an input of the run, another output of it or a file that is not a regular
//! file, whole or not at all, and under a lock file that keeps a second run off them.
//! A run that stops on a step problem its solver leaves unsolved writes that problem in
//! Siconos' format ([`failed`]), and [`solve`] solves such a file (or any LCP or FC2D file of
//! Siconos' collection) with any of `moreau-lcp`'s solvers.
//!
//! # Example
//! ```
//! use moreau_cli::grid::{Axis, Grid};
//! use moreau_cli::simulate::{SimulateOptions, run};
//! # fn main() -> anyhow::Result<()> {
//! let grid = Grid::new(vec![Axis::parse("eps_n=0.1,0.4")?, Axis::parse("dt=1e-3,1e-4")?])?;
//! assert_eq!(grid.len(), 4);
//! assert_eq!(grid.member(1), [("eps_n".into(), "0.1".into()), ("dt".into(), "1e-4".into())]);
//!
//! // A ball dropped from 1 m for 0.5 s: the last row lies at t_end.
//! let options = SimulateOptions { model: Some("ball".into()), tf: Some(0.5), ..Default::default() };
//! let result = run(&options)?;
//! assert_eq!(result.record().t.last(), Some(&0.5));
//! // A time step longer than the run is refused.
//! let bad = SimulateOptions { dt: Some(1.0), ..options };
//! assert!(run(&bad).is_err());
//! # Ok(())
//! # }
//! ```
#![deny(missing_docs)]

pub mod analysis;
pub mod cli;
pub mod contacts;
mod error;
pub mod failed;
pub mod grid;
pub mod guard;
pub mod keys;
pub mod number;
pub mod output;
pub mod parts;
pub mod runs;
pub mod simulate;
pub mod solve;
pub mod sweep;
pub mod table;

pub use error::{CliError, Divergence};
