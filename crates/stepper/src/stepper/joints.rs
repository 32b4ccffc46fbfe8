//! Bilateral constraints (joints) in the step: the constrained inverse mass, which the contact
//! problem then uses in place of M⁻¹, and the projection of the positions back onto the
//! constraints.
//!
//! With n_B bilateral constraints g_B(q, t) = 0, force directions W_B = (∂g_B/∂q)ᵀ and
//! rheonomic terms ŵ_B = ∂g_B/∂t, the constraints' velocity is γ_B = W_Bᵀ u + ŵ_B. The step
//! asks, with W_B and ŵ_B at the midpoint (γ_B,M) and at the start (γ_B,A),
//!
//!   γ_B,M(u_E) = −(γ_B,M(u_A) − γ_B,A(u_A)):
//!
//! the velocity of the constraints at the midpoint vanishes on the average of u_A and u_E once
//! the violation at the start, γ_B,A(u_A), is taken away. A start that keeps the joints then
//! gives g_B(q_E) − g_B(q_A) = O(Δt³) and impulses that do no work, and a start that violates
//! them (a starting velocity, or one left by the step before) is brought onto them by an
//! impulse that removes that violation's energy alone (docs/theory.md section 9). The impulses
//! Λ_B are free; eliminating them by the Schur complement S = W_Bᵀ M⁻¹ W_B leaves the contact
//! problem of the unilateral contacts alone, with b_B = ŵ_B,M + γ_B,M(u_A) − γ_B,A(u_A) and
//! * the free velocity ũ' = ũ − M⁻¹ W_B S⁻¹ (W_Bᵀ ũ + b_B), which satisfies the constraints;
//! * M̂⁻¹ w = M⁻¹ w − M⁻¹ W_B S⁻¹ W_Bᵀ M⁻¹ w in place of M⁻¹ w for each contact direction w.
//!
//! M̂⁻¹ is symmetric positive semidefinite, so the contact problem keeps the structure every
//! solver expects, and u_E = ũ' + M̂⁻¹ (W_N P_N + W_T P_T) satisfies the constraints whatever
//! the contact impulses are.
#![allow(non_snake_case)]

use crate::dense::{Cholesky, dot, factor_small, solve_small, weigh_bodies_alike};
use crate::mechanism::midpoint_bilaterals;
use crate::{BilateralPoint, Mechanism, StepError};

/// The ridge added to a singular S, relative to its largest diagonal entry.
const RIDGE: f64 = 1e-10;

/// The smallest share of its diagonal entry a pivot of S's factor may keep before S counts
/// as singular.
const SINGULAR: f64 = 1e-12;

/// The smallest share of its diagonal entry a pivot of the held contacts' K = Vᵀ M⁻¹ V may
/// keep before the correction counts as dominated by round-off.
const HELD_SINGULAR: f64 = 1e-10;

/// Largest number of corrections of the positions per step (on both paths).
pub(super) const PROJECTION_ITERATIONS: usize = 4;

/// The refusal of a step whose midpoint leaves the joints by `drift`, above 1e11 times the
/// drift tolerance at q (on both paths): see [`StepError::JointsApart`].
pub(super) fn check_apart(
    q: &[f64],
    joint_tolerance: f64,
    drift: f64,
    t: f64,
) -> Result<(), StepError> {
    let limit = 1e11 * drift_tolerance(q, joint_tolerance);
    if drift > limit {
        return Err(StepError::JointsApart { t, drift, limit });
    }
    Ok(())
}

/// The refusal of a correction of the positions that took the joints' largest drift from
/// `before` to `after` in [`PROJECTION_ITERATIONS`] corrections, when it grew and ends above
/// 1e3 times the drift `tolerance` (on both paths): simplified Newton corrections shrink a
/// step's drift unless W_B disagrees with g_B or the step is long enough for the joints'
/// directions to turn through it; a slow contraction is left to the next step.
pub(super) fn check_correction(
    before: f64,
    after: f64,
    tolerance: f64,
    t: f64,
) -> Result<(), StepError> {
    if (after > before && after > 1e3 * tolerance) || !after.is_finite() {
        return Err(StepError::JointCorrectionDiverged { t, before, after });
    }
    Ok(())
}

/// The drift |g_B| that the correction of the positions leaves alone at q (on both paths):
/// `StepperOptions::joint_tolerance` when it is set, else 1e-12 max(1, ‖q‖∞), round-off of
/// the positions.
pub(super) fn drift_tolerance(q: &[f64], joint_tolerance: f64) -> f64 {
    if joint_tolerance > 0.0 {
        joint_tolerance
    } else {
        1e-12 * q.iter().fold(1.0f64, |s, v| s.max(v.abs()))
    }
}

/// The bilateral constraints' part of a stepper's workspace.
pub(super) struct Joints {
    /// Number of bilateral constraints n_B.
    pub(super) n: usize,
    /// Number of coordinates f.
    f: usize,
    /// W_B, one column of length f per constraint.
    w: Vec<f64>,
    /// M⁻¹ W_B, one column of length f per constraint.
    x: Vec<f64>,
    /// b_B = ŵ_B,M + γ_B,M(u_A) − γ_B,A(u_A) and g_B (at the midpoint) of each constraint at the
    /// last assembly.
    b: Vec<f64>,
    g: Vec<f64>,
    /// The constraints' scalars as the mechanism returns them.
    points: Vec<BilateralPoint>,
    /// S = W_Bᵀ M⁻¹ W_B (column-major) and its factor.
    s: Vec<f64>,
    s_chol: Cholesky,
    /// The ridge added to S's diagonal when S is singular (constraints that repeat each
    /// other); 0 when S is positive definite.
    ridge: f64,
    /// The largest |W_Bᵀ v + b_B| of the last velocity constrained, before.
    violation: f64,
    /// Scratch of length n_B for the refinement of a solve with the ridge.
    rhs: Vec<f64>,
    correction: Vec<f64>,
    /// Scratch of length n_B.
    y: Vec<f64>,
    /// g_B at the projected positions, and W_B there (scratch, one column of length f per
    /// constraint): kept apart from the midpoint's, which M̂⁻¹ still uses.
    g_end: Vec<f64>,
    w_end: Vec<f64>,
    /// Whether `w_end` and `points` hold W_B and the constraints' scalars at the stepper's
    /// current (q, t): the correction of the positions ended on them, and nothing moved q
    /// since. The next step's start is then that evaluation.
    at_start: bool,
    /// The projection's M⁻¹ w_N of the contacts it holds, its matrix K over the constraints
    /// and those contacts, K's factor, and its right-hand side; sized at the first projection
    /// for every contact closed at once.
    held_x: Vec<f64>,
    k: Vec<f64>,
    k_rhs: Vec<f64>,
}

impl Joints {
    /// The workspace for `n` constraints on `f` coordinates.
    pub(super) fn new(n: usize, f: usize) -> Self {
        Self {
            n,
            f,
            w: vec![0.0; f * n],
            x: vec![0.0; f * n],
            b: vec![0.0; n],
            g: vec![0.0; n],
            points: vec![BilateralPoint::default(); n],
            s: vec![0.0; n * n],
            s_chol: Cholesky::new(n),
            ridge: 0.0,
            violation: 0.0,
            rhs: vec![0.0; n],
            correction: vec![0.0; n],
            y: vec![0.0; n],
            g_end: vec![0.0; n],
            w_end: vec![0.0; f * n],
            at_start: false,
            held_x: Vec::new(),
            k: Vec::new(),
            k_rhs: Vec::new(),
        }
    }

    /// The largest |g_B| at the last assembly (m or rad, as the constraints are written).
    pub(super) fn drift(&self) -> f64 {
        self.g.iter().fold(0.0, |d, g| d.max(g.abs()))
    }

    /// Forgets the constraints' evaluation at the end of the last correction, once q has moved
    /// from there (or a new state is set).
    pub(super) fn moved(&mut self) {
        self.at_start = false;
    }

    /// Evaluates the constraints at the start (`q_a`, `t_a`) and at the midpoint (`q_m`, `t_m`,
    /// from the `memo` of the step's evaluation there when the mechanism can), their offsets
    /// b_B = ŵ_B,M + γ_B,M(u_A) − γ_B,A(u_A) with the start velocity `u_a`, forms S at the
    /// midpoint with the factor `chol` of M and factorises it.
    ///
    /// # Errors
    /// [`StepError::NonFinite`] for non-finite g_B, ŵ_B or W_B, and
    /// [`StepError::RedundantConstraints`] when S is zero (a joint whose two bodies are both
    /// fixed); a singular S (constraints that repeat each other) is factored with a ridge.
    pub(super) fn assemble<K: Mechanism>(
        &mut self,
        mech: &K,
        (q_a, u_a, t_a): (&[f64], &[f64], f64),
        (q_m, t_m, memo): (&[f64], f64, &[f64]),
        chol: &Cholesky,
    ) -> Result<(), StepError> {
        let (f, n) = (self.f, self.n);
        // γ_B,A(u_A) into b, with W_B at the start in the projection's scratch, where the last
        // step's correction may have left it.
        if !self.at_start {
            mech.bilaterals(q_a, t_a, &mut self.w_end, &mut self.points);
        }
        self.at_start = false;
        for i in 0..n {
            self.b[i] = -(dot(&self.w_end[i * f..][..f], u_a) + self.points[i].w_hat);
            if !self.b[i].is_finite() {
                return Err(StepError::NonFinite {
                    what: "bilateral constraint",
                    index: i,
                    t: t_a,
                });
            }
        }
        let t = t_m;
        midpoint_bilaterals(mech, q_m, t, memo, &mut self.w, &mut self.points);
        for i in 0..n {
            let w = &self.w[i * f..][..f];
            let point = self.points[i];
            self.g[i] = point.g;
            let finite = point.g.is_finite() && point.w_hat.is_finite();
            if !finite || w.iter().any(|v| !v.is_finite()) {
                return Err(StepError::NonFinite { what: "bilateral constraint", index: i, t });
            }
            self.b[i] += 2.0 * point.w_hat + dot(w, u_a);
            let x = &mut self.x[i * f..][..f];
            x.copy_from_slice(w);
            chol.solve(x);
        }
        self.factor_s(t)
    }

    /// Forms M⁻¹ W_B and S again in the metric G = M_k / m_k body by body, in which every
    /// body weighs alike, for the contact projection of a mechanism in maximal coordinates
    /// (`mass` column-major M; see [`weigh_bodies_alike`]). [`Self::constrain`] then keeps
    /// the constraints in G; the next step's [`Self::assemble`] forms them in M again.
    ///
    /// # Errors
    /// [`StepError::RedundantConstraints`] when S is zero.
    pub(super) fn weigh_bodies_alike(&mut self, mass: &[f64], t: f64) -> Result<(), StepError> {
        for x in self.x.chunks_exact_mut(self.f) {
            weigh_bodies_alike(x, mass);
        }
        self.factor_s(t)
    }

    /// Forms S = W_Bᵀ X from W_B and X = `self.x`, and factorises it.
    fn factor_s(&mut self, t: f64) -> Result<(), StepError> {
        let (f, n) = (self.f, self.n);
        for c in 0..n {
            for r in c..n {
                let v = dot(&self.w[r * f..][..f], &self.x[c * f..][..f]);
                self.s[r + c * n] = v;
                self.s[c + r * n] = v;
            }
        }
        self.ridge = 0.0;
        let e = match self.s_chol.factor_unrolled(&self.s) {
            Ok(()) if self.s_chol.smallest_pivot_ratio(&self.s) > SINGULAR => return Ok(()),
            // A pivot that kept less than 1e-12 of its diagonal: S is singular to round-off,
            // and its factor would amplify that round-off into the impulses.
            Ok(()) => "singular to round-off".to_owned(),
            Err(e) => e.to_string(),
        };
        // Constraints that repeat each other (a parallelogram with a third crank) make S
        // singular, but their rows agree: S Λ_B = r has solutions, all of which move the
        // bodies alike (W_B Λ_B is the same), and S + ρ I picks one. The velocity the ridge
        // leaves is checked after each step's solve ([`Self::check_kept`]); a joint between
        // two bodies that cannot move (a zero S) is refused.
        let largest = (0..n).map(|i| self.s[i + i * n]).fold(0.0f64, f64::max);
        let ridge = RIDGE * largest;
        let refused = |e: &str| StepError::RedundantConstraints { t, reason: e.to_owned() };
        if !(ridge > 0.0 && ridge.is_finite()) {
            return Err(refused(&e));
        }
        for i in 0..n {
            self.s[i + i * n] += ridge;
        }
        self.s_chol.factor_unrolled(&self.s).map_err(|_| refused(&e))?;
        self.ridge = ridge;
        Ok(())
    }

    /// Solves S y = r in place (`y` holds r on entry). With the ridge of redundant constraints,
    /// the factor is that of S + ρ I, and two corrections y ← y + (S + ρ I)⁻¹ (r − S y)
    /// (iterated Tikhonov) bring a consistent r's solution from a relative error of ρ / λ to
    /// (ρ / λ)³, λ the smallest non-zero eigenvalue of S.
    fn solve_s(&mut self, y: &mut [f64]) {
        let n = self.n;
        if self.ridge == 0.0 {
            self.s_chol.solve(y);
            return;
        }
        self.rhs.copy_from_slice(y);
        self.s_chol.solve(y);
        for _ in 0..2 {
            // r − S y with S = (S + ρ I) − ρ I, as stored.
            for i in 0..n {
                let sy: f64 = (0..n).map(|j| self.s[i + j * n] * y[j]).sum::<f64>();
                self.correction[i] = self.rhs[i] - (sy - self.ridge * y[i]);
            }
            self.s_chol.solve(&mut self.correction);
            for (yi, d) in y.iter_mut().zip(&self.correction) {
                *yi += d;
            }
        }
    }

    /// After [`Self::constrain`] of a velocity `v` with the ridge of redundant constraints,
    /// checks that v keeps them: |W_Bᵀ v + b_B| at most 1e-6 of the largest violation that
    /// the constraining removed (the ridge leaves about 1e-10 of it) plus round-off of its
    /// terms. Redundant rows that disagree (a mechanism locked by its joints) cannot all be
    /// kept, and the step is refused rather than taken off them.
    ///
    /// # Errors
    /// [`StepError::RedundantConstraints`] naming the row that is not kept.
    pub(super) fn check_kept(&self, v: &[f64], t: f64) -> Result<(), StepError> {
        if self.ridge == 0.0 {
            return Ok(());
        }
        let f = self.f;
        for i in 0..self.n {
            let w = &self.w[i * f..][..f];
            let size: f64 =
                w.iter().zip(v).map(|(a, b)| (a * b).abs()).sum::<f64>() + self.b[i].abs();
            let kept = dot(w, v) + self.b[i];
            if kept.abs() > 1e-6 * self.violation + 1e-12 * size {
                return Err(StepError::RedundantConstraints {
                    t,
                    reason: format!(
                        "constraint {i} repeats others that disagree with it: its velocity \
                         {kept:e} is not kept"
                    ),
                });
            }
        }
        Ok(())
    }

    /// Applies the constraints to `v` (length f): v ← v − M⁻¹ W_B S⁻¹ (W_Bᵀ v + b_B) when
    /// `rheonomic` (a velocity, such as ũ), and v ← v − M⁻¹ W_B S⁻¹ W_Bᵀ v otherwise (a
    /// column M⁻¹ w, which becomes M̂⁻¹ w).
    #[inline(always)]
    pub(super) fn constrain(&mut self, v: &mut [f64], rheonomic: bool) {
        if self.n > 0 {
            self.apply(v, rheonomic);
        }
    }

    /// [`Self::constrain`] with at least one constraint.
    #[inline(never)]
    fn apply(&mut self, v: &mut [f64], rheonomic: bool) {
        let (f, n) = (self.f, self.n);
        for i in 0..n {
            let b = if rheonomic { self.b[i] } else { 0.0 };
            self.y[i] = dot(&self.w[i * f..][..f], v) + b;
        }
        if rheonomic {
            self.violation = self.y.iter().fold(0.0f64, |m, y| m.max(y.abs()));
        }
        let mut y = std::mem::take(&mut self.y);
        self.solve_s(&mut y);
        self.y = y;
        for i in 0..n {
            let yi = self.y[i];
            for (vj, xj) in v.iter_mut().zip(&self.x[i * f..][..f]) {
                *vj -= xj * yi;
            }
        }
    }

    /// The joints' impulses Λ_B of the step into `out` (length n_B), from ũ before the
    /// joints (`u_free`) and the contacts' impulses W_c P (`contact_impulses`, length f):
    /// M (u_E − ũ) = W_c P + W_B Λ_B and W_Bᵀ u_E + b_B = 0 give
    /// S Λ_B = −(W_Bᵀ ũ + b_B) − (M⁻¹ W_B)ᵀ W_c P, with the midpoint's W_B, M⁻¹ W_B and S.
    pub(super) fn impulses(&mut self, u_free: &[f64], contact_impulses: &[f64], out: &mut [f64]) {
        let (f, n) = (self.f, self.n);
        for (i, o) in out.iter_mut().enumerate().take(n) {
            *o = -(dot(&self.w[i * f..][..f], u_free)
                + self.b[i]
                + dot(&self.x[i * f..][..f], contact_impulses));
        }
        self.solve_s(&mut out[..n]);
    }

    /// Moves q back onto g_B(q, t) = 0 along M⁻¹ W_B (the correction of least kinetic
    /// metric) while keeping the gaps of the contacts in `held` (their w_N, one column of
    /// length f each): q ← q − M⁻¹ V K⁻¹ r with V = [W_B W_H], K = Vᵀ M⁻¹ V and
    /// r = (g_B(q), 0), at most [`PROJECTION_ITERATIONS`] times, until
    /// |g_B| ≤ `drift_tolerance` (1e-12 max(1, |q|∞) unless the options set one).
    ///
    /// The held contacts are those that carried an impulse in the step: resting or pressed,
    /// they sit at g_N ≈ 0, and a correction along M⁻¹ W_B alone would move them off it by
    /// about the joints' drift, every step; a contact opened so drops out of the next step,
    /// the body falls freely for Δt and the contact projection then pushes it back, so that
    /// a resting contact opens and closes every few steps. When K is not positive definite,
    /// or nearly singular (held contacts that repeat each other or a constraint, as a block
    /// jammed in a guide), the contacts are not held.
    ///
    /// M⁻¹ W_B and the factor of S are those of the step's midpoint assembly (a simplified
    /// Newton method), as are the held contacts' w_N: q_E lies (Δt/2) u_E from q_M, so the
    /// directions move by O(Δt |u|) between them, and each correction shrinks the drift by that
    /// factor; a step's drift of O(Δt²) then falls below the tolerance after one correction.
    /// Only g_B is evaluated at the new positions. The midpoint's M̂⁻¹ stays assembled for the
    /// contact projection that follows, which then keeps the constraints to first order.
    ///
    /// # Errors
    /// [`StepError::NonFinite`] for a non-finite g_B.
    pub(super) fn project<K: Mechanism>(
        &mut self,
        mech: &K,
        q: &mut [f64],
        t: f64,
        chol: &Cholesky,
        held: &[f64],
        joint_tolerance: f64,
    ) -> Result<(), StepError> {
        let (f, n) = (self.f, self.n);
        // K is formed only when a correction is needed.
        let mut holding = None;
        let m = n + held.len() / f;
        let tolerance = drift_tolerance(q, joint_tolerance);
        let mut before = None;
        for pass in 0..=PROJECTION_ITERATIONS {
            let mut drift = 0.0f64;
            mech.bilaterals(q, t, &mut self.w_end, &mut self.points);
            for i in 0..n {
                let g = self.points[i].g;
                if !g.is_finite() {
                    return Err(StepError::NonFinite { what: "bilateral constraint", index: i, t });
                }
                self.g_end[i] = g;
                drift = drift.max(g.abs());
            }
            if drift <= tolerance {
                self.at_start = true;
                return Ok(());
            }
            let before = *before.get_or_insert(drift);
            if pass == PROJECTION_ITERATIONS {
                return check_correction(before, drift, tolerance, t);
            }
            if *holding
                .get_or_insert_with(|| !held.is_empty() && self.factor_held(mech, chol, held))
            {
                let rhs = &mut self.k_rhs[..m];
                rhs[..n].copy_from_slice(&self.g_end);
                rhs[n..].fill(0.0);
                solve_small(&self.k, m, rhs);
                for (c, lambda) in rhs.iter().enumerate() {
                    let x = if c < n {
                        &self.x[c * f..][..f]
                    } else {
                        &self.held_x[(c - n) * f..][..f]
                    };
                    for (qj, xj) in q.iter_mut().zip(x) {
                        *qj -= xj * lambda;
                    }
                }
            } else {
                let mut y = std::mem::take(&mut self.y);
                y.copy_from_slice(&self.g_end);
                self.solve_s(&mut y);
                self.y = y;
                for (i, yi) in self.y.iter().enumerate() {
                    for (qj, xj) in q.iter_mut().zip(&self.x[i * f..][..f]) {
                        *qj -= xj * yi;
                    }
                }
            }
        }
        Ok(())
    }

    /// Forms and factorises K = Vᵀ M⁻¹ V over the constraints and the `held` contacts, with
    /// the factor `chol` of M; false when K is not positive definite or a pivot keeps at most
    /// [`HELD_SINGULAR`] of its diagonal entry, where the correction would be dominated by
    /// round-off.
    fn factor_held<K: Mechanism>(&mut self, mech: &K, chol: &Cholesky, held: &[f64]) -> bool {
        let (f, n) = (self.f, self.n);
        let h = held.len() / f;
        let m = n + h;
        if self.k_rhs.len() < m {
            // Sized once for every contact closed at once, so that later steps do not allocate.
            let most = n + mech.num_contacts().max(h);
            self.held_x.resize(f * (most - n), 0.0);
            self.k.resize(most * most, 0.0);
            self.k_rhs.resize(most, 0.0);
        }
        for c in 0..h {
            let x = &mut self.held_x[c * f..][..f];
            x.copy_from_slice(&held[c * f..][..f]);
            chol.solve(x);
        }
        let k = &mut self.k[..m * m];
        for c in 0..m {
            let x = if c < n { &self.x[c * f..][..f] } else { &self.held_x[(c - n) * f..][..f] };
            for r in c..m {
                let w = if r < n { &self.w[r * f..][..f] } else { &held[(r - n) * f..][..f] };
                let v = dot(w, x);
                k[r + c * m] = v;
                k[c + r * m] = v;
            }
        }
        factor_small::<0>(k, m, HELD_SINGULAR).is_ok()
    }
}
