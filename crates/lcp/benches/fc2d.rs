//! Time per solve of the FC2D solvers on Siconos' collection (`tests/data/siconos/fc2d`).
//!
//! Per file and tolerance: Gauss-Seidel (`nsgs`, ω = 1, as Siconos' NSGS), `auto`, Newton
//! from r = 0 where it converges, and the LCP route on small files. The problem is read
//! and the solver made outside the timed part; each solve starts from r = 0 and reuses the
//! solver's workspace and the solution. The iterations (sweeps, Newton iterations or
//! pivots), the status and the residual of each case are printed before it runs; a case
//! that does not reach its tolerance is not timed.
//!
//! `cargo bench -p moreau-lcp --bench fc2d -- --warm-up-time 1 --measurement-time 3`
//! runs in about three minutes.
#![allow(missing_docs)]

use std::fs::File;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use moreau_lcp::fc2d::{
    Fc2d, Fc2dAuto, Fc2dAutoOptions, Fc2dSolution, Fc2dSolver, Gfc2d, LcpRoute, LcpRouteOptions,
    Newton, NewtonOptions, Nsgs, NsgsOptions,
};

fn read(name: &str) -> Fc2d {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/siconos/fc2d").join(name);
    let file = File::open(&path).expect("a file of the collection");
    if name.starts_with("gfc2d") {
        Gfc2d::read_siconos(file).expect("a GFC2D file").reduce().expect("reducible").problem
    } else {
        Fc2d::read_siconos(file).expect("an FC2D file")
    }
}

fn make(solver: &str, tolerance: f64) -> Box<dyn Fc2dSolver> {
    match solver {
        "nsgs" => Box::new(
            Nsgs::new(NsgsOptions::default().with_tolerance(tolerance).with_max_sweeps(100_000))
                .expect("valid options"),
        ),
        "auto" => Box::new(
            Fc2dAuto::new(Fc2dAutoOptions::default().with_tolerance(tolerance))
                .expect("valid options"),
        ),
        "newton" => Box::new(
            Newton::new(NewtonOptions::default().with_tolerance(tolerance)).expect("valid options"),
        ),
        _ => Box::new(
            LcpRoute::new(
                LcpRouteOptions::default().with_tolerance(tolerance).with_max_contacts(300),
            )
            .expect("valid options"),
        ),
    }
}

/// (file, solvers at 1e-4, solvers at 1e-8).
const CASES: &[(&str, &[&str], &[&str])] = &[
    ("FrictionContactProblem00071.dat", &["nsgs", "auto"], &["nsgs", "auto", "newton", "lcp"]),
    ("gfc2d_granularflowonwall_00230_00206.dat", &["nsgs", "auto"], &["nsgs", "auto", "newton"]),
    ("FrictionContactProblem00727.dat", &["nsgs", "auto"], &["nsgs", "auto", "newton"]),
    ("FrictionContactProblem00237.dat", &["nsgs", "auto"], &["nsgs", "auto", "newton"]),
    ("fc2d_granularflowonwall_02020_00213.dat", &["nsgs", "auto"], &["auto"]),
    ("fc2d_granularflowonwall_07002_00801.dat", &["nsgs", "auto"], &["auto"]),
];

fn benches(c: &mut Criterion) {
    for &(file, loose, tight) in CASES {
        let problem = read(file);
        let short = file.trim_end_matches(".dat");
        for (tolerance, solvers) in [(1e-4, loose), (1e-8, tight)] {
            for &name in solvers {
                let mut solver = make(name, tolerance);
                let mut out = Fc2dSolution::new();
                solver.solve_into(problem.view(), None, &mut out).expect("a valid problem");
                let id = format!("fc2d/{short}/{tolerance:e}/{name}");
                eprintln!(
                    "{id}: {} contacts, {} by {}, {} iterations, residual {:.2e}",
                    problem.n_contacts(),
                    out.status,
                    out.method,
                    out.iterations,
                    out.residual.natural
                );
                if !out.is_solved() {
                    continue;
                }
                c.bench_function(&id, |b| {
                    b.iter(|| {
                        solver
                            .solve_into(black_box(problem.view()), None, &mut out)
                            .expect("a valid problem");
                        black_box(out.r[0])
                    })
                });
            }
        }
    }
}

criterion_group! {
    name = fc2d;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3));
    targets = benches
}
criterion_main!(fc2d);
