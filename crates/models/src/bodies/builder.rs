//! [`MultibodyBuilder`]: a declared mechanism assembled in Rust, with typed handles.

use std::ops::Range;

use super::multibody::{Multibody, Slot};
use super::spec::{
    AutoContacts, BodySpec, Closure, ContactSet, ContactSpec, DrivenState, FillSpec, ForceSpec,
    JointSpec, Motion, SystemSpec,
};
use crate::ModelError;

/// A body added to a [`MultibodyBuilder`]: its index in declaration order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct BodyHandle(pub usize);

/// A joint added to a [`MultibodyBuilder`]: its index in declaration order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct JointHandle(pub usize);

/// A force element added to a [`MultibodyBuilder`]: its index in declaration order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ForceHandle(pub usize);

/// An explicit contact added to a [`MultibodyBuilder`]: its index in declaration order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ContactHandle(pub usize);

/// Builds a [`Multibody`] step by step: bodies, then joints, force elements and contacts that
/// name them. Everything is checked once, by [`Self::build`], with errors that name the body,
/// joint or field. What a scene file cannot say (motions and loads given by closures) is said
/// here with [`Motion::Custom`] and [`super::TimeFunction::Custom`].
///
/// ```
/// use moreau_models::bodies::{BodySpec, JointSpec, MultibodyBuilder};
/// use moreau_stepper::{Mechanism, Stepper};
///
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// // A 1 kg point-like bob on a 0.5 m massless rod, hinged to the ground at the origin.
/// let mut builder = MultibodyBuilder::new([0.0, -9.81]);
/// let bob = builder.add_body(BodySpec::dynamic("bob", 1.0, 1e-6, [0.5, 0.0], 0.0));
/// builder.add_joint(JointSpec::revolute("hinge", "ground", [0.0, 0.0], "bob", [-0.5, 0.0]));
/// let pendulum = builder.build()?;
/// assert_eq!(pendulum.coordinate_names(), ["bob.x", "bob.y", "bob.theta"]);
/// assert_eq!(pendulum.num_bilaterals(), 2);
/// let (q0, u0) = pendulum.initial_state();
/// // As a scene file steps it: the projection keeps the positions on the joint despite the
/// // midpoint rule's drift, with tolerances relative to the mechanism's size.
/// let options = pendulum.stepper_options(1e-3);
/// assert!(options.projection);
/// let mut stepper = Stepper::new(pendulum, &q0, &u0, 0.0, options)?;
/// while stepper.t() < 0.1 {
///     stepper.step()?;
/// }
/// // The bob stays on its circle of radius 0.5 m.
/// let pose = stepper.mechanism().pose(bob, stepper.q(), stepper.t());
/// assert!((pose[0].hypot(pose[1]) - 0.5).abs() < 1e-9);
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct MultibodyBuilder {
    spec: SystemSpec,
}

impl MultibodyBuilder {
    /// An empty mechanism under gravity `[g_x, g_y]` (m/s²).
    pub fn new(gravity: [f64; 2]) -> Self {
        Self {
            spec: SystemSpec {
                gravity,
                bodies: Vec::new(),
                joints: Vec::new(),
                forces: Vec::new(),
                contacts: Vec::new(),
                contacts_auto: None,
                contact_set: ContactSet::Fixed,
                fill: Vec::new(),
            },
        }
    }

    /// Continues from a declaration (a scene file's, say).
    pub fn from_spec(spec: SystemSpec) -> Self {
        Self { spec }
    }

    /// Adds a body.
    pub fn add_body(&mut self, body: BodySpec) -> BodyHandle {
        self.spec.bodies.push(body);
        BodyHandle(self.spec.bodies.len() - 1)
    }

    /// Adds a joint.
    pub fn add_joint(&mut self, joint: JointSpec) -> JointHandle {
        self.spec.joints.push(joint);
        JointHandle(self.spec.joints.len() - 1)
    }

    /// Adds a force element.
    pub fn add_force(&mut self, force: ForceSpec) -> ForceHandle {
        self.spec.forces.push(force);
        ForceHandle(self.spec.forces.len() - 1)
    }

    /// Adds an explicit contact.
    pub fn add_contact(&mut self, contact: ContactSpec) -> ContactHandle {
        self.spec.contacts.push(contact);
        ContactHandle(self.spec.contacts.len() - 1)
    }

    /// Turns on automatic contacts.
    pub fn auto_contacts(&mut self, auto: AutoContacts) {
        self.spec.contacts_auto = Some(auto);
    }

    /// Chooses how the contacts are kept ([`ContactSet`]): the fixed list of slots (the
    /// default) or contacts detected at each step, for mechanisms of many bodies without
    /// joints.
    pub fn with_contact_set(&mut self, set: ContactSet) -> &mut Self {
        self.spec.contact_set = set;
        self
    }

    /// Adds a block of generated bodies ([`FillSpec`]); they follow the bodies added with
    /// [`Self::add_body`] in q, whenever they were added.
    pub fn add_fill(&mut self, fill: FillSpec) {
        self.spec.fill.push(fill);
    }

    /// The name of a body added before.
    pub fn body_name(&self, body: BodyHandle) -> Option<&str> {
        self.spec.bodies.get(body.0).map(|b| b.name.as_str())
    }

    /// The declaration so far.
    pub fn spec(&self) -> &SystemSpec {
        &self.spec
    }

    /// Validates and builds the mechanism ([`SystemSpec::build`]).
    ///
    /// # Errors
    /// As [`SystemSpec::build`].
    pub fn build(&self) -> Result<Multibody, ModelError> {
        self.spec.build()
    }
}

impl Motion {
    /// A motion given by a closure of time that returns the pose, velocity and angular
    /// velocity ([`DrivenState`]); the reference pose of the body is not used. The pose must
    /// be continuous and the rates its derivatives: the build samples the closure and refuses
    /// one that is not (see [`Motion::Custom`]).
    pub fn custom(f: impl Fn(f64) -> DrivenState + Send + Sync + 'static) -> Self {
        Motion::Custom(Closure::new(f))
    }
}

impl JointSpec {
    /// A revolute joint: the anchors (m, in each body's frame) coincide.
    pub fn revolute(
        name: &str,
        body_a: &str,
        anchor_a: [f64; 2],
        body_b: &str,
        anchor_b: [f64; 2],
    ) -> Self {
        JointSpec::Revolute {
            name: name.to_owned(),
            body_a: body_a.to_owned(),
            body_b: body_b.to_owned(),
            anchor_a,
            anchor_b,
        }
    }
}

impl Multibody {
    /// The first coordinate (x) of a dynamic body in q, `None` for a fixed or driven one.
    pub fn coordinates(&self, body: BodyHandle) -> Option<usize> {
        match self.bodies.get(body.0)?.kind {
            super::body::Kind::Dynamic { dof, .. } => Some(dof),
            _ => None,
        }
    }

    /// The pose (x, y, θ) of a body at (q, t) (m, rad).
    ///
    /// # Panics
    /// When the handle is not of this mechanism's builder.
    pub fn pose(&self, body: BodyHandle, q: &[f64], t: f64) -> [f64; 3] {
        let f = self.bodies[body.0].frame(q, t);
        [f.p[0], f.p[1], f.theta]
    }

    /// The indices of a joint's bilateral rows among `0..num_bilaterals()`.
    pub fn joint_rows(&self, joint: JointHandle) -> Range<usize> {
        let first = self.rows.iter().position(|r| r.0 == joint.0).unwrap_or(self.rows.len());
        let count = self.rows.iter().filter(|r| r.0 == joint.0).count();
        first..first + count
    }

    /// The indices of a clearance joint's contacts among `0..num_contacts()`.
    pub fn joint_contacts(&self, joint: JointHandle) -> Range<usize> {
        let of = |s: &Slot| matches!(s, Slot::Joint { joint: j, .. } if *j == joint.0);
        let first = self.slots.iter().position(of).unwrap_or(self.slots.len());
        first..first + self.slots.iter().filter(|s| of(s)).count()
    }
}

impl SystemSpec {
    /// An example declaration: a 1 kg rod of length 1 m (I_G = m ℓ²/12) hinged to the ground at
    /// one end, released horizontally under g = 9.81 m/s².
    pub fn example() -> SystemSpec {
        let mut builder = MultibodyBuilder::new([0.0, -9.81]);
        builder.add_body(BodySpec::dynamic("rod", 1.0, 1.0 / 12.0, [0.5, 0.0], 0.0));
        builder.add_joint(JointSpec::revolute(
            "hinge",
            super::GROUND,
            [0.0, 0.0],
            "rod",
            [-0.5, 0.0],
        ));
        builder.spec
    }
}
