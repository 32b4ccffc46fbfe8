//! Moreau's task runner: reproduces every figure and table of the reference report from the
//! project's own simulations, and runs the speed/accuracy study.
//!
//! **For**: `cargo xtask reproduce` and `tradeoff` (see `main.rs`), `cargo xtask
//! simulate|sweep|merge|solve`, which run the `moreau` command's code from the `moreau-cli` crate,
//! and `cargo xtask frames`, which draws any scene ([`scene_frames`]).
//! **Not for**: use as a library by other crates; the package is not published. Users who
//! simulate install the `moreau` command instead (`cargo install --path crates/cli`).
//!
//! Principal pieces: [`plot::Figure`] (multi-panel SVG/PNG/CSV figures), [`frames::Strip`]
//! (frame strips and animated SVGs), [`report`] (the HTML and Markdown report), [`reproduce`]
//! and [`tradeoff`]. The runs, key numbers, analysis, grids and tables are those of the
//! `moreau-cli` crate, re-exported here under their module names.
//!
//! # Example
//! ```
//! use xtask::table::Table;
//!
//! let mut t = Table::default();
//! t.push_column("dt", vec![1e-3, 1e-4]);
//! assert_eq!(t.to_markdown(|_, x| format!("{x:e}")), "| dt |\n|---:|\n| 1e-3 |\n| 1e-4 |\n");
//! ```
//!
//! # References
//! - Flores, P. (2010). Application of the non-smooth dynamics approach to model and analyze
//!   contact-impact events in rigid multibody systems using the LCP formulation.
//!   Universidade do Minho.
#![deny(missing_docs)]

pub use moreau_cli::{analysis, contacts, grid, keys, runs, simulate, sweep, table};

pub mod frames;
pub mod network;
pub mod plot;
pub mod report;
pub mod reproduce;
pub mod scale;
pub mod scene_frames;
pub mod tradeoff;
