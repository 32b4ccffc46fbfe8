//! The declared contacts, as plain data that reads and writes TOML: explicit contacts between
//! two shapes ([`ContactSpec`]), automatic contacts between every pair of shapes the collision
//! groups allow ([`AutoContacts`]), and how the contact set is kept ([`ContactSet`]).

use serde::{Deserialize, Serialize};

use crate::params::LawParams;

/// One explicit contact: shape `shape_a` of body a against shape `shape_b` of body b, with
/// its laws. It has `max_points` slots (one per feature pair), named `<name>` when there is
/// one and `<name>.<k>` otherwise, slot k holding the narrow phase's feature k: for a polygon
/// on a half-plane its vertex k (in declared order), for two polygons vertex k of a when
/// k < n_a and vertex k − n_a of b otherwise, for a disk the one closest pair (the full
/// numbering is in the [module's](super) documentation of contact sets).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Unique contact name.
    pub name: String,
    /// First body.
    pub body_a: String,
    /// Index of the shape on body a; default 0.
    #[serde(default)]
    pub shape_a: usize,
    /// Second body.
    pub body_b: String,
    /// Index of the shape on body b; default 0.
    #[serde(default)]
    pub shape_b: usize,
    /// Normal restitution ε_N in [0, 1].
    pub eps_n: f64,
    /// Tangential restitution ε_T in [0, 1].
    pub eps_t: f64,
    /// Friction coefficient μ >= 0.
    pub mu: f64,
    /// Detection margin of the fixed contact set (m, > 0): the features of the pair farther
    /// apart than this are not computed and report this gap. Default: 1 % of the smaller
    /// shape's bounding box diagonal at t = 0. The detected contact set uses the stepper's
    /// margin instead.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margin: Option<f64>,
}

/// The laws of the automatic contacts between one pair of bodies.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PairOverride {
    /// The two bodies (either order).
    pub bodies: [String; 2],
    /// Normal restitution ε_N.
    pub eps_n: f64,
    /// Tangential restitution ε_T.
    pub eps_t: f64,
    /// Friction coefficient μ.
    pub mu: f64,
}

/// Automatic contacts: every pair of shapes on different bodies that the collision groups
/// allow, not both on fixed or driven bodies, not between bodies connected by a joint, and
/// not already an explicit contact. Slot names are `<body>.<shape>-<body>.<shape>[.<k>]`,
/// the earlier-declared body first (it plays body a of [`ContactSpec`]) and k numbered as
/// there; the pairs follow the explicit contacts, in the order of body a, body b, shape a,
/// shape b.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AutoContacts {
    /// Default normal restitution ε_N.
    pub eps_n: f64,
    /// Default tangential restitution ε_T.
    pub eps_t: f64,
    /// Default friction coefficient μ.
    pub mu: f64,
    /// Detection margin of the fixed contact set (m, > 0), as [`ContactSpec::margin`];
    /// default 1 % of the smaller shape's bounding box diagonal at t = 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margin: Option<f64>,
    /// Laws for particular pairs of bodies.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub overrides: Vec<PairOverride>,
}

impl AutoContacts {
    /// Automatic contacts with one law for every pair.
    pub fn new(law: LawParams) -> Self {
        Self { eps_n: law.eps_n, eps_t: law.eps_t, mu: law.mu, margin: None, overrides: Vec::new() }
    }
}

/// How a declared mechanism keeps its contacts: the scene field `contact_set` (default
/// `"fixed"`) and [`super::MultibodyBuilder::with_contact_set`].
///
/// * `fixed`: a list of slots built once, one per pair of shapes that may touch and feature of
///   that pair (see [`ContactSpec`] and [`AutoContacts`]), each closed or open at each step.
///   Every slot has a name and a column in the records. The number of automatic slots grows as
///   the square of the number of bodies, which suits mechanisms, and the only mode that joints
///   support.
/// * `detected`: no slots; at each step a broad phase over all shapes and the narrow phase
///   find the contacts within the stepper's margin, the same pairs the fixed list would hold
///   (collision groups and masks, explicit contacts with their laws), each with an identity
///   built from its two shapes and its feature that persists while those features touch. The
///   mechanism then announces its body structure, so that the stepper works on 3 × 3 mass
///   blocks and per-body force directions: the mode for piles, columns and flows of many
///   bodies. Ideal joints work in this mode as in the other (their rows split by body, they
///   link bodies into islands as contacts do); a clearance joint needs the fixed list, and a
///   scene that asks otherwise is refused.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactSet {
    /// A fixed list of named slots, built once.
    #[default]
    Fixed,
    /// Contacts found at each step by a broad and a narrow phase.
    Detected,
}

impl ContactSet {
    /// Whether this is [`ContactSet::Fixed`] (the default, left out of written scene files).
    pub fn is_fixed(&self) -> bool {
        *self == ContactSet::Fixed
    }
}
