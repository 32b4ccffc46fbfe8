//! Checking a mechanism's shared-work overrides against its separate methods.
//!
//! [`SharedWork`] exists so that a mechanism can compute M, h, the gaps and the closed
//! contacts' kinematics at one q with shared work (the sines and cosines of the same angles,
//! say). It must give the values of the separate methods, and [`check_evaluate`] tells
//! whether it does.

use moreau_kinematics::ContactPoint;

#[cfg(doc)]
use crate::SharedWork;
use crate::mechanism::{evaluate, midpoint_contacts};
use crate::stepper::check_state;
use crate::{BilateralPoint, Mechanism, StepError};

/// Where an override of [`SharedWork::evaluate`], [`SharedWork::midpoint_contacts`] or
/// [`SharedWork::midpoint_bilaterals`] differs from the separate methods by more than the
/// tolerance.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error(
    "{what}[{index}]: {combined} from the shared evaluation, {separate} from the separate \
     methods (scaled difference {scaled:e})"
)]
pub struct EvaluateMismatch {
    /// The quantity: `"M"`, `"h"`, `"g_N"` (of `evaluate`), or `"contact g_N"`, `"g_T"`,
    /// `"w_N"`, `"w_T"`, `"ŵ_N"`, `"ŵ_T"` (of `midpoint_contacts` for all contacts at once),
    /// or `"w_B"`, `"g_B"`, `"ŵ_B"` (of `midpoint_bilaterals`).
    pub what: &'static str,
    /// The entry: column-major for M, the contact for the gaps and ŵ, `f · contact + j` for
    /// the entries j of w_N and w_T, the constraint for g_B and ŵ_B, `f · constraint + j`
    /// for the entries j of w_B.
    pub index: usize,
    /// The value of `evaluate`, `midpoint_contacts` or `midpoint_bilaterals`.
    pub combined: f64,
    /// The value of `mass_matrix`, `forces`, `normal_gaps`, `contacts` or `bilaterals`.
    pub separate: f64,
    /// `|combined − separate| / max(1, |combined|, |separate|)`.
    pub scaled: f64,
}

/// Compares, at the state (q, u, t), [`SharedWork::evaluate`] with [`Mechanism::mass_matrix`],
/// [`Mechanism::forces`] and [`moreau_kinematics::ContactKinematics::normal_gaps`], and then
/// [`SharedWork::midpoint_contacts`] (with the memo that `evaluate` left) with
/// [`moreau_kinematics::ContactKinematics::contacts`], for all contacts at once and for each
/// contact alone, and [`SharedWork::midpoint_bilaterals`], when the mechanism computes them,
/// with [`Mechanism::bilaterals`]. Returns the first entry whose scaled difference
/// `|a − b| / max(1, |a|, |b|)` exceeds `tol` (NaN in both counts as equal), or `None` when
/// they all agree.
///
/// Overrides that compute the same formulas in the same order agree to the last bit, so a
/// `tol` of 0 suits them; rewritten formulas (θ2 − θ1 by the difference formulas) agree to a
/// few roundings, 1e-14 of order-one values.
///
/// # Errors
/// [`StepError::Dimension`] when q or u does not have the mechanism's f entries,
/// [`StepError::NonFinite`] for non-finite q, u, t or `tol`.
///
/// ```
/// use moreau_kinematics::{ContactKinematics, ContactPoint};
/// use moreau_setvalued::ContactLaw;
/// use moreau_stepper::{Mechanism, SharedWork, check_evaluate};
///
/// /// A pendulum of length 1 whose bob meets a floor 0.9 below the pivot: q = (θ). Its
/// /// `evaluate` shares sin θ and cos θ, and has the sign of gravity wrong.
/// struct Pendulum { laws: [ContactLaw; 1] }
/// impl ContactKinematics for Pendulum {
///     fn num_coordinates(&self) -> usize { 1 }
///     fn num_contacts(&self) -> usize { 1 }
///     fn normal_gap(&self, _i: usize, q: &[f64], _t: f64) -> f64 { 0.9 - q[0].cos() }
///     fn contact(&self, i: usize, q: &[f64], t: f64, w_n: &mut [f64], w_t: &mut [f64]) -> ContactPoint {
///         (w_n[0], w_t[0]) = (q[0].sin(), q[0].cos());
///         ContactPoint { g_n: self.normal_gap(i, q, t), g_t: q[0].sin(), ..ContactPoint::default() }
///     }
/// }
/// impl Mechanism for Pendulum {
///     fn laws(&self) -> &[ContactLaw] { &self.laws }
///     fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) { m[0] = 1.0; }
///     fn forces(&self, q: &[f64], _u: &[f64], _t: f64, h: &mut [f64]) { h[0] = -9.81 * q[0].sin(); }
///     fn shared_work(&self) -> Option<&dyn SharedWork> { Some(self) }
/// }
/// impl SharedWork for Pendulum {
///     fn evaluate(
///         &self, q: &[f64], _u: &[f64], _t: f64, mass: Option<&mut [f64]>, h: &mut [f64],
///         gaps: &mut [f64], _memo: &mut [f64],
///     ) {
///         let (s, c) = q[0].sin_cos();
///         if let Some(m) = mass { m[0] = 1.0; }
///         h[0] = 9.81 * s;
///         gaps[0] = 0.9 - c;
///     }
///     fn memo_len(&self) -> usize { 0 }
///     fn midpoint_contacts(
///         &self, which: &[usize], q: &[f64], t: f64, _memo: &[f64], w_n: &mut [f64],
///         w_t: &mut [f64], points: &mut [ContactPoint],
///     ) {
///         self.contacts(which, q, t, w_n, w_t, points);
///     }
/// }
///
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let pendulum = Pendulum { laws: [ContactLaw::new(0.5, 0.0, 0.3)?] };
/// let found = check_evaluate(&pendulum, &[0.3], &[1.0], 0.0, 1e-14)?.expect("h differs");
/// assert_eq!((found.what, found.index), ("h", 0));
/// assert_eq!(found.combined, -found.separate);
/// # Ok(())
/// # }
/// ```
pub fn check_evaluate<M: Mechanism + ?Sized>(
    mech: &M,
    q: &[f64],
    u: &[f64],
    t: f64,
    tol: f64,
) -> Result<Option<EvaluateMismatch>, StepError> {
    let (f, n) = (mech.num_coordinates(), mech.num_contacts());
    check_state(f, t, q, u)?;
    if !tol.is_finite() {
        return Err(StepError::NonFinite { what: "tol", index: 0, t });
    }
    let compare = |what: &'static str, combined: &[f64], separate: &[f64]| {
        combined.iter().zip(separate).enumerate().find_map(|(index, (&a, &b))| {
            let scaled = (a - b).abs() / 1f64.max(a.abs()).max(b.abs());
            let same = scaled <= tol || (a.is_nan() && b.is_nan()) || a == b;
            (!same).then_some(EvaluateMismatch { what, index, combined: a, separate: b, scaled })
        })
    };

    let (mut m1, mut h1, mut g1) = (vec![0.0; f * f], vec![0.0; f], vec![0.0; n]);
    let mut memo = vec![f64::NAN; mech.shared_work().map_or(0, |s| s.memo_len())];
    evaluate(mech, q, u, t, Some(&mut m1), &mut h1, &mut g1, &mut memo);
    let (mut m2, mut h2, mut g2) = (vec![0.0; f * f], vec![0.0; f], vec![0.0; n]);
    mech.mass_matrix(q, t, &mut m2);
    mech.forces(q, u, t, &mut h2);
    mech.normal_gaps(q, t, &mut g2);
    for (what, a, b) in [("M", &m1, &m2), ("h", &h1, &h2), ("g_N", &g1, &g2)] {
        if let Some(m) = compare(what, a, b) {
            return Ok(Some(m));
        }
    }
    // Without M, evaluate writes the same h and gaps.
    evaluate(mech, q, u, t, None, &mut h2, &mut g2, &mut memo);
    for (what, a, b) in [("h", &h2, &h1), ("g_N", &g2, &g1)] {
        if let Some(m) = compare(what, a, b) {
            return Ok(Some(m));
        }
    }

    let all: Vec<usize> = (0..n).collect();
    // All contacts at once, then each alone.
    let lists = std::iter::once(all.clone()).chain(all.iter().map(|&i| vec![i]));
    for which in lists {
        let k = which.len();
        let fresh = contacts_of(k * f, k, |w_n, w_t, p| mech.contacts(&which, q, t, w_n, w_t, p));
        let kept = contacts_of(k * f, k, |w_n, w_t, p| {
            midpoint_contacts(mech, &which, q, t, &memo, w_n, w_t, p);
        });
        let scalars = |p: &[ContactPoint], g: fn(&ContactPoint) -> f64| -> Vec<f64> {
            p.iter().map(g).collect()
        };
        let offset = |mut m: EvaluateMismatch, per: usize| {
            m.index = which[m.index / per] * per + m.index % per;
            m
        };
        for (what, a, b, per) in [
            ("w_N", kept.0, fresh.0, f),
            ("w_T", kept.1, fresh.1, f),
            ("contact g_N", scalars(&kept.2, |p| p.g_n), scalars(&fresh.2, |p| p.g_n), 1),
            ("g_T", scalars(&kept.2, |p| p.g_t), scalars(&fresh.2, |p| p.g_t), 1),
            ("ŵ_N", scalars(&kept.2, |p| p.w_n_hat), scalars(&fresh.2, |p| p.w_n_hat), 1),
            ("ŵ_T", scalars(&kept.2, |p| p.w_t_hat), scalars(&fresh.2, |p| p.w_t_hat), 1),
        ] {
            if let Some(m) = compare(what, &a, &b) {
                return Ok(Some(offset(m, per)));
            }
        }
    }

    let nb = mech.num_bilaterals();
    let mut kept = (vec![0.0; nb * f], vec![BilateralPoint::default(); nb]);
    let computed = mech
        .shared_work()
        .is_some_and(|s| s.midpoint_bilaterals(q, t, &memo, &mut kept.0, &mut kept.1));
    if computed {
        let mut fresh = (vec![0.0; nb * f], vec![BilateralPoint::default(); nb]);
        mech.bilaterals(q, t, &mut fresh.0, &mut fresh.1);
        let scalars = |p: &[BilateralPoint], g: fn(&BilateralPoint) -> f64| -> Vec<f64> {
            p.iter().map(g).collect()
        };
        for (what, a, b) in [
            ("w_B", kept.0.clone(), fresh.0.clone()),
            ("g_B", scalars(&kept.1, |p| p.g), scalars(&fresh.1, |p| p.g)),
            ("ŵ_B", scalars(&kept.1, |p| p.w_hat), scalars(&fresh.1, |p| p.w_hat)),
        ] {
            if let Some(m) = compare(what, &a, &b) {
                return Ok(Some(m));
            }
        }
    }
    Ok(None)
}

/// Runs `fill` on fresh buffers for `k` contacts (w_N and w_T of `len` entries).
fn contacts_of(
    len: usize,
    k: usize,
    fill: impl FnOnce(&mut [f64], &mut [f64], &mut [ContactPoint]),
) -> (Vec<f64>, Vec<f64>, Vec<ContactPoint>) {
    let (mut w_n, mut w_t, mut points) =
        (vec![0.0; len], vec![0.0; len], vec![ContactPoint::default(); k]);
    fill(&mut w_n, &mut w_t, &mut points);
    (w_n, w_t, points)
}
