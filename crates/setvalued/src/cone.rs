//! The planar Coulomb friction cone and the projection onto it.
//!
//! ```text
//! K_μ = {(λ_N, λ_T) : λ_N ≥ 0, |λ_T| ≤ μ λ_N}        (μ = 0: the half-line λ_T = 0 ≤ λ_N)
//! ```
//!
//! Signorini's and Coulomb's laws of one contact together read −γ̂ ∈ N_K(λ), the normal cone
//! of K_μ at λ = (λ_N, λ_T), with De Saxcé's modified velocity γ̂ = (γ_N + μ|γ_T|, γ_T); as a
//! fixed point of the projection, λ = proj_K(λ − r γ̂) for any r > 0. This is the form in which
//! the planar frictional-contact solvers measure their residual.
//!
//! # References
//! * De Saxcé, G., & Feng, Z.-Q. (1998). The bipotential method: a constructive approach to
//!   design the complete contact law with friction and improved numerical algorithms.
//!   *Mathematical and Computer Modelling* 28(4–8), 225–245.
//! * Moreau, J. J. (1962). Décomposition orthogonale d'un espace hilbertien selon deux cônes
//!   mutuellement polaires. *C. R. Acad. Sci. Paris* 255, 238–240.

use crate::{SetValuedError, checked_mu};

/// The planar Coulomb friction cone K_μ = {(λ_N, λ_T) : λ_N ≥ 0, |λ_T| ≤ μ λ_N} of a friction
/// coefficient μ ≥ 0, for forces (λ_N, λ_T) or impulses (P_N, P_T).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionCone {
    mu: f64,
}

impl FrictionCone {
    /// The cone of friction coefficient μ.
    ///
    /// # Errors
    /// [`SetValuedError::Friction`] when μ is negative or not finite.
    pub fn new(mu: f64) -> Result<Self, SetValuedError> {
        Ok(Self { mu: checked_mu(mu)? })
    }

    /// The friction coefficient μ.
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// The Euclidean projection of (λ_N, λ_T) onto K_μ: the point itself inside the cone, the
    /// apex (0, 0) in the polar cone {λ_N + μ|λ_T| ≤ 0}, and otherwise the point
    /// n (1, μ sgn λ_T) of the nearer edge, n = (λ_N + μ|λ_T|) / (1 + μ²). NaN in, NaN out.
    pub fn project(&self, lambda_n: f64, lambda_t: f64) -> (f64, f64) {
        project_friction_cone(lambda_n, lambda_t, self.mu)
    }

    /// The Euclidean distance from (λ_N, λ_T) to K_μ; NaN for a NaN input.
    pub fn distance(&self, lambda_n: f64, lambda_t: f64) -> f64 {
        let (p_n, p_t) = self.project(lambda_n, lambda_t);
        (lambda_n - p_n).hypot(lambda_t - p_t)
    }

    /// Whether (λ_N, λ_T) lies in K_μ within `tol` (Euclidean distance at most `tol`); false
    /// for a NaN input.
    pub fn contains(&self, lambda_n: f64, lambda_t: f64, tol: f64) -> bool {
        self.distance(lambda_n, lambda_t) <= tol
    }

    /// The natural map λ − proj_K(λ − r γ̂) of one contact, with De Saxcé's modified velocity
    /// γ̂ = (γ_N + μ|γ_T|, γ_T) and a step r > 0: zero exactly when 0 ≤ γ_N ⊥ λ_N ≥ 0 and
    /// −λ_T ∈ μλ_N Sgn(γ_T) hold together. Its Euclidean norm is a residual of both laws.
    ///
    /// # Errors
    /// [`SetValuedError::Step`] when r is not positive and finite.
    pub fn natural_map(
        &self,
        lambda: (f64, f64),
        gamma: (f64, f64),
        r: f64,
    ) -> Result<(f64, f64), SetValuedError> {
        if !(r > 0.0 && r.is_finite()) {
            return Err(SetValuedError::Step { value: r });
        }
        Ok(friction_natural_map(lambda, gamma, self.mu, r))
    }
}

/// [`FrictionCone::natural_map`] for a μ and an r the caller has checked (μ finite and ≥ 0,
/// r > 0 and finite), for the inner loops of solvers: λ − proj_K(λ − r γ̂) with
/// γ̂ = (γ_N + μ|γ_T|, γ_T). With r = 1 it is the residual of the planar frictional-contact
/// solvers, bit for bit (a product by 1 is exact).
#[inline]
pub fn friction_natural_map(
    (lambda_n, lambda_t): (f64, f64),
    (gamma_n, gamma_t): (f64, f64),
    mu: f64,
    r: f64,
) -> (f64, f64) {
    // λ_N − r γ_N − r μ|γ_T|, left to right, so that r = 1 rounds as λ_N − γ_N − μ|γ_T|.
    let x_n = lambda_n - r * gamma_n - r * (mu * gamma_t.abs());
    let (p_n, p_t) = project_friction_cone(x_n, lambda_t - r * gamma_t, mu);
    (lambda_n - p_n, lambda_t - p_t)
}

/// [`FrictionCone::project`] for a μ the caller has checked (finite and ≥ 0): the projection
/// of (λ_N, λ_T) onto K_μ, for the inner loops of solvers that check μ once per problem.
#[inline]
pub fn project_friction_cone(lambda_n: f64, lambda_t: f64, mu: f64) -> (f64, f64) {
    let abs_t = lambda_t.abs();
    // λ_N ≥ 0 is tested apart: with μ = 0 and λ_T = 0, |λ_T| ≤ μ λ_N holds for λ_N < 0 too.
    if lambda_n >= 0.0 && abs_t <= mu * lambda_n {
        (lambda_n, lambda_t)
    } else if mu * abs_t <= -lambda_n {
        // In the polar cone: the nearest point of K_μ is its apex.
        (0.0, 0.0)
    } else {
        let n = (lambda_n + mu * abs_t) / (1.0 + mu * mu);
        (n, (mu * n).copysign(lambda_t))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: (f64, f64), b: (f64, f64)) -> bool {
        (a.0 - b.0).abs() < 1e-15 && (a.1 - b.1).abs() < 1e-15
    }

    #[test]
    fn projection_closed_forms() {
        let cone = FrictionCone::new(0.5).unwrap();
        // Inside: unchanged.
        assert_eq!(cone.project(1.0, 0.2), (1.0, 0.2));
        assert_eq!(cone.project(1.0, -0.5), (1.0, -0.5));
        assert_eq!(cone.distance(1.0, 0.5), 0.0);
        // In the polar cone λ_N + μ|λ_T| ≤ 0: the apex, at the point's own distance.
        assert_eq!(cone.project(-1.0, 0.1), (0.0, 0.0));
        assert_eq!(cone.project(-1.0, 2.0), (0.0, 0.0));
        assert!((cone.distance(-1.0, 2.0) - 5f64.sqrt()).abs() < 1e-15);
        // Beyond an edge: n = (1 + 0.5 · 2) / 1.25 = 1.6 on the edge λ_T = ±μ λ_N, and the
        // residual (−0.6, ±1.2) is normal to the edge.
        assert!(close(cone.project(1.0, 2.0), (1.6, 0.8)));
        assert!(close(cone.project(1.0, -2.0), (1.6, -0.8)));
        assert!((cone.distance(1.0, 2.0) - 1.8f64.sqrt()).abs() < 1e-15);
        // Above the apex with a small normal part: n = (−0.5 + 0.5 · 3) / 1.25 = 0.8.
        assert!(close(cone.project(-0.5, 3.0), (0.8, 0.4)));
        assert!(cone.contains(1.6, 0.8 + 1e-3, 1e-3) && !cone.contains(1.6, 0.81, 1e-3));
        // μ = 0: the half-line λ_T = 0 ≤ λ_N.
        let frictionless = FrictionCone::new(0.0).unwrap();
        assert_eq!(frictionless.project(2.0, 3.0), (2.0, 0.0));
        assert_eq!(frictionless.project(-2.0, 3.0), (0.0, 0.0));
        assert_eq!(frictionless.project(-2.0, 0.0), (0.0, 0.0));
        assert!((frictionless.distance(-2.0, 3.0) - 13f64.sqrt()).abs() < 1e-15);
        // NaN in, NaN out.
        let (n, t) = cone.project(f64::NAN, 1.0);
        assert!(n.is_nan() && t.is_nan());
        assert!(cone.project(1.0, f64::NAN).0.is_nan());
        assert!(!cone.contains(f64::NAN, 0.0, 1.0));
    }

    #[test]
    fn natural_map_vanishes_exactly_on_the_laws() {
        let cone = FrictionCone::new(0.5).unwrap();
        // Sliding forward at γ_T = 2 with λ_N = 4, λ_T = −μλ_N = −2, γ_N = 0.
        assert_eq!(cone.natural_map((4.0, -2.0), (0.0, 2.0), 1.0), Ok((0.0, 0.0)));
        // Sticking inside the cone, separating with no force.
        assert_eq!(cone.natural_map((4.0, 1.0), (0.0, 0.0), 0.3), Ok((0.0, 0.0)));
        assert_eq!(cone.natural_map((0.0, 0.0), (1.5, -7.0), 2.0), Ok((0.0, 0.0)));
        // A friction force below the bound while sliding: γ̂ = (0.5, 1), λ − r γ̂ = (3.5, −2.5)
        // lies beyond the lower edge, on which it projects to n (1, −μ) with
        // n = (3.5 + 1.25) / 1.25 = 3.8: the map is (4 − 3.8, −1.5 + 1.9) = (0.2, 0.4).
        let (f_n, f_t) = cone.natural_map((4.0, -1.5), (0.0, 1.0), 1.0).unwrap();
        assert!((f_n - 0.2).abs() < 1e-15 && (f_t - 0.4).abs() < 1e-15, "{f_n} {f_t}");
        // A pulling normal force.
        assert_ne!(cone.natural_map((-1.0, 0.0), (0.0, 0.0), 1.0), Ok((0.0, 0.0)));
        for r in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                cone.natural_map((1.0, 0.0), (0.0, 0.0), r),
                Err(SetValuedError::Step { .. })
            ));
        }
        assert_eq!(FrictionCone::new(-0.1), Err(SetValuedError::Friction { value: -0.1 }));
        assert!(matches!(FrictionCone::new(f64::NAN), Err(SetValuedError::Friction { .. })));
        assert_eq!(FrictionCone::new(0.25).unwrap().mu(), 0.25);
    }
}
