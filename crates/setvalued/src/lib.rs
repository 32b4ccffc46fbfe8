//! Set-valued force laws of non-smooth mechanics.
//!
//! # What this crate is for
//! The contact laws of Moreau's time-stepping in the report's notation, as set-valued maps on
//! the reals with membership tests, inverses, proximal maps and sampled graphs:
//! * [`Upr`], the unilateral primitive: Signorini's law −λ_N ∈ Upr(g_N) and the complementarity
//!   0 ≤ x ⊥ y ≥ 0 ⇔ −y ∈ Upr(x) ([`complementarity`]);
//! * [`Sgn`], the set-valued sign scaled by a bound: Coulomb's law −λ_T ∈ μλ_N Sgn(γ_T) and its
//!   split into two unilateral primitives ([`CoulombSplit`]) used by the step's LCP;
//! * Newton's impact law ξ = γ⁺ + ε γ⁻, −P_N ∈ Upr(ξ_N), −P_T ∈ μ P_N Sgn(ξ_T)
//!   ([`newton_xi`], [`check_impact`]) with the per-contact parameters [`ContactLaw`];
//! * the planar friction cone K_μ = {λ_N ≥ 0, |λ_T| ≤ μλ_N} ([`FrictionCone`]): its
//!   projection, distance and De Saxcé's natural map, which vanishes exactly when Signorini's
//!   and Coulomb's laws hold together;
//! * the graphs of Signorini's and Coulomb's laws for plotting ([`signorini_graph`],
//!   [`coulomb_graph`], [`sample_graph`]).
//!
//! # What it is not for
//! It solves nothing: the LCP solvers are in `moreau-lcp` and the time-stepping in
//! `moreau-stepper`. It knows nothing of geometry (see `moreau-kinematics`). The checks here
//! verify the laws for given numbers, e.g. for tests and reports.
//!
//! # The maps
//! ```text
//! Upr(x)   = {0} (x > 0),  (−∞, 0] (x = 0),  ∅ (x < 0)
//! b Sgn(x) = {+b} (x > 0), [−b, +b] (x = 0), {−b} (x < 0)
//! −y ∈ Upr(x)  ⇔  x ≥ 0, y ≥ 0, x y = 0
//! Upr(a x) = Upr(x),  a Upr(x) = Upr(x)  for a > 0
//! ```
//!
//! # Notation
//! | symbol | identifier |
//! |---|---|
//! | ε_N, ε_T, μ | [`ContactLaw::eps_n`], [`ContactLaw::eps_t`], [`ContactLaw::mu`] |
//! | g_N, λ_N, λ_T, γ_T | `g_n`, `lambda_n`, `lambda_t`, `gamma_t` |
//! | γ⁻, γ⁺ | `gamma_minus`, `gamma_plus`, [`RelativeVelocity`] |
//! | ξ_N, ξ_T, P_N, P_T | `xi_n`, `xi_t`, `p_n`, `p_t` |
//! | λ_R, λ_L, γ_R, γ_L | fields of [`CoulombSplit`] |
//! | K_μ, γ̂ = (γ_N + μ\|γ_T\|, γ_T) | [`FrictionCone`], De Saxcé's modified velocity |
//!
//! # Example
//! ```
//! use moreau_setvalued::{ContactLaw, FrictionCone, RelativeVelocity, SetValuedError};
//! use moreau_setvalued::{SetValuedMap, Sgn, Upr};
//! use moreau_setvalued::{check_impact, complementarity};
//!
//! # fn main() -> Result<(), SetValuedError> {
//! // A closed contact pushing with λ_N = 2 N: −λ_N ∈ Upr(0), i.e. 0 ≤ g_N ⊥ λ_N ≥ 0.
//! assert!(Upr.contains(0.0, -2.0, 0.0) && complementarity(0.0, 2.0, 0.0));
//! // Coulomb: sliding with γ_T > 0 needs λ_T = −μλ_N.
//! let relay = Sgn::coulomb(0.3, 2.0)?;
//! assert!(relay.contains(0.5, 0.6, 1e-15));
//! // Newton's impact law for a ball hitting the floor at 2 m/s with ε_N = 0.5.
//! let law = ContactLaw::frictionless(0.5)?;
//! let pre = RelativeVelocity { gamma_n: -2.0, gamma_t: 0.0 };
//! let post = RelativeVelocity { gamma_n: 1.0, gamma_t: 0.0 };
//! assert!(check_impact(pre, post, 3.0, 0.0, &law, 1e-12).holds());
//! // The friction cone |λ_T| ≤ μλ_N with μ = 1: (1, 3) lies beyond its upper edge and projects
//! // to n (1, μ) with n = (1 + μ · 3)/(1 + μ²) = 2; a pulling force projects to the apex.
//! let cone = FrictionCone::new(1.0)?;
//! assert_eq!(cone.project(1.0, 3.0), (2.0, 2.0));
//! assert_eq!(cone.project(-4.0, 1.0), (0.0, 0.0));
//! // Sliding at γ_T = 2 m/s under λ_N = 4 N with λ_T = −μλ_N: both laws hold.
//! assert_eq!(cone.natural_map((4.0, -4.0), (0.0, 2.0), 1.0)?, (0.0, 0.0));
//! # Ok(())
//! # }
//! ```
//!
//! # References
//! * Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics. In
//!   *Non-Smooth Mechanics and Applications*, CISM Courses and Lectures 302, Springer.
//! * Glocker, Ch. (2001). *Set-Valued Force Laws: Dynamics of Non-Smooth Systems*. Springer.
//! * Flores, P. (2010). *Application of the non-smooth dynamics approach to model and analyze
//!   contact-impact events in rigid multibody systems using the linear complementarity problem
//!   formulation*. Universidade do Minho.
#![deny(missing_docs)]

mod cone;
mod friction;
mod impact;
mod law;
mod maps;
mod value_set;

pub use cone::{FrictionCone, friction_natural_map, project_friction_cone};
pub use friction::{CoulombSplit, CoulombState, coulomb_holds};
pub use impact::{ImpactCheck, RelativeVelocity, check_impact, newton_xi};
pub use law::{ContactLaw, ContactLawSpec};
pub use maps::{
    GraphWindow, SetValuedMap, Sgn, Upr, complementarity, complementarity_residual, coulomb_graph,
    sample_graph, signorini_graph,
};
pub use value_set::ValueSet;

/// Errors of this crate: invalid law parameters and invalid inputs of the helpers.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SetValuedError {
    /// A restitution coefficient outside `[0, 1]` or not finite.
    #[error("restitution coefficient {name} = {value} is outside [0, 1]")]
    Restitution {
        /// Which coefficient (`eps_n` or `eps_t`).
        name: &'static str,
        /// The rejected value.
        value: f64,
    },
    /// A negative or non-finite friction coefficient.
    #[error("friction coefficient mu = {value} must be finite and >= 0")]
    Friction {
        /// The rejected value.
        value: f64,
    },
    /// A negative or non-finite bound b of a relay b Sgn (e.g. μλ_N).
    #[error("relay bound {value} must be finite and >= 0")]
    Bound {
        /// The rejected value.
        value: f64,
    },
    /// A non-finite force, impulse or velocity.
    #[error("{what} = {value} is not finite")]
    NonFinite {
        /// Which quantity.
        what: &'static str,
        /// The rejected value.
        value: f64,
    },
    /// A quantity that the given data do not determine (λ_N from a split with μ = 0).
    #[error("{quantity} is not determined by the data")]
    Undetermined {
        /// Which quantity.
        quantity: &'static str,
    },
    /// A step r of a natural map (e.g. [`FrictionCone::natural_map`]) that is not positive
    /// and finite.
    #[error("step r = {value} of a natural map must be positive and finite")]
    Step {
        /// The rejected value.
        value: f64,
    },
    /// A plotting window edge that is not finite, or leaves an empty window or one wider than
    /// f64's range.
    #[error(
        "graph window edge {name} = {value} is not finite or leaves an empty or overflowing \
         window"
    )]
    Window {
        /// Which edge (`x_min`, `x_max`, `y_min`, `y_max`, `g_max`, `lambda_max`).
        name: &'static str,
        /// The rejected value.
        value: f64,
    },
    /// More sample abscissae for a graph than memory holds.
    #[error("a graph of {points} sample points cannot be allocated")]
    TooManySamples {
        /// The number requested.
        points: usize,
    },
    /// Fewer than two sample abscissae for a graph.
    #[error("a graph needs at least 2 sample points, got {points}")]
    Samples {
        /// The number requested.
        points: usize,
    },
}

/// μ itself when it is a valid friction coefficient (finite and `>= 0`).
///
/// # Errors
/// [`SetValuedError::Friction`] naming μ otherwise.
pub(crate) fn checked_mu(mu: f64) -> Result<f64, SetValuedError> {
    if mu >= 0.0 && mu.is_finite() { Ok(mu) } else { Err(SetValuedError::Friction { value: mu }) }
}
