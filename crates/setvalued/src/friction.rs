//! Coulomb's law −λ_T ∈ μλ_N Sgn(γ_T) and its split into two unilateral primitives.
//!
//! The split used by the step's LCP (docs/theory.md section 5) introduces
//!
//! ```text
//! λ_R = μλ_N + λ_T,   λ_L = μλ_N − λ_T,   γ_T = γ_R − γ_L,
//! 0 ≤ γ_R ⊥ λ_R ≥ 0,  0 ≤ γ_L ⊥ λ_L ≥ 0,
//! ```
//!
//! and Coulomb's law holds if and only if both complementarities hold with γ_R = max(γ_T, 0)
//! and γ_L = max(−γ_T, 0). Back: λ_T = (λ_R − λ_L)/2, μλ_N = (λ_R + λ_L)/2, γ_T = γ_R − γ_L.
//! The same holds on the impulse level with (P_N, P_T, ξ_T) for (λ_N, λ_T, γ_T).
//!
//! # References
//! * Glocker, Ch. (2001). *Set-Valued Force Laws: Dynamics of Non-Smooth Systems*. Springer.
//! * Flores, P. (2010). *Application of the non-smooth dynamics approach to model and analyze
//!   contact-impact events in rigid multibody systems using the linear complementarity problem
//!   formulation*. Universidade do Minho.

use crate::{SetValuedError, SetValuedMap, Sgn, checked_mu, complementarity};

/// Whether Coulomb's law −λ_T ∈ μλ_N Sgn(γ_T) holds within `tol` (graph distance of the relay
/// with bound μλ_N). False when μ or μλ_N is negative or an input is not finite.
pub fn coulomb_holds(mu: f64, lambda_n: f64, lambda_t: f64, gamma_t: f64, tol: f64) -> bool {
    Sgn::coulomb(mu, lambda_n).is_ok_and(|relay| relay.contains(gamma_t, -lambda_t, tol))
}

/// The normal force, tangential force and tangential velocity (λ_N, λ_T, γ_T) of one contact;
/// equally the impulses and Newton's velocities (P_N, P_T, ξ_T).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoulombState {
    /// Normal force λ_N (N) or impulse P_N (N s).
    pub lambda_n: f64,
    /// Tangential force λ_T (N) or impulse P_T (N s).
    pub lambda_t: f64,
    /// Tangential relative velocity γ_T or ξ_T (m/s).
    pub gamma_t: f64,
}

/// Coulomb's law split into two unilateral primitives (see the documentation of this module).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoulombSplit {
    /// λ_R = μλ_N + λ_T.
    pub lambda_r: f64,
    /// λ_L = μλ_N − λ_T.
    pub lambda_l: f64,
    /// γ_R, the positive part of γ_T in the canonical split.
    pub gamma_r: f64,
    /// γ_L, the negative part of γ_T in the canonical split.
    pub gamma_l: f64,
}

impl CoulombSplit {
    /// The split of (λ_N, λ_T, γ_T) with friction coefficient μ: λ_R = μλ_N + λ_T,
    /// λ_L = μλ_N − λ_T, γ_R = max(γ_T, 0), γ_L = max(−γ_T, 0).
    ///
    /// # Errors
    /// [`SetValuedError::Friction`] for a negative or non-finite μ, [`SetValuedError::NonFinite`]
    /// for a non-finite λ_N, λ_T or γ_T.
    pub fn from_coulomb(mu: f64, state: CoulombState) -> Result<Self, SetValuedError> {
        checked_mu(mu)?;
        for (what, value) in
            [("lambda_n", state.lambda_n), ("lambda_t", state.lambda_t), ("gamma_t", state.gamma_t)]
        {
            if !value.is_finite() {
                return Err(SetValuedError::NonFinite { what, value });
            }
        }
        let bound = mu * state.lambda_n;
        Ok(Self {
            lambda_r: bound + state.lambda_t,
            lambda_l: bound - state.lambda_t,
            gamma_r: state.gamma_t.max(0.0),
            gamma_l: (-state.gamma_t).max(0.0),
        })
    }

    /// The friction bound μλ_N = (λ_R + λ_L)/2.
    pub fn friction_bound(&self) -> f64 {
        0.5 * (self.lambda_r + self.lambda_l)
    }

    /// The tangential force λ_T = (λ_R − λ_L)/2.
    pub fn lambda_t(&self) -> f64 {
        0.5 * (self.lambda_r - self.lambda_l)
    }

    /// The tangential velocity γ_T = γ_R − γ_L.
    pub fn gamma_t(&self) -> f64 {
        self.gamma_r - self.gamma_l
    }

    /// Back to (λ_N, λ_T, γ_T) with friction coefficient μ > 0.
    ///
    /// # Errors
    /// [`SetValuedError::Undetermined`] when μ = 0 (λ_N is then not determined by the split),
    /// [`SetValuedError::Friction`] for a negative or non-finite μ.
    pub fn to_coulomb(&self, mu: f64) -> Result<CoulombState, SetValuedError> {
        checked_mu(mu)?;
        if mu == 0.0 {
            return Err(SetValuedError::Undetermined { quantity: "lambda_n" });
        }
        Ok(CoulombState {
            lambda_n: self.friction_bound() / mu,
            lambda_t: self.lambda_t(),
            gamma_t: self.gamma_t(),
        })
    }

    /// Whether both complementarities 0 ≤ γ_R ⊥ λ_R ≥ 0 and 0 ≤ γ_L ⊥ λ_L ≥ 0 hold within `tol`
    /// (natural-map residuals, see [`complementarity`]).
    pub fn holds(&self, tol: f64) -> bool {
        complementarity(self.gamma_r, self.lambda_r, tol)
            && complementarity(self.gamma_l, self.lambda_l, tol)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(lambda_n: f64, lambda_t: f64, gamma_t: f64) -> CoulombState {
        CoulombState { lambda_n, lambda_t, gamma_t }
    }

    #[test]
    fn sliding_and_sticking_cases() {
        // μ = 0.25, λ_N = 4 N: bound 1 N.
        // Sliding forward: λ_T = −1 N, λ_R = 0, λ_L = 2 N, γ_R = 2 m/s.
        let s = CoulombSplit::from_coulomb(0.25, state(4.0, -1.0, 2.0)).unwrap();
        assert_eq!(s, CoulombSplit { lambda_r: 0.0, lambda_l: 2.0, gamma_r: 2.0, gamma_l: 0.0 });
        assert!(s.holds(0.0) && coulomb_holds(0.25, 4.0, -1.0, 2.0, 0.0));
        // Sliding backward needs λ_T = +μλ_N.
        assert!(coulomb_holds(0.25, 4.0, 1.0, -0.5, 0.0));
        assert!(!coulomb_holds(0.25, 4.0, -1.0, -0.5, 0.0));
        assert!(!CoulombSplit::from_coulomb(0.25, state(4.0, -1.0, -0.5)).unwrap().holds(0.0));
        // Sticking with |λ_T| ≤ μλ_N.
        assert!(CoulombSplit::from_coulomb(0.25, state(4.0, 0.5, 0.0)).unwrap().holds(0.0));
        assert!(!CoulombSplit::from_coulomb(0.25, state(4.0, 1.5, 0.0)).unwrap().holds(0.0));
        // A force below the bound while sliding violates the law.
        assert!(!coulomb_holds(0.25, 4.0, -0.5, 2.0, 0.0));
        assert!(!CoulombSplit::from_coulomb(0.25, state(4.0, -0.5, 2.0)).unwrap().holds(0.0));
        // A negative normal force violates it too.
        assert!(!coulomb_holds(0.25, -4.0, 0.0, 0.0, 0.0));
        assert!(!CoulombSplit::from_coulomb(0.25, state(-4.0, 0.0, 0.0)).unwrap().holds(0.0));
    }

    #[test]
    fn split_round_trip_and_errors() {
        let original = state(3.0, -0.75, -1.5);
        let s = CoulombSplit::from_coulomb(0.5, original).unwrap();
        assert_eq!(s.friction_bound(), 1.5);
        assert_eq!(s.to_coulomb(0.5).unwrap(), original);
        assert_eq!(s.to_coulomb(0.0), Err(SetValuedError::Undetermined { quantity: "lambda_n" }));
        assert_eq!(s.to_coulomb(-1.0), Err(SetValuedError::Friction { value: -1.0 }));
        assert!(CoulombSplit::from_coulomb(f64::NAN, original).is_err());
        assert!(matches!(
            CoulombSplit::from_coulomb(0.5, state(1.0, f64::INFINITY, 0.0)),
            Err(SetValuedError::NonFinite { what: "lambda_t", .. })
        ));
        // Frictionless: the split forces λ_T = 0.
        assert!(CoulombSplit::from_coulomb(0.0, state(3.0, 0.0, 2.0)).unwrap().holds(0.0));
        assert!(!CoulombSplit::from_coulomb(0.0, state(3.0, 0.1, 2.0)).unwrap().holds(0.05));
    }
}
