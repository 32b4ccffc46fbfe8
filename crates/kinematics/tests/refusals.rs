//! What contact detection and shape validation refuse, and how they name it: unsupported
//! pairs, bad margins, invalid shapes with the number at fault, half-plane normals that do
//! not normalise, and poses too far apart or not finite, which give no point.

use std::f64::consts::PI;

use approx::assert_relative_eq;
use moreau_kinematics::{KinematicsError, Pose, Shape, collide, max_points};

mod common;
use common::{cam, disk, floor, points, rect, zigzag};

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
    // A point against a shape with an inside, or a disk against a polyline, is a contact: the
    // point at the origin is 0.1 inside the 0.4 × 0.2 box (its nearest faces are the long
    // ones), on the floor's boundary and on the unit disk centred at (0, −1).
    for (other, gap) in [(rect(0.4, 0.2), -0.1), (floor(), 0.0), (disk(0.0, -1.0, 1.0), 0.0)] {
        let p = points(&point, o, &other, o, 0.01);
        assert_eq!(p.len(), 1, "{other:?}");
        assert_relative_eq!(p[0].gap, gap, epsilon = 1e-15);
    }
    // Inside the cam r(ψ) = 0.3 + 0.06 cos 3ψ, nearest to its three dents of radius 0.24,
    // sampled points at ψ = π/3, π, 5π/3: it meets the first, at 0.24 (cos 60°, sin 60°).
    let p = points(&point, o, &cam(), o, 0.01);
    assert_eq!(p.len(), 1);
    assert_relative_eq!(p[0].gap, -0.24, epsilon = 1e-12);
    assert_relative_eq!(p[0].point_b[0], 0.12, epsilon = 1e-12);
    assert_relative_eq!(p[0].point_b[1], 0.12 * 3f64.sqrt(), epsilon = 1e-12);
    // A disk of radius 0.1 at the origin sits in the zigzag's concave corner at (0, −0.05)
    // and touches both its segments there: the one from (−0.3, 0.15), at distance
    // 0.015/√0.13 from the origin, and the one to (0.2, 0.1), at distance 0.04.
    let p = points(&disk(0.0, 0.0, 0.1), o, &zigzag(), o, 0.01);
    let mut gaps: Vec<f64> = p.iter().map(|q| q.gap).collect();
    gaps.sort_by(f64::total_cmp);
    assert_eq!(gaps.len(), 2, "{p:?}");
    assert_relative_eq!(gaps[0], 0.04 - 0.1, epsilon = 1e-12);
    assert_relative_eq!(gaps[1], 0.015 / 0.13f64.sqrt() - 0.1, epsilon = 1e-12);
    let empty = Shape::Polygon { vertices: vec![] };
    assert!(matches!(
        collide(&empty, &o, &floor(), &o, 0.0, &mut out),
        Err(KinematicsError::InvalidShape {
            shape: "polygon",
            problem: "too few points",
            value: Some(0.0),
            ..
        })
    ));
    // `collide` names a bad normal as validation does.
    for normal in [[0.0, 0.0], [f64::NAN, 1.0], [1e-170, 0.0]] {
        let plane = Shape::HalfPlane { point: [0.0, 0.0], normal };
        let err = collide(&disk(0.0, 0.0, 1.0), &o, &plane, &o, 0.0, &mut out).unwrap_err();
        assert_eq!(err.to_string(), plane.validate().unwrap_err().to_string());
    }
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
    // The number at fault and the message that names it.
    let value = |s: Shape| match s.validate() {
        Err(e @ KinematicsError::InvalidShape { value, .. }) => (value, e.to_string()),
        other => panic!("expected an invalid shape, got {other:?}"),
    };
    assert_eq!(problem(disk(0.0, 0.0, -1.0)).0, "negative radius");
    assert_eq!(
        value(disk(0.0, 0.0, -0.1)),
        (Some(-0.1), "invalid disk: negative radius: -0.1".into())
    );
    let (v, message) = value(disk(0.0, 0.0, f64::NAN));
    assert!(v.unwrap().is_nan() && message == "invalid disk: non-finite radius: NaN", "{message}");
    assert_eq!(problem(disk(f64::NAN, 0.0, 1.0)).0, "non-finite centre coordinate");
    assert_eq!(value(disk(0.0, f64::INFINITY, 1.0)).0, Some(f64::INFINITY));
    let capsule = Shape::Capsule { a: [0.0, 0.0], b: [1.0, f64::NEG_INFINITY], radius: 0.1 };
    assert_eq!(problem(capsule.clone()), ("non-finite end coordinate", Some(1)));
    assert_eq!(value(capsule).1, "invalid capsule: non-finite end coordinate: -inf (at index 1)");
    let capsule = Shape::Capsule { a: [0.0, 0.0], b: [1.0, 0.0], radius: -2.5 };
    assert_eq!(value(capsule).0, Some(-2.5));
    let polyline = Shape::Polyline { points: vec![[0.0, 0.0], [1.0, 0.0], [2.0, f64::NAN]] };
    assert_eq!(problem(polyline.clone()), ("non-finite coordinate", Some(2)));
    assert!(value(polyline).0.unwrap().is_nan());
    let hp = Shape::HalfPlane { point: [f64::INFINITY, 0.0], normal: [0.0, 1.0] };
    assert_eq!(problem(hp), ("non-finite point coordinate", None));
    let hp = Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, f64::NAN] };
    assert_eq!(problem(hp), ("non-finite normal coordinate", None));
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
    // The pentagram turns twice round.
    let star = Shape::Polygon { vertices: star };
    assert_eq!(problem(star.clone()).0, "winds round more than once, turns");
    assert_relative_eq!(value(star).0.unwrap(), 2.0, epsilon = 1e-12);
    let pair = Shape::Polygon { vertices: vec![[0.0, 0.0], [1.0, 0.0]] };
    assert_eq!(problem(pair.clone()).0, "too few points");
    assert_eq!(value(pair), (Some(2.0), "invalid polygon: too few points: 2".into()));
    let cap = Shape::Capsule { a: [1.0, 1.0], b: [1.0, 1.0], radius: 0.1 };
    assert_eq!(problem(cap), ("its two ends coincide (a disk has one centre)", None));
    let hp = Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, 0.0] };
    assert_eq!(value(hp.clone()).0, None);
    assert_eq!(problem(hp).0, "zero normal");
    let line = Shape::Polyline { points: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.0]] };
    assert_eq!(problem(line), ("two consecutive points coincide", Some(1)));
    let bow = Shape::Profile {
        points: vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.2], [-0.5, 0.5]],
    };
    assert_eq!(problem(bow).0, "the contour crosses itself");
    // The clockwise unit right triangle: signed area −1/2.
    let clockwise = Shape::Profile { points: vec![[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]] };
    assert_eq!(
        problem(clockwise.clone()).0,
        "points run clockwise or enclose no area, signed area"
    );
    assert_eq!(value(clockwise).0, Some(-0.5));
    assert!(
        rect(1.0, 2.0).validate().is_ok()
            && zigzag().validate().is_ok()
            && cam().validate().is_ok()
    );
    assert_eq!(
        Shape::profile_polar(|_| 1.0, 2),
        Err(KinematicsError::InvalidOption { name: "samples", value: 2.0 })
    );
    // More samples than memory holds, where collecting them aborted on a capacity overflow.
    assert_eq!(
        Shape::profile_polar(|_| 1.0, usize::MAX),
        Err(KinematicsError::InvalidOption { name: "samples", value: usize::MAX as f64 })
    );
    // A curve through one point samples coincident points.
    assert_eq!(
        Shape::profile_from_curve(|_| [0.5, 0.5], 8),
        Err(KinematicsError::InvalidShape {
            shape: "profile",
            problem: "two consecutive points coincide",
            value: None,
            index: Some(0)
        })
    );
    // Eight samples of the unit circle: the regular octagon of area 2√2.
    let octagon = Shape::profile_polar(|_| 1.0, 8).unwrap();
    assert_relative_eq!(octagon.area(), 2.0 * 2f64.sqrt(), epsilon = 1e-14);
    // A curve run clockwise is turned counter-clockwise.
    let cw =
        Shape::profile_from_curve(|s| [(2.0 * PI * s).cos(), -(2.0 * PI * s).sin()], 32).unwrap();
    assert!(cw.area() > 0.0);
}

#[test]
fn half_plane_normal_of_any_usable_length_gives_the_unit_normal_and_others_are_refused() {
    // A disk of radius 0.5 centred at (1, 0) against the half-plane x <= 0: gap 0.5, normal
    // (-1, 0) from the disk to the plane, whatever the length of the declared normal.
    let d = disk(0.0, 0.0, 0.5);
    let at = Pose::new(1.0, 0.0, 0.0);
    for length in [1.0, 1e-150, 1e150] {
        let plane = Shape::HalfPlane { point: [0.0, 0.0], normal: [length, 0.0] };
        assert!(plane.validate().is_ok());
        let p = points(&d, at, &plane, Pose::default(), 1.0);
        assert_eq!(p.len(), 1);
        assert_relative_eq!(p[0].gap, 0.5, epsilon = 1e-15);
        assert_eq!(p[0].normal, [-1.0, 0.0]);
    }
    // The normal (3, 4): the disk's centre is 3/5 from the boundary line, the gap 0.1.
    let plane = Shape::HalfPlane { point: [0.0, 0.0], normal: [3.0, 4.0] };
    let p = points(&d, at, &plane, Pose::default(), 1.0);
    assert_relative_eq!(p[0].gap, 0.1, epsilon = 1e-15);
    assert_relative_eq!(p[0].normal[0], -0.6, epsilon = 1e-15);
    assert_relative_eq!(p[0].normal[1], -0.8, epsilon = 1e-15);
    // Normals whose squared length underflows or overflows normalised to nothing, a
    // non-unit vector or zero (the disk 0.5 inside, normal (0, 0)): refused by validation and
    // by `collide` alike.
    for normal in [[1e-200, 0.0], [1e-160, 1e-160], [1e-320, 0.0], [1e200, 0.0], [1e200, 1e200]] {
        let plane = Shape::HalfPlane { point: [0.0, 0.0], normal };
        let problem = match plane.validate() {
            Err(KinematicsError::InvalidShape { shape: "half_plane", problem, value, .. }) => {
                // The error names |n|, the length outside about 1.5e-154..1.3e154.
                assert_eq!(value, Some(normal[0].hypot(normal[1])), "{normal:?}");
                problem
            }
            other => panic!("normal {normal:?}: expected an invalid half-plane, got {other:?}"),
        };
        assert!(problem.starts_with("normal too small or too large"), "{problem}");
        let mut out = Vec::new();
        assert!(matches!(
            collide(&d, &at, &plane, &Pose::default(), 1.0, &mut out),
            Err(KinematicsError::InvalidShape { shape: "half_plane", problem: p, .. }) if p == problem
        ));
        assert!(out.is_empty());
    }
}

#[test]
fn shapes_too_far_apart_to_square_their_distance_give_no_point() {
    // At 1e160 the squared distance overflows f64: a disk far from a box gave a point of gap
    // −∞ and NaN normal at any margin, and two far disks one of gap +∞ and normal (0, 0) at an
    // infinite margin. Such points, and those of non-finite poses, are dropped.
    let far = Pose::new(1e160, 7e159, 0.3);
    let o = Pose::default();
    let square = rect(1.0, 1.0);
    let pairs = [
        (disk(0.0, 0.0, 0.5), square.clone()),
        (square.clone(), disk(0.0, 0.0, 0.5)),
        (square.clone(), square.clone()),
        (disk(0.0, 0.0, 0.5), disk(0.0, 0.0, 0.0)),
        (Shape::Capsule { a: [0.0, 0.0], b: [1.0, 0.0], radius: 0.2 }, square.clone()),
        (zigzag(), disk(0.0, 0.0, 0.5)),
        (cam(), Shape::Capsule { a: [0.0, 0.0], b: [1.0, 0.0], radius: 0.0 }),
    ];
    for (a, b) in &pairs {
        for margin in [0.0, 1.0, 1e300, f64::INFINITY] {
            for pose in [far, Pose::new(f64::NAN, 0.0, 0.0), Pose::new(0.0, f64::INFINITY, 0.0)] {
                let p = points(a, o, b, pose, margin);
                assert!(
                    p.is_empty(),
                    "{} on {} at {pose:?}, margin {margin}: {p:?}",
                    a.name(),
                    b.name()
                );
            }
        }
        // Near, with an infinite margin, the same pair gives its points, all finite.
        let p = points(a, o, b, Pose::new(0.3, 0.2, 0.3), f64::INFINITY);
        assert!(!p.is_empty() && p.iter().all(|q| q.gap.is_finite()), "{p:?}");
    }
}

#[test]
fn a_capsule_axis_or_chain_segment_too_short_to_measure_is_refused_where_it_lost_every_point() {
    // A capsule of radius 0.1 whose ends are 1e-170 apart, its axis at height 0.05, against a
    // disk of radius 0.5 centred at (0, 0.5): they overlap by 0.15. |b − a|² underflows to 0,
    // and the contact came back with no point.
    let short = Shape::Capsule { a: [0.0, 0.0], b: [1e-170, 0.0], radius: 0.1 };
    let round = disk(0.0, 0.0, 0.5);
    let err = short.validate().unwrap_err();
    let KinematicsError::InvalidShape { shape, problem, value, index } = err.clone() else {
        panic!("{err:?}")
    };
    assert_eq!((shape, index), ("capsule", None));
    assert!(problem.starts_with("axis too short or too long to measure"), "{problem}");
    assert_eq!(value, Some(1e-170));
    let mut out = Vec::new();
    let refused =
        collide(&short, &Pose::new(0.0, 0.05, 0.0), &round, &Pose::default(), 0.1, &mut out);
    assert_eq!(refused, Err(err));
    assert!(out.is_empty());
    // An axis of 1e-150, whose square is a normal f64, is measured: the overlap of 0.15.
    let measured = Shape::Capsule { a: [0.0, 0.0], b: [1e-150, 0.0], radius: 0.1 };
    assert!(measured.validate().is_ok());
    let p = points(&measured, Pose::new(0.0, 0.05, 0.0), &round, Pose::new(0.0, 0.5, 0.0), 0.1);
    assert_eq!(p.len(), 1);
    assert_relative_eq!(p[0].gap, -0.15, epsilon = 1e-15);
    // A polyline along y = 0 with a segment of 1e-170 among segments of 1: the disk of radius
    // 0.5 at height 0.45 overlapping it by 0.05 got no point from any segment.
    let floor =
        Shape::Polyline { points: vec![[-1.0, 0.0], [0.0, 0.0], [1e-170, 0.0], [1.0, 0.0]] };
    assert_eq!(
        floor.validate().map_err(|e| match e {
            KinematicsError::InvalidShape { problem, value, index, .. } =>
                (problem.split(' ').take(2).collect::<Vec<_>>().join(" "), value, index),
            other => panic!("{other:?}"),
        }),
        Err(("segment too".to_string(), Some(1e-170), Some(1)))
    );
    // The same chain with that segment 1e-150 long is measured: gap −0.05.
    let fine = Shape::Polyline { points: vec![[-1.0, 0.0], [0.0, 0.0], [1e-150, 0.0], [1.0, 0.0]] };
    assert!(fine.validate().is_ok());
    let p = points(&round, Pose::new(0.0, 0.45, 0.0), &fine, Pose::default(), 0.1);
    assert!(!p.is_empty());
    assert!(p.iter().all(|p| (p.gap + 0.05).abs() < 1e-15), "{p:?}");
    // A profile's edge and a capsule far too long (1e160 m) are refused alike.
    let long = Shape::Capsule { a: [-1e160, 0.0], b: [1e160, 0.0], radius: 0.1 };
    assert!(
        matches!(long.validate(), Err(KinematicsError::InvalidShape { value: Some(v), .. }) if v == 2e160)
    );
}
