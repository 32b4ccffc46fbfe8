//! Once warm, the narrow phase and the broad phase allocate nothing: counted with a global
//! allocator that tallies every allocation of the test's thread.

use moreau_kinematics::{Aabb, BroadPhase, Pose, Shape, SplitMix64, collide};
use moreau_testsupport::{CountingAllocator, allocations_in};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn warm_detection_allocates_nothing() {
    let floor = Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, 1.0] };
    let square =
        Shape::Polygon { vertices: vec![[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]] };
    let disk = Shape::Disk { center: [0.0, 0.0], radius: 0.1 };
    let road = Shape::Polyline {
        points: (0..=100)
            .map(|k| [-1.0 + 0.02 * k as f64, 0.02 * (0.2 * k as f64).cos()])
            .collect(),
    };
    let cam = Shape::profile_polar(|psi| 0.3 + 0.05 * psi.cos(), 64).unwrap();
    let pairs = [
        (&disk, &floor),
        (&square, &floor),
        (&square, &square),
        (&disk, &road),
        (&square, &road),
        (&cam, &disk),
        (&cam, &square),
    ];
    let mut rng = SplitMix64::new(3);
    let mut out = Vec::with_capacity(64);
    let mut boxes: Vec<Aabb> = (0..2000)
        .map(|_| {
            let (x, y) = (rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0));
            Aabb { min: [x, y], max: [x + 0.02, y + 0.02] }
        })
        .collect();
    boxes[5] = floor.aabb(&Pose::default());
    let mut broad = BroadPhase::new();
    let mut found = Vec::new();
    // Warm: the tree is built and the buffers grow to their size.
    broad.pairs(&boxes, 0.001, &mut found);
    broad.pairs(&boxes, 0.001, &mut found);
    found.reserve(found.len());
    let mut points = 0;
    let count = allocations_in(|| {
        for step in 0..100 {
            let y = 0.05 + 0.001 * step as f64;
            for (a, b) in pairs {
                out.clear();
                collide(
                    a,
                    &Pose::new(0.02, y, 0.01 * step as f64),
                    b,
                    &Pose::new(0.0, 0.0, 0.0),
                    0.2,
                    &mut out,
                )
                .unwrap();
                points += out.len();
            }
            for b in &mut boxes[..5] {
                b.min[0] += 1e-4;
                b.max[0] += 1e-4;
            }
            broad.pairs(&boxes, 0.001, &mut found);
        }
    });
    assert_eq!(count, 0, "{count} allocations in 100 warm detections");
    assert!(points > 200 && !found.is_empty(), "{points} points, {} pairs", found.len());
}
