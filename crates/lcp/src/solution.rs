//! Results shared by every solver: [`Status`], [`Method`], [`Residual`], [`Solution`],
//! and the [`Solver`] trait.
#![allow(non_snake_case)]

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::{Lcp, LcpError, LcpRef};

/// How a solve ended. Not converging is a status, not an error.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// z and w = M z + q satisfy `0 <= z ⊥ w >= 0` within the solver's tolerance
    /// (see [`Residual::relative`]).
    Solved,
    /// Complete enumeration proved that the LCP has no solution.
    NoSolution,
    /// Lemke's method ended on a secondary ray: no complementary basis was reached. For a
    /// copositive-plus M (for example positive semidefinite) this proves that no solution
    /// exists; for other M it proves nothing.
    RayTermination,
    /// The pivot or iteration limit was reached first.
    IterationLimit,
    /// The method ended but its result failed the residual check, a factorisation was
    /// singular, or the iterates stopped being finite. Also the status of a fresh
    /// [`Solution::new`].
    NumericalFailure,
    /// A complete search was not attempted because the problem is larger than the size
    /// guard (see [`EnumerationOptions`](crate::EnumerationOptions)).
    TooLarge,
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Status::Solved => "solved",
            Status::NoSolution => "no_solution",
            Status::RayTermination => "ray_termination",
            Status::IterationLimit => "iteration_limit",
            Status::NumericalFailure => "numerical_failure",
            Status::TooLarge => "too_large",
        })
    }
}

/// Which method produced a [`Solution`].
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// z = 0, taken at once because q >= 0.
    Trivial,
    /// Lemke's complementary pivoting method ([`Lemke`](crate::Lemke)).
    Lemke,
    /// Projected Gauss-Seidel ([`Pgs`](crate::Pgs)).
    Pgs,
    /// Complete enumeration of complementary bases ([`Enumeration`](crate::Enumeration)).
    Enumeration,
    /// The complementary basis named by a warm start, solved directly
    /// ([`Auto`](crate::Auto) with a warm start).
    WarmBasis,
    /// Solved in closed form by the caller, which checked the few cases of a one-contact
    /// problem (a time-stepper's single active contact); the residual is still computed.
    ClosedForm,
    /// Nonsmooth block Gauss-Seidel on a planar frictional-contact problem
    /// ([`fc2d::Nsgs`](crate::fc2d::Nsgs)).
    Nsgs,
    /// The exact LCP reformulation of a planar frictional-contact problem
    /// ([`fc2d::LcpRoute`](crate::fc2d::LcpRoute)); the LCP solver's method is recorded
    /// beside it.
    LcpRoute,
    /// The nonsmooth Newton method on Alart and Curnier's function for a planar
    /// frictional-contact problem ([`fc2d::Newton`](crate::fc2d::Newton)).
    Newton,
    /// Nonsmooth Gauss-Seidel on a planar frictional-contact problem completed by exact
    /// solves (LCP route) of the clusters of contacts where it stalled
    /// ([`fc2d::Fc2dAuto`](crate::fc2d::Fc2dAuto)).
    NsgsClusters,
    /// The proximal point method on a planar frictional-contact problem, its regularised
    /// sub-problems solved by nonsmooth Newton ([`fc2d::Proximal`](crate::fc2d::Proximal)).
    ProximalNewton,
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Method::Trivial => "trivial",
            Method::Lemke => "lemke",
            Method::Pgs => "pgs",
            Method::Enumeration => "enumeration",
            Method::WarmBasis => "warm_basis",
            Method::ClosedForm => "closed_form",
            Method::Nsgs => "nsgs",
            Method::LcpRoute => "lcp_route",
            Method::Newton => "newton",
            Method::NsgsClusters => "nsgs_clusters",
            Method::ProximalNewton => "proximal_newton",
        })
    }
}

/// The residual of a candidate (z, w) for LCP(M, q): one definition shared by every
/// solver, test and report.
///
/// | field | definition |
/// |---|---|
/// | `natural` | `‖min(z, w)‖∞ / max(1, ‖q‖∞)` (the natural-map residual) |
/// | `complementarity` | `max_i \|z_i w_i\|` |
/// | `z_violation` | `max(0, -min_i z_i)` |
/// | `w_violation` | `max(0, -min_i w_i)` |
/// | `equation` | `‖M z + q - w‖∞` |
/// | `relative` | the scale-free acceptance measure below |
///
/// With the row scale `s_i = max(|q_i|, Σ_j |M_ij z_j|)` (the magnitude of the terms that
/// make up w_i, against which the round-off of `(M z + q)_i` is measured) and
/// `Z = ‖z‖∞`,
///
/// `relative = max_i max( z⁻_i / Z, w⁻_i / s_i, |M z + q - w|_i / s_i, min(z⁺_i / Z, w⁺_i / s_i) )`
///
/// where `x⁺ = max(x, 0)`, `x⁻ = max(-x, 0)` and `0 / 0 = 0`. The last term is the
/// complementarity of z_i and w_i, each measured in its own scale. A solver reports
/// [`Status::Solved`] only when `relative <= tolerance`.
///
/// `relative` does not change when a row of (M, q) is multiplied by a positive number
/// (which leaves the solutions unchanged), so rows of very different magnitude (entries
/// of M from 1e-9 to 1e6) are each checked to the tolerance. A fixed bound such as
/// `max|z_i w_i| <= 1e-9 max(|q|, |M| |z|)` is not scale invariant: it would reject the
/// exact solution z = 1e9 of M = 1e-9, q = -1, and accept wrong z in rows of order 1e-9.
///
/// If z or w has the wrong length or a non-finite entry (or the products overflow), every
/// field is `+∞`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Residual {
    /// `‖min(z, w)‖∞ / max(1, ‖q‖∞)`.
    pub natural: f64,
    /// `max_i |z_i w_i|`.
    pub complementarity: f64,
    /// `max(0, -min_i z_i)`.
    pub z_violation: f64,
    /// `max(0, -min_i w_i)`.
    pub w_violation: f64,
    /// `‖M z + q - w‖∞`.
    pub equation: f64,
    /// The scale-free acceptance measure defined in the type's documentation.
    pub relative: f64,
}

/// `x / s` with `0 / 0 = 0` (x >= 0, s >= 0).
#[inline]
fn ratio(x: f64, s: f64) -> f64 {
    if x <= 0.0 {
        0.0
    } else if s > 0.0 {
        x / s
    } else {
        f64::INFINITY
    }
}

/// `max(a, b)` as one compare; a NaN in `b` is dropped (the residual tracks non-finite
/// values separately).
#[inline]
fn fmax(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

/// Running maxima for a residual; shared by the generic and the row-major kernels.
#[derive(Clone, Debug)]
struct Acc {
    q_max: f64,
    z_max: f64,
    natural: f64,
    complementarity: f64,
    z_violation: f64,
    w_violation: f64,
    equation: f64,
    relative: f64,
    /// `false` once any z_i, w_i or `(M z + q)_i` was not finite.
    finite: bool,
}

impl Acc {
    fn new(z: &[f64]) -> Acc {
        Acc {
            q_max: 0.0,
            z_max: z.iter().fold(0.0f64, |a, v| fmax(a, v.abs())),
            natural: 0.0,
            complementarity: 0.0,
            z_violation: 0.0,
            w_violation: 0.0,
            equation: 0.0,
            relative: 0.0,
            finite: true,
        }
    }

    /// One row: `mz_abs = Σ_j |M_ij z_j|`, `mzq = (M z + q)_i` as computed.
    #[inline]
    fn row(&mut self, q: f64, z: f64, w: f64, mz_abs: f64, mzq: f64) {
        self.finite &= z.is_finite() & w.is_finite() & mzq.is_finite();
        self.q_max = fmax(self.q_max, q.abs());
        self.natural = fmax(self.natural, if z < w { z } else { w }.abs());
        self.complementarity = fmax(self.complementarity, (z * w).abs());
        self.z_violation = fmax(self.z_violation, -z);
        self.w_violation = fmax(self.w_violation, -w);
        let eq = (mzq - w).abs();
        self.equation = fmax(self.equation, eq);
        // The w terms against the row scale s_i; the z violation against Z = ‖z‖∞ is added
        // in `finish`. Divisions only happen for nonzero terms.
        let s = fmax(q.abs(), mz_abs);
        if w < 0.0 || eq > 0.0 {
            let w_rel = fmax(ratio(-w, s), ratio(eq, s));
            self.relative = fmax(self.relative, w_rel);
        }
        if z > 0.0 && w > 0.0 {
            // The complementarity term min(z_i / Z, w_i / s_i) matters only if it can
            // raise the maximum.
            let wp = ratio(w, s);
            if wp > self.relative {
                let zr = if self.z_max > 0.0 { z / self.z_max } else { 0.0 };
                self.relative = fmax(self.relative, if zr < wp { zr } else { wp });
            }
        }
    }

    fn finish(self) -> Residual {
        let r = Residual {
            natural: self.natural / fmax(self.q_max, 1.0),
            complementarity: self.complementarity,
            z_violation: self.z_violation,
            w_violation: self.w_violation,
            equation: self.equation,
            relative: fmax(self.relative, ratio(self.z_violation, self.z_max)),
        };
        if !self.finite
            || [r.natural, r.complementarity, r.z_violation, r.w_violation, r.equation, r.relative]
                .iter()
                .any(|v| v.is_nan())
        {
            Residual::INFINITE
        } else {
            r
        }
    }
}

/// [`Residual`] accumulated row by row, for an M that is not stored densely (a block-sparse
/// problem reformulated as an LCP): each row gives q_i, z_i, w_i, `Σ_j |M_ij z_j|` and
/// `(M z + q)_i`, and [`ResidualRows::finish`] gives the residual [`Residual::compute`] would
/// give for the same rows.
///
/// Every quantity it keeps is a maximum, so rows may be given in any order and split among
/// several accumulators started alike (clones of one fresh accumulator), then combined by
/// [`ResidualRows::merge`]: the result is the same, bit for bit, as one accumulator given
/// every row.
#[derive(Clone, Debug)]
pub struct ResidualRows {
    acc: Acc,
}

impl ResidualRows {
    /// Starts a residual for the candidate z, given as its entries in any order (only
    /// `‖z‖∞` is taken from them).
    pub fn new(z: impl IntoIterator<Item = f64>) -> ResidualRows {
        let z_max = z.into_iter().fold(0.0f64, |a, v| fmax(a, v.abs()));
        let mut acc = Acc::new(&[]);
        acc.z_max = z_max;
        ResidualRows { acc }
    }

    /// Adds row i: `q_i`, `z_i`, `w_i`, `Σ_j |M_ij z_j|` and `(M z + q)_i` as computed.
    #[inline]
    pub fn row(&mut self, q: f64, z: f64, w: f64, mz_abs: f64, mzq: f64) {
        self.acc.row(q, z, w, mz_abs, mzq);
    }

    /// Takes in the rows given to `other`, an accumulator started with the same z.
    pub fn merge(&mut self, other: &ResidualRows) {
        let (a, b) = (&mut self.acc, &other.acc);
        debug_assert_eq!(a.z_max.to_bits(), b.z_max.to_bits(), "accumulators started alike");
        a.q_max = fmax(a.q_max, b.q_max);
        a.natural = fmax(a.natural, b.natural);
        a.complementarity = fmax(a.complementarity, b.complementarity);
        a.z_violation = fmax(a.z_violation, b.z_violation);
        a.w_violation = fmax(a.w_violation, b.w_violation);
        a.equation = fmax(a.equation, b.equation);
        a.relative = fmax(a.relative, b.relative);
        a.finite &= b.finite;
    }

    /// The residual of the rows given.
    pub fn finish(self) -> Residual {
        self.acc.finish()
    }
}

impl Residual {
    /// A residual with every field `+∞`: the value for unusable candidates.
    pub const INFINITE: Residual = Residual {
        natural: f64::INFINITY,
        complementarity: f64::INFINITY,
        z_violation: f64::INFINITY,
        w_violation: f64::INFINITY,
        equation: f64::INFINITY,
        relative: f64::INFINITY,
    };

    /// Computes the residual of (z, w) for the problem, recomputing `M z + q`. A z or w
    /// whose length is not n, or with an entry that is not finite, gives
    /// [`Residual::INFINITE`], which no tolerance accepts.
    pub fn compute(lcp: LcpRef<'_>, z: &[f64], w: &[f64]) -> Residual {
        let (m, q) = (lcp.m(), lcp.q());
        Self::from_entries(lcp.n(), |i, j| m[(i, j)], |i| q[i], z, w)
    }

    /// [`Self::compute`] for M given as a column-major slice of order n (`m[i + j n] =
    /// M_ij`), without building an [`LcpRef`]: for callers that assemble small problems in
    /// their own buffers and solve some of them without a solver (a time-stepper's one-contact
    /// problems). Entries that are not finite, or slices of the wrong lengths, give
    /// [`Residual::INFINITE`].
    #[inline]
    pub fn compute_column_major(n: usize, m: &[f64], q: &[f64], z: &[f64], w: &[f64]) -> Residual {
        if n.checked_mul(n) != Some(m.len()) || q.len() != n {
            return Residual::INFINITE;
        }
        Self::from_entries(n, |i, j| m[i + j * n], |i| q[i], z, w)
    }

    /// The residual of (z, w) for the problem with entries `m(i, j)` and `q(i)`.
    #[inline]
    fn from_entries(
        n: usize,
        m: impl Fn(usize, usize) -> f64,
        q: impl Fn(usize) -> f64,
        z: &[f64],
        w: &[f64],
    ) -> Residual {
        if z.len() != n || w.len() != n || z.iter().chain(w).any(|v| !v.is_finite()) {
            return Residual::INFINITE;
        }
        let mut acc = Acc::new(z);
        for i in 0..n {
            let qi = q(i);
            let mut sum = qi;
            let mut abs = 0.0;
            for j in 0..n {
                let t = m(i, j) * z[j];
                sum += t;
                abs += t.abs();
            }
            acc.row(qi, z[i], w[i], abs, sum);
        }
        acc.finish()
    }

    /// The largest of `natural`, `complementarity`, `z_violation`, `w_violation` and
    /// `equation` (absolute numbers; use [`Residual::relative`] for acceptance).
    pub fn max(&self) -> f64 {
        self.natural
            .max(self.complementarity)
            .max(self.z_violation)
            .max(self.w_violation)
            .max(self.equation)
    }
}

/// Sets `w = M z + q` (M row-major, `m[i n + j] = M_ij`) and returns the residual of
/// (z, w); `equation` is then zero by construction.
pub(crate) fn finish_row_major(
    m: &[f64],
    n: usize,
    q: &[f64],
    z: &[f64],
    w: &mut [f64],
) -> Residual {
    let mut acc = Acc::new(&z[..n]);
    for i in 0..n {
        let row = &m[i * n..(i + 1) * n];
        let mut sum = q[i];
        let mut abs = 0.0;
        for (a, b) in row.iter().zip(&z[..n]) {
            let t = a * b;
            sum += t;
            abs += t.abs();
        }
        w[i] = sum;
        acc.row(q[i], z[i], sum, abs, sum);
    }
    acc.finish()
}

/// Sets `w = M z + q` for a z that is zero off the (ascending) columns `cols`, and returns the
/// residual of (z, w): the sparse product gives the dense one's w. `block` holds those
/// columns of M one after the other (`block[t n + i] = M_i,cols[t]`); the product is
/// accumulated column by column, each row summing its terms in ascending column order.
/// `abs` (length n) is scratch.
pub(crate) fn finish_sparse(
    block: &[f64],
    n: usize,
    q: &[f64],
    z: &[f64],
    cols: &[usize],
    w: &mut [f64],
    abs: &mut [f64],
) -> Residual {
    let (z, q, w, abs) = (&z[..n], &q[..n], &mut w[..n], &mut abs[..n]);
    w.copy_from_slice(q);
    abs.fill(0.0);
    for (col, &j) in block.chunks_exact(n).zip(cols) {
        let zj = z[j];
        for ((wi, ai), m) in w.iter_mut().zip(abs.iter_mut()).zip(col) {
            let v = m * zj;
            *wi += v;
            *ai += v.abs();
        }
    }
    let mut acc = Acc::new(z);
    for i in 0..n {
        acc.row(q[i], z[i], w[i], abs[i], w[i]);
    }
    acc.finish()
}

/// Four consecutive rows: the unit of the lane-wise kernels (Lemke's tableau columns are
/// padded to a multiple of four rows).
pub(crate) type Chunk = [f64; 4];

/// The residual from the maxima over the rows of the terms of `Acc::row` (with
/// `equation` zero): for kernels that take them lane by lane.
#[inline(always)]
pub(crate) fn residual_from_maxima(
    q_max: f64,
    z_max: f64,
    natural: f64,
    complementarity: f64,
    z_violation: f64,
    w_violation: f64,
    relative: f64,
    finite: bool,
) -> Residual {
    Acc {
        q_max,
        z_max,
        natural,
        complementarity,
        z_violation,
        w_violation,
        equation: 0.0,
        relative,
        finite,
    }
    .finish()
}

/// The result of a solve: z, w = M z + q, status, method, iterations and residual.
///
/// `z` and `w` always hold the solver's last iterate (length n); they are a solution of
/// the LCP only when `status` is [`Status::Solved`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Solution {
    /// How the solve ended.
    pub status: Status,
    /// Which method produced `z`.
    pub method: Method,
    /// The complementary variable z (impulses P_N, ... in the time-stepper).
    pub z: Vec<f64>,
    /// `w = M z + q`, recomputed from z (velocities ξ_N, ... in the time-stepper).
    pub w: Vec<f64>,
    /// Pivots (Lemke, counting the first one that brings in z_0), sweeps (PGS) or bases
    /// examined (enumeration); 0 for the trivial solution.
    pub iterations: usize,
    /// The residual of (z, w), see [`Residual`].
    pub residual: Residual,
}

impl Default for Solution {
    fn default() -> Self {
        Solution::new()
    }
}

impl Solution {
    /// An empty solution to be filled by [`Solver::solve_into`] (its vectors are reused).
    pub fn new() -> Self {
        Solution {
            status: Status::NumericalFailure,
            method: Method::Trivial,
            z: Vec::new(),
            w: Vec::new(),
            iterations: 0,
            residual: Residual::INFINITE,
        }
    }

    /// `true` when the status is [`Status::Solved`].
    pub fn is_solved(&self) -> bool {
        self.status == Status::Solved
    }

    /// Sizes z and w to n and resets the other fields, without zeroing z and w when they
    /// already have length n: for callers that overwrite every entry of both.
    pub(crate) fn prepare(&mut self, n: usize, method: Method) {
        if self.z.len() != n {
            self.z.clear();
            self.z.resize(n, 0.0);
        }
        if self.w.len() != n {
            self.w.clear();
            self.w.resize(n, 0.0);
        }
        self.iterations = 0;
        self.method = method;
        self.status = Status::NumericalFailure;
        self.residual = Residual::INFINITE;
    }

    /// Replaces a candidate whose z or w has an entry beyond f64's range (an overflow, as
    /// data of extreme range can give) by z = 0, w = q, with status
    /// [`Status::NumericalFailure`]: a solver never returns NaN or infinity.
    pub(crate) fn drop_non_finite(&mut self, q: &[f64]) {
        if self.z.iter().chain(&self.w).all(|v| v.is_finite()) {
            return;
        }
        self.z.fill(0.0);
        self.w.copy_from_slice(q);
        self.residual = residual_of_zero(q);
        self.status = Status::NumericalFailure;
    }

    /// [`Self::prepare`] with z and w zeroed (no allocation once the capacity has been reached).
    pub(crate) fn reset(&mut self, n: usize, method: Method) {
        self.prepare(n, method);
        self.z.fill(0.0);
        self.w.fill(0.0);
    }
}

/// A solver of LCP(M, q).
pub trait Solver {
    /// Solves into `out`, reusing its vectors and the solver's own workspace: no
    /// allocation once sizes have been seen.
    ///
    /// `warm_start` is an initial z of length n; PGS starts from it (projected onto
    /// z >= 0), [`Auto`](crate::Auto) first tries the complementary basis it names, and
    /// Lemke's method and enumeration check its length and otherwise ignore it.
    ///
    /// # Errors
    /// Only for invalid input (wrong warm start length, non-finite warm start, a
    /// method-specific precondition); not finding a solution is reported in
    /// `out.status`.
    fn solve_into(
        &mut self,
        lcp: LcpRef<'_>,
        warm_start: Option<&[f64]>,
        out: &mut Solution,
    ) -> Result<(), LcpError>;

    /// Solves an owned problem from z = 0 into a new [`Solution`].
    ///
    /// # Errors
    /// As [`Solver::solve_into`].
    fn solve(&mut self, lcp: &Lcp) -> Result<Solution, LcpError> {
        let mut out = Solution::new();
        self.solve_into(lcp.view(), None, &mut out)?;
        Ok(out)
    }
}

/// Checks a warm start: length n and finite entries.
pub(crate) fn check_warm_start(n: usize, warm_start: Option<&[f64]>) -> Result<(), LcpError> {
    if let Some(z) = warm_start {
        if z.len() != n {
            return Err(LcpError::WarmStartLength { expected: n, found: z.len() });
        }
        if let Some(i) = z.iter().position(|v| !v.is_finite()) {
            return Err(LcpError::NonFinite { what: "warm start", index: (i, 0) });
        }
    }
    Ok(())
}

/// The residual of z = 0, w = q.
pub(crate) fn residual_of_zero(q: &[f64]) -> Residual {
    let mut acc = Acc::new(&[]);
    for &qi in q {
        acc.row(qi, 0.0, qi, 0.0, qi);
    }
    acc.finish()
}
