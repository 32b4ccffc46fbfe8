//! Contacts with chains of segments: polylines (open, two-sided) and profiles (closed solids),
//! against a convex shape or a half-plane.
//!
//! Written here because parry2d-f64 has no contact for a chain that keeps each local minimum of
//! the distance as its own point: its polyline is a composite shape whose per-segment contacts
//! would repeat a shared vertex, and a disk against a non-convex profile needs the inside test
//! of a solid, which parry's polyline (a curve) lacks. Each segment is a convex core and goes
//! through the convex pair's method; what is added here is the naming of the points, the
//! removal of the repeats at shared vertices and of the vertex points that are not local
//! minima of the distance.

use super::collide::manifold_point;
use super::convex::{Core, CorePoint, Feature, closest_to_point, point_pair, polygon_contacts};
use super::shape::{Placement, V};
use super::{Aabb, ManifoldPoint};

/// The slope, relative to a segment's length, below which two chain points count as level.
const LEVEL: f64 = 1e-9;

/// A convex shape `x` (its world box `x_box`) against the chain through `points` (closed for a
/// profile) at `frame`; `x_is_a` tells which of A and B the convex shape is.
pub(crate) fn convex_chain(
    x: &Core<'_>,
    x_box: Aabb,
    points: &[[f64; 2]],
    closed: bool,
    frame: &Placement,
    x_is_a: bool,
    margin: f64,
    out: &mut Vec<ManifoldPoint>,
) {
    let p = points.len();
    let m = if closed { p } else { p - 1 };
    let n_x = x.len();
    let start = out.len();
    let point = |v: usize| frame.point(points[v % p]);
    let vertex_id = |v: usize| m * n_x + v % p;
    let flip = !x_is_a;

    if closed && n_x == 1 && inside(x.vertex(0), frame, points) {
        // A disk whose centre has entered the solid: one point, on the nearest segment, with
        // the direction reversed so that the gap −(d + r) grows as the disk comes out.
        let c = x.vertex(0);
        let mut best: Option<(V, V, f64, usize, Feature)> = None;
        for k in 0..m {
            let ends = [points[k], points[(k + 1) % p]];
            let seg = Core::new(&ends, *frame, 0.0, true);
            let (q, dir, d, feature) = closest_to_point(&seg, c);
            if best.is_none_or(|b| d < b.2) {
                best = Some((q, dir, d, k, feature));
            }
        }
        if let Some((q, dir, d, k, feature)) = best {
            let cp = point_pair(c, x.radius, q, 0.0, -dir, -d, feature, true);
            if cp.gap <= margin {
                let id = match feature {
                    Feature::Vertex(local) => vertex_id(k + local),
                    Feature::Edge(_) => k,
                };
                out.push(manifold_point(&cp, id, flip));
            }
        }
        return;
    }

    let mut p1 = point(0);
    for k in 0..m {
        let p0 = p1;
        p1 = point(k + 1);
        let grow = margin + 1e-12;
        if p0.x.max(p1.x) < x_box.min[0] - grow
            || p0.x.min(p1.x) > x_box.max[0] + grow
            || p0.y.max(p1.y) < x_box.min[1] - grow
            || p0.y.min(p1.y) > x_box.max[1] + grow
        {
            continue;
        }
        let ends = [points[k], points[(k + 1) % p]];
        let seg = Core::new(&ends, *frame, 0.0, closed);
        let mut emit = |cp: CorePoint| {
            let id = match cp.on_b {
                Feature::Edge(_) => match cp.on_a {
                    Feature::Vertex(i) => k * n_x + i,
                    Feature::Edge(_) => unreachable!("a point has a vertex"),
                },
                Feature::Vertex(local) => {
                    let v = k + local;
                    if !kept(x, &cp, v, k + 1 - local, &point, p, closed) {
                        return;
                    }
                    vertex_id(v)
                }
            };
            let id32 = id as u32;
            if out[start..].iter().all(|q| q.feature != id32) {
                out.push(manifold_point(&cp, id, flip));
            }
        };
        if n_x == 1 {
            if let Some(cp) =
                super::convex::point_contact(x.vertex(0), x.radius, &seg, true, margin)
            {
                emit(cp);
            }
        } else {
            polygon_contacts(x, &seg, margin, &mut emit);
        }
    }
}

/// Whether chain point v, in contact `cp` with the convex core `x` (which is A) through the
/// segment from v to `u`, is kept, so that its point is not a repeat of a neighbouring
/// segment's. For a disk: the centre does not project inside a segment next to v. For a
/// polygon or capsule: v lies on its face ([`on_face`]), at a local minimum of the distance or
/// at the far end of that segment when it is the chord lying on the face.
fn kept(
    x: &Core<'_>,
    cp: &CorePoint,
    v: usize,
    u: usize,
    point: &impl Fn(usize) -> V,
    p: usize,
    closed: bool,
) -> bool {
    let neighbours = |w: usize| neighbours(w % p, p, closed);
    if x.len() == 1 {
        // A disk: the centre does not project inside a segment next to v.
        let (c, here) = (x.vertex(0), point(v));
        return neighbours(v).into_iter().flatten().all(|w| {
            let e = point(w) - here;
            (c - here).dot(&e) / e.norm_squared() <= 0.0
        });
    }
    // The rise of chain point w over chain point `from` along the normal, per unit length.
    let n = cp.normal;
    let rise = |from: usize, w: usize| {
        let e = point(w) - point(from);
        n.dot(&e) / e.norm()
    };
    on_face(v % p, [Some(u % p), None], &neighbours, &rise)
}

/// The points before and after point w of a chain of p points (none past an open chain's
/// ends).
fn neighbours(w: usize, p: usize, closed: bool) -> [Option<usize>; 2] {
    [(closed || w > 0).then(|| (w + p - 1) % p), (closed || w + 1 < p).then(|| (w + 1) % p)]
}

/// Whether chain point v lies on a flat face (of a polygon, a capsule or a half-plane's
/// boundary), given the rise per unit length of one chain point over another towards the
/// face's outside: when v is a local minimum of the distance (a neighbour level with it to
/// rounding, both ends of a chord lying flat on the face, does not disqualify it), or the far
/// end of the chord at a local minimum u among `us` that is the flatter of u's two chords (to
/// rounding). The far end closes as soon as the face turns onto the chord: a box declared as a
/// profile rests on both corners, as the same box declared as a polygon does.
fn on_face(
    v: usize,
    us: [Option<usize>; 2],
    neighbours: &impl Fn(usize) -> [Option<usize>; 2],
    rise: &impl Fn(usize, usize) -> f64,
) -> bool {
    let minimum = |w: usize| neighbours(w).into_iter().flatten().all(|q| rise(w, q) >= -LEVEL);
    minimum(v)
        || us.into_iter().flatten().any(|u| {
            minimum(u)
                && neighbours(u)
                    .into_iter()
                    .flatten()
                    .filter(|&w| w != v)
                    .all(|w| rise(u, v) <= rise(u, w) + LEVEL)
        })
}

/// Whether the world point `c` lies inside the closed chain through `points` at `frame`, by
/// the parity of the crossings of a ray towards +x.
fn inside(c: V, frame: &Placement, points: &[[f64; 2]]) -> bool {
    let p = points.len();
    let mut odd = false;
    let mut a = frame.point(points[p - 1]);
    for q in points {
        let b = frame.point(*q);
        if (a.y > c.y) != (b.y > c.y) && c.x < a.x + (c.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            odd = !odd;
        }
        a = b;
    }
    odd
}

/// A half-plane (boundary through `origin`, unit outward normal `n`) against the chain through
/// `points` at `frame`: each point at most `margin` above the boundary that lies on it
/// ([`on_face`]): a local minimum of the height along the chain (every point of a flat run),
/// or the far end of the chord lying on the boundary there.
pub(crate) fn half_plane_chain(
    origin: V,
    n: V,
    points: &[[f64; 2]],
    closed: bool,
    frame: &Placement,
    plane_is_a: bool,
    margin: f64,
    out: &mut Vec<ManifoldPoint>,
) {
    let p = points.len();
    let point = |v: usize| frame.point(points[v % p]);
    let height = |v: usize| n.dot(&(point(v) - origin));
    let neighbours = |w: usize| neighbours(w, p, closed);
    // The rise of point w over point `from` above the boundary, per unit length.
    let rise = |from: usize, w: usize| (height(w) - height(from)) / (point(w) - point(from)).norm();
    for v in 0..p {
        let h = height(v);
        if h > margin {
            continue;
        }
        if on_face(v, neighbours(v), &neighbours, &rise) {
            let w = frame.point(points[v]);
            let cp = CorePoint {
                on_a: Feature::Edge(0),
                on_b: Feature::Vertex(v),
                point_a: w - h * n,
                point_b: w,
                normal: n,
                gap: h,
            };
            out.push(manifold_point(&cp, v, !plane_is_a));
        }
    }
}
