//! Writes the problems of the bench sets in Siconos numerics' LCP file format, for
//! cross-checks with other solvers: `cargo run --release -p moreau-lcp --example
//! write_bench_sets -- DIR [SET ...]` writes `DIR/SET_K.dat` for K = 0 to 15 and each named
//! set (all six by default: `friction_3`, `friction_9`, `spd_3`, `spd_9`, `spd_30`,
//! `spd_90`, the same sets as `benches/solvers.rs`). `siconos/compare.c` reads them.
#![allow(missing_docs)]

#[path = "../tests/common/mod.rs"]
mod common;

use std::fs::File;
use std::io::BufWriter;
use std::path::PathBuf;

use common::{BENCH_SETS, bench_set};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let dir = PathBuf::from(args.next().ok_or("usage: write_bench_sets DIR [SET ...]")?);
    let mut names: Vec<String> = args.collect();
    if names.is_empty() {
        names = BENCH_SETS.map(String::from).to_vec();
    }
    std::fs::create_dir_all(&dir)?;
    for name in &names {
        let set = bench_set(name)
            .ok_or_else(|| format!("unknown set {name}; known: {}", BENCH_SETS.join(", ")))?;
        for (k, lcp) in set.iter().enumerate() {
            let path = dir.join(format!("{name}_{k}.dat"));
            lcp.write_siconos(BufWriter::new(File::create(&path)?))?;
        }
        println!("{name}: {} problems in {}", set.len(), dir.display());
    }
    Ok(())
}
