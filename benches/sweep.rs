//! A parameter sweep of 64 woodpecker runs (1 s each at Δt = 1e-4 s, each recorded as
//! `moreau sweep` records it), on one thread and on two: the speed-up is the ratio of
//! the two times.
//!
//! `cargo bench --bench sweep`

use criterion::{Criterion, criterion_group, criterion_main};
use moreau::models::{ModelKind, Scene};
use rayon::prelude::*;

/// The 64 members: μ of all three contacts from 0.15 to 0.45 and ε_N of the beak from 0.3
/// to 0.7 (8 × 8).
fn members() -> Vec<Scene> {
    let mut scenes = Vec::with_capacity(64);
    for i in 0..8 {
        for j in 0..8 {
            let mut s = Scene::report(ModelKind::Woodpecker);
            let mu = 0.15 + 0.3 * i as f64 / 7.0;
            for key in ["beak.mu", "lower.mu", "upper.mu"] {
                s.set(key, &mu.to_string()).expect("woodpecker key");
            }
            s.set("beak.eps_n", &(0.3 + 0.4 * j as f64 / 7.0).to_string()).expect("woodpecker key");
            scenes.push(s);
        }
    }
    scenes
}

fn sweep(c: &mut Criterion) {
    faer::set_global_parallelism(faer::Par::Seq);
    let scenes = members();
    let mut group = c.benchmark_group("sweep/woodpecker, 64 runs");
    group.sample_size(10);
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        group.bench_function(format!("{threads} thread(s)"), |b| {
            b.iter(|| {
                pool.install(|| {
                    scenes
                        .par_iter()
                        .map(|s| s.run().expect("sweep member runs").steps)
                        .sum::<u64>()
                })
            })
        });
    }
    group.finish();
}

criterion_group!(benches, sweep);
criterion_main!(benches);
