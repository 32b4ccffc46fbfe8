//! Shared fixtures of Moreau's tests and benches, so that each exists once.
//!
//! - [`SplitMix64`]: the seeded generator of every randomised test (the run-time generator
//!   of `moreau-kinematics`, re-exported, so that tests and the Jacobian sampler draw from
//!   one implementation);
//! - small mechanisms with closed-form answers: [`Ball`] over a moving floor, [`Block`] on
//!   an incline, [`Rod`] with two ends on the ground, [`Chain`] of balls on a line (Newton's
//!   cradle); [`Disks`] on a floor between walls, with fixed contacts or with a body
//!   structure whose contacts are detected at each step; [`Pairs`], a [`ContactKinematics`](moreau_kinematics::ContactKinematics) made
//!   of closures over the planar pairs;
//! - LCP problems: random SPD and P-matrices ([`random_spd`], [`random_p_matrix`]), planted
//!   solutions ([`planted`]) and Murty's exponential problem ([`murty`]);
//! - reading a [`Record`](moreau_stepper::Record): impact onsets, level crossings,
//!   interpolated velocities, finiteness, energy gain, deepest penetration, and the path of
//!   a shipped scene file;
//! - [`CountingAllocator`] and [`allocations_in`]: the per-thread allocation count of the
//!   tests that assert a warm hot path does not touch the heap.
//!
//! **For**: the integration tests, doc tests and benches of this workspace (it is a
//! dev-dependency only and is not published). **Not for**: users' simulations, whose
//! mechanisms belong in `moreau-models` or in their own code; nor the unit tests inside
//! `moreau-lcp`, `moreau-kinematics` or `moreau-stepper` that need their crate's own types
//! (a `#[cfg(test)]` build of a crate is another crate than the one this one links).
//!
//! # Example: the test ball's first impact
//! ```
//! use moreau_stepper::{Stepper, StepperOptions};
//! use moreau_testsupport::{Ball, G, SplitMix64, onsets, random_spd};
//!
//! let ball = Ball::new(0.9);
//! let mut stepper = Stepper::new(ball, &[1.0], &[0.0], 0.0, StepperOptions::new(1e-3)).unwrap();
//! let record = stepper.record_until(0.5).unwrap();
//! // The ball (radius 0.1 m) falls 0.9 m: it lands at t = sqrt(2 · 0.9 / g) ≈ 0.428 s.
//! let first = onsets(&record, 0)[0];
//! assert!((record.t[first] - (2.0 * 0.9 / G).sqrt()).abs() < 2e-3);
//!
//! // Equal seeds give equal problems.
//! let a = random_spd(5, &mut SplitMix64::new(3));
//! let b = random_spd(5, &mut SplitMix64::new(3));
//! assert_eq!(a, b);
//! ```
#![deny(missing_docs)]

mod allocations;
mod disks;
mod mechanisms;
mod pairs;
mod problems;
mod record;

pub use allocations::{CountingAllocator, allocations_in};
pub use disks::{Disks, Feature};
pub use mechanisms::{Ball, Block, Chain, G, Rod};
pub use moreau_kinematics::SplitMix64;
pub use pairs::{Pair, Pairs};
pub use problems::{murty, planted, random_p_matrix, random_spd};
pub use record::{
    deepest_penetration, energy_gain, onsets, record_is_finite, scene_path, up_crossings,
    velocity_at,
};

#[cfg(test)]
mod tests {
    use super::*;

    /// The re-exported generator is SplitMix64: its first outputs from seed 0 are the
    /// published reference values, and it stays in [0, 1) and [lo, hi).
    #[test]
    fn generator_matches_the_reference_sequence() {
        let mut rng = SplitMix64::new(0);
        assert_eq!(rng.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(rng.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        assert_eq!(rng.next_u64(), 0x06C4_5D18_8009_454F);
        let mut rng = SplitMix64::new(1);
        for _ in 0..1000 {
            let (x, y) = (rng.next_f64(), rng.uniform(-2.0, 3.0));
            assert!((0.0..1.0).contains(&x) && (-2.0..3.0).contains(&y));
        }
    }
}
