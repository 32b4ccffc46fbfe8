//! Contacts with chains (polylines and profiles) and segments: corners, a sampled cam against
//! a flat follower, a floor and a roller, a convex profile against the same polygon, segments
//! standing square to a face, and capsules and boxes sunk into a square and an L-shaped
//! profile.

use std::f64::consts::PI;

use approx::assert_relative_eq;
use moreau_kinematics::{ManifoldPoint, Pose, Shape, SplitMix64, max_points};

mod common;
use common::{cam, disk, floor, points, rect, sorted_by_feature};

#[test]
fn disk_in_a_concave_corner_touches_both_segments() {
    // A V of two segments at ±45°, the disk centred on its axis touching both.
    let v = Shape::Polyline { points: vec![[-1.0, 1.0], [0.0, 0.0], [1.0, 1.0]] };
    let r = 0.2;
    let y = r * 2f64.sqrt() + 1e-3;
    let p = sorted_by_feature(points(
        &disk(0.0, 0.0, r),
        Pose::new(0.0, y, 0.0),
        &v,
        Pose::default(),
        0.01,
    ));
    assert_eq!(p.iter().map(|q| q.feature).collect::<Vec<_>>(), vec![0, 1]);
    for q in &p {
        assert_relative_eq!(q.gap, 1e-3 / 2f64.sqrt(), epsilon = 1e-12);
    }
    // On a convex corner (the V upside down) the disk touches the vertex once.
    let ridge = Shape::Polyline { points: vec![[-1.0, -1.0], [0.0, 0.0], [1.0, -1.0]] };
    let p =
        points(&disk(0.0, 0.0, r), Pose::new(0.0, r + 1e-3, 0.0), &ridge, Pose::default(), 0.01);
    assert_eq!(p.len(), 1);
    assert_eq!(p[0].feature as usize, 2 + 1);
    assert_relative_eq!(p[0].gap, 1e-3, epsilon = 1e-12);
}

#[test]
fn cam_profile_against_a_flat_follower_and_a_roller() {
    // A circular cam of radius R sampled every degree, a sample at its top (ψ = 90°).
    let r_cam = 0.3;
    let cam = Shape::profile_polar(|_| r_cam, 360).unwrap();
    assert_relative_eq!(
        cam.area(),
        180.0 * r_cam * r_cam * (2.0 * PI / 360.0).sin(),
        epsilon = 1e-12
    );
    // A flat-faced follower 1 mm above the top: the top sample, its gap exact, and the far
    // ends of the two chords there, onto which the follower closes as soon as it tilts.
    let follower = rect(0.4, 0.1);
    let p =
        points(&cam, Pose::default(), &follower, Pose::new(0.0, r_cam + 0.05 + 1e-3, 0.0), 0.01);
    let p = sorted_by_feature(p);
    assert_eq!(p.len(), 3, "{p:?}");
    let sag = r_cam * (1.0 - 1f64.to_radians().cos());
    for (q, gap) in p.iter().zip([1e-3 + sag, 1e-3, 1e-3 + sag]) {
        assert_relative_eq!(q.gap, gap, epsilon = 1e-12);
        assert_relative_eq!(q.normal[1], 1.0, epsilon = 1e-12);
    }
    assert_relative_eq!(p[1].point_a[1], r_cam, epsilon = 1e-12);
    // The cam turned by half a degree: the follower rests on the two samples astride the top.
    let half = 0.5f64.to_radians();
    let p =
        points(&cam, Pose::new(0.0, 0.0, half), &follower, Pose::new(0.0, r_cam + 0.05, 0.0), 0.01);
    let lift = r_cam * half.cos();
    assert_eq!(p.len(), 2, "{p:?}");
    for q in &p {
        assert_relative_eq!(q.gap, r_cam - lift, epsilon = 1e-12);
    }
    // The same cam on a floor: the sample at the bottom and its chords' far ends; two
    // samples astride the bottom, level on the floor.
    let p = sorted_by_feature(points(
        &floor(),
        Pose::default(),
        &cam,
        Pose::new(0.1, r_cam, 0.0),
        0.01,
    ));
    assert_eq!(p.iter().map(|q| q.feature).collect::<Vec<_>>(), vec![269, 270, 271]);
    for (q, gap) in p.iter().zip([sag, 0.0, sag]) {
        assert_relative_eq!(q.gap, gap, epsilon = 1e-12);
    }
    let p = points(&floor(), Pose::default(), &cam, Pose::new(0.1, r_cam, half), 0.01);
    assert_eq!(p.iter().map(|q| q.feature).collect::<Vec<_>>(), vec![269, 270]);
    for q in &p {
        assert_relative_eq!(q.gap, r_cam - lift, epsilon = 1e-12);
    }
    // A roller of radius r on the cam at 40°, off the samples: the chord's distance.
    let (r, psi) = (0.05, 40.5f64.to_radians());
    let d = r_cam + r + 2e-3;
    let p = points(
        &disk(0.0, 0.0, r),
        Pose::new(d * psi.cos(), d * psi.sin(), 0.0),
        &cam,
        Pose::default(),
        0.01,
    );
    assert_eq!(p.len(), 1);
    let chord = r_cam * 0.5f64.to_radians().cos();
    assert_relative_eq!(p[0].gap, d - chord - r, epsilon = 1e-12);
    assert_eq!(p[0].feature, 40, "segment 40 runs from 40° to 41°");
}

/// A square declared as a profile (a solid bounded by a chain) meets a slab, a floor and a
/// small box on its top face at the same points, gaps and normals as the same square declared
/// as a polygon: on both corners of a face lying on a face, and on no corner of the other
/// body seen behind a side that faces away from it or stands square to it. Seeded poses from
/// upright to tilted by 0.3 rad, from 1 mm deep to 5 mm apart.
#[test]
fn a_convex_profile_meets_faces_as_the_same_polygon_does() {
    let corners = vec![[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]];
    let profile = Shape::Profile { points: corners.clone() };
    let polygon = Shape::Polygon { vertices: corners };
    let slab =
        Shape::Polygon { vertices: vec![[-1.0, -0.2], [1.0, -0.2], [1.0, 0.0], [-1.0, 0.0]] };
    let small = rect(0.06, 0.04);
    let key = |p: &[ManifoldPoint]| {
        let mut v: Vec<[f64; 5]> = p
            .iter()
            .map(|q| [q.point_b[0], q.point_b[1], q.gap, q.normal[0], q.normal[1]])
            .collect();
        v.sort_by(|a, b| a.partial_cmp(b).unwrap());
        v
    };
    let mut rng = SplitMix64::new(77);
    let (mut two, mut compared) = (0, 0);
    for i in 0..400 {
        // Every eighth pose exactly upright, where the sides stand square to the faces.
        let theta = if i % 8 == 0 { 0.0 } else { rng.uniform(-0.3, 0.3) };
        let depth = rng.uniform(-1e-3, 5e-3);
        // The lowest corner of the square at height `depth`.
        let low = 0.1 * (theta.cos() + theta.sin().abs());
        let pose = Pose::new(rng.uniform(-0.5, 0.5), low + depth, theta);
        let small_pose = {
            // The small box on the square's top face, tilted a little against it.
            let (s, c) = theta.sin_cos();
            let lift = 0.1 + 0.02 + depth;
            Pose::new(pose.x - s * lift, pose.y + c * lift, theta + rng.uniform(-0.02, 0.02))
        };
        let cases: [(&Shape, Pose, bool); 3] = [
            (&slab, Pose::default(), true),
            (&floor(), Pose::default(), true),
            (&small, small_pose, false),
        ];
        for (other, other_pose, other_is_a) in cases {
            let get = |square: &Shape| {
                if other_is_a {
                    points(other, other_pose, square, pose, 0.01)
                } else {
                    points(square, pose, other, other_pose, 0.01)
                }
            };
            let (a, b) = (key(&get(&profile)), key(&get(&polygon)));
            assert_eq!(a.len(), b.len(), "θ {theta}, depth {depth}: {a:?} against {b:?}");
            for (x, y) in a.iter().zip(&b) {
                for k in 0..5 {
                    assert!((x[k] - y[k]).abs() <= 1e-12, "θ {theta}: {x:?} against {y:?}");
                }
            }
            two += usize::from(a.len() == 2);
            compared += 1;
        }
    }
    assert_eq!(compared, 1200);
    assert!(two > 100, "{two} manifolds of two points");
}

/// A segment standing upright with its lower end 0.1 mm into a slab, as a polyline and as a
/// capsule of radius 0: one point, at that end, 0.1 mm deep, for either side of the segment
/// and a slab reaching 1 m to each side (neither corner of the slab lies on the segment's
/// faces, which stand square to the slab's).
#[test]
fn an_upright_segment_in_a_slab_touches_at_its_end_only() {
    let slab =
        Shape::Polygon { vertices: vec![[-1.0, -0.2], [1.0, -0.2], [1.0, 0.0], [-1.0, 0.0]] };
    for shape in [
        Shape::Polyline { points: vec![[0.0, -0.1], [0.0, 0.1]] },
        Shape::Polyline { points: vec![[0.0, 0.1], [0.0, -0.1]] },
        Shape::Capsule { a: [0.0, -0.1], b: [0.0, 0.1], radius: 0.0 },
        Shape::Capsule { a: [0.0, 0.1], b: [0.0, -0.1], radius: 0.0 },
    ] {
        for x in [-0.5, 0.0, 0.3] {
            let p = points(&slab, Pose::default(), &shape, Pose::new(x, 0.1 - 1e-4, 0.0), 0.01);
            assert_eq!(p.len(), 1, "{shape:?} at {x}: {p:?}");
            assert_relative_eq!(p[0].gap, -1e-4, epsilon = 1e-12);
            assert_eq!(p[0].normal, [0.0, 1.0]);
            assert_relative_eq!(p[0].point_b[0], x, epsilon = 1e-15);
        }
    }
}

/// The square of side 1 about the origin as a profile and as a polygon.
fn square_profile_and_polygon() -> (Shape, Shape) {
    let corners = vec![[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]];
    (Shape::Profile { points: corners.clone() }, Shape::Polygon { vertices: corners })
}

/// An L of two unit arms: the lower from x = 0 to 2, the upper from y = 0 to 2; its top face
/// y = 1 (1 ≤ x ≤ 2) and its inner face x = 1 (1 ≤ y ≤ 2) meet at a concave corner.
fn l_profile() -> Shape {
    Shape::Profile {
        points: vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]],
    }
}

/// The points as (point on B, gap, normal), sorted, to compare two pairs whose ids differ.
fn key(p: &[ManifoldPoint]) -> Vec<[f64; 5]> {
    let mut v: Vec<[f64; 5]> =
        p.iter().map(|q| [q.point_b[0], q.point_b[1], q.gap, q.normal[0], q.normal[1]]).collect();
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v
}

fn assert_same(a: &[ManifoldPoint], b: &[ManifoldPoint], what: &str) {
    let (a, b) = (key(a), key(b));
    assert_eq!(a.len(), b.len(), "{what}: {a:?} against {b:?}");
    for (x, y) in a.iter().zip(&b) {
        for k in 0..5 {
            assert!((x[k] - y[k]).abs() <= 1e-12, "{what}: {x:?} against {y:?}");
        }
    }
}

fn deepest(p: &[ManifoldPoint]) -> ManifoldPoint {
    *p.iter().min_by(|a, b| a.gap.total_cmp(&b.gap)).expect("a point")
}

/// A capsule (radius 0.1, axis 0.4) and a box (0.2 square) sunk into a square profile through
/// its bottom face, from a few millimetres to wholly inside: the points of the same square
/// declared as a polygon (separating axes), bit for bit to 1e-12, upright and tilted, and
/// pushing out of the solid (normal (0, −1) from the square) by the depth.
#[test]
fn shapes_sunk_into_a_square_profile_meet_it_as_the_same_polygon_does() {
    let (profile, polygon) = square_profile_and_polygon();
    let capsule = Shape::Capsule { a: [-0.2, 0.0], b: [0.2, 0.0], radius: 0.1 };
    let square = rect(0.2, 0.2);
    let o = Pose::default();
    // The capsule's axis at height −0.5 + d: 0.1 + d deep when level.
    for d in [-0.05, 0.02, 0.05, 0.12, 0.3] {
        for (x, theta) in [(0.0, 0.0f64), (0.1, 0.25), (-0.15, -0.4)] {
            let pose = Pose::new(x, -0.5 + d, theta);
            let p = points(&profile, o, &capsule, pose, 0.0);
            assert_same(&p, &points(&polygon, o, &capsule, pose, 0.0), &format!("capsule {d}"));
            // Out through the bottom face: its highest end, grown by the radius, below it.
            let q = deepest(&p);
            assert_relative_eq!(q.gap, -(d + 0.2 * theta.sin().abs() + 0.1), epsilon = 1e-12);
            assert_relative_eq!(q.normal[1], -1.0, epsilon = 1e-12);
        }
    }
    // Upright, at d = 0.05: both ends, 0.15 deep, where the faces of the profile met alone
    // gave one point 0.05 deep pushing the capsule further in.
    let p = points(&profile, o, &capsule, Pose::new(0.0, -0.45, 0.0), 0.0);
    assert_eq!(p.len(), 2);
    for q in &p {
        assert_relative_eq!(q.gap, -0.15, epsilon = 1e-12);
        assert_eq!(q.normal, [0.0, -1.0]);
    }
    // The box with its top at height −0.5 + d: d deep, past its middle from d = 0.1 on and
    // wholly inside from d = 0.2 on.
    for d in [0.02, 0.05, 0.12, 0.19, 0.25, 0.4] {
        for (x, theta) in [(0.0, 0.0f64), (0.2, 0.2), (-0.1, -0.35)] {
            let top = 0.1 * (theta.cos() + theta.sin().abs());
            let pose = Pose::new(x, -0.5 + d - top, theta);
            let p = points(&profile, o, &square, pose, 0.0);
            assert_same(&p, &points(&polygon, o, &square, pose, 0.0), &format!("box {d}"));
            let q = deepest(&p);
            assert_relative_eq!(q.gap, -d, epsilon = 1e-12);
            assert_relative_eq!(q.normal[1], -1.0, epsilon = 1e-12);
        }
    }
    // 0.12 deep and upright: its top corners, where the profile's faces alone gave none.
    let p = sorted_by_feature(points(&profile, o, &square, Pose::new(0.0, -0.48, 0.0), 0.0));
    assert_eq!(p.iter().map(|q| q.feature).collect::<Vec<_>>(), vec![2, 3]);
    for (q, x) in p.iter().zip([0.1, -0.1]) {
        assert_relative_eq!(q.gap, -0.12, epsilon = 1e-12);
        assert_eq!(q.normal, [0.0, -1.0]);
        assert_relative_eq!(q.point_b[0], x, epsilon = 1e-12);
        assert_relative_eq!(q.point_b[1], -0.38, epsilon = 1e-12);
    }
}

/// A box and a capsule sunk into the faces of an L-shaped profile (its lower arm's top face,
/// its upper arm's inner face), upright and tilted, from 5 mm to wholly inside: the points that
/// a half-plane on the face's line gives them (every vertex), those of the face's side of the
/// shape, the deepest the same; normals out of the solid.
#[test]
fn shapes_sunk_into_an_l_profile_meet_its_faces_as_half_planes_do() {
    let l = l_profile();
    let o = Pose::default();
    let top = Shape::HalfPlane { point: [0.0, 1.0], normal: [0.0, 1.0] };
    let inner = Shape::HalfPlane { point: [1.0, 0.0], normal: [1.0, 0.0] };
    let square = rect(0.2, 0.2);
    let capsule = Shape::Capsule { a: [-0.2, 0.0], b: [0.2, 0.0], radius: 0.1 };
    let contained = |p: &[ManifoldPoint], plane: &[ManifoldPoint], what: &str| {
        let plane = key(plane);
        for x in key(p) {
            let found = plane.iter().any(|y| (0..5).all(|k| (x[k] - y[k]).abs() <= 1e-12));
            assert!(found, "{what}: {x:?} not among {plane:?}");
        }
    };
    for theta in [0.0, 0.3, -0.2] {
        // The box's lowest corner d below the top face, at x = 1.5.
        let low = 0.1 * (f64::cos(theta) + f64::sin(theta).abs());
        for d in [0.005, 0.05, 0.12, 0.19, 0.3, 0.5] {
            let pose = Pose::new(1.5, 1.0 + low - d, theta);
            let (p, h) = (points(&l, o, &square, pose, 0.0), points(&top, o, &square, pose, 0.0));
            contained(&p, &h, &format!("box θ {theta} d {d}"));
            let q = deepest(&p);
            assert_relative_eq!(q.gap, -d, epsilon = 1e-12);
            assert_relative_eq!(q.gap, deepest(&h).gap, epsilon = 1e-12);
            assert_eq!(q.normal, [0.0, 1.0]);
            if d < 0.2 * theta.cos() {
                // Not yet wholly inside: the same points, every vertex below the face.
                assert_same(&p, &h, &format!("box θ {theta} d {d}"));
            }
        }
        // The capsule standing upright d into the inner face (its axis at x = 1.1 − d).
        let rot = std::f64::consts::FRAC_PI_2 + theta;
        for d in [0.05, 0.15, 0.3] {
            let x = 1.0 + 0.1 - d + 0.2 * theta.sin().abs();
            let pose = Pose::new(x, 1.5, rot);
            let (p, h) =
                (points(&l, o, &capsule, pose, 0.0), points(&inner, o, &capsule, pose, 0.0));
            assert_same(&p, &h, &format!("capsule θ {theta} d {d}"));
            let q = deepest(&p);
            assert_relative_eq!(q.gap, -d, epsilon = 1e-12);
            assert_relative_eq!(q.normal[0], 1.0, epsilon = 1e-12);
        }
    }
}

/// A tilted box pushed 1 mm at a time from 5 mm outside a square profile's bottom face to
/// wholly inside it, and into the L's top face: a point at every step, its deepest gap −(depth)
/// to 1e-12, until the way out through the square's right face is the shorter (0.418 m, from
/// the box's leftmost corner), whose depth it keeps from there on: no jump, and no step
/// without a point.
#[test]
fn a_box_sinking_into_a_profile_keeps_a_point_whose_gap_falls_with_its_depth() {
    let o = Pose::default();
    let square = rect(0.2, 0.2);
    let theta = 0.2f64;
    let low = 0.1 * (theta.cos() + theta.sin().abs());
    let (square_profile, _) = square_profile_and_polygon();
    // (profile, the box's x, the face's height, whether it sinks upwards, the side's depth).
    let cases = [
        (square_profile, 0.2, -0.5, true, 0.5 - (0.2 - low)),
        (l_profile(), 1.5, 1.0, false, f64::INFINITY),
    ];
    for (profile, x, face, upwards, side) in cases {
        let mut previous: Option<f64> = None;
        for i in 0..=480 {
            let depth = -0.005 + 1e-3 * i as f64;
            let y = if upwards { face - low + depth } else { face + low - depth };
            let p = points(&profile, o, &square, Pose::new(x, y, theta), 0.01);
            assert!(!p.is_empty(), "no point at depth {depth}");
            let gap = deepest(&p).gap;
            assert_relative_eq!(gap, -depth.min(side), epsilon = 1e-12);
            if let Some(g) = previous {
                assert!(gap <= g + 1e-12 && gap >= g - 1e-3 - 1e-12, "{depth}: {gap} after {g}");
            }
            previous = Some(gap);
        }
    }
}

/// The points of a box and a capsule deep in the L (seeded poses in its lower arm, by its
/// concave corner and across its faces, both bodies moving): each gap changes at the rate of
/// the normal relative velocity of its two material points, by central differences, and each
/// id is below `max_points`.
#[test]
fn deep_points_change_at_the_rate_of_the_normal_relative_velocity() {
    let l = l_profile();
    let shapes = [rect(0.3, 0.2), Shape::Capsule { a: [-0.2, 0.0], b: [0.15, 0.05], radius: 0.06 }];
    let advance = |p: Pose, v: [f64; 3], t: f64| {
        Pose::new(p.x + v[0] * t, p.y + v[1] * t, p.theta + v[2] * t)
    };
    let velocity = |p: Pose, v: [f64; 3], at: [f64; 2]| {
        [v[0] - v[2] * (at[1] - p.y), v[1] + v[2] * (at[0] - p.x)]
    };
    let mut rng = SplitMix64::new(31);
    let h = 1e-6;
    let (mut checked, mut deep) = (0, 0);
    for shape in &shapes {
        for _ in 0..300 {
            let pa = Pose::new(rng.uniform(-0.02, 0.02), rng.uniform(-0.02, 0.02), 0.0);
            let pb = Pose::new(rng.uniform(0.2, 1.8), rng.uniform(0.1, 1.3), rng.uniform(-PI, PI));
            let va = [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)];
            let vb = [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-2.0, 2.0)];
            let p = points(&l, pa, shape, pb, 0.05);
            let plus = points(&l, advance(pa, va, h), shape, advance(pb, vb, h), 1.0);
            let minus = points(&l, advance(pa, va, -h), shape, advance(pb, vb, -h), 1.0);
            for q in &p {
                assert!((q.feature as usize) < max_points(&l, shape), "{p:?}");
                let find = |s: &[ManifoldPoint]| s.iter().find(|r| r.feature == q.feature).copied();
                let (Some(gp), Some(gm)) = (find(&plus), find(&minus)) else { continue };
                let rate = (gp.gap - gm.gap) / (2.0 * h);
                let (wa, wb) = (velocity(pa, va, q.point_a), velocity(pb, vb, q.point_b));
                let n = q.normal;
                let expected = n[0] * (wb[0] - wa[0]) + n[1] * (wb[1] - wa[1]);
                assert!(
                    (rate - expected).abs() <= 1e-5 * (1.0 + expected.abs()),
                    "{shape:?} at {pb:?}: feature {} rate {rate}, expected {expected}",
                    q.feature
                );
                checked += 1;
                deep += usize::from(q.gap < -0.1);
            }
        }
    }
    assert!(checked > 300 && deep > 100, "{checked} points checked, {deep} deeper than 0.1");
}

/// What stays as it was: a box resting 1 mm into a plate 2 cm thick gets its two corners on
/// the top face and none from the bottom face behind it, upright or tilted; a box pressed
/// 1 mm into the L's concave corner touches both faces (the corner's point on its bottom face,
/// a corner on each face).
#[test]
fn a_box_on_a_thin_plate_or_in_a_concave_corner_meets_only_the_faces_it_touches() {
    let o = Pose::default();
    let square = rect(0.2, 0.2);
    let plate =
        Shape::Profile { points: vec![[-1.0, -0.02], [1.0, -0.02], [1.0, 0.0], [-1.0, 0.0]] };
    for theta in [0.0, 0.05] {
        let low = 0.1 * (f64::cos(theta) + f64::sin(theta));
        let p = points(&plate, o, &square, Pose::new(0.0, low - 1e-3, theta), 0.03);
        assert!(!p.is_empty());
        for q in &p {
            assert_eq!(q.normal, [0.0, 1.0], "{p:?}");
            assert!(q.feature >= 4 * 2 && q.feature < 4 * 3, "segment 2 is the top: {p:?}");
        }
        assert_relative_eq!(deepest(&p).gap, -1e-3, epsilon = 1e-12);
    }
    let p = sorted_by_feature(points(&l_profile(), o, &square, Pose::new(1.099, 1.099, 0.0), 0.01));
    let seen: Vec<(u32, [f64; 2])> = p.iter().map(|q| (q.feature, q.normal)).collect();
    assert_eq!(seen.len(), 3, "{p:?}");
    // Vertex 1 of the box on segment 2 (the top face y = 1), vertex 3 on segment 3 (the inner
    // face x = 1), chain point 3 (the corner) on the box's bottom face.
    assert_eq!(seen.iter().map(|s| s.0).collect::<Vec<_>>(), vec![9, 15, 6 * 4 + 3]);
    for q in &p {
        assert_relative_eq!(q.gap, -1e-3, epsilon = 1e-12);
    }
    assert_relative_eq!(p[1].normal[0], 1.0, epsilon = 1e-12);
    assert_relative_eq!(p[2].normal[1], 1.0, epsilon = 1e-12);
}

/// A box and a capsule sunk sideways into the tip of a lobe of the sampled cam (0.36 from its
/// centre at sample 0), across many segments much shorter than themselves: the tip sample
/// against the box's face or the capsule's side, the depth to 1e-12 and the normal out of the
/// cam, as a face of the convex solid there would give; before, the box past its middle got no
/// point.
#[test]
fn shapes_sunk_into_a_cam_lobe_are_pushed_out_through_its_tip() {
    let cam = cam();
    let o = Pose::default();
    let square = rect(0.2, 0.2);
    let capsule = Shape::Capsule { a: [0.0, -0.1], b: [0.0, 0.1], radius: 0.05 };
    for d in [0.005, 0.05, 0.12, 0.19] {
        let p = points(&square, Pose::new(0.36 + 0.1 - d, 0.0, 0.0), &cam, o, 0.0);
        let q = deepest(&p);
        assert_relative_eq!(q.gap, -d, epsilon = 1e-12);
        assert_eq!(q.normal, [-1.0, 0.0]);
        assert_relative_eq!(q.point_b[0], 0.36, epsilon = 1e-12);
        // Every point pushes the box out of the cam (its corners on the lobe's flanks too).
        let out = |r: &ManifoldPoint| r.normal[0] * r.point_b[0] + r.normal[1] * r.point_b[1];
        assert!(p.iter().all(|r| out(r) < 0.0), "{p:?}");
    }
    // The capsule's ends inside the cam (from 0.06 on).
    for d in [0.09, 0.11, 0.15] {
        let p = points(&capsule, Pose::new(0.36 + 0.05 - d, 0.0, 0.0), &cam, o, 0.0);
        let q = deepest(&p);
        assert_relative_eq!(q.gap, -d, epsilon = 1e-12);
        assert_eq!(q.normal, [-1.0, 0.0]);
    }
}
