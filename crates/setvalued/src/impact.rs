//! Newton's impact law in the normal and tangential directions.
//!
//! With the relative velocities γ⁻ before and γ⁺ after an impact (or a time step) and the
//! restitution coefficients ε_N, ε_T of a [`ContactLaw`](crate::ContactLaw):
//!
//! ```text
//! ξ_N = γ_N⁺ + ε_N γ_N⁻,   ξ_T = γ_T⁺ + ε_T γ_T⁻,
//! −P_N ∈ Upr(ξ_N),         −P_T ∈ μ P_N Sgn(ξ_T).
//! ```
//!
//! In smooth motion ξ = (1 + ε) γ and the positive factor changes neither Upr nor Sgn, so the
//! same laws hold for impacts and persistent contact.
//!
//! # References
//! * Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics. In
//!   *Non-Smooth Mechanics and Applications*, CISM 302, Springer.
//! * Glocker, Ch. (2001). *Set-Valued Force Laws: Dynamics of Non-Smooth Systems*. Springer.
//! * Flores, P. (2010). *Application of the non-smooth dynamics approach to model and analyze
//!   contact-impact events in rigid multibody systems using the linear complementarity problem
//!   formulation*. Universidade do Minho.

use crate::{ContactLaw, SetValuedMap, Sgn, Upr};

/// Newton's velocity ξ = γ⁺ + ε γ⁻ from the post-impact velocity γ⁺, the pre-impact velocity
/// γ⁻ and the restitution coefficient ε (normal or tangential).
pub fn newton_xi(gamma_plus: f64, gamma_minus: f64, eps: f64) -> f64 {
    gamma_plus + eps * gamma_minus
}

/// The normal and tangential relative velocities γ_N, γ_T of one contact (m/s).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RelativeVelocity {
    /// Normal relative velocity γ_N.
    pub gamma_n: f64,
    /// Tangential relative velocity γ_T.
    pub gamma_t: f64,
}

/// The verdict of [`check_impact`]: Newton's velocities and the residuals of both laws.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactCheck {
    /// ξ_N = γ_N⁺ + ε_N γ_N⁻ (m/s).
    pub xi_n: f64,
    /// ξ_T = γ_T⁺ + ε_T γ_T⁻ (m/s).
    pub xi_t: f64,
    /// Distance of (ξ_N, −P_N) to the graph of Upr, i.e. |min(ξ_N, P_N)|.
    pub normal_residual: f64,
    /// Distance of (ξ_T, −P_T) to the graph of μ P_N Sgn (with P_N cut at zero).
    pub tangential_residual: f64,
    /// The tolerance the verdict was taken with.
    pub tol: f64,
}

impl ImpactCheck {
    /// Whether −P_N ∈ Upr(ξ_N) holds within the tolerance.
    pub fn normal_holds(&self) -> bool {
        self.normal_residual <= self.tol
    }

    /// Whether −P_T ∈ μ P_N Sgn(ξ_T) holds within the tolerance.
    pub fn tangential_holds(&self) -> bool {
        self.tangential_residual <= self.tol
    }

    /// Whether both laws hold.
    pub fn holds(&self) -> bool {
        self.normal_holds() && self.tangential_holds()
    }
}

/// Checks Newton's impact law for one contact: −P_N ∈ Upr(ξ_N) and −P_T ∈ μ P_N Sgn(ξ_T), with
/// ξ from the velocities `pre` (γ⁻) and `post` (γ⁺) and ε_N, ε_T, μ from `law`. Residuals are
/// graph distances (see [`SetValuedMap::graph_distance`]); NaN inputs give NaN residuals and a
/// failed verdict.
pub fn check_impact(
    pre: RelativeVelocity,
    post: RelativeVelocity,
    p_n: f64,
    p_t: f64,
    law: &ContactLaw,
    tol: f64,
) -> ImpactCheck {
    let xi_n = newton_xi(post.gamma_n, pre.gamma_n, law.eps_n());
    let xi_t = newton_xi(post.gamma_t, pre.gamma_t, law.eps_t());
    let normal_residual = Upr.graph_distance(xi_n, -p_n);
    // A negative P_N already fails the normal law; the friction bound is taken at P_N ≥ 0.
    let tangential_residual = match Sgn::coulomb(law.mu(), p_n.max(0.0)) {
        Ok(relay) if !p_n.is_nan() => relay.graph_distance(xi_t, -p_t),
        _ => f64::NAN,
    };
    ImpactCheck { xi_n, xi_t, normal_residual, tangential_residual, tol }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(gamma_n: f64, gamma_t: f64) -> RelativeVelocity {
        RelativeVelocity { gamma_n, gamma_t }
    }

    #[test]
    fn bouncing_ball_impact() {
        // A 1 kg ball hits the floor at 4.43 m/s with ε_N = 0.9: γ⁺ = 3.987, P_N = 1.9 · 4.43.
        let law = ContactLaw::frictionless(0.9).unwrap();
        let (pre, post) = (v(-4.43, 0.0), v(0.9 * 4.43, 0.0));
        assert!((newton_xi(post.gamma_n, pre.gamma_n, 0.9)).abs() < 1e-15);
        let c = check_impact(pre, post, 1.9 * 4.43, 0.0, &law, 1e-12);
        assert!(c.holds(), "{c:?}");
        // Too slow a rebound with a positive impulse violates the law by |ξ_N|.
        let c = check_impact(pre, v(3.0, 0.0), 1.9 * 4.43, 0.0, &law, 1e-12);
        assert!(!c.normal_holds() && c.tangential_holds());
        assert!((c.xi_n - (3.0 - 0.9 * 4.43)).abs() < 1e-15);
        assert!((c.normal_residual - (0.9 * 4.43 - 3.0)).abs() < 1e-15);
        // Separating with no impulse is fine; a pulling impulse is not.
        assert!(check_impact(v(1.0, 0.0), v(1.0, 0.0), 0.0, 0.0, &law, 0.0).holds());
        assert!(!check_impact(v(1.0, 0.0), v(1.0, 0.0), -0.1, 0.0, &law, 0.01).normal_holds());
        // A frictionless contact carries no tangential impulse.
        assert!(!check_impact(pre, post, 1.9 * 4.43, 0.2, &law, 0.1).tangential_holds());
    }

    #[test]
    fn frictional_impact_sticks_or_slides() {
        let law = ContactLaw::new(0.5, 0.0, 0.3).unwrap();
        // Sticking after the impact: ξ_T = 0, |P_T| ≤ μ P_N = 0.6.
        let c = check_impact(v(-2.0, 1.0), v(1.0, 0.0), 2.0, -0.5, &law, 0.0);
        assert!(c.holds(), "{c:?}");
        assert_eq!(c.xi_n, 0.0);
        // Still sliding forward: P_T = −μ P_N.
        assert!(check_impact(v(-2.0, 1.0), v(1.0, 0.5), 2.0, -0.6, &law, 1e-15).holds());
        let c = check_impact(v(-2.0, 1.0), v(1.0, 0.5), 2.0, -0.4, &law, 1e-15);
        assert!(c.normal_holds() && !c.tangential_holds());
        assert!((c.tangential_residual - 0.2).abs() < 1e-15);
        // Tangential restitution enters ξ_T.
        let law = ContactLaw::new(0.5, 0.5, 0.3).unwrap();
        assert_eq!(check_impact(v(-2.0, 1.0), v(1.0, -0.5), 2.0, 0.0, &law, 0.0).xi_t, 0.0);
        assert!(!check_impact(v(f64::NAN, 0.0), v(0.0, 0.0), 0.0, 0.0, &law, 1.0).holds());
        assert!(
            !check_impact(v(0.0, 0.0), v(0.0, 0.0), f64::NAN, 0.0, &law, 1.0).tangential_holds()
        );
    }
}
