//! A chain's index of runs of segments changes no point: disks, boxes and capsules placed on,
//! near and deep inside long polylines and profiles (turned and moved, far from the origin),
//! and half-planes cutting them, meet them in the same points, bit for bit, with the index and
//! without.

use moreau_kinematics::{
    ChainIndex, ManifoldPoint, Placement, Pose, Shape, SplitMix64, collide_indexed, collide_placed,
};

/// A profile round a bumpy star of `n` points, radius about `r`, centred at `c`.
fn star(n: usize, r: f64, c: [f64; 2], rng: &mut SplitMix64) -> Vec<[f64; 2]> {
    let bumps = 3.0 + (rng.next_f64() * 8.0).floor();
    let depth = 0.1 + 0.3 * rng.next_f64();
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            let rho = r * (1.0 + depth * (bumps * a).cos() + 0.02 * (rng.next_f64() - 0.5));
            [c[0] + rho * a.cos(), c[1] + rho * a.sin()]
        })
        .collect()
}

/// A rough floor of `n` points from x0 on, steps of about `h`, with a notch of depth `h`.
fn floor(n: usize, h: f64, x0: f64, rng: &mut SplitMix64) -> Vec<[f64; 2]> {
    let mut x = x0;
    (0..n)
        .map(|k| {
            x += h * (0.5 + rng.next_f64());
            let notch = if k % 37 == 0 { -h } else { 0.0 };
            [x, 3.0 * h * (x / (20.0 * h)).sin() + 0.3 * h * rng.next_f64() + notch]
        })
        .collect()
}

/// The convex shapes placed against the chains: a disk, a point, a box and a capsule of size
/// about `s`.
fn convex(s: f64) -> [Shape; 4] {
    [
        Shape::Disk { center: [0.0, 0.0], radius: s },
        Shape::Disk { center: [0.0, 0.0], radius: 0.0 },
        Shape::Polygon {
            vertices: vec![[-s, -0.6 * s], [s, -0.6 * s], [s, 0.6 * s], [-s, 0.6 * s]],
        },
        Shape::Capsule { a: [-s, 0.0], b: [s, 0.0], radius: 0.4 * s },
    ]
}

/// The points of `x` at `at` with `chain` at `frame`, each way round, with and without the
/// chain's index: asserted equal; returns how many there were.
fn same_points(x: &Shape, at: Pose, chain: &Shape, frame: Pose, margin: f64) -> usize {
    let index = ChainIndex::new(chain).expect("a long chain");
    let (pa, pb) = (Placement::new(&at), Placement::new(&frame));
    let (mut fast, mut plain) = (Vec::<ManifoldPoint>::new(), Vec::<ManifoldPoint>::new());
    collide_indexed(x, &pa, chain, &pb, Some(&index), margin, &mut fast).expect("a pair");
    collide_placed(x, &pa, chain, &pb, margin, &mut plain).expect("a pair");
    assert_eq!(fast, plain, "{x:?} at {at:?}");
    let found = fast.len();
    fast.clear();
    plain.clear();
    collide_indexed(chain, &pb, x, &pa, Some(&index), margin, &mut fast).expect("a pair");
    collide_placed(chain, &pb, x, &pa, margin, &mut plain).expect("a pair");
    assert_eq!(fast, plain, "{x:?} at {at:?}, the chain first");
    found
}

#[test]
fn shapes_on_and_in_long_chains_meet_the_same_points_with_the_index() {
    let mut rng = SplitMix64::new(7);
    let mut found = [0usize; 2];
    for case in 0..40 {
        let n = 65 + (rng.next_f64() * 3000.0) as usize;
        let scale = [1e-3, 1.0, 1e3][case % 3];
        let far = [0.0, 1e4 * scale][case % 2];
        let frame = Pose::new(far - 3.0 * scale, 2.0 * scale, [0.0, 0.3, -2.1][case % 3]);
        let profile = Shape::Profile { points: star(n, scale, [far, -far], &mut rng) };
        let road = Shape::Polyline { points: floor(n, scale / n as f64 * 4.0, far, &mut rng) };
        for (c, chain) in [profile, road].iter().enumerate() {
            let (Shape::Profile { points } | Shape::Polyline { points }) = chain else {
                unreachable!()
            };
            let s = scale * [0.05, 0.01][c];
            for _ in 0..30 {
                // Near a point of the chain, off it by up to twice the shape's size either
                // way, so that some shapes sit on it, some lie inside the profile and some
                // stand clear.
                let v = points[(rng.next_f64() * points.len() as f64) as usize];
                let placed = Placement::new(&frame).pose();
                let (sin, cos) = placed.theta.sin_cos();
                let w = [
                    placed.x + cos * v[0] - sin * v[1] + 2.0 * s * (2.0 * rng.next_f64() - 1.0),
                    placed.y + sin * v[0] + cos * v[1] + 2.0 * s * (2.0 * rng.next_f64() - 1.0),
                ];
                let at = Pose::new(w[0], w[1], 6.0 * rng.next_f64());
                for x in &convex(s) {
                    // A point has no thickness and meets no polyline.
                    let thin = matches!(x, Shape::Disk { radius, .. } if *radius == 0.0);
                    if thin && c == 1 {
                        continue;
                    }
                    found[c] += same_points(x, at, chain, frame, 0.5 * s);
                }
            }
        }
    }
    // The placements touch the chains often enough for the comparison to mean something.
    assert!(found[0] > 1000 && found[1] > 1000, "points found: {found:?}");
}

#[test]
fn half_planes_through_long_chains_meet_the_same_points_with_the_index() {
    // Floors and walls of every slope cutting profiles and polylines at every depth: the
    // points at the local minima of the height, kept bit for bit and in the same order.
    let mut rng = SplitMix64::new(5);
    let mut found = 0;
    for case in 0..60 {
        let n = 65 + (rng.next_f64() * 2000.0) as usize;
        let far = [0.0, 3e3][case % 2];
        let frame = Pose::new(far + 0.5, -far, [0.0, 1.1, -0.4][case % 3]);
        let chain = if case % 2 == 0 {
            Shape::Profile { points: star(n, 1.0, [0.0, 0.0], &mut rng) }
        } else {
            Shape::Polyline { points: floor(n, 2.0 / n as f64, -1.0, &mut rng) }
        };
        let centre = Placement::new(&frame).pose();
        for _ in 0..20 {
            let a = std::f64::consts::TAU * rng.next_f64();
            let depth = 1.6 * rng.next_f64() - 0.8;
            let plane = Shape::HalfPlane { point: [0.0, 0.0], normal: [a.cos(), a.sin()] };
            let at = Pose::new(centre.x - depth * a.cos(), centre.y - depth * a.sin(), 0.0);
            found += same_points(&plane, at, &chain, frame, 0.01);
        }
    }
    assert!(found > 2000, "points found: {found}");
}

#[test]
fn a_disk_deep_inside_a_long_profile_is_pushed_out_alike() {
    // Centres inside the solid take the parity of a ray's crossings over the whole loop.
    let mut rng = SplitMix64::new(11);
    let profile = Shape::Profile { points: star(5000, 1.0, [0.0, 0.0], &mut rng) };
    let frame = Pose::new(0.4, -0.2, 1.0);
    let disk = Shape::Disk { center: [0.0, 0.0], radius: 0.05 };
    let mut found = 0;
    for k in 0..200 {
        let a = k as f64 * 0.0314;
        let r = 0.3 + 0.6 * rng.next_f64();
        let at = Pose::new(0.4 + r * a.cos(), -0.2 + r * a.sin(), 0.0);
        found += same_points(&disk, at, &profile, frame, 1.0);
    }
    assert!(found >= 200, "every disk inside gets its way out: {found}");
}

#[test]
fn an_index_of_another_chain_is_not_used() {
    let mut rng = SplitMix64::new(3);
    let long = Shape::Profile { points: star(400, 1.0, [0.0, 0.0], &mut rng) };
    let other = Shape::Profile { points: star(500, 1.0, [0.0, 0.0], &mut rng) };
    let wrong = ChainIndex::new(&other).expect("indexed");
    let disk = Shape::Disk { center: [0.0, 0.0], radius: 0.1 };
    let (at, origin) =
        (Placement::new(&Pose::new(1.0, 0.0, 0.0)), Placement::new(&Pose::default()));
    let (mut with_wrong, mut plain) = (Vec::new(), Vec::new());
    collide_indexed(&disk, &at, &long, &origin, Some(&wrong), 0.5, &mut with_wrong).unwrap();
    collide_placed(&disk, &at, &long, &origin, 0.5, &mut plain).unwrap();
    assert_eq!(with_wrong, plain);
    assert!(!plain.is_empty());
}
