//! Generated bodies: a `[[fill]]` table of a scene file expands into many dynamic bodies of one
//! template shape, placed on a pattern, with sizes drawn from a seeded generator, so that a
//! pile of ten thousand grains is one table whose `count` a `--set` changes.

use moreau_kinematics::{Shape, SplitMix64};
use serde::{Deserialize, Serialize};

use super::build::bad;
use super::shape_check::check_shape;
use super::spec::BodySpec;
use crate::ModelError;
use crate::params::{finite, non_negative, positive, relation};

/// Where a [`FillSpec`] puts its bodies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FillPattern {
    /// Rows of `columns` bodies from `origin`: body k at
    /// origin + ((k mod columns) s_x, ⌊k / columns⌋ s_y), `count` bodies in all.
    Lattice,
    /// Box2D's pyramid: a base row of `base` bodies and each row above one shorter, centred
    /// on the row below; row i (from 0 at the bottom) holds bodies j = 0 .. base − i at
    /// origin + ((i/2 + j) s_x, i s_y), base (base + 1)/2 bodies in all.
    Pyramid,
}

/// The most bodies the fills of one mechanism may make together: 10⁷. A generated body
/// takes about a kilobyte between its declaration, the mechanism's body and the stepper's
/// state and contacts, so that 10⁷ of them already need some 10 GB, beyond a workstation's
/// memory, while the largest scene of the repository has 10⁴ (`scenes/scale`). A larger
/// fill is refused naming its field rather than aborting on a failed allocation.
pub const MAX_FILL_BODIES: usize = 10_000_000;

fn one_to_one() -> [f64; 2] {
    [1.0, 1.0]
}

fn default_group() -> u32 {
    1
}

fn default_mask() -> u32 {
    u32::MAX
}

/// A block of generated dynamic bodies (the scene table `[[fill]]`), expanded when the
/// mechanism is built: bodies `<name>0`, `<name>1`, ... follow the declared `[[bodies]]` in
/// q, in the pattern's order.
///
/// Each body is the template `shape` scaled by a factor drawn uniformly in `scale` (a disk of
/// radius r gets a radius in [scale₀ r, scale₁ r]), with mass and inertia from `density`, at
/// its pattern place moved by an offset drawn uniformly in [−jitter, jitter] along each axis.
/// The draws come from a SplitMix64 generator seeded with `seed`, in body order (the scale
/// unless its range is one value, then the offsets x and y), so that a scene file gives the
/// same bodies on every machine. The
/// spacing must leave room for the largest body and its jitter: generated bodies never
/// overlap at t = 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FillSpec {
    /// The bodies' name prefix (unique among fills, and no body may be called `<name><k>`).
    pub name: String,
    /// The placement: `lattice` or `pyramid`.
    pub pattern: FillPattern,
    /// Number of bodies, for `lattice` (>= 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub count: Option<usize>,
    /// Bodies per row, for `lattice` (>= 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub columns: Option<usize>,
    /// Bodies in the base row, for `pyramid` (>= 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<usize>,
    /// The place of the first body's origin `[x, y]` (m).
    pub origin: [f64; 2],
    /// The distances `[s_x, s_y]` between neighbouring places along a row and between rows
    /// (m, > 0).
    pub spacing: [f64; 2],
    /// Largest random offset of a body from its place along each axis (m, >= 0); default 0.
    #[serde(default)]
    pub jitter: f64,
    /// The template shape, in the body frame (m): a disk, polygon or capsule, best centred on
    /// the origin so that the origin is the centre of mass.
    pub shape: Shape,
    /// The range `[lo, hi]` of the scale factor (0 < lo <= hi); default `[1, 1]`.
    #[serde(default = "one_to_one")]
    pub scale: [f64; 2],
    /// Density ρ (kg/m², > 0): each body's mass and inertia follow from its scaled shape.
    pub density: f64,
    /// Initial velocity of every body `[ẋ, ẏ]` (m/s); default 0.
    #[serde(default)]
    pub velocity: [f64; 2],
    /// Seed of the generator; default 1.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Collision group bits of every body (see [`BodySpec::group`]); default 1.
    #[serde(default = "default_group")]
    pub group: u32,
    /// Collision mask bits of every body (see [`BodySpec::mask`]); default all.
    #[serde(default = "default_mask")]
    pub mask: u32,
}

fn default_seed() -> u64 {
    1
}

impl FillSpec {
    /// A lattice of `count` bodies in rows of `columns`, no jitter, scale 1, seed 1.
    pub fn lattice(
        name: &str,
        count: usize,
        columns: usize,
        origin: [f64; 2],
        spacing: [f64; 2],
        shape: Shape,
        density: f64,
    ) -> Self {
        Self {
            name: name.to_owned(),
            pattern: FillPattern::Lattice,
            count: Some(count),
            columns: Some(columns),
            base: None,
            origin,
            spacing,
            jitter: 0.0,
            shape,
            scale: one_to_one(),
            density,
            velocity: [0.0; 2],
            seed: default_seed(),
            group: default_group(),
            mask: default_mask(),
        }
    }

    /// The number of bodies the fill makes (0 when its size field is missing; `usize::MAX`
    /// when a pyramid's base (base + 1)/2 does not fit a `usize`).
    pub fn len(&self) -> usize {
        match self.pattern {
            FillPattern::Lattice => self.count.unwrap_or(0),
            FillPattern::Pyramid => self.base.map_or(0, |b| {
                // b (b + 1)/2 without overflow: the even factor halved first.
                let (half, other) =
                    if b % 2 == 0 { (b / 2, b.checked_add(1)) } else { (b / 2 + 1, Some(b)) };
                other.and_then(|o| half.checked_mul(o)).unwrap_or(usize::MAX)
            }),
        }
    }

    /// Whether the fill makes no body.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The places of the bodies before jitter, in body order.
    fn places(&self) -> Vec<[f64; 2]> {
        let [sx, sy] = self.spacing;
        let at = |i: f64, j: f64| [self.origin[0] + i * sx, self.origin[1] + j * sy];
        match self.pattern {
            FillPattern::Lattice => {
                let columns = self.columns.unwrap_or(1).max(1);
                (0..self.len()).map(|k| at((k % columns) as f64, (k / columns) as f64)).collect()
            }
            FillPattern::Pyramid => {
                let base = self.base.unwrap_or(0);
                (0..base)
                    .flat_map(|i| (0..base - i).map(move |j| (i, j)))
                    .map(|(i, j)| at(0.5 * i as f64 + j as f64, i as f64))
                    .collect()
            }
        }
    }

    /// Validates the fill (`index` is its place among the fills, for the field names) and
    /// returns its bodies.
    ///
    /// # Errors
    /// [`ModelError::InvalidParameter`] or [`ModelError::BadValue`] naming the field as
    /// `fill.<name>.<field>`; a fill of more than [`MAX_FILL_BODIES`] bodies is refused so,
    /// naming its `count` or `base`, before any body is made.
    pub fn bodies(&self) -> Result<Vec<BodySpec>, ModelError> {
        let field = |f: &str| format!("fill.{}.{f}", self.name);
        let missing = |f: &str, given: Option<usize>, pattern: &str| {
            let value = given.map_or_else(|| "(missing)".to_owned(), |v| v.to_string());
            bad(field(f), &value, format!("a `{pattern}` fill needs `{f}` >= 1"))
        };
        let refuse = |f: &str, present: bool, pattern: &str| {
            if present {
                Err(bad(field(f), "(given)", format!("a `{pattern}` fill has no `{f}`")))
            } else {
                Ok(())
            }
        };
        match self.pattern {
            FillPattern::Lattice => {
                for f in ["count", "columns"] {
                    let v = if f == "count" { self.count } else { self.columns };
                    if v.unwrap_or(0) == 0 {
                        return Err(missing(f, v, "lattice"));
                    }
                }
                refuse("base", self.base.is_some(), "lattice")?;
            }
            FillPattern::Pyramid => {
                if self.base.unwrap_or(0) == 0 {
                    return Err(missing("base", self.base, "pyramid"));
                }
                refuse("count", self.count.is_some(), "pyramid")?;
                refuse("columns", self.columns.is_some(), "pyramid")?;
            }
        }
        let n = self.len();
        if n > MAX_FILL_BODIES {
            let (f, given) = match self.pattern {
                FillPattern::Lattice => ("count", self.count),
                FillPattern::Pyramid => ("base", self.base),
            };
            return Err(bad(
                field(f),
                &given.unwrap_or(0).to_string(),
                format!(
                    "the fill would make {} bodies, more than the {MAX_FILL_BODIES} a mechanism's \
                     fills may make",
                    if n == usize::MAX { "more than usize::MAX".to_owned() } else { n.to_string() }
                ),
            ));
        }
        for k in 0..2 {
            finite(&format!("{}.{k}", field("origin")), self.origin[k])?;
            positive(&format!("{}.{k}", field("spacing")), self.spacing[k])?;
            finite(&format!("{}.{k}", field("velocity")), self.velocity[k])?;
        }
        non_negative(&field("jitter"), self.jitter)?;
        positive(&field("density"), self.density)?;
        positive(&format!("{}.0", field("scale")), self.scale[0])?;
        finite(&format!("{}.1", field("scale")), self.scale[1])?;
        if self.scale[1] < self.scale[0] {
            return Err(relation(
                &format!("{}.1", field("scale")),
                self.scale[1],
                "must be >= scale.0",
            ));
        }
        check_shape(&field("shape"), &self.shape)?;
        let area = self.shape.area();
        if !(area.is_finite() && area > 0.0) {
            return Err(bad(
                field("shape"),
                self.shape.name(),
                "a generated body needs a shape with an area (disk, polygon or capsule)".to_owned(),
            ));
        }
        // The largest body with the largest offsets must fit its place.
        let b = self.shape.scaled(self.scale[1]).aabb(&Default::default());
        for (k, axis) in ["x", "y"].iter().enumerate() {
            let reach = (b.max[k] - b.min[k]) + 2.0 * self.jitter;
            if reach > self.spacing[k] {
                return Err(relation(
                    &format!("{}.{k}", field("spacing")),
                    self.spacing[k],
                    &format!(
                        "neighbouring bodies would overlap: the largest body spans {reach} m along \
                         {axis} with its jitter"
                    ),
                ));
            }
        }
        let mut rng = SplitMix64::new(self.seed);
        let bodies = self
            .places()
            .into_iter()
            .enumerate()
            .map(|(k, place)| {
                let s = if self.scale[1] > self.scale[0] {
                    rng.uniform(self.scale[0], self.scale[1])
                } else {
                    self.scale[0]
                };
                let dx = rng.uniform(-self.jitter, self.jitter);
                let dy = rng.uniform(-self.jitter, self.jitter);
                let mut body = BodySpec::with_density(
                    &format!("{}{k}", self.name),
                    self.density,
                    [place[0] + dx, place[1] + dy],
                    0.0,
                )
                .with_shape(self.shape.scaled(s))
                .with_velocity(self.velocity, 0.0);
                body.group = self.group;
                body.mask = self.mask;
                body
            })
            .collect();
        Ok(bodies)
    }
}
