//! The error type of this crate.

use crate::check::Component;

/// Errors of the contact kinematics helpers and of the finite-difference checker.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum KinematicsError {
    /// A vector or slice has the wrong length, e.g. a sample `q` whose length is not `f`.
    #[error("dimension mismatch in {what}: expected {expected}, found {found}")]
    DimensionMismatch {
        /// Which quantity has the wrong length.
        what: &'static str,
        /// The length required.
        expected: usize,
        /// The length given.
        found: usize,
    },
    /// An index past the end of what it indexes, e.g. a coordinate j >= f.
    #[error("{what} {index} is out of range: there are {len}, numbered from 0")]
    IndexOutOfRange {
        /// What the index counts.
        what: &'static str,
        /// The index given.
        index: usize,
        /// How many there are.
        len: usize,
    },
    /// A NaN or infinite value in an input or in a value returned by the kinematics.
    #[error("non-finite {what}{}", non_finite_where(what, *contact, *sample))]
    NonFinite {
        /// Which quantity is not finite (`q`, `t`, `g_N`, `w_T`, ...).
        what: &'static str,
        /// The contact concerned, if any.
        contact: Option<usize>,
        /// The index of the sample state concerned, if any.
        sample: Option<usize>,
    },
    /// A force direction w_N, w_T or rheonomic term ŵ_N, ŵ_T that disagrees with the
    /// finite-difference derivative of g_N, g_T, or a `normal_gap` that disagrees with the
    /// g_N of `contact`.
    #[error(
        "contact {contact}: {component} disagrees with its finite-difference reference at \
         sample {sample} (abs {abs:.3e}, rel {rel:.3e})"
    )]
    JacobianMismatch {
        /// The contact index i.
        contact: usize,
        /// Which entry disagrees.
        component: Component,
        /// The index of the sample state at which the worst disagreement was found.
        sample: usize,
        /// Absolute difference |analytic − reference|.
        abs: f64,
        /// Relative difference |analytic − reference| / max(|analytic|, |reference|).
        rel: f64,
    },
    /// An option outside its valid range (a non-positive step, a negative radius, ...).
    #[error("invalid option {name} = {value}")]
    InvalidOption {
        /// The option's name.
        name: &'static str,
        /// The rejected value.
        value: f64,
    },
    /// A geometric input that defines no contact: a negative radius, two coincident circle
    /// centres, ...
    #[error("invalid geometry: {what} = {value}")]
    InvalidGeometry {
        /// What is wrong.
        what: &'static str,
        /// The offending value.
        value: f64,
    },
    /// The finite-difference checker was given no sample state, so it could check nothing.
    #[error("no sample states to check")]
    NoSamples,
    /// A shape that fails [`crate::Shape::validate`]: a non-finite coordinate, a negative
    /// radius, a polygon that is not convex and counter-clockwise, too few points, ...
    #[error("invalid {shape}: {problem}{}{}", the_value(*.value), at_index(*.index))]
    InvalidShape {
        /// The shape's name (`disk`, `polygon`, `capsule`, `half_plane`, `polyline`, `profile`).
        shape: &'static str,
        /// What is wrong, e.g. "negative radius".
        problem: &'static str,
        /// The number at fault, if one is: the radius, the non-finite coordinate, the length
        /// |n| of a half-plane's normal.
        value: Option<f64>,
        /// The vertex, point or edge concerned, if one is.
        index: Option<usize>,
    },
    /// A pair of shapes for which [`crate::collide`] has no contact method, such as two
    /// half-planes or two polylines.
    #[error("no contact method for the pair ({a}, {b})")]
    UnsupportedPair {
        /// The name of shape A.
        a: &'static str,
        /// The name of shape B.
        b: &'static str,
    },
    /// A pair of shapes neither of which has an inside or a thickness: a point (a disk of
    /// radius 0), a segment (a capsule of radius 0) or a polyline against another of these.
    /// Their distance never changes sign, so a crossing between two steps is not seen and one
    /// would pass through the other.
    #[error(
        "no contact method for the pair ({a}, {b}): neither has an inside or a thickness, so \
         their distance has no sign and one would pass through the other between two steps; \
         give one of them a radius or an area"
    )]
    NoThickness {
        /// The name of shape A.
        a: &'static str,
        /// The name of shape B.
        b: &'static str,
    },
    /// A mass property asked of a shape that has none: a half-plane (infinite) or a polyline
    /// (no area).
    #[error("a {shape} has no {what}")]
    NoMassProperties {
        /// The shape's name.
        shape: &'static str,
        /// The property asked for (`unit inertia`, ...).
        what: &'static str,
    },
}

/// The ": value" part of a shape error, or nothing.
fn the_value(value: Option<f64>) -> String {
    value.map(|v| format!(": {v}")).unwrap_or_default()
}

/// The " at index i" suffix of a shape error, or nothing.
fn at_index(index: Option<usize>) -> String {
    index.map(|i| format!(" (at index {i})")).unwrap_or_default()
}

/// Where a [`KinematicsError::NonFinite`] value was found, and for a force direction what is
/// most likely wrong.
fn non_finite_where(what: &str, contact: Option<usize>, sample: Option<usize>) -> String {
    let at: Vec<String> = [("contact", contact), ("sample state", sample)]
        .into_iter()
        .filter_map(|(name, i)| i.map(|i| format!("{name} {i}")))
        .collect();
    let mut text = if at.is_empty() { String::new() } else { format!(" at {}", at.join(", ")) };
    if matches!(what, "w_N" | "w_T") {
        text.push_str(
            ": an entry left unwritten (the checks hand the directions over filled with NaN, \
             and `contact` must write every entry) or a value computed as NaN or infinite",
        );
    }
    text
}
