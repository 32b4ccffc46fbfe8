//! Moreau's midpoint time-stepping for planar rigid multibody systems with hard unilateral
//! contacts, Coulomb friction and Newton impacts.
//!
//! A mechanism with generalised coordinates `q` and velocities `u` obeys the equality of
//! measures `M(q, t) du − h(q, u, t) dt − W_N dP_N − W_T dP_T = 0`. The [`Stepper`] integrates it
//! with Moreau's midpoint scheme at the velocity-impulse level: each step evaluates `M` and `h`
//! at the midpoint, collects the contacts whose gap g_N is closed there, and solves one linear
//! complementarity problem (LCP) for the impulses P_N, P_T that satisfy Signorini's law,
//! Coulomb's law and Newton's impact law (ξ_N = γ_N⁺ + ε_N γ_N⁻) at once. Impacts and persistent
//! contact need no event detection and no switching.
//!
//! **For**: mechanisms of a few to a few dozen coordinates with impacts and stick-slip, long
//! runs and parameter sweeps; and, through a [`BodyStructure`], piles and stacks of thousands
//! of rigid bodies whose contacts are detected at each step (see *The many-body path*). **Not for**: smooth multibody dynamics without contact (use an
//! ODE/DAE integrator with error control), compliant contact models, 3-D friction cones.
//!
//! Principal types: the [`Mechanism`] trait a user implements; [`Stepper`] with
//! [`Stepper::step`] returning a [`StepReport`]; [`Stepper::run_until`] streaming steps to an
//! [`Observer`]; [`Recorder`] and [`Record`] for keeping a trajectory, with every [`Impact`]
//! listed; [`StepperOptions`] and
//! [`SolverChoice`]; [`StepError`]; [`check_evaluate`] for the overrides that share work
//! between M, h, the gaps and the contacts' kinematics; [`BodyStructure`] and [`BodyContact`]
//! for the many-body path.
//!
//! | symbol | identifier | meaning |
//! |---|---|---|
//! | q, u | `q`, `u` | generalised coordinates and velocities |
//! | M, h | [`Mechanism::mass_matrix`], [`Mechanism::forces`] | mass matrix, smooth forces |
//! | g_N, w_N, w_T, ŵ_N, ŵ_T | `moreau_kinematics::ContactKinematics` | gaps and force directions |
//! | ε_N, ε_T, μ | `moreau_setvalued::ContactLaw` | restitution and friction |
//! | P_N, P_T | [`ContactReport::p_n`], [`ContactReport::p_t`] | impulses over one step |
//! | γ_N,A, γ_N,E | [`ContactReport::gamma_n_a`], [`ContactReport::gamma_n`] | normal relative velocity before and after a step |
//! | Δt | [`StepperOptions::dt`] | time step |
//!
//! # Example: a ball dropped on the floor
//! ```
//! use moreau_kinematics::{ContactKinematics, ContactPoint};
//! use moreau_setvalued::ContactLaw;
//! use moreau_stepper::{Mechanism, Stepper, StepperOptions};
//!
//! /// A ball of mass m and radius r above the floor y = 0: q = (y).
//! struct Ball { m: f64, r: f64, laws: [ContactLaw; 1] }
//!
//! impl ContactKinematics for Ball {
//!     fn num_coordinates(&self) -> usize { 1 }
//!     fn num_contacts(&self) -> usize { 1 }
//!     fn normal_gap(&self, _i: usize, q: &[f64], _t: f64) -> f64 { q[0] - self.r }
//!     fn contact(&self, i: usize, q: &[f64], t: f64, w_n: &mut [f64], w_t: &mut [f64]) -> ContactPoint {
//!         w_n[0] = 1.0;
//!         w_t[0] = 0.0;
//!         ContactPoint { g_n: self.normal_gap(i, q, t), ..ContactPoint::default() }
//!     }
//! }
//!
//! impl Mechanism for Ball {
//!     fn laws(&self) -> &[ContactLaw] { &self.laws }
//!     fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) { m[0] = self.m; }
//!     fn forces(&self, _q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) { h[0] = -self.m * 9.81; }
//!     fn constant_mass_matrix(&self) -> bool { true }
//! }
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let ball = Ball { m: 1.0, r: 0.1, laws: [ContactLaw::frictionless(0.9)?] };
//! // A contact counts as closed at g_N <= 1e-12 m: with the default of 0, a contact left
//! // open by round-off after it closed sits out a step (see `StepperOptions::gap_tolerance`).
//! let options = StepperOptions::new(1e-3).with_gap_tolerance(1e-12);
//! let mut stepper = Stepper::new(ball, &[1.0], &[0.0], 0.0, options)?;
//! let record = stepper.record_until(1.0)?;
//! // The first impact happens at t1 = sqrt(2 (y0 − r) / g) ≈ 0.428 s.
//! let first = record.p_n.iter().position(|p| p[0] > 0.0).unwrap();
//! assert!((record.t[first] - (2.0 * 0.9 / 9.81f64).sqrt()).abs() < 2e-3);
//! # Ok(())
//! # }
//! ```
//!
//! # The many-body path
//! A mechanism made of rigid bodies in maximal coordinates (x, y, θ per body) that returns its
//! [`BodyStructure`] from [`Mechanism::body_structure`] is stepped without the f × f mass
//! matrix or rows of length f (docs/theory.md section 10): M is kept as one 3 × 3 block per
//! body, the contacts are those [`BodyStructure::detect`] finds at the midpoint (each with an
//! identity kept from step to step, and its force directions on its two bodies), and the
//! step's contact problem is split into islands (the bodies linked by contacts; fixed and
//! driven bodies link nothing). Each island's planar frictional-contact problem is assembled
//! on 2 × 2 blocks W_ij = w_iᵀ M⁻¹ w_j and solved by `moreau_lcp::fc2d`: the default
//! [`SolverChoice::Auto`] by `Fc2dAuto` (unrelaxed to 1e-13 for islands of up to 8 contacts,
//! a one-contact island in one sweep, pivoting and at most 2,000 sweeps; over-relaxed to
//! 1e-10 beyond, within 5,000 sweeps; and for any island still unsolved, to 1e-10, nonsmooth
//! Newton started cold, the proximal point method, 100,000 more sweeps, and pivoting for
//! islands of up to 300 contacts, straight after the sweeps for a frictionless one of that
//! size or one with joints, its candidate finished by Newton when it falls short; islands of
//! bodies far from 1 kg in scaled units),
//! [`SolverChoice::Pgs`] by
//! `Nsgs` with its options, [`SolverChoice::Lemke`] and [`SolverChoice::Enumeration`] by the
//! exact `LcpRoute` with that pivoting solver. Every contact is warm-started from the impulses
//! last found under its identity. Islands are solved in parallel on rayon's current pool,
//! batched so that many one-contact islands do not cost a task each; the results are
//! bit-identical for any number of threads. A failed island is [`StepError::IslandFailed`],
//! carrying its problem, unless [`StepperOptions::inexact_residual`] takes it: then the step's
//! [`LcpInfo`] has status `IterationLimit` and [`RunSummary`] counts the step.
//!
//! The midpoint rule, Newton's impact law, the impact test, the projection and the reports are
//! those of the path of fixed contacts: [`StepReport::contacts`] lists the contacts detected at
//! the step's midpoint in increasing order of identity, [`StepReport::contact_ids`] their
//! identities, [`StepReport::lcp`] the worst island and [`StepReport::times`] the wall time of
//! detection, assembly, solution and projection. A [`Recorder`] keeps the bodies' q and u and the
//! energies, and lists impacts by contact identity; it keeps no per-contact columns, since the
//! contacts come and go. Nothing is allocated per step once the buffers have grown to the
//! largest contact set and the islands' solvers have seen their block structures (Newton
//! keeps the last four of each). Joints (bilateral constraints, split by body through
//! [`BodyStructure::bilateral_rows`]) link their bodies into islands as contacts do and join
//! each island's problem as bilateral groups; the projection corrects their drift.
//!
//! # References
//! - Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics.
//!   In *Non-smooth Mechanics and Applications*, CISM 302, Springer.
//! - Glocker, Ch. (2001). *Set-Valued Force Laws*. Springer.
//! - Flores, P. (2010). Application of the non-smooth dynamics approach to model and analyze
//!   contact-impact events in rigid multibody systems using the LCP formulation.
//!   Universidade do Minho.
#![deny(missing_docs)]

/// Everything a hand-derived mechanism needs, in one import: the two traits to implement
/// ([`Mechanism`] and its supertrait `ContactKinematics`), their value types, the contact law,
/// the finite-difference check of the force directions (`check_jacobians` at
/// `sample_states`), and the stepper with its options, observers, record, reports and error.
///
/// ```
/// use moreau_stepper::prelude::*;
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let law = ContactLaw::new(0.5, 0.0, 0.3)?;
/// let options = StepperOptions::new(1e-3).with_gap_tolerance(1e-12);
/// assert_eq!((law.mu(), options.dt, options.solver), (0.3, 1e-3, SolverChoice::Auto));
/// let samples = sample_states(&[0.0, 0.2, 0.1], 0.0, SampleOptions::default())?;
/// assert_eq!(samples.len(), SampleOptions::default().count);
/// # Ok(())
/// # }
/// ```
pub mod prelude {
    pub use crate::{
        BilateralPoint, ContactReport, ContactState, Impact, Mechanism, Observer, Record, Recorder,
        RunSummary, SharedWork, SolverChoice, StepError, StepReport, Stepper, StepperOptions,
    };
    pub use moreau_kinematics::{
        ContactKinematics, ContactPoint, FdOptions, SampleOptions, check_jacobians, sample_states,
    };
    pub use moreau_setvalued::ContactLaw;
}

mod bodies;
mod check;
mod dense;
mod error;
mod mechanism;
mod observer;
mod options;
mod report;
mod rows;
mod stepper;

pub use bodies::{BodyBilateral, BodyContact, BodyStructure, NO_BODY};
pub use check::{EvaluateMismatch, check_evaluate};
pub use error::StepError;
pub use mechanism::{BilateralPoint, Mechanism, SharedWork};
pub use observer::{Impact, Observer, Record, Recorder};
pub use options::{SolverChoice, StepperOptions, UnknownSolver};
pub use rows::{RowIter, Rows};
pub use stepper::{
    ContactReport, ContactState, Impulses, LcpInfo, PhaseTimes, RunSummary, StepReport, Stepper,
};
