//! Contacts between two rounded convex cores: a point, a segment or a convex polygon, each
//! grown by a radius (a disk, a capsule, a polygon; a segment of a polyline or a profile).
//!
//! Written here rather than taken from parry2d-f64 for two reasons. Parry's polygon manifolds
//! clip the incident face against the reference face and give both clipped points the reference
//! face's normal; a point clipped at a reference vertex then slides along the incident face, and
//! its gap's rate differs from the normal relative velocity by that sliding times the sine of
//! the angle between the faces, which the time-stepper's w_N cannot carry. Here each point is a
//! vertex against the line of an edge, with that edge's own normal, or a pair of closest points.
//! And parry's polygons own their vertices: building one from a [`super::Shape`] per call
//! would allocate, where these cores borrow the shape's slices.

use super::shape::{Placement, V};

/// Right-hand normal of an edge direction: outward for a counter-clockwise polygon.
#[inline]
fn outward(e: V) -> V {
    V::new(e.y, -e.x)
}

/// How far past its ends a vertex may project and still count as on an edge, as a fraction of
/// the edge's length: the rounding that two coincident corners (a stack of equal boxes) need
/// to give one point, not two or none.
const EDGE_SLACK: f64 = 1e-9;

/// How many world vertices a core keeps at hand; larger polygons map theirs on each use.
const CACHED: usize = 8;

/// A convex core in the world: its vertices (body frame), its radius, and whether, as a
/// segment, it is touched from its outward side only (an edge of a profile). The world
/// vertices of a small core are mapped once, since every method below visits them many times.
#[derive(Clone, Copy)]
pub(crate) struct Core<'a> {
    vertices: &'a [[f64; 2]],
    frame: Placement,
    pub radius: f64,
    one_sided: bool,
    world: [V; CACHED],
    normals: [V; CACHED],
    has_normals: bool,
}

/// A feature of a core: a vertex, or an edge (edge i runs from vertex i to vertex i + 1; a
/// two-sided segment's edge 1 is its back, from vertex 1 to vertex 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Feature {
    Vertex(usize),
    Edge(usize),
}

/// One contact point between cores A and B, before the caller names it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CorePoint {
    pub on_a: Feature,
    pub on_b: Feature,
    pub point_a: V,
    pub point_b: V,
    pub normal: V,
    pub gap: f64,
}

impl<'a> Core<'a> {
    pub fn new(vertices: &'a [[f64; 2]], frame: Placement, radius: f64, one_sided: bool) -> Self {
        let mut world = [V::zeros(); CACHED];
        if vertices.len() <= CACHED {
            for (w, v) in world.iter_mut().zip(vertices) {
                *w = frame.point(*v);
            }
        }
        let normals = [V::zeros(); CACHED];
        Self { vertices, frame, radius, one_sided, world, normals, has_normals: false }
    }

    /// The same core with the unit normals of its faces at hand, for the methods that visit
    /// each face many times (a half-plane or a point needs none of them); a core that has them
    /// keeps them.
    pub fn with_normals(&self) -> Self {
        let n = self.len();
        let mut core = *self;
        if !self.has_normals && (2..=CACHED).contains(&n) {
            // A segment's second face is its first reversed.
            let faces = if n == 2 { 1 } else { n };
            for i in 0..faces {
                core.normals[i] = outward(self.world[(i + 1) % n] - self.world[i]).normalize();
            }
            core.has_normals = true;
        }
        core
    }

    /// This core if its face normals are at hand (or it needs none), else a copy with them
    /// ([`Self::with_normals`]): no copy for a core that has them.
    fn normals_at_hand(&self) -> std::borrow::Cow<'_, Self> {
        if self.has_normals || !(2..=CACHED).contains(&self.len()) {
            std::borrow::Cow::Borrowed(self)
        } else {
            std::borrow::Cow::Owned(self.with_normals())
        }
    }

    pub fn len(&self) -> usize {
        self.vertices.len()
    }

    #[inline]
    pub fn vertex(&self, i: usize) -> V {
        if self.vertices.len() <= CACHED {
            self.world[i]
        } else {
            self.frame.point(self.vertices[i])
        }
    }

    /// The number of faces that can be touched: a polygon's edges, a segment's two sides or
    /// its outward side alone.
    pub fn faces(&self) -> usize {
        match self.len() {
            1 => 0,
            2 if self.one_sided => 1,
            2 => 2,
            n => n,
        }
    }

    /// The ends (start, end) of face i, and its unit outward normal.
    #[inline]
    pub fn face(&self, i: usize) -> (V, V, V) {
        let n = self.len();
        let (p, q) = if n == 2 && i == 1 {
            (self.vertex(1), self.vertex(0))
        } else {
            (self.vertex(i), self.vertex((i + 1) % n))
        };
        let normal = match (self.has_normals, n == 2 && i == 1) {
            (true, false) => self.normals[i],
            (true, true) => -self.normals[0],
            (false, _) => outward(q - p).normalize(),
        };
        (p, q, normal)
    }

    /// The indices of the vertices of face i, in the order of [`Self::face`].
    fn face_vertices(&self, i: usize) -> (usize, usize) {
        let n = self.len();
        if n == 2 && i == 1 { (1, 0) } else { (i, (i + 1) % n) }
    }
}

/// The closest point of core `c` to the point `p`, the unit direction from that point towards
/// `p` (the outward normal of `c` there), the signed distance (negative inside a polygon) and
/// the feature of `c` it lies on.
pub(crate) fn closest_to_point(c: &Core<'_>, p: V) -> (V, V, f64, Feature) {
    if c.len() == 1 {
        let q = c.vertex(0);
        let d = p - q;
        let l = d.norm();
        // Two coincident centres have no direction between them; any unit vector serves.
        let dir = if l > 0.0 { d / l } else { V::new(1.0, 0.0) };
        return (q, dir, l, Feature::Vertex(0));
    }
    if c.len() > 2 {
        // Inside, the face of least penetration; outside, the closest edge below.
        let mut best = (f64::NEG_INFINITY, 0);
        for i in 0..c.faces() {
            let (a, _, n) = c.face(i);
            let s = n.dot(&(p - a));
            if s > best.0 {
                best = (s, i);
            }
        }
        if best.0 <= 0.0 {
            let (_, _, n) = c.face(best.1);
            return (p - best.0 * n, n, best.0, Feature::Edge(best.1));
        }
    }
    let mut best: Option<(V, f64, Feature, usize)> = None;
    let edges = if c.len() == 2 { 1 } else { c.len() };
    for i in 0..edges {
        let (a, b, _) = c.face(i);
        let e = b - a;
        let t = (p - a).dot(&e) / e.norm_squared();
        let (q, feature) = if t <= 0.0 {
            (a, Feature::Vertex(c.face_vertices(i).0))
        } else if t >= 1.0 {
            (b, Feature::Vertex(c.face_vertices(i).1))
        } else {
            (a + t * e, Feature::Edge(i))
        };
        let d2 = (p - q).norm_squared();
        if best.is_none_or(|b| d2 < b.1) {
            best = Some((q, d2, feature, i));
        }
    }
    let (q, d2, feature, i) = best.expect("a segment or polygon has an edge");
    let l = d2.sqrt();
    let dir = if l > 0.0 {
        (p - q) / l
    } else {
        // On the segment itself: its front side's normal.
        c.face(i).2
    };
    (q, dir, l, feature)
}

/// The single contact of the world point `p` grown by `radius` (a disk, or a core's vertex)
/// with any core, if its gap is at most `margin`; `point_is_a` tells which of A and B the point
/// is.
pub(crate) fn point_contact(
    p: V,
    radius: f64,
    other: &Core<'_>,
    point_is_a: bool,
    margin: f64,
) -> Option<CorePoint> {
    let (q, dir, s, feature) = closest_to_point(other, p);
    let gap = s - radius - other.radius;
    (gap <= margin).then(|| point_pair(p, radius, q, other.radius, dir, s, feature, point_is_a))
}

/// The contact of a point `p` of radius `r_p` with the point `q` of another core of radius
/// `r_q` that lies on its `feature`, `dir` the outward normal of that core at q and `s` the
/// signed distance of p from it along `dir`.
pub(crate) fn point_pair(
    p: V,
    r_p: f64,
    q: V,
    r_q: f64,
    dir: V,
    s: f64,
    feature: Feature,
    point_is_a: bool,
) -> CorePoint {
    let gap = s - r_p - r_q;
    let on_point = p - r_p * dir;
    let on_other = q + r_q * dir;
    if point_is_a {
        CorePoint {
            on_a: Feature::Vertex(0),
            on_b: feature,
            point_a: on_point,
            point_b: on_other,
            normal: -dir,
            gap,
        }
    } else {
        CorePoint {
            on_a: feature,
            on_b: Feature::Vertex(0),
            point_a: on_other,
            point_b: on_point,
            normal: dir,
            gap,
        }
    }
}

/// The face of `c` whose separation from the vertices of `other` is greatest, and that
/// separation: the signed distance, along the face's normal, of `other`'s deepest vertex.
fn max_separation(c: &Core<'_>, other: &Core<'_>) -> (f64, usize) {
    max_separation_among(c, other, |_| true)
}

/// [`max_separation`] over the faces of `c` whose outward normal `n` passes `keep(n)`
/// (−∞ when none does).
#[inline(always)]
fn max_separation_among(c: &Core<'_>, other: &Core<'_>, keep: impl Fn(V) -> bool) -> (f64, usize) {
    let mut best = (f64::NEG_INFINITY, 0);
    for i in 0..c.faces() {
        let (a, _, n) = c.face(i);
        if !keep(n) {
            continue;
        }
        let mut s = f64::INFINITY;
        for j in 0..other.len() {
            s = s.min(n.dot(&(other.vertex(j) - a)));
        }
        if s > best.0 {
            best = (s, i);
        }
    }
    best
}

/// The face of `c` most opposed to the direction `n`.
fn incident_face(c: &Core<'_>, n: V) -> usize {
    let mut best = (f64::INFINITY, 0);
    for i in 0..c.faces() {
        let d = c.face(i).2.dot(&n);
        if d < best.0 {
            best = (d, i);
        }
    }
    best.1
}

/// Vertex `vertex` of one core against face `face` of the other, as seen from the face's core
/// (`face_core`): its gap along the face's normal, if it projects within the face (widened by
/// `slack` of its length at each end) and the gap is at most `margin`. `face_is_a` tells which
/// of A and B owns the face.
fn vertex_on_face(
    face_core: &Core<'_>,
    face: usize,
    vertex_core: &Core<'_>,
    vertex: usize,
    face_is_a: bool,
    slack: (f64, f64),
    margin: f64,
) -> Option<CorePoint> {
    let (a, b, n) = face_core.face(face);
    let v = vertex_core.vertex(vertex);
    let e = b - a;
    let t = (v - a).dot(&e) / e.norm_squared();
    if !(t >= slack.0 && t <= 1.0 - slack.1) {
        return None;
    }
    let distance = n.dot(&(v - a));
    let gap = distance - face_core.radius - vertex_core.radius;
    if gap > margin {
        return None;
    }
    let on_face = v - distance * n + face_core.radius * n;
    let on_vertex = v - vertex_core.radius * n;
    Some(if face_is_a {
        CorePoint {
            on_a: Feature::Edge(face),
            on_b: Feature::Vertex(vertex),
            point_a: on_face,
            point_b: on_vertex,
            normal: n,
            gap,
        }
    } else {
        CorePoint {
            on_a: Feature::Vertex(vertex),
            on_b: Feature::Edge(face),
            point_a: on_vertex,
            point_b: on_face,
            normal: -n,
            gap,
        }
    })
}

/// The cosine of the largest angle between an incident face and the reversed reference
/// normal at which the reference face's ends are taken on the incident face (60°).
const FACING: f64 = 0.5;

/// What the contact of a core A with a profile's segment B does when the face of A that
/// separates them most is a back face of A (one whose outward normal has a positive component
/// along B's: the solid lies behind B, so such a face separates A from the segment but not from
/// the solid, and the point it gives pushes A into the solid through B), or when A and B overlap
/// (no face separates them), where the caller may take the reference from the solid around B.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Backs {
    /// The face counts as any other: A meets B as a thin segment.
    Count,
    /// A has entered the solid through B: only the faces of A within 60° of facing B count
    /// besides B's, so that the reference is B's face or a face of A turned towards the solid
    /// and the points push A out through B.
    Skip,
    /// No point from B: its reference would be the back face, which pushes A in, or the caller
    /// takes the points of the overlap from the solid around B.
    Drop,
}

/// The contact points of two cores of at least two vertices each (segments, polygons) whose
/// gaps are at most `margin`, passed to `emit`: the vertex-on-edge points of the pair of faces
/// that separates them most (two for a face on a face), the closest pair when they are apart,
/// and, if none of these, the pair of closest features.
pub(crate) fn polygon_contacts(
    a: &Core<'_>,
    b: &Core<'_>,
    margin: f64,
    emit: &mut impl FnMut(CorePoint),
) {
    contacts(a, b, margin, None, emit);
}

/// [`polygon_contacts`] of a core A with B, a segment of a profile (one-sided, the solid behind
/// its outward face): when the face of A that separates them most is a back face, or when they
/// overlap (every separation of the cores at most the sum of the radii), `backs` is asked, told
/// the cores' greatest separation and whether that face is a back face, what to do ([`Backs`]).
/// With [`Backs::Skip`] the pair of closest features, which would still hold A in, gives way to
/// A's deepest vertex against the line of B.
pub(crate) fn solid_segment_contacts(
    a: &Core<'_>,
    b: &Core<'_>,
    margin: f64,
    backs: &mut dyn FnMut(f64, bool) -> Backs,
    emit: &mut impl FnMut(CorePoint),
) {
    contacts(a, b, margin, Some(backs), emit);
}

/// [`polygon_contacts`], with B a profile's segment when `backs` is given
/// ([`solid_segment_contacts`]).
fn contacts(
    a: &Core<'_>,
    b: &Core<'_>,
    margin: f64,
    backs: Option<&mut dyn FnMut(f64, bool) -> Backs>,
    emit: &mut impl FnMut(CorePoint),
) {
    let (a, b) = (&*a.normals_at_hand(), &*b.normals_at_hand());
    let radii = a.radius + b.radius;
    let (mut sep_a, mut face_a) = max_separation(a, b);
    let (sep_b, face_b) = max_separation(b, a);
    // A keeps the reference face unless B's separates clearly more, so that two parallel faces
    // (equal separations) do not trade roles from one call to the next.
    let tie = |sep_a: f64| 1e-12 * (1.0 + sep_a.abs().max(sep_b.abs()));
    let mut inside = false;
    if let Some(backs) = backs {
        let out = b.face(0).2;
        let back = !(sep_b > sep_a + tie(sep_a)) && a.face(face_a).2.dot(&out) > 0.0;
        let sep = sep_a.max(sep_b);
        if back || sep - radii <= 0.0 {
            match backs(sep, back) {
                Backs::Count => {}
                Backs::Drop => return,
                Backs::Skip => {
                    (sep_a, face_a) = max_separation_towards(a, b, out);
                    inside = true;
                }
            }
        }
    }
    if sep_a.max(sep_b) - radii > margin {
        return;
    }
    let scale = tie(sep_a);
    let (ref_is_a, ref_face) = if sep_b > sep_a + scale { (false, face_b) } else { (true, face_a) };
    // Cores apart: their closest pair always counts, whether or not it is a vertex on one of
    // the two faces below (two corners facing each other are not).
    let closest = if sep_a.max(sep_b) > 0.0 { closest_features(a, b, margin) } else { None };
    face_points(a, b, ref_is_a, ref_face, closest, inside, margin, emit);
}

/// The points of cores A and B that overlap, with face `face` of A (if `face` is given) or
/// face 0 of B, a profile's segment, as the reference face: those of [`polygon_contacts`] for
/// that reference, and if there are none, A's deepest vertex against the line of B (B's face)
/// or the deepest pair of closest features (A's).
pub(crate) fn reference_contacts(
    a: &Core<'_>,
    b: &Core<'_>,
    face: Option<usize>,
    margin: f64,
    emit: &mut impl FnMut(CorePoint),
) {
    let (a, b) = (&*a.normals_at_hand(), &*b.normals_at_hand());
    face_points(a, b, face.is_some(), face.unwrap_or(0), None, face.is_none(), margin, emit);
}

/// The vertex-on-edge points of the reference face `ref_face` (of A if `ref_is_a`, else of B)
/// and the face of the other core most opposed to it, after the closest pair `closest` if
/// given; if none, the deepest pair of closest features, or for A inside a solid (`inside`)
/// A's deepest vertex against the line of B.
fn face_points(
    a: &Core<'_>,
    b: &Core<'_>,
    ref_is_a: bool,
    ref_face: usize,
    closest: Option<CorePoint>,
    inside: bool,
    margin: f64,
    emit: &mut impl FnMut(CorePoint),
) {
    let (reference, incident) = if ref_is_a { (a, b) } else { (b, a) };
    let normal = reference.face(ref_face).2;
    let inc_face = incident_face(incident, normal);
    let (i0, i1) = incident.face_vertices(inc_face);
    let (r0, r1) = reference.face_vertices(ref_face);
    // Points of the same vertex as the closest pair would repeat it.
    let mut found = 0;
    if let Some(p) = closest {
        emit(p);
        found += 1;
    }
    let mut emit_new = |p: CorePoint, found: &mut usize| {
        if closest.is_none_or(|c| vertex_key(&c) != vertex_key(&p)) {
            emit(p);
            *found += 1;
        }
    };
    // The incident face's ends on the reference face, closed at both ends; then the reference
    // face's ends on the incident face, open at both ends, so that two coincident corners
    // give one point.
    let closed = (-EDGE_SLACK, -EDGE_SLACK);
    let open = (EDGE_SLACK, EDGE_SLACK);
    for v in [i0, i1] {
        if let Some(p) = vertex_on_face(reference, ref_face, incident, v, ref_is_a, closed, margin)
        {
            emit_new(p, &mut found);
        }
    }
    // Only a face that faces the reference face can be met by its ends (two faces on each
    // other). Behind a face at an angle θ from facing it, the reference's end can lie as deep as
    // the cores' overlap over cos θ: a profile's side (a one-sided segment, which may even
    // face away) or a segment standing upright would count a box's corner 1 m away as 1 m deep.
    // Within 60° of facing it, that depth is at most twice the overlap; a corner on a steeper
    // face is the incident face's end on the reference face, found above.
    if incident.face(inc_face).2.dot(&normal) <= -FACING {
        for v in [r0, r1] {
            if let Some(p) =
                vertex_on_face(incident, inc_face, reference, v, !ref_is_a, open, margin)
            {
                emit_new(p, &mut found);
            }
        }
    }
    // Cores that overlap with no vertex inside the other's face: the deepest pair of closest
    // features still holds them apart; for A inside a solid, A's deepest vertex against the
    // line of B pushes it out.
    if found == 0 {
        let deepest =
            if inside { deepest_against(b, a, margin) } else { closest_features(a, b, margin) };
        if let Some(p) = deepest {
            emit(p);
        }
    }
}

/// [`max_separation`] of `c` from `other` over the faces of `c` within 60° of facing the
/// direction `out` (their normals' component along `out` at most −[`FACING`]): those that can
/// push `c` out of a solid through a face of outward normal `out`. A face standing square to
/// it would push `c` along the face, as if the solid ended at the face's ends, where a short
/// segment of a sampled outline ends but the solid does not.
fn max_separation_towards(c: &Core<'_>, other: &Core<'_>, out: V) -> (f64, usize) {
    max_separation_among(c, other, |n| n.dot(&out) <= -FACING)
}

/// The deepest vertex of `a` (which is A) against the line of face 0 of `b`, wherever along
/// the line it projects, if its gap is at most `margin`.
pub(crate) fn deepest_against(b: &Core<'_>, a: &Core<'_>, margin: f64) -> Option<CorePoint> {
    let (p, _, n) = b.face(0);
    let deepest = (0..a.len())
        .min_by(|&i, &j| n.dot(&(a.vertex(i) - p)).total_cmp(&n.dot(&(a.vertex(j) - p))))?;
    let anywhere = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    vertex_on_face(b, 0, a, deepest, false, anywhere, margin)
}

/// The vertex that names a point: A's if the point is at a vertex of A, else B's.
fn vertex_key(p: &CorePoint) -> (bool, usize) {
    match (p.on_a, p.on_b) {
        (Feature::Vertex(i), _) => (true, i),
        (_, Feature::Vertex(j)) => (false, j),
        (Feature::Edge(_), Feature::Edge(_)) => unreachable!("a point has a vertex"),
    }
}

/// The pair of closest points of two cores that no vertex-on-edge point caught: two corners
/// facing each other, or the ends of two capsules in line. Each vertex of one core against each
/// edge of the other, the closest pair kept.
fn closest_features(a: &Core<'_>, b: &Core<'_>, margin: f64) -> Option<CorePoint> {
    let mut best: Option<CorePoint> = None;
    let mut consider = |vertex_core: &Core<'_>, other: &Core<'_>, vertex_is_a: bool| {
        for i in 0..vertex_core.len() {
            let (v, r) = (vertex_core.vertex(i), vertex_core.radius);
            if let Some(mut p) = point_contact(v, r, other, vertex_is_a, f64::INFINITY) {
                if vertex_is_a {
                    p.on_a = Feature::Vertex(i);
                } else {
                    p.on_b = Feature::Vertex(i);
                }
                if best.is_none_or(|q| p.gap < q.gap) {
                    best = Some(p);
                }
            }
        }
    };
    consider(a, b, true);
    consider(b, a, false);
    best.filter(|p| p.gap <= margin)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::Pose;

    fn square() -> [[f64; 2]; 4] {
        [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
    }

    #[test]
    fn closest_point_of_a_polygon_outside_at_a_corner_and_inside() {
        let v = square();
        let c = Core::new(&v, Placement::new(&Pose::default()), 0.0, false);
        // Beside a face: its interior, at distance 0.5.
        let (q, dir, s, f) = closest_to_point(&c, V::new(1.5, 0.2));
        assert_eq!(f, Feature::Edge(1));
        assert!((q - V::new(1.0, 0.2)).norm() < 1e-15 && (dir - V::new(1.0, 0.0)).norm() < 1e-15);
        assert!((s - 0.5).abs() < 1e-15);
        // Beyond a corner: the corner, at distance 5.
        let (q, _, s, f) = closest_to_point(&c, V::new(4.0, 5.0));
        assert_eq!((q, s, f), (V::new(1.0, 1.0), 5.0, Feature::Vertex(2)));
        // Inside: the face of least penetration, negative.
        let (q, dir, s, f) = closest_to_point(&c, V::new(0.1, -0.7));
        assert_eq!((dir, f), (V::new(0.0, -1.0), Feature::Edge(0)));
        assert!((s + 0.3).abs() < 1e-15 && (q - V::new(0.1, -1.0)).norm() < 1e-15);
    }

    #[test]
    fn a_one_sided_segment_has_one_face_and_a_two_sided_one_two() {
        let ends = [[0.0, 0.0], [1.0, 0.0]];
        let frame = Placement::new(&Pose::default());
        let one = Core::new(&ends, frame, 0.0, true);
        let two = Core::new(&ends, frame, 0.0, false);
        assert_eq!((one.faces(), two.faces()), (1, 2));
        // Edge 0 of a segment from (0, 0) to (1, 0) faces −y (outward of a CCW chain).
        assert_eq!(one.face(0).2, V::new(0.0, -1.0));
        assert_eq!(two.face(1).2, V::new(0.0, 1.0));
        assert_eq!(two.face_vertices(1), (1, 0));
    }

    #[test]
    fn corners_facing_each_other_give_their_closest_pair() {
        // Two unit squares, the second moved by (3, 4) from the first's corner (1, 1).
        let v = square();
        let a = Core::new(&v, Placement::new(&Pose::default()), 0.0, false);
        let b = Core::new(&v, Placement::new(&Pose::new(5.0, 6.0, 0.0)), 0.0, false);
        let mut points = Vec::new();
        polygon_contacts(&a, &b, 10.0, &mut |p| points.push(p));
        let closest = points.iter().map(|p| p.gap).fold(f64::INFINITY, f64::min);
        assert!((closest - 5.0).abs() < 1e-14);
        let p = points.iter().find(|p| p.gap == closest).unwrap();
        assert!((p.normal - V::new(0.6, 0.8)).norm() < 1e-15);
        assert_eq!((p.on_a, p.on_b), (Feature::Vertex(2), Feature::Vertex(0)));
    }
}
