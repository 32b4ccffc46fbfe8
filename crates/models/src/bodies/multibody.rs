//! [`Multibody`]: a declared mechanism, built, as a `moreau_stepper::Mechanism`.

use std::cell::Cell;

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;
use moreau_stepper::{BilateralPoint, BodyStructure, Mechanism, SharedWork, StepperOptions};
use rayon::prelude::*;

use super::body::{Body, Frame, Kind};
use super::contacts::Pair;
use super::detect::{CHUNK_ITEMS, Detector, in_parallel};
use super::forces::{Force, body_forces, gravity_potential, mass_block};
use super::joints::{Joint, SlotGeometry};
use super::spec::SystemSpec;

thread_local! {
    /// The bodies' frames at one (q, t), reused by every call on this thread so that a step
    /// does not allocate once the buffer has grown to the number of bodies.
    static FRAMES: Cell<Vec<Frame>> = const { Cell::new(Vec::new()) };
}

/// The numbers [`SharedWork::evaluate`] keeps of one contact slot: its two points, normal and
/// gap.
const SLOT_MEMO: usize = 7;

/// The numbers [`SharedWork::evaluate`] keeps of one body's frame: p, θ, cos θ, sin θ, v, ω.
const FRAME_MEMO: usize = 8;

/// One contact slot: a fixed index of the contact list, closed or open at each step.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Slot {
    /// Contact `k` of a clearance joint.
    Joint { joint: usize, k: usize },
    /// Feature `feature` of a pair of shapes.
    Pair { pair: usize, feature: usize },
}

/// A contact of a step, located: the bodies on its two sides and its geometry
/// ([`Multibody::locate_contact`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocatedContact {
    /// The bodies of sides a and b, as indices into [`Multibody::body_names`] (fixed and
    /// driven bodies included).
    pub bodies: [usize; 2],
    /// The point on each body's surface (m), the unit normal from a towards b and the gap g_N
    /// (m).
    pub geometry: SlotGeometry,
}

/// A declared mechanism built into maximal coordinates: q = (x, y, θ) of each dynamic body's
/// origin in declaration order (f = 3 n_dyn), u = (ẋ, ẏ, θ̇) likewise.
///
/// It implements [`Mechanism`]: M is block diagonal (constant when every dynamic body's origin
/// is its centre of mass), h holds gravity, the centrifugal terms of bodies whose origin is not
/// their centre of mass and the force elements, the joints are the bilateral rows and the
/// contacts are a fixed list of slots, each closed or open at each step. Build one with
/// [`super::MultibodyBuilder`] or [`SystemSpec::build`].
#[derive(Clone, Debug)]
pub struct Multibody {
    pub(crate) spec: SystemSpec,
    pub(crate) bodies: Vec<Body>,
    pub(crate) joints: Vec<Joint>,
    /// Bilateral row i is row `rows[i].1` of joint `rows[i].0`.
    pub(crate) rows: Vec<(usize, usize)>,
    pub(crate) forces: Vec<Force>,
    pub(crate) gravity: [f64; 2],
    pub(crate) slots: Vec<Slot>,
    pub(crate) pairs: Vec<Pair>,
    /// The contact rules and colliders of the detected contact set, `None` for the fixed one.
    pub(crate) detector: Option<Detector>,
    pub(crate) laws: Vec<ContactLaw>,
    pub(crate) contact_names: Vec<String>,
    pub(crate) coordinate_names: Vec<String>,
    pub(crate) velocity_names: Vec<String>,
    pub(crate) q0: Vec<f64>,
    pub(crate) u0: Vec<f64>,
    /// The start time t₀ (s) at which (q₀, u₀) is the state ([`super::SystemSpec::build_at`]).
    pub(crate) t0: f64,
    /// The indices of the dynamic bodies, in coordinate order.
    pub(crate) dynamic: Vec<usize>,
    pub(crate) constant_mass: bool,
    /// The centre and half-size (m) of the region the bodies occupy at t = 0, for drawing
    /// half-planes.
    pub(crate) extent: ([f64; 2], f64),
    /// The size of the moving bodies ([`Multibody::size`]).
    pub(crate) size: f64,
}

impl Multibody {
    /// The mechanism's size, in the length unit of its declaration: 0.6 times the diagonal of
    /// the box around its moving (dynamic and driven) bodies' origins and finite shapes at
    /// t = 0; over every body when none moves, and 1 for a mechanism of no size. What must
    /// not depend on the unit is measured against it: the tolerances below, and the guards of
    /// a run. The fixed geometry does not count: a box resting on a floor drawn as a polygon
    /// 2 km long had a size of 1,200 m, a projection tolerance of 1.2 mm, and came to rest
    /// 0.6 mm deep and tilted.
    pub fn size(&self) -> f64 {
        self.size
    }

    /// The penetration that the contact projection leaves alone when this mechanism is
    /// stepped with the projection at time step `dt` (`StepperOptions::projection_tolerance`):
    /// the larger of 1e-6 of the mechanism's [size](Self::size), so that a scene written in
    /// any length unit is projected alike, and 2 |g| Δt², twice the depth by which the
    /// midpoint rule lets a body resting under gravity sink in one step.
    ///
    /// The projection moves q_E and leaves u_E, so a resting contact projected onto g_N = 0
    /// comes out slightly open and falls back within a few steps: it opens and closes every
    /// few steps. With ε_N > 0 each closing is an impact that sends the body up again at
    /// ε_N g Δt / (1 + ε_N), and a box dropped onto a floor at ε_N = 0.5 and Δt = 1 ms,
    /// projected below 2e-7 m, never came to rest (1,000 impacts a second). Left alone below
    /// this depth, a contact rests at the O(g Δt²) penetration of the scheme without
    /// projection.
    pub fn projection_tolerance(&self, dt: f64) -> f64 {
        let g = self.gravity[0].hypot(self.gravity[1]);
        (1e-6 * self.size()).max(2.0 * g * dt * dt)
    }

    /// The gap at or below which a contact counts as closed when this mechanism is stepped
    /// from a scene file, with or without the projection (`StepperOptions::gap_tolerance`):
    /// 1e-9 of the mechanism's [size](Self::size).
    ///
    /// Without the projection, a block resting flat has both corners' midpoint gaps at zero
    /// up to round-off; with a threshold of zero, a corner at +3.5e-18 m sat out a step and a
    /// block on a moving belt rocked and stayed tilted through stick-slip.
    ///
    /// The projection's linearised correction leaves the contacts it pushed out open by
    /// round-off (a threshold of 1e-13 m keeps them closed in a stack of five boxes 0.5 m
    /// tall, which is exact for a translation). With a threshold of zero
    /// such a contact sits out the next step, and what it carried falls through it for Δt:
    /// in a stack of five equal boxes a box landing on one whose support sat out that step
    /// pushed both down and set the stack rocking; the top box, which should rest, slid 0.16 m
    /// in 2 s.
    pub fn gap_tolerance(&self) -> f64 {
        1e-9 * self.size()
    }

    /// The drift of the joints that the correction of the positions leaves alone when this
    /// mechanism is stepped with the projection (`StepperOptions::joint_tolerance`): 1e-12 of
    /// the mechanism's size (see [`Self::size`]), so that a mechanism of a
    /// fraction of its length unit holds its joints as closely, relative to its size, as one of
    /// the unit's size.
    pub fn joint_tolerance(&self) -> f64 {
        1e-12 * self.size()
    }

    /// The stepper's options at time step `dt` with which a scene file steps this mechanism:
    /// the projection on, with this mechanism's [projection](Self::projection_tolerance),
    /// [gap](Self::gap_tolerance) and [joint](Self::joint_tolerance) tolerances, and the
    /// default solver. A mechanism built in Rust gets from it what a scene file gets:
    /// `StepperOptions::new(dt).with_projection(true)` alone would count contacts closed only
    /// at g_N <= 0, so that round-off in the initial gaps of touching bodies (a row of equal
    /// disks, Newton's cradle) or in the projection's result decides which contacts act.
    pub fn stepper_options(&self, dt: f64) -> StepperOptions {
        StepperOptions::new(dt)
            .with_projection(true)
            .with_projection_tolerance(self.projection_tolerance(dt))
            .with_gap_tolerance(self.gap_tolerance())
            .with_joint_tolerance(self.joint_tolerance())
    }

    /// The declaration it was built from.
    pub fn spec(&self) -> &SystemSpec {
        &self.spec
    }

    /// Names of the coordinates: `<body>.x`, `<body>.y`, `<body>.theta` per dynamic body.
    pub fn coordinate_names(&self) -> &[String] {
        &self.coordinate_names
    }

    /// Names of the velocities: `<body>.vx`, `<body>.vy`, `<body>.omega` per dynamic body.
    pub fn velocity_names(&self) -> &[String] {
        &self.velocity_names
    }

    /// Names of the contact slots, in the order of the contact list.
    pub fn contact_names(&self) -> Vec<String> {
        self.contact_names.clone()
    }

    /// Names of the joints' impulses Λ_B, one per bilateral constraint in the order of
    /// `Mechanism::bilaterals` (and of `StepReport::joint_impulses`): `<joint>.Lx`,
    /// `<joint>.Ly` for a revolute joint or a weld (the world components of the impulse on
    /// body b at its anchor, N s; body a takes the opposite), `<joint>.Ltheta` for an angle (a
    /// weld's, a prismatic joint's, a motor's: the torque impulse on body b, N m s),
    /// `<joint>.Ln` for a distance across a line (a prismatic joint's or a point on a line's:
    /// the impulse along the line's normal on the body of the point, N s; the line's body
    /// takes the opposite). Divided by Δt, each is the mean reaction over the step.
    pub fn bilateral_names(&self) -> Vec<String> {
        self.rows
            .iter()
            .map(|&(joint, k)| {
                let j = &self.joints[joint];
                format!("{}.{}", j.name, j.kind.row_name(k))
            })
            .collect()
    }

    /// The initial state (q₀, u₀), with q₀ assembled onto the joints.
    pub fn initial_state(&self) -> (Vec<f64>, Vec<f64>) {
        (self.q0.clone(), self.u0.clone())
    }

    /// The names of all bodies, in declaration order (an implicit `ground` last, if used).
    pub fn body_names(&self) -> Vec<&str> {
        self.bodies.iter().map(|b| b.name.as_str()).collect()
    }

    /// The index of a body by name.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    /// The pose (x, y, θ) of every body at (q, t) (m, rad), in the order of [`Self::body_names`].
    pub fn body_poses(&self, q: &[f64], t: f64) -> Vec<[f64; 3]> {
        self.bodies
            .iter()
            .map(|b| {
                let f = b.frame(q, t);
                [f.p[0], f.p[1], f.theta]
            })
            .collect()
    }

    /// The mass m (kg), the moment of inertia about the origin I_O (kg m²) and the centre of
    /// mass in the body frame (m) of body i when it is dynamic, `None` otherwise.
    pub fn mass_properties(&self, body: usize) -> Option<(f64, f64, [f64; 2])> {
        match self.bodies.get(body)?.kind {
            Kind::Dynamic { mass, inertia, com, .. } => Some((mass, inertia, com)),
            _ => None,
        }
    }

    /// The kinetic energy ½ uᵀ M(q) u (J).
    pub fn kinetic_energy(&self, q: &[f64], u: &[f64]) -> f64 {
        self.dynamic
            .iter()
            .map(|&i| {
                let body = &self.bodies[i];
                let Kind::Dynamic { dof, mass, inertia, com } = body.kind else { return 0.0 };
                let m = mass_block(mass, inertia, com, &body.frame(q, 0.0));
                let v = [u[dof], u[dof + 1], u[dof + 2]];
                let mut e = 0.0;
                for c in 0..3 {
                    for r in 0..3 {
                        e += v[r] * m[r + 3 * c] * v[c];
                    }
                }
                0.5 * e
            })
            .sum()
    }

    /// Runs `op` with the frames of all bodies at (q, t), each computed once: the sines and
    /// cosines of a body's angle then serve all its joints, contacts and forces.
    pub(crate) fn with_frames<R>(&self, q: &[f64], t: f64, op: impl FnOnce(&[Frame]) -> R) -> R {
        // Taken out of the cell rather than borrowed, so that a nested call gets a buffer of
        // its own instead of a conflict.
        let mut frames = FRAMES.take();
        self.frames_into(q, t, &mut frames);
        let out = op(&frames);
        FRAMES.set(frames);
        out
    }

    /// The frames of all bodies at (q, t) into `frames` (cleared first), in chunks in parallel
    /// for many bodies; written in place into its capacity, so that nothing is allocated once
    /// warm.
    pub(crate) fn frames_into(&self, q: &[f64], t: f64, frames: &mut Vec<Frame>) {
        let frame = |b: &Body| b.frame(q, t);
        frames.clear();
        if in_parallel(self.bodies.len()) {
            frames.par_extend(self.bodies.par_iter().with_min_len(CHUNK_ITEMS).map(frame));
        } else {
            frames.extend(self.bodies.iter().map(frame));
        }
    }

    /// The normal gaps of all slots at the bodies' `frames`, and each slot's geometry to
    /// `keep`: one narrow phase per pair of shapes for all its slots.
    fn gaps_at(&self, frames: &[Frame], mut keep: impl FnMut(usize, &SlotGeometry)) {
        for (i, slot) in self.slots.iter().enumerate() {
            if let Slot::Joint { joint, k } = *slot {
                let j = &self.joints[joint];
                keep(i, &j.kind.contact(k, &frames[j.a], &frames[j.b]));
            }
        }
        for p in &self.pairs {
            self.pair_slots(p, &frames[p.a], &frames[p.b], |k, g| keep(p.first + k, &g));
        }
    }

    /// M at the bodies' `frames` into `m` (f × f, column-major).
    fn mass_at(&self, frames: &[Frame], m: &mut [f64]) {
        let f = self.num_coordinates();
        m.fill(0.0);
        for &i in &self.dynamic {
            if let Kind::Dynamic { dof, mass, inertia, com } = self.bodies[i].kind {
                let block = mass_block(mass, inertia, com, &frames[i]);
                for c in 0..3 {
                    for r in 0..3 {
                        m[dof + r + (dof + c) * f] = block[r + 3 * c];
                    }
                }
            }
        }
    }

    /// h at the bodies' `frames` into `h`.
    fn forces_at(&self, frames: &[Frame], u: &[f64], t: f64, h: &mut [f64]) {
        // Body by body, in chunks in parallel for many bodies; each body's three entries are
        // its own (h has exactly three per dynamic body), so the bits are the same either way.
        debug_assert_eq!(h.len(), 3 * self.dynamic.len());
        let (blocks, _) = h.as_chunks_mut::<3>();
        let body = |(h, &i): (&mut [f64; 3], &usize)| {
            *h = body_forces(&self.bodies[i], &frames[i], u, self.gravity);
        };
        if in_parallel(self.dynamic.len()) {
            blocks.par_iter_mut().zip(&self.dynamic).with_min_len(CHUNK_ITEMS).for_each(body);
        } else {
            blocks.iter_mut().zip(&self.dynamic).for_each(body);
        }
        for force in &self.forces {
            force.add_to::<false>(&self.bodies, |b| frames[b], u, t, h);
        }
    }

    /// The frame of body i at (q, t).
    #[inline]
    pub(crate) fn frame(&self, i: usize, q: &[f64], t: f64) -> Frame {
        self.bodies[i].frame(q, t)
    }

    /// The geometry of contact slot i at (q, t), and the two bodies' frames.
    #[inline]
    pub(crate) fn slot_geometry(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
    ) -> (SlotGeometry, Frame, Frame) {
        match self.slots[i] {
            Slot::Joint { joint, k } => {
                let j = &self.joints[joint];
                let (fa, fb) = (self.frame(j.a, q, t), self.frame(j.b, q, t));
                (j.kind.contact(k, &fa, &fb), fa, fb)
            }
            Slot::Pair { pair, feature } => {
                let p = &self.pairs[pair];
                let (fa, fb) = (self.frame(p.a, q, t), self.frame(p.b, q, t));
                (self.pair_slot(p, feature, &fa, &fb), fa, fb)
            }
        }
    }

    /// The points, normal and gap of contact slot i at (q, t), closed or open.
    ///
    /// # Panics
    /// When `i >= num_contacts()`.
    pub fn contact_geometry(&self, i: usize, q: &[f64], t: f64) -> SlotGeometry {
        self.slot_geometry(i, q, t).0
    }

    /// The two bodies and the geometry at (q, t) of the contact that a step reports under the
    /// identity `id` (`moreau_stepper::StepReport::contact_ids`), or `None` when there is no
    /// such contact.
    ///
    /// With the fixed contact set the identity is the contact's index in the contact list,
    /// closed or open. With the detected one it names two shapes and a feature; their narrow
    /// phase is run again, and the contact is found when that feature's gap is at most
    /// `margin`. At a step's midpoint (q_M, t_M) = (q_A + Δt/2 u_A, t_A + Δt/2) with the
    /// stepper's `gap_tolerance` as the margin, this finds exactly the contacts the step
    /// detected, with the points, normal and gap its problem was written for.
    pub fn locate_contact(
        &self,
        id: u64,
        q: &[f64],
        t: f64,
        margin: f64,
    ) -> Option<LocatedContact> {
        let (bodies, geometry) = match &self.detector {
            Some(detector) => self.locate_detected(detector, id, q, t, margin)?,
            None => {
                let i = usize::try_from(id).ok().filter(|&i| i < self.slots.len())?;
                let bodies = match self.slots[i] {
                    Slot::Joint { joint, .. } => [self.joints[joint].a, self.joints[joint].b],
                    Slot::Pair { pair, .. } => [self.pairs[pair].a, self.pairs[pair].b],
                };
                (bodies, self.slot_geometry(i, q, t).0)
            }
        };
        Some(LocatedContact { bodies, geometry })
    }

    /// Where each contact slot's points are at (q, t): the midpoint of the two surface points
    /// (m).
    pub fn contact_points(&self, q: &[f64], t: f64) -> Vec<[f64; 2]> {
        (0..self.slots.len())
            .map(|i| {
                let (g, _, _) = self.slot_geometry(i, q, t);
                [0.5 * (g.point_a[0] + g.point_b[0]), 0.5 * (g.point_a[1] + g.point_b[1])]
            })
            .collect()
    }
}

impl ContactKinematics for Multibody {
    fn num_coordinates(&self) -> usize {
        3 * self.dynamic.len()
    }

    fn num_contacts(&self) -> usize {
        self.slots.len()
    }

    fn normal_gap(&self, i: usize, q: &[f64], t: f64) -> f64 {
        self.slot_geometry(i, q, t).0.gap
    }

    /// One narrow phase per pair of shapes for all its slots.
    fn normal_gaps(&self, q: &[f64], t: f64, g: &mut [f64]) {
        self.with_frames(q, t, |frames| self.gaps_at(frames, |i, s| g[i] = s.gap));
    }

    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        w_n.fill(0.0);
        w_t.fill(0.0);
        let (g, fa, fb) = self.slot_geometry(i, q, t);
        g.rows(&fa, &fb, w_n, w_t)
    }
}

impl Mechanism for Multibody {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }

    fn mass_matrix(&self, q: &[f64], t: f64, m: &mut [f64]) {
        self.with_frames(q, t, |frames| self.mass_at(frames, m));
    }

    fn forces(&self, q: &[f64], u: &[f64], t: f64, h: &mut [f64]) {
        self.with_frames(q, t, |frames| self.forces_at(frames, u, t, h));
    }

    fn potential_energy(&self, q: &[f64], t: f64) -> Option<f64> {
        let gravity: f64 = self
            .dynamic
            .iter()
            .map(|&i| gravity_potential(&self.bodies[i], &self.frame(i, q, t), self.gravity))
            .sum();
        let springs: f64 = self.forces.iter().map(|f| f.potential(|b| self.frame(b, q, t))).sum();
        Some(gravity + springs)
    }

    fn damping_forces(&self, q: &[f64], u: &[f64], t: f64, h_d: &mut [f64]) -> bool {
        super::forces::damping_forces(self, q, u, t, h_d)
    }

    fn constant_mass_matrix(&self) -> bool {
        self.constant_mass
    }

    /// Every body with coordinates is a rigid body in maximal coordinates, in either contact
    /// set.
    fn maximal_coordinates(&self) -> bool {
        true
    }

    /// Announced in the detected contact set only.
    fn body_structure(&self) -> Option<&dyn BodyStructure> {
        self.detector.as_ref().map(|_| self as &dyn BodyStructure)
    }

    fn num_bilaterals(&self) -> usize {
        self.rows.len()
    }

    fn bilateral(&self, i: usize, q: &[f64], t: f64, w: &mut [f64]) -> BilateralPoint {
        w.fill(0.0);
        let (joint, k) = self.rows[i];
        let j = &self.joints[joint];
        j.kind.row(k, &self.frame(j.a, q, t), &self.frame(j.b, q, t), t, w)
    }

    /// Every row at the bodies' frames, each frame computed once.
    fn bilaterals(&self, q: &[f64], t: f64, w: &mut [f64], points: &mut [BilateralPoint]) {
        self.with_frames(q, t, |frames| self.rows_at(|b| frames[b], t, w, points));
    }

    fn shared_work(&self) -> Option<&dyn SharedWork> {
        Some(self)
    }
}

/// M, h and the gaps from one set of frames at the midpoint; the memo keeps the slots'
/// geometry and the frames, so that the closed contacts' force directions need neither a
/// narrow phase nor a sine again.
impl SharedWork for Multibody {
    fn evaluate(
        &self,
        q: &[f64],
        u: &[f64],
        t: f64,
        mass: Option<&mut [f64]>,
        h: &mut [f64],
        gaps: &mut [f64],
        memo: &mut [f64],
    ) {
        self.with_frames(q, t, |frames| {
            if let Some(m) = mass {
                self.mass_at(frames, m);
            }
            self.forces_at(frames, u, t, h);
            let (slots, bodies) = memo.split_at_mut(SLOT_MEMO * self.slots.len());
            self.gaps_at(frames, |i, s| {
                gaps[i] = s.gap;
                slots[SLOT_MEMO * i..][..SLOT_MEMO].copy_from_slice(&[
                    s.point_a[0],
                    s.point_a[1],
                    s.point_b[0],
                    s.point_b[1],
                    s.normal[0],
                    s.normal[1],
                    s.gap,
                ]);
            });
            for (frame, m) in frames.iter().zip(bodies.chunks_exact_mut(FRAME_MEMO)) {
                m.copy_from_slice(&[
                    frame.p[0],
                    frame.p[1],
                    frame.theta,
                    frame.cos,
                    frame.sin,
                    frame.v[0],
                    frame.v[1],
                    frame.omega,
                ]);
            }
        });
    }

    fn memo_len(&self) -> usize {
        SLOT_MEMO * self.slots.len() + FRAME_MEMO * self.bodies.len()
    }

    fn midpoint_contacts(
        &self,
        which: &[usize],
        _q: &[f64],
        _t: f64,
        memo: &[f64],
        w_n: &mut [f64],
        w_t: &mut [f64],
        points: &mut [ContactPoint],
    ) {
        let f = self.num_coordinates();
        let (slots, bodies) = memo.split_at(SLOT_MEMO * self.slots.len());
        let frame = |b: usize| self.memo_frame(bodies, b);
        for (a, &i) in which.iter().enumerate() {
            let m = &slots[SLOT_MEMO * i..][..SLOT_MEMO];
            let geometry = SlotGeometry {
                point_a: [m[0], m[1]],
                point_b: [m[2], m[3]],
                normal: [m[4], m[5]],
                gap: m[6],
            };
            let (body_a, body_b) = match self.slots[i] {
                Slot::Joint { joint, .. } => (self.joints[joint].a, self.joints[joint].b),
                Slot::Pair { pair, .. } => (self.pairs[pair].a, self.pairs[pair].b),
            };
            let (w_n, w_t) = (&mut w_n[a * f..][..f], &mut w_t[a * f..][..f]);
            w_n.fill(0.0);
            w_t.fill(0.0);
            points[a] = geometry.rows(&frame(body_a), &frame(body_b), w_n, w_t);
        }
    }

    /// Every row from the frames in the memo.
    fn midpoint_bilaterals(
        &self,
        _q: &[f64],
        t: f64,
        memo: &[f64],
        w: &mut [f64],
        points: &mut [BilateralPoint],
    ) -> bool {
        let bodies = &memo[SLOT_MEMO * self.slots.len()..];
        self.rows_at(|b| self.memo_frame(bodies, b), t, w, points);
        true
    }
}

impl Multibody {
    /// Every joint row at t into `w` (one row of f entries each) and `points`, with body b's
    /// frame `frame(b)`.
    #[inline]
    fn rows_at(
        &self,
        frame: impl Fn(usize) -> Frame,
        t: f64,
        w: &mut [f64],
        points: &mut [BilateralPoint],
    ) {
        let f = self.num_coordinates();
        for (i, &(joint, k)) in self.rows.iter().enumerate() {
            let j = &self.joints[joint];
            let w = &mut w[i * f..][..f];
            w.fill(0.0);
            points[i] = j.kind.row(k, &frame(j.a), &frame(j.b), t, w);
        }
    }

    /// The frame of body `b` as [`SharedWork::evaluate`] kept it in the memo's `bodies` part.
    #[inline]
    fn memo_frame(&self, bodies: &[f64], b: usize) -> Frame {
        let m = &bodies[FRAME_MEMO * b..][..FRAME_MEMO];
        let dof = match self.bodies[b].kind {
            Kind::Dynamic { dof, .. } => Some(dof),
            _ => None,
        };
        Frame {
            p: [m[0], m[1]],
            theta: m[2],
            cos: m[3],
            sin: m[4],
            v: [m[5], m[6]],
            omega: m[7],
            dof,
        }
    }
}
