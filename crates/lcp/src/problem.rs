//! The problem types: an owned [`Lcp`] and a borrowed [`LcpRef`].
#![allow(non_snake_case)]

use faer::{Col, ColRef, Mat, MatRef};

use crate::LcpError;

/// A validated linear complementarity problem LCP(M, q): find z with
/// `w = M z + q`, `0 <= z ⊥ w >= 0`.
///
/// M is a dense square n x n matrix and q a vector of length n >= 1, all entries finite
/// and at most [`MAX_ENTRY`] in magnitude.
/// The problem owns its data; [`Lcp::view`] gives the borrowed [`LcpRef`] that the
/// solvers take.
#[derive(Clone, Debug, PartialEq)]
pub struct Lcp {
    m: Mat<f64>,
    q: Col<f64>,
}

/// A borrowed, validated view of an LCP (M, q): the allocation-free entry point of the
/// solvers, for callers that assemble M and q in their own buffers.
#[derive(Clone, Copy, Debug)]
pub struct LcpRef<'a> {
    m: MatRef<'a, f64>,
    q: ColRef<'a, f64>,
}

/// The largest magnitude of an entry of M or q that the solvers accept: 2^500 ≈ 3.3e150.
///
/// Products of two entries then stay below 2^1000 and sums of up to 2^23 such products stay
/// finite, so the pivots, factorisations and residuals of the solvers do not overflow on
/// data of ordinary range. Entries near f64's largest value (1.8e308) would make w = M z + q
/// overflow even for z of order one (`M = 1e308`, `z = 2`), so a solver could neither
/// represent nor check a solution. Such a problem is refused with
/// [`LcpError::OutOfRange`]; scaling it first keeps its solutions: a row of (M, q) times any
/// positive factor leaves z unchanged, and a column j of M times `c_j > 0` maps z_j to
/// `z_j / c_j`.
pub const MAX_ENTRY: f64 = {
    // 2^500, built in the exponent bits (a literal power would need a const pow).
    f64::from_bits((1023 + 500) << 52)
};

/// Checks shape, finiteness and range (at most [`MAX_ENTRY`] in magnitude) of (M, q)
/// without allocating.
fn validate(m: MatRef<'_, f64>, q: ColRef<'_, f64>) -> Result<(), LcpError> {
    let (rows, cols) = (m.nrows(), m.ncols());
    if rows != cols {
        return Err(LcpError::NotSquare { rows, cols });
    }
    if rows == 0 {
        return Err(LcpError::Empty);
    }
    if q.nrows() != rows {
        return Err(LcpError::DimensionMismatch { what: "q", expected: rows, found: q.nrows() });
    }
    // One pass without early exits (x · 0 is 0 for a finite x and NaN otherwise, and the
    // largest magnitude ignores NaN); the offending entry is looked for only when there is
    // one.
    let (mut poison, mut big) = (0.0, 0.0f64);
    for j in 0..cols {
        let col = m.col(j);
        if let Some(slice) = col.try_as_col_major().map(|c| c.as_slice()) {
            for v in slice {
                poison += v * 0.0;
                big = big.max(v.abs());
            }
        } else {
            for i in 0..rows {
                poison += col[i] * 0.0;
                big = big.max(col[i].abs());
            }
        }
    }
    for i in 0..rows {
        poison += q[i] * 0.0;
        big = big.max(q[i].abs());
    }
    if poison != 0.0 {
        return Err(first_non_finite(m, q));
    }
    if big > MAX_ENTRY {
        return Err(first_out_of_range(m, q));
    }
    Ok(())
}

/// The error naming the first entry of M (column by column), else of q, above
/// [`MAX_ENTRY`] in magnitude.
#[cold]
fn first_out_of_range(m: MatRef<'_, f64>, q: ColRef<'_, f64>) -> LcpError {
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            if m[(i, j)].abs() > MAX_ENTRY {
                return LcpError::OutOfRange { what: "M", index: (i, j), value: m[(i, j)] };
            }
        }
    }
    let i = (0..q.nrows()).find(|&i| q[i].abs() > MAX_ENTRY).unwrap_or(0);
    LcpError::OutOfRange { what: "q", index: (i, 0), value: q[i] }
}

/// The error naming the first non-finite entry of M (column by column), else of q.
#[cold]
fn first_non_finite(m: MatRef<'_, f64>, q: ColRef<'_, f64>) -> LcpError {
    for j in 0..m.ncols() {
        for i in 0..m.nrows() {
            if !m[(i, j)].is_finite() {
                return LcpError::NonFinite { what: "M", index: (i, j) };
            }
        }
    }
    let i = (0..q.nrows()).find(|&i| !q[i].is_finite()).unwrap_or(0);
    LcpError::NonFinite { what: "q", index: (i, 0) }
}

impl Lcp {
    /// Builds an LCP from an n x n matrix M and a vector q of length n.
    ///
    /// # Errors
    /// [`LcpError::NotSquare`], [`LcpError::Empty`], [`LcpError::DimensionMismatch`],
    /// [`LcpError::NonFinite`] or [`LcpError::OutOfRange`] (an entry above [`MAX_ENTRY`]
    /// in magnitude) when the data is not a valid LCP.
    pub fn new(m: Mat<f64>, q: Col<f64>) -> Result<Lcp, LcpError> {
        validate(m.as_ref(), q.as_ref())?;
        Ok(Lcp { m, q })
    }

    /// Builds an LCP from the rows of M and the vector q.
    ///
    /// # Errors
    /// As [`Lcp::new`]; the first row whose length is not the number of rows gives
    /// [`LcpError::RaggedRow`] with its index.
    pub fn from_rows(rows: &[Vec<f64>], q: &[f64]) -> Result<Lcp, LcpError> {
        let n = rows.len();
        if let Some((row, bad)) = rows.iter().enumerate().find(|(_, r)| r.len() != n) {
            return Err(LcpError::RaggedRow { row, expected: n, found: bad.len() });
        }
        let m = Mat::from_fn(n, n, |i, j| rows[i][j]);
        let q = Col::from_fn(q.len(), |i| q[i]);
        Lcp::new(m, q)
    }

    /// Builds an LCP from M stored column by column (`m[i + j n] = M_ij`) and q.
    ///
    /// # Errors
    /// As [`Lcp::new`]; `m.len() != n n` gives [`LcpError::DimensionMismatch`].
    pub fn from_column_major(n: usize, m: &[f64], q: &[f64]) -> Result<Lcp, LcpError> {
        LcpRef::from_column_major(n, m, q).map(|view| view.to_owned())
    }

    /// The size n of the problem.
    pub fn n(&self) -> usize {
        self.q.nrows()
    }

    /// The matrix M.
    pub fn m(&self) -> MatRef<'_, f64> {
        self.m.as_ref()
    }

    /// The vector q.
    pub fn q(&self) -> ColRef<'_, f64> {
        self.q.as_ref()
    }

    /// The borrowed view that the solvers take.
    pub fn view(&self) -> LcpRef<'_> {
        LcpRef { m: self.m.as_ref(), q: self.q.as_ref() }
    }
}

impl<'a> LcpRef<'a> {
    /// Validates (square, sizes, finite entries within [`MAX_ENTRY`]) and wraps M and q, without allocating.
    ///
    /// # Errors
    /// As [`Lcp::new`].
    pub fn new(m: MatRef<'a, f64>, q: ColRef<'a, f64>) -> Result<Self, LcpError> {
        validate(m, q)?;
        Ok(LcpRef { m, q })
    }

    /// A view of M stored column by column in a slice (`m[i + j n] = M_ij`) and q, checked as
    /// [`Self::new`] checks, in one pass over the two slices: for callers that assemble small
    /// problems in their own buffers, many times.
    ///
    /// # Errors
    /// [`LcpError::Empty`] for n = 0, [`LcpError::DimensionMismatch`] when `m` does not
    /// have n² entries (`expected` is `usize::MAX` when n² overflows) or `q` n, [`LcpError::NonFinite`] for a non-finite entry and
    /// [`LcpError::OutOfRange`] for one above [`MAX_ENTRY`] in magnitude.
    pub fn from_column_major(n: usize, m: &'a [f64], q: &'a [f64]) -> Result<Self, LcpError> {
        // n² beyond usize cannot be the length of a slice: no m matches it.
        let entries = n.checked_mul(n);
        if entries != Some(m.len()) {
            return Err(LcpError::DimensionMismatch {
                what: "M (column-major, n*n entries)",
                expected: entries.unwrap_or(usize::MAX),
                found: m.len(),
            });
        }
        if n == 0 {
            return Err(LcpError::Empty);
        }
        if q.len() != n {
            return Err(LcpError::DimensionMismatch { what: "q", expected: n, found: q.len() });
        }
        let view = LcpRef { m: MatRef::from_column_major_slice(m, n, n), q: ColRef::from_slice(q) };
        // x · 0 is 0 for a finite x and NaN otherwise: one test for all entries, and one
        // for their range.
        let (mut poison, mut big) = (0.0, 0.0f64);
        for v in m.iter().chain(q) {
            poison += v * 0.0;
            big = big.max(v.abs());
        }
        if poison != 0.0 {
            Err(first_non_finite(view.m, view.q))
        } else if big > MAX_ENTRY {
            Err(first_out_of_range(view.m, view.q))
        } else {
            Ok(view)
        }
    }

    /// The size n of the problem.
    pub fn n(&self) -> usize {
        self.q.nrows()
    }

    /// The matrix M.
    pub fn m(&self) -> MatRef<'a, f64> {
        self.m
    }

    /// The vector q.
    pub fn q(&self) -> ColRef<'a, f64> {
        self.q
    }

    /// Copies the data into an owned [`Lcp`].
    pub fn to_owned(&self) -> Lcp {
        Lcp { m: self.m.to_owned(), q: self.q.to_owned() }
    }

    /// Copies M into `out` in row-major order (`out[i n + j] = M_ij`).
    pub(crate) fn copy_m_row_major(&self, out: &mut [f64]) {
        let n = self.n();
        for j in 0..n {
            let col = self.m.col(j);
            if let Some(slice) = col.try_as_col_major().map(|c| c.as_slice()) {
                for (i, v) in slice.iter().enumerate() {
                    out[i * n + j] = *v;
                }
            } else {
                for i in 0..n {
                    out[i * n + j] = col[i];
                }
            }
        }
    }

    /// Copies the columns of M listed in `cols` into `out`, one after the other (`out[t n + i]
    /// = M_i,cols[t]`).
    pub(crate) fn copy_columns(&self, cols: &[usize], out: &mut [f64]) {
        let n = self.n();
        for (dst, &j) in out.chunks_exact_mut(n).zip(cols) {
            let col = self.m.col(j);
            if let Some(slice) = col.try_as_col_major().map(|c| c.as_slice()) {
                dst.copy_from_slice(slice);
            } else {
                for (i, v) in dst.iter_mut().enumerate() {
                    *v = col[i];
                }
            }
        }
    }

    /// Copies q into `out`.
    pub(crate) fn copy_q(&self, out: &mut [f64]) {
        if let Some(slice) = self.q.try_as_col_major().map(|c| c.as_slice()) {
            out[..slice.len()].copy_from_slice(slice);
        } else {
            for (i, v) in out.iter_mut().enumerate().take(self.n()) {
                *v = self.q[i];
            }
        }
    }
}
