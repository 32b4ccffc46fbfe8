//! Set-valued force laws of non-smooth mechanics.
#![deny(missing_docs)]

mod law;

pub use law::{ContactLaw, ContactLawSpec};

/// Errors of this crate: invalid law parameters.
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
}
