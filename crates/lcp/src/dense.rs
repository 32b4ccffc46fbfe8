//! Small dense LU factorisations on a reusable workspace.
//!
//! The solvers factor principal submatrices `M_αα` (Lemke's final basis, every
//! complementary basis of the enumeration). Below [`FAER_MIN`] the factorisation is a
//! plain partial-pivoting loop over a preallocated column-major buffer, because faer's
//! calls cost more than the whole factorisation at these sizes; from [`FAER_MIN`] on,
//! faer's allocation-free `lu_in_place` and `solve_in_place` run on the same buffer.
#![allow(non_snake_case)]

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::perm::PermRef;
use faer::{MatMut, MatRef, Par};

/// Size from which faer's blocked LU is used instead of the plain loop.
pub(crate) const FAER_MIN: usize = 32;

/// A pivot `|u_kk|` at or below this fraction of the largest magnitude in the original
/// column k marks the matrix as numerically singular.
pub(crate) const SINGULAR_RELATIVE: f64 = 1e-13;

/// Reusable LU workspace for square systems of size up to the largest size seen.
#[derive(Default)]
pub(crate) struct Lu {
    a: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    colmax: Vec<f64>,
    rowscale: Vec<f64>,
    k: usize,
    stack: Option<MemBuffer>,
    stack_for: usize,
}

impl Lu {
    /// Sizes the workspace for systems up to n x n, so that later factorisations of any
    /// size k <= n do not allocate.
    pub(crate) fn reserve(&mut self, n: usize) {
        if self.a.len() < n * n {
            self.a.resize(n * n, 0.0);
        }
        if self.perm.len() < n {
            self.perm.resize(n, 0);
            self.perm_inv.resize(n, 0);
            self.colmax.resize(n, 0.0);
            self.rowscale.resize(n, 0.0);
        }
        if n >= FAER_MIN && (self.stack.is_none() || self.stack_for < n) {
            self.stack = Some(MemBuffer::new(Self::scratch(n)));
            self.stack_for = n;
        }
    }

    /// Fills the k x k matrix with `entry(i, j)`, factors it, and returns `false` when it
    /// is numerically singular (see [`SINGULAR_RELATIVE`]) or has non-finite entries.
    pub(crate) fn factor_with(
        &mut self,
        k: usize,
        mut entry: impl FnMut(usize, usize) -> f64,
    ) -> bool {
        self.k = k;
        self.reserve(k);
        if k == 0 {
            return true;
        }
        // Rows are equilibrated by powers of two (exact in floating point) so that partial
        // pivoting is not misled by rows of very different magnitude.
        self.rowscale[..k].fill(0.0);
        for j in 0..k {
            let col = &mut self.a[j * k..(j + 1) * k];
            for (i, slot) in col.iter_mut().enumerate() {
                let v = entry(i, j);
                *slot = v;
                self.rowscale[i] = self.rowscale[i].max(v.abs());
            }
        }
        for r in self.rowscale[..k].iter_mut() {
            if !(r.is_finite() && *r > 0.0) {
                return false;
            }
            *r = pow2_inverse(*r);
        }
        for j in 0..k {
            let mut cmax = 0.0f64;
            let col = &mut self.a[j * k..(j + 1) * k];
            for (slot, r) in col.iter_mut().zip(&self.rowscale[..k]) {
                *slot *= r;
                cmax = cmax.max(slot.abs());
            }
            if cmax == 0.0 {
                return false;
            }
            self.colmax[j] = cmax;
        }
        if k >= FAER_MIN { self.factor_faer() } else { self.factor_plain() }
    }

    fn factor_plain(&mut self) -> bool {
        let k = self.k;
        let a = &mut self.a[..k * k];
        for (i, p) in self.perm[..k].iter_mut().enumerate() {
            *p = i;
        }
        for c in 0..k {
            // Partial pivoting: the largest magnitude in column c at or below the diagonal.
            let mut p = c;
            let mut best = a[c * k + c].abs();
            for i in c + 1..k {
                let v = a[c * k + i].abs();
                if v > best {
                    best = v;
                    p = i;
                }
            }
            if !(best > SINGULAR_RELATIVE * self.colmax[c]) {
                return false;
            }
            if p != c {
                for j in 0..k {
                    a.swap(j * k + c, j * k + p);
                }
                self.perm.swap(c, p);
            }
            let inv = 1.0 / a[c * k + c];
            for i in c + 1..k {
                a[c * k + i] *= inv;
            }
            let (left, right) = a.split_at_mut((c + 1) * k);
            let lcol = &left[c * k + c + 1..c * k + k];
            for col in right.chunks_exact_mut(k) {
                let f = col[c];
                if f != 0.0 {
                    for (x, l) in col[c + 1..].iter_mut().zip(lcol) {
                        *x -= l * f;
                    }
                }
            }
        }
        true
    }

    fn scratch(k: usize) -> StackReq {
        factor::lu_in_place_scratch::<usize, f64>(k, k, Par::Seq, Default::default())
            .or(solve::solve_in_place_scratch::<usize, f64>(k, 1, Par::Seq))
    }

    fn factor_faer(&mut self) -> bool {
        let k = self.k;
        let Some(buf) = self.stack.as_mut() else { return false };
        let mat = MatMut::from_column_major_slice_mut(&mut self.a[..k * k], k, k);
        factor::lu_in_place(
            mat,
            &mut self.perm[..k],
            &mut self.perm_inv[..k],
            Par::Seq,
            MemStack::new(buf),
            Default::default(),
        );
        (0..k).all(|c| {
            let u = self.a[c * k + c].abs();
            u > SINGULAR_RELATIVE * self.colmax[c]
        })
    }

    /// Solves `A x = rhs` in place with the last successful factorisation.
    pub(crate) fn solve(&mut self, rhs: &mut [f64]) {
        let k = self.k;
        if k == 0 {
            return;
        }
        let rhs = &mut rhs[..k];
        for (x, r) in rhs.iter_mut().zip(&self.rowscale[..k]) {
            *x *= r;
        }
        if k >= FAER_MIN {
            let Some(buf) = self.stack.as_mut() else { return };
            let lu = MatRef::from_column_major_slice(&self.a[..k * k], k, k);
            let perm = PermRef::new_checked(&self.perm[..k], &self.perm_inv[..k], k);
            let rhs = MatMut::from_column_major_slice_mut(rhs, k, 1);
            solve::solve_in_place(lu, lu, perm, rhs, Par::Seq, MemStack::new(buf));
            return;
        }
        let a = &self.a[..k * k];
        // The plain factorisation swapped whole rows, so row i of the factors is row
        // perm[i] of A, and the right-hand side must be gathered the same way.
        permute_in_place(rhs, &self.perm[..k], &mut self.perm_inv[..k]);
        for c in 0..k {
            let x = rhs[c];
            if x != 0.0 {
                for i in c + 1..k {
                    rhs[i] -= a[c * k + i] * x;
                }
            }
        }
        for c in (0..k).rev() {
            let x = rhs[c] / a[c * k + c];
            rhs[c] = x;
            if x != 0.0 {
                for i in 0..c {
                    rhs[i] -= a[c * k + i] * x;
                }
            }
        }
    }
}

/// Largest system that [`solve_tiny`] solves.
pub(crate) const TINY_MAX: usize = 6;

/// Solves the k × k system `A x = rhs` (k ≤ [`TINY_MAX`], `A_rc = entry(r, c)`) in place
/// by Gaussian elimination with partial pivoting on stack arrays, for the few-row bases
/// of a time-stepper's contacts where the equilibrated [`Lu`] costs more than the
/// arithmetic. Returns `false` (rhs then undefined) when a pivot is zero or not finite.
/// It makes no accuracy claim: callers check the residual of the result.
pub(crate) fn solve_tiny(k: usize, entry: impl Fn(usize, usize) -> f64, rhs: &mut [f64]) -> bool {
    // One copy per order, so that the loops have constant bounds and unroll.
    match k {
        0 => true,
        1 => solve_fixed::<1>(entry, rhs),
        2 => solve_fixed::<2>(entry, rhs),
        3 => solve_fixed::<3>(entry, rhs),
        4 => solve_fixed::<4>(entry, rhs),
        5 => solve_fixed::<5>(entry, rhs),
        6 => solve_fixed::<6>(entry, rhs),
        _ => false,
    }
}

/// [`solve_tiny`] for one order K.
#[inline(always)]
fn solve_fixed<const K: usize>(entry: impl Fn(usize, usize) -> f64, rhs: &mut [f64]) -> bool {
    let rhs: &mut [f64; K] = match (&mut rhs[..K]).try_into() {
        Ok(r) => r,
        Err(_) => return false,
    };
    let mut a = [[0.0f64; K]; K];
    for (r, row) in a.iter_mut().enumerate() {
        for (c, v) in row.iter_mut().enumerate() {
            *v = entry(r, c);
        }
    }
    let mut x = *rhs;
    for c in 0..K {
        let mut p = c;
        for r in c + 1..K {
            if a[r][c].abs() > a[p][c].abs() {
                p = r;
            }
        }
        let pivot = a[p][c];
        if !(pivot != 0.0 && pivot.is_finite()) {
            return false;
        }
        a.swap(c, p);
        x.swap(c, p);
        let inv = 1.0 / pivot;
        let pivot_row = a[c];
        for r in c + 1..K {
            let f = a[r][c] * inv;
            // The whole row, so that the loop has constant bounds: the entries left of the
            // pivot column are never read again.
            for j in 0..K {
                a[r][j] -= f * pivot_row[j];
            }
            x[r] -= f * x[c];
        }
    }
    for c in (0..K).rev() {
        let mut v = x[c];
        for j in c + 1..K {
            v -= a[c][j] * x[j];
        }
        x[c] = v / a[c][c];
    }
    *rhs = x;
    true
}

/// One step of iterative refinement of `x` for `M_{rows, cols} x = -q_rows` with the
/// factors in `lu` (M row-major, n columns); `r` is scratch of length `rows.len()`.
///
/// It restores a componentwise small backward error when the rows or columns of the
/// system are of very different magnitude.
pub(crate) fn refine(
    lu: &mut Lu,
    m_rows: &[f64],
    n: usize,
    rows: &[usize],
    cols: &[usize],
    q: &[f64],
    x: &mut [f64],
    r: &mut [f64],
) {
    for (t, &i) in rows.iter().enumerate() {
        let row = &m_rows[i * n..(i + 1) * n];
        let mut acc = -q[i];
        for (u, &j) in cols.iter().enumerate() {
            acc -= row[j] * x[u];
        }
        r[t] = acc;
    }
    lu.solve(r);
    for (xi, ri) in x.iter_mut().zip(r.iter()).take(cols.len()) {
        *xi += ri;
    }
}

/// A power of two within a factor 2 of `1 / x` (x > 0, finite): `2^-e` for the binary
/// exponent e of x, read from its bits, with e clamped to [-1000, 1000]. Scaling by it is
/// exact.
#[inline]
pub(crate) fn pow2_inverse(x: f64) -> f64 {
    let e = ((x.to_bits() >> 52) & 0x7ff) as i64 - 1023;
    let e = e.clamp(-1000, 1000);
    f64::from_bits(((1023 - e) as u64) << 52)
}

/// Reorders `v` so that `v_new[i] = v_old[perm[i]]`, using `mark` as scratch.
fn permute_in_place(v: &mut [f64], perm: &[usize], mark: &mut [usize]) {
    let k = v.len();
    for m in mark.iter_mut() {
        *m = 0;
    }
    for start in 0..k {
        if mark[start] != 0 || perm[start] == start {
            continue;
        }
        // Follow the cycle start -> perm[start] -> ... moving values forward.
        let first = v[start];
        let mut i = start;
        loop {
            mark[i] = 1;
            let src = perm[i];
            if src == start {
                v[i] = first;
                break;
            }
            v[i] = v[src];
            i = src;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(k: usize, seed: u64) {
        let mut rng = moreau_testsupport::SplitMix64::new(seed);
        let mut next = || rng.uniform(-1.0, 1.0);
        let a: Vec<f64> = (0..k * k).map(|_| next()).collect();
        let x: Vec<f64> = (0..k).map(|_| next()).collect();
        let mut b = vec![0.0; k];
        for i in 0..k {
            for j in 0..k {
                b[i] += a[j * k + i] * x[j];
            }
        }
        let mut lu = Lu::default();
        assert!(lu.factor_with(k, |i, j| a[j * k + i]));
        lu.solve(&mut b);
        for i in 0..k {
            assert!((b[i] - x[i]).abs() < 1e-9, "k={k} i={i}: {} vs {}", b[i], x[i]);
        }
    }

    #[test]
    fn plain_and_faer_paths_solve_random_systems() {
        for k in [1, 2, 3, 5, 9, 17, 31, 32, 40, 64] {
            check(k, k as u64 * 7 + 1);
        }
    }

    #[test]
    fn pow2_inverse_is_a_nearby_power_of_two() {
        for x in [1.0, 0.75, 3.0, 1e-9, 1e6, 5e-300, 1e300] {
            let r = pow2_inverse(x);
            assert_eq!(r.to_bits() & ((1u64 << 52) - 1), 0, "{x}: {r} is not a power of two");
            assert!(r * x > 0.5 && r * x <= 2.0, "{x}: {r}");
        }
        // Outside 2^-1000..2^1000 the exponent is clamped, keeping the scale finite.
        assert_eq!(pow2_inverse(f64::MIN_POSITIVE), 2f64.powi(1000));
        assert_eq!(pow2_inverse(f64::MAX), 2f64.powi(-1000));
    }

    #[test]
    fn singular_matrix_is_reported() {
        let mut lu = Lu::default();
        assert!(!lu.factor_with(2, |_, _| 1.0));
        assert!(!lu.factor_with(40, |i, j| (i + j) as f64));
    }
}
