//! The cost of contact detection: `collide` for a disk on a half-plane, a box on a half-plane,
//! two boxes, a disk on a polyline of 100 segments and on one of 10,000 (with and without its
//! index of runs), a box and a capsule on a cam profile of 96
//! points (resting on it, and sunk into it past their middle), and the broad phase over 10³ and 10⁴
//! disks of radius 5 mm, at random and in a column, beside parry2d-f64's refitted hierarchy on
//! the same boxes.
//!
//! Run with `cargo bench -p moreau-kinematics --bench collide -- --warm-up-time 1
//! --measurement-time 3`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use moreau_kinematics::{
    Aabb, BroadPhase, ChainIndex, ManifoldPoint, Placement, Pose, Shape, SplitMix64, collide,
    collide_indexed,
};
use parry2d_f64::bounding_volume::Aabb as ParryAabb;
use parry2d_f64::math::Vector as ParryVector;
use parry2d_f64::partitioning::{Bvh, BvhBuildStrategy, BvhWorkspace};

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
    // The same pair through parry2d-f64's shape dispatcher, measured in the same run: the
    // peer that the closed form was chosen over.
    {
        use parry2d_f64::math::{Pose as P, Vector as V};
        use parry2d_f64::shape::{Ball, HalfSpace};
        let (plane, ball) = (HalfSpace::new(V::new(0.0, 1.0)), Ball::new(0.1));
        let (p1, p2) = (P::new(V::new(0.0, 0.0), 0.0), P::new(V::new(0.3, 0.099), 0.2));
        assert!(parry2d_f64::query::contact(&p1, &plane, &p2, &ball, 0.01).unwrap().is_some());
        c.bench_function("collide/disk-halfplane (parry dispatcher)", |bench| {
            bench.iter(|| {
                let (a, b) = (black_box(&p1), black_box(&p2));
                black_box(parry2d_f64::query::contact(a, &plane, b, &ball, 0.01).unwrap())
            })
        });
    }
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
    // A three-lobed cam r(ψ) = 0.3 + 0.06 cos 3ψ of 96 samples, a lobe's tip (0.36) at ψ = 0,
    // with a box and a capsule on the tip, 1 mm into it.
    let cam = Shape::profile_polar(|psi| 0.3 + 0.06 * (3.0 * psi).cos(), 96).expect("valid cam");
    bench_pair(c, "collide/box-profile-96", &square, Pose::new(0.459, 0.0, 0.0), &cam, origin);
    let capsule = Shape::Capsule { a: [0.0, -0.1], b: [0.0, 0.1], radius: 0.05 };
    let on_tip = Pose::new(0.409, 0.0, 0.0);
    bench_pair(c, "collide/capsule-profile-96", &capsule, on_tip, &cam, origin);
    // The box 0.12 into the tip (past its middle), the capsule 0.11 (its ends inside).
    bench_pair(c, "collide/box-in-profile-96", &square, Pose::new(0.34, 0.0, 0.0), &cam, origin);
    let in_tip = Pose::new(0.3, 0.0, 0.0);
    bench_pair(c, "collide/capsule-in-profile-96", &capsule, in_tip, &cam, origin);
    long_floor(c);
}

/// A grain of radius 5 mm resting 0.1 mm deep on a wavy floor 10 m long of 10,000 segments,
/// margin 1 mm, without and with the floor's [`ChainIndex`] (the same points, bit for bit).
fn long_floor(c: &mut Criterion) {
    let points: Vec<[f64; 2]> = (0..=10_000)
        .map(|k| {
            let x = k as f64 * 1e-3;
            [x, 0.05 * (3.0 * x).sin()]
        })
        .collect();
    let floor = Shape::Polyline { points };
    let index = ChainIndex::new(&floor).expect("a long floor is indexed");
    let grain = Shape::Disk { center: [0.0, 0.0], radius: 0.005 };
    let at = Placement::new(&Pose::new(5.0, 0.05 * 15f64.sin() + 0.0049, 0.0));
    let origin = Placement::new(&Pose::default());
    let mut out: Vec<ManifoldPoint> = Vec::with_capacity(8);
    collide_indexed(&grain, &at, &floor, &origin, Some(&index), 1e-3, &mut out).expect("a pair");
    assert_eq!(out.len(), 1, "the grain rests on one segment");
    for (name, index) in [
        ("collide/disk-polyline-10000", None),
        ("collide/disk-polyline-10000 (indexed)", Some(&index)),
    ] {
        c.bench_function(name, |bench| {
            bench.iter(|| {
                out.clear();
                collide_indexed(
                    black_box(&grain),
                    black_box(&at),
                    black_box(&floor),
                    &origin,
                    index,
                    1e-3,
                    &mut out,
                )
                .expect("supported pair");
                black_box(out.len())
            })
        });
    }
}

/// n disks of radius 5 mm at random in a square of side √n / 100 m (10⁴ in 1 m²), margin 1 mm:
/// about 6 boxes meet each; and the same disks settled in a column 20 diameters wide.
fn disk_boxes(n: usize, column: bool) -> Vec<Aabb> {
    let mut rng = SplitMix64::new(7);
    let side = (n as f64).sqrt() / 100.0;
    (0..n)
        .map(|k| {
            let (x, y) = if column {
                // Rows of 20 touching disks, each moved by up to 0.5 mm.
                let (i, j) = ((k % 20) as f64, (k / 20) as f64);
                (0.01 * i + rng.uniform(-5e-4, 5e-4), 0.01 * j + rng.uniform(-5e-4, 5e-4))
            } else {
                (rng.uniform(0.0, side), rng.uniform(0.0, side))
            };
            Aabb { min: [x - 0.005, y - 0.005], max: [x + 0.005, y + 0.005] }
        })
        .collect()
}

fn broad(c: &mut Criterion) {
    let mut group = c.benchmark_group("broad");
    group.sample_size(20);
    for (n, column) in [(1000, false), (10_000, false), (10_000, true)] {
        let boxes = disk_boxes(n, column);
        let mut broad = BroadPhase::new();
        let mut out = Vec::new();
        broad.pairs(&boxes, 0.001, &mut out);
        let count = out.len();
        let layout = if column { "column" } else { "random" };
        group.bench_function(format!("grid/disks-{n}-{layout} ({count} pairs)"), |bench| {
            bench.iter(|| {
                broad.pairs(black_box(&boxes), 0.001, &mut out);
                black_box(out.len())
            })
        });
        // parry2d-f64's hierarchy built once, then refitted and traversed at every call: the
        // incremental alternative the grid replaced.
        let grown = |b: &Aabb| {
            ParryAabb::new(
                ParryVector::new(b.min[0] - 0.001, b.min[1] - 0.001),
                ParryVector::new(b.max[0] + 0.001, b.max[1] + 0.001),
            )
        };
        let mut tree = Bvh::from_iter(
            BvhBuildStrategy::Binned,
            boxes.iter().enumerate().map(|(i, b)| (i, grown(b))),
        );
        let mut workspace = BvhWorkspace::default();
        group.bench_function(format!("parry-refit/disks-{n}-{layout}"), |bench| {
            bench.iter(|| {
                out.clear();
                for (i, b) in boxes.iter().enumerate() {
                    tree.insert_or_update_partially(grown(b), i as u32, 0.0);
                }
                tree.refit(&mut workspace);
                tree.traverse_bvtt_single_tree::<false>(&mut workspace, &mut |i, j| {
                    let (i, j) = (i as usize, j as usize);
                    if boxes[i].overlaps(&boxes[j], 0.001) {
                        out.push((i.min(j), i.max(j)));
                    }
                });
                out.sort_unstable();
                black_box(out.len())
            })
        });
    }
    group.finish();
}

criterion_group!(benches, narrow, broad);
criterion_main!(benches);
