//! Force elements: gravity, springs and dampers, applied loads; the smooth forces h(q, u, t)
//! and the potential energy V(q) of the conservative ones.

use super::body::{Body, Frame, Kind, cross, dot, scale, sub};
use super::multibody::Multibody;
use super::spec::TimeFunction;

/// A built force element (bodies by index).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Force {
    Spring { a: usize, ra: [f64; 2], b: usize, rb: [f64; 2], k: f64, rest: f64, c: f64 },
    Torsion { a: usize, b: usize, k: f64, rest: f64, c: f64 },
    Point { body: usize, r: [f64; 2], fx: TimeFunction, fy: TimeFunction },
    Torque { body: usize, torque: TimeFunction },
}

/// Adds the generalised force of a world force `force` at world point `at` of a body.
#[inline]
fn apply(h: &mut [f64], frame: &Frame, force: [f64; 2], at: [f64; 2]) {
    if let Some(d) = frame.dof {
        h[d] += force[0];
        h[d + 1] += force[1];
        h[d + 2] += cross(sub(at, frame.p), force);
    }
}

#[inline]
fn apply_torque(h: &mut [f64], frame: &Frame, torque: f64) {
    if let Some(d) = frame.dof {
        h[d + 2] += torque;
    }
}

/// The inertial and gravity part of h for one dynamic body: with s = R(θ) c the centre of
/// mass' offset from the origin, m g + m ω² s on (x, y) (the centrifugal term of an origin
/// that is not the centre of mass) and s × m g on θ.
#[inline]
pub(crate) fn body_forces(body: &Body, frame: &Frame, u: &[f64], gravity: [f64; 2]) -> [f64; 3] {
    match body.kind {
        Kind::Dynamic { dof, mass, com, .. } => {
            let s = frame.rotate(com);
            let omega = u[dof + 2];
            let weight = scale(gravity, mass);
            [
                weight[0] + mass * omega * omega * s[0],
                weight[1] + mass * omega * omega * s[1],
                cross(s, weight),
            ]
        }
        _ => [0.0; 3],
    }
}

/// The mass matrix block of a dynamic body, column-major 3 × 3:
/// [[m, 0, −m s_y], [0, m, m s_x], [−m s_y, m s_x, I_O]] with s = R(θ) c.
pub(crate) fn mass_block(mass: f64, inertia: f64, com: [f64; 2], frame: &Frame) -> [f64; 9] {
    let s = frame.rotate(com);
    let (a, b) = (-mass * s[1], mass * s[0]);
    [mass, 0.0, a, 0.0, mass, b, a, b, inertia]
}

/// The gravity potential −m g · (p + s) of a dynamic body.
pub(crate) fn gravity_potential(body: &Body, frame: &Frame, gravity: [f64; 2]) -> f64 {
    match body.kind {
        Kind::Dynamic { mass, com, .. } => {
            let c = frame.point(com);
            -mass * dot(gravity, c)
        }
        _ => 0.0,
    }
}

impl Force {
    /// Whether the element damps: a spring or torsion spring with a damping coefficient c ≠ 0.
    pub fn damps(&self) -> bool {
        matches!(self, Force::Spring { c, .. } | Force::Torsion { c, .. } if *c != 0.0)
    }

    /// Adds the element's generalised force to h at (q, u, t), or with `DAMPERS_ONLY` its
    /// damping force alone (c times the rate of its length or angle: its part of h_D);
    /// `frame(i)` gives body i's frame.
    #[inline]
    pub fn add_to<const DAMPERS_ONLY: bool>(
        &self,
        bodies: &[Body],
        frame: impl Fn(usize) -> Frame,
        u: &[f64],
        t: f64,
        h: &mut [f64],
    ) {
        let stiff = |k: f64, stretch: f64| if DAMPERS_ONLY { 0.0 } else { k * stretch };
        match self {
            Force::Spring { a, ra, b, rb, k, rest, c } => {
                let (fa, fb) = (frame(*a), frame(*b));
                let (pa, pb) = (fa.point(*ra), fb.point(*rb));
                let d = sub(pb, pa);
                let length = d[0].hypot(d[1]);
                // Coincident anchors give no direction, and then no force.
                if length == 0.0 {
                    return;
                }
                let e = scale(d, 1.0 / length);
                let rate = dot(
                    e,
                    sub(
                        bodies[*b].point_velocity(&fb, u, pb),
                        bodies[*a].point_velocity(&fa, u, pa),
                    ),
                );
                let tension = stiff(*k, length - rest) + c * rate;
                apply(h, &fa, scale(e, tension), pa);
                apply(h, &fb, scale(e, -tension), pb);
            }
            Force::Torsion { a, b, k, rest, c } => {
                let (fa, fb) = (frame(*a), frame(*b));
                let rate =
                    bodies[*b].angular_velocity(&fb, u) - bodies[*a].angular_velocity(&fa, u);
                let torque = stiff(*k, fb.theta - fa.theta - rest) + c * rate;
                apply_torque(h, &fa, torque);
                apply_torque(h, &fb, -torque);
            }
            Force::Point { .. } | Force::Torque { .. } if DAMPERS_ONLY => {}
            Force::Point { body, r, fx, fy } => {
                let f = frame(*body);
                apply(h, &f, [fx.at(t), fy.at(t)], f.point(*r));
            }
            Force::Torque { body, torque } => apply_torque(h, &frame(*body), torque.at(t)),
        }
    }

    /// The element's potential energy (J): ½ k (ℓ − ℓ₀)² or ½ k Δθ² for springs, 0 for loads.
    pub fn potential(&self, frame: impl Fn(usize) -> Frame) -> f64 {
        match self {
            Force::Spring { a, ra, b, rb, k, rest, .. } => {
                let d = sub(frame(*b).point(*rb), frame(*a).point(*ra));
                let stretch = d[0].hypot(d[1]) - rest;
                0.5 * k * stretch * stretch
            }
            Force::Torsion { a, b, k, rest, .. } => {
                let delta = frame(*b).theta - frame(*a).theta - rest;
                0.5 * k * delta * delta
            }
            Force::Point { .. } | Force::Torque { .. } => 0.0,
        }
    }
}

/// `Mechanism::damping_forces` of a declared mechanism: the dampers' part of h at (q, u, t)
/// into `h_d`, and whether it has dampers. Each force's bodies' frames are computed anew, as
/// for the potential energy: only the record's energy balance reads this, once per step.
#[inline(never)]
pub(crate) fn damping_forces(
    mb: &Multibody,
    q: &[f64],
    u: &[f64],
    t: f64,
    h_d: &mut [f64],
) -> bool {
    let mut damped = false;
    for force in mb.forces.iter().filter(|f| f.damps()) {
        force.add_to::<true>(&mb.bodies, |b| mb.bodies[b].frame(q, t), u, t, h_d);
        damped = true;
    }
    damped
}
