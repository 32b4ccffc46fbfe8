//! Planar contact kinematics for Moreau's time-stepping.
//!
//! # What this crate is for
//! The kinematic side of a contact in a planar rigid multibody system with `f` generalised
//! coordinates q and velocities u: the normal gap g_N(q, t), the tangential position
//! g_T(q, t), the force directions w_N = (∂g_N/∂q)ᵀ and w_T = (∂g_T/∂q)ᵀ, and the rheonomic
//! terms ŵ_N = ∂g_N/∂t and ŵ_T = ∂g_T/∂t, from which the relative velocities are
//! γ_N = w_Nᵀ u + ŵ_N and γ_T = w_Tᵀ u + ŵ_T. It provides
//! * the [`ContactKinematics`] trait that the time-stepper calls and the models implement;
//! * planar contact pairs in [`planar`]: a point or a circle against a line (floor, guide
//!   surface, cam face, pole, possibly moving with t), two circles, a rectangle's corner
//!   against a guide line, each returning a [`ContactGeometry`] with the Jacobian rows, and the
//!   chain rule from body pose coordinates to q ([`ContactGeometry::chain`]);
//! * a finite-difference checker ([`check_jacobians`], [`assert_consistent`]) that verifies
//!   w_N, w_T, ŵ_N, ŵ_T against the gaps, with seeded sample states ([`sample_states`]);
//! * for mechanisms declared by bodies and shapes, the geometry of [`shapes`]: disks, convex
//!   polygons, capsules, half-planes, polylines and sampled profiles ([`Shape`]) placed by a
//!   body [`Pose`], their contact points with normals, gaps and persistent feature ids
//!   ([`collide`], [`ManifoldPoint`], [`max_points`]; [`collide_placed`] from a [`Placement`]
//!   whose sine and cosine are computed once per body, [`collide_indexed`] with a long chain's
//!   [`ChainIndex`]), and a broad phase ([`BroadPhase`]) over
//!   their bounding boxes ([`Aabb`]); each point's gap changes at the rate of the normal
//!   relative velocity of its two material points, from which w_N follows.
//!
//! # What it is not for
//! It does not integrate motion or evaluate contact laws: the set-valued laws (Upr, Sgn,
//! Newton's impact law) are in `moreau-setvalued`, the time-stepping in `moreau-stepper`.
//! Its contact detection is for the planar mechanisms and granular assemblies of the method,
//! not a general physics engine: no continuous collision detection, no shapes beyond the six,
//! no pairs of two unbounded or non-convex surfaces.
//!
//! # Notation
//! | symbol | identifier | meaning |
//! |---|---|---|
//! | q, u, t | `q`, `u`, `t` | generalised coordinates, velocities, time |
//! | f | [`ContactKinematics::num_coordinates`] | number of coordinates |
//! | g_N | [`ContactPoint::g_n`] | normal gap (> 0 open) |
//! | g_T | [`ContactPoint::g_t`] | tangential position of the contact point |
//! | w_N, w_T | `w_n`, `w_t` | force directions (∂g/∂q)ᵀ |
//! | ŵ_N, ŵ_T | [`ContactPoint::w_n_hat`], [`ContactPoint::w_t_hat`] | rheonomic terms ∂g/∂t |
//! | γ_N, γ_T | [`relative_velocity`] | relative velocities wᵀu + ŵ |
//! | p, ∂p/∂q, ∂p/∂t | [`PointMotion`] | a point with its Jacobian and time derivative |
//! | (x, y, θ) | [`PoseMotion`] | a body frame |
//! | (x, y, θ) of a body | [`Pose`] | where a shape's body frame is |
//! | n, p_A, p_B, g_N of a shape pair | [`ManifoldPoint`] | normal from A to B, surface points, gap |
//! | n, t, s | [`LineMotion::normal`], [`LineMotion::tangent`], [`Side::sign`] | a surface line's normal, tangent, open side |
//!
//! # Example
//! A ball of radius R with q = (y) above the floor, built from [`circle_line`] and checked
//! against finite differences.
//! ```
//! use moreau_kinematics::{ContactKinematics, ContactPoint, KinematicsError};
//! use moreau_kinematics::{Circle, LineMotion, PointMotion, Side, circle_line};
//! use moreau_kinematics::{assert_consistent, relative_velocity, sample_states, SampleOptions};
//! use moreau_kinematics::nalgebra::{Matrix2x1, Point2, Vector2};
//!
//! struct Ball { radius: f64 }
//!
//! impl Ball {
//!     fn geometry(&self, q: &[f64]) -> Result<moreau_kinematics::ContactGeometry<1>, KinematicsError> {
//!         // The centre (0, y) moves with q = (y): ∂c/∂q = (0, 1)ᵀ.
//!         let center = PointMotion {
//!             position: Point2::new(0.0, q[0]),
//!             jacobian: Matrix2x1::new(0.0, 1.0),
//!             time_derivative: Vector2::zeros(),
//!         };
//!         let floor = LineMotion::fixed(Point2::origin(), 0.0, Side::Left);
//!         circle_line(&Circle::non_rotating(center, self.radius), &floor)
//!     }
//! }
//!
//! impl ContactKinematics for Ball {
//!     fn num_coordinates(&self) -> usize { 1 }
//!     fn num_contacts(&self) -> usize { 1 }
//!     fn normal_gap(&self, _i: usize, q: &[f64], _t: f64) -> f64 { q[0] - self.radius }
//!     fn contact(&self, _i: usize, q: &[f64], _t: f64, w_n: &mut [f64], w_t: &mut [f64]) -> ContactPoint {
//!         // The model keeps its inputs finite, so the geometry cannot fail here.
//!         let geometry = self.geometry(q).expect("finite ball state");
//!         w_n[0] = geometry.w_n[0];
//!         w_t[0] = geometry.w_t[0];
//!         geometry.contact_point()
//!     }
//! }
//!
//! # fn main() -> Result<(), KinematicsError> {
//! let ball = Ball { radius: 0.1 };
//! let geometry = ball.geometry(&[1.0])?;
//! assert!((geometry.g_n - 0.9).abs() < 1e-15 && geometry.w_n[0] == 1.0);
//! let samples = sample_states(&[1.0], 0.0, SampleOptions::default())?;
//! let report = assert_consistent(&ball, &samples, 1e-6)?;
//! assert!(report.worst().unwrap().scaled < 1e-9);
//! // γ_N = w_Nᵀ u + ŵ_N for a ball falling at 2 m/s.
//! assert_eq!(relative_velocity(&[1.0], 0.0, &[-2.0])?, -2.0);
//! # Ok(())
//! # }
//! ```
//!
//! A box resting on a floor, detected as two corner contacts:
//! ```
//! use moreau_kinematics::{collide, KinematicsError, Pose, Shape};
//!
//! # fn main() -> Result<(), KinematicsError> {
//! let floor = Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, 1.0] };
//! let corners = vec![[-0.2, -0.1], [0.2, -0.1], [0.2, 0.1], [-0.2, 0.1]];
//! let block = Shape::Polygon { vertices: corners };
//! block.validate()?;
//! let mut points = Vec::new();
//! // The block's centre 0.101 m above the floor: its two lower corners are 1 mm above it.
//! collide(&block, &Pose::new(0.0, 0.101, 0.0), &floor, &Pose::default(), 0.01, &mut points)?;
//! assert_eq!(points.len(), 2);
//! assert!(points.iter().all(|p| (p.gap - 0.001).abs() < 1e-12 && p.normal == [0.0, -1.0]));
//! # Ok(())
//! # }
//! ```
//!
//! # References
//! * Ericson, C. (2005). *Real-Time Collision Detection*. Morgan Kaufmann.
//! * Glocker, Ch. (2001). *Set-Valued Force Laws: Dynamics of Non-Smooth Systems*. Springer.
//! * Pfeiffer, F., & Glocker, Ch. (1996). *Multibody Dynamics with Unilateral Contacts*. Wiley.
//! * Flores, P. (2010). *Application of the non-smooth dynamics approach to model and analyze
//!   contact-impact events in rigid multibody systems using the linear complementarity problem
//!   formulation*. Universidade do Minho.
#![deny(missing_docs)]

mod check;
mod error;
pub mod planar;
mod sample;
pub mod shapes;

/// The points, vectors and Jacobian matrices that [`planar`]'s pairs take and give
/// ([`PointMotion`], [`LineMotion`], [`ContactGeometry`]) are nalgebra's, re-exported here so
/// that a user of this crate needs no nalgebra dependency of a matching version.
pub use nalgebra;

pub use check::{Component, FdOptions, FdReport, Mismatch, assert_consistent, check_jacobians};
pub use error::KinematicsError;
pub use planar::{
    Circle, ContactGeometry, LineMotion, PointMotion, PoseMotion, ScalarMotion, Side, chain_rule,
    circle_circle, circle_line, corner_line, point_line, rectangle_corners,
};
pub use sample::{SampleOptions, SplitMix64, sample_states};
pub use shapes::{
    Aabb, BroadPhase, ChainIndex, ManifoldPoint, Placement, Pose, Shape, collide, collide_indexed,
    collide_placed, max_points,
};

/// Kinematic quantities of one contact at `(q, t)`, besides its force directions.
///
/// The force directions `w_N = (∂g_N/∂q)ᵀ` and `w_T = (∂g_T/∂q)ᵀ` are written into
/// caller-provided slices by [`ContactKinematics::contact`]; this struct carries the scalars.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactPoint {
    /// Normal gap g_N: positive open, zero closed, negative penetration (m).
    pub g_n: f64,
    /// Tangential position g_T of the contact point along the tangent (m); only its
    /// derivatives enter the dynamics, but the finite-difference checker uses it.
    pub g_t: f64,
    /// Rheonomic normal term ŵ_N = ∂g_N/∂t (m/s).
    pub w_n_hat: f64,
    /// Rheonomic tangential term ŵ_T = ∂g_T/∂t (m/s).
    pub w_t_hat: f64,
}

/// The contact kinematics of a mechanism with `f` generalised coordinates and `n` contacts.
///
/// Implementors write the gaps and their derivatives; the time-stepper and the
/// finite-difference checker only call these methods.
pub trait ContactKinematics {
    /// Number of generalised coordinates `f` (the length of `q` and `u`).
    fn num_coordinates(&self) -> usize;
    /// Number of contacts `n` (closed or open).
    fn num_contacts(&self) -> usize;
    /// The normal gap g_N of contact `i` at `(q, t)` alone, for the active-set test.
    fn normal_gap(&self, i: usize, q: &[f64], t: f64) -> f64;
    /// The normal gaps of all contacts at `(q, t)`, written into `g` (length `n`): what the
    /// time-stepper's active-set test needs once per step.
    ///
    /// The default calls [`Self::normal_gap`] for each contact. Override it when the gaps
    /// share work (the sines and cosines of the same angles, say); it must give the same
    /// values, which [`check_jacobians`] verifies.
    fn normal_gaps(&self, q: &[f64], t: f64, g: &mut [f64]) {
        for (i, gi) in g.iter_mut().enumerate() {
            *gi = self.normal_gap(i, q, t);
        }
    }
    /// Full kinematics of contact `i` at `(q, t)`: writes `w_N` into `w_n` and `w_T` into
    /// `w_t` (both of length `f`; every entry must be written, the buffers are reused) and
    /// returns g_N, g_T, ŵ_N and ŵ_T.
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint;
    /// Full kinematics of the contacts listed in `which`, at one `(q, t)`: for the k-th of
    /// them, [`Self::contact`]'s w_N into `w_n[k f..(k + 1) f]`, w_T into `w_t[k f..(k + 1) f]`
    /// and its [`ContactPoint`] into `points[k]`. What the time-stepper asks for the closed
    /// contacts once per step.
    ///
    /// The default calls [`Self::contact`] for each. Override it when the contacts share work
    /// (the sines and cosines of the same angles, say); it must give the same values, which
    /// [`check_jacobians`] verifies.
    fn contacts(
        &self,
        which: &[usize],
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
        points: &mut [ContactPoint],
    ) {
        let f = q.len();
        for (k, &i) in which.iter().enumerate() {
            points[k] =
                self.contact(i, q, t, &mut w_n[k * f..(k + 1) * f], &mut w_t[k * f..(k + 1) * f]);
        }
    }
}

/// The relative velocity γ = wᵀ u + ŵ of a contact, normal (w_N, ŵ_N) or tangential
/// (w_T, ŵ_T).
///
/// # Errors
/// [`KinematicsError::DimensionMismatch`] when `w` and `u` differ in length.
pub fn relative_velocity(w: &[f64], w_hat: f64, u: &[f64]) -> Result<f64, KinematicsError> {
    if w.len() != u.len() {
        return Err(KinematicsError::DimensionMismatch {
            what: "u against w",
            expected: w.len(),
            found: u.len(),
        });
    }
    Ok(w.iter().zip(u).map(|(a, b)| a * b).sum::<f64>() + w_hat)
}
