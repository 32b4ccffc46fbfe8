//! [`BodyStructure`]: the opt-in structure of a mechanism made of rigid bodies in maximal
//! coordinates, whose contacts are found anew at each step.
//!
//! A mechanism of many bodies (a pile of grains, a stack of boxes) has a mass matrix made of one
//! 3 × 3 block per body and contacts that each touch at most two bodies; which pairs touch
//! changes from step to step. The stepper then keeps M⁻¹ by blocks, stores each contact's force
//! directions as two 3-vectors, and solves each step's contact problem on sparse 2 × 2 blocks,
//! island by island, instead of the dense rows of length f that suit a mechanism of a few
//! coordinates. Its joints' rows are split by body the same way ([`BodyBilateral`]) and join
//! the islands' problems as bilateral groups.

use moreau_kinematics::ContactPoint;
use moreau_setvalued::ContactLaw;

use crate::BilateralPoint;

/// The body index of a contact's side that carries no coordinates: a fixed or driven body.
pub const NO_BODY: u32 = u32::MAX;

/// One contact found at (q, t) between at most two bodies with coordinates.
///
/// Body `k` owns q[3k..3k + 3] = (x, y, θ) and the same entries of u. The generalised force
/// direction w_N of the contact has non-zero entries only in the coordinates of its two bodies:
/// `w_n[s]` holds those of body `bodies[s]` (and is ignored when `bodies[s]` is [`NO_BODY`]).
/// The same holds for w_T.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyContact {
    /// The contact's identity, the same from step to step while the same two features touch
    /// (a pair of bodies and a vertex or edge of each, say): the stepper warm-starts the
    /// contact from the impulses last found under this identity, and reports it by it.
    pub id: u64,
    /// The two bodies the contact acts on, [`NO_BODY`] for a side without coordinates.
    pub bodies: [u32; 2],
    /// w_N restricted to each body's (x, y, θ): `w_n[s]` belongs to `bodies[s]`.
    pub w_n: [[f64; 3]; 2],
    /// w_T restricted to each body's (x, y, θ): `w_t[s]` belongs to `bodies[s]`.
    pub w_t: [[f64; 3]; 2],
    /// The gap g_N, tangential position g_T and rheonomic terms ŵ_N, ŵ_T (non-zero when a
    /// side is driven).
    pub point: ContactPoint,
    /// The contact's restitution and friction (ε_N, ε_T, μ).
    pub law: ContactLaw,
}

/// One bilateral constraint row (a joint's equation g_B(q, t) = 0) at (q, t), restricted to
/// the at most two bodies with coordinates it acts on.
///
/// As for a [`BodyContact`], `w[s]` holds the entries of w_B = (∂g_B/∂q)ᵀ in the coordinates
/// (x, y, θ) of body `bodies[s]`, ignored when `bodies[s]` is [`NO_BODY`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyBilateral {
    /// The two bodies the row acts on, [`NO_BODY`] for a side without coordinates.
    pub bodies: [u32; 2],
    /// w_B restricted to each body's (x, y, θ): `w[s]` belongs to `bodies[s]`.
    pub w: [[f64; 3]; 2],
    /// g_B and ŵ_B = ∂g_B/∂t.
    pub point: BilateralPoint,
}

impl Default for BodyBilateral {
    /// A row on no body, with w_B = 0 and g_B = ŵ_B = 0.
    fn default() -> Self {
        Self { bodies: [NO_BODY; 2], w: [[0.0; 3]; 2], point: BilateralPoint::default() }
    }
}

/// The structure of a mechanism made of rigid bodies in maximal coordinates, announced by
/// [`crate::Mechanism::body_structure`].
///
/// With it, the stepper never forms the f × f mass matrix nor rows of length f: it asks for
/// the 3 × 3 mass block of each body and for the contacts closing at each step, found by the
/// mechanism's own detection. The mechanism's [`crate::Mechanism::forces`] still gives h.
/// [`moreau_kinematics::ContactKinematics::num_contacts`] is then not used for the step: the
/// contacts are those [`Self::detect`] returns.
pub trait BodyStructure: Sync {
    /// The number of bodies with coordinates; f = 3 × this.
    fn num_bodies(&self) -> usize;

    /// Writes the 3 × 3 mass block of body `k` at (q, t), column-major, into `blocks[k]`.
    /// Whether it depends on (q, t) is [`crate::Mechanism::constant_mass_matrix`].
    fn mass_blocks(&self, q: &[f64], t: f64, blocks: &mut [[f64; 9]]);

    /// Appends to `out` every contact at (q, t) whose gap g_N is at most `margin`, with its
    /// force directions, in increasing order of [`BodyContact::id`], each id once.
    ///
    /// The stepper passes [`crate::StepperOptions::gap_tolerance`] as the margin and keeps only
    /// the contacts with g_N at most that; it refuses ids out of order and bodies that do not
    /// exist ([`crate::StepError::InvalidContact`]) and non-finite numbers
    /// ([`crate::StepError::NonFinite`]).
    fn detect(&self, q: &[f64], t: f64, margin: f64, out: &mut Vec<BodyContact>);

    /// Writes bilateral constraint i of [`crate::Mechanism::bilaterals`] at (q, t), split by
    /// body, into `rows[i]`, for every `i < rows.len()` = [`crate::Mechanism::num_bilaterals`].
    ///
    /// The stepper solves consecutive rows on the same two bodies as one group of at most two
    /// rows (a revolute joint's two rows together, a weld's three as two and one), and corrects
    /// the positions' drift off g_B = 0 after each step when the projection is on. The
    /// default, for mechanisms without bilateral constraints, writes non-finite values, so that
    /// a mechanism that states constraints but does not split them fails with
    /// [`crate::StepError::NonFinite`] at its first step.
    fn bilateral_rows(&self, q: &[f64], t: f64, rows: &mut [BodyBilateral]) {
        let _ = (q, t);
        let nan = BilateralPoint { g: f64::NAN, w_hat: f64::NAN };
        rows.fill(BodyBilateral { point: nan, ..BodyBilateral::default() });
    }
}
