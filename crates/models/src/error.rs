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
    /// A `--set key=value` whose key the scene does not have.
    #[error("unknown key `{key}`; the scene's keys: {}{}", accepted.join(", "),
        if *declared {
            "; and the optional fields that a body, joint, contact or the scene leaves out \
             (such as `bodies.<name>.density`, `joints.<name>.angle`, `projection`)"
        } else {
            ""
        })]
    UnknownKey {
        /// The rejected key.
        key: String,
        /// The keys the scene writes ([`Scene::keys`](crate::Scene::keys)).
        accepted: Vec<String>,
        /// Whether the scene declares its mechanism, whose tables also take the optional
        /// fields they leave out.
        declared: bool,
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
    /// The time-stepper refused the model or stopped the run.
    #[error(transparent)]
    Step(#[from] StepError),
    /// A contact law that `moreau_setvalued::ContactLaw` rejects.
    #[error(transparent)]
    Law(#[from] SetValuedError),
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
