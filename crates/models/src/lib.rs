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
//! Besides these, any planar mechanism can be DECLARED ([`bodies`]): dynamic, fixed and driven
//! bodies with shapes, joints (revolute, prismatic, weld, point-on-line, motor, and clearance
//! joints as contacts), force elements and contacts between shapes, in Rust with
//! [`bodies::MultibodyBuilder`] or in a scene file; Moreau builds the mechanism
//! ([`bodies::Multibody`]: maximal coordinates, M, h, the joints' rows and the contacts' force
//! directions) and runs it with the same stepper. Scenes of many bodies (piles, columns and
//! flows of grains, stacks of boxes) find their contacts at each step instead of keeping a fixed
//! list ([`bodies::ContactSet`]) and generate their bodies from `[[fill]]` tables
//! ([`bodies::FillSpec`]); `scenes/scale/` has a disk column, Box2D's pyramid and a granular
//! flow.
//!
//! Contacts a scene does not need can be switched off (the woodpecker's beak, the
//! slider-crank's upper or lower guide surface): they are then not listed at all, so the
//! number of contacts and the LCP shrink. Contacts with μ = 0 stay frictionless and get only
//! their normal row in the stepper.
//!
//! # What it is not for
//! It holds no collision geometry of its own: the shapes, the narrow phase and the broad phase
//! are `moreau-kinematics`', which a declared mechanism calls for its contacts (at each step
//! for a detected contact set). It has no three-dimensional bodies and no flexible ones, and does not
//! reduce declared mechanisms to minimal coordinates. The time-stepping is `moreau-stepper`'s, the LCP solvers `moreau-lcp`'s; figures and the
//! report are written by the `xtask` runner.
//!
//! # Principal types
//! [`ModelKind`] names the models, [`ModelParams`] holds any model's parameters, [`AnyModel`]
//! is any built model as one `Mechanism`, [`Scene`] runs one and returns a [`Simulation`],
//! [`Drawing`] draws one, [`ModelError`] is every failure; [`bodies`] declares mechanisms.
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
//! let again = Scene::from_toml_str(&scene.to_toml_string()?)?;
//! assert_eq!(again, scene);
//! # Ok(())
//! # }
//! ```
//!
//! A declared mechanism, built in Rust and stepped:
//! ```
//! use moreau_kinematics::Shape;
//! use moreau_models::LawParams;
//! use moreau_models::bodies::{BodySpec, ContactSpec, MultibodyBuilder};
//! use moreau_stepper::Stepper;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // A disk of radius 0.1 m dropped from 0.5 m onto a floor, ε_N = 0.5.
//! let mut builder = MultibodyBuilder::new([0.0, -9.81]);
//! builder.add_body(BodySpec::fixed("floor", [0.0, 0.0], 0.0)
//!     .with_shape(Shape::HalfPlane { point: [0.0, 0.0], normal: [0.0, 1.0] }));
//! builder.add_body(BodySpec::dynamic("ball", 1.0, 0.005, [0.0, 0.5], 0.0)
//!     .with_shape(Shape::Disk { center: [0.0, 0.0], radius: 0.1 }));
//! let law = LawParams::new(0.5, 0.0, 0.0);
//! builder.add_contact(ContactSpec::new("bounce", "floor", "ball", law));
//! let ball = builder.build()?;
//! let (q0, u0) = ball.initial_state();
//! // The mechanism's own options: its gap, projection and joint tolerances, scaled to its
//! // size (`StepperOptions::new(dt)` alone counts a contact closed only at g_N <= 0, so that a
//! // resting contact left open by round-off sits out a step and its body falls for Δt).
//! let options = ball.stepper_options(1e-3);
//! let mut stepper = Stepper::new(ball, &q0, &u0, 0.0, options)?;
//! let mut bounced = false;
//! while stepper.t() < 0.4 {
//!     bounced |= stepper.step()?.contacts[0].p_n > 0.0;
//! }
//! // It falls 0.4 m in sqrt(0.8 / 9.81) ≈ 0.286 s, and comes back up at half the speed.
//! assert!(bounced && stepper.u()[1] > 0.0);
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
pub use error::{ModelError, unknown_key_text};
pub use painleve::{PainleveInit, PainleveParams, PainleveRod};
pub use params::LawParams;
pub use registry::{AnyModel, ModelKind, ModelParams, Names};
pub use scene::{Scene, SceneEdit, Simulation, StopRule};
pub use slider_crank::{SliderCrank, SliderCrankInit, SliderCrankParams};
pub use slider_crank_ideal::{SliderCrankIdeal, SliderCrankIdealInit, SliderCrankIdealParams};
pub use woodpecker::{Woodpecker, WoodpeckerInit, WoodpeckerParams};
