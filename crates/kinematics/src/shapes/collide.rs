//! The narrow phase: which method each pair of shapes gets, and the ids of its points.

use parry2d_f64::math::{Pose as ParryPose, Vector as ParryVector};
use parry2d_f64::query;
use parry2d_f64::shape::{Ball, Capsule, HalfSpace, Shape as ParryShape};

use super::convex::{Core, CorePoint, Feature, point_contact, polygon_contacts};
use super::nonconvex::{convex_chain, half_plane_chain};
use super::shape::{Frame, V};
use super::{ManifoldPoint, Pose, Shape};
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
        Polyline { points } => Some((points.len() - 1, points.len())),
        Profile { points } => Some((points.len(), points.len())),
        _ => None,
    };
    match (a, b) {
        (HalfPlane { .. }, HalfPlane { .. }) => 0,
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
///   most, at most two (a box resting on a face gives its two corners), or the closest pair of
///   vertices; feature i for vertex i of A, nA + j for vertex j of B;
/// * a polygon or capsule on a half-plane: each vertex (a capsule's ends) within the margin,
///   feature the vertex;
/// * a polyline or profile on a half-plane: each point that is a local minimum of the height
///   above the boundary (all of a flat run), feature the point;
/// * a disk, capsule or polygon (n core vertices) against a polyline or profile of m
///   segments: per segment k, the points of the convex pair, vertex i of the convex shape on
///   segment k having feature k·n + i and point v of the chain m·n + v, each chain point at
///   most once and only where it is a local minimum of the distance; a disk in a concave corner
///   touches both segments. A polyline is touched from both sides; a profile is a solid, so a
///   disk whose centre has entered it gets one point on the nearest segment with gap −(d + r).
///
/// # Errors
/// [`KinematicsError::UnsupportedPair`] for two half-planes, or two shapes among polylines
/// and profiles; [`KinematicsError::InvalidOption`] for a negative or NaN margin.
pub fn collide(
    a: &Shape,
    pose_a: &Pose,
    b: &Shape,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<ManifoldPoint>,
) -> Result<(), KinematicsError> {
    use Shape::*;
    if !(margin >= 0.0) {
        return Err(KinematicsError::InvalidOption { name: "margin", value: margin });
    }
    let unsupported = || KinematicsError::UnsupportedPair { a: a.name(), b: b.name() };
    match (a, b) {
        (Disk { .. }, Disk { .. } | Capsule { .. } | HalfPlane { .. })
        | (Capsule { .. } | HalfPlane { .. }, Disk { .. }) => {
            parry_pair(a, pose_a, b, pose_b, margin, out);
            Ok(())
        }
        (HalfPlane { .. }, HalfPlane { .. }) => Err(unsupported()),
        (Polyline { .. } | Profile { .. }, Polyline { .. } | Profile { .. }) => Err(unsupported()),
        (HalfPlane { point, normal }, other) => {
            half_plane(point, normal, pose_a, other, pose_b, true, margin, out);
            Ok(())
        }
        (other, HalfPlane { point, normal }) => {
            half_plane(point, normal, pose_b, other, pose_a, false, margin, out);
            Ok(())
        }
        (Polyline { points }, convex) | (Profile { points }, convex) => {
            let closed = matches!(a, Profile { .. });
            with_core(convex, pose_b, |x| {
                convex_chain(x, convex.aabb(pose_b), points, closed, pose_a, false, margin, out)
            });
            Ok(())
        }
        (convex, Polyline { points }) | (convex, Profile { points }) => {
            let closed = matches!(b, Profile { .. });
            with_core(convex, pose_a, |x| {
                convex_chain(x, convex.aabb(pose_a), points, closed, pose_b, true, margin, out)
            });
            Ok(())
        }
        _ => {
            with_core(a, pose_a, |ca| {
                with_core(b, pose_b, |cb| convex_pair(ca, cb, margin, out));
            });
            Ok(())
        }
    }
}

/// Calls `f` with the convex core of a disk, capsule or polygon at `pose`.
fn with_core<R>(shape: &Shape, pose: &Pose, f: impl FnOnce(&Core<'_>) -> R) -> R {
    let frame = Frame::new(pose);
    match shape {
        Shape::Disk { center, radius } => f(&Core {
            vertices: std::slice::from_ref(center),
            frame,
            radius: *radius,
            one_sided: false,
        }),
        Shape::Capsule { a, b, radius } => {
            let ends = [*a, *b];
            f(&Core { vertices: &ends, frame, radius: *radius, one_sided: false })
        }
        Shape::Polygon { vertices } => f(&Core { vertices, frame, radius: 0.0, one_sided: false }),
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

/// Two convex cores: one closest pair when either is a point, else vertex-on-edge points.
fn convex_pair(a: &Core<'_>, b: &Core<'_>, margin: f64, out: &mut Vec<ManifoldPoint>) {
    if a.len() == 1 || b.len() == 1 {
        let p = if a.len() == 1 {
            point_contact(a, b, true, margin)
        } else {
            point_contact(b, a, false, margin)
        };
        out.extend(p.map(|p| manifold_point(&p, 0, false)));
        return;
    }
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

/// A half-plane (boundary through `point`, outward `normal`, body at `pose`) against `other`
/// at `other_pose`; `plane_is_a` tells which of A and B the half-plane is.
fn half_plane(
    point: &[f64; 2],
    normal: &[f64; 2],
    pose: &Pose,
    other: &Shape,
    other_pose: &Pose,
    plane_is_a: bool,
    margin: f64,
    out: &mut Vec<ManifoldPoint>,
) {
    let frame = Frame::new(pose);
    let origin = frame.point(*point);
    let n = frame.vector(*normal).normalize();
    match other {
        Shape::Polyline { points } | Shape::Profile { points } => {
            let closed = matches!(other, Shape::Profile { .. });
            half_plane_chain(origin, n, points, closed, other_pose, plane_is_a, margin, out);
        }
        _ => with_core(other, other_pose, |c| {
            for i in 0..c.len() {
                let v = c.vertex(i);
                let height = n.dot(&(v - origin));
                let gap = height - c.radius;
                if gap <= margin {
                    let p = CorePoint {
                        on_a: Feature::Edge(0),
                        on_b: Feature::Vertex(i),
                        point_a: v - height * n,
                        point_b: v - c.radius * n,
                        normal: n,
                        gap,
                    };
                    out.push(manifold_point(&p, i, !plane_is_a));
                }
            }
        }),
    }
}

/// parry2d-f64's shape of a disk, capsule or half-plane, and its pose in parry's types.
fn parry_shape(shape: &Shape, pose: &Pose) -> (ParryPose, ParryShapeOf) {
    let frame = Frame::new(pose);
    let at = |p: V| ParryPose::new(ParryVector::new(p.x, p.y), pose.theta);
    match shape {
        Shape::Disk { center, radius } => {
            (at(frame.point(*center)), ParryShapeOf::Ball(Ball::new(*radius)))
        }
        Shape::Capsule { a, b, radius } => (
            at(frame.origin),
            ParryShapeOf::Capsule(Capsule::new(
                ParryVector::new(a[0], a[1]),
                ParryVector::new(b[0], b[1]),
                *radius,
            )),
        ),
        Shape::HalfPlane { point, normal } => {
            let n = V::from(*normal).normalize();
            (
                at(frame.point(*point)),
                ParryShapeOf::HalfSpace(HalfSpace::new(ParryVector::new(n.x, n.y))),
            )
        }
        _ => unreachable!("only disks, capsules and half-planes go to parry"),
    }
}

/// The parry shapes used here, held by value so that no call allocates.
enum ParryShapeOf {
    Ball(Ball),
    Capsule(Capsule),
    HalfSpace(HalfSpace),
}

impl ParryShapeOf {
    fn as_dyn(&self) -> &dyn ParryShape {
        match self {
            ParryShapeOf::Ball(s) => s,
            ParryShapeOf::Capsule(s) => s,
            ParryShapeOf::HalfSpace(s) => s,
        }
    }
}

/// A disk against a disk, a capsule or a half-plane: parry's closest points, which for these
/// smooth convex pairs are exact in f64 and allocate nothing.
fn parry_pair(
    a: &Shape,
    pose_a: &Pose,
    b: &Shape,
    pose_b: &Pose,
    margin: f64,
    out: &mut Vec<ManifoldPoint>,
) {
    // parry2d-f64 0.31.1 answers a shape against a half-space with the relative pose of the
    // reverse order (`contact_support_map_halfspace` does not invert `pos12`), so the
    // half-space is always passed first and the answer flipped back.
    let flip = matches!(b, Shape::HalfPlane { .. });
    let (first, first_pose, second, second_pose) =
        if flip { (b, pose_b, a, pose_a) } else { (a, pose_a, b, pose_b) };
    let (p1, s1) = parry_shape(first, first_pose);
    let (p2, s2) = parry_shape(second, second_pose);
    // Every pair routed here is one that parry's dispatcher supports, so `Err` cannot occur.
    if let Ok(Some(c)) = query::contact(&p1, s1.as_dyn(), &p2, s2.as_dyn(), margin) {
        let (on_a, on_b, normal) =
            if flip { (c.point2, c.point1, -c.normal1) } else { (c.point1, c.point2, c.normal1) };
        out.push(ManifoldPoint {
            feature: 0,
            point_a: [on_a.x, on_a.y],
            point_b: [on_b.x, on_b.y],
            normal: [normal.x, normal.y],
            gap: c.dist,
        });
    }
}
