//! The broad phase against brute force: random boxes, piles of grains with walls, floors and
//! strays, boxes of zero size, and inputs a grid cannot hold.

use moreau_kinematics::{Aabb, BroadPhase, Pose, Shape, SplitMix64};

mod common;
use common::floor;

#[test]
fn broad_phase_matches_brute_force() {
    let mut rng = SplitMix64::new(42);
    let mut broad = BroadPhase::new();
    let mut out = Vec::new();
    for round in 0..6 {
        let n = if round < 3 { 300 } else { 200 + 40 * round };
        let mut boxes: Vec<Aabb> = (0..n)
            .map(|_| {
                let (x, y) = (rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0));
                let (w, h) = (rng.uniform(0.0, 0.05), rng.uniform(0.0, 0.05));
                Aabb { min: [x, y], max: [x + w, y + h] }
            })
            .collect();
        // A floor and a wall (infinite boxes) among them.
        boxes[7] = floor().aabb(&Pose::new(0.0, 0.1, 0.0));
        boxes[11] = Shape::HalfPlane { point: [0.0, 0.0], normal: [-1.0, 0.0] }
            .aabb(&Pose::new(0.9, 0.0, 0.0));
        let margin = 0.005;
        broad.pairs(&boxes, margin, &mut out);
        let mut brute = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                if boxes[i].overlaps(&boxes[j], margin) {
                    brute.push((i, j));
                }
            }
        }
        assert!(brute.len() > n / 2, "too few pairs to test: {}", brute.len());
        assert_eq!(out, brute, "round {round}");
        // The searches of consecutive ranges of boxes, the walls' among them, give the list
        // in consecutive runs.
        let mut runs = Vec::new();
        for start in (0..n).step_by(37) {
            broad.pairs_of(&boxes, start..n.min(start + 37), &mut runs);
        }
        assert_eq!(runs, brute, "round {round}, by ranges");
    }
    // The same boxes moved a little: the refitted tree still finds every pair.
    let mut boxes: Vec<Aabb> = (0..500)
        .map(|_| {
            let (x, y) = (rng.uniform(0.0, 1.0), rng.uniform(0.0, 1.0));
            Aabb { min: [x, y], max: [x + 0.03, y + 0.03] }
        })
        .collect();
    for _ in 0..5 {
        broad.pairs(&boxes, 0.0, &mut out);
        let brute: Vec<(usize, usize)> = (0..500)
            .flat_map(|i| (i + 1..500).map(move |j| (i, j)))
            .filter(|&(i, j)| boxes[i].overlaps(&boxes[j], 0.0))
            .collect();
        assert_eq!(out, brute);
        for b in &mut boxes {
            let d = [rng.uniform(-0.02, 0.02), rng.uniform(-0.02, 0.02)];
            *b = Aabb {
                min: [b.min[0] + d[0], b.min[1] + d[1]],
                max: [b.max[0] + d[0], b.max[1] + d[1]],
            };
        }
    }
}

/// The pairs by testing every pair of boxes.
fn brute_pairs(boxes: &[Aabb], margin: f64) -> Vec<(usize, usize)> {
    let n = boxes.len();
    (0..n)
        .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
        .filter(|&(i, j)| boxes[i].overlaps(&boxes[j], margin))
        .collect()
}

#[test]
fn broad_phase_matches_brute_force_on_piles_walls_and_strays() {
    let mut rng = SplitMix64::new(2024);
    let mut broad = BroadPhase::new();
    let mut out = Vec::new();
    for round in 0..8 {
        let n = 200 + 100 * round;
        // Grains of radii in [0.8, 1.2] r packed in a column (many touching), some boxes far
        // out (a stray grain), long walls and a floor, a zero-size box and a NaN one.
        let r = 0.01;
        let mut boxes: Vec<Aabb> = (0..n)
            .map(|k| {
                let (x, y) = (0.021 * (k % 20) as f64, 0.021 * (k / 20) as f64);
                let (x, y) = (x + rng.uniform(-0.002, 0.002), y + rng.uniform(-0.002, 0.002));
                let rk = r * rng.uniform(0.8, 1.2);
                Aabb { min: [x - rk, y - rk], max: [x + rk, y + rk] }
            })
            .collect();
        boxes[3] = Aabb { min: [-0.05, -0.5], max: [-0.01, 5.0] }; // a long wall
        boxes[17] = Aabb { min: [-1.0, -0.02], max: [1.0, -0.005] }; // a long floor board
        boxes[29] = floor().aabb(&Pose::new(0.0, -0.001, 0.0));
        boxes[41] =
            Aabb { min: [50.0 * round as f64, -300.0], max: [50.0 * round as f64 + 0.02, -299.98] };
        boxes[53] = Aabb { min: [0.1, 0.1], max: [0.1, 0.1] };
        boxes[59] = Aabb { min: [f64::NAN, 0.0], max: [0.1, 0.1] };
        let margin = 0.0005 * round as f64;
        broad.pairs(&boxes, margin, &mut out);
        let brute = brute_pairs(&boxes, margin);
        assert!(brute.len() > n, "too few pairs to test: {}", brute.len());
        assert!(brute.iter().any(|&(i, j)| i == 3 || j == 3), "the wall touches grains");
        assert_eq!(out, brute, "round {round}");
    }
    // Boxes all of zero size, some coinciding, with no margin.
    let points: Vec<Aabb> = (0..50)
        .map(|k| {
            let p = [(k % 7) as f64, (k % 5) as f64];
            Aabb { min: p, max: p }
        })
        .collect();
    broad.pairs(&points, 0.0, &mut out);
    assert_eq!(out, brute_pairs(&points, 0.0));
    assert!(!out.is_empty());
}

#[test]
fn boxes_a_grid_cannot_hold_are_paired_by_testing_every_pair() {
    let mut broad = BroadPhase::new();
    let mut out = Vec::new();
    let unit = |x: f64, y: f64| Aabb { min: [x, y], max: [x + 1.0, y + 1.0] };
    // Boxes 2e308 apart: their span overflows f64, so no grid cell size covers it. The two
    // far boxes touch each other and nothing else; the middle ones overlap each other.
    let spread = vec![
        unit(-1e308, 0.0),
        unit(0.0, 0.0),
        unit(0.5, 0.5),
        unit(1e308, 0.0),
        unit(-1e308, 0.5),
    ];
    broad.pairs(&spread, 0.0, &mut out);
    assert_eq!(out, vec![(0, 4), (1, 2)]);
    assert_eq!(out, brute_pairs(&spread, 0.0));
    // An infinite margin makes every two boxes overlap, except a box with a NaN coordinate.
    let mut boxes: Vec<Aabb> = (0..6).map(|k| unit(10.0 * k as f64, 0.0)).collect();
    boxes[4].min[0] = f64::NAN;
    broad.pairs(&boxes, f64::INFINITY, &mut out);
    assert_eq!(out.len(), 10, "{out:?}");
    assert!(out.iter().all(|&(i, j)| i < j && i != 4 && j != 4));
    assert_eq!(out, brute_pairs(&boxes, f64::INFINITY));
    // The same broad phase then grids ordinary boxes again.
    broad.pairs(&boxes[..2], 5.0, &mut out);
    assert_eq!(out, vec![(0, 1)]);
}
