//! Capsules, segments and boxes overlapping a profile by a few centimetres near its convex
//! corners and beside faces their core does not cross, where the core has entered the solid:
//! the deepest gap against the square profile is that of the same square declared as a polygon,
//! and against the L-shaped profile that of the L as the union of two polygons.

use approx::assert_relative_eq;
use moreau_kinematics::{ManifoldPoint, Pose, Shape, SplitMix64};

mod common;
use common::{points, rect};

/// The least gap of a set of points, +∞ for none.
fn deepest_gap(p: &[ManifoldPoint]) -> f64 {
    p.iter().map(|q| q.gap).fold(f64::INFINITY, f64::min)
}

/// The shape families: segments (capsules of radius 0), capsules thinner than the depth, thick
/// capsules and boxes (core radius 0), from a seeded draw.
fn shape(family: usize, rng: &mut SplitMix64) -> Shape {
    let half = rng.uniform(0.05, 0.55);
    match family {
        0 => Shape::Capsule { a: [-half, 0.0], b: [half, 0.0], radius: 0.0 },
        1 => Shape::Capsule { a: [-half, 0.0], b: [half, 0.0], radius: 0.01 },
        2 => Shape::Capsule { a: [-half, 0.0], b: [half, 0.0], radius: 0.05 },
        _ => rect(2.0 * half, 2.0 * rng.uniform(0.002, 0.2)),
    }
}

/// The square [−0.5, 0.5]² as a profile and as a polygon, against seeded shapes of the four
/// families at random poses about its corners: of those the polygon finds overlapping by at
/// most 3 cm (the separating-axis answer for a convex solid), the profile gives a point for
/// each and the same deepest gap to 1e-9. Before, a core that had entered the solid near a
/// corner was pushed out through the far face of a segment it barely crossed, or got no point
/// when the shallowest way out was a segment beside it that it does not cross.
#[test]
fn shapes_at_a_square_profiles_corners_meet_it_as_the_same_polygon_does() {
    let corners = vec![[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]];
    let profile = Shape::Profile { points: corners.clone() };
    let polygon = Shape::Polygon { vertices: corners };
    let o = Pose::default();
    let mut rng = SplitMix64::new(7);
    for family in 0..4 {
        let (mut overlapping, mut differ, mut missing) = (0, 0, 0);
        for i in 0..4000 {
            let x = shape(family, &mut rng);
            // About a corner, beside its two faces.
            let (cx, cy) = ([-0.5, 0.5][i % 2], [-0.5, 0.5][i / 2 % 2]);
            let pose = Pose::new(
                cx + rng.uniform(-0.4, 0.4),
                cy + rng.uniform(-0.4, 0.4),
                rng.uniform(0.0, 6.3),
            );
            let reference = deepest_gap(&points(&polygon, o, &x, pose, 0.0));
            if !(reference <= 0.0 && reference > -0.03) {
                continue;
            }
            overlapping += 1;
            let p = points(&profile, o, &x, pose, 0.0);
            missing += usize::from(p.is_empty());
            differ += usize::from((deepest_gap(&p) - reference).abs() > 1e-9);
        }
        assert!(overlapping > 100, "family {family}: {overlapping} overlapping poses");
        assert_eq!((differ, missing), (0, 0), "family {family} of {overlapping} poses");
    }
}

/// A box 2 mm into the square's bottom face beside its corner (0.5, −0.5), its top face almost
/// level: the polygon's two points (its top-left corner on the bottom face, 1.9 mm deep, and the
/// square's corner on its top face, 0.9 mm), not a push out of 0.206 through its left face from
/// the right face (x = 0.5), which its top face barely crosses below the corner.
#[test]
fn a_box_beside_a_corner_is_pushed_out_through_the_face_it_sinks_into() {
    let (profile, polygon) = square();
    let o = Pose::default();
    let x = Shape::Polygon {
        vertices: vec![
            [-0.1370552864086546, -0.11850895353825781],
            [0.1370552864086546, -0.11850895353825781],
            [0.1370552864086546, 0.11850895353825781],
            [-0.1370552864086546, 0.11850895353825781],
        ],
    };
    let pose = Pose::new(0.4119232027779022, -0.6357417714206008, 1.5656859894548114);
    let p = sorted_by_gap(points(&profile, o, &x, pose, 0.0));
    assert_eq!(p.len(), 2, "{p:?}");
    for (q, gap) in p.iter().zip([-0.00191734344939654, -0.00086518728302040]) {
        assert_relative_eq!(q.gap, gap, epsilon = 1e-15);
        assert!(q.normal[1] < -0.9999, "{q:?}");
    }
    assert_relative_eq!(p[0].point_b[0], 0.29411619239863757, epsilon = 1e-15);
    assert_same_gaps(&p, &points(&polygon, o, &x, pose, 0.0));
}

/// A segment standing almost upright 2.1 mm inside the square's left face, across its bottom
/// face: out through the left face (the shallowest way, though the segment does not cross it
/// and lies outside the segment's box), at its upper end (2.1 mm) and the square's corner
/// (−0.5, −0.5) on it (1.9 mm), as the polygon gives; before, no point.
#[test]
fn a_segment_inside_a_face_it_does_not_cross_leaves_through_it() {
    let (profile, polygon) = square();
    let o = Pose::default();
    let x =
        Shape::Capsule { a: [-0.118043224710645, 0.0], b: [0.118043224710645, 0.0], radius: 0.0 };
    let pose = Pose::new(-0.4979991148964121, -0.4337955065622763, 1.5699715804123888);
    let p = sorted_by_gap(points(&profile, o, &x, pose, 0.0));
    assert_eq!(p.len(), 2, "{p:?}");
    for (q, gap) in p.iter().zip([-0.00209824081511056, -0.00194628251280192]) {
        assert_relative_eq!(q.gap, gap, epsilon = 1e-15);
        assert!(q.normal[0] < -0.9999, "{q:?}");
    }
    assert_relative_eq!(p[0].point_b[1], -0.315752321998519, epsilon = 1e-15);
    assert_same_gaps(&p, &points(&polygon, o, &x, pose, 0.0));
}

/// The L of chains.rs (arms x ≤ 1 and y ≤ 1 of [0, 2]²) as a profile, and as the union of its
/// two arms declared as polygons, [0, 2] × [0, 1] and [0, 1] × [0, 2]: seeded shapes of the four
/// families at half their size (up to 0.55 long) about its five convex corners, overlapping it
/// by at most 3 cm. A shape out of the union is out of each arm, so its depth in the L is at
/// least its depth in either arm: the reference deepest gap is the least of the two arms'
/// (separating axes each). Near a convex corner of the L only one arm is met there, or both
/// with the same corner and faces ((0, 0)), so that this bound is the L's own depth; the
/// profile gives a point for each pose and that deepest gap to 1e-9.
#[test]
fn shapes_at_an_l_profiles_convex_corners_meet_it_as_the_union_of_its_arms() {
    let l = Shape::Profile {
        points: vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 1.0], [1.0, 2.0], [0.0, 2.0]],
    };
    let arms = [
        Shape::Polygon { vertices: vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]] },
        Shape::Polygon { vertices: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 2.0], [0.0, 2.0]] },
    ];
    let convex = [[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [1.0, 2.0], [0.0, 2.0]];
    let o = Pose::default();
    let mut rng = SplitMix64::new(11);
    for family in 0..4 {
        let (mut overlapping, mut differ, mut missing) = (0, 0, 0);
        for i in 0..4000 {
            // Half the size: up to 0.55 long, radii 0, 5 mm and 25 mm.
            let x = shape(family, &mut rng).scaled(0.5);
            let c = convex[i % convex.len()];
            let pose = Pose::new(
                c[0] + rng.uniform(-0.3, 0.3),
                c[1] + rng.uniform(-0.3, 0.3),
                rng.uniform(0.0, 6.3),
            );
            let reference = arms
                .iter()
                .map(|a| deepest_gap(&points(a, o, &x, pose, 0.0)))
                .fold(f64::INFINITY, f64::min);
            if !(reference <= 0.0 && reference > -0.03) {
                continue;
            }
            overlapping += 1;
            let p = points(&l, o, &x, pose, 0.0);
            missing += usize::from(p.is_empty());
            differ += usize::from((deepest_gap(&p) - reference).abs() > 1e-9);
        }
        assert!(overlapping > 100, "family {family}: {overlapping} overlapping poses");
        assert_eq!((differ, missing), (0, 0), "family {family} of {overlapping} poses");
    }
}

/// The square of side 1 about the origin as a profile and as a polygon.
fn square() -> (Shape, Shape) {
    let corners = vec![[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]];
    (Shape::Profile { points: corners.clone() }, Shape::Polygon { vertices: corners })
}

fn sorted_by_gap(mut p: Vec<ManifoldPoint>) -> Vec<ManifoldPoint> {
    p.sort_by(|a, b| a.gap.total_cmp(&b.gap));
    p
}

/// The same gaps, to 1e-15, in order.
fn assert_same_gaps(p: &[ManifoldPoint], reference: &[ManifoldPoint]) {
    let reference = sorted_by_gap(reference.to_vec());
    assert_eq!(p.len(), reference.len(), "{p:?} against {reference:?}");
    for (q, r) in p.iter().zip(&reference) {
        assert_relative_eq!(q.gap, r.gap, epsilon = 1e-15);
    }
}
