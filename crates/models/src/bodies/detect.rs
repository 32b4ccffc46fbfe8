//! The detected contact set: [`Multibody`] as a `moreau_stepper::BodyStructure`, its contacts
//! found at each (q, t) by the broad phase over every shape and the narrow phase on the pairs
//! it returns.
//!
//! Every shape of every body is a collider, numbered in body then shape order. A pair of
//! colliders (i, j), i < j, is in contact under the same rules as the fixed slots
//! ([`Rules`]): an explicit contact between the two shapes, else the automatic contacts when the
//! collision groups allow the bodies, no joint connects them and one of them has coordinates.
//! Each point of the narrow phase within the margin becomes a `BodyContact` whose identity is
//! i · 2⁴⁰ + j · 2¹⁶ + feature: unique, the same while the same features touch, and increasing
//! in the order the broad phase and the sorted features give. Its force directions are those of
//! the fixed slots ([`SlotGeometry::rows`]) restricted to each body's three coordinates, and
//! the joints' rows are split by body the same way.

use std::cell::RefCell;

use moreau_kinematics::{Aabb, BroadPhase, ManifoldPoint, Shape, max_points};
use moreau_setvalued::ContactLaw;
use moreau_stepper::{BodyBilateral, BodyContact, BodyStructure, NO_BODY};
use rayon::prelude::*;

use super::body::{Body, Frame, Kind};
use super::build::bad;
use super::contacts::Rules;
use super::forces::mass_block;
use super::joints::SlotGeometry;
use super::multibody::Multibody;
use crate::ModelError;

/// Colliders are numbered in 24 bits and features in 16 within a contact's identity.
const COLLIDER_BITS: u32 = 24;
pub(crate) const FEATURE_BITS: u32 = 16;

/// The contact rules and colliders of a mechanism whose contacts are detected at each step.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Detector {
    pub rules: Rules,
    /// (body, shape) of each collider, in body then shape order.
    pub colliders: Vec<(usize, usize)>,
}

/// Items (colliders, bodies) per chunk of parallel work: enough work per rayon task (the broad
/// phase's search and the narrow phase of the pairs of a few hundred colliders) that its
/// overhead is small, few enough that two threads share the chunks evenly.
pub(crate) const CHUNK_ITEMS: usize = 256;

/// Whether `n` items (colliders, bodies) are worked on in chunks on rayon's current pool: above
/// 2,048 on a pool of several threads; below, the chunks' buffers and the tasks cost more than
/// they save.
pub(crate) fn in_parallel(n: usize) -> bool {
    n > 2048 && rayon::current_num_threads() > 1
}

/// One chunk of colliders' detection: the broad phase's pairs of its colliders, the narrow
/// phase's manifold points and the chunk's contacts, concatenated in chunk order.
#[derive(Default)]
struct Chunk {
    pairs: Vec<(usize, usize)>,
    points: Vec<ManifoldPoint>,
    contacts: Vec<BodyContact>,
}

/// The buffers of one detection, kept from call to call so that, once they have grown, a step
/// allocates nothing.
#[derive(Default)]
struct Scratch {
    broad: BroadPhase,
    frames: Vec<Frame>,
    boxes: Vec<Aabb>,
    chunks: Vec<Chunk>,
    /// The first place of each chunk's contacts in the whole list.
    starts: Vec<usize>,
}

thread_local! {
    /// The idle scratches of this thread. A detection takes one out and puts it back, so that a
    /// detection that the thread runs while it waits for the chunks of its own (a rayon worker
    /// steals other work, such as another simulation's step) gets a scratch of its own.
    static SCRATCH: RefCell<Vec<Scratch>> = const { RefCell::new(Vec::new()) };
}

/// A contact's identity from its two colliders (i < j) and its feature.
pub(crate) fn contact_id(i: usize, j: usize, feature: u32) -> u64 {
    ((i as u64) << (COLLIDER_BITS + FEATURE_BITS)) | ((j as u64) << FEATURE_BITS) | feature as u64
}

/// The two colliders and the feature of a contact's identity ([`contact_id`]'s inverse).
pub(crate) fn split_id(id: u64) -> (usize, usize, u32) {
    let low = |bits: u32, v: u64| (v & ((1 << bits) - 1)) as usize;
    let i = (id >> (COLLIDER_BITS + FEATURE_BITS)) as usize;
    (i, low(COLLIDER_BITS, id >> FEATURE_BITS), low(FEATURE_BITS, id) as u32)
}

impl Detector {
    /// The colliders of the built bodies, after checking that the identities can name every
    /// contact and that the narrow phase supports every pair of shapes the rules may bring
    /// together.
    pub fn new(rules: Rules, bodies: &[Body]) -> Result<Self, ModelError> {
        let colliders: Vec<(usize, usize)> = bodies
            .iter()
            .enumerate()
            .flat_map(|(b, body)| (0..body.shapes.len()).map(move |s| (b, s)))
            .collect();
        if colliders.len() >= 1 << COLLIDER_BITS {
            return Err(bad(
                "contact_set".to_owned(),
                "detected",
                format!("{} shapes; detected contacts name at most 2^24", colliders.len()),
            ));
        }
        let detector = Self { rules, colliders };
        // Half-planes, polylines and profiles are few (floors, walls, guides); the narrow phase
        // refuses two of them together and bounds their features, so they are checked against
        // every other collider of their kind, and the largest feature count against all.
        let special = |s: &Shape| {
            matches!(s, Shape::HalfPlane { .. } | Shape::Polyline { .. } | Shape::Profile { .. })
        };
        let widest = detector
            .colliders
            .iter()
            .map(|&(b, s)| &bodies[b].shapes[s])
            .filter(|s| !special(s))
            .max_by_key(|s| max_points(s, s))
            .cloned();
        for (i, &(a, sa)) in detector.colliders.iter().enumerate() {
            let shape = &bodies[a].shapes[sa];
            if !special(shape) {
                continue;
            }
            let field = format!("bodies.{}.shapes.{sa}", bodies[a].name);
            if let Some(w) = &widest
                && max_points(shape, w) >= 1 << FEATURE_BITS
            {
                return Err(bad(
                    field,
                    shape.name(),
                    "too many points for a detected contact's feature (at most 2^16)".to_owned(),
                ));
            }
            for &(b, sb) in &detector.colliders[i + 1..] {
                let other = &bodies[b].shapes[sb];
                if special(other)
                    && detector.law(bodies, (a, sa), (b, sb)).is_some()
                    && max_points(shape, other) == 0
                {
                    return Err(bad(
                        field,
                        shape.name(),
                        format!(
                            "may touch shape {sb} ({}) of body `{}`, a pair the narrow phase \
                             does not support; separate them with collision groups",
                            other.name(),
                            bodies[b].name
                        ),
                    ));
                }
            }
        }
        Ok(detector)
    }

    /// The law of the pair of colliders at (body, shape) `x` and `y` (x before y), and whether
    /// the contact's side a is `y` (an explicit contact declared the other way round); `None`
    /// when the rules give the pair no contact.
    pub(crate) fn law(
        &self,
        bodies: &[Body],
        (a, sa): (usize, usize),
        (b, sb): (usize, usize),
    ) -> Option<(ContactLaw, bool)> {
        if a == b || !(bodies[a].is_dynamic() || bodies[b].is_dynamic()) {
            return None;
        }
        if let Some(e) = self.rules.explicit(a, sa, b, sb) {
            return Some((e.law, e.a != a || e.shape_a != sa));
        }
        self.rules.automatic(bodies, a, b).map(|law| (law, false))
    }
}

/// The coordinates' body index of a frame, or [`NO_BODY`].
fn coordinate_body(frame: &Frame) -> u32 {
    frame.dof.map_or(NO_BODY, |d| (d / 3) as u32)
}

/// The frames of a row's two bodies with their coordinates renumbered 0..3 and 3..6, so that
/// the rows written for the dense q fill the six numbers of a split row.
fn local_frames(fa: &Frame, fb: &Frame) -> (Frame, Frame) {
    (Frame { dof: fa.dof.map(|_| 0), ..*fa }, Frame { dof: fb.dof.map(|_| 3), ..*fb })
}

/// Six numbers (body a's x, y, θ, then body b's) as the two sides of a split row.
fn split(w: [f64; 6]) -> [[f64; 3]; 2] {
    [[w[0], w[1], w[2]], [w[3], w[4], w[5]]]
}

impl Multibody {
    /// The contacts of the broad-phase pair of colliders (i, j) at the bodies' `frames`,
    /// appended to `out` in increasing order of feature; `points` is the narrow phase's
    /// scratch.
    fn narrow_phase(
        &self,
        detector: &Detector,
        frames: &[Frame],
        (i, j): (usize, usize),
        margin: f64,
        points: &mut Vec<ManifoldPoint>,
        out: &mut Vec<BodyContact>,
    ) {
        let (x, y) = (detector.colliders[i], detector.colliders[j]);
        let Some((law, flipped)) = detector.law(&self.bodies, x, y) else { return };
        let ((a, sa), (b, sb)) = if flipped { (y, x) } else { (x, y) };
        let (fa, fb) = (&frames[a], &frames[b]);
        points.clear();
        let (pa, pb) = (fa.placement(), fb.placement());
        if self.collide_shapes((a, sa, &pa), (b, sb, &pb), margin, points).is_err() {
            // The pairs were checked at build time; a margin that is not a number gives a gap
            // that is not one, and the stepper stops with a typed error.
            let failed = ManifoldPoint {
                feature: 0,
                point_a: fa.p,
                point_b: fb.p,
                normal: [0.0; 2],
                gap: f64::NAN,
            };
            out.push(Self::body_contact(contact_id(i, j, 0), &failed, fa, fb, law));
            return;
        }
        points.sort_unstable_by_key(|p| p.feature);
        let mut last = None;
        for p in points.iter() {
            if p.gap <= margin && last != Some(p.feature) {
                last = Some(p.feature);
                out.push(Self::body_contact(contact_id(i, j, p.feature), p, fa, fb, law));
            }
        }
    }

    /// The contact of one narrow-phase point between the bodies at frames `fa` and `fb`.
    fn body_contact(
        id: u64,
        point: &ManifoldPoint,
        fa: &Frame,
        fb: &Frame,
        law: ContactLaw,
    ) -> BodyContact {
        let geometry = SlotGeometry {
            point_a: point.point_a,
            point_b: point.point_b,
            normal: point.normal,
            gap: point.gap,
        };
        // The fixed slots' rows, written into the six coordinates of the two bodies.
        let (local_a, local_b) = local_frames(fa, fb);
        let (mut w_n, mut w_t) = ([0.0; 6], [0.0; 6]);
        let contact_point = geometry.rows(&local_a, &local_b, &mut w_n, &mut w_t);
        BodyContact {
            id,
            bodies: [coordinate_body(fa), coordinate_body(fb)],
            w_n: split(w_n),
            w_t: split(w_t),
            point: contact_point,
            law,
        }
    }
}

impl Multibody {
    /// The contact of identity `id` at (q, t), found again by the narrow phase of its two
    /// shapes with `margin`: the bodies of its sides a and b and its geometry; `None` when the
    /// identity names no pair of colliders in contact under the rules, or no point of that
    /// feature within the margin.
    pub(crate) fn locate_detected(
        &self,
        detector: &Detector,
        id: u64,
        q: &[f64],
        t: f64,
        margin: f64,
    ) -> Option<([usize; 2], SlotGeometry)> {
        let (i, j, feature) = split_id(id);
        let (&x, &y) = (detector.colliders.get(i)?, detector.colliders.get(j)?);
        let (_, flipped) = detector.law(&self.bodies, x, y)?;
        let ((a, sa), (b, sb)) = if flipped { (y, x) } else { (x, y) };
        let (fa, fb) = (self.frame(a, q, t), self.frame(b, q, t));
        let mut points = Vec::new();
        let (pa, pb) = (fa.placement(), fb.placement());
        self.collide_shapes((a, sa, &pa), (b, sb, &pb), margin, &mut points).ok()?;
        let p = points.iter().find(|p| p.feature == feature && p.gap <= margin)?;
        let geometry =
            SlotGeometry { point_a: p.point_a, point_b: p.point_b, normal: p.normal, gap: p.gap };
        Some(([a, b], geometry))
    }
}

impl BodyStructure for Multibody {
    fn num_bodies(&self) -> usize {
        self.dynamic.len()
    }

    fn mass_blocks(&self, q: &[f64], t: f64, blocks: &mut [[f64; 9]]) {
        for (block, &i) in blocks.iter_mut().zip(&self.dynamic) {
            let body = &self.bodies[i];
            if let Kind::Dynamic { mass, inertia, com, .. } = body.kind {
                *block = mass_block(mass, inertia, com, &body.frame(q, t));
            }
        }
    }

    /// The broad phase grows each shape's box by half the margin, so that it keeps every pair
    /// of boxes at most `margin` apart along each axis, a bound below their gap; the narrow
    /// phase then keeps the points whose gap is at most `margin`.
    ///
    /// Above a few thousand colliders, when rayon's current pool has several threads, the
    /// frames, the boxes and then the broad and narrow phases of chunks of consecutive
    /// colliders run in parallel, each chunk into buffers of its own, concatenated in chunk
    /// order: the contacts and their order are those of the sequential detection, bit for bit,
    /// for any number of threads.
    fn detect(&self, q: &[f64], t: f64, margin: f64, out: &mut Vec<BodyContact>) {
        let Some(detector) = &self.detector else { return };
        let mut scratch = SCRATCH.with(|cell| cell.borrow_mut().pop()).unwrap_or_default();
        let Scratch { broad, frames, boxes, chunks, starts } = &mut scratch;
        let n = detector.colliders.len();
        let parallel = in_parallel(n);
        self.frames_into(q, t, frames);
        let frames = &*frames;
        let aabb =
            |&(b, s): &(usize, usize)| self.bodies[b].shapes[s].aabb_placed(&frames[b].placement());
        boxes.clear();
        if parallel {
            boxes.par_extend(detector.colliders.par_iter().with_min_len(CHUNK_ITEMS).map(aabb));
        } else {
            boxes.extend(detector.colliders.iter().map(aabb));
        }
        broad.build(boxes, 0.5 * margin);
        let (broad, boxes) = (&*broad, &*boxes);
        // The pairs of the colliders of `range`, then their contacts, appended to `out`.
        let search = |range: std::ops::Range<usize>, chunk: &mut Chunk, out: &mut Vec<_>| {
            chunk.pairs.clear();
            broad.pairs_of(boxes, range, &mut chunk.pairs);
            for &(i, j) in &chunk.pairs {
                self.narrow_phase(detector, frames, (i, j), margin, &mut chunk.points, out);
            }
        };
        if parallel {
            let k = n.div_ceil(CHUNK_ITEMS);
            if chunks.len() < k {
                chunks.resize_with(k, Chunk::default);
            }
            chunks[..k].par_iter_mut().enumerate().for_each(|(c, chunk)| {
                let range = c * CHUNK_ITEMS..n.min((c + 1) * CHUNK_ITEMS);
                let mut contacts = std::mem::take(&mut chunk.contacts);
                contacts.clear();
                search(range, chunk, &mut contacts);
                chunk.contacts = contacts;
            });
            // The chunks' contacts concatenated in chunk order, written in parallel straight
            // into their places: contact `i` of the whole list belongs to the last chunk
            // that starts at or before it.
            let chunks = &chunks[..k];
            starts.clear();
            starts.extend(chunks.iter().scan(out.len(), |next, chunk| {
                let start = *next;
                *next += chunk.contacts.len();
                Some(start)
            }));
            let (first, total) =
                (out.len(), chunks.iter().map(|c| c.contacts.len()).sum::<usize>());
            let starts = &*starts;
            out.par_extend((first..first + total).into_par_iter().with_min_len(CHUNK_ITEMS).map(
                |i| {
                    let c = starts.partition_point(|&s| s <= i) - 1;
                    chunks[c].contacts[i - starts[c]]
                },
            ));
        } else {
            let mut chunk = chunks.pop().unwrap_or_default();
            search(0..n, &mut chunk, out);
            chunks.push(chunk);
        }
        SCRATCH.with(|cell| cell.borrow_mut().push(scratch));
    }

    /// The joints' rows of `Mechanism::bilaterals`, each written for the six coordinates of
    /// its two bodies and split, from one frame per body.
    fn bilateral_rows(&self, q: &[f64], t: f64, rows: &mut [BodyBilateral]) {
        self.with_frames(q, t, |frames| {
            for (row, &(joint, k)) in rows.iter_mut().zip(&self.rows) {
                let j = &self.joints[joint];
                let (fa, fb) = (&frames[j.a], &frames[j.b]);
                let (local_a, local_b) = local_frames(fa, fb);
                let mut w = [0.0; 6];
                let point = j.kind.row(k, &local_a, &local_b, t, &mut w);
                *row = BodyBilateral {
                    bodies: [coordinate_body(fa), coordinate_body(fb)],
                    w: split(w),
                    point,
                };
            }
        });
    }
}
