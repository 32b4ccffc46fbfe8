//! The shapes, their validation, mass properties and bounding boxes.

use std::f64::consts::PI;

use nalgebra::Vector2;
use serde::{Deserialize, Serialize};

use super::{Aabb, Pose};
use crate::KinematicsError;

/// A world vector or point.
pub(crate) type V = Vector2<f64>;

/// A body's placement in the world: its [`Pose`] with the cosine and sine of its orientation,
/// computed once. [`collide_placed`](crate::shapes::collide_placed) and [`Shape::aabb_placed`]
/// take shapes so placed, so that a body placed against several others, or whose caller has
/// cos θ and sin θ already, does not have them computed again; [`crate::collide`] and
/// [`Shape::aabb`] place their poses themselves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    pub(crate) cos: f64,
    pub(crate) sin: f64,
    pub(crate) origin: V,
    theta: f64,
}

impl Placement {
    /// The placement at `pose`: cos θ and sin θ by `f64::sin_cos` (no call at θ = 0).
    #[inline]
    pub fn new(pose: &Pose) -> Self {
        // Fixed bodies (floors, walls) are mostly unturned: their frame costs no sine.
        let (sin, cos) = if pose.theta == 0.0 { (0.0, 1.0) } else { pose.theta.sin_cos() };
        Self::with_rotation(pose, cos, sin)
    }

    /// The placement at `pose` with the caller's `cos` and `sin`, which must be cos θ and
    /// sin θ of `pose.theta` as [`Placement::new`] computes them (`(1, 0)` at θ = 0, else
    /// `f64::sin_cos`): the results are then those of the placement by `new`, bit for bit.
    #[inline]
    pub fn with_rotation(pose: &Pose, cos: f64, sin: f64) -> Self {
        Self { cos, sin, origin: V::new(pose.x, pose.y), theta: pose.theta }
    }

    /// The pose.
    #[inline]
    pub fn pose(&self) -> Pose {
        Pose { x: self.origin.x, y: self.origin.y, theta: self.theta }
    }

    /// A body vector in the world.
    #[inline]
    pub(crate) fn vector(&self, v: [f64; 2]) -> V {
        V::new(self.cos * v[0] - self.sin * v[1], self.sin * v[0] + self.cos * v[1])
    }

    /// A body point in the world.
    #[inline]
    pub(crate) fn point(&self, p: [f64; 2]) -> V {
        self.origin + self.vector(p)
    }
}

/// A shape in its body's frame (m).
///
/// Build it as a literal or with [`Shape::profile_from_curve`] and [`Shape::profile_polar`], and
/// check it once with [`Shape::validate`]; [`crate::collide`] assumes valid shapes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    /// A disk of centre `center` and radius `radius` ≥ 0; radius 0 is a point.
    Disk {
        /// The centre (m).
        center: [f64; 2],
        /// The radius (m).
        radius: f64,
    },
    /// A convex polygon, its vertices counter-clockwise.
    Polygon {
        /// The vertices (m), at least 3, counter-clockwise, strictly convex.
        vertices: Vec<[f64; 2]>,
    },
    /// The points within `radius` of the segment from `a` to `b`; radius 0 is a segment.
    Capsule {
        /// The first end of the axis (m).
        a: [f64; 2],
        /// The second end of the axis (m), distinct from `a`.
        b: [f64; 2],
        /// The radius (m).
        radius: f64,
    },
    /// The half-plane bounded by the line through `point` normal to `normal`, solid on the
    /// side opposite `normal` (a floor has normal (0, 1)).
    HalfPlane {
        /// A point of the boundary line (m).
        point: [f64; 2],
        /// The outward normal, non-zero; it need not be of unit length, but its length must lie
        /// in about 1.5e-154..1.3e154 (|n|² a normal f64), so that it can be normalised.
        normal: [f64; 2],
    },
    /// An open chain of segments through `points`, touched from either side and possibly
    /// non-convex (a guide, a ramp, a measured road profile).
    Polyline {
        /// The points (m), at least 2, consecutive ones distinct.
        points: Vec<[f64; 2]>,
    },
    /// The solid bounded by the closed chain of segments through `points` (the last joined
    /// to the first), possibly non-convex: a cam sampled along its contour.
    Profile {
        /// The points (m), at least 3, counter-clockwise, the chain not crossing itself.
        points: Vec<[f64; 2]>,
    },
}

/// The error of a shape `shape` with `problem`, the number at fault `value` and the vertex or
/// point `index`.
pub(crate) fn invalid(
    shape: &'static str,
    problem: &'static str,
    value: Option<f64>,
    index: Option<usize>,
) -> KinematicsError {
    KinematicsError::InvalidShape { shape, problem, value, index }
}

/// The first coordinate of `points` that is not finite, with its point's index.
fn non_finite<'p>(points: impl IntoIterator<Item = &'p [f64; 2]>) -> Option<(usize, f64)> {
    points
        .into_iter()
        .enumerate()
        .find_map(|(i, p)| p.iter().find(|v| !v.is_finite()).map(|&v| (i, v)))
}

/// Checks that every point is finite and that consecutive points differ (the last and the
/// first too when `closed`) by a segment whose squared length is a normal f64.
fn check_chain(
    shape: &'static str,
    points: &[[f64; 2]],
    min: usize,
    closed: bool,
) -> Result<(), KinematicsError> {
    if points.len() < min {
        return Err(too_few(shape, points.len()));
    }
    if let Some((i, v)) = non_finite(points) {
        return Err(invalid(shape, "non-finite coordinate", Some(v), Some(i)));
    }
    let n = points.len();
    let segments = if closed { n } else { n - 1 };
    for i in 0..segments {
        let (a, b) = (&points[i], &points[(i + 1) % n]);
        if a == b {
            return Err(invalid(shape, "two consecutive points coincide", None, Some(i)));
        }
        if !segment_scales(a, b) {
            let length = segment_length(a, b);
            return Err(invalid(shape, SEGMENT_OUT_OF_SCALE, Some(length), Some(i)));
        }
    }
    Ok(())
}

/// Why a capsule is refused whose two ends are one point.
pub(crate) const ENDS_COINCIDE: &str = "its two ends coincide (a disk has one centre)";

/// Why a capsule is refused whose two ends differ but whose axis' squared length is not a
/// normal f64, before the length |b − a|: its projections would divide by zero (or by ∞) and
/// lose every point of its contacts.
pub(crate) const AXIS_OUT_OF_SCALE: &str = "axis too short or too long to measure (|b − a|² \
     outside 2.2e-308..1.8e308, |b − a| outside about 1.5e-154..1.3e154), |b − a|";

/// Why a polyline, polygon or profile is refused with two consecutive points that differ but
/// whose segment's squared length is not a normal f64, before the segment's length.
pub(crate) const SEGMENT_OUT_OF_SCALE: &str = "segment too short or too long to measure (its \
     squared length outside 2.2e-308..1.8e308, its length outside about 1.5e-154..1.3e154), \
     length";

/// Whether the segment from `a` to `b` can be measured accurately: |b − a|² is a normal f64,
/// as a half-plane's normal must be ([`normal_scales`]), so |b − a| lies in about
/// 1.5e-154..1.3e154.
#[inline]
pub(crate) fn segment_scales(a: &[f64; 2], b: &[f64; 2]) -> bool {
    normal_scales(&[b[0] - a[0], b[1] - a[1]])
}

/// The length |b − a| of a segment, for the errors.
pub(crate) fn segment_length(a: &[f64; 2], b: &[f64; 2]) -> f64 {
    (b[0] - a[0]).hypot(b[1] - a[1])
}

/// The error of a shape with `count` points, fewer than it needs.
pub(crate) fn too_few(shape: &'static str, count: usize) -> KinematicsError {
    invalid(shape, "too few points", Some(count as f64), None)
}

/// The error of a half-plane whose normal is not finite, is zero, or is of a squared length
/// that is not a normal f64, so that normalising it would give a zero, inaccurate or
/// non-finite unit normal; it names the coordinate at fault or the length |n|.
pub(crate) fn bad_normal(normal: &[f64; 2]) -> KinematicsError {
    if let Some((_, v)) = non_finite([normal]) {
        invalid("half_plane", "non-finite normal coordinate", Some(v), None)
    } else if *normal == [0.0, 0.0] {
        invalid("half_plane", "zero normal", None, None)
    } else {
        invalid("half_plane", NORMAL_OUT_OF_SCALE, Some(normal[0].hypot(normal[1])), None)
    }
}

/// Why a half-plane's normal that is not zero is refused, before its length |n|.
pub(crate) const NORMAL_OUT_OF_SCALE: &str = "normal too small or too large to normalise (|n|² \
     outside 2.2e-308..1.8e308, |n| outside about 1.5e-154..1.3e154), |n|";

/// Whether a half-plane's normal can be normalised accurately: |n|² is a normal f64 (neither
/// zero, subnormal nor beyond f64's range), so |n| lies in about 1.5e-154..1.3e154.
#[inline]
pub(crate) fn normal_scales(normal: &[f64; 2]) -> bool {
    (normal[0] * normal[0] + normal[1] * normal[1]).is_normal()
}

/// The signed area, the first moments and the polar second moment about the origin of the
/// polygon through `points` (positive when counter-clockwise), by the shoelace sums.
fn polygon_moments(points: &[[f64; 2]]) -> (f64, [f64; 2], f64) {
    let n = points.len();
    let (mut area, mut sx, mut sy, mut j) = (0.0, 0.0, 0.0, 0.0);
    for i in 0..n {
        let [x0, y0] = points[i];
        let [x1, y1] = points[(i + 1) % n];
        let cross = x0 * y1 - x1 * y0;
        area += cross;
        sx += cross * (x0 + x1);
        sy += cross * (y0 + y1);
        j += cross * (x0 * x0 + x0 * x1 + x1 * x1 + y0 * y0 + y0 * y1 + y1 * y1);
    }
    (area / 2.0, [sx / 6.0, sy / 6.0], j / 12.0)
}

/// Whether the segments p0p1 and q0q1 share a point (touching counts).
fn segments_meet(p0: V, p1: V, q0: V, q1: V) -> bool {
    let cross = |a: V, b: V| a.x * b.y - a.y * b.x;
    let d1 = cross(p1 - p0, q0 - p0);
    let d2 = cross(p1 - p0, q1 - p0);
    let d3 = cross(q1 - q0, p0 - q0);
    let d4 = cross(q1 - q0, p1 - q0);
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return true;
    }
    let on = |a: V, b: V, p: V, d: f64| {
        d == 0.0
            && p.x >= a.x.min(b.x)
            && p.x <= a.x.max(b.x)
            && p.y >= a.y.min(b.y)
            && p.y <= a.y.max(b.y)
    };
    on(p0, p1, q0, d1) || on(p0, p1, q1, d2) || on(q0, q1, p0, d3) || on(q0, q1, p1, d4)
}

/// Where the closed contour through `points` crosses or touches itself: of the pairs of
/// segments i < j that are not neighbours and meet (segment i runs from point i to point
/// i + 1, the last one back to point 0), the j of the first pair in the order of (i, j); `None`
/// for a simple contour.
///
/// Only segments whose x-ranges overlap can meet, so the segments are swept in the order of
/// their smallest x, each tested against those still open there: about n log n operations for
/// a profile's samples rather than the n²/2 of every pair.
fn first_crossing(points: &[[f64; 2]]) -> Option<usize> {
    let n = points.len();
    let p = |i: usize| V::from(points[i % n]);
    let range = |i: usize| {
        let (a, b) = (points[i], points[(i + 1) % n]);
        ([a[0].min(b[0]), a[1].min(b[1])], [a[0].max(b[0]), a[1].max(b[1])])
    };
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| range(a).0[0].total_cmp(&range(b).0[0]).then(a.cmp(&b)));
    let mut open: Vec<usize> = Vec::new();
    let mut first: Option<(usize, usize)> = None;
    for &k in &order {
        let (lo, hi) = range(k);
        open.retain(|&m| range(m).1[0] >= lo[0]);
        for &m in &open {
            let (i, j) = (m.min(k), m.max(k));
            // Neighbours share a point by construction; only the others count.
            if j == i + 1 || (i == 0 && j == n - 1) || first.is_some_and(|f| f <= (i, j)) {
                continue;
            }
            let (mlo, mhi) = range(m);
            if mlo[1] <= hi[1] && lo[1] <= mhi[1] && segments_meet(p(i), p(i + 1), p(j), p(j + 1)) {
                first = Some((i, j));
            }
        }
        open.push(k);
    }
    first.map(|(_, j)| j)
}

impl Shape {
    /// The shape's name as in scene files: `disk`, `polygon`, `capsule`, `half_plane`,
    /// `polyline` or `profile`.
    pub fn name(&self) -> &'static str {
        match self {
            Shape::Disk { .. } => "disk",
            Shape::Polygon { .. } => "polygon",
            Shape::Capsule { .. } => "capsule",
            Shape::HalfPlane { .. } => "half_plane",
            Shape::Polyline { .. } => "polyline",
            Shape::Profile { .. } => "profile",
        }
    }

    /// Checks the shape once, before it is used: finite coordinates, radius ≥ 0, a polygon
    /// strictly convex and counter-clockwise with at least 3 vertices, a capsule's ends
    /// distinct, a half-plane's normal non-zero and of a length that normalises (|n|² a normal
    /// f64), a polyline of at least 2 points and a profile of at least 3, counter-clockwise and
    /// not crossing itself, no two consecutive points equal, and every segment (a capsule's
    /// axis, a chain's or polygon's edge) of a length whose square is a normal f64 (about
    /// 1.5e-154 to 1.3e154 m).
    ///
    /// # Errors
    /// [`KinematicsError::InvalidShape`] naming the shape, the problem, the number at fault (the
    /// radius, the non-finite coordinate, the normal's length |n|, the length of a segment too
    /// short or too long to measure, the number of points, a
    /// profile's signed area, the turns of a polygon that winds round more than once) and the
    /// vertex or point concerned (for a capsule's end, 0 for `a` and 1 for `b`).
    pub fn validate(&self) -> Result<(), KinematicsError> {
        let name = self.name();
        let radius_ok = |r: f64| {
            if !r.is_finite() {
                Err(invalid(name, "non-finite radius", Some(r), None))
            } else if r < 0.0 {
                Err(invalid(name, "negative radius", Some(r), None))
            } else {
                Ok(())
            }
        };
        match self {
            Shape::Disk { center, radius } => {
                if let Some((_, v)) = non_finite([center]) {
                    return Err(invalid(name, "non-finite centre coordinate", Some(v), None));
                }
                radius_ok(*radius)
            }
            Shape::Capsule { a, b, radius } => {
                if let Some((i, v)) = non_finite([a, b]) {
                    return Err(invalid(name, "non-finite end coordinate", Some(v), Some(i)));
                }
                if a == b {
                    return Err(invalid(name, ENDS_COINCIDE, None, None));
                }
                if !segment_scales(a, b) {
                    return Err(invalid(name, AXIS_OUT_OF_SCALE, Some(segment_length(a, b)), None));
                }
                radius_ok(*radius)
            }
            Shape::HalfPlane { point, normal } => {
                if let Some((_, v)) = non_finite([point]) {
                    return Err(invalid(name, "non-finite point coordinate", Some(v), None));
                }
                if !normal_scales(normal) {
                    return Err(bad_normal(normal));
                }
                Ok(())
            }
            Shape::Polyline { points } => check_chain(name, points, 2, false),
            Shape::Polygon { vertices } => {
                check_chain(name, vertices, 3, true)?;
                let n = vertices.len();
                let mut turning = 0.0;
                for i in 0..n {
                    let p0 = V::from(vertices[i]);
                    let p1 = V::from(vertices[(i + 1) % n]);
                    let p2 = V::from(vertices[(i + 2) % n]);
                    let (e0, e1) = (p1 - p0, p2 - p1);
                    let cross = e0.x * e1.y - e0.y * e1.x;
                    if !(cross > 0.0) {
                        return Err(invalid(
                            name,
                            "not strictly convex and counter-clockwise",
                            None,
                            Some((i + 1) % n),
                        ));
                    }
                    turning += cross.atan2(e0.dot(&e1));
                }
                // Left turns all round that add up to more than one revolution draw a star.
                if (turning - 2.0 * PI).abs() > 1e-6 {
                    let turns = turning / (2.0 * PI);
                    return Err(invalid(
                        name,
                        "winds round more than once, turns",
                        Some(turns),
                        None,
                    ));
                }
                Ok(())
            }
            Shape::Profile { points } => {
                check_chain(name, points, 3, true)?;
                let area = polygon_moments(points).0;
                if !(area > 0.0) {
                    let problem = "points run clockwise or enclose no area, signed area";
                    return Err(invalid(name, problem, Some(area), None));
                }
                match first_crossing(points) {
                    Some(j) => Err(invalid(name, "the contour crosses itself", None, Some(j))),
                    None => Ok(()),
                }
            }
        }
    }

    /// The profile through the closed curve `f(s)`, s ∈ [0, 1), sampled at `samples` equally
    /// spaced values of s; the points are put in counter-clockwise order if `f` runs clockwise.
    ///
    /// # Errors
    /// [`KinematicsError::InvalidOption`] for fewer than 3 samples or more than memory holds;
    /// [`Shape::validate`]'s errors for the sampled profile.
    pub fn profile_from_curve(
        f: impl Fn(f64) -> [f64; 2],
        samples: usize,
    ) -> Result<Shape, KinematicsError> {
        let refused = || KinematicsError::InvalidOption { name: "samples", value: samples as f64 };
        if samples < 3 {
            return Err(refused());
        }
        let mut points: Vec<[f64; 2]> = Vec::new();
        points.try_reserve_exact(samples).map_err(|_| refused())?;
        points.extend((0..samples).map(|k| f(k as f64 / samples as f64)));
        if polygon_moments(&points).0 < 0.0 {
            points[1..].reverse();
        }
        let shape = Shape::Profile { points };
        shape.validate()?;
        Ok(shape)
    }

    /// The profile of the polar curve r(ψ), ψ ∈ [0, 2π), sampled at `samples` equally spaced
    /// angles: a cam of radius r(ψ) about the body origin.
    ///
    /// # Errors
    /// As [`Shape::profile_from_curve`].
    pub fn profile_polar(r: impl Fn(f64) -> f64, samples: usize) -> Result<Shape, KinematicsError> {
        Self::profile_from_curve(
            |s| {
                let psi = 2.0 * PI * s;
                let radius = r(psi);
                [radius * psi.cos(), radius * psi.sin()]
            },
            samples,
        )
    }

    /// The shape scaled by the factor `s` about its body's origin: every point and length
    /// times s (a half-plane's boundary point moves, its normal stays). A valid shape stays
    /// valid for a positive finite s, its area times s² and its unit inertia times s²; any
    /// other s (a negative radius, coincident points) is for [`Shape::validate`] to refuse.
    pub fn scaled(&self, s: f64) -> Shape {
        let p = |v: &[f64; 2]| [v[0] * s, v[1] * s];
        match self {
            Shape::Disk { center, radius } => Shape::Disk { center: p(center), radius: radius * s },
            Shape::Capsule { a, b, radius } => {
                Shape::Capsule { a: p(a), b: p(b), radius: radius * s }
            }
            Shape::HalfPlane { point, normal } => {
                Shape::HalfPlane { point: p(point), normal: *normal }
            }
            Shape::Polygon { vertices } => {
                Shape::Polygon { vertices: vertices.iter().map(p).collect() }
            }
            Shape::Polyline { points } => {
                Shape::Polyline { points: points.iter().map(p).collect() }
            }
            Shape::Profile { points } => Shape::Profile { points: points.iter().map(p).collect() },
        }
    }

    /// The area (m²): 0 for a polyline, +∞ for a half-plane.
    pub fn area(&self) -> f64 {
        match self {
            Shape::Disk { radius, .. } => PI * radius * radius,
            Shape::Capsule { a, b, radius } => {
                2.0 * radius * (V::from(*b) - V::from(*a)).norm() + PI * radius * radius
            }
            Shape::Polygon { vertices: points } | Shape::Profile { points } => {
                polygon_moments(points).0
            }
            Shape::HalfPlane { .. } => f64::INFINITY,
            Shape::Polyline { .. } => 0.0,
        }
    }

    /// The centroid in the body frame (m): of the area, or for a polyline of its length; a
    /// half-plane's `point`.
    pub fn centroid(&self) -> [f64; 2] {
        match self {
            Shape::Disk { center, .. } => *center,
            Shape::Capsule { a, b, .. } => [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0],
            Shape::Polygon { vertices: points } | Shape::Profile { points } => {
                let (area, first, _) = polygon_moments(points);
                [first[0] / area, first[1] / area]
            }
            Shape::HalfPlane { point, .. } => *point,
            Shape::Polyline { points } => {
                let (mut length, mut sum) = (0.0, V::zeros());
                for w in points.windows(2) {
                    let (p, q) = (V::from(w[0]), V::from(w[1]));
                    let l = (q - p).norm();
                    length += l;
                    sum += l * (p + q) / 2.0;
                }
                (sum / length).into()
            }
        }
    }

    /// The polar second moment of area about the body origin divided by the area (m²), so
    /// that a body of mass m made of this shape has moment of inertia I = m · unit_inertia
    /// about its origin. A disk or capsule of radius 0 gives the limit (a point, a rod).
    ///
    /// # Errors
    /// [`KinematicsError::NoMassProperties`] for a half-plane or a polyline.
    pub fn unit_inertia(&self) -> Result<f64, KinematicsError> {
        match self {
            Shape::Disk { center, radius } => {
                Ok(radius * radius / 2.0 + V::from(*center).norm_squared())
            }
            Shape::Capsule { a, b, radius: r } => {
                // The rectangle of length L and width 2r, and the two half-disks whose flat
                // sides sit at ±L/2 from the centre, about the capsule's centre.
                let l = (V::from(*b) - V::from(*a)).norm();
                let unit = if *r == 0.0 {
                    l * l / 12.0
                } else {
                    let j = r * l * (l * l + 4.0 * r * r) / 6.0
                        + PI * r.powi(4) / 2.0
                        + 4.0 * l * r.powi(3) / 3.0
                        + PI * r * r * l * l / 4.0;
                    j / self.area()
                };
                Ok(unit + V::from(self.centroid()).norm_squared())
            }
            Shape::Polygon { vertices: points } | Shape::Profile { points } => {
                let (area, _, j) = polygon_moments(points);
                Ok(j / area)
            }
            Shape::HalfPlane { .. } | Shape::Polyline { .. } => {
                Err(KinematicsError::NoMassProperties { shape: self.name(), what: "unit inertia" })
            }
        }
    }

    /// The world bounding box of the shape at `pose`. A half-plane's box is bounded only
    /// along an axis that its normal is exactly parallel to.
    pub fn aabb(&self, pose: &Pose) -> Aabb {
        self.aabb_placed(&Placement::new(pose))
    }

    /// [`Shape::aabb`] of the shape so placed.
    // Inlined into each caller, which has just built `frame`: called, it read the placement
    // back from the stack as wider loads than the stores that wrote it, and waited for them.
    #[inline(always)]
    pub fn aabb_placed(&self, frame: &Placement) -> Aabb {
        /// The box around the body points `points` grown by `r`.
        #[inline(always)]
        fn around<'p>(
            frame: &Placement,
            points: impl IntoIterator<Item = &'p [f64; 2]>,
            r: f64,
        ) -> Aabb {
            let mut min = V::repeat(f64::INFINITY);
            let mut max = V::repeat(f64::NEG_INFINITY);
            for p in points {
                let p = frame.point(*p);
                min = min.inf(&p);
                max = max.sup(&p);
            }
            Aabb { min: [min.x - r, min.y - r], max: [max.x + r, max.y + r] }
        }
        match self {
            Shape::Disk { center, radius } => around(frame, [center], *radius),
            Shape::Capsule { a, b, radius } => around(frame, [a, b], *radius),
            Shape::Polygon { vertices: points }
            | Shape::Polyline { points }
            | Shape::Profile { points } => around(frame, points, 0.0),
            Shape::HalfPlane { point, normal } => {
                let p = frame.point(*point);
                let n = frame.vector(*normal);
                let inf = f64::INFINITY;
                let mut aabb = Aabb { min: [-inf, -inf], max: [inf, inf] };
                if n.x == 0.0 {
                    if n.y > 0.0 {
                        aabb.max[1] = p.y;
                    } else {
                        aabb.min[1] = p.y;
                    }
                } else if n.y == 0.0 {
                    if n.x > 0.0 {
                        aabb.max[0] = p.x;
                    } else {
                        aabb.min[0] = p.x;
                    }
                }
                aabb
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The first crossing by testing every pair of non-neighbouring segments in the order of
    /// (i, j).
    fn every_pair(points: &[[f64; 2]]) -> Option<usize> {
        let n = points.len();
        let p = |i: usize| V::from(points[i % n]);
        (0..n)
            .flat_map(|i| (i + 2..n).map(move |j| (i, j)))
            .filter(|&(i, j)| !(i == 0 && j == n - 1))
            .find(|&(i, j)| segments_meet(p(i), p(i + 1), p(j), p(j + 1)))
            .map(|(_, j)| j)
    }

    /// A star-shaped contour: the point k at angle 2πk/n and radius r_k.
    fn star(radii: &[f64]) -> Vec<[f64; 2]> {
        let n = radii.len() as f64;
        radii
            .iter()
            .enumerate()
            .map(|(k, r)| {
                let a = 2.0 * PI * k as f64 / n;
                [r * a.cos(), r * a.sin()]
            })
            .collect()
    }

    #[test]
    fn a_sampled_circle_is_simple_and_a_folded_one_is_not() {
        let circle = star(&[1.0; 20_000]);
        assert_eq!(first_crossing(&circle), None);
        // Point 10,000 (at (-1, 0)) moved across the circle to (1.5, 0.001): its two segments
        // come back through the circle's right side, and the first pair they form is segment 2
        // (from the angle 2 × 2π/20,000 to 3 × 2π/20,000) with segment 9,999.
        let mut folded = circle.clone();
        folded[10_000] = [1.5, 0.001];
        assert_eq!(first_crossing(&folded), Some(9_999));
        assert_eq!(every_pair(&folded), Some(9_999));
    }

    proptest! {
        // Random contours (most cross themselves many times) and star-shaped ones with points
        // on a coarse grid (so that segments touch, overlap and share points exactly): the
        // sweep finds the same first crossing as the test of every pair.
        #[test]
        fn the_sweep_finds_the_first_crossing_of_every_pair(
            points in prop::collection::vec((-4i32..=4, -4i32..=4), 3..24),
            radii in prop::collection::vec(1u8..=4, 3..40),
        ) {
            let random: Vec<[f64; 2]> =
                points.iter().map(|&(x, y)| [f64::from(x), f64::from(y)]).collect();
            prop_assert_eq!(first_crossing(&random), every_pair(&random));
            let star = star(&radii.iter().map(|&r| f64::from(r)).collect::<Vec<_>>());
            let grid: Vec<[f64; 2]> =
                star.iter().map(|p| [(2.0 * p[0]).round(), (2.0 * p[1]).round()]).collect();
            prop_assert_eq!(first_crossing(&star), every_pair(&star));
            prop_assert_eq!(first_crossing(&grid), every_pair(&grid));
        }
    }
}
