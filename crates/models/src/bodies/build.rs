//! [`SystemSpec::build`]: validation of a declaration and its translation into a
//! [`Multibody`], with errors that name the offending field by its `--set` path.

use moreau_kinematics::ChainIndex;
use moreau_lcp::MAX_ENTRY;
use moreau_setvalued::ContactLaw;

use super::assemble::assemble;
use super::body::{Body, Kind, scale};
use super::contact_spec::ContactSet;
use super::contacts::{Rules, pairs};
use super::detect::Detector;
use super::fill::{FillPattern, MAX_FILL_BODIES};
use super::forces::Force;
use super::joints::{Joint, JointKind};
use super::motion::check_motion;
use super::multibody::{Multibody, Slot};
use super::shape_check::check_shape;
use super::spec::{BodySpec, BodyType, ForceSpec, JointSpec, SystemSpec};
use crate::ModelError;
use crate::params::{LawParams, finite, non_negative, positive, relation};

/// The name that stands for the world frame; reserved, so no declared body may take it.
pub const GROUND: &str = "ground";

pub(crate) fn bad(key: String, value: &str, reason: String) -> ModelError {
    ModelError::BadValue { key, value: value.to_owned(), reason }
}

fn finite2(field: &str, v: [f64; 2]) -> Result<(), ModelError> {
    finite(&format!("{field}.0"), v[0])?;
    finite(&format!("{field}.1"), v[1])
}

/// A direction made unit; refuses a zero or non-finite one.
fn unit(field: &str, v: [f64; 2]) -> Result<[f64; 2], ModelError> {
    finite2(field, v)?;
    let n = v[0].hypot(v[1]);
    if n > 0.0 { Ok(scale(v, 1.0 / n)) } else { Err(relation(field, 0.0, "must not be zero")) }
}

pub(crate) fn law(prefix: &str, eps_n: f64, eps_t: f64, mu: f64) -> Result<ContactLaw, ModelError> {
    LawParams::new(eps_n, eps_t, mu).law(prefix)
}

/// Finds a body by name for the field `field`, adding the implicit ground when named.
pub(crate) fn resolve(
    bodies: &mut Vec<Body>,
    field: &str,
    name: &str,
) -> Result<usize, ModelError> {
    if let Some(i) = bodies.iter().position(|b| b.name == name) {
        return Ok(i);
    }
    if name == GROUND {
        bodies.push(Body {
            name: GROUND.to_owned(),
            kind: Kind::fixed([0.0; 3]),
            pose0: [0.0; 3],
            shapes: Vec::new(),
            chains: Vec::new(),
            group: 0,
            mask: 0,
        });
        return Ok(bodies.len() - 1);
    }
    // The world, added when a joint or force first names it, is named apart.
    let known: Vec<&str> =
        bodies.iter().map(|b| b.name.as_str()).filter(|n| *n != GROUND).collect();
    Err(bad(
        field.to_owned(),
        name,
        format!(
            "no body has this name; bodies: {} (or `{GROUND}` for the world)",
            known.join(", ")
        ),
    ))
}

fn body(spec: &BodySpec, dof: usize) -> Result<Body, ModelError> {
    let path = format!("bodies.{}", spec.name);
    let field = |f: &str| format!("{path}.{f}");
    finite2(&field("position"), spec.position)?;
    finite(&field("angle"), spec.angle)?;
    finite2(&field("velocity"), spec.velocity)?;
    finite(&field("omega"), spec.omega)?;
    let refuse = |f: &str, present: bool, why: &str| {
        if present { Err(bad(field(f), "(given)", why.to_owned())) } else { Ok(()) }
    };
    let moving = spec.velocity != [0.0; 2] || spec.omega != 0.0;
    for (k, shape) in spec.shapes.iter().enumerate() {
        check_shape(&format!("{path}.shapes.{k}"), shape)?;
    }
    let kind = match spec.kind {
        BodyType::Dynamic => {
            refuse("motion", spec.motion.is_some(), "only a driven body has a motion")?;
            let why = |what: &str| {
                format!("a dynamic body needs either mass and inertia or a density; {what}")
            };
            let (mass, inertia, com) = match (spec.mass, spec.inertia, spec.density) {
                (Some(m), Some(i), None) => {
                    positive(&field("mass"), m)?;
                    if i == 0.0 {
                        // A point mass has no rotation to speak of, but its θ is a coordinate
                        // all the same, and M must be positive definite.
                        return Err(relation(
                            &field("inertia"),
                            i,
                            "a body's θ is one of its coordinates, so M needs an inertia > 0: \
                             give a point mass that of a small disk (m r² / 2)",
                        ));
                    }
                    positive(&field("inertia"), i)?;
                    let com = spec.center_of_mass.unwrap_or([0.0; 2]);
                    finite2(&field("center_of_mass"), com)?;
                    let c2 = com[0] * com[0] + com[1] * com[1];
                    if i <= m * c2 {
                        return Err(relation(
                            &field("inertia"),
                            i,
                            "the inertia about the origin must exceed m |center_of_mass|²",
                        ));
                    }
                    (m, i, com)
                }
                (None, None, Some(rho)) => {
                    positive(&field("density"), rho)?;
                    refuse(
                        "center_of_mass",
                        spec.center_of_mass.is_some(),
                        "follows from the shapes when a density is given",
                    )?;
                    // Shapes without a finite area (half-planes, polylines) only collide.
                    let (mut area, mut first, mut polar) = (0.0, [0.0; 2], 0.0);
                    for shape in &spec.shapes {
                        let (a, Ok(unit)) = (shape.area(), shape.unit_inertia()) else { continue };
                        if a.is_finite() && a > 0.0 {
                            let c = shape.centroid();
                            area += a;
                            first = [first[0] + a * c[0], first[1] + a * c[1]];
                            polar += a * unit;
                        }
                    }
                    if area <= 0.0 {
                        return Err(bad(
                            field("density"),
                            &rho.to_string(),
                            "the body's shapes have no area; give mass and inertia".to_owned(),
                        ));
                    }
                    (rho * area, rho * polar, [first[0] / area, first[1] / area])
                }
                (Some(_), None, None) => {
                    return Err(bad(field("inertia"), "(missing)", why("`mass` is given")));
                }
                (None, Some(_), None) => {
                    return Err(bad(field("mass"), "(missing)", why("`inertia` is given")));
                }
                (None, None, None) => {
                    return Err(bad(field("mass"), "(missing)", why("none is given")));
                }
                (_, _, Some(rho)) => {
                    return Err(bad(
                        field("density"),
                        &rho.to_string(),
                        why("`density` is given with `mass` or `inertia`, not instead"),
                    ));
                }
            };
            // The step's problem holds 1/m and 1/I: beyond moreau-lcp's range of entries
            // (2^±500, about 3e±150) its first contact would be refused, far from the cause.
            let range = 1.0 / MAX_ENTRY..=MAX_ENTRY;
            for (name, value) in [("mass", mass), ("inertia", inertia)] {
                if !range.contains(&value) {
                    let bounds = "[2^-500, 2^500] (about 3e-151 to 3e150), the range of the \
                                  step's problem; choose other units";
                    // The field the user wrote, with its own value: a density names the mass or
                    // inertia it gives.
                    return Err(match spec.density {
                        Some(rho) => relation(
                            &field("density"),
                            rho,
                            &format!("gives a {name} of {value:e}, outside {bounds}"),
                        ),
                        None => relation(&field(name), value, &format!("outside {bounds}")),
                    });
                }
            }
            Kind::Dynamic { dof, mass, inertia, com }
        }
        BodyType::Fixed | BodyType::Driven => {
            let what = if spec.kind == BodyType::Fixed { "fixed" } else { "driven" };
            let why = format!("a {what} body has no mass properties");
            refuse("mass", spec.mass.is_some(), &why)?;
            refuse("inertia", spec.inertia.is_some(), &why)?;
            refuse("density", spec.density.is_some(), &why)?;
            refuse("center_of_mass", spec.center_of_mass.is_some(), &why)?;
            refuse("velocity", moving, &format!("a {what} body's motion is not an initial state"))?;
            if spec.kind == BodyType::Fixed {
                refuse("motion", spec.motion.is_some(), "only a driven body has a motion")?;
                Kind::fixed([spec.position[0], spec.position[1], spec.angle])
            } else {
                let motion = spec.motion.clone().ok_or_else(|| {
                    bad(field("motion"), "(missing)", "a driven body needs a motion".to_owned())
                })?;
                check_motion(
                    &field("motion"),
                    &motion,
                    [spec.position[0], spec.position[1], spec.angle],
                )?;
                Kind::Driven(motion)
            }
        }
    };
    Ok(Body {
        name: spec.name.clone(),
        kind,
        pose0: [spec.position[0], spec.position[1], spec.angle],
        shapes: spec.shapes.clone(),
        chains: spec.shapes.iter().map(ChainIndex::new).collect(),
        group: spec.group,
        mask: spec.mask,
    })
}

/// The relative angle θ_b − θ_a at the start time t₀ of two built bodies.
fn relative_angle(bodies: &[Body], a: usize, b: usize, t0: f64) -> f64 {
    let frame = |i: usize| bodies[i].frame(&[], t0);
    // Dynamic bodies' frames need q; their declared angle is their pose0.
    let angle = |i: usize| match bodies[i].kind {
        Kind::Dynamic { .. } => bodies[i].pose0[2],
        _ => frame(i).theta,
    };
    angle(b) - angle(a)
}

fn joint(
    spec: &JointSpec,
    bodies: &mut Vec<Body>,
    t0: f64,
) -> Result<(Joint, Option<ContactLaw>), ModelError> {
    let name = spec.name();
    let path = format!("joints.{name}");
    let field = |f: &str| format!("{path}.{f}");
    let (na, nb) = spec.bodies();
    let a = resolve(bodies, &field("body_a"), na)?;
    let b = resolve(bodies, &field("body_b"), nb)?;
    if a == b {
        return Err(bad(field("body_b"), nb, "a joint needs two different bodies".to_owned()));
    }
    if !bodies[a].is_dynamic() && !bodies[b].is_dynamic() {
        return Err(bad(field("body_b"), nb, "a joint needs at least one dynamic body".to_owned()));
    }
    let reference = |angle: Option<f64>| -> Result<f64, ModelError> {
        match angle {
            Some(v) => finite(&field("angle"), v).map(|()| v),
            None => Ok(relative_angle(bodies, a, b, t0)),
        }
    };
    // The anchors of every kind are checked alike, before what is particular to the kind.
    if let Some((ra, rb)) = spec.anchors() {
        finite2(&field("anchor_a"), ra)?;
        finite2(&field("anchor_b"), rb)?;
    }
    let kind = match *spec {
        JointSpec::Revolute { anchor_a, anchor_b, .. } => {
            JointKind::Revolute { ra: anchor_a, rb: anchor_b }
        }
        JointSpec::Prismatic { anchor_a, anchor_b, axis, angle, .. } => {
            let d = unit(&field("axis"), axis)?;
            JointKind::Prismatic {
                ra: anchor_a,
                rb: anchor_b,
                normal_a: [-d[1], d[0]],
                angle: reference(angle)?,
            }
        }
        JointSpec::Weld { anchor_a, anchor_b, angle, .. } => {
            JointKind::Weld { ra: anchor_a, rb: anchor_b, angle: reference(angle)? }
        }
        JointSpec::PointOnLine { anchor_a, anchor_b, axis, .. } => {
            let d = unit(&field("axis"), axis)?;
            JointKind::PointOnLine { ra: anchor_a, rb: anchor_b, normal_b: [-d[1], d[0]] }
        }
        JointSpec::Motor { omega, angle, .. } => {
            finite(&field("omega"), omega)?;
            // θ_b − θ_a − angle − Ω t vanishes at t₀ by default.
            let angle = match angle {
                Some(_) => reference(angle)?,
                None => relative_angle(bodies, a, b, t0) - omega * t0,
            };
            JointKind::Motor { omega, angle }
        }
        JointSpec::RevoluteClearance { anchor_a, anchor_b, pin_radius, bearing_radius, .. } => {
            non_negative(&field("pin_radius"), pin_radius)?;
            non_negative(&field("bearing_radius"), bearing_radius)?;
            if bearing_radius < pin_radius {
                return Err(relation(
                    &field("bearing_radius"),
                    bearing_radius,
                    "must be at least pin_radius",
                ));
            }
            JointKind::RevoluteClearance { ra: anchor_a, rb: anchor_b, pin_radius, bearing_radius }
        }
        JointSpec::TranslationalClearance {
            anchor_a,
            axis_a,
            length,
            width,
            anchor_b,
            axis_b,
            guide_width,
            ..
        } => {
            positive(&field("length"), length)?;
            positive(&field("width"), width)?;
            positive(&field("guide_width"), guide_width)?;
            if guide_width < width {
                return Err(relation(&field("guide_width"), guide_width, "must be at least width"));
            }
            JointKind::TranslationalClearance {
                ra: anchor_a,
                axis_a: unit(&field("axis_a"), axis_a)?,
                half_length: 0.5 * length,
                half_width: 0.5 * width,
                rb: anchor_b,
                axis_b: unit(&field("axis_b"), axis_b)?,
                half_guide: 0.5 * guide_width,
            }
        }
    };
    let contact_law =
        spec.clearance_law().map(|(eps_n, eps_t, mu)| law(&path, eps_n, eps_t, mu)).transpose()?;
    Ok((Joint { name: name.to_owned(), a, b, kind }, contact_law))
}

fn force(spec: &ForceSpec, index: usize, bodies: &mut Vec<Body>) -> Result<Force, ModelError> {
    let path = format!("forces.{}", spec.name().map_or_else(|| index.to_string(), str::to_owned));
    let field = |f: &str| format!("{path}.{f}");
    // An element must be able to move something: a load on a dynamic body, a spring or
    // torsion between two bodies of which one at least is dynamic.
    let loaded = |bodies: &[Body], body: usize, name: &str| {
        if bodies[body].is_dynamic() {
            Ok(())
        } else {
            Err(bad(field("body"), name, "not a dynamic body: a load on it moves nothing".into()))
        }
    };
    let pair = |bodies: &[Body], a: usize, b: usize, name_b: &str| {
        if a == b {
            Err(bad(
                field("body_b"),
                name_b,
                "the same body as body_a: an element between a body and itself exerts no force"
                    .into(),
            ))
        } else if !bodies[a].is_dynamic() && !bodies[b].is_dynamic() {
            Err(bad(
                field("body_b"),
                name_b,
                "neither body_a nor body_b is a dynamic body: the element moves nothing".into(),
            ))
        } else {
            Ok(())
        }
    };
    Ok(match spec {
        ForceSpec::Spring {
            body_a,
            anchor_a,
            body_b,
            anchor_b,
            stiffness,
            rest_length,
            damping,
            ..
        } => {
            let a = resolve(bodies, &field("body_a"), body_a)?;
            let b = resolve(bodies, &field("body_b"), body_b)?;
            pair(bodies, a, b, body_b)?;
            finite2(&field("anchor_a"), *anchor_a)?;
            finite2(&field("anchor_b"), *anchor_b)?;
            non_negative(&field("stiffness"), *stiffness)?;
            non_negative(&field("rest_length"), *rest_length)?;
            non_negative(&field("damping"), *damping)?;
            Force::Spring {
                a,
                ra: *anchor_a,
                b,
                rb: *anchor_b,
                k: *stiffness,
                rest: *rest_length,
                c: *damping,
            }
        }
        ForceSpec::Torsion { body_a, body_b, stiffness, rest_angle, damping, .. } => {
            let a = resolve(bodies, &field("body_a"), body_a)?;
            let b = resolve(bodies, &field("body_b"), body_b)?;
            pair(bodies, a, b, body_b)?;
            non_negative(&field("stiffness"), *stiffness)?;
            finite(&field("rest_angle"), *rest_angle)?;
            non_negative(&field("damping"), *damping)?;
            Force::Torsion { a, b, k: *stiffness, rest: *rest_angle, c: *damping }
        }
        ForceSpec::Force { body: name, point, fx, fy, .. } => {
            let body = resolve(bodies, &field("body"), name)?;
            loaded(bodies, body, name)?;
            finite2(&field("point"), *point)?;
            check_time_function(&field("fx"), fx)?;
            check_time_function(&field("fy"), fy)?;
            Force::Point { body, r: *point, fx: fx.clone(), fy: fy.clone() }
        }
        ForceSpec::Torque { body: name, torque, .. } => {
            let body = resolve(bodies, &field("body"), name)?;
            loaded(bodies, body, name)?;
            check_time_function(&field("torque"), torque)?;
            Force::Torque { body, torque: torque.clone() }
        }
    })
}

fn check_time_function(field: &str, f: &super::spec::TimeFunction) -> Result<(), ModelError> {
    use super::spec::TimeFunction;
    match f {
        TimeFunction::Constant(v) => finite(field, *v),
        TimeFunction::Sine { amplitude, omega, phase, offset } => {
            finite(&format!("{field}.amplitude"), *amplitude)?;
            finite(&format!("{field}.omega"), *omega)?;
            finite(&format!("{field}.phase"), *phase)?;
            finite(&format!("{field}.offset"), *offset)
        }
        TimeFunction::Custom(_) => Ok(()),
    }
}

/// Requires unique, non-empty names, each usable as one `--set` path segment.
fn unique<'a>(what: &str, names: impl Iterator<Item = &'a str>) -> Result<(), ModelError> {
    // A set, since generated bodies number in the thousands.
    let mut seen = std::collections::HashSet::new();
    for name in names {
        if name.is_empty() || name.contains(['.', '=']) || name.parse::<usize>().is_ok() {
            return Err(bad(
                format!("{what}.name"),
                name,
                "a name must be non-empty, not a number, and hold no `.` or `=`".to_owned(),
            ));
        }
        if !seen.insert(name) {
            return Err(bad(format!("{what}.{name}.name"), name, "declared twice".to_owned()));
        }
    }
    Ok(())
}

impl SystemSpec {
    /// Validates the declaration and builds the mechanism.
    ///
    /// The initial positions are assembled onto the joints (the smallest change of q₀, by
    /// Gauss-Newton iterations), so declared positions need only be close: assembly may move
    /// a body's origin by at most [`MAX_ASSEMBLY_MOVE`](super::MAX_ASSEMBLY_MOVE) (10 %) of the mechanism's length, the
    /// larger of its [size](Multibody::size) and 0.6 times the diagonal of the box around its
    /// dynamic bodies' declared origins and its joints' anchors; a declaration further off is
    /// refused, naming the body, the joint and how far it had to move. The initial
    /// velocities are left as declared, and the first step's joint impulses make them
    /// consistent.
    ///
    /// # Errors
    /// [`ModelError::InvalidParameter`] or [`ModelError::BadValue`] naming the field by its
    /// `--set` path (`bodies.block.mass`, `joints.hinge.anchor_a.1`, `forces.0.stiffness`,
    /// `contacts.floor.mu`, ...), [`ModelError::Law`] for a contact law; a body named
    /// [`GROUND`] (`bodies.ground.name`), which is reserved for the world; a body that
    /// assembly would move too far (`bodies.<name>.position`).
    pub fn build(&self) -> Result<Multibody, ModelError> {
        self.build_at(0.0)
    }

    /// [`Self::build`] for a run that starts at t₀ (s) rather than 0: the declared positions
    /// and velocities are the state at t₀, where the driven bodies' motions, the joints'
    /// reference angles left to their default (the relative angle at t₀; a motor's such that
    /// θ_b − θ_a − angle − Ω t vanishes at t₀) and the assembly are evaluated.
    ///
    /// # Errors
    /// As [`Self::build`]; [`ModelError::InvalidParameter`] for a t₀ that is not finite.
    pub fn build_at(&self, t0: f64) -> Result<Multibody, ModelError> {
        finite("t_start", t0)?;
        if self.fill.is_empty() {
            return self.build_expanded(self, t0);
        }
        unique("fill", self.fill.iter().map(|f| f.name.as_str()))?;
        // The fills together, each within the limit (checked by `FillSpec::bodies`).
        let mut total = 0usize;
        for f in &self.fill {
            if f.len() > MAX_FILL_BODIES {
                break;
            }
            total += f.len();
            if total > MAX_FILL_BODIES {
                let size = if f.pattern == FillPattern::Pyramid { "base" } else { "count" };
                return Err(bad(
                    format!("fill.{}.{size}", f.name),
                    &f.base.or(f.count).unwrap_or(0).to_string(),
                    format!(
                        "the fills up to this one would make {total} bodies, more than the \
                         {MAX_FILL_BODIES} a mechanism's fills may make"
                    ),
                ));
            }
        }
        let mut expanded = self.clone();
        for fill in std::mem::take(&mut expanded.fill) {
            expanded.bodies.extend(fill.bodies()?);
        }
        expanded.build_expanded(self, t0)
    }

    /// Builds a declaration without fills, its initial state at t₀; `original` is kept as the
    /// mechanism's declaration.
    fn build_expanded(&self, original: &SystemSpec, t0: f64) -> Result<Multibody, ModelError> {
        finite2("gravity", self.gravity)?;
        // A clearance joint's contacts are slots of the fixed contact list, which the detected
        // set does not keep; its ideal joints are rows of the step problem in either set.
        if self.contact_set == ContactSet::Detected
            && let Some(j) = self.joints.iter().find(|j| j.clearance_law().is_some())
        {
            return Err(bad(
                "contact_set".to_owned(),
                "detected",
                format!(
                    "the clearance joint `{}` is a set of contact slots, which need the fixed \
                     contact set; use `contact_set = \"fixed\"`",
                    j.name()
                ),
            ));
        }
        unique("bodies", self.bodies.iter().map(|b| b.name.as_str()))?;
        // Joints and forces name the world `ground`: a body of that name would silently take
        // its place in every one of them.
        if self.bodies.iter().any(|b| b.name == GROUND) {
            return Err(bad(
                format!("bodies.{GROUND}.name"),
                GROUND,
                format!(
                    "the name `{GROUND}` is reserved for the world, which joints and forces \
                     name `{GROUND}`; give the body another name"
                ),
            ));
        }
        unique("joints", self.joints.iter().map(JointSpec::name))?;
        unique("forces", self.forces.iter().filter_map(ForceSpec::name))?;
        unique("contacts", self.contacts.iter().map(|c| c.name.as_str()))?;
        let mut bodies = Vec::with_capacity(self.bodies.len() + 1);
        let mut dynamic = Vec::new();
        for spec in &self.bodies {
            let b = body(spec, 3 * dynamic.len())?;
            if b.is_dynamic() {
                dynamic.push(bodies.len());
            }
            bodies.push(b);
        }
        let mut joints = Vec::new();
        let mut rows = Vec::new();
        let mut slots = Vec::new();
        let mut laws = Vec::new();
        let mut contact_names = Vec::new();
        for spec in &self.joints {
            let (j, contact_law) = joint(spec, &mut bodies, t0)?;
            let index = joints.len();
            rows.extend((0..j.kind.num_rows()).map(|k| (index, k)));
            let n = j.kind.num_contacts();
            for k in 0..n {
                slots.push(Slot::Joint { joint: index, k });
                laws.extend(contact_law);
                contact_names.push(if n == 1 {
                    j.name.clone()
                } else {
                    format!("{}.corner{}", j.name, k + 1)
                });
            }
            joints.push(j);
        }
        let forces = self
            .forces
            .iter()
            .enumerate()
            .map(|(i, f)| force(f, i, &mut bodies))
            .collect::<Result<Vec<_>, _>>()?;
        // A clearance joint's contacts are named after it, and so is an explicit contact: the
        // two would share the record's columns (`<name>.PN`, ...).
        if let Some(c) = self
            .contacts
            .iter()
            .find(|c| self.joints.iter().any(|j| j.name() == c.name && j.clearance_law().is_some()))
        {
            return Err(bad(
                format!("contacts.{}.name", c.name),
                &c.name,
                format!(
                    "is the name of the clearance joint `{}`, whose contacts are named after \
                     it; give the contact or the joint another name",
                    c.name
                ),
            ));
        }
        let jointed: Vec<(usize, usize)> = joints.iter().map(|j| (j.a, j.b)).collect();
        let rules = Rules::new(self, &mut bodies, jointed)?;
        let (pairs, detector) = match self.contact_set {
            ContactSet::Fixed => {
                let pairs = pairs(&rules, &bodies, &mut slots, &mut laws, &mut contact_names)?;
                (pairs, None)
            }
            ContactSet::Detected => (Vec::new(), Some(Detector::new(rules, &bodies)?)),
        };
        // Every contact has a name of its own: the names of the explicit contacts, the
        // automatic ones (`<body>.<shape>-<body>.<shape>`) and the clearance joints' differ by
        // construction once the check above holds; this keeps it so.
        let mut seen = std::collections::HashSet::new();
        if let Some(name) = contact_names.iter().find(|n| !seen.insert(n.as_str())) {
            return Err(bad(
                format!("contacts.{name}.name"),
                name,
                "names two contacts, which would share the record's columns".to_owned(),
            ));
        }
        let mut coordinate_names = Vec::new();
        let mut velocity_names = Vec::new();
        let mut q0 = Vec::new();
        let mut u0 = Vec::new();
        for &i in &dynamic {
            let (b, s) = (&bodies[i], &self.bodies[i]);
            for (q, u) in [("x", "vx"), ("y", "vy"), ("theta", "omega")] {
                coordinate_names.push(format!("{}.{q}", b.name));
                velocity_names.push(format!("{}.{u}", b.name));
            }
            q0.extend(b.pose0);
            u0.extend([s.velocity[0], s.velocity[1], s.omega]);
        }
        let constant_mass = dynamic
            .iter()
            .all(|&i| matches!(bodies[i].kind, Kind::Dynamic { com, .. } if com == [0.0; 2]));
        let whole = extent(&bodies, |_| true, t0);
        let moves = |b: &Body| !matches!(b.kind, Kind::Fixed(_));
        let size = if bodies.iter().any(moves) { extent(&bodies, moves, t0).1 } else { whole.1 };
        let mut mb = Multibody {
            spec: original.clone(),
            bodies,
            joints,
            rows,
            forces,
            gravity: self.gravity,
            slots,
            pairs,
            detector,
            laws,
            contact_names,
            coordinate_names,
            velocity_names,
            q0,
            u0,
            t0,
            dynamic,
            constant_mass,
            extent: whole,
            size,
        };
        mb.q0 = assemble(&mb)?;
        Ok(mb)
    }
}

/// The centre and 0.6 times the diagonal of the box around the origins and finite shapes at
/// the start time t₀ of the bodies that `counts`. Over every body it is the scene's extent, within which a
/// half-plane is drawn; over the bodies that move it is the mechanism's size, in its own length
/// unit, so that what is relative to it (the tolerances, the guards of a run) is the same in
/// any unit and whatever the length of the fixed geometry drawn around it. A box of no size
/// (every origin and shape at one point) gives 1.
fn extent(bodies: &[Body], counts: impl Fn(&Body) -> bool, t0: f64) -> ([f64; 2], f64) {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let mut grow = |p: [f64; 2], q: [f64; 2]| {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(q[k]);
        }
    };
    let frame = |body: &Body| match body.kind {
        Kind::Dynamic { .. } => super::body::Frame::at(body.pose0, [0.0; 2], 0.0, None),
        _ => body.frame(&[], t0),
    };
    for body in bodies.iter().filter(|b| (b.name != GROUND || !b.shapes.is_empty()) && counts(b)) {
        let frame = frame(body);
        grow(frame.p, frame.p);
        for shape in &body.shapes {
            let b = shape.aabb(&frame.pose());
            if b.is_finite() {
                grow(b.min, b.max);
            }
        }
    }
    if !lo[0].is_finite() {
        return ([0.0; 2], 1.0);
    }
    let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let size = 0.6 * (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    (centre, if size > 0.0 { size } else { 1.0 })
}
