//! Time per solve of each solver on contact-like problems of size 3, 9, 30 and 90.
//!
//! - `friction_3`, `friction_9`: the step LCP with friction (docs/theory.md section 5) of
//!   1 and 3 contacts, from random W_N, W_T, SPD mass matrix and μ;
//! - `spd_N`: random symmetric positive definite M with planted solutions (the
//!   frictionless step LCP `W_N' M^-1 W_N` is of this kind).
//!
//! Each case cycles over 16 problems; the solver and the solution are reused outside the
//! timed part, so the times are those of allocation-free solves. The mean pivot or
//! iteration count of each case is printed before it runs.
//!
//! `lemke_pivots/friction_9/k` stops Lemke's method after at most k pivots (status
//! `IterationLimit` for the problems that need more): the differences between k = 1, 4
//! and 7 are the cost of a pivot, and k = 1 that of the set-up, one pivot and the
//! residual of the candidate.
#![allow(missing_docs)]

#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;

use common::{BENCH_SETS, bench_set};
use criterion::{Criterion, criterion_group, criterion_main};
use moreau_lcp::{Auto, Enumeration, Lcp, Lemke, LemkeOptions, Pgs, Solution, Solver};

fn run(c: &mut Criterion, group: &str, name: &str, solver: &mut dyn Solver, problems: &[Lcp]) {
    let mut out = Solution::new();
    let mut iterations = 0;
    for p in problems {
        solver.solve_into(p.view(), None, &mut out).expect("valid problem");
        assert!(out.is_solved(), "{group}/{name}: {:?}", out.status);
        iterations += out.iterations;
    }
    eprintln!("{group}/{name}: mean iterations {:.1}", iterations as f64 / problems.len() as f64);
    time_solves(c, &format!("{group}/{name}"), solver, problems);
}

/// Times one solve, cycling over the problems.
fn time_solves(c: &mut Criterion, id: &str, solver: &mut dyn Solver, problems: &[Lcp]) {
    let mut out = Solution::new();
    let mut k = 0;
    c.bench_function(id, |b| {
        b.iter(|| {
            k = (k + 1) % problems.len();
            solver
                .solve_into(black_box(problems[k].view()), None, &mut out)
                .expect("valid problem");
            black_box(out.z[0])
        })
    });
}

fn benches(c: &mut Criterion) {
    let set = |name| bench_set(name).expect("a bench set");
    let [friction_3, friction_9, spd_3, spd_9, spd_30, spd_90] = BENCH_SETS.map(set);

    let mut lemke = Lemke::default();
    for (name, set) in [
        ("friction_3", &friction_3),
        ("friction_9", &friction_9),
        ("spd_3", &spd_3),
        ("spd_9", &spd_9),
        ("spd_30", &spd_30),
        ("spd_90", &spd_90),
    ] {
        run(c, "lemke", name, &mut lemke, set);
    }
    for k in [1, 4, 7] {
        let options = LemkeOptions::default().with_max_pivots(k);
        let mut capped = Lemke::new(options).expect("valid options");
        time_solves(c, &format!("lemke_pivots/friction_9/{k}"), &mut capped, &friction_9);
    }
    let mut pgs = Pgs::default();
    for (name, set) in
        [("spd_3", &spd_3), ("spd_9", &spd_9), ("spd_30", &spd_30), ("spd_90", &spd_90)]
    {
        run(c, "pgs", name, &mut pgs, set);
    }
    let mut auto = Auto::default();
    for (name, set) in [
        ("friction_3", &friction_3),
        ("friction_9", &friction_9),
        ("spd_30", &spd_30),
        ("spd_90", &spd_90),
    ] {
        run(c, "auto", name, &mut auto, set);
    }
    let mut enumeration = Enumeration::default();
    for (name, set) in [("friction_3", &friction_3), ("friction_9", &friction_9), ("spd_9", &spd_9)]
    {
        run(c, "enumeration", name, &mut enumeration, set);
    }
}

criterion_group!(solvers, benches);
criterion_main!(solvers);
