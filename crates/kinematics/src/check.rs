//! Finite-difference checking of contact kinematics.
//!
//! For every contact i and every sample state (q, t) the checker compares
//!
//! * each entry of w_N = (∂g_N/∂q)ᵀ and w_T = (∂g_T/∂q)ᵀ with the central difference
//!   (g(q + h e_j, t) − g(q − h e_j, t)) / (2h), with the step h = `rel_step` · max(|q_j|, `q_scale`);
//! * ŵ_N = ∂g_N/∂t and ŵ_T = ∂g_T/∂t with the central difference in t, with the step
//!   h_t = `rel_step` · max(|t|, `t_scale`);
//! * `normal_gap(i, q, t)` and entry i of `normal_gaps(q, t, ..)` with the g_N returned by
//!   `contact(i, q, t, ..)`.
//!
//! Each comparison yields the absolute difference `abs = |a − r|` between the analytic value a
//! and the reference r, the relative difference `rel = abs / max(|a|, |r|)` and the scaled
//! difference `scaled = abs / max(1, |a|, |r|)`, which is absolute for entries below one and
//! relative above. A check passes with tolerance `tol` when every scaled difference is at most
//! `tol`. With the default step the central differences are accurate to about 1e-9 for smooth
//! kinematics of order-one size, so `tol = 1e-6` separates correct from wrong Jacobians.
//!
//! # References
//! * Glocker, Ch. (2001). *Set-Valued Force Laws: Dynamics of Non-Smooth Systems*. Springer.
//! * Flores, P. (2010). *Application of the non-smooth dynamics approach to model and analyze
//!   contact-impact events in rigid multibody systems using the linear complementarity problem
//!   formulation*. Universidade do Minho.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::{ContactKinematics, ContactPoint, KinematicsError};

/// Options of the finite-difference checker [`check_jacobians`].
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FdOptions {
    /// Relative step of the central differences (dimensionless, `> 0`). Default `1e-6`.
    pub rel_step: f64,
    /// Smallest magnitude of q_j used to size the step in q: h = `rel_step` · max(|q_j|,
    /// `q_scale`) (units of q, `> 0`). Default `1.0`.
    pub q_scale: f64,
    /// Smallest magnitude of t used to size the step in t: h_t = `rel_step` · max(|t|,
    /// `t_scale`) (s, `> 0`). Default `1.0`.
    pub t_scale: f64,
    /// Whether to check ŵ_N and ŵ_T against the time derivatives (default `true`). Turn it off
    /// for kinematics whose time dependence is not differentiable at the sample times.
    pub check_time: bool,
}

impl Default for FdOptions {
    fn default() -> Self {
        Self { rel_step: 1e-6, q_scale: 1.0, t_scale: 1.0, check_time: true }
    }
}

impl FdOptions {
    fn validate(&self) -> Result<(), KinematicsError> {
        for (name, value) in
            [("rel_step", self.rel_step), ("q_scale", self.q_scale), ("t_scale", self.t_scale)]
        {
            if !(value > 0.0 && value.is_finite()) {
                return Err(KinematicsError::InvalidOption { name, value });
            }
        }
        Ok(())
    }
}

/// Which quantity of a contact a comparison concerns.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Component {
    /// `normal_gap(i, q, t)` against the g_N returned by `contact(i, q, t, ..)`.
    NormalGap,
    /// Entry `coordinate` of w_N against ∂g_N/∂q_j.
    WN {
        /// The coordinate index j.
        coordinate: usize,
    },
    /// Entry `coordinate` of w_T against ∂g_T/∂q_j.
    WT {
        /// The coordinate index j.
        coordinate: usize,
    },
    /// ŵ_N against ∂g_N/∂t.
    WNHat,
    /// ŵ_T against ∂g_T/∂t.
    WTHat,
    /// Entry i of `normal_gaps(q, t, ..)` against the g_N returned by `contact(i, q, t, ..)`.
    NormalGaps,
    /// Contact i's w_N, w_T, g_N, g_T, ŵ_N and ŵ_T from `contacts(&[0, .., n − 1], q, t, ..)`
    /// against those of `contact(i, q, t, ..)` (the entry that differs most).
    Contacts,
}

impl fmt::Display for Component {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NormalGap => write!(f, "normal_gap vs g_N"),
            Self::WN { coordinate } => write!(f, "w_N[{coordinate}]"),
            Self::WT { coordinate } => write!(f, "w_T[{coordinate}]"),
            Self::WNHat => write!(f, "ŵ_N"),
            Self::WTHat => write!(f, "ŵ_T"),
            Self::NormalGaps => write!(f, "normal_gaps vs g_N"),
            Self::Contacts => write!(f, "contacts vs contact"),
        }
    }
}

/// One comparison of an analytic value with its reference (usually the worst of a contact).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Mismatch {
    /// The contact index i.
    pub contact: usize,
    /// The quantity compared.
    pub component: Component,
    /// The index of the sample state in the slice given to the checker.
    pub sample: usize,
    /// The value the kinematics returned (an entry of w_N or w_T, ŵ_N, ŵ_T, or `normal_gap`).
    pub analytic: f64,
    /// The reference: the central difference, or the g_N of `contact` for [`Component::NormalGap`].
    pub reference: f64,
    /// |analytic − reference|.
    pub abs: f64,
    /// |analytic − reference| / max(|analytic|, |reference|), zero when both vanish.
    pub rel: f64,
    /// |analytic − reference| / max(1, |analytic|, |reference|): the measure `passed` tests.
    pub scaled: f64,
}

impl Mismatch {
    fn new(
        contact: usize,
        component: Component,
        sample: usize,
        analytic: f64,
        reference: f64,
    ) -> Self {
        let abs = (analytic - reference).abs();
        let magnitude = analytic.abs().max(reference.abs());
        let rel = if magnitude > 0.0 { abs / magnitude } else { 0.0 };
        let scaled = abs / magnitude.max(1.0);
        Self { contact, component, sample, analytic, reference, abs, rel, scaled }
    }

    /// The [`KinematicsError::JacobianMismatch`] describing this comparison.
    pub fn to_error(&self) -> KinematicsError {
        KinematicsError::JacobianMismatch {
            contact: self.contact,
            component: self.component,
            sample: self.sample,
            abs: self.abs,
            rel: self.rel,
        }
    }
}

/// The result of [`check_jacobians`]: the worst comparison of each contact.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FdReport {
    /// The worst comparison (largest `scaled` difference) of each contact, indexed by contact i.
    pub contacts: Vec<Mismatch>,
    /// Number of sample states checked.
    pub samples: usize,
    /// Number of calls of `contact`, `contacts`, `normal_gap` and `normal_gaps` made.
    pub evaluations: usize,
    /// The options used.
    pub options: FdOptions,
}

impl FdReport {
    /// Whether every comparison of every contact has a scaled difference of at most `tol`.
    pub fn passed(&self, tol: f64) -> bool {
        self.contacts.iter().all(|m| m.scaled <= tol)
    }

    /// The worst comparison over all contacts, `None` for a mechanism without contacts.
    pub fn worst(&self) -> Option<&Mismatch> {
        self.contacts.iter().max_by(|a, b| a.scaled.total_cmp(&b.scaled))
    }

    /// The worst comparison of each contact that fails the tolerance `tol`.
    pub fn failures(&self, tol: f64) -> impl Iterator<Item = &Mismatch> {
        self.contacts.iter().filter(move |m| m.scaled > tol)
    }
}

/// Evaluation buffers reused across the calls of one check.
struct Probe<'a, K: ContactKinematics + ?Sized> {
    k: &'a K,
    w_n: Vec<f64>,
    w_t: Vec<f64>,
    evaluations: usize,
}

impl<K: ContactKinematics + ?Sized> Probe<'_, K> {
    /// g_N and g_T of contact `i` at `(q, t)`, checked to be finite.
    fn gaps(
        &mut self,
        i: usize,
        q: &[f64],
        t: f64,
        sample: usize,
    ) -> Result<(f64, f64), KinematicsError> {
        self.evaluations += 1;
        let cp = self.k.contact(i, q, t, &mut self.w_n, &mut self.w_t);
        finite("g_N", cp.g_n, i, sample)?;
        finite("g_T", cp.g_t, i, sample)?;
        Ok((cp.g_n, cp.g_t))
    }
}

fn finite(
    what: &'static str,
    value: f64,
    contact: usize,
    sample: usize,
) -> Result<(), KinematicsError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(KinematicsError::NonFinite { what, contact: Some(contact), sample: Some(sample) })
    }
}

/// Checks the force directions and rheonomic terms of every contact of `k` against central
/// finite differences of its gaps, at every sample state `(q, t)`.
///
/// The steps are those of [`FdOptions`]; [`Mismatch`] defines the measures compared. The
/// returned report holds the worst comparison of each contact; decide with [`FdReport::passed`].
///
/// It is for kinematics whose gaps are functions of (q, t) written out, as a hand-derived
/// mechanism's are, with g_T a tangential coordinate. Contacts found between shapes
/// ([`collide`](crate::collide), a declared mechanism's) give g_T = 0 in their own frame and,
/// beyond their margin, a gap that does not follow q, so their w_T and distant w_N do not
/// match differences of those values; their directions are tested against the shapes'
/// geometry instead.
///
/// # Errors
/// [`KinematicsError::NoSamples`] for an empty `samples`, [`KinematicsError::DimensionMismatch`]
/// for a `q` whose length is not `num_coordinates()`, [`KinematicsError::NonFinite`] for a
/// non-finite input or a non-finite value returned by the kinematics (including entries of
/// w_N, w_T that `contact` leaves unwritten: the buffers are filled with NaN before each call),
/// and
/// [`KinematicsError::InvalidOption`] for a non-positive step or scale.
pub fn check_jacobians<K: ContactKinematics + ?Sized>(
    k: &K,
    samples: &[(Vec<f64>, f64)],
    options: FdOptions,
) -> Result<FdReport, KinematicsError> {
    options.validate()?;
    if samples.is_empty() {
        return Err(KinematicsError::NoSamples);
    }
    let f = k.num_coordinates();
    let n = k.num_contacts();
    for (s, (q, t)) in samples.iter().enumerate() {
        if q.len() != f {
            return Err(KinematicsError::DimensionMismatch {
                what: "sample q",
                expected: f,
                found: q.len(),
            });
        }
        if q.iter().any(|x| !x.is_finite()) {
            return Err(KinematicsError::NonFinite { what: "q", contact: None, sample: Some(s) });
        }
        if !t.is_finite() {
            return Err(KinematicsError::NonFinite { what: "t", contact: None, sample: Some(s) });
        }
    }

    let mut probe = Probe { k, w_n: vec![0.0; f], w_t: vec![0.0; f], evaluations: 0 };
    let mut w_n = vec![0.0; f];
    let mut w_t = vec![0.0; f];
    let mut shifted = vec![0.0; f];
    let mut worst: Vec<Option<Mismatch>> = vec![None; n];

    let mut gaps = vec![0.0; n];
    let all: Vec<usize> = (0..n).collect();
    let (mut all_w_n, mut all_w_t) = (vec![0.0; n * f], vec![0.0; n * f]);
    let mut points = vec![ContactPoint::default(); n];
    for (s, (q, t)) in samples.iter().enumerate() {
        let t = *t;
        gaps.fill(f64::NAN);
        probe.evaluations += 1;
        k.normal_gaps(q, t, &mut gaps);
        all_w_n.fill(f64::NAN);
        all_w_t.fill(f64::NAN);
        points.fill(ContactPoint {
            g_n: f64::NAN,
            g_t: f64::NAN,
            w_n_hat: f64::NAN,
            w_t_hat: f64::NAN,
        });
        probe.evaluations += 1;
        k.contacts(&all, q, t, &mut all_w_n, &mut all_w_t, &mut points);
        for i in 0..n {
            let record = |m: Mismatch, slot: &mut Option<Mismatch>| {
                if slot.is_none_or(|w| m.scaled > w.scaled) {
                    *slot = Some(m);
                }
            };
            probe.evaluations += 1;
            // NaN sentinels expose entries of w_N, w_T that `contact` leaves unwritten.
            w_n.fill(f64::NAN);
            w_t.fill(f64::NAN);
            let cp = k.contact(i, q, t, &mut w_n, &mut w_t);
            for (what, v) in
                [("g_N", cp.g_n), ("g_T", cp.g_t), ("ŵ_N", cp.w_n_hat), ("ŵ_T", cp.w_t_hat)]
            {
                finite(what, v, i, s)?;
            }
            if w_n.iter().any(|x| !x.is_finite()) {
                return Err(KinematicsError::NonFinite {
                    what: "w_N",
                    contact: Some(i),
                    sample: Some(s),
                });
            }
            if w_t.iter().any(|x| !x.is_finite()) {
                return Err(KinematicsError::NonFinite {
                    what: "w_T",
                    contact: Some(i),
                    sample: Some(s),
                });
            }
            probe.evaluations += 1;
            let gap = k.normal_gap(i, q, t);
            finite("normal_gap", gap, i, s)?;
            record(Mismatch::new(i, Component::NormalGap, s, gap, cp.g_n), &mut worst[i]);
            finite("normal_gaps", gaps[i], i, s)?;
            record(Mismatch::new(i, Component::NormalGaps, s, gaps[i], cp.g_n), &mut worst[i]);
            let p = points[i];
            let (p_scalars, cp_scalars) =
                ([p.g_n, p.g_t, p.w_n_hat, p.w_t_hat], [cp.g_n, cp.g_t, cp.w_n_hat, cp.w_t_hat]);
            let batched = all_w_n[i * f..(i + 1) * f]
                .iter()
                .chain(&all_w_t[i * f..(i + 1) * f])
                .chain(&p_scalars);
            let single = w_n.iter().chain(&w_t).chain(&cp_scalars);
            for (&b, &a) in batched.zip(single) {
                finite("contacts", b, i, s)?;
                record(Mismatch::new(i, Component::Contacts, s, b, a), &mut worst[i]);
            }

            shifted.copy_from_slice(q);
            for j in 0..f {
                let step = options.rel_step * q[j].abs().max(options.q_scale);
                shifted[j] = q[j] + step;
                let upper = shifted[j];
                let (gn_plus, gt_plus) = probe.gaps(i, &shifted, t, s)?;
                shifted[j] = q[j] - step;
                let lower = shifted[j];
                let (gn_minus, gt_minus) = probe.gaps(i, &shifted, t, s)?;
                shifted[j] = q[j];
                // The representable step (upper − lower) replaces 2h to cancel rounding of q ± h.
                let width = upper - lower;
                let fd_n = (gn_plus - gn_minus) / width;
                let fd_t = (gt_plus - gt_minus) / width;
                record(
                    Mismatch::new(i, Component::WN { coordinate: j }, s, w_n[j], fd_n),
                    &mut worst[i],
                );
                record(
                    Mismatch::new(i, Component::WT { coordinate: j }, s, w_t[j], fd_t),
                    &mut worst[i],
                );
            }

            if options.check_time {
                let step = options.rel_step * t.abs().max(options.t_scale);
                let (upper, lower) = (t + step, t - step);
                let (gn_plus, gt_plus) = probe.gaps(i, q, upper, s)?;
                let (gn_minus, gt_minus) = probe.gaps(i, q, lower, s)?;
                let width = upper - lower;
                record(
                    Mismatch::new(i, Component::WNHat, s, cp.w_n_hat, (gn_plus - gn_minus) / width),
                    &mut worst[i],
                );
                record(
                    Mismatch::new(i, Component::WTHat, s, cp.w_t_hat, (gt_plus - gt_minus) / width),
                    &mut worst[i],
                );
            }
        }
    }

    let contacts = worst.into_iter().flatten().collect::<Vec<_>>();
    Ok(FdReport { contacts, samples: samples.len(), evaluations: probe.evaluations, options })
}

/// [`check_jacobians`] with the default [`FdOptions`], turned into an error when a comparison
/// fails the tolerance `tol` (see [`FdReport::passed`]).
///
/// # Errors
/// Those of [`check_jacobians`], and [`KinematicsError::JacobianMismatch`] naming the contact,
/// component and sample of the worst failing comparison; [`KinematicsError::InvalidOption`]
/// for a negative or NaN `tol`.
pub fn assert_consistent<K: ContactKinematics + ?Sized>(
    k: &K,
    samples: &[(Vec<f64>, f64)],
    tol: f64,
) -> Result<FdReport, KinematicsError> {
    if tol.is_nan() || tol < 0.0 {
        return Err(KinematicsError::InvalidOption { name: "tol", value: tol });
    }
    let report = check_jacobians(k, samples, FdOptions::default())?;
    match report.worst() {
        Some(worst) if worst.scaled > tol => Err(worst.to_error()),
        _ => Ok(report),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ContactPoint;
    use crate::{SampleOptions, sample_states};

    /// One contact with g_N = q0² + q1 sin t, g_T = q0 q1 + t², with analytic derivatives; the
    /// `error` entry is added to w_N[1] to plant a wrong Jacobian.
    struct Quadratic {
        error: f64,
    }

    impl ContactKinematics for Quadratic {
        fn num_coordinates(&self) -> usize {
            2
        }
        fn num_contacts(&self) -> usize {
            1
        }
        fn normal_gap(&self, _i: usize, q: &[f64], t: f64) -> f64 {
            q[0] * q[0] + q[1] * t.sin()
        }
        fn contact(
            &self,
            _i: usize,
            q: &[f64],
            t: f64,
            w_n: &mut [f64],
            w_t: &mut [f64],
        ) -> ContactPoint {
            w_n[0] = 2.0 * q[0];
            w_n[1] = t.sin() + self.error;
            w_t[0] = q[1];
            w_t[1] = q[0];
            ContactPoint {
                g_n: q[0] * q[0] + q[1] * t.sin(),
                g_t: q[0] * q[1] + t * t,
                w_n_hat: q[1] * t.cos(),
                w_t_hat: 2.0 * t,
            }
        }
    }

    fn samples() -> Vec<(Vec<f64>, f64)> {
        sample_states(
            &[0.3, -1.2],
            0.7,
            SampleOptions { count: 5, q_radius: 0.5, t_radius: 0.3, seed: 7 },
        )
        .unwrap()
    }

    #[test]
    fn correct_kinematics_pass_with_small_mismatch() {
        let report =
            check_jacobians(&Quadratic { error: 0.0 }, &samples(), FdOptions::default()).unwrap();
        assert_eq!(report.samples, 5);
        assert_eq!(report.contacts.len(), 1);
        // One normal_gaps and one contacts per sample; per contact one full evaluation, one
        // normal_gap, 2 per coordinate per gap pair and 2 in time.
        assert_eq!(report.evaluations, 5 * (2 + 2 + 2 * 2 + 2));
        assert!(report.passed(1e-7), "{report:?}");
        assert!(report.worst().unwrap().scaled < 1e-8);
    }

    #[test]
    fn planted_error_is_found_with_its_component_and_size() {
        let report =
            check_jacobians(&Quadratic { error: 1e-3 }, &samples(), FdOptions::default()).unwrap();
        let worst = report.worst().unwrap();
        assert_eq!(worst.component, Component::WN { coordinate: 1 });
        assert!((worst.abs - 1e-3).abs() < 1e-8, "{worst:?}");
        assert!(!report.passed(1e-6));
        assert_eq!(report.failures(1e-6).count(), 1);
        let err = assert_consistent(&Quadratic { error: 1e-3 }, &samples(), 1e-6).unwrap_err();
        match err {
            KinematicsError::JacobianMismatch { contact, component, abs, .. } => {
                assert_eq!(contact, 0);
                assert_eq!(component, Component::WN { coordinate: 1 });
                assert!((abs - 1e-3).abs() < 1e-8);
            }
            other => panic!("unexpected error {other:?}"),
        }
    }

    /// Writes w_N but forgets w_T.
    struct Forgetful;

    impl ContactKinematics for Forgetful {
        fn num_coordinates(&self) -> usize {
            1
        }
        fn num_contacts(&self) -> usize {
            2
        }
        fn normal_gap(&self, _i: usize, q: &[f64], _t: f64) -> f64 {
            q[0]
        }
        fn contact(
            &self,
            i: usize,
            q: &[f64],
            _t: f64,
            w_n: &mut [f64],
            w_t: &mut [f64],
        ) -> ContactPoint {
            w_n[0] = 1.0;
            if i == 0 {
                w_t[0] = 0.0;
            }
            ContactPoint { g_n: q[0], ..ContactPoint::default() }
        }
    }

    /// Correct per-contact kinematics with a batched gap that drops a term.
    struct BatchedGapOff;

    impl ContactKinematics for BatchedGapOff {
        fn num_coordinates(&self) -> usize {
            1
        }
        fn num_contacts(&self) -> usize {
            2
        }
        fn normal_gap(&self, i: usize, q: &[f64], _t: f64) -> f64 {
            q[0] + i as f64
        }
        fn normal_gaps(&self, q: &[f64], _t: f64, g: &mut [f64]) {
            g[0] = q[0];
            g[1] = q[0] + 0.5;
        }
        fn contact(
            &self,
            i: usize,
            q: &[f64],
            _t: f64,
            w_n: &mut [f64],
            w_t: &mut [f64],
        ) -> ContactPoint {
            w_n[0] = 1.0;
            w_t[0] = 0.0;
            ContactPoint { g_n: q[0] + i as f64, ..ContactPoint::default() }
        }
    }

    /// Contact 1's batched w_T differs from its single one.
    struct BatchedContactOff;

    impl ContactKinematics for BatchedContactOff {
        fn num_coordinates(&self) -> usize {
            2
        }
        fn num_contacts(&self) -> usize {
            2
        }
        fn normal_gap(&self, i: usize, q: &[f64], _t: f64) -> f64 {
            q[i]
        }
        fn contact(
            &self,
            i: usize,
            q: &[f64],
            _t: f64,
            w_n: &mut [f64],
            w_t: &mut [f64],
        ) -> ContactPoint {
            w_n.fill(0.0);
            w_t.fill(0.0);
            w_n[i] = 1.0;
            ContactPoint { g_n: q[i], ..ContactPoint::default() }
        }
        fn contacts(
            &self,
            which: &[usize],
            q: &[f64],
            t: f64,
            w_n: &mut [f64],
            w_t: &mut [f64],
            points: &mut [ContactPoint],
        ) {
            for (k, &i) in which.iter().enumerate() {
                points[k] = self.contact(i, q, t, &mut w_n[2 * k..], &mut w_t[2 * k..2 * k + 2]);
                if i == 1 {
                    w_t[2 * k] = 0.25;
                }
            }
        }
    }

    #[test]
    fn a_batched_contact_that_disagrees_is_flagged() {
        let report =
            check_jacobians(&BatchedContactOff, &[(vec![0.5, 1.0], 0.0)], FdOptions::default())
                .unwrap();
        let worst = report.worst().unwrap();
        assert_eq!((worst.contact, worst.component), (1, Component::Contacts));
        assert_eq!((worst.analytic, worst.reference), (0.25, 0.0));
        assert_eq!(report.failures(1e-6).count(), 1);
    }

    #[test]
    fn a_batched_gap_that_disagrees_is_flagged() {
        let report =
            check_jacobians(&BatchedGapOff, &[(vec![0.25], 0.0)], FdOptions::default()).unwrap();
        let worst = report.worst().unwrap();
        assert_eq!((worst.contact, worst.component), (1, Component::NormalGaps));
        assert!((worst.abs - 0.5).abs() < 1e-15, "{worst:?}");
        assert_eq!(report.failures(1e-6).count(), 1);
    }

    #[test]
    fn checker_types_are_send_and_sync() {
        fn assert_send_sync<T: Send + Sync>() {}
        assert_send_sync::<FdOptions>();
        assert_send_sync::<FdReport>();
        assert_send_sync::<KinematicsError>();
        assert_send_sync::<crate::ContactGeometry<3>>();
        assert_send_sync::<crate::LineMotion<3>>();
    }

    #[test]
    fn unwritten_force_directions_are_reported() {
        let err =
            check_jacobians(&Forgetful, &[(vec![0.5], 0.0)], FdOptions::default()).unwrap_err();
        assert_eq!(
            err,
            KinematicsError::NonFinite { what: "w_T", contact: Some(1), sample: Some(0) }
        );
        let text = err.to_string();
        assert!(text.starts_with("non-finite w_T at contact 1, sample state 0: an entry left"));
        let q = KinematicsError::NonFinite { what: "q", contact: None, sample: Some(2) };
        assert_eq!(q.to_string(), "non-finite q at sample state 2");
    }

    #[test]
    fn wrong_inputs_are_typed_errors() {
        let k = Quadratic { error: 0.0 };
        assert_eq!(check_jacobians(&k, &[], FdOptions::default()), Err(KinematicsError::NoSamples));
        assert!(matches!(
            check_jacobians(&k, &[(vec![1.0], 0.0)], FdOptions::default()),
            Err(KinematicsError::DimensionMismatch { expected: 2, found: 1, .. })
        ));
        assert!(matches!(
            check_jacobians(&k, &[(vec![1.0, f64::NAN], 0.0)], FdOptions::default()),
            Err(KinematicsError::NonFinite { what: "q", sample: Some(0), .. })
        ));
        let bad = FdOptions { rel_step: 0.0, ..FdOptions::default() };
        assert!(matches!(
            check_jacobians(&k, &samples(), bad),
            Err(KinematicsError::InvalidOption { name: "rel_step", .. })
        ));
        assert!(matches!(
            assert_consistent(&k, &samples(), f64::NAN),
            Err(KinematicsError::InvalidOption { .. })
        ));
    }
}
