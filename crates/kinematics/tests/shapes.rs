//! Shapes and contact detection: closed-form gaps, the rate of the gap against the relative
//! velocity of the contact points, persistent feature ids, resting manifolds, agreement with
//! parry, scaling and mass properties.

use std::f64::consts::PI;

use approx::assert_relative_eq;
use moreau_kinematics::{
    KinematicsError, ManifoldPoint, Placement, Pose, Shape, SplitMix64, collide_placed, max_points,
};

mod common;
use common::{cam, disk, floor, points, rect, sorted_by_feature, zigzag};

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
    // Centres (1, 2) and (4, 6), 5 apart, radii 0.2 and 0.3: gap 4.5, normal (0.6, 0.8), the
    // surface points p_A = c_A + r_A n and p_B = c_B − r_B n, with g_N = (p_B − p_A) · n.
    let p = points(&a, Pose::new(1.0, 2.0, 0.7), &b, Pose::new(4.0, 6.0, -1.1), 5.0);
    assert_eq!(p.len(), 1);
    assert_relative_eq!(p[0].gap, 4.5, epsilon = 1e-12);
    assert_relative_eq!(p[0].point_a[0], 1.12, epsilon = 1e-12);
    assert_relative_eq!(p[0].point_a[1], 2.16, epsilon = 1e-12);
    assert_relative_eq!(p[0].point_b[0], 3.82, epsilon = 1e-12);
    assert_relative_eq!(p[0].point_b[1], 5.76, epsilon = 1e-12);
    // Beyond the margin, nothing.
    assert!(points(&a, Pose::new(1.0, 2.0, 0.7), &b, Pose::new(4.0, 6.0, 0.0), 4.49).is_empty());
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
fn scaling_multiplies_areas_and_unit_inertias_by_the_square_of_the_factor() {
    let capsule = Shape::Capsule { a: [0.1, 0.0], b: [0.5, 0.3], radius: 0.05 };
    for shape in [rect(0.4, 0.2), disk(0.3, -0.1, 0.2), capsule, cam()] {
        let big = shape.scaled(2.5);
        big.validate().unwrap();
        assert_relative_eq!(big.area(), 6.25 * shape.area(), max_relative = 1e-13);
        let (i, j) = (shape.unit_inertia().unwrap(), big.unit_inertia().unwrap());
        assert_relative_eq!(j, 6.25 * i, max_relative = 1e-13);
        let (c, d) = (shape.centroid(), big.centroid());
        assert_relative_eq!(d[0], 2.5 * c[0], max_relative = 1e-13);
        assert_relative_eq!(d[1], 2.5 * c[1], max_relative = 1e-13);
    }
    // A negative factor makes a negative radius, which validation names.
    assert_eq!(
        disk(0.0, 0.0, 0.2).scaled(-1.0).validate(),
        Err(KinematicsError::InvalidShape {
            shape: "disk",
            problem: "negative radius",
            value: Some(-0.2),
            index: None
        })
    );
    let floor = Shape::HalfPlane { point: [0.0, -1.0], normal: [0.0, 3.0] };
    assert_eq!(floor.scaled(2.0), Shape::HalfPlane { point: [0.0, -2.0], normal: [0.0, 3.0] });
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
