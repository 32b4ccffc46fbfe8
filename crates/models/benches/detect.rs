//! The cost of one step's contact detection on the disk column (`scenes/scale/disk-column.toml`)
//! of 10³ and 10⁴ grains: the broad phase over every shape, the narrow phase on its pairs and
//! the contacts' force directions, as `BodyStructure::detect` gives them to the stepper, on
//! rayon pools of one and two threads.
//!
//! The grains are at their places on the lattice, each 0.5 to 9 mm from its neighbours, and the
//! margin is 6 mm, so that each grain has about as many contacts as in a settled column.
//!
//! Run with `cargo bench -p moreau-models --bench detect -- --warm-up-time 1
//! --measurement-time 3`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use moreau_models::{ModelParams, Scene};
use moreau_stepper::Mechanism;

fn detect(c: &mut Criterion) {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/scale/disk-column.toml");
    let mut group = c.benchmark_group("detect");
    group.sample_size(20);
    for n in [1000, 10_000] {
        let mut scene = Scene::from_path(&path).expect("the scene loads");
        scene.set("fill.grain.count", &n.to_string()).expect("the count is a field");
        let ModelParams::Declared(spec) = &scene.params else { panic!("a declared scene") };
        let column = spec.build().expect("the column builds");
        let structure = column.body_structure().expect("detected contacts");
        let (q0, _) = column.initial_state();
        let mut out = Vec::new();
        structure.detect(&q0, 0.0, 0.006, &mut out);
        let contacts = out.len();
        // The narrow phase runs in chunks in parallel on the pool of the calling thread.
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let name = format!("disk-column-{n} ({contacts} contacts), {threads} thread(s)");
            group.bench_function(name, |bench| {
                bench.iter_custom(|iters| {
                    pool.install(|| {
                        let start = std::time::Instant::now();
                        for _ in 0..iters {
                            out.clear();
                            structure.detect(black_box(&q0), 0.0, 0.006, &mut out);
                            black_box(out.len());
                        }
                        start.elapsed()
                    })
                })
            });
        }
    }
    group.finish();
}

criterion_group!(benches, detect);
criterion_main!(benches);
