//! A driver for instruction-count profiles of Lemke's method:
//! `valgrind --tool=callgrind --toggle-collect='*solve_covering*' \
//!   target/release/examples/lemke_profile friction_9 1000`
//! solves the 16 problems of the named bench case (`friction_3`, `friction_9`, `spd_3`,
//! `spd_9`, `spd_30`, `spd_90`, the same sets as `benches/solvers.rs`) the given number of
//! times each, and prints the mean pivot count.
#![allow(missing_docs)]

#[path = "../tests/common/mod.rs"]
mod common;

use common::{BENCH_SETS, bench_set};
use moreau_lcp::{Lemke, Solution, Solver};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let case = args.get(1).map_or("friction_9", String::as_str);
    let repeat: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(100);
    let Some(set) = bench_set(case) else {
        eprintln!("unknown case {case}; known: {}", BENCH_SETS.join(", "));
        std::process::exit(2);
    };
    let mut lemke = Lemke::default();
    let mut out = Solution::new();
    let mut pivots = 0;
    let mut solved = 0;
    for _ in 0..repeat {
        for p in &set {
            lemke.solve_into(p.view(), None, &mut out).expect("valid problem");
            pivots += out.iterations;
            solved += usize::from(out.is_solved());
        }
    }
    let solves = repeat * set.len();
    println!(
        "{case}: {solves} solves, {solved} solved, mean pivots {:.2}",
        pivots as f64 / solves.max(1) as f64
    );
}
