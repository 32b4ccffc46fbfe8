//! Contacts with chains (polylines and profiles) and segments: corners, a sampled cam against
//! a flat follower, a floor and a roller, a convex profile against the same polygon, and
//! segments standing square to a face.

use std::f64::consts::PI;

use approx::assert_relative_eq;
use moreau_kinematics::{ManifoldPoint, Pose, Shape, SplitMix64};

mod common;
use common::{disk, floor, points, rect, sorted_by_feature};

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
