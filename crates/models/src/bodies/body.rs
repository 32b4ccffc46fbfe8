//! Built bodies: where each body is at (q, t), and how a point of it moves with q and t.

use moreau_kinematics::{ChainIndex, Placement, Pose, Shape};

use super::spec::{DrivenState, Motion};

/// What a built body is.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Kind {
    /// Coordinates q[dof..dof + 3] = (x, y, θ) of the origin; mass m, inertia I_O about the
    /// origin and centre of mass `com` in the body frame.
    Dynamic { dof: usize, mass: f64, inertia: f64, com: [f64; 2] },
    /// At its initial pose for ever: its frame there, computed once.
    Fixed(Frame),
    /// Moving as told.
    Driven(Motion),
}

/// A built body.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Body {
    pub name: String,
    pub kind: Kind,
    /// (x, y, θ) at t = 0 for dynamic and fixed bodies; p₀, θ₀ of a driven body's motion.
    pub pose0: [f64; 3],
    /// The shapes, in the body frame.
    pub shapes: Vec<Shape>,
    /// Per shape: the index of its runs of segments, for a long polyline or profile
    /// ([`ChainIndex::new`]), which makes its narrow phase visit only the runs near the other
    /// shape.
    pub chains: Vec<Option<ChainIndex>>,
    /// Collision group and mask bits.
    pub group: u32,
    pub mask: u32,
}

/// A body's frame at (q, t): its origin p, angle θ with cos and sin, the rheonomic velocity
/// (v, ω) of a driven body (zero for the others), and where its coordinates are in q.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Frame {
    pub p: [f64; 2],
    pub theta: f64,
    pub cos: f64,
    pub sin: f64,
    pub v: [f64; 2],
    pub omega: f64,
    pub dof: Option<usize>,
}

/// The vector turned by +90°: (−y, x).
#[inline]
pub(crate) fn perp(a: [f64; 2]) -> [f64; 2] {
    [-a[1], a[0]]
}

#[inline]
pub(crate) fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// The scalar cross product a × b = a_x b_y − a_y b_x.
#[inline]
pub(crate) fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

#[inline]
pub(crate) fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

#[inline]
pub(crate) fn add(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] + b[0], a[1] + b[1]]
}

#[inline]
pub(crate) fn scale(a: [f64; 2], s: f64) -> [f64; 2] {
    [a[0] * s, a[1] * s]
}

impl Frame {
    /// A frame without coordinates at a pose, moving with (v, ω).
    pub fn at(pose: [f64; 3], v: [f64; 2], omega: f64, dof: Option<usize>) -> Self {
        // Fixed bodies and grounds mostly sit at θ = 0, whose sine and cosine need no call.
        let (sin, cos) = if pose[2] == 0.0 { (0.0, 1.0) } else { pose[2].sin_cos() };
        Self { p: [pose[0], pose[1]], theta: pose[2], cos, sin, v, omega, dof }
    }

    /// The frame as the kinematics' pose.
    #[inline]
    pub fn pose(&self) -> Pose {
        Pose { x: self.p[0], y: self.p[1], theta: self.theta }
    }

    /// The frame as the kinematics' placement, with the frame's cos θ and sin θ.
    #[inline]
    pub fn placement(&self) -> Placement {
        Placement::with_rotation(&self.pose(), self.cos, self.sin)
    }

    /// R(θ) r: a body-frame vector in the world.
    #[inline]
    pub fn rotate(&self, r: [f64; 2]) -> [f64; 2] {
        [self.cos * r[0] - self.sin * r[1], self.sin * r[0] + self.cos * r[1]]
    }

    /// The world position p + R(θ) r of the body point r.
    #[inline]
    pub fn point(&self, r: [f64; 2]) -> [f64; 2] {
        add(self.p, self.rotate(r))
    }

    /// The rheonomic velocity v + ω (P − p)^⊥ of the body point now at world point P (zero
    /// for dynamic and fixed bodies).
    #[inline]
    pub fn velocity(&self, at: [f64; 2]) -> [f64; 2] {
        add(self.v, scale(perp(sub(at, self.p)), self.omega))
    }

    /// Adds `sign` · (∂(e · P)/∂q_body)ᵀ = sign · (e, (P − p) × e) to w for the body point now at
    /// world point P and a fixed world direction e; returns sign · e · (rheonomic velocity of P).
    #[inline]
    pub fn add_row(&self, w: &mut [f64], sign: f64, e: [f64; 2], at: [f64; 2]) -> f64 {
        if let Some(d) = self.dof {
            w[d] += sign * e[0];
            w[d + 1] += sign * e[1];
            w[d + 2] += sign * cross(sub(at, self.p), e);
        }
        sign * dot(e, self.velocity(at))
    }

    /// Adds `sign` to the θ entry of w and returns sign · ω (the rheonomic angular rate).
    #[inline]
    pub fn add_angle(&self, w: &mut [f64], sign: f64) -> f64 {
        if let Some(d) = self.dof {
            w[d + 2] += sign;
        }
        sign * self.omega
    }
}

impl Motion {
    /// The pose and its rates at time t for the reference pose p₀, θ₀.
    pub fn state(&self, pose0: [f64; 3], t: f64) -> DrivenState {
        match self {
            Motion::Rotate { pivot, omega, phase } => {
                let phi = omega * t + phase;
                let (s, c) = phi.sin_cos();
                let r = sub([pose0[0], pose0[1]], *pivot);
                let rr = [c * r[0] - s * r[1], s * r[0] + c * r[1]];
                let p = add(*pivot, rr);
                DrivenState {
                    pose: [p[0], p[1], pose0[2] + phi],
                    velocity: scale(perp(rr), *omega),
                    omega: *omega,
                }
            }
            Motion::Oscillate { amplitude, omega, phase } => {
                let (sx, cx) = (omega * t + phase[0]).sin_cos();
                let (sy, cy) = (omega * t + phase[1]).sin_cos();
                DrivenState {
                    pose: [pose0[0] + amplitude[0] * sx, pose0[1] + amplitude[1] * sy, pose0[2]],
                    velocity: [amplitude[0] * omega * cx, amplitude[1] * omega * cy],
                    omega: 0.0,
                }
            }
            Motion::Linear { velocity, omega } => DrivenState {
                pose: [
                    pose0[0] + velocity[0] * t,
                    pose0[1] + velocity[1] * t,
                    pose0[2] + omega * t,
                ],
                velocity: *velocity,
                omega: *omega,
            },
            Motion::Custom(f) => (f.0)(t),
        }
    }
}

impl Kind {
    /// A fixed body at `pose`.
    pub fn fixed(pose: [f64; 3]) -> Self {
        Kind::Fixed(Frame::at(pose, [0.0; 2], 0.0, None))
    }
}

impl Body {
    /// The index of the runs of segments of shape `k`, for a long polyline or profile. The
    /// shape, which the narrow phase reads next, says whether there is one to read: a pair of
    /// disks does not touch the bodies' lists of indexes.
    #[inline]
    pub fn chain(&self, k: usize) -> Option<&ChainIndex> {
        match self.shapes[k] {
            Shape::Polyline { .. } | Shape::Profile { .. } => self.chains[k].as_ref(),
            _ => None,
        }
    }

    /// The body's frame at (q, t).
    #[inline]
    pub fn frame(&self, q: &[f64], t: f64) -> Frame {
        match &self.kind {
            Kind::Dynamic { dof, .. } => {
                Frame::at([q[*dof], q[dof + 1], q[dof + 2]], [0.0; 2], 0.0, Some(*dof))
            }
            Kind::Fixed(frame) => *frame,
            Kind::Driven(motion) => {
                let s = motion.state(self.pose0, t);
                Frame::at(s.pose, s.velocity, s.omega, None)
            }
        }
    }

    /// The full velocity of the body point now at world point P: the rheonomic part for a
    /// driven body, the one given by u for a dynamic one.
    #[inline]
    pub fn point_velocity(&self, frame: &Frame, u: &[f64], at: [f64; 2]) -> [f64; 2] {
        match self.kind {
            Kind::Dynamic { dof, .. } => {
                add([u[dof], u[dof + 1]], scale(perp(sub(at, frame.p)), u[dof + 2]))
            }
            _ => frame.velocity(at),
        }
    }

    /// The full angular velocity.
    #[inline]
    pub fn angular_velocity(&self, frame: &Frame, u: &[f64]) -> f64 {
        match self.kind {
            Kind::Dynamic { dof, .. } => u[dof + 2],
            _ => frame.omega,
        }
    }

    /// Whether the body has coordinates.
    pub fn is_dynamic(&self) -> bool {
        matches!(self.kind, Kind::Dynamic { .. })
    }
}
