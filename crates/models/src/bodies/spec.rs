//! The declared form of a mechanism: bodies, joints, force elements and contacts, as plain data
//! that reads and writes TOML. [`SystemSpec::build`] turns it into a [`super::Multibody`].
//!
//! Units are SI throughout: metres, radians, seconds, kilograms, newtons.

use std::fmt;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

pub use super::contact_spec::{AutoContacts, ContactSet, ContactSpec, PairOverride};
pub use super::fill::FillSpec;
pub use super::joint_spec::JointSpec;

/// A body's pose, velocity and angular velocity at a time t, as a driven body's closure
/// returns them (the rheonomic part of the contacts and joints with that body).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DrivenState {
    /// Position `[x, y]` of the body origin (m) and orientation θ (rad).
    pub pose: [f64; 3],
    /// Velocity `[ẋ, ẏ]` of the body origin (m/s).
    pub velocity: [f64; 2],
    /// Angular velocity θ̇ (rad/s).
    pub omega: f64,
}

/// A closure of time, shared (cheap to clone) and thread-safe, for the builder's motions and
/// loads that a scene file cannot state.
pub struct Closure<T>(pub Arc<dyn Fn(f64) -> T + Send + Sync>);

impl<T> Clone for Closure<T> {
    fn clone(&self) -> Self {
        Self(Arc::clone(&self.0))
    }
}

impl<T> fmt::Debug for Closure<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Closure(..)")
    }
}

impl<T> PartialEq for Closure<T> {
    /// Two closures are equal when they are the same closure.
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

impl<T> Closure<T> {
    /// Wraps a closure of time.
    pub fn new(f: impl Fn(f64) -> T + Send + Sync + 'static) -> Self {
        Self(Arc::new(f))
    }
}

/// What kind of body a [`BodySpec`] declares.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BodyType {
    /// A body that moves under its forces: three coordinates (x, y, θ) of q.
    Dynamic,
    /// A body that does not move (the ground, a wall).
    Fixed,
    /// A body whose pose is a given function of time (a cam, a shaken table): no coordinates,
    /// but the contacts and joints with it are rheonomic.
    Driven,
}

/// The motion of a driven body, relative to its declared `position` p₀ and `angle` θ₀: its
/// pose (x, y, θ) and the rates (ẋ, ẏ, θ̇) from which the contacts and joints with it get their
/// rheonomic terms ŵ = ∂g/∂t, as functions of the time t (s).
///
/// The closed forms `rotate`, `oscillate` and `linear` are continuous by construction, their
/// rates the exact derivatives of their poses, for every t. A [`Motion::Custom`] closure must
/// be so too: the build samples it and refuses one that is not finite, jumps or states rates
/// that are not its pose's derivatives (see [`Motion::Custom`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Motion {
    /// Rotation about the fixed point `pivot` by φ(t) = ω t + phase:
    /// p(t) = pivot + R(φ)(p₀ − pivot), θ(t) = θ₀ + φ(t); velocity ṗ(t) = ω k × (p(t) − pivot),
    /// θ̇ = ω. At t = 0 the body has already turned by `phase` from its declared pose.
    Rotate {
        /// The fixed centre of rotation `[x, y]` (m).
        pivot: [f64; 2],
        /// Angular velocity ω (rad/s).
        omega: f64,
        /// Phase: the angle turned at t = 0 (rad); default 0.
        #[serde(default)]
        phase: f64,
    },
    /// A shaken table, per axis i ∈ {x, y}, with A_i = `amplitude[i]` (m), Ω = `omega`
    /// (rad/s) and φ_i = `phase[i]` (rad):
    ///
    /// p_i(t) = p₀,i + A_i sin(Ω t + φ_i),  ṗ_i(t) = A_i Ω cos(Ω t + φ_i),  θ(t) = θ₀, θ̇ = 0.
    ///
    /// The declared `position` p₀ is the centre of the oscillation. With the default phase 0
    /// the body starts AT p₀ MOVING at its largest speed A_i Ω (a body declared at rest on
    /// it starts with a velocity −A_i Ω relative to it); with φ_i = π/2 it starts at rest at p₀,i + A_i, an end of its
    /// stroke (p_i = p₀,i + A_i cos Ω t). A quarter period later, t = π/(2Ω), phase 0 gives
    /// p₀ + A at rest. The period is 2π/Ω (s), the frequency Ω/(2π) (Hz).
    Oscillate {
        /// Amplitudes `[A_x, A_y]` (m).
        amplitude: [f64; 2],
        /// Angular frequency Ω (rad/s).
        omega: f64,
        /// Phases `[φ_x, φ_y]` (rad) at t = 0; default `[0, 0]` (start at the centre, moving).
        #[serde(default)]
        phase: [f64; 2],
    },
    /// Constant velocity: p(t) = p₀ + v t, θ(t) = θ₀ + ω t; ṗ = v, θ̇ = ω.
    Linear {
        /// Velocity `[v_x, v_y]` (m/s).
        velocity: [f64; 2],
        /// Angular velocity ω (rad/s); default 0.
        #[serde(default)]
        omega: f64,
    },
    /// Any motion, as a closure of time returning the pose and its rates (builder only; a
    /// scene file cannot hold it, and writing such a scene as TOML fails).
    ///
    /// The closure must give a pose continuous in t (θ included: an angle wrapped to
    /// (−π, π] jumps by 2π) and its exact rates: velocity = dp/dt, omega = dθ/dt. The rates
    /// may jump (a kink in the pose, an impulsive drive), the pose may not. The build checks
    /// it over 0 ≤ t ≤ 10 s and refuses it, as [`crate::ModelError::InvalidParameter`], where
    /// a value at t = 0, 0.01, ..., 10 s is not finite (naming `bodies.<name>.motion.pose.<k>`,
    /// `.velocity.<k>` or `.omega`), or where the pose's change over an interval is not the
    /// integral of the stated rate (naming `.velocity.<k>` or `.omega`): the intervals between
    /// those times are halved where Simpson's rule on the rate disagrees with the change by
    /// more than 1e-4 of the interval times the largest rate, down to 1e-8 s, where a change
    /// outside the interval times the range of the rate is a jump or a wrong rate. After 10 s,
    /// and past a million evaluations of a motion so fast that it needs them, the closure is
    /// trusted.
    #[serde(skip)]
    Custom(Closure<DrivenState>),
}

fn default_group() -> u32 {
    1
}

fn default_mask() -> u32 {
    u32::MAX
}

/// One body.
///
/// A dynamic body states either `mass` and `inertia` (with `center_of_mass`, default the body
/// origin) or a `density` from which its shapes give mass, centre of mass and inertia. The
/// body's coordinates are the pose (x, y, θ) of its ORIGIN, which need not be its centre of
/// mass: the mass matrix then couples translation and rotation (and depends on θ), and h gets
/// the centrifugal term. Put the origin at the centre of mass to keep M constant and diagonal,
/// or at the anchor of a revolute joint to a fixed body, where the joint's rows are constant.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Unique name; the coordinates are named `<name>.x`, `<name>.y`, `<name>.theta`.
    pub name: String,
    /// Dynamic, fixed or driven.
    #[serde(rename = "type")]
    pub kind: BodyType,
    /// Mass m (kg, > 0), dynamic bodies only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
    /// Moment of inertia about the body ORIGIN I_O (kg m², > 0), with `mass`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia: Option<f64>,
    /// Centre of mass in the body frame `[x, y]` (m), with `mass`; default the origin.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub center_of_mass: Option<[f64; 2]>,
    /// Density ρ (kg/m², > 0), instead of `mass` and `inertia`: m = ρ · area of the shapes,
    /// I_O = m · (their polar moment about the origin per area).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Position of the body origin `[x, y]` at t = 0 (m); for a driven body, p₀ of its motion.
    pub position: [f64; 2],
    /// Orientation θ at t = 0 (rad); default 0. Written out even at its default, with
    /// `velocity` and `omega`, so that every body's initial state is a key of its scene
    /// (`--set bodies.<name>.velocity.0=1`).
    #[serde(default)]
    pub angle: f64,
    /// Initial velocity of the origin `[ẋ, ẏ]` (m/s), dynamic bodies; default 0.
    #[serde(default)]
    pub velocity: [f64; 2],
    /// Initial angular velocity θ̇ (rad/s), dynamic bodies; default 0.
    #[serde(default)]
    pub omega: f64,
    /// The motion of a driven body (required for `type = "driven"`, refused otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motion: Option<Motion>,
    /// The body's shapes, in its frame (m), in the kinematics' form
    /// (`{ type = "disk", center = [0, 0], radius = 0.1 }`, `polygon` with `vertices`,
    /// `capsule`, `half_plane`, `polyline`, `profile`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub shapes: Vec<moreau_kinematics::Shape>,
    /// Collision group bits: automatic contacts exist between bodies a and b only when
    /// `a.group & b.mask != 0` and `b.group & a.mask != 0`. Default 1.
    #[serde(default = "default_group")]
    pub group: u32,
    /// Collision mask bits (see `group`). Default all bits.
    #[serde(default = "default_mask")]
    pub mask: u32,
}

impl BodySpec {
    /// A dynamic body with mass m (kg) and inertia about its origin, which is its centre of
    /// mass, I (kg m²), at `position` (m) and `angle` (rad), at rest.
    pub fn dynamic(name: &str, mass: f64, inertia: f64, position: [f64; 2], angle: f64) -> Self {
        Self {
            mass: Some(mass),
            inertia: Some(inertia),
            ..Self::with_kind(name, BodyType::Dynamic, position, angle)
        }
    }

    /// A dynamic body whose mass, centre of mass and inertia come from its shapes and the
    /// density ρ (kg/m²).
    pub fn with_density(name: &str, density: f64, position: [f64; 2], angle: f64) -> Self {
        Self { density: Some(density), ..Self::with_kind(name, BodyType::Dynamic, position, angle) }
    }

    /// A fixed body at `position` (m) and `angle` (rad).
    pub fn fixed(name: &str, position: [f64; 2], angle: f64) -> Self {
        Self::with_kind(name, BodyType::Fixed, position, angle)
    }

    /// A driven body with reference pose p₀ = `position`, θ₀ = `angle` and a motion.
    pub fn driven(name: &str, position: [f64; 2], angle: f64, motion: Motion) -> Self {
        Self { motion: Some(motion), ..Self::with_kind(name, BodyType::Driven, position, angle) }
    }

    fn with_kind(name: &str, kind: BodyType, position: [f64; 2], angle: f64) -> Self {
        Self {
            name: name.to_owned(),
            kind,
            mass: None,
            inertia: None,
            center_of_mass: None,
            density: None,
            position,
            angle,
            velocity: [0.0; 2],
            omega: 0.0,
            motion: None,
            shapes: Vec::new(),
            group: default_group(),
            mask: default_mask(),
        }
    }

    /// The same body with one more shape.
    pub fn with_shape(mut self, shape: moreau_kinematics::Shape) -> Self {
        self.shapes.push(shape);
        self
    }

    /// The same body with an initial velocity (m/s) and angular velocity (rad/s).
    pub fn with_velocity(mut self, velocity: [f64; 2], omega: f64) -> Self {
        self.velocity = velocity;
        self.omega = omega;
        self
    }
}

/// A load as a function of time: a constant, or A sin(Ω t + φ) + offset, or (builder only)
/// any closure. In a scene file `fx = 2.0` or
/// `fx = { amplitude = 1.0, omega = 6.28, phase = 0.0, offset = 0.0 }`; a table with any
/// other field is refused by name.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum TimeFunction {
    /// A constant value.
    Constant(f64),
    /// A sin(Ω t + φ) + offset.
    Sine {
        /// Amplitude A (the load's unit).
        amplitude: f64,
        /// Angular frequency Ω (rad/s).
        omega: f64,
        /// Phase φ (rad); default 0.
        phase: f64,
        /// Offset (the load's unit); default 0.
        offset: f64,
    },
    /// Any function of time (builder only).
    #[serde(skip)]
    Custom(Closure<f64>),
}

impl<'de> Deserialize<'de> for TimeFunction {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        use serde::de::{Error, MapAccess, Visitor};
        const FIELDS: &[&str] = &["amplitude", "omega", "phase", "offset"];
        struct Read;
        impl<'de> Visitor<'de> for Read {
            type Value = TimeFunction;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a number, or a table { amplitude, omega, phase, offset }")
            }
            fn visit_f64<E: Error>(self, v: f64) -> Result<TimeFunction, E> {
                Ok(TimeFunction::Constant(v))
            }
            fn visit_i64<E: Error>(self, v: i64) -> Result<TimeFunction, E> {
                Ok(TimeFunction::Constant(v as f64))
            }
            fn visit_u64<E: Error>(self, v: u64) -> Result<TimeFunction, E> {
                Ok(TimeFunction::Constant(v as f64))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<TimeFunction, A::Error> {
                let mut values = [None; 4];
                while let Some(key) = map.next_key::<String>()? {
                    let Some(i) = FIELDS.iter().position(|f| *f == key) else {
                        return Err(A::Error::unknown_field(&key, FIELDS));
                    };
                    if values[i].is_some() {
                        return Err(A::Error::duplicate_field(FIELDS[i]));
                    }
                    values[i] = Some(map.next_value::<f64>()?);
                }
                let [amplitude, omega, phase, offset] = values;
                Ok(TimeFunction::Sine {
                    amplitude: amplitude.ok_or_else(|| A::Error::missing_field("amplitude"))?,
                    omega: omega.ok_or_else(|| A::Error::missing_field("omega"))?,
                    phase: phase.unwrap_or(0.0),
                    offset: offset.unwrap_or(0.0),
                })
            }
        }
        deserializer.deserialize_any(Read)
    }
}

impl TimeFunction {
    /// The value at time t.
    #[inline]
    pub fn at(&self, t: f64) -> f64 {
        match self {
            TimeFunction::Constant(v) => *v,
            TimeFunction::Sine { amplitude, omega, phase, offset } => {
                amplitude * (omega * t + phase).sin() + offset
            }
            TimeFunction::Custom(f) => (f.0)(t),
        }
    }
}

/// One force element. Body names as for joints (`ground` is the world).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum ForceSpec {
    /// A linear spring-damper between two anchors: tension F = k (ℓ − ℓ₀) + c ℓ̇ along the
    /// line of the anchors, potential ½ k (ℓ − ℓ₀)².
    Spring {
        /// Optional name (for `--set forces.<name>.<field>`).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        name: Option<String>,
        /// First body.
        body_a: String,
        /// Anchor on body a (m).
        anchor_a: [f64; 2],
        /// Second body.
        body_b: String,
        /// Anchor on body b (m).
        anchor_b: [f64; 2],
        /// Stiffness k (N/m, >= 0).
        stiffness: f64,
        /// Rest length ℓ₀ (m, >= 0).
        rest_length: f64,
        /// Damping c (N s/m, >= 0); default 0.
        #[serde(default)]
        damping: f64,
    },
    /// A torsional spring-damper between two bodies' angles: torque τ = k (θ_b − θ_a − θ₀) +
    /// c (θ̇_b − θ̇_a) on a, −τ on b, potential ½ k (θ_b − θ_a − θ₀)².
    Torsion {
        /// Optional name.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        name: Option<String>,
        /// First body.
        body_a: String,
        /// Second body.
        body_b: String,
        /// Stiffness k (N m/rad, >= 0).
        stiffness: f64,
        /// Rest relative angle θ₀ (rad).
        rest_angle: f64,
        /// Damping c (N m s/rad, >= 0); default 0.
        #[serde(default)]
        damping: f64,
    },
    /// A force (f_x, f_y)(t) in the world frame (N) applied at a point of a body.
    Force {
        /// Optional name.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        name: Option<String>,
        /// The loaded body.
        body: String,
        /// The point of application on the body (m); default the origin.
        #[serde(default)]
        point: [f64; 2],
        /// f_x(t) (N).
        fx: TimeFunction,
        /// f_y(t) (N).
        fy: TimeFunction,
    },
    /// A torque τ(t) on a body (N m).
    Torque {
        /// Optional name.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        name: Option<String>,
        /// The loaded body.
        body: String,
        /// τ(t) (N m).
        torque: TimeFunction,
    },
}

impl ForceSpec {
    /// The force element's name, if it has one.
    pub fn name(&self) -> Option<&str> {
        match self {
            ForceSpec::Spring { name, .. }
            | ForceSpec::Torsion { name, .. }
            | ForceSpec::Force { name, .. }
            | ForceSpec::Torque { name, .. } => name.as_deref(),
        }
    }
}

/// A declared mechanism: gravity, bodies, joints, force elements and contacts.
///
/// In a scene file these are the top-level `gravity` and `contact_set`, the arrays of tables
/// `[[bodies]]`, `[[fill]]`, `[[joints]]`, `[[forces]]`, `[[contacts]]`, and the table
/// `[contacts_auto]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SystemSpec {
    /// Gravity `[g_x, g_y]` (m/s²), acting on every dynamic body's centre of mass.
    pub gravity: [f64; 2],
    /// The bodies; the dynamic ones give q = (x, y, θ) each, in this order.
    pub bodies: Vec<BodySpec>,
    /// The joints.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joints: Vec<JointSpec>,
    /// The force elements besides gravity.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub forces: Vec<ForceSpec>,
    /// The explicit contacts.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub contacts: Vec<ContactSpec>,
    /// Automatic contacts, none when omitted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contacts_auto: Option<AutoContacts>,
    /// How the contacts are kept: a fixed list of slots (default) or detected at each step.
    #[serde(default, skip_serializing_if = "ContactSet::is_fixed")]
    pub contact_set: ContactSet,
    /// Generated bodies, which follow `bodies` in q.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fill: Vec<FillSpec>,
}
