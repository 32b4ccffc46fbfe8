//! Declared mechanisms: bodies, joints, force elements and contacts, from which Moreau builds
//! the `moreau_stepper::Mechanism` ([`Multibody`]) instead of the user deriving M, h, the gaps
//! and their force directions by hand.
//!
//! # Coordinates
//! Maximal coordinates: q = (x, y, θ) of each DYNAMIC body's origin, in declaration order
//! (f = 3 n_dyn), named `<body>.x`, `<body>.y`, `<body>.theta`; velocities `<body>.vx`,
//! `<body>.vy`, `<body>.omega`. Fixed bodies have no coordinates; driven bodies move as a
//! given function of time, so that joints and contacts with them are rheonomic (ŵ ≠ 0).
//!
//! # Mass
//! A body's mass m and inertia I_O are about its origin; with the centre of mass at c in the
//! body frame and s = R(θ) c, the body's block of M is [[m, 0, −m s_y], [0, m, m s_x],
//! [−m s_y, m s_x, I_O]] and h gets the centrifugal m θ̇² s. Putting the origin at the centre
//! of mass makes M constant and diagonal, which the stepper factorises once; putting it at
//! the anchor of a revolute joint to a fixed body keeps that joint exact (see Joints).
//!
//! # Joints
//! Bilateral rows g_B(q, t) = 0 (solved in the step problem, free in sign): revolute (2 rows),
//! prismatic (2), weld (3), point-on-line (1), motor (1, θ_b − θ_a − θ₀ − Ω t, ŵ = −Ω).
//! Clearance joints are unilateral contacts instead: a revolute joint with radial clearance
//! (pin in a bearing, one contact) and a translational joint with clearance (a block's four
//! corners against a guide's two lines).
//!
//! The step holds a joint at the velocity level at the midpoint, on the average of the start
//! and end velocities (docs/theory.md section 9): its impulses do no work, its drift is
//! O(Δt³) per step (the projection puts it back), and a starting velocity that violates it is
//! brought onto it by the first step, which `Record::cumulative_dissipation` counts. A rod 1 m
//! long hinged at one end, released at 1 rad, over 40 s (about 22 swings): its energy ends
//! 4.5e-6 of its swing energy m g (L/2)(1 − cos 1) lower at Δt = 1e-3 s and 1.9e-8 at 1e-4 s,
//! without the projection.
//!
//! # Contacts and contact sets
//! Explicit contacts name a shape of one body against a shape of another; automatic contacts
//! cover every pair of shapes the collision groups allow (not both on bodies without
//! coordinates, not joined by a joint). The scene field `contact_set` says how they are kept
//! ([`ContactSet`]):
//! * `fixed` (default): a list of slots built once, one per pair and feature of the pair, each
//!   named and closed or open at each step, the contacts of
//!   `moreau_kinematics::ContactKinematics`. Automatic slots grow as the square of the number
//!   of bodies; clearance joints, whose contacts are slots, need this mode. The list holds
//!   the clearance joints' slots, then the explicit contacts' in declaration order, then the
//!   automatic pairs' (by body a, body b, shape a, shape b, a the earlier body). Within a
//!   pair slot k is feature k of the narrow phase: a polygon on a half-plane has one slot per
//!   vertex, slot k its vertex k in declared order (a box declared counter-clockwise from its
//!   lower left corner, resting flat on a floor, closes slots 0 and 1); two polygons have
//!   n_a + n_b, slot i vertex i of a on a face of b, slot n_a + j vertex j of b on a face of a;
//!   a disk has one. A pair of one slot names it `<name>`, otherwise `<name>.<k>`, with the
//!   explicit contact's name or `<body a>.<shape a>-<body b>.<shape b>`.
//! * `detected`: no slots, so `num_contacts()` is 0; [`Multibody`] announces
//!   `Mechanism::body_structure` and implements `moreau_stepper::BodyStructure`: a 3 × 3 mass
//!   block per dynamic body, and at each (q, t) the contacts within the stepper's margin found
//!   by the broad phase over all shapes and the narrow phase, under the same rules and with the
//!   same force directions as the slots. Each contact's identity is built from its two shapes
//!   (numbered in body then shape order) and its feature: unique, increasing in the order
//!   returned, and the same while the same features touch. The ideal joints' rows are split
//!   by body too (`BodyStructure::bilateral_rows`) and solved in each island's problem; a
//!   scene with a clearance joint is refused in this mode, naming `contact_set`.
//!
//! # Generated bodies
//! A [`FillSpec`] (`[[fill]]` in a scene file) expands at build time into many dynamic bodies
//! of one template shape, on a lattice or in Box2D's pyramid layout, with sizes and offsets
//! drawn from a seeded generator; they follow the declared bodies in q.
//!
//! # Force elements
//! Gravity, linear and torsional spring-dampers, applied forces and torques as functions of
//! time; the potential energy V(q) covers gravity and the springs.
//!
//! # Units
//! SI: m, rad, s, kg, N; inertia kg m², density kg/m², stiffness N/m or N m/rad.

mod assemble;
mod body;
mod build;
mod builder;
mod contact_spec;
mod contacts;
mod crossing;
pub(crate) mod detect;
mod draw;
mod fill;
mod forces;
mod joint_spec;
pub(crate) mod joints;
mod motion;
mod multibody;
mod shape_check;
mod spec;

pub use assemble::MAX_ASSEMBLY_MOVE;
pub use build::GROUND;
pub use builder::{BodyHandle, ContactHandle, ForceHandle, JointHandle, MultibodyBuilder};
pub use crossing::{Crossing, CrossingCheck};
pub use fill::{FillPattern, MAX_FILL_BODIES};
pub use joints::SlotGeometry;
pub use multibody::{LocatedContact, Multibody};
pub use spec::{
    AutoContacts, BodySpec, BodyType, Closure, ContactSet, ContactSpec, DrivenState, FillSpec,
    ForceSpec, JointSpec, Motion, PairOverride, SystemSpec, TimeFunction,
};
