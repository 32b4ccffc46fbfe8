//! The contact law of one contact: Newton's impact law in the normal and tangential
//! directions and Coulomb's friction coefficient.

use serde::{Deserialize, Serialize};

use crate::{SetValuedError, checked_mu};

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
        checked_mu(mu)?;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn law_types_are_send_and_sync() {
        fn assert_send_sync<T: Send + Sync>() {}
        assert_send_sync::<ContactLaw>();
        assert_send_sync::<ContactLawSpec>();
        assert_send_sync::<SetValuedError>();
    }

    #[test]
    fn valid_laws_keep_their_parameters() {
        let law = ContactLaw::new(0.5, 0.1, 0.3).unwrap();
        assert_eq!((law.eps_n(), law.eps_t(), law.mu()), (0.5, 0.1, 0.3));
        assert!(law.is_frictional());
        let law = ContactLaw::frictionless(0.9).unwrap();
        assert_eq!((law.eps_n(), law.eps_t(), law.mu()), (0.9, 0.0, 0.0));
        assert!(!law.is_frictional());
        // The edges of the ranges are valid.
        assert!(ContactLaw::new(0.0, 1.0, 0.0).is_ok() && ContactLaw::new(1.0, 0.0, 1e6).is_ok());
    }

    #[test]
    fn invalid_parameters_are_rejected_with_context() {
        assert_eq!(
            ContactLaw::new(1.1, 0.0, 0.0),
            Err(SetValuedError::Restitution { name: "eps_n", value: 1.1 })
        );
        assert_eq!(
            ContactLaw::new(0.5, -0.1, 0.0),
            Err(SetValuedError::Restitution { name: "eps_t", value: -0.1 })
        );
        assert_eq!(ContactLaw::new(0.5, 0.0, -0.3), Err(SetValuedError::Friction { value: -0.3 }));
        assert_eq!(
            ContactLaw::frictionless(-1e-12),
            Err(SetValuedError::Restitution { name: "eps_n", value: -1e-12 })
        );
        assert!(matches!(
            ContactLaw::new(f64::NAN, 0.0, 0.0),
            Err(SetValuedError::Restitution { name: "eps_n", .. })
        ));
        assert!(matches!(
            ContactLaw::new(0.5, f64::NAN, 0.0),
            Err(SetValuedError::Restitution { name: "eps_t", .. })
        ));
        assert!(matches!(
            ContactLaw::new(0.5, 0.0, f64::NAN),
            Err(SetValuedError::Friction { .. })
        ));
        assert!(matches!(
            ContactLaw::new(0.5, 0.0, f64::INFINITY),
            Err(SetValuedError::Friction { .. })
        ));
        let message = ContactLaw::new(0.5, 0.0, -0.3).unwrap_err().to_string();
        assert!(message.contains("-0.3"), "{message}");
    }

    #[test]
    fn json_round_trip_and_validation_on_deserialisation() {
        let law = ContactLaw::new(0.4, 0.2, 0.01).unwrap();
        let json = serde_json::to_string(&law).unwrap();
        assert_eq!(json, r#"{"eps_n":0.4,"eps_t":0.2,"mu":0.01}"#);
        assert_eq!(serde_json::from_str::<ContactLaw>(&json).unwrap(), law);
        // eps_t and mu default to zero.
        let law: ContactLaw = serde_json::from_str(r#"{"eps_n":0.9}"#).unwrap();
        assert_eq!(law, ContactLaw::frictionless(0.9).unwrap());
        // Deserialisation runs the constructor's checks and rejects unknown fields.
        let err = serde_json::from_str::<ContactLaw>(r#"{"eps_n":1.5}"#).unwrap_err().to_string();
        assert!(err.contains("eps_n") && err.contains("1.5"), "{err}");
        assert!(serde_json::from_str::<ContactLaw>(r#"{"eps_n":0.5,"mu":-1}"#).is_err());
        assert!(serde_json::from_str::<ContactLaw>(r#"{"eps_n":0.5,"friction":0.3}"#).is_err());
        assert!(serde_json::from_str::<ContactLaw>(r#"{"mu":0.3}"#).is_err());
        let spec: ContactLawSpec = law.into();
        assert_eq!(ContactLaw::try_from(spec).unwrap(), law);
    }
}
