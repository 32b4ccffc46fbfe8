//! The narrow phase: which method each pair of shapes gets, and the ids of its points.

use super::convex::{Core, CorePoint, Feature, point_contact, polygon_contacts};
use super::nonconvex::{Chain, convex_chain, half_plane_chain};
use super::shape::{
    AXIS_OUT_OF_SCALE, ENDS_COINCIDE, Placement, V, bad_normal, invalid, normal_scales,
    segment_length, segment_scales, too_few,
};
use super::{ChainIndex, ManifoldPoint, Pose, Shape};
use crate::KinematicsError;

/// The upper bound of the number of points of the pair (a, b) and of their `feature` + 1, a
/// fixed number for the pair whatever the poses: 1 for a disk with a disk, polygon, capsule or
/// half-plane; nA + nB for two polygons or capsules (nA, nB their vertices, a capsule's two
/// ends counted as vertices); n for a polygon or capsule on a half-plane; the number of points
/// of a polyline or profile on a half-plane; m·n + p for a disk (n = 1), capsule (n = 2) or
/// polygon (n vertices) against a polyline or profile of p points and m segments. 0 for the
/// pairs that [`collide`] does not support.
pub fn max_points(a: &Shape, b: &Shape) -> usize {
    use Shape::*;
    let core_len = |s: &Shape| match s {
        Disk { .. } => 1,
        Capsule { .. } => 2,
        Polygon { vertices } => vertices.len(),
        _ => 0,
    };
    let chain = |s: &Shape| match s {
        Polyline { points } => Some((points.len().saturating_sub(1), points.len())),
        Profile { points } => Some((points.len(), points.len())),
        _ => None,
    };
    match (a, b) {
        (HalfPlane { .. }, HalfPlane { .. }) => 0,
        _ if thin(a) && thin(b) => 0,
        (HalfPlane { .. }, other) | (other, HalfPlane { .. }) => match chain(other) {
            Some((_, points)) => points,
            None => core_len(other),
        },
        _ => match (chain(a), chain(b)) {
            (Some(_), Some(_)) => 0,
            (Some((m, p)), None) => m * core_len(b) + p,
            (None, Some((m, p))) => m * core_len(a) + p,
            (None, None) if matches!(a, Disk { .. }) || matches!(b, Disk { .. }) => 1,
            (None, None) => core_len(a) + core_len(b),
        },
    }
}

/// Appends to `out` the points of the contact between shape A at `pose_a` and shape B at
/// `pose_b` whose gap is at most `margin` (m); clears nothing and allocates nothing beyond
/// `out`'s growth. The shapes must have passed [`Shape::validate`].
///
/// The pairs and their points (see the [module](crate::shapes) table):
/// * a disk with a disk, a capsule, a half-plane or a polygon: the one pair of closest points
///   (inside a polygon, the face of least penetration), feature 0;
/// * two polygons or capsules: the vertex-on-edge points of the two faces that separate them
///   most (two for a face on a face: a box resting on a face gives its two corners; one for a
///   corner on a face) and, when they are apart, their closest pair (two corners facing each
///   other); feature i for vertex i of A, nA + j for vertex j of B;
/// * a polygon or capsule on a half-plane: each vertex (a capsule's ends) within the margin,
///   feature the vertex;
/// * a polyline or profile on a half-plane: each point that is a local minimum of the height
///   above the boundary (all of a flat run), and the far end of the chord lying on the
///   boundary there (the flatter of its two), feature the point;
/// * a disk, capsule or polygon (n core vertices) against a polyline or profile of m
///   segments: per segment k, the points of the convex pair, vertex i of the convex shape on
///   segment k having feature k·n + i and point v of the chain m·n + v, each chain point at
///   most once: for a disk only where it is a local minimum of the distance, for a polygon or
///   capsule also at the far end of the chord lying on its face there, so that a face rests on
///   a chain as on a polygon; a disk in a concave corner touches both segments. A polyline is
///   touched from both sides; a profile is a solid, so a disk whose centre has entered it gets
///   one point on the nearest segment with gap −(d + r), and a capsule or polygon with a core
///   vertex inside it (a capsule's end centre, a polygon's corner) is pushed out as a convex
///   solid's face pushes it: from each segment it crosses, by the segment's face or a face of
///   the shape within 60° of facing it (the reference of the pair), with the normal
///   out of the solid and the gap −(depth) of the vertices behind the segment, as against a
///   half-plane on the segment's line or the same outline declared as a polygon; segments
///   behind the core give no point; a core wholly inside leaves by the segment its deepest
///   vertex is least deep behind (for a polygonal profile, one of the profile's own directions,
///   which may be a little deeper than the least of the shape's). Points, ids and bounds are
///   those above. Shallow contacts (the shape's own face separating less than the solid's),
///   faces resting on a chain and concave corners are met segment by segment as before. A
///   capsule whose axis a convex corner of a profile crosses between its two ends, both
///   outside, is still met by the segments alone: its ends on the corner's segments.
///
/// Poses are not checked: a non-finite coordinate gives non-finite gaps, which no margin
/// admits, so no point; nor do shapes so far apart (beyond about 1e154 m) that their squared
/// distance overflows f64.
///
/// # Errors
/// [`KinematicsError::UnsupportedPair`] for two half-planes, or two shapes among polylines
/// and profiles; [`KinematicsError::NoThickness`] for two shapes among points (disks of radius
/// 0), segments (capsules of radius 0) and polylines; [`KinematicsError::InvalidOption`] for a
/// negative or NaN margin;
/// [`KinematicsError::InvalidShape`] for a shape with too few points, a capsule whose ends
/// coincide or whose axis is too short or too long to measure (|b − a|² not a normal f64), or a
/// half-plane whose normal is zero or too small or large to normalise (|n|² not a normal f64)
/// (the checks that cost nothing; the others, among them the segments of a chain, are
/// [`Shape::validate`]'s: a chain segment too short to measure, left unchecked, can make the
/// chain's whole contact lose its points).
pub fn collide(
    a: &Shape,
    pose_a: &Pose,
    b: &Shape,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<ManifoldPoint>,
) -> Result<(), KinematicsError> {
    collide_placed(a, &Placement::new(pose_a), b, &Placement::new(pose_b), margin, out)
}

/// [`collide`] of two shapes so placed: the same points, bit for bit, without computing the
/// placements' sines and cosines again.
///
/// # Errors
/// As [`collide`].
pub fn collide_placed(
    a: &Shape,
    place_a: &Placement,
    b: &Shape,
    place_b: &Placement,
    margin: f64,
    out: &mut Vec<ManifoldPoint>,
) -> Result<(), KinematicsError> {
    collide_indexed(a, place_a, b, place_b, None, margin, out)
}

/// [`collide_placed`] with the [`ChainIndex`] of whichever of `a` and `b` is a polyline or a
/// profile (at most one is): the same points, bit for bit, visiting only the runs of segments
/// near the other shape. An index built for another chain (of another length or kind) is not
/// used.
///
/// # Errors
/// As [`collide`].
pub fn collide_indexed(
    a: &Shape,
    place_a: &Placement,
    b: &Shape,
    place_b: &Placement,
    index: Option<&ChainIndex>,
    margin: f64,
    out: &mut Vec<ManifoldPoint>,
) -> Result<(), KinematicsError> {
    if !(margin >= 0.0) {
        return Err(KinematicsError::InvalidOption { name: "margin", value: margin });
    }
    // The checks of `Shape::validate` that would otherwise end in a panic or a NaN, at the
    // cost of a comparison each; the rest (convexity, orientation) is validation's job.
    usable(a)?;
    usable(b)?;
    let start = out.len();
    let found = dispatch(a, place_a, b, place_b, index, margin, out);
    // Drop what overflow or a non-finite pose left: a gap of ±∞ or a NaN, a NaN normal.
    let mut kept = start;
    for k in start..out.len() {
        let p = out[k];
        let finite = |v: [f64; 2]| v[0].is_finite() && v[1].is_finite();
        if p.gap.is_finite() && finite(p.normal) && finite(p.point_a) && finite(p.point_b) {
            out[kept] = p;
            kept += 1;
        }
    }
    out.truncate(kept);
    found
}

/// `index` if it was built for the chain through `points`.
fn fitting<'a>(
    index: Option<&'a ChainIndex>,
    points: &[[f64; 2]],
    closed: bool,
) -> Option<&'a ChainIndex> {
    index.filter(|ix| ix.fits(points, closed))
}

/// The points of a pair of usable shapes, by the method of the pair.
fn dispatch(
    a: &Shape,
    place_a: &Placement,
    b: &Shape,
    place_b: &Placement,
    index: Option<&ChainIndex>,
    margin: f64,
    out: &mut Vec<ManifoldPoint>,
) -> Result<(), KinematicsError> {
    use Shape::*;
    let unsupported = || KinematicsError::UnsupportedPair { a: a.name(), b: b.name() };
    match (a, b) {
        (HalfPlane { .. }, HalfPlane { .. }) => Err(unsupported()),
        (Polyline { .. } | Profile { .. }, Polyline { .. } | Profile { .. }) => Err(unsupported()),
        _ if thin(a) && thin(b) => Err(KinematicsError::NoThickness { a: a.name(), b: b.name() }),
        (HalfPlane { point, normal }, other) => {
            half_plane(point, normal, place_a, (other, place_b, index), true, margin, out);
            Ok(())
        }
        (other, HalfPlane { point, normal }) => {
            half_plane(point, normal, place_b, (other, place_a, index), false, margin, out);
            Ok(())
        }
        (Polyline { points }, convex) | (Profile { points }, convex) => {
            let closed = matches!(a, Profile { .. });
            let chain =
                Chain { points, closed, frame: place_a, index: fitting(index, points, closed) };
            with_core(convex, place_b, |x| {
                convex_chain(x, convex.aabb_placed(place_b), &chain, false, margin, out)
            });
            Ok(())
        }
        (convex, Polyline { points }) | (convex, Profile { points }) => {
            let closed = matches!(b, Profile { .. });
            let chain =
                Chain { points, closed, frame: place_b, index: fitting(index, points, closed) };
            with_core(convex, place_a, |x| {
                convex_chain(x, convex.aabb_placed(place_a), &chain, true, margin, out)
            });
            Ok(())
        }
        // A disk is its centre, placed, grown by its radius: only the other shape needs a core.
        (Disk { center, radius }, other) => {
            let p = place_a.point(*center);
            with_core(other, place_b, |c| {
                out.extend(point_contact(p, *radius, c, true, margin).map(|p| single(&p)));
            });
            Ok(())
        }
        (other, Disk { center, radius }) => {
            let p = place_b.point(*center);
            with_core(other, place_a, |c| {
                out.extend(point_contact(p, *radius, c, false, margin).map(|p| single(&p)));
            });
            Ok(())
        }
        _ => {
            with_core(a, place_a, |ca| {
                with_core(b, place_b, |cb| convex_pair(ca, cb, margin, out));
            });
            Ok(())
        }
    }
}

/// The one point of a disk's contact, feature 0.
fn single(p: &CorePoint) -> ManifoldPoint {
    manifold_point(p, 0, false)
}

/// Refuses a shape with too few points, a capsule whose ends coincide or whose axis is too
/// short or too long to measure, or a normal that is zero or does not normalise.
fn usable(shape: &Shape) -> Result<(), KinematicsError> {
    let (count, min) = match shape {
        Shape::Polygon { vertices: points } | Shape::Profile { points } => (points.len(), 3),
        Shape::Polyline { points } => (points.len(), 2),
        Shape::Capsule { a, b, .. } if a == b => {
            return Err(invalid(shape.name(), ENDS_COINCIDE, None, None));
        }
        Shape::Capsule { a, b, .. } if !segment_scales(a, b) => {
            let length = segment_length(a, b);
            return Err(invalid(shape.name(), AXIS_OUT_OF_SCALE, Some(length), None));
        }
        Shape::HalfPlane { normal, .. } if !normal_scales(normal) => {
            return Err(bad_normal(normal));
        }
        _ => return Ok(()),
    };
    if count < min { Err(too_few(shape.name(), count)) } else { Ok(()) }
}

/// Calls `f` with the convex core of a disk, capsule or polygon so placed.
fn with_core<R>(shape: &Shape, frame: &Placement, f: impl FnOnce(&Core<'_>) -> R) -> R {
    let frame = *frame;
    match shape {
        Shape::Disk { center, radius } => {
            f(&Core::new(std::slice::from_ref(center), frame, *radius, false))
        }
        Shape::Capsule { a, b, radius } => {
            let ends = [*a, *b];
            f(&Core::new(&ends, frame, *radius, false))
        }
        Shape::Polygon { vertices } => f(&Core::new(vertices, frame, 0.0, false)),
        _ => unreachable!("only disks, capsules and polygons have a convex core"),
    }
}

/// The world contact point of a core point with id `feature`, its A and B swapped when `flip`.
pub(crate) fn manifold_point(p: &CorePoint, feature: usize, flip: bool) -> ManifoldPoint {
    let (point_a, point_b, normal) =
        if flip { (p.point_b, p.point_a, -p.normal) } else { (p.point_a, p.point_b, p.normal) };
    ManifoldPoint {
        feature: feature as u32,
        point_a: point_a.into(),
        point_b: point_b.into(),
        normal: normal.into(),
        gap: p.gap,
    }
}

/// Two convex cores of two or more vertices (capsules, polygons): vertex-on-edge points.
fn convex_pair(a: &Core<'_>, b: &Core<'_>, margin: f64, out: &mut Vec<ManifoldPoint>) {
    let n_a = a.len();
    polygon_contacts(a, b, margin, &mut |p| {
        let feature = match (p.on_a, p.on_b) {
            (Feature::Vertex(i), _) => i,
            (_, Feature::Vertex(j)) => n_a + j,
            (Feature::Edge(_), Feature::Edge(_)) => unreachable!("a point has a vertex"),
        };
        out.push(manifold_point(&p, feature, false));
    });
}

/// A half-plane (boundary through `point`, outward `normal`, body at `frame`) against `other`
/// at `other_frame` (with its index, for a chain); `plane_is_a` tells which of A and B the
/// half-plane is.
fn half_plane(
    point: &[f64; 2],
    normal: &[f64; 2],
    frame: &Placement,
    (other, other_frame, index): (&Shape, &Placement, Option<&ChainIndex>),
    plane_is_a: bool,
    margin: f64,
    out: &mut Vec<ManifoldPoint>,
) {
    let origin = frame.point(*point);
    let n = frame.vector(*normal).normalize();
    // Vertex i of the other shape, at world point v and grown by `radius`, on the plane.
    let mut vertex = |i: usize, v: V, radius: f64| {
        let height = n.dot(&(v - origin));
        let gap = height - radius;
        if gap <= margin {
            let p = CorePoint {
                on_a: Feature::Edge(0),
                on_b: Feature::Vertex(i),
                point_a: v - height * n,
                point_b: v - radius * n,
                normal: n,
                gap,
            };
            out.push(manifold_point(&p, i, !plane_is_a));
        }
    };
    match other {
        Shape::Polyline { points } | Shape::Profile { points } => {
            let closed = matches!(other, Shape::Profile { .. });
            let index = fitting(index, points, closed);
            let chain = Chain { points, closed, frame: other_frame, index };
            half_plane_chain(origin, n, &chain, plane_is_a, margin, out);
        }
        // A disk is its placed centre grown by its radius, without a core.
        Shape::Disk { center, radius } => vertex(0, other_frame.point(*center), *radius),
        _ => with_core(other, other_frame, |c| {
            for i in 0..c.len() {
                vertex(i, c.vertex(i), c.radius);
            }
        }),
    }
}

/// Whether a shape has neither an inside nor a thickness: a point, a segment or a polyline,
/// whose distance to another such shape never changes sign.
fn thin(shape: &Shape) -> bool {
    match shape {
        Shape::Disk { radius, .. } | Shape::Capsule { radius, .. } => *radius == 0.0,
        Shape::Polyline { .. } => true,
        _ => false,
    }
}
