//! Moreau's task runner: reproduces every figure and table of the reference report from the
//! project's own simulations, runs one model to CSV, and runs parameter sweeps.
//!
//! **For**: `cargo xtask reproduce`, `simulate`, `sweep`, `merge` and `tradeoff` (see
//! `main.rs`), the analysis of recorded runs ([`analysis`]) and the speed/accuracy study
//! ([`tradeoff`]). **Not for**: use as a library by other crates;
//! the package is not published.
//!
//! Principal pieces: [`plot::Figure`] (multi-panel SVG/PNG/CSV figures), [`frames::Strip`]
//! (frame strips and animated SVGs), [`table::Table`] (CSV and Markdown tables),
//! [`analysis`] (impacts, rest time, limit cycles, contact events), [`grid`] (sweep grids,
//! shards and merging).
//!
//! # Example
//! ```
//! use xtask::grid::{Axis, product};
//! # fn main() -> anyhow::Result<()> {
//! let members = product(&[Axis::parse("eps_n=0.1,0.4")?, Axis::parse("dt=1e-3,1e-4")?]);
//! assert_eq!(members.len(), 4);
//! # Ok(())
//! # }
//! ```
//!
//! # References
//! - Flores, P. (2010). Application of the non-smooth dynamics approach to model and analyze
//!   contact-impact events in rigid multibody systems using the LCP formulation.
//!   Universidade do Minho.
#![deny(missing_docs)]

pub mod analysis;
pub mod frames;
pub mod grid;
pub mod keys;
pub mod plot;
pub mod report;
pub mod reproduce;
pub mod runs;
pub mod simulate;
pub mod sweep;
pub mod table;
pub mod tradeoff;
