//! The mechanisms of the reference report as Moreau mechanisms, with their parameter tables,
//! drawings, and scene files that run them.
//!
//! # What this crate is for
//! Each model of docs/theory.md section 7 implements `moreau_stepper::Mechanism`: its mass
//! matrix M(q, t), smooth forces h(q, u, t), potential energy, and through
//! `moreau_kinematics::ContactKinematics` its gaps g_N, force directions w_N, w_T and
//! rheonomic terms ŵ_N. Every model has a parameter struct that reads and writes TOML
//! (`deny_unknown_fields`, no silent defaults for physical data) with a named constructor for
//! the report's table, is validated once by its `new`, and can draw itself
//! ([`Drawing`], in metres). A [`Scene`] bundles parameters, Δt, the stop rule and the LCP
//! solver, reads and writes TOML, takes `--set key=value` overrides and runs the stepper.
//!
//! | model | coordinates q | contacts | parameters |
//! |---|---|---|---|
//! | [`Ball`] (7.1) | y | floor (μ = 0) | [`BallParams`] |
//! | [`Woodpecker`] (7.2) | y, phiM, phiS | beak, lower and upper sleeve edge | [`WoodpeckerParams`] |
//! | [`SliderCrank`] (7.3) | th1, th2, th3 | slider corners 1-4 | [`SliderCrankParams`] |
//! | [`SliderCrankIdeal`] (7.3) | th1 | none | [`SliderCrankIdealParams`] |
//! | [`Cam`] (7.4) | y | cam/follower (μ = 0, rheonomic) | [`CamParams`] |
//! | [`PainleveRod`] (7.5) | x, y, phi | lower end/ground | [`PainleveParams`] |
//!
//! Contacts a scene does not need can be switched off (the woodpecker's beak, the
//! slider-crank's upper or lower guide surface): they are then not listed at all, so the
//! number of contacts and the LCP shrink. Contacts with μ = 0 stay frictionless and get only
//! their normal row in the stepper.
//!
//! # What it is not for
//! It is not a general multibody modeller: no body or joint library, no collision detection.
//! The time-stepping is `moreau-stepper`'s, the LCP solvers `moreau-lcp`'s; figures and the
//! report are written by the `xtask` runner.
//!
//! # Principal types
//! [`ModelKind`] names the models, [`ModelParams`] holds any model's parameters, [`AnyModel`]
//! is any built model as one `Mechanism`, [`Scene`] runs one and returns a [`Simulation`],
//! [`Drawing`] draws one, [`ModelError`] is every failure.
//!
//! # Example
//! ```
//! use moreau_models::{ModelKind, Scene};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let mut scene = Scene::report(ModelKind::Ball);
//! scene.set("t_end", "0.6")?;
//! scene.set("eps_n", "0.5")?;
//! let sim = scene.run()?;
//! // The ball released from y0 = 1 m (R = 0.1 m) first hits the floor at
//! // t1 = sqrt(2 · 0.9 / 9.81) ≈ 0.4284 s.
//! let first = sim.record.p_n.iter().position(|p| p[0] > 0.0).ok_or("no impact")?;
//! assert!((sim.record.t[first] - 0.4284).abs() < 2e-3);
//! // Scenes round-trip through TOML.
//! let again = Scene::from_toml_str(&scene.to_toml_string())?;
//! assert_eq!(again, scene);
//! # Ok(())
//! # }
//! ```
//!
//! # References
//! - Moreau, J. J. (1988). Unilateral contact and dry friction in finite freedom dynamics.
//!   In *Non-smooth Mechanics and Applications*, CISM 302, Springer.
//! - Glocker, Ch. (2001). *Set-Valued Force Laws*. Springer.
//! - Flores, P. (2010). Application of the non-smooth dynamics approach to model and analyze
//!   contact-impact events in rigid multibody systems using the LCP formulation.
//!   Universidade do Minho.
#![deny(missing_docs)]

mod ball;
pub mod bodies;
mod cam;
mod draw;
mod error;
mod painleve;
mod params;
mod registry;
mod scene;
mod slider_crank;
mod slider_crank_ideal;
mod woodpecker;

pub use ball::{Ball, BallInit, BallParams};
pub use cam::{Cam, CamInit, CamParams, SpringLaw};
pub use draw::{Bounds, Circle, Drawing, Polyline, Role};
pub use error::ModelError;
pub use painleve::{PainleveInit, PainleveParams, PainleveRod};
pub use params::LawParams;
pub use registry::{AnyModel, ModelKind, ModelParams, Names};
pub use scene::{Scene, Simulation, StopRule};
pub use slider_crank::{SliderCrank, SliderCrankInit, SliderCrankParams};
pub use slider_crank_ideal::{SliderCrankIdeal, SliderCrankIdealInit, SliderCrankIdealParams};
pub use woodpecker::{Woodpecker, WoodpeckerInit, WoodpeckerParams};
