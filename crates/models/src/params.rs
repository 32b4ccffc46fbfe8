//! Shared parameter pieces: contact laws and the checks every model runs at construction.

use moreau_setvalued::ContactLaw;
use serde::{Deserialize, Serialize};

use crate::ModelError;

/// The laws of one frictional contact: restitutions ε_N, ε_T and friction coefficient μ.
///
/// All three are required in a scene file (no silent defaults for physical data).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LawParams {
    /// Normal restitution coefficient ε_N (dimensionless, in `[0, 1]`).
    pub eps_n: f64,
    /// Tangential restitution coefficient ε_T (dimensionless, in `[0, 1]`).
    pub eps_t: f64,
    /// Coulomb friction coefficient μ (dimensionless, `>= 0`); μ = 0 makes the contact
    /// frictionless, and the stepper then gives it only its normal row.
    pub mu: f64,
}

impl LawParams {
    /// Laws with the given ε_N, ε_T and μ.
    pub fn new(eps_n: f64, eps_t: f64, mu: f64) -> Self {
        Self { eps_n, eps_t, mu }
    }

    /// Validates the fields (named `prefix.eps_n`, ...) and builds the [`ContactLaw`].
    pub(crate) fn law(&self, prefix: &str) -> Result<ContactLaw, ModelError> {
        let name = |f: &str| if prefix.is_empty() { f.to_owned() } else { format!("{prefix}.{f}") };
        unit_interval(&name("eps_n"), self.eps_n)?;
        unit_interval(&name("eps_t"), self.eps_t)?;
        non_negative(&name("mu"), self.mu)?;
        Ok(ContactLaw::new(self.eps_n, self.eps_t, self.mu)?)
    }
}

fn invalid(field: &str, value: f64, reason: &str) -> ModelError {
    ModelError::InvalidParameter { field: field.to_owned(), value, reason: reason.to_owned() }
}

/// Requires a finite value.
pub(crate) fn finite(field: &str, value: f64) -> Result<(), ModelError> {
    if value.is_finite() { Ok(()) } else { Err(invalid(field, value, "must be finite")) }
}

/// Requires a finite value `> 0`.
pub(crate) fn positive(field: &str, value: f64) -> Result<(), ModelError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(invalid(field, value, "must be finite and > 0"))
    }
}

/// Requires a finite value `>= 0`.
pub(crate) fn non_negative(field: &str, value: f64) -> Result<(), ModelError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(invalid(field, value, "must be finite and >= 0"))
    }
}

/// Requires a value in `[0, 1]`.
pub(crate) fn unit_interval(field: &str, value: f64) -> Result<(), ModelError> {
    if (0.0..=1.0).contains(&value) {
        Ok(())
    } else {
        Err(invalid(field, value, "must lie in [0, 1]"))
    }
}

/// Requires every value of a list to be finite.
pub(crate) fn all_finite(fields: &[(&str, f64)]) -> Result<(), ModelError> {
    fields.iter().try_for_each(|&(f, v)| finite(f, v))
}

/// Builds an [`ModelError::InvalidParameter`] for a relation between parameters.
pub(crate) fn relation(field: &str, value: f64, reason: &str) -> ModelError {
    invalid(field, value, reason)
}
