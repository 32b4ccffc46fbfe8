//! The stepper's checks of what a mechanism hands it: finite states, forces and force
//! directions, directions written in full, finite rheonomic terms.

use moreau_kinematics::ContactPoint;

use moreau_lcp::Status;

use crate::StepError;

#[inline(always)]
pub(super) fn check_finite(what: &'static str, v: &[f64], t: f64) -> Result<(), StepError> {
    if v.iter().all(|x| x.is_finite()) {
        return Ok(());
    }
    let index = v.iter().position(|x| !x.is_finite()).unwrap_or(0);
    Err(StepError::NonFinite { what, index, t })
}

/// (t, q, u) as a state of a mechanism of f coordinates: q and u of f entries each (else
/// [`StepError::Dimension`]), t, q and u finite (else [`StepError::NonFinite`], t first).
pub(crate) fn check_state(f: usize, t: f64, q: &[f64], u: &[f64]) -> Result<(), StepError> {
    for (what, len) in [("q", q.len()), ("u", u.len())] {
        if len != f {
            return Err(StepError::Dimension { what, expected: f, found: len });
        }
    }
    if !t.is_finite() {
        return Err(StepError::NonFinite { what: "t", index: 0, t });
    }
    check_finite("q", q, t)?;
    check_finite("u", u, t)
}

/// What the stepper writes into the buffers of w_N and w_T before it asks the mechanism for
/// them: a NaN whose payload no arithmetic produces, so that an entry the mechanism leaves
/// alone is told apart from one it computed as NaN.
pub(super) const UNWRITTEN: f64 = f64::from_bits(0x7ff8_0000_dead_beef);

/// Fills buffers of force directions with [`UNWRITTEN`].
#[inline(always)]
pub(super) fn mark_unwritten(w_n: &mut [f64], w_t: &mut [f64]) {
    w_n.fill(UNWRITTEN);
    w_t.fill(UNWRITTEN);
}

/// The force directions w_N and w_T of contact `contact` must be written and finite; the
/// error names the first entry that is not: an entry left at [`UNWRITTEN`] as
/// [`LcpFailure::Unwritten`], otherwise by its index in w_N's entries, then w_T's.
#[inline(always)]
pub(super) fn check_directions(contact: usize, w_n: &[f64], w_t: &[f64]) -> Result<(), LcpFailure> {
    match w_n.iter().chain(w_t).position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(index) => Err(unwritten_or_non_finite(contact, w_n, w_t, index)),
    }
}

/// The failure of [`check_directions`] at entry `index` of w_N, w_T.
#[cold]
#[inline(never)]
fn unwritten_or_non_finite(contact: usize, w_n: &[f64], w_t: &[f64], index: usize) -> LcpFailure {
    let f = w_n.len();
    let value = if index < f { w_n[index] } else { w_t[index - f] };
    if value.to_bits() != UNWRITTEN.to_bits() {
        return LcpFailure::NonFinite { what: "w_N/w_T", index };
    }
    let (what, entry) = if index < f { ("w_N", index) } else { ("w_T", index - f) };
    LcpFailure::Unwritten { what, contact, entry }
}

/// The rheonomic terms ŵ_N, ŵ_T of the contacts `which` (their `points`) must be finite; the
/// error names the first contact whose terms are not, by its index among all contacts.
#[cold]
#[inline(never)]
pub(super) fn check_rheonomic(which: &[usize], points: &[ContactPoint]) -> Result<(), LcpFailure> {
    match which.iter().zip(points).find(|(_, p)| !(p.w_n_hat.is_finite() && p.w_t_hat.is_finite()))
    {
        None => Ok(()),
        Some((&index, _)) => Err(LcpFailure::NonFinite { what: "ŵ_N/ŵ_T of contact", index }),
    }
}

/// Names the first non-finite value among h, u_E and q_E of a step (in that order); `Ok` when
/// all are finite after all.
#[cold]
#[inline(never)]
pub(super) fn diagnose_non_finite(
    h: &[f64],
    u: &[f64],
    q: &[f64],
    t: f64,
) -> Result<(), StepError> {
    check_finite("h", h, t)?;
    check_finite("u", u, t)?;
    check_finite("q", q, t)
}

/// Internal failure of a contact step, turned into a [`StepError`] with context.
pub(super) enum LcpFailure {
    NonFinite { what: &'static str, index: usize },
    Unwritten { what: &'static str, contact: usize, entry: usize },
    Input(moreau_lcp::LcpError),
    Solver(moreau_lcp::LcpError),
    Status(Status),
}
