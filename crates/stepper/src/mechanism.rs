//! The [`Mechanism`] trait: what the time-stepper needs to know of a mechanism.

use moreau_kinematics::{ContactKinematics, ContactPoint};
use moreau_setvalued::ContactLaw;

use crate::bodies::BodyStructure;

/// A planar rigid multibody system with unilateral frictional contacts.
///
/// With `f` generalised coordinates `q` and velocities `u`, the equality of measures
/// `M(q, t) du − h(q, u, t) dt − W_N dP_N − W_T dP_T = 0` is described by the mass matrix `M`,
/// the smooth forces `h`, and, through the [`ContactKinematics`] supertrait, the gaps g_N and
/// force directions w_N, w_T of each contact. Each contact has a [`ContactLaw`] (ε_N, ε_T, μ).
pub trait Mechanism: ContactKinematics {
    /// The laws of the contacts, one per contact, in the order of the kinematics.
    fn laws(&self) -> &[ContactLaw];

    /// Writes the symmetric positive definite mass matrix M(q, t), column-major `f × f`,
    /// into `m` (length `f²`), every entry (the buffer keeps what the last call wrote).
    ///
    /// The stepper refuses with [`crate::StepError::MassNotSpd`] an M whose two triangles
    /// differ beyond 1e-12 of their entries, one with a pivot of its Cholesky factor that is
    /// not positive, and one that is singular to round-off: a pivot L_jj² that keeps at most
    /// 1e-12 of its diagonal entry M_jj (the kinetic energy of coordinate j nearly that of a
    /// combination of the coordinates before it: coordinates that describe one motion twice),
    /// where M⁻¹ would amplify round-off by more than 1e12.
    fn mass_matrix(&self, q: &[f64], t: f64, m: &mut [f64]);

    /// Writes the smooth generalised forces h(q, u, t) (gravity, springs, gyroscopic and
    /// centrifugal terms) into `h` (length `f`). The stepper hands `h` over filled with zeros,
    /// so that a mechanism may write its non-zero entries only (`h[1] = -m * g`).
    fn forces(&self, q: &[f64], u: &[f64], t: f64, h: &mut [f64]);

    /// The potential energy V(q, t) of the conservative part of `h`, if the mechanism has one (J).
    fn potential_energy(&self, q: &[f64], t: f64) -> Option<f64> {
        let _ = (q, t);
        None
    }

    /// Writes the dampers' part h_D(q, u, t) of `h` (viscous forces, already included in
    /// [`Self::forces`]) into `h_d` (length `f`, handed over filled with zeros), and returns
    /// whether the mechanism has dampers; the default has none and writes nothing.
    ///
    /// Only the energy balance reads it: the [`crate::Recorder`] counts the work the dampers
    /// take out of a step, −(Δt/2) h_D(q_M, u_A, t_M)ᵀ (u_A + u_E), with the impulses' in
    /// [`crate::Record::cumulative_dissipation`], so that kinetic plus potential energy plus
    /// the dissipation stays at its start (to the midpoint rule's error on the springs).
    fn damping_forces(&self, q: &[f64], u: &[f64], t: f64, h_d: &mut [f64]) -> bool {
        let _ = (q, u, t, h_d);
        false
    }

    /// Whether M does not depend on `q` and `t`, so that the stepper may factorise it once.
    fn constant_mass_matrix(&self) -> bool {
        false
    }

    /// The number n_B of bilateral constraints g_B(q, t) = 0 (the equations of joints): 0 by
    /// default. Their impulses are free in sign and are found in the same step problem as the
    /// contacts' (docs/theory.md section 9).
    fn num_bilaterals(&self) -> usize {
        0
    }

    /// Bilateral constraint `i` at (q, t): writes its force direction w_B = (∂g_B/∂q)ᵀ into `w`
    /// (length f; every entry must be written) and returns g_B and ŵ_B = ∂g_B/∂t.
    ///
    /// Called only for `i < num_bilaterals()`. The default, for mechanisms without bilateral
    /// constraints, writes zeros and returns non-finite values, so that a mechanism that
    /// states constraints but does not write them fails with a typed error at its first step.
    fn bilateral(&self, i: usize, q: &[f64], t: f64, w: &mut [f64]) -> BilateralPoint {
        let _ = (i, q, t);
        w.fill(0.0);
        BilateralPoint { g: f64::NAN, w_hat: f64::NAN }
    }

    /// All bilateral constraints at (q, t) in one call: W_B of constraint i into
    /// `w[i f..(i + 1) f]` (every entry written) and its g_B and ŵ_B into `points[i]`, for
    /// `i < num_bilaterals()`.
    ///
    /// The default calls [`Self::bilateral`] for each constraint; a mechanism whose
    /// constraints share work (the sines and cosines of the same bodies' angles) overrides it
    /// with the same values.
    fn bilaterals(&self, q: &[f64], t: f64, w: &mut [f64], points: &mut [BilateralPoint]) {
        let f = q.len();
        for (i, (w, point)) in w.chunks_exact_mut(f.max(1)).zip(points.iter_mut()).enumerate() {
            *point = self.bilateral(i, q, t, w);
        }
    }

    /// The mechanism's [`SharedWork`], when it shares work between M, h, the gaps and the
    /// closed contacts' kinematics: `None` by default. A mechanism that implements
    /// [`SharedWork`] returns `Some(self)`, and the stepper then calls it instead of
    /// [`Self::mass_matrix`], [`Self::forces`] and [`ContactKinematics::normal_gaps`] once per
    /// step; [`crate::check_evaluate`] checks that it gives the same values.
    fn shared_work(&self) -> Option<&dyn SharedWork> {
        None
    }

    /// Whether q holds rigid bodies in maximal coordinates, (x, y, θ) of one body after
    /// another, so that M is block diagonal by 3 × 3 blocks M_k whose first entry is the
    /// body's mass m_k: `false` by default. A mechanism with a [`BodyStructure`] is taken to
    /// be so whatever this says.
    ///
    /// The contact projection ([`crate::StepperOptions::projection`]) then measures its
    /// correction body by body in M_k / m_k instead of M: every body weighs alike, so that a
    /// light body is not moved farther than a heavy one (docs/theory.md §4).
    fn maximal_coordinates(&self) -> bool {
        false
    }

    /// The mechanism's [`BodyStructure`], when it is made of rigid bodies in maximal
    /// coordinates whose contacts are detected at each step: `None` by default. With it the
    /// stepper keeps M by 3 × 3 blocks and each contact's force directions by body, finds the
    /// contacts through [`BodyStructure::detect`] at every step, and solves their problem by
    /// islands on sparse blocks, so that thousands of bodies and contacts cost what they touch.
    fn body_structure(&self) -> Option<&dyn BodyStructure> {
        None
    }
}

/// An opt-in speed hook: everything the stepper evaluates at the midpoint of a step, in one
/// call, for a mechanism whose M, h, gaps and contact kinematics share work (the sines and
/// cosines of the same angles, say). A mechanism that implements it says so through
/// [`Mechanism::shared_work`]; its values must be those of the [`Mechanism`] methods, which
/// [`crate::check_evaluate`] verifies.
pub trait SharedWork {
    /// M(q, t) into `mass` (skipped when `None`, as when a constant M is already
    /// factorised), h(q, u, t) into `h` (handed over filled with zeros, as to
    /// [`Mechanism::forces`]) and the normal gaps of all contacts into `gaps`.
    ///
    /// `memo` (length [`Self::memo_len`]) keeps what the same step's
    /// [`Self::midpoint_contacts`] may reuse at this q. The stepper passes it back unchanged,
    /// and only at the same q and t.
    #[allow(clippy::too_many_arguments)]
    fn evaluate(
        &self,
        q: &[f64],
        u: &[f64],
        t: f64,
        mass: Option<&mut [f64]>,
        h: &mut [f64],
        gaps: &mut [f64],
        memo: &mut [f64],
    );

    /// The length of the `memo` that [`Self::evaluate`] fills for
    /// [`Self::midpoint_contacts`].
    fn memo_len(&self) -> usize;

    /// [`ContactKinematics::contacts`] at the q and t of the last [`Self::evaluate`], which
    /// left `memo` as it was.
    #[allow(clippy::too_many_arguments)]
    fn midpoint_contacts(
        &self,
        which: &[usize],
        q: &[f64],
        t: f64,
        memo: &[f64],
        w_n: &mut [f64],
        w_t: &mut [f64],
        points: &mut [ContactPoint],
    );

    /// [`Mechanism::bilaterals`] at the q and t of the last [`Self::evaluate`], which left
    /// `memo` as it was: the same values into `w` and `points`, and `true`. The default
    /// writes nothing and returns `false`, and the stepper then calls
    /// [`Mechanism::bilaterals`].
    fn midpoint_bilaterals(
        &self,
        q: &[f64],
        t: f64,
        memo: &[f64],
        w: &mut [f64],
        points: &mut [BilateralPoint],
    ) -> bool {
        let _ = (q, t, memo, w, points);
        false
    }
}

/// M, h and the gaps at the midpoint: through the mechanism's [`SharedWork`] when it has one,
/// otherwise by [`Mechanism::mass_matrix`], [`Mechanism::forces`] and
/// [`ContactKinematics::normal_gaps`].
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn evaluate<M: Mechanism + ?Sized>(
    mech: &M,
    q: &[f64],
    u: &[f64],
    t: f64,
    mass: Option<&mut [f64]>,
    h: &mut [f64],
    gaps: &mut [f64],
    memo: &mut [f64],
) {
    // h arrives zeroed (`Mechanism::forces`): the buffer holds the last step's values, or
    // for more than 8 coordinates M⁻¹ h of the last step.
    h.fill(0.0);
    match mech.shared_work() {
        Some(shared) => shared.evaluate(q, u, t, mass, h, gaps, memo),
        None => {
            if let Some(m) = mass {
                mech.mass_matrix(q, t, m);
            }
            mech.forces(q, u, t, h);
            mech.normal_gaps(q, t, gaps);
        }
    }
}

/// The closed contacts' kinematics at the midpoint of the last [`evaluate`]: through the
/// mechanism's [`SharedWork`] when it has one, otherwise [`ContactKinematics::contacts`].
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn midpoint_contacts<M: Mechanism + ?Sized>(
    mech: &M,
    which: &[usize],
    q: &[f64],
    t: f64,
    memo: &[f64],
    w_n: &mut [f64],
    w_t: &mut [f64],
    points: &mut [ContactPoint],
) {
    match mech.shared_work() {
        Some(shared) => shared.midpoint_contacts(which, q, t, memo, w_n, w_t, points),
        None => mech.contacts(which, q, t, w_n, w_t, points),
    }
}

/// The bilateral constraints at the midpoint of the last [`evaluate`]: through the
/// mechanism's [`SharedWork`] when it computes them from its memo, otherwise
/// [`Mechanism::bilaterals`].
#[inline(always)]
pub(crate) fn midpoint_bilaterals<M: Mechanism + ?Sized>(
    mech: &M,
    q: &[f64],
    t: f64,
    memo: &[f64],
    w: &mut [f64],
    points: &mut [BilateralPoint],
) {
    let kept = mech.shared_work().is_some_and(|s| s.midpoint_bilaterals(q, t, memo, w, points));
    if !kept {
        mech.bilaterals(q, t, w, points);
    }
}

/// The scalars of one bilateral constraint at (q, t), besides its force direction w_B.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BilateralPoint {
    /// The constraint's value g_B(q, t): zero on the constraint, its drift otherwise (m or rad).
    pub g: f64,
    /// The rheonomic term ŵ_B = ∂g_B/∂t, non-zero for a driven joint such as a motor (m/s or
    /// rad/s).
    pub w_hat: f64,
}
