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

impl ContactSpec {
    /// A contact named `name` between the first shapes of bodies `body_a` and `body_b`, with
    /// the laws `law` and the default margin; [`Self::with_shapes`] and [`Self::with_margin`]
    /// change the rest.
    ///
    /// ```
    /// use moreau_models::LawParams;
    /// use moreau_models::bodies::ContactSpec;
    ///
    /// let hit = ContactSpec::new("hit", "wall", "bob", LawParams::new(0.5, 0.0, 0.2))
    ///     .with_shapes(1, 0);
    /// assert_eq!((hit.shape_a, hit.shape_b, hit.eps_n, hit.mu, hit.margin), (1, 0, 0.5, 0.2, None));
    /// ```
    pub fn new(name: &str, body_a: &str, body_b: &str, law: LawParams) -> Self {
        Self {
            name: name.to_owned(),
            body_a: body_a.to_owned(),
            shape_a: 0,
            body_b: body_b.to_owned(),
            shape_b: 0,
            eps_n: law.eps_n,
            eps_t: law.eps_t,
            mu: law.mu,
            margin: None,
        }
    }

    /// The same contact between shape `shape_a` of body a and shape `shape_b` of body b.
    pub fn with_shapes(mut self, shape_a: usize, shape_b: usize) -> Self {
        (self.shape_a, self.shape_b) = (shape_a, shape_b);
        self
    }

    /// The same contact with the detection margin `margin` (m, > 0) of the fixed contact set.
    pub fn with_margin(mut self, margin: f64) -> Self {
        self.margin = Some(margin);
        self
    }
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
    /// Laws for particular pairs of bodies, each pair once. A pair that gets no automatic
    /// contact is refused: a body with itself, two bodies that do not move, a jointed pair,
    /// a pair the collision groups exclude, or one whose shapes explicit contacts all join.
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
///   the square of the number of bodies, which suits mechanisms, and the only mode that the
///   clearance joints support.
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
