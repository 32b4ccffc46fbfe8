//! The LCP solvers on the problems the report's mechanisms actually produce.
//!
//! The woodpecker and slider-crank report scenes are run once, and every step's LCP of eq. 7.41
//! that needed a solver is kept (`Stepper::last_lcp`); up to 50 instances per size, spread
//! evenly over the run, form the sample of that size. Each solver then solves the whole sample
//! per iteration into one reused `Solution`, so criterion's time per element is the time of
//! one solve. Pivot (or sweep) counts and residuals are printed before the timings.
//!
//! Projected Gauss-Seidel needs positive diagonal entries, which the friction LCP of eq. 7.41
//! lacks (its ξ_L block is zero); it is benched only on the normal-only problems of the same
//! scenes run with μ = 0, where the LCP is the Delassus system W_Nᵀ M⁻¹ W_N P_N + b.
//!
//! ```text
//! cargo bench --bench lcp_from_models -- --warm-up-time 1 --measurement-time 2
//! ```

use std::collections::BTreeMap;
use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use moreau::lcp::{Auto, Enumeration, Lcp, Lemke, Pgs, Solution, Solver, Status};
use moreau::models::{ModelKind, Scene};

/// Instances kept per LCP size.
const PER_SIZE: usize = 50;

/// The LCPs of one scene: how many steps had each size, and the sample per size.
struct Collected {
    name: &'static str,
    /// Steps per LCP size (0 = no contact closed), over the whole run.
    histogram: BTreeMap<usize, u64>,
    /// Steps per size whose LCP needed a solver (not settled by the zero impulse).
    solved: BTreeMap<usize, u64>,
    /// Up to `PER_SIZE` instances per size, spread evenly over the run.
    sample: BTreeMap<usize, Vec<Lcp>>,
    /// Whether every contact is frictionless (normal-only LCPs).
    frictionless: bool,
}

/// Runs a scene step by step, to its stop rule or end time, keeping every solver LCP.
fn collect(name: &'static str, scene: &Scene, frictionless: bool) -> Collected {
    let mut stepper = scene.stepper().expect("the scene builds");
    let names = scene.kind().coordinate_names();
    let stop = scene
        .stop_at
        .as_ref()
        .map(|s| (names.iter().position(|n| *n == s.coordinate).expect("a coordinate"), s.value));
    let steps = (scene.t_end / scene.dt).round() as u64;
    let mut histogram = BTreeMap::new();
    let mut all: BTreeMap<usize, Vec<Lcp>> = BTreeMap::new();
    for _ in 0..steps {
        let report = stepper.step().expect("the report scenes run");
        *histogram.entry(report.lcp_size).or_insert(0) += 1;
        if let Some(lcp) = stepper.last_lcp() {
            all.entry(lcp.n()).or_default().push(lcp.to_owned());
        }
        if stop.is_some_and(|(index, value)| stepper.q()[index] >= value) {
            break;
        }
    }
    let solved = all.iter().map(|(n, v)| (*n, v.len() as u64)).collect();
    let sample = all
        .into_iter()
        .map(|(n, v)| {
            let k = v.len().min(PER_SIZE);
            let picked = (0..k).map(|i| v[i * v.len() / k].clone()).collect();
            (n, picked)
        })
        .collect();
    Collected { name, histogram, solved, sample, frictionless }
}

/// The scenes: the report's woodpecker (1 s at Δt = 1e-4 s) and slider-crank (to θ1 = 4π at
/// Δt = 1e-5 s), each also with μ = 0 for normal-only LCPs.
fn scenes() -> Vec<Collected> {
    let mut out = Vec::new();
    for kind in [ModelKind::Woodpecker, ModelKind::SliderCrank] {
        let scene = Scene::report(kind);
        let name = if kind == ModelKind::Woodpecker { "woodpecker" } else { "slider-crank" };
        out.push(collect(name, &scene, false));
        let mut frictionless = scene.clone();
        frictionless.set("mu", "0").expect("μ = 0 is valid");
        let name =
            if kind == ModelKind::Woodpecker { "woodpecker-mu0" } else { "slider-crank-mu0" };
        out.push(collect(name, &frictionless, true));
    }
    out
}

/// A named solver (boxed: their workspaces differ much in size).
enum AnySolver {
    Lemke(Box<Lemke>),
    Auto(Box<Auto>),
    Enumeration(Box<Enumeration>),
    Pgs(Box<Pgs>),
}

impl AnySolver {
    fn all(frictionless: bool) -> Vec<(&'static str, AnySolver)> {
        let mut v = vec![
            ("lemke", AnySolver::Lemke(Box::default())),
            ("auto", AnySolver::Auto(Box::default())),
            ("enumeration", AnySolver::Enumeration(Box::default())),
        ];
        if frictionless {
            v.push(("pgs", AnySolver::Pgs(Box::default())));
        }
        v
    }

    fn solve(&mut self, lcp: &Lcp, out: &mut Solution) {
        let result = match self {
            AnySolver::Lemke(s) => s.solve_into(lcp.view(), None, out),
            AnySolver::Auto(s) => s.solve_into(lcp.view(), None, out),
            AnySolver::Enumeration(s) => s.solve_into(lcp.view(), None, out),
            AnySolver::Pgs(s) => s.solve_into(lcp.view(), None, out),
        };
        result.expect("valid input");
    }
}

/// Prints the histogram of LCP sizes per scene.
fn print_histograms(scenes: &[Collected]) {
    println!("\nLCP sizes per step (rows: 0 = no contact closed; solver = steps needing a solver)");
    for c in scenes {
        let total: u64 = c.histogram.values().sum();
        let cells: Vec<String> = c
            .histogram
            .iter()
            .map(|(n, k)| format!("{n}: {k} (solver {})", c.solved.get(n).copied().unwrap_or(0)))
            .collect();
        println!("  {:<17} {total} steps | {}", c.name, cells.join(" | "));
    }
}

/// Prints, per scene, size and solver: solved fraction, mean and largest pivot or sweep count,
/// and the largest relative residual.
fn print_statistics(scenes: &[Collected]) {
    println!("\nsolver statistics on the samples (mean/max iterations, largest relative residual)");
    for c in scenes {
        for (n, sample) in &c.sample {
            for (name, mut solver) in AnySolver::all(c.frictionless) {
                let mut out = Solution::new();
                let (mut solved, mut sum, mut max_it, mut res) = (0, 0usize, 0usize, 0.0f64);
                for lcp in sample {
                    solver.solve(lcp, &mut out);
                    solved += usize::from(out.status == Status::Solved);
                    sum += out.iterations;
                    max_it = max_it.max(out.iterations);
                    res = res.max(out.residual.relative);
                }
                println!(
                    "  {:<17} n = {n:>2} {name:<12} solved {solved}/{} iterations {:.1}/{max_it} residual {res:.1e}",
                    c.name,
                    sample.len(),
                    sum as f64 / sample.len() as f64,
                );
            }
        }
    }
}

fn lcp_from_models(c: &mut Criterion) {
    let scenes = scenes();
    print_histograms(&scenes);
    print_statistics(&scenes);
    println!();
    for scene in &scenes {
        for (n, sample) in &scene.sample {
            let mut group = c.benchmark_group(format!("lcp/{}/n={n}", scene.name));
            group.throughput(Throughput::Elements(sample.len() as u64));
            group.sample_size(20);
            for (name, mut solver) in AnySolver::all(scene.frictionless) {
                let mut out = Solution::new();
                group.bench_function(name, |b| {
                    b.iter(|| {
                        for lcp in sample {
                            solver.solve(black_box(lcp), &mut out);
                        }
                        black_box(out.z.first().copied())
                    })
                });
            }
            group.finish();
        }
    }
}

criterion_group!(benches, lcp_from_models);
criterion_main!(benches);
