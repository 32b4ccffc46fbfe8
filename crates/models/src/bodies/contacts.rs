//! Contacts between shapes: the fixed list of slots (one per pair of shapes and feature), and
//! their gaps and force directions from the kinematics' narrow phase at each (q, t).
//!
//! Each pair of shapes that may touch gets `max_points` slots at build time, one per feature
//! id, so that a slot's index names the same contact (a vertex on an edge, say) from step to
//! step, for warm starts and records. At (q, t) a pair whose bounding boxes are farther apart
//! than its margin reports their distance, a positive lower bound of its gap, for every slot
//! without calling the narrow phase; otherwise `collide` fills the slots of the features it
//! finds within the margin and the others report the margin. A slot with a positive gap is
//! open, and the stepper leaves it out of the step's problem.

use std::cell::RefCell;

use moreau_kinematics::{
    Aabb, KinematicsError, ManifoldPoint, Placement, Shape, collide, collide_indexed, max_points,
};
use moreau_setvalued::ContactLaw;

use super::body::{Body, Frame, Kind};
use super::build::{bad, law, resolve};
use super::joints::SlotGeometry;
use super::multibody::{Multibody, Slot};
use super::spec::SystemSpec;
use crate::ModelError;
use crate::params::positive;

/// A pair of shapes with slots `first..first + count`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Pair {
    pub a: usize,
    pub shape_a: usize,
    pub b: usize,
    pub shape_b: usize,
    pub margin: f64,
    pub first: usize,
    pub count: usize,
    /// The world boxes of shapes a and b when their bodies are fixed, computed once.
    pub fixed_boxes: [Option<Aabb>; 2],
}

thread_local! {
    /// The narrow phase's output, reused by every call on this thread so that a step does not
    /// allocate once the buffer has grown to the largest manifold.
    static POINTS: RefCell<Vec<ManifoldPoint>> = RefCell::new(Vec::with_capacity(16));
}

/// The Euclidean distance between two boxes, 0 when they overlap.
fn box_distance(a: &Aabb, b: &Aabb) -> f64 {
    let dx = (a.min[0] - b.max[0]).max(b.min[0] - a.max[0]).max(0.0);
    let dy = (a.min[1] - b.max[1]).max(b.min[1] - a.max[1]).max(0.0);
    // Boxes apart along one axis only (always so against an axis-aligned half-plane): the
    // distance is that one, which `hypot` would return exactly, without its call.
    if dx == 0.0 {
        dy
    } else if dy == 0.0 {
        dx
    } else {
        dx.hypot(dy)
    }
}

/// The default margin of a pair: 1 % of the smaller finite bounding-box diagonal at t = 0.
fn default_margin(boxes: [&Aabb; 2]) -> f64 {
    let size = |b: &Aabb| (b.max[0] - b.min[0]).hypot(b.max[1] - b.min[1]);
    let sizes = boxes.map(size);
    let smallest =
        sizes.into_iter().filter(|s| s.is_finite() && *s > 0.0).fold(f64::INFINITY, f64::min);
    if smallest.is_finite() { 0.01 * smallest } else { 1e-3 }
}

/// One explicit contact, resolved: shape `shape_a` of body `a` against shape `shape_b` of body
/// `b`, oriented as declared (the normal points from a towards b).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Explicit {
    pub a: usize,
    pub shape_a: usize,
    pub b: usize,
    pub shape_b: usize,
    pub margin: Option<f64>,
    pub law: ContactLaw,
    pub name: String,
}

impl Explicit {
    /// Whether this contact joins shape `sa` of body `a` and shape `sb` of body `b`, in either
    /// order.
    fn joins(&self, a: usize, sa: usize, b: usize, sb: usize) -> bool {
        (self.a, self.shape_a, self.b, self.shape_b) == (a, sa, b, sb)
            || (self.b, self.shape_b, self.a, self.shape_a) == (a, sa, b, sb)
    }
}

/// Which pairs of shapes are in contact and under which law: the explicit contacts, and the
/// automatic ones when declared. Both contact sets read the scene through these rules, so that
/// a fixed slot and a detected contact exist for the same pairs with the same laws.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Rules {
    pub explicit: Vec<Explicit>,
    /// The automatic contacts' default law and margin, if declared.
    pub auto: Option<(ContactLaw, Option<f64>)>,
    /// The laws of particular pairs of bodies among the automatic contacts.
    pub overrides: Vec<(usize, usize, ContactLaw)>,
    /// The pairs of bodies connected by a joint, which get no automatic contact.
    pub jointed: Vec<(usize, usize)>,
}

impl Rules {
    /// Validates the contacts of a declaration and resolves their bodies.
    pub fn new(
        spec: &SystemSpec,
        bodies: &mut Vec<Body>,
        jointed: Vec<(usize, usize)>,
    ) -> Result<Self, ModelError> {
        let mut explicit: Vec<Explicit> = Vec::new();
        for c in &spec.contacts {
            let path = format!("contacts.{}", c.name);
            let a = resolve(bodies, &format!("{path}.body_a"), &c.body_a)?;
            let b = resolve(bodies, &format!("{path}.body_b"), &c.body_b)?;
            for (side, body, shape) in [("shape_a", a, c.shape_a), ("shape_b", b, c.shape_b)] {
                let n = bodies[body].shapes.len();
                if shape >= n {
                    return Err(bad(
                        format!("{path}.{side}"),
                        &shape.to_string(),
                        match n {
                            0 => format!("body `{}` has no shapes", bodies[body].name),
                            1 => format!("body `{}` has one shape, shape 0", bodies[body].name),
                            _ => format!(
                                "body `{}` has {n} shapes, numbered from 0 to {}",
                                bodies[body].name,
                                n - 1
                            ),
                        },
                    ));
                }
            }
            if a == b {
                return Err(bad(
                    format!("{path}.body_b"),
                    &c.body_b,
                    "a contact needs two bodies".to_owned(),
                ));
            }
            if !bodies[a].is_dynamic() && !bodies[b].is_dynamic() {
                // Its impulse would move nothing, and its step problem would have no solution
                // once the two bodies meet.
                return Err(bad(
                    format!("{path}.body_b"),
                    &c.body_b,
                    "a contact needs at least one dynamic body".to_owned(),
                ));
            }
            if let Some(m) = c.margin {
                positive(&format!("{path}.margin"), m)?;
            }
            // A second contact between the same two shapes would close with the first: the
            // step problem would split their impulse at will, and the friction taken would be
            // the larger of their laws', not either one's.
            if let Some(first) = explicit.iter().find(|e| e.joins(a, c.shape_a, b, c.shape_b)) {
                return Err(bad(
                    format!("{path}.body_b"),
                    &c.body_b,
                    format!(
                        "contact `{}` is already between these two shapes (shape {} of `{}` and \
                         shape {} of `{}`); declare each pair of shapes once",
                        first.name, c.shape_a, c.body_a, c.shape_b, c.body_b
                    ),
                ));
            }
            explicit.push(Explicit {
                a,
                shape_a: c.shape_a,
                b,
                shape_b: c.shape_b,
                margin: c.margin,
                law: law(&path, c.eps_n, c.eps_t, c.mu)?,
                name: c.name.clone(),
            });
        }
        let mut rules = Rules { explicit, auto: None, overrides: Vec::new(), jointed };
        let Some(auto) = &spec.contacts_auto else { return Ok(rules) };
        if let Some(m) = auto.margin {
            positive("contacts_auto.margin", m)?;
        }
        rules.auto = Some((law("contacts_auto", auto.eps_n, auto.eps_t, auto.mu)?, auto.margin));
        for (k, o) in auto.overrides.iter().enumerate() {
            let path = format!("contacts_auto.overrides.{k}");
            let a = resolve(bodies, &format!("{path}.bodies.0"), &o.bodies[0])?;
            let b = resolve(bodies, &format!("{path}.bodies.1"), &o.bodies[1])?;
            // An override that no automatic pair takes would be dropped without a word.
            let refuse = |why: String| Err(bad(format!("{path}.bodies.1"), &o.bodies[1], why));
            if let Some(reason) = rules.excluded(bodies, a, b) {
                return refuse(format!("{reason}: the pair gets no automatic contact"));
            }
            let (ba, bb) = (&bodies[a], &bodies[b]);
            let shape_pairs = (0..ba.shapes.len())
                .flat_map(|sa| (0..bb.shapes.len()).map(move |sb| (sa, sb)))
                .collect::<Vec<_>>();
            if shape_pairs.iter().all(|&(sa, sb)| rules.explicit(a, sa, b, sb).is_some()) {
                return refuse(
                    "explicit contacts already join every shape of the two bodies, under their \
                     own laws: the pair gets no automatic contact"
                        .to_owned(),
                );
            }
            let same =
                |&(x, y, _): &(usize, usize, ContactLaw)| (x, y) == (a, b) || (y, x) == (a, b);
            if let Some(k) = rules.overrides.iter().position(same) {
                return refuse(format!(
                    "contacts_auto.overrides.{k} already gives the laws of `{}` and `{}`",
                    o.bodies[0], o.bodies[1]
                ));
            }
            rules.overrides.push((a, b, law(&path, o.eps_n, o.eps_t, o.mu)?));
        }
        Ok(rules)
    }

    /// The explicit contact between shape `sa` of body `a` and shape `sb` of body `b`, in
    /// either order.
    pub fn explicit(&self, a: usize, sa: usize, b: usize, sb: usize) -> Option<&Explicit> {
        self.explicit.iter().find(|e| e.joins(a, sa, b, sb))
    }

    /// Why bodies a and b get no automatic contact, whatever the shapes, or `None` when they
    /// may: the same body, the collision groups exclude the pair, neither has coordinates, or
    /// a joint connects them.
    #[inline]
    fn excluded(&self, bodies: &[Body], a: usize, b: usize) -> Option<&'static str> {
        let (ba, bb) = (&bodies[a], &bodies[b]);
        if a == b {
            Some("the same body as bodies.0: a body has no contact with itself")
        } else if ba.group & bb.mask == 0 || bb.group & ba.mask == 0 {
            Some("the collision groups and masks exclude the pair")
        } else if !(ba.is_dynamic() || bb.is_dynamic()) {
            Some("neither body is dynamic")
        } else if self.jointed.iter().any(|&(x, y)| (x, y) == (a, b) || (y, x) == (a, b)) {
            Some("a joint connects the two bodies")
        } else {
            None
        }
    }

    /// The law of the automatic contacts between bodies a and b, or `None` when they get none:
    /// no automatic contacts declared, or [`Self::excluded`] gives a reason.
    pub fn automatic(&self, bodies: &[Body], a: usize, b: usize) -> Option<ContactLaw> {
        let (default, _) = self.auto?;
        if self.excluded(bodies, a, b).is_some() {
            return None;
        }
        let same = |&(x, y, _): &(usize, usize, ContactLaw)| (x, y) == (a, b) || (y, x) == (a, b);
        Some(self.overrides.iter().find(|o| same(o)).map_or(default, |o| o.2))
    }
}

/// Adds the slots of the explicit and the automatic contacts, their laws and names, for the
/// fixed contact set: one pair per explicit contact and per pair of shapes the automatic
/// contacts allow, each with `max_points` slots.
///
/// # Numbering
/// The slots follow those of the clearance joints (`<joint>` for a revolute one,
/// `<joint>.corner1` .. `.corner4` for a translational one): first the explicit contacts in
/// declaration order, then the automatic pairs, by body a then body b (a before b in the
/// order of `[[bodies]]`, then the `[[fill]]` bodies), then by shape index on a, then on b.
/// Shape a is A: the explicit contact's `body_a`, or the automatic pair's earlier body.
///
/// Within a pair, slot `first + k` holds the narrow phase's feature k
/// (`moreau_kinematics::collide`), the same feature at every step, whether or not it touches:
/// * a disk against anything: one slot, the pair of closest points;
/// * a polygon (n vertices, in their declared counter-clockwise order) or a capsule (n = 2:
///   end `a`, then end `b`) on a half-plane: n slots, slot k the polygon's vertex k on the
///   boundary. A box with vertices declared from its lower left corner counter-clockwise and
///   resting flat on a floor closes slots 0 and 1, its lower corners;
/// * two polygons or capsules with n_A and n_B vertices: n_A + n_B slots, slot i vertex i of A
///   on a face of B, slot n_A + j vertex j of B on a face of A. Faces get no slot of their
///   own: a face resting on a face closes the slots of the two corners that bound the contact
///   (either shape's), and two corners facing each other across a gap use the slot of A's;
/// * a polyline or profile of p points on a half-plane: p slots, slot v its point v;
/// * a disk, capsule or polygon with n core vertices against a polyline or profile of m
///   segments and p points: m n + p slots, slot k n + i vertex i on segment k, slot m n + v
///   the chain's point v against the convex shape.
///
/// A pair's slots are named `<name>` when it has one and `<name>.<k>` otherwise, where the
/// name is the explicit contact's or `<body a>.<shape a>-<body b>.<shape b>`: a box `box`
/// (shape 0) declared after a floor `floor` (shape 0) with automatic contacts has slots
/// `floor.0-box.0.0` .. `floor.0-box.0.3`, its vertices 0 to 3.
pub(crate) fn pairs(
    rules: &Rules,
    bodies: &[Body],
    slots: &mut Vec<Slot>,
    laws: &mut Vec<ContactLaw>,
    names: &mut Vec<String>,
) -> Result<Vec<Pair>, ModelError> {
    let mut pairs = Vec::new();
    let initial = |i: usize| {
        let body = &bodies[i];
        match body.kind {
            Kind::Dynamic { .. } => Frame::at(body.pose0, [0.0; 2], 0.0, None),
            _ => body.frame(&[], 0.0),
        }
    };
    // Adds one pair after checking that the narrow phase supports it.
    let mut add = |path: &str,
                   (a, shape_a, b, shape_b): (usize, usize, usize, usize),
                   margin: Option<f64>,
                   contact_law: ContactLaw,
                   name: &str|
     -> Result<(), ModelError> {
        let (sa, sb) = (&bodies[a].shapes[shape_a], &bodies[b].shapes[shape_b]);
        let (fa, fb) = (initial(a), initial(b));
        let (ba, bb) = (sa.aabb(&fa.pose()), sb.aabb(&fb.pose()));
        let margin = margin.unwrap_or_else(|| default_margin([&ba, &bb]));
        let mut probe = Vec::new();
        collide(sa, &fa.pose(), sb, &fb.pose(), margin, &mut probe)
            .map_err(|e| bad(path.to_owned(), name, e.to_string()))?;
        let count = max_points(sa, sb);
        let index = pairs.len();
        let fixed = |i: usize, bx: Aabb| matches!(bodies[i].kind, Kind::Fixed(_)).then_some(bx);
        let fixed_boxes = [fixed(a, ba), fixed(b, bb)];
        pairs.push(Pair { a, shape_a, b, shape_b, margin, first: slots.len(), count, fixed_boxes });
        for k in 0..count {
            slots.push(Slot::Pair { pair: index, feature: k });
            laws.push(contact_law);
            names.push(if count == 1 { name.to_owned() } else { format!("{name}.{k}") });
        }
        Ok(())
    };
    for e in &rules.explicit {
        let path = format!("contacts.{}", e.name);
        add(&path, (e.a, e.shape_a, e.b, e.shape_b), e.margin, e.law, &e.name)?;
    }
    let n = bodies.len();
    for a in 0..n {
        for b in a + 1..n {
            let Some(contact_law) = rules.automatic(bodies, a, b) else { continue };
            let margin = rules.auto.and_then(|(_, m)| m);
            for sa in 0..bodies[a].shapes.len() {
                for sb in 0..bodies[b].shapes.len() {
                    if rules.explicit(a, sa, b, sb).is_some() {
                        continue;
                    }
                    let name = format!("{}.{sa}-{}.{sb}", bodies[a].name, bodies[b].name);
                    add("contacts_auto", (a, sa, b, sb), margin, contact_law, &name)?;
                }
            }
        }
    }
    Ok(pairs)
}

impl Multibody {
    /// The narrow phase of shape `sa` of body `a` placed at `pa` with shape `sb` of body `b`
    /// placed at `pb`, the pair's chain (if one is) with its index of runs: the points within
    /// `margin` appended to `out`.
    ///
    /// # Errors
    /// Those of [`collide_indexed`], for a pair or a margin the narrow phase refuses.
    // Always inlined: a call of its own cost the declared woodpecker 1.3 % of its instructions
    // per step (callgrind), and the ball 11 of its 1,178.
    #[inline(always)]
    pub(crate) fn collide_shapes(
        &self,
        (a, sa, pa): (usize, usize, &Placement),
        (b, sb, pb): (usize, usize, &Placement),
        margin: f64,
        out: &mut Vec<ManifoldPoint>,
    ) -> Result<(), KinematicsError> {
        let (body_a, body_b) = (&self.bodies[a], &self.bodies[b]);
        let chain = body_a.chain(sa).or_else(|| body_b.chain(sb));
        collide_indexed(&body_a.shapes[sa], pa, &body_b.shapes[sb], pb, chain, margin, out)
    }

    /// Calls `emit(feature, geometry)` for every slot of a pair at the bodies' frames: the
    /// narrow phase's points, and for the features it does not find, the margin (or the
    /// bounding boxes' distance) as the gap with a zero normal, which gives zero force
    /// directions.
    #[inline]
    pub(crate) fn pair_slots(
        &self,
        pair: &Pair,
        fa: &Frame,
        fb: &Frame,
        mut emit: impl FnMut(usize, SlotGeometry),
    ) {
        let (sa, sb): (&Shape, &Shape) =
            (&self.bodies[pair.a].shapes[pair.shape_a], &self.bodies[pair.b].shapes[pair.shape_b]);
        let (pa, pb) = (fa.placement(), fb.placement());
        let [box_a, box_b] = pair.fixed_boxes;
        let far = box_distance(
            &box_a.unwrap_or_else(|| sa.aabb_placed(&pa)),
            &box_b.unwrap_or_else(|| sb.aabb_placed(&pb)),
        );
        let open = SlotGeometry { gap: far.max(pair.margin), ..SlotGeometry::default() };
        if far > pair.margin {
            (0..pair.count).for_each(|k| emit(k, open));
            return;
        }
        POINTS.with(|cell| {
            let mut points = cell.borrow_mut();
            points.clear();
            // A pair was accepted at build time, so the narrow phase cannot refuse it; should it
            // still fail, the gaps are not numbers and the stepper stops with a typed error.
            let (a, b) = ((pair.a, pair.shape_a, &pa), (pair.b, pair.shape_b, &pb));
            if self.collide_shapes(a, b, pair.margin, &mut points).is_err() {
                let failed = SlotGeometry { gap: f64::NAN, ..SlotGeometry::default() };
                (0..pair.count).for_each(|k| emit(k, failed));
                return;
            }
            let mut seen = 0u64;
            for p in points.iter() {
                let k = p.feature as usize;
                if k < pair.count {
                    if k < 64 {
                        seen |= 1 << k;
                    }
                    emit(
                        k,
                        SlotGeometry {
                            point_a: p.point_a,
                            point_b: p.point_b,
                            normal: p.normal,
                            gap: p.gap,
                        },
                    );
                }
            }
            for k in 0..pair.count {
                let found = if k < 64 {
                    seen & (1 << k) != 0
                } else {
                    points.iter().any(|p| p.feature as usize == k)
                };
                if !found {
                    emit(k, open);
                }
            }
        });
    }

    /// The geometry of one feature of a pair.
    pub(crate) fn pair_slot(
        &self,
        pair: &Pair,
        feature: usize,
        fa: &Frame,
        fb: &Frame,
    ) -> SlotGeometry {
        let mut out = SlotGeometry::default();
        self.pair_slots(pair, fa, fb, |k, g| {
            if k == feature {
                out = g;
            }
        });
        out
    }
}
