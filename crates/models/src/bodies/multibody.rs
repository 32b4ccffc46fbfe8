//! [`Multibody`]: a declared mechanism, built, as a `moreau_stepper::Mechanism`.

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;
use moreau_stepper::{BilateralPoint, BodyStructure, Mechanism};

use super::body::{Body, Frame, Kind};
use super::contacts::Pair;
use super::detect::Detector;
use super::forces::{Force, body_forces, gravity_potential, mass_block};
use super::joints::{Joint, SlotGeometry};
use super::spec::SystemSpec;

/// One contact slot: a fixed index of the contact list, closed or open at each step.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Slot {
    /// Contact `k` of a clearance joint.
    Joint { joint: usize, k: usize },
    /// Feature `feature` of a pair of shapes.
    Pair { pair: usize, feature: usize },
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
    /// The indices of the dynamic bodies, in coordinate order.
    pub(crate) dynamic: Vec<usize>,
    pub(crate) constant_mass: bool,
    /// The centre and half-size (m) of the region the bodies occupy at t = 0, for drawing
    /// half-planes.
    pub(crate) extent: ([f64; 2], f64),
}

impl Multibody {
    /// The penetration (m) that the contact projection leaves alone when this mechanism is
    /// stepped with the projection (`StepperOptions::projection_tolerance`): 1e-6 of the
    /// mechanism's size (the half-diagonal of the box around its bodies at t = 0).
    ///
    /// The projection moves q_E and leaves u_E, so a resting contact projected onto g_N = 0
    /// comes out slightly open and falls back within a few steps: it opens and closes every
    /// few steps. Left alone below this depth, it rests at the O(g Δt²) penetration of the
    /// scheme without projection.
    pub fn projection_tolerance(&self) -> f64 {
        1e-6 * self.extent.1
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
        for (i, slot) in self.slots.iter().enumerate() {
            if let Slot::Joint { .. } = slot {
                g[i] = self.slot_geometry(i, q, t).0.gap;
            }
        }
        for p in &self.pairs {
            let (fa, fb) = (self.frame(p.a, q, t), self.frame(p.b, q, t));
            self.pair_slots(p, &fa, &fb, |k, geometry| g[p.first + k] = geometry.gap);
        }
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
        let f = self.num_coordinates();
        m.fill(0.0);
        for &i in &self.dynamic {
            let body = &self.bodies[i];
            if let Kind::Dynamic { dof, mass, inertia, com } = body.kind {
                let block = mass_block(mass, inertia, com, &body.frame(q, t));
                for c in 0..3 {
                    for r in 0..3 {
                        m[dof + r + (dof + c) * f] = block[r + 3 * c];
                    }
                }
            }
        }
    }

    fn forces(&self, q: &[f64], u: &[f64], t: f64, h: &mut [f64]) {
        h.fill(0.0);
        for &i in &self.dynamic {
            let body = &self.bodies[i];
            body_forces(body, &body.frame(q, t), u, self.gravity, h);
        }
        for force in &self.forces {
            force.add_to(&self.bodies, |b| self.frame(b, q, t), u, t, h);
        }
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

    fn constant_mass_matrix(&self) -> bool {
        self.constant_mass
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
}
