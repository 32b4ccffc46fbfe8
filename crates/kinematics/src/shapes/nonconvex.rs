//! Contacts with chains of segments: polylines (open, two-sided) and profiles (closed solids),
//! against a convex shape or a half-plane.
//!
//! Written here because parry2d-f64 has no contact for a chain that keeps each local minimum of
//! the distance as its own point: its polyline is a composite shape whose per-segment contacts
//! would repeat a shared vertex, and a shape against a non-convex profile needs the inside of a
//! solid, which parry has only as a point query (`point_in_poly2d`, or a polyline's projection
//! assuming a solid interior) on vertices it owns. Each segment is a convex core and goes
//! through the convex pair's method; what is added here is the naming of the points, the
//! removal of the repeats at shared vertices and of the vertex points that are not local
//! minima of the distance, and the solid behind a profile's segments.
//!
//! A segment alone is thin: a capsule whose axis has crossed it, or a polygon more than half across
//! it, is separated from it most by a face of its own on the far side, which pushes it further in
//! or, past the segment's ends, gives no point. So a capsule or polygon that has entered a profile
//! is pushed out as a face of a convex solid pushes it (a half-plane's, a polygon's by separating
//! axes): where that far face would separate it most from a segment behind whose line one of its
//! core vertices lies inside the solid (the parity of a ray's crossings), the reference is the
//! segment's face or a face of the shape within 60° of facing it if the core crosses the segment,
//! and the segment gives no point if the core lies wholly behind it; a core wholly inside, crossing
//! no segment, leaves by the segment whose line its deepest vertex is least deep behind. Elsewhere
//! (shallow contacts, faces resting on a chain, concave corners, a core outside behind a thin part
//! of the solid) nothing changes, and the test costs two comparisons per segment in the shape's
//! band of heights (the parity of one vertex) and a product where a face turned away from the solid
//! separates most.

use super::collide::manifold_point;
use super::convex::{
    Backs, Core, CorePoint, Feature, closest_to_point, deepest_against, point_pair,
    polygon_contacts, reference_contacts, solid_segment_contacts,
};
use super::shape::{Placement, V};
use super::{Aabb, ChainIndex, ManifoldPoint};

/// The slope, relative to a segment's length, below which two chain points count as level.
const LEVEL: f64 = 1e-9;

/// A polyline's or a profile's points, closed for a profile, placed at `frame`, with the
/// index of its runs of segments when it has one.
pub(crate) struct Chain<'a> {
    pub points: &'a [[f64; 2]],
    pub closed: bool,
    pub frame: &'a Placement,
    pub index: Option<&'a ChainIndex>,
}

impl<'a> Chain<'a> {
    /// The chain's segments k (from point k to point k + 1) in runs whose world box `keep`
    /// accepts, in increasing order: every segment, in one run, without an index.
    fn runs<F: Fn(&Aabb) -> bool + 'a>(
        &self,
        keep: F,
    ) -> impl Iterator<Item = std::ops::Range<usize>> + use<'a, F> {
        let p = self.points.len();
        let m = if self.closed { p } else { p - 1 };
        let (indexed, whole) = match self.index {
            Some(ix) => (Some(ix.runs(self.frame, keep)), None),
            None => (None, Some(0..m)),
        };
        indexed.into_iter().flatten().chain(whole)
    }
}

/// A convex shape `x` (its world box `x_box`) against `chain`; `x_is_a` tells which of A and B
/// the convex shape is.
pub(crate) fn convex_chain(
    x: &Core<'_>,
    x_box: Aabb,
    chain: &Chain<'_>,
    x_is_a: bool,
    margin: f64,
    out: &mut Vec<ManifoldPoint>,
) {
    let (points, closed, frame) = (chain.points, chain.closed, chain.frame);
    let p = points.len();
    let m = if closed { p } else { p - 1 };
    let n_x = x.len();
    // A polygon's or capsule's face normals, found once for all the segments it meets.
    let x = &if n_x > 1 { x.with_normals() } else { *x };
    let start = out.len();
    let point = |v: usize| frame.point(points[v % p]);
    let vertex_id = |v: usize| m * n_x + v % p;
    let flip = !x_is_a;

    if closed && n_x == 1 && inside(x.vertex(0), chain) {
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

    // A capsule or polygon against a profile: whether its core has entered the solid. The
    // parity of core vertex 0 is counted along the loop, over the segments in its band of
    // heights; the others are counted only when a segment asks ([`entered`]).
    let solid = closed && n_x > 1;
    let c0 = x.vertex(0);
    let mut odd = false;
    let mut crossed = false;
    let mut parity = Parity::default();
    // The last few ways out taken, so that the segments of one overlap that lead to the same
    // way out give its points once.
    let mut taken = [(usize::MAX, None); 4];
    let mut next_taken = 0;
    let mut climbed: Option<Climb> = None;
    // Segments off the convex shape's box (grown by the margin) are passed over. Vertex 0
    // lies in that box, so those above or below it or to its left cannot cross the ray from
    // vertex 0 towards +x: only the few in its band of heights count for the parity. An
    // indexed chain passes over the runs of segments whose box fails the same test, and,
    // where no parity is counted, the runs wholly to the right of the shape's box too.
    let grow = margin + 1e-12;
    let off = |lo: [f64; 2], hi: [f64; 2]| {
        hi[1] < x_box.min[1] - grow || lo[1] > x_box.max[1] + grow || hi[0] < x_box.min[0] - grow
    };
    let right = |lo: [f64; 2]| lo[0] > x_box.max[0] + grow;
    for run in chain.runs(|b| !off(b.min, b.max) && (solid || !right(b.min))) {
        let mut p1 = point(run.start);
        for k in run {
            let p0 = p1;
            p1 = point(k + 1);
            if off([p0.x.min(p1.x), p0.y.min(p1.y)], [p0.x.max(p1.x), p0.y.max(p1.y)]) {
                continue;
            }
            if solid && (p0.y > c0.y) != (p1.y > c0.y) && crosses(c0, p0, p1) {
                odd = !odd;
            }
            if right([p0.x.min(p1.x), p0.y.min(p1.y)]) {
                continue;
            }
            let ends = [points[k], points[(k + 1) % p]];
            let seg = Core::new(&ends, *frame, 0.0, closed);
            let mut emit =
                |cp: CorePoint| emit_point(x, &cp, k, &point, p, closed, start, flip, out);
            if n_x == 1 {
                if let Some(cp) =
                    super::convex::point_contact(x.vertex(0), x.radius, &seg, true, margin)
                {
                    emit(cp);
                }
            } else if closed {
                // Across the segment (the core crossing it: no face separating them and a vertex
                // on or in front of its line; or a core that has entered the solid reaching it by
                // its radius), the shape meets the solid around it: the reference is found from
                // there ([`way_out_near`]) in place of the segment's own.
                let mut across: Option<(Across, bool)> = None;
                let mut backs = |sep: f64, back: bool| {
                    let line = Across::of(p0, p1);
                    let reach = |h: f64| (0..n_x).any(|i| line.height(x.vertex(i)) >= h);
                    let front = sep <= 0.0 && reach(0.0);
                    if front
                        || sep <= x.radius
                            && reach(-x.radius)
                            && entered(x, &line, &mut parity, chain) == Backs::Drop
                    {
                        across = Some((line, front));
                        Backs::Drop
                    } else if back {
                        entered(x, &line, &mut parity, chain)
                    } else {
                        Backs::Count
                    }
                };
                solid_segment_contacts(x, &seg, margin, &mut backs, &mut emit);
                if let Some((line, front)) = across {
                    // The core crosses the segment if a vertex lies on or in front of its line.
                    crossed = crossed || front || (0..n_x).any(|i| line.height(x.vertex(i)) >= 0.0);
                    let way = way_out_near(x, k, line, &point, m, &mut climbed);
                    if !taken.contains(&way) {
                        taken[next_taken % taken.len()] = way;
                        next_taken += 1;
                        let (j, face) = way;
                        let ends = [points[j], points[(j + 1) % p]];
                        let seg = Core::new(&ends, *frame, 0.0, true);
                        let mut emit = |cp: CorePoint| {
                            emit_point(x, &cp, j, &point, p, closed, start, flip, out)
                        };
                        reference_contacts(x, &seg, face, margin, &mut emit);
                    }
                }
            } else {
                polygon_contacts(x, &seg, margin, &mut emit);
            }
        }
    }
    if solid && odd && !crossed {
        // The whole core inside the solid, crossing none of its segments: what the loop found
        // within the margin held it in. It is pushed out through the segment it would leave
        // by the shortest way, as a face of a convex solid would push it.
        out.truncate(start);
        let k = way_out(x, &point, m);
        let ends = [points[k], points[(k + 1) % p]];
        let seg = Core::new(&ends, *frame, 0.0, true);
        let mut emit = |cp: CorePoint| emit_point(x, &cp, k, &point, p, closed, start, flip, out);
        solid_segment_contacts(
            x,
            &seg,
            margin,
            &mut |_: f64, back: bool| if back { Backs::Skip } else { Backs::Count },
            &mut emit,
        );
        if out.len() == start
            && let Some(cp) = deepest_against(&seg, x, margin)
        {
            emit_point(x, &cp, k, &point, p, closed, start, flip, out);
        }
    }
}

/// Appends the point `cp` of the convex core `x` (which is A) with segment k of the chain of
/// p points, named: vertex i of `x` on the segment k·n + i, chain point v m·n + v if [`kept`]
/// and not already among the points from `start` on; A and B swapped when `flip`.
fn emit_point(
    x: &Core<'_>,
    cp: &CorePoint,
    k: usize,
    point: &impl Fn(usize) -> V,
    p: usize,
    closed: bool,
    start: usize,
    flip: bool,
    out: &mut Vec<ManifoldPoint>,
) {
    let n_x = x.len();
    let m = if closed { p } else { p - 1 };
    let id = match cp.on_b {
        Feature::Edge(_) => match cp.on_a {
            Feature::Vertex(i) => k * n_x + i,
            Feature::Edge(_) => unreachable!("a point has a vertex"),
        },
        Feature::Vertex(local) => {
            let v = k + local;
            if !kept(x, cp, v, k + 1 - local, point, p, closed) {
                return;
            }
            m * n_x + v % p
        }
    };
    let id32 = id as u32;
    if out[start..].iter().all(|q| q.feature != id32) {
        out.push(manifold_point(cp, id, flip));
    }
}

/// The line of a segment from p0 to p1 of a counter-clockwise chain, with its outward normal.
struct Across {
    p0: V,
    e: V,
    normal: V,
}

impl Across {
    fn of(p0: V, p1: V) -> Self {
        let e = p1 - p0;
        Self { p0, e, normal: V::new(e.y, -e.x) / e.norm() }
    }

    /// The height of `v` above the line, positive on the outward side.
    fn height(&self, v: V) -> f64 {
        self.normal.dot(&(v - self.p0))
    }

    /// Where `v` projects along the segment: 0 at p0, 1 at p1.
    fn along(&self, v: V) -> f64 {
        (v - self.p0).dot(&self.e) / self.e.norm_squared()
    }
}

/// Whether the core vertices of a convex shape lie inside a profile, each counted once on
/// demand; vertices from the 64th on are counted on every demand.
#[derive(Default)]
struct Parity {
    known: u64,
    inside: u64,
}

impl Parity {
    fn inside(&mut self, i: usize, c: V, chain: &Chain<'_>) -> bool {
        if i >= 64 {
            return inside(c, chain);
        }
        let bit = 1u64 << i;
        if self.known & bit == 0 {
            self.known |= bit;
            if inside(c, chain) {
                self.inside |= bit;
            }
        }
        self.inside & bit != 0
    }
}

/// What the contact of the convex core `x` with the profile's segment on `line` does when a
/// back face of `x` separates them most and the core does not cross the segment ([`Backs`]). If
/// a core vertex behind the segment's line lies inside the solid, `x` has entered the solid, and
/// the segment lies behind the core: its point would push the core further in, so it gives none
/// (the segment may still be the way out from a segment the core crosses, [`way_out_near`]).
/// Otherwise (the core outside, behind a segment of a thin part of the solid, or resting on a
/// sharp corner) the face counts as any other.
fn entered(x: &Core<'_>, line: &Across, parity: &mut Parity, chain: &Chain<'_>) -> Backs {
    let entered = (0..x.len()).any(|i| {
        let v = x.vertex(i);
        line.height(v) < 0.0 && parity.inside(i, v, chain)
    });
    if entered { Backs::Drop } else { Backs::Count }
}

/// The 2-d cross product.
#[inline]
fn cross(a: V, b: V) -> f64 {
    a.x * b.y - a.y * b.x
}

/// The segment and reference face through which the convex core `x`, overlapping segment `k`
/// (on `line`) of the profile (m segments through `point`), leaves the solid: the least deep of the
/// separating axes of the locally convex part of the solid around the segment, as for a
/// convex polygon. Those axes are the segment's half-plane (the depth of the core's deepest
/// vertex behind its line), the half-plane of each neighbour met at a convex corner, and each
/// face of `x` whose reversed normal lies between the normals of the two segments at a convex
/// end (the face's separation from that corner). A face of `x` is the reference on the segment
/// of the two at its corner more opposed to it; a neighbour's half-plane less deep than the
/// others makes the neighbour the segment, and its own axes are compared in turn, so that the
/// way out climbs to the least deep half-plane near the overlap, whether or not the core
/// crosses that segment. Returns the segment and the face of `x` (`None`: the segment's face).
/// `climbed` is the last climb, whose segments all lead to its way out: a climb that reaches it
/// takes its way out, and it is extended by, or replaced with, each new climb.
fn way_out_near(
    x: &Core<'_>,
    k: usize,
    line: Across,
    point: &impl Fn(usize) -> V,
    m: usize,
    climbed: &mut Option<Climb>,
) -> (usize, Option<usize>) {
    let deepest = |line: &Across| {
        (0..x.len()).map(|i| line.height(x.vertex(i))).fold(f64::INFINITY, f64::min)
    };
    let tie = |s: f64| 1e-12 * (1.0 + s.abs());
    let start = k;
    let (mut forward, mut steps) = (true, 0);
    let mut k = k;
    let mut line = line;
    let mut own = deepest(&line);
    for _ in 0..m {
        if let Some(c) = *climbed
            && let Some(rest) = c.from(k, m)
        {
            if steps > 0 {
                let steps = if forward == c.forward { steps + rest } else { steps };
                *climbed = Some(Climb { start, forward, steps, way: c.way });
            }
            return c.way;
        }
        // (separation, face of x, the segment it meets) of the faces of x at a convex end, and
        // (depth, segment, line) of the neighbours there.
        let mut face: Option<(f64, usize, usize)> = None;
        let mut next: Option<(f64, usize, Across)> = None;
        for end in 0..2 {
            let (w, j, other) = if end == 0 {
                let j = (k + m - 1) % m;
                (line.p0, j, Across::of(point(j), line.p0))
            } else {
                let j = (k + 1) % m;
                let w = point(k + 1);
                (w, j, Across::of(w, point(j + 1)))
            };
            let (n_in, n_out) =
                if end == 0 { (other.normal, line.normal) } else { (line.normal, other.normal) };
            if cross(n_in, n_out) <= 0.0 {
                // A concave or straight corner: the solid goes on behind the segment's line.
                continue;
            }
            for f in 0..x.faces() {
                let (a, _, n) = x.face(f);
                if cross(n_in, -n) >= 0.0 && cross(-n, n_out) >= 0.0 {
                    let s = n.dot(&(w - a));
                    if face.is_none_or(|b| s > b.0) {
                        // The point lies on the segment more opposed to the face.
                        let on = if other.normal.dot(&n) < line.normal.dot(&n) { j } else { k };
                        face = Some((s, f, on));
                    }
                }
            }
            let h = deepest(&other);
            if next.as_ref().is_none_or(|b| h > b.0) {
                next = Some((h, j, other));
            }
        }
        // A face of x keeps the reference unless the segment's separates clearly more, as
        // between two cores; a neighbour takes the way out only if clearly less deep.
        let (best, way) = match face {
            Some((s, f, on)) if s >= own - tie(own) => (s, (on, Some(f))),
            _ => (own, (k, None)),
        };
        match next {
            Some((h, j, other)) if h > best + tie(best) => {
                // A climb keeps its direction: the segment it left is deeper than this one.
                forward = j == (k + 1) % m;
                steps += 1;
                (k, line, own) = (j, other, h);
            }
            _ => {
                *climbed = Some(Climb { start, forward, steps, way });
                return way;
            }
        }
    }
    (k, None)
}

/// A climb of [`way_out_near`]: from segment `start`, `steps` segments forward (in the order of
/// the chain) or backward, to the way out `way`.
#[derive(Clone, Copy)]
struct Climb {
    start: usize,
    forward: bool,
    steps: usize,
    way: (usize, Option<usize>),
}

impl Climb {
    /// If segment k (of m) lies on the climb, the number of steps left from it.
    fn from(&self, k: usize, m: usize) -> Option<usize> {
        let offset = if self.forward { (k + m - self.start) % m } else { (self.start + m - k) % m };
        (offset <= self.steps).then(|| self.steps - offset)
    }
}

/// The segment of the profile (m segments through `point`) through which the convex core `x`,
/// lying wholly inside the solid, leaves it by the shortest way: of the segments whose line has
/// the whole core behind it and onto which the core projects, the one its deepest vertex is
/// least deep behind; if there is none, the segment nearest to a core vertex.
fn way_out(x: &Core<'_>, point: &impl Fn(usize) -> V, m: usize) -> usize {
    let mut best: Option<(f64, usize)> = None;
    let mut nearest = (f64::INFINITY, 0);
    for k in 0..m {
        let line = Across::of(point(k), point(k + 1));
        let (mut low, mut high) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut first, mut last) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..x.len() {
            let v = x.vertex(i);
            let (h, t) = (line.height(v), line.along(v));
            (low, high) = (low.min(h), high.max(h));
            (first, last) = (first.min(t), last.max(t));
            let q = line.p0 + t.clamp(0.0, 1.0) * line.e;
            let d = (v - q).norm();
            if d < nearest.0 {
                nearest = (d, k);
            }
        }
        if high < 0.0 && last >= 0.0 && first <= 1.0 && best.is_none_or(|b| -low < b.0) {
            best = Some((-low, k));
        }
    }
    best.map_or(nearest.1, |b| b.1)
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

/// Whether the world point `c` lies inside the closed `chain`, by the parity of the crossings
/// of a ray towards +x: of the segments whose heights span c's and that reach to its right
/// (on an indexed chain, in the runs whose box does).
fn inside(c: V, chain: &Chain<'_>) -> bool {
    let (points, frame) = (chain.points, chain.frame);
    let p = points.len();
    let mut odd = false;
    let spans = |b: &Aabb| b.min[1] <= c.y && c.y <= b.max[1] && c.x <= b.max[0];
    for run in chain.runs(spans) {
        let mut a = frame.point(points[run.start]);
        for k in run {
            let b = frame.point(points[(k + 1) % p]);
            if (a.y > c.y) != (b.y > c.y) && crosses(c, a, b) {
                odd = !odd;
            }
            a = b;
        }
    }
    odd
}

/// Whether the ray from `c` towards +x crosses the segment from a to b, whose ends lie on
/// either side of the ray's line.
#[inline]
fn crosses(c: V, a: V, b: V) -> bool {
    c.x < a.x + (c.y - a.y) / (b.y - a.y) * (b.x - a.x)
}

/// A half-plane (boundary through `origin`, unit outward normal `n`) against `chain`: each
/// point at most `margin` above the boundary that lies on it
/// ([`on_face`]): a local minimum of the height along the chain (every point of a flat run),
/// or the far end of the chord lying on the boundary there.
pub(crate) fn half_plane_chain(
    origin: V,
    n: V,
    chain: &Chain<'_>,
    plane_is_a: bool,
    margin: f64,
    out: &mut Vec<ManifoldPoint>,
) {
    let (points, closed, frame) = (chain.points, chain.closed, chain.frame);
    let p = points.len();
    let point = |v: usize| frame.point(points[v % p]);
    let height = |v: usize| n.dot(&(point(v) - origin));
    let neighbours = |w: usize| neighbours(w, p, closed);
    // The rise of point w over point `from` above the boundary, per unit length.
    let rise = |from: usize, w: usize| (height(w) - height(from)) / (point(w) - point(from)).norm();
    // On an indexed chain, the runs whose box lies wholly above the margin are passed over:
    // the lowest height in a box is its centre's less the half-widths along |n|. The
    // vertices of a run of segments k0..k1 are k0..k1, and the last point too on a polyline.
    let low = |b: &Aabb| {
        let c = V::new(0.5 * (b.min[0] + b.max[0]), 0.5 * (b.min[1] + b.max[1]));
        let w = [0.5 * (b.max[0] - b.min[0]), 0.5 * (b.max[1] - b.min[1])];
        let size = c.x.abs().max(c.y.abs()) + origin.x.abs().max(origin.y.abs()) + w[0] + w[1];
        n.dot(&(c - origin)) - n.x.abs() * w[0] - n.y.abs() * w[1] <= margin + 1e-10 * size
    };
    for run in chain.runs(low) {
        let vertices = if !closed && run.end == p - 1 { run.start..p } else { run };
        for v in vertices {
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
}
