//! Moreau: non-smooth rigid multibody dynamics.
//!
//! Planar rigid multibody systems with hard unilateral contacts (Signorini), set-valued dry
//! friction (Coulomb) and Newton impacts, integrated by Moreau's midpoint time-stepping with
//! one linear complementarity problem (LCP) per step. This package re-exports the workspace's
//! crates under short names:
//!
//! | module | crate | for |
//! |---|---|---|
//! | [`setvalued`] | `moreau-setvalued` | Upr, Sgn, contact laws |
//! | [`lcp`] | `moreau-lcp` | LCP solvers (Lemke, PGS, enumeration, `Auto`), planar frictional-contact (FC2D) solvers in [`lcp::fc2d`], and faer as [`lcp::faer`] |
//! | [`kinematics`] | `moreau-kinematics` | gaps, contact Jacobians, finite-difference checks |
//! | [`stepper`] | `moreau-stepper` | the Moreau midpoint time-stepper |
//! | [`models`] | `moreau-models` | the reference report's mechanisms, declared mechanisms and scene files |
//! | [`nalgebra`] | `nalgebra` | the geometry types of [`kinematics::planar`] (points, vectors, Jacobians) |
//!
//! A mechanism of one's own implements [`stepper::Mechanism`] and
//! [`kinematics::ContactKinematics`], both in [`stepper::prelude`] with what they use;
//! `examples/box_on_incline` is one, with its Jacobians
//! checked, its run, its record and its impacts, and `docs/theory.md` holds the equations.
//!
//! **Not for**: the `moreau` command and its sweeps (the `moreau-cli` crate, not re-exported
//! here) or the report's figures (the repository's `cargo xtask`). A project that needs one
//! part only, the LCP solvers say, can depend on that crate alone.
//!
//! # Example
//! ```
//! use moreau::models::{ModelKind, Scene};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let mut scene = Scene::report(ModelKind::Ball);
//! scene.set("t_end", "1.0")?;
//! let sim = scene.run()?;
//! // The ball of the report first hits the floor at t1 = sqrt(2 · 0.9 / 9.81) ≈ 0.428 s,
//! // at v1 = sqrt(2 · 9.81 · 0.9) ≈ 4.20 m/s, and leaves at ε_N v1 with ε_N = 0.9.
//! let first = sim.record.impacts[0];
//! assert!((first.t - 0.4284).abs() < 2e-3);
//! assert!((first.gamma_n_before + 4.202).abs() < 1e-2);
//! assert!((first.gamma_n_after + 0.9 * first.gamma_n_before).abs() < 1e-12);
//! # Ok(())
//! # }
//! ```
#![deny(missing_docs)]

pub use moreau_kinematics as kinematics;
pub use moreau_lcp as lcp;
pub use moreau_models as models;
pub use moreau_setvalued as setvalued;
pub use moreau_stepper as stepper;
pub use nalgebra;
