//! Shapes and contact detection: closed-form gaps, the rate of the gap against the relative
//! velocity of the contact points, persistent feature ids, resting manifolds, validation,
//! the broad phase against brute force, and mass properties.

use std::f64::consts::PI;

use approx::assert_relative_eq;
use moreau_kinematics::{
    Aabb, BroadPhase, KinematicsError, ManifoldPoint, Placement, Pose, Shape, SplitMix64, collide,
    collide_placed, max_points,
};

fn points(a: &Shape, pa: Pose, b: &Shape, pb: Pose, margin: f64) -> Vec<ManifoldPoint> {
    let mut out = Vec::new();
    collide(a, &pa, b, &pb, margin, &mut out).expect("supported pair");
    out
}

fn disk(x: f64, y: f64, r: f64) -> Shape {
    Shape::Disk { center: [x, y], radius: r }
}

fn rect(w: f64, h: f64) -> Shape {
    let (a, b) = (w / 2.0, h / 2.0);
    Shape::Polygon { vertices: vec![[-a, -b], [a, -b], [a, b], [-a, b]] }
}

fn floor() -> Shape {
    Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, 1.0] }
}

fn sorted_by_feature(mut p: Vec<ManifoldPoint>) -> Vec<ManifoldPoint> {
    p.sort_by_key(|q| q.feature);
    p
}

/// A non-convex cam: r(ψ) = 0.3 + 0.06 cos 3ψ, sampled at 96 points.
fn cam() -> Shape {
    Shape::profile_polar(|psi| 0.3 + 0.06 * (3.0 * psi).cos(), 96).expect("valid cam")
}

/// A zigzag guide with concave and convex corners.
fn zigzag() -> Shape {
    Shape::Polyline {
        points: vec![[-0.6, 0.0], [-0.3, 0.15], [0.0, -0.05], [0.2, 0.1], [0.45, 0.0], [0.7, 0.2]],
    }
}

#[test]
fn disk_on_half_plane_gap_is_height_minus_radius() {
    // The disk's centre is offset in its body, which is turned: the gap uses the world centre.
    let d = disk(0.1, 0.0, 0.25);
    let pose = Pose::new(0.3, 0.7, PI / 2.0);
    let p = points(&d, pose, &floor(), Pose::default(), 1.0);
    assert_eq!(p.len(), 1);
    let centre = [0.3, 0.7 + 0.1];
    assert_relative_eq!(p[0].gap, centre[1] - 0.25, epsilon = 1e-12);
    assert_relative_eq!(p[0].normal[1], -1.0, epsilon = 1e-12);
    assert_relative_eq!(p[0].point_b[1], 0.0, epsilon = 1e-12);
    assert_relative_eq!(p[0].point_a[0], centre[0], epsilon = 1e-12);
    // Either order, turned or not; beyond the margin, nothing.
    for theta in [0.0, 0.5, 2.0] {
        let pose = Pose::new(0.3, 0.7, theta);
        let c = [0.3 + 0.1 * theta.cos(), 0.7 + 0.1 * theta.sin()];
        let p = points(&floor(), Pose::new(0.0, 0.0, 0.0), &d, pose, 1.0);
        assert_relative_eq!(p[0].gap, c[1] - 0.25, epsilon = 1e-12);
        assert_eq!(p[0].point_a, [c[0], 0.0]);
        assert!(points(&d, pose, &floor(), Pose::default(), c[1] - 0.25 - 1e-9).is_empty());
    }
}

#[test]
fn two_disks_gap_and_normal() {
    let a = disk(0.0, 0.0, 0.2);
    let b = disk(0.0, 0.0, 0.3);
    let p = points(&a, Pose::new(0.0, 0.0, 0.0), &b, Pose::new(0.3, 0.4, 1.0), 0.1);
    assert_eq!(p.len(), 1);
    assert_relative_eq!(p[0].gap, 0.5 - 0.5, epsilon = 1e-12);
    assert_relative_eq!(p[0].normal[0], 0.6, epsilon = 1e-12);
    assert_relative_eq!(p[0].normal[1], 0.8, epsilon = 1e-12);
    let p = points(&a, Pose::default(), &b, Pose::new(0.0, 0.45, 0.0), 0.1);
    assert_relative_eq!(p[0].gap, -0.05, epsilon = 1e-12);
}

#[test]
fn box_corners_on_a_tilted_half_plane() {
    // A 0.4 × 0.2 box turned by 0.3 rad above a half-plane whose normal is tilted by 0.2 rad.
    let alpha: f64 = 0.2;
    let plane = Shape::HalfPlane { point: [0.1, -0.05], normal: [-alpha.sin(), alpha.cos()] };
    let pose = Pose::new(0.2, 0.12, 0.3);
    let p = sorted_by_feature(points(&rect(0.4, 0.2), pose, &plane, Pose::default(), 0.05));
    let n = [-alpha.sin(), alpha.cos()];
    let (c, s) = (pose.theta.cos(), pose.theta.sin());
    let corners = [[-0.2, -0.1], [0.2, -0.1], [0.2, 0.1], [-0.2, 0.1]];
    let depth = |k: usize| {
        let [x, y] = corners[k];
        let w = [pose.x + c * x - s * y, pose.y + s * x + c * y];
        n[0] * (w[0] - 0.1) + n[1] * (w[1] + 0.05)
    };
    let expected: Vec<usize> = (0..4).filter(|&k| depth(k) <= 0.05).collect();
    assert!(!expected.is_empty());
    assert_eq!(p.iter().map(|q| q.feature as usize).collect::<Vec<_>>(), expected);
    for q in &p {
        assert_relative_eq!(q.gap, depth(q.feature as usize), epsilon = 1e-12);
        // A is the box: the normal points from the box into the half-plane.
        assert_relative_eq!(q.normal[0], -n[0], epsilon = 1e-12);
        assert_relative_eq!(q.normal[1], -n[1], epsilon = 1e-12);
    }
}

#[test]
fn capsule_and_disk_closed_form() {
    let cap = Shape::Capsule { a: [-0.3, 0.0], b: [0.3, 0.0], radius: 0.05 };
    let d = disk(0.0, 0.0, 0.1);
    // Beside the axis: distance to the axis; beyond an end: distance to that end.
    let p = points(&cap, Pose::default(), &d, Pose::new(0.1, 0.2, 0.0), 1.0);
    assert_relative_eq!(p[0].gap, 0.2 - 0.15, epsilon = 1e-12);
    let p = points(&d, Pose::new(0.6, 0.4, 0.0), &cap, Pose::default(), 1.0);
    assert_relative_eq!(p[0].gap, 0.5 - 0.15, epsilon = 1e-12);
    assert_relative_eq!(p[0].normal[0], -0.6, epsilon = 1e-12);
    // The capsule turned by 90° about its centre, the disk on its axis beyond the end.
    let p = points(&cap, Pose::new(0.0, 0.0, PI / 2.0), &d, Pose::new(0.0, 0.5, 0.0), 1.0);
    assert_relative_eq!(p[0].gap, 0.2 - 0.15, epsilon = 1e-12);
}

/// The pose at time t of a body moving from `pose` with velocity (v, ω).
fn advance(pose: Pose, v: [f64; 3], t: f64) -> Pose {
    Pose::new(pose.x + v[0] * t, pose.y + v[1] * t, pose.theta + v[2] * t)
}

/// The velocity of the material point `p` of a body at `pose` moving with (v, ω).
fn velocity(pose: Pose, v: [f64; 3], p: [f64; 2]) -> [f64; 2] {
    let r = [p[0] - pose.x, p[1] - pose.y];
    [v[0] - v[2] * r[1], v[1] + v[2] * r[0]]
}

/// Checks d g / dt = n · (v_B(p_B) − v_A(p_A)) by central differences at random poses near
/// contact, and that every feature is below `max_points`; returns the number of points checked.
fn check_rate(a: &Shape, b: &Shape, seed: u64, deepest: f64) -> usize {
    let mut rng = SplitMix64::new(seed);
    let bound = max_points(a, b);
    let (h, margin) = (1e-6, 0.2);
    let mut checked = 0;
    for _ in 0..60 {
        // Draw poses until the pair is near contact: some point within the margin, none deeper
        // than `deepest`. The draws are bounded; a pair that is never near contact fails below.
        let mut found = None;
        for _ in 0..400 {
            let pa =
                Pose::new(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-PI, PI));
            let pb =
                Pose::new(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-PI, PI));
            let p = points(a, pa, b, pb, margin);
            if !p.is_empty() && p.iter().all(|q| q.gap > -deepest) {
                found = Some((pa, pb, p));
                break;
            }
        }
        let Some((pa, pb, p)) = found else { continue };
        let va = [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-2.0, 2.0)];
        let vb = [rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-2.0, 2.0)];
        let plus = points(a, advance(pa, va, h), b, advance(pb, vb, h), margin + 1.0);
        let minus = points(a, advance(pa, va, -h), b, advance(pb, vb, -h), margin + 1.0);
        for q in &p {
            assert!((q.feature as usize) < bound, "feature {} >= {bound}", q.feature);
            let n = q.normal;
            assert_relative_eq!(n[0].hypot(n[1]), 1.0, epsilon = 1e-12);
            let d = [q.point_b[0] - q.point_a[0], q.point_b[1] - q.point_a[1]];
            assert_relative_eq!(d[0] * n[0] + d[1] * n[1], q.gap, epsilon = 1e-12);
            let find = |set: &[ManifoldPoint]| set.iter().find(|r| r.feature == q.feature).copied();
            let (Some(gp), Some(gm)) = (find(&plus), find(&minus)) else { continue };
            let rate = (gp.gap - gm.gap) / (2.0 * h);
            let (wa, wb) = (velocity(pa, va, q.point_a), velocity(pb, vb, q.point_b));
            let expected = n[0] * (wb[0] - wa[0]) + n[1] * (wb[1] - wa[1]);
            assert!(
                (rate - expected).abs() <= 1e-5 * (1.0 + expected.abs()),
                "{} vs {}: feature {} rate {rate} expected {expected} at {pa:?} {pb:?}",
                a.name(),
                b.name(),
                q.feature
            );
            checked += 1;
        }
    }
    checked
}

/// One pair of every supported kind of shapes, named.
fn every_pair() -> Vec<(&'static str, Shape, Shape)> {
    let tri = Shape::Polygon { vertices: vec![[-0.15, -0.1], [0.2, -0.05], [0.0, 0.2]] };
    let cap = Shape::Capsule { a: [-0.2, 0.0], b: [0.15, 0.05], radius: 0.06 };
    let seg = Shape::Capsule { a: [-0.2, 0.03], b: [0.2, -0.03], radius: 0.0 };
    let plane = Shape::HalfPlane { point: [0.0, 0.05], normal: [0.3, 1.0] };
    let d = disk(0.03, -0.02, 0.12);
    vec![
        ("disk-disk", d.clone(), disk(0.0, 0.05, 0.1)),
        ("disk-polygon", d.clone(), rect(0.3, 0.2)),
        ("polygon-disk", tri.clone(), d.clone()),
        ("disk-capsule", d.clone(), cap.clone()),
        ("disk-half_plane", d.clone(), plane.clone()),
        ("half_plane-disk", plane.clone(), d.clone()),
        ("disk-polyline", d.clone(), zigzag()),
        ("polyline-disk", zigzag(), disk(0.0, 0.0, 0.05)),
        ("disk-profile", disk(0.0, 0.0, 0.05), cam()),
        ("polygon-polygon", rect(0.3, 0.2), tri.clone()),
        ("polygon-capsule", rect(0.3, 0.2), cap.clone()),
        ("capsule-capsule", cap.clone(), seg.clone()),
        ("polygon-half_plane", rect(0.3, 0.2), plane.clone()),
        ("half_plane-capsule", plane.clone(), cap.clone()),
        ("polygon-polyline", tri.clone(), zigzag()),
        ("capsule-polyline", cap.clone(), zigzag()),
        ("profile-polygon", cam(), rect(0.3, 0.1)),
        ("capsule-profile", seg.clone(), cam()),
        ("half_plane-polyline", plane.clone(), zigzag()),
        ("profile-half_plane", cam(), plane.clone()),
    ]
}

#[test]
fn gap_rate_is_the_normal_relative_velocity_for_every_pair() {
    let pairs = every_pair();
    for (k, (name, a, b)) in pairs.iter().enumerate() {
        let checked = check_rate(a, b, 100 + k as u64, 0.05);
        assert!(checked >= 30, "{name}: only {checked} points checked");
    }
}

#[test]
fn shapes_placed_once_collide_and_bound_as_their_poses_do() {
    let mut rng = SplitMix64::new(17);
    let mut touching = 0;
    for (name, a, b) in every_pair() {
        for _ in 0..200 {
            let mut pose = || {
                let theta = if rng.below(4) == 0 { 0.0 } else { rng.uniform(-PI, PI) };
                Pose::new(rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2), theta)
            };
            let (pa, pb) = (pose(), pose());
            // The rotation as a caller that already has it would give it.
            let given = |p: &Pose| {
                let (sin, cos) = if p.theta == 0.0 { (0.0, 1.0) } else { p.theta.sin_cos() };
                Placement::with_rotation(p, cos, sin)
            };
            let expected = points(&a, pa, &b, pb, 0.1);
            touching += usize::from(!expected.is_empty());
            for (la, lb) in [(Placement::new(&pa), Placement::new(&pb)), (given(&pa), given(&pb))] {
                assert_eq!((la.pose(), lb.pose()), (pa, pb));
                let mut out = Vec::new();
                collide_placed(&a, &la, &b, &lb, 0.1, &mut out).unwrap();
                assert_eq!(out, expected, "{name}");
                assert_eq!((a.aabb_placed(&la), b.aabb_placed(&lb)), (a.aabb(&pa), b.aabb(&pb)));
            }
        }
    }
    assert!(touching > 1000, "{touching} touching placements");
}

#[test]
fn resting_box_gives_its_two_corners() {
    // On a floor.
    let p = sorted_by_feature(points(
        &rect(0.4, 0.2),
        Pose::new(0.5, 0.1 + 1e-3, 0.0),
        &floor(),
        Pose::default(),
        0.01,
    ));
    assert_eq!(p.iter().map(|q| q.feature).collect::<Vec<_>>(), vec![0, 1]);
    for q in &p {
        assert_relative_eq!(q.gap, 1e-3, epsilon = 1e-12);
    }
    assert_relative_eq!(p[0].point_a[0], 0.3, epsilon = 1e-12);
    assert_relative_eq!(p[1].point_a[0], 0.7, epsilon = 1e-12);
    // On the wider top face of another box, shifted and slightly penetrating.
    let base = rect(1.0, 0.5);
    let top = Pose::new(0.2, 0.25 + 0.1 - 2e-4, 0.0);
    let p = sorted_by_feature(points(&base, Pose::default(), &rect(0.4, 0.2), top, 0.01));
    assert_eq!(p.len(), 2);
    for q in &p {
        assert_relative_eq!(q.gap, -2e-4, epsilon = 1e-12);
        assert_relative_eq!(q.normal[1], 1.0, epsilon = 1e-12);
    }
    let xs: Vec<f64> = p.iter().map(|q| q.point_b[0]).collect();
    assert_relative_eq!(xs[0].min(xs[1]), 0.0, epsilon = 1e-12);
    assert_relative_eq!(xs[0].max(xs[1]), 0.4, epsilon = 1e-12);
    // Two equal boxes stacked exactly: two points, not four, at the shared corners.
    let p =
        points(&rect(0.4, 0.2), Pose::default(), &rect(0.4, 0.2), Pose::new(0.0, 0.2, 0.0), 0.01);
    assert_eq!(p.len(), 2);
    // A box slightly tilted on a flat profile face (a cam with a flat dwell would do the same):
    // only the lower corner when the other is out of the margin.
    let p =
        points(&rect(0.4, 0.2), Pose::new(0.5, 0.1 + 0.02, 0.2), &floor(), Pose::default(), 0.01);
    assert_eq!(p.len(), 1);
}

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
fn features_persist_while_the_contact_persists() {
    // A box sliding and rocking slightly on another keeps its corner ids.
    let base = rect(1.0, 0.5);
    let top = rect(0.4, 0.2);
    let ids = |x: f64, th: f64| {
        let mut f: Vec<u32> =
            points(&base, Pose::default(), &top, Pose::new(x, 0.35 + 1e-4, th), 0.02)
                .iter()
                .map(|q| q.feature)
                .collect();
        f.sort();
        f
    };
    let first = ids(0.0, 0.0);
    assert_eq!(first.len(), 2);
    for k in 1..20 {
        let s = k as f64 * 1e-3;
        assert_eq!(ids(s, 1e-4 * (s * 50.0).sin()), first);
    }
    // A disk rolling along one segment of a polyline keeps the segment's id.
    let road = zigzag();
    let mut seen = None;
    for k in 0..20 {
        let t = 0.3 + 0.02 * k as f64;
        // Along segment 1, from (-0.3, 0.15) to (0, -0.05), just above it.
        let (x, y) = (-0.3 + 0.3 * t, 0.15 - 0.2 * t);
        let n = [0.2 / 0.3605551275463989, 0.3 / 0.3605551275463989];
        let p = points(
            &disk(0.0, 0.0, 0.05),
            Pose::new(x + 0.051 * n[0], y + 0.051 * n[1], 0.1 * k as f64),
            &road,
            Pose::default(),
            0.005,
        );
        assert_eq!(p.len(), 1);
        assert_relative_eq!(p[0].gap, 1e-3, epsilon = 1e-12);
        assert_eq!(*seen.get_or_insert(p[0].feature), p[0].feature);
    }
    assert_eq!(seen, Some(1));
}

#[test]
fn disk_inside_a_profile_is_pushed_out_by_the_nearest_face() {
    // A square profile; the disk's centre 1 cm inside its right face.
    let square =
        Shape::Profile { points: vec![[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]] };
    let p = points(&disk(0.0, 0.0, 0.1), Pose::new(0.49, 0.1, 0.0), &square, Pose::default(), 0.0);
    assert_eq!(p.len(), 1);
    assert_relative_eq!(p[0].gap, -0.11, epsilon = 1e-12);
    assert_relative_eq!(p[0].normal[0], -1.0, epsilon = 1e-12);
    // Its gap changes at the rate of the normal relative velocity there too.
    let checked = check_rate(&disk(0.0, 0.0, 0.02), &cam(), 7, 0.2);
    assert!(checked >= 30, "{checked}");
    // Outside, the same face gives the ordinary gap.
    let p = points(&disk(0.0, 0.0, 0.1), Pose::new(0.65, 0.1, 0.0), &square, Pose::default(), 0.1);
    assert_eq!(p.len(), 1);
    assert_relative_eq!(p[0].gap, 0.05, epsilon = 1e-12);
}

#[test]
fn unsupported_pairs_and_bad_margins_are_refused() {
    let mut out = Vec::new();
    let o = Pose::default();
    let err = collide(&floor(), &o, &floor(), &o, 0.0, &mut out).unwrap_err();
    assert_eq!(err, KinematicsError::UnsupportedPair { a: "half_plane", b: "half_plane" });
    let err = collide(&zigzag(), &o, &cam(), &o, 0.0, &mut out).unwrap_err();
    assert_eq!(err, KinematicsError::UnsupportedPair { a: "polyline", b: "profile" });
    assert_eq!(max_points(&zigzag(), &cam()), 0);
    // Points, segments and polylines have no inside: two of them are refused, in either order.
    let point = disk(0.0, 0.0, 0.0);
    let segment = Shape::Capsule { a: [-1.0, 0.0], b: [1.0, 0.0], radius: 0.0 };
    for (a, b) in
        [(&point, &zigzag()), (&segment, &zigzag()), (&point, &segment), (&segment, &point)]
    {
        for (x, y) in [(a, b), (b, a)] {
            let err = collide(x, &o, y, &o, 0.01, &mut out).unwrap_err();
            assert_eq!(err, KinematicsError::NoThickness { a: x.name(), b: y.name() });
            assert!(err.to_string().contains("give one of them a radius or an area"), "{err}");
            assert_eq!(max_points(x, y), 0);
        }
    }
    // A point against a shape with an inside, or a disk against a polyline, is a contact.
    for other in [cam(), rect(0.4, 0.2), floor(), disk(0.0, -1.0, 1.0)] {
        assert!(collide(&point, &o, &other, &o, 0.01, &mut out).is_ok());
    }
    assert!(collide(&disk(0.0, 0.0, 0.1), &o, &zigzag(), &o, 0.01, &mut out).is_ok());
    let empty = Shape::Polygon { vertices: vec![] };
    assert!(matches!(
        collide(&empty, &o, &floor(), &o, 0.0, &mut out),
        Err(KinematicsError::InvalidShape { shape: "polygon", problem: "too few points", .. })
    ));
    let dot = Shape::Capsule { a: [0.0, 0.0], b: [0.0, 0.0], radius: 1.0 };
    assert!(matches!(
        collide(&disk(0.0, 0.0, 1.0), &o, &dot, &o, 0.0, &mut out),
        Err(KinematicsError::InvalidShape { shape: "capsule", .. })
    ));
    assert!(matches!(
        collide(&disk(0.0, 0.0, 1.0), &o, &floor(), &o, f64::NAN, &mut out),
        Err(KinematicsError::InvalidOption { name: "margin", .. })
    ));
}

#[test]
fn validation_names_what_is_wrong() {
    let problem = |s: Shape| match s.validate() {
        Err(KinematicsError::InvalidShape { problem, index, .. }) => (problem, index),
        other => panic!("expected an invalid shape, got {other:?}"),
    };
    assert_eq!(problem(disk(0.0, 0.0, -1.0)).0, "negative radius");
    assert_eq!(problem(disk(f64::NAN, 0.0, 1.0)).0, "non-finite centre");
    let cw = Shape::Polygon { vertices: vec![[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]] };
    assert_eq!(problem(cw), ("not strictly convex and counter-clockwise", Some(1)));
    let dent = Shape::Polygon {
        vertices: vec![[0.0, 0.0], [2.0, 0.0], [1.0, 0.2], [2.0, 1.0], [0.0, 1.0]],
    };
    assert_eq!(problem(dent).0, "not strictly convex and counter-clockwise");
    let star: Vec<[f64; 2]> = (0..5)
        .map(|k| {
            let a = 4.0 * PI * k as f64 / 5.0;
            [a.cos(), a.sin()]
        })
        .collect();
    assert_eq!(problem(Shape::Polygon { vertices: star }).0, "winds round more than once");
    assert_eq!(
        problem(Shape::Polygon { vertices: vec![[0.0, 0.0], [1.0, 0.0]] }).0,
        "too few points"
    );
    let cap = Shape::Capsule { a: [1.0, 1.0], b: [1.0, 1.0], radius: 0.1 };
    assert_eq!(problem(cap).0, "its two ends coincide (a disk has one centre)");
    let hp = Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, 0.0] };
    assert_eq!(problem(hp).0, "zero normal");
    let line = Shape::Polyline { points: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.0]] };
    assert_eq!(problem(line), ("two consecutive points coincide", Some(1)));
    let bow = Shape::Profile {
        points: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.2], [-0.5, 0.5]],
    };
    assert_eq!(problem(bow).0, "the contour crosses itself");
    let clockwise = Shape::Profile { points: vec![[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]] };
    assert_eq!(problem(clockwise).0, "points run clockwise or enclose no area");
    assert!(
        rect(1.0, 2.0).validate().is_ok()
            && zigzag().validate().is_ok()
            && cam().validate().is_ok()
    );
    assert!(matches!(
        Shape::profile_polar(|_| 1.0, 2),
        Err(KinematicsError::InvalidOption { name: "samples", .. })
    ));
    // A curve run clockwise is turned counter-clockwise.
    let cw =
        Shape::profile_from_curve(|s| [(2.0 * PI * s).cos(), -(2.0 * PI * s).sin()], 32).unwrap();
    assert!(cw.area() > 0.0);
}

#[test]
fn mass_properties_closed_forms() {
    // A 0.4 × 0.2 box about its centre, then offset by (1, 2).
    let (w, h) = (0.4, 0.2);
    assert_relative_eq!(rect(w, h).area(), w * h, epsilon = 1e-15);
    assert_relative_eq!(
        rect(w, h).unit_inertia().unwrap(),
        (w * w + h * h) / 12.0,
        epsilon = 1e-15
    );
    let shifted = Shape::Polygon { vertices: vec![[0.8, 1.9], [1.2, 1.9], [1.2, 2.1], [0.8, 2.1]] };
    let c = shifted.centroid();
    assert_relative_eq!(c[0], 1.0, epsilon = 1e-12);
    assert_relative_eq!(c[1], 2.0, epsilon = 1e-12);
    assert_relative_eq!(
        shifted.unit_inertia().unwrap(),
        (w * w + h * h) / 12.0 + 5.0,
        epsilon = 1e-12
    );
    // A disk: r²/2 plus the parallel-axis term.
    let d = disk(0.3, -0.4, 0.5);
    assert_relative_eq!(d.area(), PI * 0.25, epsilon = 1e-15);
    assert_relative_eq!(d.unit_inertia().unwrap(), 0.125 + 0.25, epsilon = 1e-15);
    // A right triangle with legs a, b at the origin: centroid (a/3, b/3), J_O = ab(a² + b²)/12.
    let (a, b) = (0.6, 0.3);
    let tri = Shape::Polygon { vertices: vec![[0.0, 0.0], [a, 0.0], [0.0, b]] };
    assert_relative_eq!(tri.area(), a * b / 2.0, epsilon = 1e-15);
    assert_relative_eq!(tri.centroid()[0], a / 3.0, epsilon = 1e-15);
    assert_relative_eq!(tri.centroid()[1], b / 3.0, epsilon = 1e-15);
    assert_relative_eq!(tri.unit_inertia().unwrap(), (a * a + b * b) / 6.0, epsilon = 1e-15);
    // A capsule of radius 0 is a rod (L²/12); of length → 0 it tends to a disk.
    let rod = Shape::Capsule { a: [-0.5, 0.0], b: [0.5, 0.0], radius: 0.0 };
    assert_relative_eq!(rod.unit_inertia().unwrap(), 1.0 / 12.0, epsilon = 1e-15);
    let short = Shape::Capsule { a: [-1e-9, 0.0], b: [1e-9, 0.0], radius: 0.2 };
    assert_relative_eq!(short.unit_inertia().unwrap(), 0.02, epsilon = 1e-8);
    // The capsule against a fine polygon approximation of the same outline.
    let (l, r) = (0.6, 0.1);
    let cap = Shape::Capsule { a: [-l / 2.0, 0.0], b: [l / 2.0, 0.0], radius: r };
    let mut outline = Vec::new();
    for k in 0..=2000 {
        let t = -PI / 2.0 + PI * k as f64 / 2000.0;
        outline.push([l / 2.0 + r * t.cos(), r * t.sin()]);
    }
    for k in 0..=2000 {
        let t = PI / 2.0 + PI * k as f64 / 2000.0;
        outline.push([-l / 2.0 + r * t.cos(), r * t.sin()]);
    }
    let fine = Shape::Profile { points: outline };
    assert_relative_eq!(cap.area(), fine.area(), max_relative = 1e-6);
    assert_relative_eq!(
        cap.unit_inertia().unwrap(),
        fine.unit_inertia().unwrap(),
        max_relative = 1e-6
    );
    // No inertia for shapes without area.
    assert!(matches!(floor().unit_inertia(), Err(KinematicsError::NoMassProperties { .. })));
    assert!(matches!(zigzag().unit_inertia(), Err(KinematicsError::NoMassProperties { .. })));
}

#[test]
fn bounding_boxes() {
    let b = rect(0.4, 0.2).aabb(&Pose::new(1.0, 2.0, PI / 2.0));
    assert_relative_eq!(b.min[0], 0.9, epsilon = 1e-12);
    assert_relative_eq!(b.max[1], 2.2, epsilon = 1e-12);
    let f = floor().aabb(&Pose::new(0.0, -1.0, 0.0));
    assert_eq!((f.max[1], f.min[1], f.max[0]), (-1.0, f64::NEG_INFINITY, f64::INFINITY));
    let tilted = floor().aabb(&Pose::new(0.0, -1.0, 0.1));
    assert!(!tilted.is_finite() && tilted.max[1] == f64::INFINITY);
}

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

#[test]
fn shapes_round_trip_through_serde() {
    let json = serde_json::to_string(&rect(1.0, 1.0)).unwrap();
    assert!(json.starts_with(r#"{"type":"polygon""#));
    let back: Shape =
        serde_json::from_str(r#"{"type":"half_plane","point":[0,0],"normal":[0,1]}"#).unwrap();
    assert_eq!(back, floor());
}

/// parry2d-f64's contact of two shapes given in its own types (shape 1 first).
fn parry_contact(
    s1: &dyn parry2d_f64::shape::Shape,
    p1: Pose,
    s2: &dyn parry2d_f64::shape::Shape,
    p2: Pose,
) -> parry2d_f64::query::Contact {
    use parry2d_f64::math::{Pose as P, Vector as V};
    let pose = |p: Pose| P::new(V::new(p.x, p.y), p.theta);
    parry2d_f64::query::contact(&pose(p1), s1, &pose(p2), s2, 10.0)
        .expect("supported by parry")
        .expect("within the prediction")
}

#[test]
fn smooth_pairs_and_polygon_distances_agree_with_parry() {
    use parry2d_f64::math::Vector as V;
    use parry2d_f64::shape::{Ball, Capsule, ConvexPolygon, HalfSpace};
    let mut rng = SplitMix64::new(9);
    let verts = [[-0.2, -0.1], [0.25, -0.12], [0.3, 0.1], [-0.1, 0.2]];
    let poly = Shape::Polygon { vertices: verts.to_vec() };
    let parry_poly =
        ConvexPolygon::from_convex_polyline(verts.iter().map(|v| V::new(v[0], v[1])).collect())
            .unwrap();
    let cap = Shape::Capsule { a: [-0.2, 0.05], b: [0.2, -0.05], radius: 0.07 };
    let parry_cap = Capsule::new(V::new(-0.2, 0.05), V::new(0.2, -0.05), 0.07);
    // A half-plane through the body origin, as parry's half-space is.
    let plane = Shape::HalfPlane { point: [0.0, 0.0], normal: [0.6, 0.8] };
    let parry_plane = HalfSpace::new(V::new(0.6, 0.8));
    let d = disk(0.0, 0.0, 0.1);
    let ball = Ball::new(0.1);
    let mut compared = 0;
    for _ in 0..200 {
        let pa = Pose::new(rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4), rng.uniform(-PI, PI));
        let pb = Pose::new(rng.uniform(-0.4, 0.4), rng.uniform(-0.4, 0.4), rng.uniform(-PI, PI));
        let cases: [(
            &Shape,
            &Shape,
            &dyn parry2d_f64::shape::Shape,
            &dyn parry2d_f64::shape::Shape,
        ); 4] = [
            (&d, &d, &ball, &ball),
            (&cap, &d, &parry_cap, &ball),
            (&plane, &d, &parry_plane, &ball),
            (&poly, &d, &parry_poly, &ball),
        ];
        for (a, b, s1, s2) in cases {
            let ours = points(a, pa, b, pb, 10.0);
            let theirs = parry_contact(s1, pa, s2, pb);
            assert_eq!(ours.len(), 1);
            assert_relative_eq!(ours[0].gap, theirs.dist, epsilon = 1e-9);
            if theirs.dist > 1e-6 {
                assert_relative_eq!(ours[0].normal[0], theirs.normal1.x, epsilon = 1e-9);
                assert_relative_eq!(ours[0].normal[1], theirs.normal1.y, epsilon = 1e-9);
                assert_relative_eq!(ours[0].point_b[0], theirs.point2.x, epsilon = 1e-9);
            }
            compared += 1;
        }
        // Two polygons: the smallest gap of our points is parry's signed distance, apart (two
        // faces, two corners or a corner and a face) or overlapping by a little (the least
        // penetration; deep overlaps, which a time-stepper never reaches, may list deeper
        // vertex points).
        let ours = points(&poly, pa, &poly, pb, 10.0);
        let theirs = parry_contact(&parry_poly, pa, &parry_poly, pb);
        let smallest = ours.iter().map(|p| p.gap).fold(f64::INFINITY, f64::min);
        if theirs.dist > -0.02 {
            assert_relative_eq!(smallest, theirs.dist, epsilon = 1e-9);
            compared += 1;
        }
    }
    assert!(compared > 850, "{compared}");
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
