//! Small dense linear algebra of one step, on column-major slices.
//!
//! The mass matrices of the mechanisms this crate is for have a handful of rows, where a
//! call into faer's general routines costs more than the arithmetic. Up to
//! [`SMALL_LIMIT`] rows the Cholesky factorisation and the triangular solves are plain loops;
//! above it they go through faer's allocation-free kernels into a preallocated buffer.
#![allow(non_snake_case)]

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt;
use faer::{MatMut, MatRef, Par};

/// Largest order factorised with plain loops.
pub(crate) const SMALL_LIMIT: usize = 24;

/// Largest order for which the inverse is formed explicitly, so that a solve is one
/// matrix-vector product without divisions (the common case of a few coordinates, where
/// the triangular solves' divisions dominate).
pub(crate) const INVERSE_LIMIT: usize = 8;

/// The least share L_jj² / M_jj of its diagonal entry that a pivot of a mass matrix's factor
/// keeps (a column j at an angle θ to the columns before it in the metric of M keeps sin² θ):
/// below it M is singular to round-off, as in the joints' S = W_Bᵀ M⁻¹ W_B.
pub(crate) const MASS_SINGULAR: f64 = 1e-12;

/// Why a Cholesky factorisation failed.
#[derive(Debug)]
pub(crate) enum FactorError {
    /// `M[i][j]` and `M[j][i]` differ beyond round-off.
    Asymmetric { i: usize, j: usize },
    /// The pivot of column `index` is not positive.
    NotPositive { index: usize },
    /// The pivot of column `index` kept only `ratio` of its diagonal entry, at most the
    /// factor's least share ([`Cholesky::for_mass_matrix`]): the matrix is singular to
    /// round-off.
    Singular { index: usize, ratio: f64 },
}

impl std::fmt::Display for FactorError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Asymmetric { i, j } => write!(f, "M[{i}][{j}] differs from M[{j}][{i}]"),
            Self::NotPositive { index } => write!(f, "non-positive pivot in column {index}"),
            Self::Singular { index, ratio } => write!(
                f,
                "singular to round-off: the pivot of column {index} keeps {ratio:.1e} of its \
                 diagonal entry (at most {MASS_SINGULAR:e}), so that column is a combination of \
                 the columns before it"
            ),
        }
    }
}

/// A Cholesky factor L (lower triangle, column-major) of an SPD matrix, with its workspace.
pub(crate) struct Cholesky {
    n: usize,
    l: Vec<f64>,
    /// M⁻¹, column-major, for n ≤ [`INVERSE_LIMIT`].
    inverse: Vec<f64>,
    /// L⁻¹ (lower triangle, column-major), scratch of the inverse.
    l_inv: Vec<f64>,
    buffer: Option<MemBuffer>,
    /// The least share of its diagonal entry a pivot keeps (0 but for a mass matrix).
    min_pivot_ratio: f64,
}

impl Cholesky {
    /// Workspace for matrices of order `n`.
    pub(crate) fn new(n: usize) -> Self {
        let buffer = (n > SMALL_LIMIT).then(|| {
            MemBuffer::new(llt::factor::cholesky_in_place_scratch::<f64>(
                n,
                Par::Seq,
                Default::default(),
            ))
        });
        let inverse = if n <= INVERSE_LIMIT { vec![0.0; n * n] } else { Vec::new() };
        let l_inv = inverse.clone();
        Self { n, l: vec![0.0; n * n], inverse, l_inv, buffer, min_pivot_ratio: 0.0 }
    }

    /// Workspace for mass matrices of order `n`, whose factorisation also refuses a matrix
    /// that is singular to round-off ([`FactorError::Singular`], [`MASS_SINGULAR`]).
    pub(crate) fn for_mass_matrix(n: usize) -> Self {
        Self { min_pivot_ratio: MASS_SINGULAR, ..Self::new(n) }
    }

    /// Factorises the column-major matrix `m` (order n), checking symmetry first; `N` as in
    /// [`Self::solve_scaled_add`].
    pub(crate) fn factor<const N: usize>(&mut self, m: &[f64]) -> Result<(), FactorError> {
        let n = order::<N>(self.n);
        let m = &m[..n * n];
        for j in 0..n {
            for i in (j + 1)..n {
                let (a, b) = (m[i + j * n], m[j + i * n]);
                if (a - b).abs() > 1e-12 * (a.abs() + b.abs()).max(f64::MIN_POSITIVE) {
                    return Err(FactorError::Asymmetric { i, j });
                }
            }
        }
        self.l[..n * n].copy_from_slice(m);
        match self.buffer.as_mut() {
            // The stepper states the orders of the common small mechanisms as N.
            None => self.factor_and_invert::<N>(),
            Some(buffer) => {
                let mut l = MatMut::from_column_major_slice_mut(&mut self.l, n, n);
                llt::factor::cholesky_in_place(
                    l.as_mut(),
                    Default::default(),
                    Par::Seq,
                    MemStack::new(buffer),
                    Default::default(),
                )
                .map_err(|_| FactorError::NotPositive { index: first_bad_pivot(m, n) })?;
                let l = &self.l;
                let ratio = |j: usize| l[j + j * n].powi(2) / m[j + j * n];
                match (0..n).find(|&j| ratio(j) <= self.min_pivot_ratio) {
                    Some(index) => Err(FactorError::Singular { index, ratio: ratio(index) }),
                    None => Ok(()),
                }
            }
        }
    }

    /// The smallest ratio L_jj² / m_jj of the last factorisation of `m`: how much of its
    /// diagonal the elimination left, down to round-off when `m` is singular.
    pub(crate) fn smallest_pivot_ratio(&self, m: &[f64]) -> f64 {
        let n = self.n;
        (0..n).map(|j| self.l[j + j * n].powi(2) / m[j + j * n]).fold(f64::INFINITY, f64::min)
    }

    /// [`Self::factor`] with the order stated at compile time for the orders 1 to 6 (the
    /// joints' Schur complements S and the mass matrices of a body or two), where loops of
    /// constant bounds unroll; the general loop otherwise.
    pub(crate) fn factor_unrolled(&mut self, m: &[f64]) -> Result<(), FactorError> {
        match self.n {
            1 => self.factor::<1>(m),
            2 => self.factor::<2>(m),
            3 => self.factor::<3>(m),
            4 => self.factor::<4>(m),
            5 => self.factor::<5>(m),
            6 => self.factor::<6>(m),
            _ => self.factor::<0>(m),
        }
    }

    /// The plain-loop factorisation of `l` (holding M), and M⁻¹ for n ≤ [`INVERSE_LIMIT`];
    /// `N` as in [`factor_small`].
    #[inline(always)]
    fn factor_and_invert<const N: usize>(&mut self) -> Result<(), FactorError> {
        factor_small::<N>(&mut self.l, self.n, self.min_pivot_ratio)?;
        if self.n <= INVERSE_LIMIT {
            invert_from_factor::<N>(&self.l, self.n, &mut self.l_inv, &mut self.inverse);
        }
        Ok(())
    }

    /// Writes `out = base + scale · M⁻¹ x`, using `x` as scratch (all of length n). `N > 0`
    /// states n at compile time, as in [`factor_small`].
    #[inline(always)]
    pub(crate) fn solve_scaled_add<const N: usize>(
        &self,
        x: &mut [f64],
        scale: f64,
        base: &[f64],
        out: &mut [f64],
    ) {
        let n = order::<N>(self.n);
        match n {
            1 => out[0] = base[0] + scale * self.inverse[0] * x[0],
            2..=INVERSE_LIMIT => {
                let inv = &self.inverse[..n * n];
                for i in 0..n {
                    let mut s = 0.0;
                    for j in 0..n {
                        s += inv[i + j * n] * x[j];
                    }
                    out[i] = base[i] + scale * s;
                }
            }
            _ => {
                self.solve(x);
                for i in 0..n {
                    out[i] = base[i] + scale * x[i];
                }
            }
        }
    }

    /// Writes M⁻¹ b into `x` (both of length n); `N` as in [`Self::solve_scaled_add`].
    #[inline(always)]
    pub(crate) fn solve_into<const N: usize>(&self, b: &[f64], x: &mut [f64]) {
        let n = order::<N>(self.n);
        if n <= INVERSE_LIMIT {
            let inv = &self.inverse[..n * n];
            for i in 0..n {
                let mut s = 0.0;
                for j in 0..n {
                    s += inv[i + j * n] * b[j];
                }
                x[i] = s;
            }
        } else {
            x.copy_from_slice(b);
            self.solve(x);
        }
    }

    /// Overwrites `x` (length n) with M⁻¹ x.
    #[inline]
    pub(crate) fn solve(&self, x: &mut [f64]) {
        let n = self.n;
        if n == 1 {
            x[0] *= self.inverse[0];
        } else if n <= INVERSE_LIMIT {
            // The orders of one to three bodies' or joints' matrices with constant bounds.
            match n {
                2 => self.multiply_inverse::<2>(x),
                3 => self.multiply_inverse::<3>(x),
                6 => self.multiply_inverse::<6>(x),
                _ => self.multiply_inverse::<0>(x),
            }
        } else if self.buffer.is_none() {
            solve_small(&self.l, n, x);
        } else {
            let l = MatRef::from_column_major_slice(&self.l, n, n);
            let rhs = MatMut::from_column_major_slice_mut(x, n, 1);
            llt::solve::solve_in_place(l, rhs, Par::Seq, MemStack::new(&mut []));
        }
    }
}

impl Cholesky {
    /// x ← M⁻¹ x by the explicit inverse (n ≤ [`INVERSE_LIMIT`]); `N` as in [`factor_small`].
    #[inline(always)]
    fn multiply_inverse<const N: usize>(&self, x: &mut [f64]) {
        let n = order::<N>(self.n);
        let (inv, x) = (&self.inverse[..n * n], &mut x[..n]);
        let mut y = [0.0; INVERSE_LIMIT];
        for j in 0..n {
            let xj = x[j];
            let col = &inv[j * n..][..n];
            for i in 0..n {
                y[i] += col[i] * xj;
            }
        }
        x.copy_from_slice(&y[..n]);
    }
}

/// In-place Cholesky of a column-major matrix of order n (lower triangle used and written).
/// `N > 0` fixes the order at compile time (n is then ignored), so that the loops of the
/// common small orders have constant bounds; `N = 0` takes n. A pivot that keeps at most
/// `min_ratio` of its diagonal entry is [`FactorError::Singular`] (with `min_ratio` = 0, only a
/// non-positive one fails).
#[inline(always)]
pub(crate) fn factor_small<const N: usize>(
    a: &mut [f64],
    n: usize,
    min_ratio: f64,
) -> Result<(), FactorError> {
    let n = if N == 0 { n } else { N };
    for j in 0..n {
        let diagonal = a[j + j * n];
        let mut d = diagonal;
        for k in 0..j {
            d -= a[j + k * n] * a[j + k * n];
        }
        // `!(d > 0)` also catches NaN.
        if !(d > 0.0) {
            return Err(FactorError::NotPositive { index: j });
        }
        if d <= min_ratio * diagonal {
            return Err(FactorError::Singular { index: j, ratio: d / diagonal });
        }
        let d = d.sqrt();
        a[j + j * n] = d;
        for i in (j + 1)..n {
            let mut s = a[i + j * n];
            for k in 0..j {
                s -= a[i + k * n] * a[j + k * n];
            }
            a[i + j * n] = s / d;
        }
    }
    Ok(())
}

/// M⁻¹ = L⁻ᵀ L⁻¹ from the Cholesky factor L (column-major, lower triangle), with n
/// divisions in all: the divisions of n triangular solves would dominate at these sizes.
/// `N` as in [`factor_small`].
#[inline(always)]
fn invert_from_factor<const N: usize>(l: &[f64], n: usize, l_inv: &mut [f64], inv: &mut [f64]) {
    let n = if N == 0 { n } else { N };
    // L⁻¹ column by column: X_jj = 1 / L_jj, X_ij = −(Σ_{k=j}^{i−1} L_ik X_kj) / L_ii.
    for i in 0..n {
        l_inv[i + i * n] = 1.0 / l[i + i * n];
    }
    for j in 0..n {
        for i in (j + 1)..n {
            let mut s = 0.0;
            for k in j..i {
                s += l[i + k * n] * l_inv[k + j * n];
            }
            l_inv[i + j * n] = -s * l_inv[i + i * n];
        }
    }
    // (M⁻¹)_ij = Σ_{k ≥ max(i, j)} X_ki X_kj.
    for j in 0..n {
        for i in j..n {
            let mut s = 0.0;
            for k in i..n {
                s += l_inv[k + i * n] * l_inv[k + j * n];
            }
            inv[i + j * n] = s;
            inv[j + i * n] = s;
        }
    }
}

/// Solves L Lᵀ x = b in place, with the factor L of [`factor_small`] (order n).
pub(crate) fn solve_small(l: &[f64], n: usize, x: &mut [f64]) {
    for i in 0..n {
        let mut s = x[i];
        for k in 0..i {
            s -= l[i + k * n] * x[k];
        }
        x[i] = s / l[i + i * n];
    }
    for i in (0..n).rev() {
        let mut s = x[i];
        for k in (i + 1)..n {
            s -= l[k + i * n] * x[k];
        }
        x[i] = s / l[i + i * n];
    }
}

/// The first column at which the plain factorisation meets a non-positive pivot (for the
/// error message of the faer path, which does not report it).
fn first_bad_pivot(m: &[f64], n: usize) -> usize {
    let mut a = m.to_vec();
    match factor_small::<0>(&mut a, n, 0.0) {
        Err(FactorError::NotPositive { index }) => index,
        _ => 0,
    }
}

/// xᵀ M x / 2 for a column-major M of order n.
pub(crate) fn half_quadratic(m: &[f64], n: usize, x: &[f64]) -> f64 {
    half_bilinear(m, n, |i| x[i], |j| x[j])
}

/// xᵀ M y / 2 for a column-major M of order n, with the entries of x and y given by index.
#[inline(always)]
pub(crate) fn half_bilinear(
    m: &[f64],
    n: usize,
    x: impl Fn(usize) -> f64,
    y: impl Fn(usize) -> f64,
) -> f64 {
    let mut s = 0.0;
    for j in 0..n {
        let mut c = 0.0;
        for i in 0..n {
            c += m[i + j * n] * x(i);
        }
        s += c * y(j);
    }
    0.5 * s
}

/// The order n of a matrix or vector: `N` when it is stated at compile time (`N > 0`, and
/// then equal to the run-time `n`), otherwise `n`.
#[inline(always)]
pub(crate) fn order<const N: usize>(n: usize) -> usize {
    debug_assert!(N == 0 || N == n);
    if N == 0 { n } else { N }
}

/// The dot product of two slices of equal length.
#[inline]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// x ← m_k x_k body by body, for x = M⁻¹ w of a mechanism in maximal coordinates (M
/// column-major f × f, block diagonal by 3 × 3 blocks whose first entry is the body's mass
/// m_k): then x = G⁻¹ w in the metric G = M_k / m_k, in which every body weighs alike.
pub(crate) fn weigh_bodies_alike(x: &mut [f64], mass: &[f64]) {
    let f = x.len();
    for (k, x_k) in x.chunks_exact_mut(3).enumerate() {
        let m_k = mass[3 * k * (f + 1)];
        x_k.iter_mut().for_each(|v| *v *= m_k);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spd(n: usize) -> Vec<f64> {
        // A = B Bᵀ + n I with a fixed B.
        let b: Vec<f64> = (0..n * n).map(|k| ((k * 7 + 3) % 11) as f64 / 11.0 - 0.5).collect();
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                let mut s = if i == j { n as f64 } else { 0.0 };
                for k in 0..n {
                    s += b[i + k * n] * b[j + k * n];
                }
                a[i + j * n] = s;
            }
        }
        a
    }

    #[test]
    fn small_and_faer_paths_solve_the_same_system() {
        for n in [1, 2, 3, 4, 5, INVERSE_LIMIT, INVERSE_LIMIT + 1, 12, SMALL_LIMIT + 6] {
            let a = spd(n);
            let x_true: Vec<f64> = (0..n).map(|i| (i as f64 + 1.0).sin()).collect();
            let mut b: Vec<f64> =
                (0..n).map(|i| (0..n).map(|j| a[i + j * n] * x_true[j]).sum()).collect();
            let mut c = Cholesky::new(n);
            c.factor::<0>(&a).unwrap();
            c.solve(&mut b);
            for i in 0..n {
                assert!((b[i] - x_true[i]).abs() < 1e-12, "n = {n}, i = {i}");
            }
        }
    }

    #[test]
    fn indefinite_and_asymmetric_matrices_are_rejected() {
        let mut c = Cholesky::new(2);
        assert!(matches!(
            c.factor::<0>(&[1.0, 2.0, 2.0, 1.0]),
            Err(FactorError::NotPositive { index: 1 })
        ));
        assert!(matches!(
            c.factor::<0>(&[1.0, 0.5, 0.0, 1.0]),
            Err(FactorError::Asymmetric { .. })
        ));
        // Every path (fixed orders 2 to 4, the plain loop, faer) names the failing column.
        for n in [3, 4, 5, INVERSE_LIMIT + 1] {
            let mut a = spd(n);
            a[(n - 1) + (n - 1) * n] = -1e6;
            assert!(
                matches!(Cholesky::new(n).factor::<0>(&a), Err(FactorError::NotPositive { index }) if index == n - 1),
                "n = {n}"
            );
        }
        let n = SMALL_LIMIT + 2;
        let mut a = spd(n);
        a[(n - 1) + (n - 1) * n] = -1e6;
        let mut c = Cholesky::new(n);
        assert!(
            matches!(c.factor::<0>(&a), Err(FactorError::NotPositive { index }) if index == n - 1)
        );
    }
}
