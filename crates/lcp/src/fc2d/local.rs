//! The exact solution of one contact's (or one bilateral group's) local problem, the step
//! of the nonsmooth Gauss-Seidel method.

use super::residual::natural_map;

/// Solves the local problem of one contact: find r = (r_N, r_T) with u = A r + v,
/// `0 <= r_N ⊥ u_N >= 0`, `|r_T| <= μ r_N` and r_T opposing u_T when the contact slips.
///
/// `a = [A_NN, A_NT, A_TN, A_TT]` is the contact's diagonal block of W (positive
/// semidefinite, possibly unsymmetric by rounding) and v the velocity that the other
/// reactions produce. The cases are tried in turn and the first that satisfies its
/// conditions is returned:
///
/// 1. open: `v_N >= 0`, r = 0;
/// 2. stick: u = 0, `r = -A⁻¹ v` (when A is regular), valid if r lies in the cone;
/// 3. slip with `u_T > 0` then with `u_T < 0`: `r_T = -s μ r_N` with s the sign of u_T,
///    `u_N = 0` gives `r_N = -v_N / (A_NN - s μ A_NT)`, valid if `s u_T >= 0`.
///
/// For μ = 0 the slip cases are the frictionless solution. When rounding (a boundary
/// between two cases, or a singular A) leaves no case exactly valid, the candidate with
/// the smallest local natural map is returned, so the step never fails.
#[inline]
pub(crate) fn solve_contact(a: &[f64; 4], v_n: f64, v_t: f64, mu: f64) -> (f64, f64) {
    if v_n >= 0.0 {
        return (0.0, 0.0);
    }
    let [ann, ant, atn, att] = *a;
    let det = ann * att - ant * atn;
    let scale = ann.abs().max(att.abs());
    let mut stick = None;
    if det > 1e-14 * scale * scale {
        let r_n = (-att * v_n + ant * v_t) / det;
        let r_t = (atn * v_n - ann * v_t) / det;
        if r_n >= 0.0 && r_t.abs() <= mu * r_n {
            return (r_n, r_t);
        }
        stick = Some((r_n, r_t));
    }
    let mut slips = [None; 2];
    for (k, s) in [1.0, -1.0].into_iter().enumerate() {
        let denom = ann - s * mu * ant;
        if denom > 0.0 {
            let r_n = -v_n / denom;
            let u_t = v_t + (atn - s * mu * att) * r_n;
            if s * u_t >= 0.0 {
                return (r_n, -s * mu * r_n);
            }
            slips[k] = Some((r_n, -s * mu * r_n));
        }
    }
    fallback(a, v_n, v_t, mu, [Some((0.0, 0.0)), stick, slips[0], slips[1]])
}

/// The candidate with the smallest local natural map.
#[cold]
fn fallback(
    a: &[f64; 4],
    v_n: f64,
    v_t: f64,
    mu: f64,
    candidates: [Option<(f64, f64)>; 4],
) -> (f64, f64) {
    let mut best = (0.0, 0.0);
    let mut best_error = f64::INFINITY;
    for (r_n, r_t) in candidates.into_iter().flatten() {
        let u_n = a[0] * r_n + a[1] * r_t + v_n;
        let u_t = a[2] * r_n + a[3] * r_t + v_t;
        let (e_n, e_t) = natural_map(r_n, r_t, u_n, u_t, mu);
        let e = e_n * e_n + e_t * e_t;
        if e < best_error {
            best_error = e;
            best = (r_n, r_t);
        }
    }
    best
}

/// Solves the local problem of a bilateral group, `A x + v = 0`, for its free multipliers.
///
/// A one-row group has `x_0 = -v_0 / A_00`; a two-row group solves the 2x2 system. A
/// singular block (a redundant constraint) keeps the rows it cannot determine at `old`,
/// and solves the others alone.
#[inline]
pub(crate) fn solve_bilateral(
    a: &[f64; 4],
    v: (f64, f64),
    rows: usize,
    old: (f64, f64),
) -> (f64, f64) {
    let [a00, a01, a10, a11] = *a;
    if rows == 2 {
        let det = a00 * a11 - a01 * a10;
        let scale = a00.abs().max(a11.abs());
        if det.abs() > 1e-14 * scale * scale {
            return ((-a11 * v.0 + a01 * v.1) / det, (a10 * v.0 - a00 * v.1) / det);
        }
        let x0 = if a00 > 0.0 { -(v.0 + a01 * old.1) / a00 } else { old.0 };
        let x1 = if a11 > 0.0 { -(v.1 + a10 * x0) / a11 } else { old.1 };
        return (x0, x1);
    }
    (if a00 > 0.0 { -v.0 / a00 } else { old.0 }, 0.0)
}
