//! The cost of contact detection: `collide` for a disk on a half-plane, a box on a half-plane,
//! two boxes and a disk on a polyline of 100 segments, and the broad phase over 10⁴ disks.
//!
//! Run with `cargo bench -p moreau-kinematics --bench collide -- --warm-up-time 1
//! --measurement-time 3`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use moreau_kinematics::{Aabb, BroadPhase, ManifoldPoint, Pose, Shape, SplitMix64, collide};

fn bench_pair(c: &mut Criterion, name: &str, a: &Shape, pose_a: Pose, b: &Shape, pose_b: Pose) {
    let mut out: Vec<ManifoldPoint> = Vec::with_capacity(8);
    // The pair must be in contact, or the bench would time an early exit.
    collide(a, &pose_a, b, &pose_b, 0.01, &mut out).expect("supported pair");
    assert!(!out.is_empty(), "{name}: no contact");
    c.bench_function(name, |bench| {
        bench.iter(|| {
            out.clear();
            collide(
                black_box(a),
                black_box(&pose_a),
                black_box(b),
                black_box(&pose_b),
                0.01,
                &mut out,
            )
            .expect("supported pair");
            black_box(out.len())
        })
    });
}

fn narrow(c: &mut Criterion) {
    let floor = Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, 1.0] };
    let disk = Shape::Disk { center: [0.0, 0.0], radius: 0.1 };
    let square =
        Shape::Polygon { vertices: vec![[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]] };
    let origin = Pose::default();
    bench_pair(c, "collide/disk-halfplane", &disk, Pose::new(0.3, 0.099, 0.2), &floor, origin);
    bench_pair(c, "collide/box-halfplane", &square, Pose::new(0.3, 0.099, 0.0), &floor, origin);
    bench_pair(c, "collide/box-box", &square, origin, &square, Pose::new(0.05, 0.199, 0.01));
    // A wavy road of 100 segments with the disk resting in one of its troughs.
    let points: Vec<[f64; 2]> = (0..=100)
        .map(|k| {
            let x = -1.0 + 0.02 * k as f64;
            [x, 0.02 * (10.0 * x).cos()]
        })
        .collect();
    let road = Shape::Polyline { points };
    let trough = std::f64::consts::PI / 10.0;
    bench_pair(c, "collide/disk-polyline-100", &disk, Pose::new(trough, 0.081, 0.0), &road, origin);
}

fn broad(c: &mut Criterion) {
    // 10⁴ disks of radius 0.01 m at random in a 1 m square: about 3 neighbours each.
    let mut rng = SplitMix64::new(7);
    let boxes: Vec<Aabb> = (0..10_000)
        .map(|_| {
            let (x, y) = (rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0));
            Aabb { min: [x - 0.005, y - 0.005], max: [x + 0.005, y + 0.005] }
        })
        .collect();
    let mut broad = BroadPhase::new();
    let mut out = Vec::new();
    broad.pairs(&boxes, 0.001, &mut out);
    let count = out.len();
    let mut group = c.benchmark_group("broad");
    group.sample_size(20);
    group.bench_function(format!("disks-10000 ({count} pairs)"), |bench| {
        bench.iter(|| {
            broad.pairs(black_box(&boxes), 0.001, &mut out);
            black_box(out.len())
        })
    });
    group.finish();
}

criterion_group!(benches, narrow, broad);
criterion_main!(benches);
