//! Planar contact pairs: a point or a circle against a line, two circles, a rectangle's corner
//! against a guide line.
//!
//! Every moving quantity carries its value, its gradient with respect to the `F` coordinates
//! it depends on, and its partial time derivative: a [`ScalarMotion`] (an angle θ), a
//! [`PointMotion`] (a point p(q, t) with ∂p/∂q, a 2×F matrix, and ∂p/∂t), a [`PoseMotion`]
//! (a body frame: origin and angle) and a [`LineMotion`] (a surface line: origin, tangent angle
//! and the side on which the gap is open). The pair functions return a [`ContactGeometry`]:
//! g_N, g_T, w_N = (∂g_N/∂q)ᵀ, w_T = (∂g_T/∂q)ᵀ, ŵ_N = ∂g_N/∂t and ŵ_T = ∂g_T/∂t.
//!
//! The coordinates may be the generalised coordinates q themselves, or the pose (x, y, θ) of
//! one body (`F = 3`, see [`PoseMotion::body`]): [`ContactGeometry::chain`] then composes the
//! result with the Jacobian of the pose with respect to q.
//!
//! # Point against a line
//! A line through o(q, t) with unit tangent t = (cos θ, sin θ) and unit normal n pointing to the
//! open side, n = s (−sin θ, cos θ) with s = +1 for [`Side::Left`] and s = −1 for
//! [`Side::Right`]. For a point p(q, t) and d = p − o:
//!
//! ```text
//! g_N = nᵀ d                 w_N = (∂p/∂q − ∂o/∂q)ᵀ n − s (tᵀ d) ∇θ
//! g_T = tᵀ d                 w_T = (∂p/∂q − ∂o/∂q)ᵀ t + s (nᵀ d) ∇θ
//! ŵ_N = nᵀ (ṗ − ȯ) − s (tᵀ d) θ̇          ŵ_T = tᵀ (ṗ − ȯ) + s (nᵀ d) θ̇
//! ```
//!
//! where ṗ, ȯ, θ̇ are partial time derivatives. Then γ_T = w_Tᵀ u + ŵ_T is the tangential
//! velocity of the point relative to the material point of the line's body that it passes.
//!
//! # Circle against a line
//! A circle of radius r, centre c and body angle φ: g_N = nᵀ(c − o) − r and
//! g_T = tᵀ(c − o) + s r (φ − θ). The term s r (φ − θ) makes γ_T the sliding velocity of the
//! circle's material contact point (rolling without slip has γ_T = 0).
//!
//! # Circle against a circle
//! Circles a and b with centres c_a, c_b, radii r_a, r_b, body angles φ_a, φ_b; d = c_a − c_b,
//! L = |d|, n = d / L (from b to a), t = (n_y, −n_x), α = atan2(d_y, d_x):
//!
//! ```text
//! g_N = L − r_a − r_b        g_T = −(r_a + r_b) α + r_a φ_a + r_b φ_b
//! ```
//!
//! so that γ_T = w_Tᵀ u + ŵ_T is the sliding velocity of a on b when the contact is closed
//! (L = r_a + r_b). g_T jumps by 2π (r_a + r_b) where d crosses the negative x-axis.
//!
//! # References
//! * Glocker, Ch. (2001). *Set-Valued Force Laws: Dynamics of Non-Smooth Systems*. Springer.
//! * Pfeiffer, F., & Glocker, Ch. (1996). *Multibody Dynamics with Unilateral Contacts*. Wiley.
//! * Flores, P. (2010). *Application of the non-smooth dynamics approach to model and analyze
//!   contact-impact events in rigid multibody systems using the linear complementarity problem
//!   formulation*. Universidade do Minho.

use nalgebra::{Isometry2, Point2, SMatrix, SVector, Vector2, Vector3};
use serde::{Deserialize, Serialize};

use crate::{ContactPoint, KinematicsError};

/// The left perpendicular (−v_y, v_x): the derivative of R(θ) v with respect to θ.
fn perp(v: &Vector2<f64>) -> Vector2<f64> {
    Vector2::new(-v.y, v.x)
}

/// A scalar a(q, t) (an angle θ or φ) with its gradient ∇a = (∂a/∂q)ᵀ and ∂a/∂t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScalarMotion<const F: usize> {
    /// The value a(q, t).
    pub value: f64,
    /// The gradient (∂a/∂q)ᵀ.
    pub gradient: SVector<f64, F>,
    /// The partial time derivative ∂a/∂t.
    pub time_derivative: f64,
}

impl<const F: usize> ScalarMotion<F> {
    /// A value that depends neither on q nor on t.
    pub fn constant(value: f64) -> Self {
        Self { value, gradient: SVector::zeros(), time_derivative: 0.0 }
    }

    /// The coordinate q_j itself: value `value`, gradient the unit vector e_j.
    ///
    /// # Errors
    /// [`KinematicsError::IndexOutOfRange`] when `j >= F`.
    pub fn coordinate(j: usize, value: f64) -> Result<Self, KinematicsError> {
        if j >= F {
            return Err(KinematicsError::IndexOutOfRange { what: "coordinate", index: j, len: F });
        }
        let mut gradient = SVector::zeros();
        gradient[j] = 1.0;
        Ok(Self { value, gradient, time_derivative: 0.0 })
    }

    /// A value that depends only on time: a(t) with da/dt = `rate`.
    pub fn rheonomic(value: f64, rate: f64) -> Self {
        Self { value, gradient: SVector::zeros(), time_derivative: rate }
    }

    /// The total rate ȧ = ∇aᵀ u + ∂a/∂t.
    pub fn rate(&self, u: &SVector<f64, F>) -> f64 {
        self.gradient.dot(u) + self.time_derivative
    }
}

/// A point p(q, t) with its Jacobian ∂p/∂q (2×F) and its partial time derivative ∂p/∂t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointMotion<const F: usize> {
    /// The position p(q, t) (m).
    pub position: Point2<f64>,
    /// The Jacobian ∂p/∂q (2×F).
    pub jacobian: SMatrix<f64, 2, F>,
    /// The partial time derivative ∂p/∂t (m/s).
    pub time_derivative: Vector2<f64>,
}

impl<const F: usize> PointMotion<F> {
    /// A point fixed in space.
    pub fn fixed(position: Point2<f64>) -> Self {
        Self { position, jacobian: SMatrix::zeros(), time_derivative: Vector2::zeros() }
    }

    /// A point moving with time only, at `velocity`.
    pub fn rheonomic(position: Point2<f64>, velocity: Vector2<f64>) -> Self {
        Self { position, jacobian: SMatrix::zeros(), time_derivative: velocity }
    }

    /// The velocity ṗ = (∂p/∂q) u + ∂p/∂t.
    pub fn velocity(&self, u: &SVector<f64, F>) -> Vector2<f64> {
        self.jacobian * u + self.time_derivative
    }
}

/// The frame of a rigid body: origin o(q, t) and angle θ(q, t), each with its derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PoseMotion<const F: usize> {
    /// The origin of the body frame.
    pub origin: PointMotion<F>,
    /// The angle θ of the body frame (rad), counter-clockwise from the x-axis.
    pub angle: ScalarMotion<F>,
}

impl PoseMotion<3> {
    /// The pose (x, y, θ) of a body taken as the coordinates themselves (`F = 3`, Jacobian the
    /// identity): contact rows are then the derivatives with respect to the body's pose, to be
    /// composed with ∂(x, y, θ)/∂q by [`ContactGeometry::chain`].
    pub fn body(x: f64, y: f64, theta: f64) -> Self {
        let jacobian = SMatrix::<f64, 2, 3>::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
        Self {
            origin: PointMotion {
                position: Point2::new(x, y),
                jacobian,
                time_derivative: Vector2::zeros(),
            },
            angle: ScalarMotion {
                value: theta,
                gradient: Vector3::new(0.0, 0.0, 1.0),
                time_derivative: 0.0,
            },
        }
    }
}

impl<const F: usize> PoseMotion<F> {
    /// A body frame fixed in space at (x, y) with angle θ.
    pub fn fixed(x: f64, y: f64, theta: f64) -> Self {
        Self { origin: PointMotion::fixed(Point2::new(x, y)), angle: ScalarMotion::constant(theta) }
    }

    /// A pose (x, y, θ) given with its Jacobian ∂(x, y, θ)/∂q (3×F) and its partial time
    /// derivative.
    pub fn from_parts(
        pose: Vector3<f64>,
        jacobian: SMatrix<f64, 3, F>,
        time_derivative: Vector3<f64>,
    ) -> Self {
        Self {
            origin: PointMotion {
                position: Point2::new(pose.x, pose.y),
                jacobian: jacobian.fixed_rows::<2>(0).into_owned(),
                time_derivative: Vector2::new(time_derivative.x, time_derivative.y),
            },
            angle: ScalarMotion {
                value: pose.z,
                gradient: jacobian.row(2).transpose(),
                time_derivative: time_derivative.z,
            },
        }
    }

    /// The pose as an isometry (rotation by θ, then translation by the origin).
    pub fn isometry(&self) -> Isometry2<f64> {
        Isometry2::new(self.origin.position.coords, self.angle.value)
    }

    /// The material point at `local` (body-frame coordinates, m): p = o + R(θ) local, with
    /// ∂p/∂q = ∂o/∂q + R'(θ) local ∇θᵀ and ∂p/∂t = ∂o/∂t + R'(θ) local ∂θ/∂t.
    pub fn point(&self, local: &Point2<f64>) -> PointMotion<F> {
        let r = self.isometry().rotation * local.coords;
        let dr = perp(&r);
        PointMotion {
            position: self.origin.position + r,
            jacobian: self.origin.jacobian + dr * self.angle.gradient.transpose(),
            time_derivative: self.origin.time_derivative + dr * self.angle.time_derivative,
        }
    }

    /// A line fixed to the body, through `local_origin` with tangent angle `local_angle`
    /// (both in the body frame) and the gap open on `side`.
    pub fn line(&self, local_origin: &Point2<f64>, local_angle: f64, side: Side) -> LineMotion<F> {
        LineMotion {
            origin: self.point(local_origin),
            angle: ScalarMotion { value: self.angle.value + local_angle, ..self.angle },
            side,
        }
    }

    /// A circle fixed to the body, centred at `local_center` (body frame), with the body's angle.
    pub fn circle(&self, local_center: &Point2<f64>, radius: f64) -> Circle<F> {
        Circle { center: self.point(local_center), angle: self.angle, radius }
    }
}

/// On which side of its tangent t a line's gap is open, i.e. where its normal n points.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Side {
    /// n = (−t_y, t_x): the open side is on the left when walking along t (s = +1).
    Left,
    /// n = (t_y, −t_x): the open side is on the right when walking along t (s = −1).
    Right,
}

impl Side {
    /// The sign s: +1 for [`Side::Left`], −1 for [`Side::Right`].
    pub fn sign(self) -> f64 {
        match self {
            Self::Left => 1.0,
            Self::Right => -1.0,
        }
    }
}

/// A straight surface line (floor, guide surface, cam face, pole), possibly moving with q
/// and t: origin o, tangent angle θ (t = (cos θ, sin θ)) and the side where the gap is open.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineMotion<const F: usize> {
    /// A point o of the line.
    pub origin: PointMotion<F>,
    /// The angle θ of the tangent t (rad), counter-clockwise from the x-axis.
    pub angle: ScalarMotion<F>,
    /// The side of t on which the normal n points and the gap g_N is positive.
    pub side: Side,
}

impl<const F: usize> LineMotion<F> {
    /// A line fixed in space through `origin` with tangent angle θ.
    pub fn fixed(origin: Point2<f64>, angle: f64, side: Side) -> Self {
        Self { origin: PointMotion::fixed(origin), angle: ScalarMotion::constant(angle), side }
    }

    /// A line moving with time only: its origin moves at `velocity` and its tangent turns at
    /// `angular_velocity` (rad/s).
    pub fn rheonomic(
        origin: Point2<f64>,
        velocity: Vector2<f64>,
        angle: f64,
        angular_velocity: f64,
        side: Side,
    ) -> Self {
        Self {
            origin: PointMotion::rheonomic(origin, velocity),
            angle: ScalarMotion::rheonomic(angle, angular_velocity),
            side,
        }
    }

    /// The unit tangent t = (cos θ, sin θ).
    pub fn tangent(&self) -> Vector2<f64> {
        Vector2::new(self.angle.value.cos(), self.angle.value.sin())
    }

    /// The unit normal n, pointing to the open side.
    pub fn normal(&self) -> Vector2<f64> {
        perp(&self.tangent()) * self.side.sign()
    }
}

/// A circle of radius r whose centre and body angle φ move with q and t.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Circle<const F: usize> {
    /// The centre c.
    pub center: PointMotion<F>,
    /// The angle φ of the body carrying the circle; it enters g_T through rolling.
    pub angle: ScalarMotion<F>,
    /// The radius r (m, `>= 0`).
    pub radius: f64,
}

impl<const F: usize> Circle<F> {
    /// A circle centred at `center` that does not turn (its angle φ is constant), e.g. a ball
    /// whose rotation is not modelled.
    pub fn non_rotating(center: PointMotion<F>, radius: f64) -> Self {
        Self { center, angle: ScalarMotion::constant(0.0), radius }
    }

    fn checked_radius(&self) -> Result<f64, KinematicsError> {
        if self.radius >= 0.0 && self.radius.is_finite() {
            Ok(self.radius)
        } else {
            Err(KinematicsError::InvalidGeometry { what: "circle radius", value: self.radius })
        }
    }
}

/// The kinematics of one contact with respect to `F` coordinates: g_N, g_T, w_N, w_T, ŵ_N, ŵ_T.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactGeometry<const F: usize> {
    /// Normal gap g_N (m), positive when open.
    pub g_n: f64,
    /// Tangential position g_T (m).
    pub g_t: f64,
    /// Force direction w_N = (∂g_N/∂q)ᵀ.
    pub w_n: SVector<f64, F>,
    /// Force direction w_T = (∂g_T/∂q)ᵀ.
    pub w_t: SVector<f64, F>,
    /// Rheonomic term ŵ_N = ∂g_N/∂t (m/s).
    pub w_n_hat: f64,
    /// Rheonomic term ŵ_T = ∂g_T/∂t (m/s).
    pub w_t_hat: f64,
}

impl<const F: usize> ContactGeometry<F> {
    /// The scalars g_N, g_T, ŵ_N, ŵ_T as a [`ContactPoint`].
    pub fn contact_point(&self) -> ContactPoint {
        ContactPoint { g_n: self.g_n, g_t: self.g_t, w_n_hat: self.w_n_hat, w_t_hat: self.w_t_hat }
    }

    /// Copies w_N into `w_n` and w_T into `w_t` and returns the scalars, as
    /// [`ContactKinematics::contact`](crate::ContactKinematics::contact) does.
    ///
    /// # Errors
    /// [`KinematicsError::DimensionMismatch`] when a slice's length is not `F`.
    pub fn write(&self, w_n: &mut [f64], w_t: &mut [f64]) -> Result<ContactPoint, KinematicsError> {
        for (what, len) in [("w_n slice", w_n.len()), ("w_t slice", w_t.len())] {
            if len != F {
                return Err(KinematicsError::DimensionMismatch { what, expected: F, found: len });
            }
        }
        w_n.copy_from_slice(self.w_n.as_slice());
        w_t.copy_from_slice(self.w_t.as_slice());
        Ok(self.contact_point())
    }

    /// The normal relative velocity γ_N = w_Nᵀ u + ŵ_N.
    pub fn normal_velocity(&self, u: &SVector<f64, F>) -> f64 {
        self.w_n.dot(u) + self.w_n_hat
    }

    /// The tangential relative velocity γ_T = w_Tᵀ u + ŵ_T.
    pub fn tangential_velocity(&self, u: &SVector<f64, F>) -> f64 {
        self.w_t.dot(u) + self.w_t_hat
    }

    /// The same contact with respect to other coordinates q̃ (`G` of them), when the present
    /// coordinates p (e.g. a body pose) are p(q̃, t) with Jacobian ∂p/∂q̃ = `jacobian` (F×G) and
    /// partial time derivative ∂p/∂t = `time_derivative`: w̃ = (∂p/∂q̃)ᵀ w and
    /// ŵ̃ = ŵ + wᵀ ∂p/∂t.
    pub fn chain<const G: usize>(
        &self,
        jacobian: &SMatrix<f64, F, G>,
        time_derivative: &SVector<f64, F>,
    ) -> ContactGeometry<G> {
        ContactGeometry {
            g_n: self.g_n,
            g_t: self.g_t,
            w_n: chain_rule(&self.w_n, jacobian),
            w_t: chain_rule(&self.w_t, jacobian),
            w_n_hat: self.w_n_hat + self.w_n.dot(time_derivative),
            w_t_hat: self.w_t_hat + self.w_t.dot(time_derivative),
        }
    }

    fn checked(self) -> Result<Self, KinematicsError> {
        let scalars =
            [("g_N", self.g_n), ("g_T", self.g_t), ("ŵ_N", self.w_n_hat), ("ŵ_T", self.w_t_hat)];
        for (what, value) in scalars {
            if !value.is_finite() {
                return Err(KinematicsError::NonFinite { what, contact: None, sample: None });
            }
        }
        for (what, w) in [("w_N", &self.w_n), ("w_T", &self.w_t)] {
            if w.iter().any(|x| !x.is_finite()) {
                return Err(KinematicsError::NonFinite { what, contact: None, sample: None });
            }
        }
        Ok(self)
    }
}

/// The chain rule for a gradient row: with a(p) and p(q̃), ∇_q̃ a = (∂p/∂q̃)ᵀ ∇_p a.
pub fn chain_rule<const F: usize, const G: usize>(
    gradient: &SVector<f64, F>,
    jacobian: &SMatrix<f64, F, G>,
) -> SVector<f64, G> {
    jacobian.tr_mul(gradient)
}

/// A point p against a line: g_N = nᵀ(p − o), g_T = tᵀ(p − o) and their derivatives (see the
/// [module documentation](self)). The general building block of the other pairs.
///
/// # Errors
/// [`KinematicsError::NonFinite`] when an input is NaN or infinite.
pub fn point_line<const F: usize>(
    point: &PointMotion<F>,
    line: &LineMotion<F>,
) -> Result<ContactGeometry<F>, KinematicsError> {
    let s = line.side.sign();
    let (t, n) = (line.tangent(), line.normal());
    let d = point.position - line.origin.position;
    let (dn, dt) = (n.dot(&d), t.dot(&d));
    let jacobian = point.jacobian - line.origin.jacobian;
    let velocity = point.time_derivative - line.origin.time_derivative;
    ContactGeometry {
        g_n: dn,
        g_t: dt,
        w_n: jacobian.tr_mul(&n) - line.angle.gradient * (s * dt),
        w_t: jacobian.tr_mul(&t) + line.angle.gradient * (s * dn),
        w_n_hat: n.dot(&velocity) - s * dt * line.angle.time_derivative,
        w_t_hat: t.dot(&velocity) + s * dn * line.angle.time_derivative,
    }
    .checked()
}

/// A circle against a line: g_N = nᵀ(c − o) − r, g_T = tᵀ(c − o) + s r (φ − θ) (see the
/// [module documentation](self)).
///
/// # Errors
/// [`KinematicsError::InvalidGeometry`] for a negative or non-finite radius,
/// [`KinematicsError::NonFinite`] when an input is NaN or infinite.
pub fn circle_line<const F: usize>(
    circle: &Circle<F>,
    line: &LineMotion<F>,
) -> Result<ContactGeometry<F>, KinematicsError> {
    let r = circle.checked_radius()?;
    let mut geometry = point_line(&circle.center, line)?;
    let sr = line.side.sign() * r;
    geometry.g_n -= r;
    geometry.g_t += sr * (circle.angle.value - line.angle.value);
    geometry.w_t += (circle.angle.gradient - line.angle.gradient) * sr;
    geometry.w_t_hat += sr * (circle.angle.time_derivative - line.angle.time_derivative);
    geometry.checked()
}

/// Circle `a` against circle `b` (outside each other): g_N = |c_a − c_b| − r_a − r_b,
/// g_T = −(r_a + r_b) α + r_a φ_a + r_b φ_b (see the [module documentation](self)); the
/// normal n points from b to a.
///
/// # Errors
/// [`KinematicsError::InvalidGeometry`] for a negative radius or coincident centres,
/// [`KinematicsError::NonFinite`] when an input is NaN or infinite.
pub fn circle_circle<const F: usize>(
    a: &Circle<F>,
    b: &Circle<F>,
) -> Result<ContactGeometry<F>, KinematicsError> {
    let (ra, rb) = (a.checked_radius()?, b.checked_radius()?);
    let d = a.center.position - b.center.position;
    let length = d.norm();
    if !length.is_finite() {
        return Err(KinematicsError::NonFinite {
            what: "circle centre",
            contact: None,
            sample: None,
        });
    }
    if length <= 0.0 {
        return Err(KinematicsError::InvalidGeometry {
            what: "distance of circle centres",
            value: length,
        });
    }
    let n = d / length;
    let t = Vector2::new(n.y, -n.x);
    let alpha = d.y.atan2(d.x);
    let jacobian = a.center.jacobian - b.center.jacobian;
    let velocity = a.center.time_derivative - b.center.time_derivative;
    let k = (ra + rb) / length;
    ContactGeometry {
        g_n: length - ra - rb,
        g_t: -(ra + rb) * alpha + ra * a.angle.value + rb * b.angle.value,
        w_n: jacobian.tr_mul(&n),
        w_t: jacobian.tr_mul(&t) * k + a.angle.gradient * ra + b.angle.gradient * rb,
        w_n_hat: n.dot(&velocity),
        w_t_hat: k * t.dot(&velocity) + ra * a.angle.time_derivative + rb * b.angle.time_derivative,
    }
    .checked()
}

/// The corner `corner` (body-frame coordinates) of a rigid body with pose `body` against a
/// line: [`point_line`] of the body point p = o + R(θ) corner.
///
/// # Errors
/// [`KinematicsError::NonFinite`] when an input is NaN or infinite.
pub fn corner_line<const F: usize>(
    body: &PoseMotion<F>,
    corner: &Point2<f64>,
    line: &LineMotion<F>,
) -> Result<ContactGeometry<F>, KinematicsError> {
    point_line(&body.point(corner), line)
}

/// The corners of a `2a × 2b` rectangle centred on its body frame, in the report's order:
/// 1 (−a, +b), 2 (+a, +b), 3 (−a, −b), 4 (+a, −b).
///
/// # Errors
/// [`KinematicsError::InvalidGeometry`] when a half-size is negative or not finite.
pub fn rectangle_corners(a: f64, b: f64) -> Result<[Point2<f64>; 4], KinematicsError> {
    for (what, value) in [("rectangle half-width a", a), ("rectangle half-height b", b)] {
        if value < 0.0 || !value.is_finite() {
            return Err(KinematicsError::InvalidGeometry { what, value });
        }
    }
    Ok([Point2::new(-a, b), Point2::new(a, b), Point2::new(-a, -b), Point2::new(a, -b)])
}
