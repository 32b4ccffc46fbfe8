//! Planar contact kinematics for Moreau's time-stepping.
#![deny(missing_docs)]

/// Kinematic quantities of one contact at `(q, t)`, besides its force directions.
///
/// The force directions `w_N = (∂g_N/∂q)ᵀ` and `w_T = (∂g_T/∂q)ᵀ` are written into
/// caller-provided slices by [`ContactKinematics::contact`]; this struct carries the scalars.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactPoint {
    /// Normal gap g_N: positive open, zero closed, negative penetration (m).
    pub g_n: f64,
    /// Tangential position g_T of the contact point along the tangent (m); only its
    /// derivatives enter the dynamics, but the finite-difference checker uses it.
    pub g_t: f64,
    /// Rheonomic normal term ŵ_N = ∂g_N/∂t (m/s).
    pub w_n_hat: f64,
    /// Rheonomic tangential term ŵ_T = ∂g_T/∂t (m/s).
    pub w_t_hat: f64,
}

/// The contact kinematics of a mechanism with `f` generalised coordinates and `n` contacts.
///
/// Implementors write the gaps and their derivatives; the time-stepper and the
/// finite-difference checker only call these methods.
pub trait ContactKinematics {
    /// Number of generalised coordinates `f` (the length of `q` and `u`).
    fn num_coordinates(&self) -> usize;
    /// Number of contacts `n` (closed or open).
    fn num_contacts(&self) -> usize;
    /// The normal gap g_N of contact `i` at `(q, t)` alone, for the active-set test.
    fn normal_gap(&self, i: usize, q: &[f64], t: f64) -> f64;
    /// Full kinematics of contact `i` at `(q, t)`: writes `w_N` into `w_n` and `w_T` into
    /// `w_t` (both of length `f`) and returns g_N, g_T, ŵ_N and ŵ_T.
    fn contact(&self, i: usize, q: &[f64], t: f64, w_n: &mut [f64], w_t: &mut [f64]) -> ContactPoint;
}
