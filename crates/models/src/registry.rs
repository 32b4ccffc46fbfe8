//! The registry of models: [`ModelKind`], [`ModelParams`] and [`AnyModel`].

use std::fmt;
use std::str::FromStr;

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;
use moreau_stepper::{BilateralPoint, BodyStructure, Mechanism, SharedWork};
use serde::{Deserialize, Serialize};

use crate::bodies::{Multibody, SystemSpec};
use crate::draw::Drawing;
use crate::{
    Ball, BallParams, Cam, CamParams, ModelError, PainleveParams, PainleveRod, SliderCrank,
    SliderCrankIdeal, SliderCrankIdealParams, SliderCrankParams, Woodpecker, WoodpeckerParams,
};

/// The models of the report, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModelKind {
    /// The bouncing ball (7.1), `ball`.
    Ball,
    /// The woodpecker toy (7.2), `woodpecker`.
    Woodpecker,
    /// The slider-crank with a clearance joint (7.3), `slider-crank`.
    SliderCrank,
    /// The ideal slider-crank (7.3, ideal joint), `slider-crank-ideal`.
    SliderCrankIdeal,
    /// The cam with a flat-face follower (7.4), `cam`.
    Cam,
    /// Painlevé's rod (7.5), `painleve`.
    Painleve,
    /// A declared mechanism (bodies, joints, forces, contacts), `declared`; not one of
    /// [`ModelKind::ALL`], whose names are the report's models.
    Declared,
}

impl ModelKind {
    /// Every model, in the report's order.
    pub const ALL: [ModelKind; 6] = [
        ModelKind::Ball,
        ModelKind::Woodpecker,
        ModelKind::SliderCrank,
        ModelKind::SliderCrankIdeal,
        ModelKind::Cam,
        ModelKind::Painleve,
    ];

    /// The model's name, as accepted by [`FromStr`].
    pub fn name(self) -> &'static str {
        match self {
            ModelKind::Ball => "ball",
            ModelKind::Woodpecker => "woodpecker",
            ModelKind::SliderCrank => "slider-crank",
            ModelKind::SliderCrankIdeal => "slider-crank-ideal",
            ModelKind::Cam => "cam",
            ModelKind::Painleve => "painleve",
            ModelKind::Declared => "declared",
        }
    }

    /// Names of the coordinates q; empty for [`ModelKind::Declared`], whose names depend on
    /// the scene ([`AnyModel::coordinate_names`] has them).
    pub fn coordinate_names(self) -> &'static [&'static str] {
        match self {
            ModelKind::Ball => Ball::COORDINATES,
            ModelKind::Woodpecker => Woodpecker::COORDINATES,
            ModelKind::SliderCrank => SliderCrank::COORDINATES,
            ModelKind::SliderCrankIdeal => SliderCrankIdeal::COORDINATES,
            ModelKind::Cam => Cam::COORDINATES,
            ModelKind::Painleve => PainleveRod::COORDINATES,
            ModelKind::Declared => &[],
        }
    }

    /// Names of the velocities u; empty for [`ModelKind::Declared`].
    pub fn velocity_names(self) -> &'static [&'static str] {
        match self {
            ModelKind::Ball => Ball::VELOCITIES,
            ModelKind::Woodpecker => Woodpecker::VELOCITIES,
            ModelKind::SliderCrank => SliderCrank::VELOCITIES,
            ModelKind::SliderCrankIdeal => SliderCrankIdeal::VELOCITIES,
            ModelKind::Cam => Cam::VELOCITIES,
            ModelKind::Painleve => PainleveRod::VELOCITIES,
            ModelKind::Declared => &[],
        }
    }
}

impl fmt::Display for ModelKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ModelKind {
    type Err = ModelError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        ModelKind::ALL.into_iter().find(|k| k.name() == s).ok_or_else(|| ModelError::BadValue {
            key: "model".to_owned(),
            value: s.to_owned(),
            reason: format!(
                "unknown model; accepted: {}",
                ModelKind::ALL.map(ModelKind::name).join(", ")
            ),
        })
    }
}

/// The parameters of any model, tagged by the model's name in the field `model`; a declared
/// mechanism's declaration is not under `[params]` but at the top level of its scene file
/// (see [`crate::Scene`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ModelParams {
    /// Bouncing ball.
    Ball(BallParams),
    /// Woodpecker toy.
    Woodpecker(WoodpeckerParams),
    /// Slider-crank with a clearance joint.
    SliderCrank(SliderCrankParams),
    /// Ideal slider-crank.
    SliderCrankIdeal(SliderCrankIdealParams),
    /// Cam-follower.
    Cam(CamParams),
    /// Painlevé rod.
    Painleve(PainleveParams),
    /// A declared mechanism.
    #[serde(skip)]
    Declared(Box<SystemSpec>),
}

impl ModelParams {
    /// The report's parameters of a model; for [`ModelKind::Declared`], the example
    /// [`SystemSpec::example`].
    pub fn report(kind: ModelKind) -> Self {
        match kind {
            ModelKind::Ball => ModelParams::Ball(BallParams::report()),
            ModelKind::Woodpecker => ModelParams::Woodpecker(WoodpeckerParams::report()),
            ModelKind::SliderCrank => ModelParams::SliderCrank(SliderCrankParams::report()),
            ModelKind::SliderCrankIdeal => {
                ModelParams::SliderCrankIdeal(SliderCrankIdealParams::report())
            }
            ModelKind::Cam => ModelParams::Cam(CamParams::report()),
            ModelKind::Painleve => ModelParams::Painleve(PainleveParams::report()),
            ModelKind::Declared => ModelParams::Declared(Box::new(SystemSpec::example())),
        }
    }

    /// Which model these parameters are for.
    pub fn kind(&self) -> ModelKind {
        match self {
            ModelParams::Ball(_) => ModelKind::Ball,
            ModelParams::Woodpecker(_) => ModelKind::Woodpecker,
            ModelParams::SliderCrank(_) => ModelKind::SliderCrank,
            ModelParams::SliderCrankIdeal(_) => ModelKind::SliderCrankIdeal,
            ModelParams::Cam(_) => ModelKind::Cam,
            ModelParams::Painleve(_) => ModelKind::Painleve,
            ModelParams::Declared(_) => ModelKind::Declared,
        }
    }

    /// Validates the parameters and builds the model.
    ///
    /// # Errors
    /// The model's [`ModelError::InvalidParameter`] or [`ModelError::Law`].
    pub fn build(&self) -> Result<AnyModel, ModelError> {
        self.build_at(0.0)
    }

    /// [`Self::build`] for a run that starts at t₀ (s): a declared mechanism's initial state
    /// is then the state at t₀ ([`SystemSpec::build_at`]); a report model's does not depend
    /// on when it starts.
    ///
    /// # Errors
    /// As [`Self::build`].
    pub fn build_at(&self, t0: f64) -> Result<AnyModel, ModelError> {
        Ok(match self {
            ModelParams::Ball(p) => AnyModel::Ball(Ball::new(p.clone())?),
            ModelParams::Woodpecker(p) => AnyModel::Woodpecker(Woodpecker::new(p.clone())?),
            ModelParams::SliderCrank(p) => AnyModel::SliderCrank(SliderCrank::new(p.clone())?),
            ModelParams::SliderCrankIdeal(p) => {
                AnyModel::SliderCrankIdeal(SliderCrankIdeal::new(p.clone())?)
            }
            ModelParams::Cam(p) => AnyModel::Cam(Cam::new(p.clone())?),
            ModelParams::Painleve(p) => AnyModel::Painleve(PainleveRod::new(p.clone())?),
            ModelParams::Declared(spec) => AnyModel::Declared(spec.build_at(t0)?),
        })
    }
}

/// Any model of the report, as one [`Mechanism`] type (dispatching each call by `match`;
/// [`crate::Scene::run`] and [`crate::Scene::run_with`] instead step the model's own type,
/// the choice made once per run).
// One model is built per run, so the size of the largest variant costs nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug)]
pub enum AnyModel {
    /// Bouncing ball.
    Ball(Ball),
    /// Woodpecker toy.
    Woodpecker(Woodpecker),
    /// Slider-crank with a clearance joint.
    SliderCrank(SliderCrank),
    /// Ideal slider-crank.
    SliderCrankIdeal(SliderCrankIdeal),
    /// Cam-follower.
    Cam(Cam),
    /// Painlevé rod.
    Painleve(PainleveRod),
    /// A declared mechanism.
    Declared(Multibody),
}

macro_rules! dispatch {
    ($self:expr, $m:ident => $e:expr) => {
        match $self {
            AnyModel::Ball($m) => $e,
            AnyModel::Woodpecker($m) => $e,
            AnyModel::SliderCrank($m) => $e,
            AnyModel::SliderCrankIdeal($m) => $e,
            AnyModel::Cam($m) => $e,
            AnyModel::Painleve($m) => $e,
            AnyModel::Declared($m) => $e,
        }
    };
}
pub(crate) use dispatch;

impl AnyModel {
    /// Which model this is.
    pub fn kind(&self) -> ModelKind {
        match self {
            AnyModel::Ball(_) => ModelKind::Ball,
            AnyModel::Woodpecker(_) => ModelKind::Woodpecker,
            AnyModel::SliderCrank(_) => ModelKind::SliderCrank,
            AnyModel::SliderCrankIdeal(_) => ModelKind::SliderCrankIdeal,
            AnyModel::Cam(_) => ModelKind::Cam,
            AnyModel::Painleve(_) => ModelKind::Painleve,
            AnyModel::Declared(_) => ModelKind::Declared,
        }
    }

    /// Names of the coordinates q (as in docs/theory.md; `<body>.x`, `<body>.y`,
    /// `<body>.theta` for a declared mechanism).
    pub fn coordinate_names(&self) -> Names<'_> {
        match self {
            AnyModel::Declared(m) => Names::Owned(m.coordinate_names()),
            _ => Names::Static(self.kind().coordinate_names()),
        }
    }

    /// Names of the velocities u (as in docs/theory.md; `<body>.vx`, `<body>.vy`,
    /// `<body>.omega` for a declared mechanism).
    pub fn velocity_names(&self) -> Names<'_> {
        match self {
            AnyModel::Declared(m) => Names::Owned(m.velocity_names()),
            _ => Names::Static(self.kind().velocity_names()),
        }
    }

    /// Names of the listed contacts (switched-off contacts are not listed).
    pub fn contact_names(&self) -> Vec<String> {
        dispatch!(self, m => m.contact_names())
    }

    /// The initial state (q0, u0) of the parameters.
    pub fn initial_state(&self) -> (Vec<f64>, Vec<f64>) {
        dispatch!(self, m => m.initial_state())
    }

    /// A drawing of the mechanism at (q, t), in metres.
    pub fn draw(&self, q: &[f64], t: f64) -> Drawing {
        dispatch!(self, m => m.draw(q, t))
    }

    /// Where each listed contact's point is at (q, t) (m), for highlighting active contacts.
    pub fn contact_points(&self, q: &[f64], t: f64) -> Vec<[f64; 2]> {
        match self {
            AnyModel::SliderCrankIdeal(_) => Vec::new(),
            AnyModel::Ball(m) => m.contact_points(q, t),
            AnyModel::Woodpecker(m) => m.contact_points(q, t),
            AnyModel::SliderCrank(m) => m.contact_points(q, t),
            AnyModel::Cam(m) => m.contact_points(q, t),
            AnyModel::Painleve(m) => m.contact_points(q, t),
            AnyModel::Declared(m) => m.contact_points(q, t),
        }
    }

    /// The parameters the model was built from.
    pub fn params(&self) -> ModelParams {
        match self {
            AnyModel::Ball(m) => ModelParams::Ball(m.params().clone()),
            AnyModel::Woodpecker(m) => ModelParams::Woodpecker(m.params().clone()),
            AnyModel::SliderCrank(m) => ModelParams::SliderCrank(m.params().clone()),
            AnyModel::SliderCrankIdeal(m) => ModelParams::SliderCrankIdeal(m.params().clone()),
            AnyModel::Cam(m) => ModelParams::Cam(m.params().clone()),
            AnyModel::Painleve(m) => ModelParams::Painleve(m.params().clone()),
            AnyModel::Declared(m) => ModelParams::Declared(Box::new(m.spec().clone())),
        }
    }
}

impl ContactKinematics for AnyModel {
    #[inline]
    fn num_coordinates(&self) -> usize {
        dispatch!(self, m => m.num_coordinates())
    }
    #[inline]
    fn num_contacts(&self) -> usize {
        dispatch!(self, m => m.num_contacts())
    }
    #[inline]
    fn normal_gap(&self, i: usize, q: &[f64], t: f64) -> f64 {
        dispatch!(self, m => m.normal_gap(i, q, t))
    }
    #[inline]
    fn normal_gaps(&self, q: &[f64], t: f64, g: &mut [f64]) {
        dispatch!(self, m => m.normal_gaps(q, t, g))
    }
    #[inline(always)]
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> ContactPoint {
        dispatch!(self, m => m.contact(i, q, t, w_n, w_t))
    }
    #[inline]
    fn contacts(
        &self,
        which: &[usize],
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
        points: &mut [ContactPoint],
    ) {
        dispatch!(self, m => m.contacts(which, q, t, w_n, w_t, points))
    }
}

impl Mechanism for AnyModel {
    #[inline]
    fn laws(&self) -> &[ContactLaw] {
        dispatch!(self, m => m.laws())
    }
    #[inline]
    fn mass_matrix(&self, q: &[f64], t: f64, mass: &mut [f64]) {
        dispatch!(self, m => m.mass_matrix(q, t, mass))
    }
    #[inline]
    fn forces(&self, q: &[f64], u: &[f64], t: f64, h: &mut [f64]) {
        dispatch!(self, m => m.forces(q, u, t, h))
    }
    #[inline]
    fn potential_energy(&self, q: &[f64], t: f64) -> Option<f64> {
        dispatch!(self, m => m.potential_energy(q, t))
    }
    #[inline]
    fn damping_forces(&self, q: &[f64], u: &[f64], t: f64, h_d: &mut [f64]) -> bool {
        dispatch!(self, m => m.damping_forces(q, u, t, h_d))
    }
    #[inline]
    fn constant_mass_matrix(&self) -> bool {
        dispatch!(self, m => m.constant_mass_matrix())
    }
    #[inline]
    fn shared_work(&self) -> Option<&dyn SharedWork> {
        dispatch!(self, m => m.shared_work())
    }
    fn body_structure(&self) -> Option<&dyn BodyStructure> {
        dispatch!(self, m => m.body_structure())
    }
    #[inline]
    fn maximal_coordinates(&self) -> bool {
        dispatch!(self, m => m.maximal_coordinates())
    }
    #[inline]
    fn num_bilaterals(&self) -> usize {
        dispatch!(self, m => m.num_bilaterals())
    }
    #[inline]
    fn bilateral(&self, i: usize, q: &[f64], t: f64, w: &mut [f64]) -> BilateralPoint {
        dispatch!(self, m => m.bilateral(i, q, t, w))
    }

    fn bilaterals(&self, q: &[f64], t: f64, w: &mut [f64], points: &mut [BilateralPoint]) {
        dispatch!(self, m => m.bilaterals(q, t, w, points))
    }
}

/// Names of a model's coordinates or velocities, borrowed without allocating: the report's
/// models have static names, a declared mechanism owns its own.
#[derive(Clone, Copy, Debug)]
pub enum Names<'a> {
    /// A report model's names.
    Static(&'static [&'static str]),
    /// A declared mechanism's names.
    Owned(&'a [String]),
}

impl<'a> Names<'a> {
    /// The number of names.
    pub fn len(&self) -> usize {
        match self {
            Names::Static(s) => s.len(),
            Names::Owned(s) => s.len(),
        }
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Name `i`.
    pub fn get(&self, i: usize) -> Option<&'a str> {
        match self {
            Names::Static(s) => s.get(i).copied(),
            Names::Owned(s) => s.get(i).map(String::as_str),
        }
    }

    /// The names in order.
    pub fn iter(&self) -> impl Iterator<Item = &'a str> + 'a {
        let this = *self;
        (0..this.len()).filter_map(move |i| this.get(i))
    }

    /// The index of a name.
    pub fn position(&self, name: &str) -> Option<usize> {
        self.iter().position(|n| n == name)
    }

    /// The names as owned strings.
    pub fn to_vec(&self) -> Vec<String> {
        self.iter().map(str::to_owned).collect()
    }
}
