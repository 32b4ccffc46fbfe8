//! The contact law of one contact: Newton's impact law in the normal and tangential
//! directions and Coulomb's friction coefficient.

use serde::{Deserialize, Serialize};

use crate::SetValuedError;

/// The parameters of one contact's laws: restitution ε_N, ε_T ∈ [0, 1] and friction μ ≥ 0.
///
/// The fields are validated at construction: ε outside `[0, 1]`, a negative or non-finite μ
/// is rejected with a [`SetValuedError`]. Deserialisation goes through the same checks.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "ContactLawSpec", into = "ContactLawSpec")]
pub struct ContactLaw {
    eps_n: f64,
    eps_t: f64,
    mu: f64,
}

/// The unvalidated, serialisable form of a [`ContactLaw`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactLawSpec {
    /// Normal restitution coefficient ε_N (dimensionless, in `[0, 1]`).
    pub eps_n: f64,
    /// Tangential restitution coefficient ε_T (dimensionless, in `[0, 1]`).
    #[serde(default)]
    pub eps_t: f64,
    /// Coulomb friction coefficient μ (dimensionless, `>= 0`).
    #[serde(default)]
    pub mu: f64,
}

impl ContactLaw {
    /// A contact with restitutions ε_N, ε_T and friction coefficient μ.
    ///
    /// # Errors
    /// [`SetValuedError::Restitution`] when ε_N or ε_T is outside `[0, 1]` or not finite,
    /// [`SetValuedError::Friction`] when μ is negative or not finite.
    pub fn new(eps_n: f64, eps_t: f64, mu: f64) -> Result<Self, SetValuedError> {
        for (name, value) in [("eps_n", eps_n), ("eps_t", eps_t)] {
            if !(0.0..=1.0).contains(&value) {
                return Err(SetValuedError::Restitution { name, value });
            }
        }
        if !(mu >= 0.0 && mu.is_finite()) {
            return Err(SetValuedError::Friction { value: mu });
        }
        Ok(Self { eps_n, eps_t, mu })
    }

    /// A frictionless contact (μ = 0, ε_T = 0) with normal restitution ε_N.
    ///
    /// # Errors
    /// [`SetValuedError::Restitution`] when ε_N is outside `[0, 1]`.
    pub fn frictionless(eps_n: f64) -> Result<Self, SetValuedError> {
        Self::new(eps_n, 0.0, 0.0)
    }

    /// Normal restitution coefficient ε_N.
    pub fn eps_n(&self) -> f64 {
        self.eps_n
    }

    /// Tangential restitution coefficient ε_T.
    pub fn eps_t(&self) -> f64 {
        self.eps_t
    }

    /// Coulomb friction coefficient μ.
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// Whether the contact has friction (μ > 0) and so needs tangential rows in the LCP.
    pub fn is_frictional(&self) -> bool {
        self.mu > 0.0
    }
}

impl TryFrom<ContactLawSpec> for ContactLaw {
    type Error = SetValuedError;
    fn try_from(spec: ContactLawSpec) -> Result<Self, Self::Error> {
        Self::new(spec.eps_n, spec.eps_t, spec.mu)
    }
}

impl From<ContactLaw> for ContactLawSpec {
    fn from(law: ContactLaw) -> Self {
        Self { eps_n: law.eps_n, eps_t: law.eps_t, mu: law.mu }
    }
}
