//! Seeded sample states for the finite-difference checker: the SplitMix64 generator and
//! perturbations of a state (q, t) within given radii.

use serde::{Deserialize, Serialize};

use crate::KinematicsError;

/// The SplitMix64 generator (Steele, Lea & Flood 2014): a tiny seeded source of pseudo-random
/// numbers for reproducible sample states, with no dependency.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SplitMix64 {
    state: u64,
}

impl SplitMix64 {
    /// A generator started from `seed`; equal seeds give equal sequences.
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64 pseudo-random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A pseudo-random number uniformly distributed in `[0, 1)` (53 random bits).
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A pseudo-random number uniformly distributed in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next_f64()
    }

    /// A pseudo-random integer in `0..k` (`k >= 1`), by the remainder of [`Self::next_u64`]:
    /// its bias, below k / 2^64, does not matter for test data.
    ///
    /// # Panics
    /// When `k = 0`: the range `0..0` holds no integer.
    pub fn below(&mut self, k: u64) -> u64 {
        self.next_u64() % k
    }
}

/// Options of [`sample_states`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SampleOptions {
    /// Number of sample states, the centre included (`>= 1`). Default `8`.
    pub count: usize,
    /// Half-width of the uniform perturbation of each coordinate q_j (units of q, `>= 0`).
    /// Default `0.1`.
    pub q_radius: f64,
    /// Half-width of the uniform perturbation of the time t (s, `>= 0`). Default `0.0`.
    pub t_radius: f64,
    /// Seed of the [`SplitMix64`] generator. Default `0x5EED`.
    pub seed: u64,
}

impl Default for SampleOptions {
    fn default() -> Self {
        Self { count: 8, q_radius: 0.1, t_radius: 0.0, seed: 0x5EED }
    }
}

/// Deterministic sample states around `(q0, t0)` for [`crate::check_jacobians`]: the first is
/// `(q0, t0)` itself, the others perturb each q_j uniformly within ±`q_radius` and t within
/// ±`t_radius`, drawn from a [`SplitMix64`] seeded with `seed`.
///
/// # Errors
/// [`KinematicsError::NonFinite`] for a non-finite `q0` or `t0`,
/// [`KinematicsError::InvalidOption`] for a zero `count` or a negative or non-finite radius.
pub fn sample_states(
    q0: &[f64],
    t0: f64,
    options: SampleOptions,
) -> Result<Vec<(Vec<f64>, f64)>, KinematicsError> {
    if options.count == 0 {
        return Err(KinematicsError::InvalidOption { name: "count", value: 0.0 });
    }
    for (name, value) in [("q_radius", options.q_radius), ("t_radius", options.t_radius)] {
        if value < 0.0 || !value.is_finite() {
            return Err(KinematicsError::InvalidOption { name, value });
        }
    }
    if q0.iter().any(|x| !x.is_finite()) {
        return Err(KinematicsError::NonFinite { what: "q0", contact: None, sample: None });
    }
    if !t0.is_finite() {
        return Err(KinematicsError::NonFinite { what: "t0", contact: None, sample: None });
    }
    let mut rng = SplitMix64::new(options.seed);
    let mut samples = Vec::with_capacity(options.count);
    samples.push((q0.to_vec(), t0));
    for _ in 1..options.count {
        let q = q0.iter().map(|&x| x + rng.uniform(-options.q_radius, options.q_radius)).collect();
        let t = t0 + rng.uniform(-options.t_radius, options.t_radius);
        samples.push((q, t));
    }
    Ok(samples)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix_matches_reference_sequence_and_is_seeded() {
        // Reference values of SplitMix64 seeded with 1234567 (from the published C code).
        let mut rng = SplitMix64::new(1_234_567);
        assert_eq!(rng.next_u64(), 6_457_827_717_110_365_317);
        assert_eq!(rng.next_u64(), 3_203_168_211_198_807_973);
        let a = sample_states(
            &[1.0, 2.0],
            0.5,
            SampleOptions { count: 4, q_radius: 0.2, t_radius: 0.1, seed: 3 },
        )
        .unwrap();
        let b = sample_states(
            &[1.0, 2.0],
            0.5,
            SampleOptions { count: 4, q_radius: 0.2, t_radius: 0.1, seed: 3 },
        )
        .unwrap();
        assert_eq!(a, b);
        assert_eq!(a[0], (vec![1.0, 2.0], 0.5));
        for (q, t) in &a[1..] {
            assert!(
                (q[0] - 1.0).abs() <= 0.2 && (q[1] - 2.0).abs() <= 0.2 && (t - 0.5).abs() <= 0.1
            );
            assert_ne!(q[0], 1.0);
        }
        let mut rng = SplitMix64::new(9);
        for _ in 0..1000 {
            let x = rng.next_f64();
            assert!((0.0..1.0).contains(&x));
        }
    }

    #[test]
    fn wrong_sample_options_and_states_are_typed_errors() {
        assert_eq!(
            sample_states(&[0.0], 0.0, SampleOptions { count: 0, ..Default::default() }),
            Err(KinematicsError::InvalidOption { name: "count", value: 0.0 })
        );
        assert_eq!(
            sample_states(&[0.0], 0.0, SampleOptions { q_radius: -0.5, ..Default::default() }),
            Err(KinematicsError::InvalidOption { name: "q_radius", value: -0.5 })
        );
        assert!(matches!(
            sample_states(&[0.0], 0.0, SampleOptions { t_radius: f64::NAN, ..Default::default() }),
            Err(KinematicsError::InvalidOption { name: "t_radius", .. })
        ));
        assert_eq!(
            sample_states(&[0.0, f64::INFINITY], 0.0, SampleOptions::default()),
            Err(KinematicsError::NonFinite { what: "q0", contact: None, sample: None })
        );
        assert_eq!(
            sample_states(&[0.0], f64::NAN, SampleOptions::default()),
            Err(KinematicsError::NonFinite { what: "t0", contact: None, sample: None })
        );
    }
}
