//! Builder-style setters of the solvers' options.

/// Implements `with_<field>(value) -> Self` on an options struct for each listed field.
///
/// The options structs are `#[non_exhaustive]`, so that fields can be added without breaking
/// callers; outside this crate they are built from their `Default` and these setters (or by
/// assigning the public fields of a default value), never by a struct literal.
macro_rules! with_setters {
    ($options:ident { $($setter:ident => $field:ident: $ty:ty),* $(,)? }) => {
        impl $options {
            $(
                #[doc = concat!(
                    "These options with [`", stringify!($field), "`](", stringify!($options),
                    "::", stringify!($field), ") set to `value` (checked when a solver is built)."
                )]
                #[must_use]
                pub fn $setter(mut self, value: $ty) -> Self {
                    self.$field = value;
                    self
                }
            )*
        }
    };
}
