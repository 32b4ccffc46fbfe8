//! Moreau facade.
pub use moreau_setvalued as setvalued;
