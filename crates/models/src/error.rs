//! The error type of this crate.

use std::path::PathBuf;

use moreau_setvalued::SetValuedError;
use moreau_stepper::StepError;

/// Everything that makes a model, a scene or a run refuse its input or stop.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ModelError {
    /// A model parameter is out of its admissible range (a non-positive mass, ε_N outside
    /// `[0, 1]`, a negative μ, a non-finite number, ...).
    #[error("invalid parameter `{field}` = {}: {reason}", number(*value))]
    InvalidParameter {
        /// Dotted name of the field inside the model's parameters (`m`, `beak.eps_n`, ...).
        field: String,
        /// The rejected value.
        value: f64,
        /// What the value must satisfy.
        reason: String,
    },
    /// A scene file that is not valid TOML or does not match the scene's fields.
    ///
    /// The message is the TOML reader's and names the offending key and line.
    #[error("invalid scene{}{}: {message}",
        path.as_ref().map(|p| format!(" file {}", p.display())).unwrap_or_default(),
        field.as_ref().map(|f| format!(" (field `{f}`)")).unwrap_or_default())]
    Parse {
        /// The file, when the scene was read from one.
        path: Option<PathBuf>,
        /// Dotted name of the offending field, when it could be located.
        field: Option<String>,
        /// The TOML reader's message.
        message: String,
    },
    /// A scene file that could not be read.
    #[error("cannot read scene file {}: {cause}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error, which the message includes (it is not also given as
        /// the error's source, so that a report of the chain says it once).
        cause: std::io::Error,
    },
    /// A `--set key=value` whose key names no entry of the scene, nor a field that a table of
    /// the scene leaves out: the level of the scene's tree where the key leaves it, the keys of
    /// that level and the key meant, when one is obvious.
    #[error("{}", unknown_key_text(key, level, name, valid, suggestion.as_deref()))]
    UnknownKey {
        /// The key as given.
        key: String,
        /// The level of the scene's tree where the key leaves it, as the key names it
        /// (`bodies.ball`, `init`; empty for the top).
        level: String,
        /// The key's part that the level does not have (`masss`), or a field that the level
        /// leaves out when the key goes on below it (`motion` in `bodies.ball.motion.kind`).
        name: String,
        /// The keys of that level: a table's fields, those it leaves out included, and any
        /// other keys it holds (a tag such as a joint's `type`); the names (or else indices)
        /// of an array's elements; on the top level of a report model, the scene's keys
        /// ([`Scene::keys`](crate::Scene::keys)) with the fields it leaves out.
        valid: Vec<String>,
        /// The whole key meant, when one key of the level alone lies within two edits of
        /// `name` (`bodies.ball.mass` for `bodies.ball.masss` or `bodies.bal.mass`).
        suggestion: Option<String>,
    },
    /// A `--set key=value` whose value does not parse or is out of range.
    #[error("bad value `{value}` for `{key}`: {reason}")]
    BadValue {
        /// The key.
        key: String,
        /// The rejected value as given.
        value: String,
        /// Why it was rejected.
        reason: String,
    },
    /// A scene that TOML cannot hold, such as an impulse's contact identity above
    /// 2⁶³ − 1, TOML's largest integer.
    #[error("the scene cannot be written as TOML: {message}")]
    Unwritable {
        /// The TOML writer's message.
        message: String,
    },
    /// The time-stepper refused the model or stopped the run.
    #[error(transparent)]
    Step(#[from] StepError),
    /// A contact law that `moreau_setvalued::ContactLaw` rejects.
    #[error(transparent)]
    Law(#[from] SetValuedError),
}

/// The explanation of an unknown `--set` key, as [`ModelError::UnknownKey`] gives it: `key`
/// leaves the scene's tree at `level` (empty for the top), whose part `name` is not among the
/// keys `valid` of that level (or is a field that the level leaves out, when the key goes on
/// below it), and `suggestion` is the key meant, if any.
pub fn unknown_key_text(
    key: &str,
    level: &str,
    name: &str,
    valid: &[String],
    suggestion: Option<&str>,
) -> String {
    let place = if level.is_empty() { "the scene".to_owned() } else { format!("`{level}`") };
    let whole = if level.is_empty() { name.to_owned() } else { format!("{level}.{name}") };
    if key != whole && valid.iter().any(|v| v == name) {
        return format!(
            "unknown key `{key}`: {place} leaves out `{name}`, whose parts cannot be set one by \
             one; set `{whole}` whole"
        );
    }
    let meant = suggestion.map(|s| format!(" (did you mean `{s}`?)")).unwrap_or_default();
    let keys = if valid.is_empty() {
        format!("{place} has no keys")
    } else {
        format!("the keys of {place} are {}", valid.join(", "))
    };
    if key == name {
        format!("unknown key `{key}`{meant}; {keys}")
    } else {
        format!("unknown key `{key}`: {place} has no key `{name}`{meant}; {keys}")
    }
}

/// A number as written in a message: plainly in the range people write so, in scientific
/// notation outside it (1e-300, not three hundred zeros).
fn number(value: f64) -> String {
    let size = value.abs();
    if size == 0.0 || !size.is_finite() || (1e-4..1e15).contains(&size) {
        value.to_string()
    } else {
        format!("{value:e}")
    }
}
