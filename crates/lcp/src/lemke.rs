//! Lemke's complementary pivoting method with lexicographic degeneracy resolution.
#![allow(non_snake_case)]

use serde::{Deserialize, Serialize};

use crate::dense::{Lu, TINY_MAX, pow2_inverse, refine, solve_tiny};
use crate::solution::{
    check_warm_start, finish_col_major_sparse, finish_row_major, finish_row_major_sparse,
};
use crate::{LcpError, LcpRef, Method, Residual, Solution, Solver, Status};

const NONE: usize = usize::MAX;

/// Above this relative residual the re-solved basis gets a step of iterative refinement.
const REFINE_ABOVE: f64 = 1e-14;

/// The covering vector d > 0 of Lemke's augmented problem `w = q + M z + d z_0`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub enum Covering {
    /// d = (1, ..., 1), the classic choice.
    #[default]
    Ones,
    /// d_i = 1 / r_i, with r_i the power of two nearest to `1 / max_j |M_ij|`: ones for the
    /// row-equilibrated problem. It covers rows of very different magnitude alike and
    /// suits badly scaled M (entries from 1e-9 to 1e6), where d = 1 makes the column of
    /// z_0 span as many orders of magnitude as the rows do.
    RowScaled,
    /// A given vector; every entry must be finite and > 0, and its length n.
    Custom(Vec<f64>),
}

/// Options of [`Lemke`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct LemkeOptions {
    /// Largest number of pivots before giving up with [`Status::IterationLimit`].
    /// Default 131072 = 2^17, enough for Murty's n = 16 problem (2^16 - 1 pivots);
    /// Murty's problem of size n needs 2^n - 1.
    pub max_pivots: usize,
    /// Acceptance tolerance on [`Residual::relative`] of the final z (dimensionless).
    /// Default 1e-9, the robust recipe of the step LCP.
    pub tolerance: f64,
    /// A tableau entry takes part in the ratio test only when its magnitude exceeds this
    /// fraction of the largest magnitude in the entering column (dimensionless).
    /// Default 1e-12.
    pub pivot_tolerance: f64,
    /// Two ratios count as tied (and the lexicographic rule decides) when they differ by
    /// less than this fraction of the largest basic value (dimensionless). Default 1e-12.
    pub tie_tolerance: f64,
    /// The covering vector d. Default [`Covering::Ones`].
    pub covering: Covering,
}

impl Default for LemkeOptions {
    fn default() -> Self {
        LemkeOptions {
            max_pivots: 1 << 17,
            tolerance: 1e-9,
            pivot_tolerance: 1e-12,
            tie_tolerance: 1e-12,
            covering: Covering::Ones,
        }
    }
}

impl LemkeOptions {
    pub(crate) fn validate(&self) -> Result<(), LcpError> {
        let bad = |name: &'static str, reason: &str| {
            Err(LcpError::InvalidOption { name, reason: reason.to_string() })
        };
        if self.max_pivots == 0 {
            return bad("max_pivots", "must be at least 1");
        }
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return bad("tolerance", "must be finite and > 0");
        }
        if !(self.pivot_tolerance.is_finite()
            && self.pivot_tolerance > 0.0
            && self.pivot_tolerance < 1.0)
        {
            return bad("pivot_tolerance", "must be in (0, 1)");
        }
        if !(self.tie_tolerance.is_finite()
            && self.tie_tolerance >= 0.0
            && self.tie_tolerance < 1.0)
        {
            return bad("tie_tolerance", "must be in [0, 1)");
        }
        if let Covering::Custom(d) = &self.covering {
            if d.is_empty() {
                return bad("covering", "custom covering vector is empty");
            }
            if d.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
                return bad("covering", "every entry must be finite and > 0");
            }
        }
        Ok(())
    }
}

/// Lemke's complementary pivoting method (Lemke 1965; Cottle, Pang & Stone 1992, §4.4).
///
/// The augmented problem `w = q + M z + d z_0`, `0 <= z ⊥ w >= 0`, `z_0 >= 0` starts
/// from the basis {w} with `z_0 = max_i(-q_i / d_i)`, which makes every basic variable
/// non-negative. Each step brings in the complement of the variable that just left, and
/// the ratio test keeps the basic variables non-negative. The method ends when z_0 leaves
/// (a complementary basis: a solution), on a secondary ray (the entering column has no
/// blocking entry), or at the pivot limit.
///
/// **Degeneracy.** The ratio test is lexicographic: among the tied rows it takes the one
/// whose row of `[q̄ | B^{-1}]` divided by the pivot entry is lexicographically smallest.
/// These rows stay lexicographically positive and distinct, so no basis repeats and the
/// method cannot cycle, whatever the zeros in q and ties in the ratios. When z_0 is among
/// the tied rows it leaves at once.
///
/// **Accuracy.** After a complementary basis is reached, the tableau's basic values are
/// taken as z (α = basic z), w is recomputed as `M z + q`, and the result is accepted
/// (`Status::Solved`) only when [`Residual::relative`] `<= tolerance`. Otherwise the
/// basic part is re-solved directly, `M_αα z_α = -q_α` with an LU factorisation and one
/// step of iterative refinement, and checked the same way; failing both, the better
/// candidate is returned with [`Status::NumericalFailure`].
///
/// **Cost.** A condensed n x (n + 2) tableau (rows: basic variables, columns: the n + 1
/// non-basic variables and q̄; each row padded to a multiple of four entries) is pivoted
/// by plain loops over a preallocated buffer: about n (n + 2) multiply-adds per pivot.
/// Accepting the tableau's own z costs one product with the basic columns of M; the LU
/// re-solve runs only when that z fails the residual test. Warm starts are checked and ignored.
///
/// **Secondary ray.** For copositive-plus M (for example positive semidefinite) a
/// secondary ray proves that the LCP has no solution (Cottle, Pang & Stone 1992,
/// Thm 4.4.13); the status is then [`Status::RayTermination`].
///
/// # References
/// - C. E. Lemke, Bimatrix equilibrium points and mathematical programming, Management
///   Science 11 (1965) 681-689.
/// - R. W. Cottle, J.-S. Pang, R. E. Stone, The Linear Complementarity Problem, Academic
///   Press, 1992.
#[derive(Default)]
pub struct Lemke {
    options: LemkeOptions,
    ws: Workspace,
}

#[derive(Default)]
struct Workspace {
    n: usize,
    /// The n the buffers were last sized for.
    prepared: Option<usize>,
    /// Row length of the tableau: n + 2 rounded up to a multiple of [`LANES`] (the padding
    /// columns stay zero).
    width: usize,
    row_scaled: bool,
    /// M column-major, as the pivoting path reads it (tableau set-up, residual).
    m_cols: Vec<f64>,
    /// M row-major, filled only for the LU paths (warm basis, re-solve fallback).
    m_rows: Vec<f64>,
    /// Per row: the largest |M_ij| while setting up, then the power-of-two row scale.
    rscale: Vec<f64>,
    /// Scratch of the residual: the row sums `Σ_j |M_ij z_j|`.
    abs: Vec<f64>,
    q: Vec<f64>,
    d: Vec<f64>,
    tab: Vec<f64>,
    basic: Vec<usize>,
    nonbasic: Vec<usize>,
    row_of: Vec<usize>,
    col_of: Vec<usize>,
    ties: Vec<usize>,
    acol: Vec<f64>,
    cval: Vec<f64>,
    alpha: Vec<usize>,
    rhs: Vec<f64>,
    z_alt: Vec<f64>,
    w_alt: Vec<f64>,
    z_tab: Vec<f64>,
    w_tab: Vec<f64>,
    lu: Lu,
}

/// The covering vector of one solve.
pub(crate) enum Cover<'a> {
    /// The one in the options.
    FromOptions,
    /// [`Covering::RowScaled`].
    RowScaled,
    /// A given vector (checked: length n, finite, > 0).
    Given(&'a [f64]),
}

/// How the pivoting phase ended.
enum End {
    Complementary,
    Ray,
    Limit,
}

impl Lemke {
    /// A solver with the given options.
    ///
    /// # Errors
    /// [`LcpError::InvalidOption`] for out-of-range options.
    pub fn new(options: LemkeOptions) -> Result<Lemke, LcpError> {
        options.validate()?;
        Ok(Lemke { options, ws: Workspace::default() })
    }

    /// The options in use.
    pub fn options(&self) -> &LemkeOptions {
        &self.options
    }

    /// Solves with the given covering vector.
    pub(crate) fn solve_covering(
        &mut self,
        lcp: LcpRef<'_>,
        cover: Cover<'_>,
        out: &mut Solution,
    ) -> Result<(), LcpError> {
        let n = lcp.n();
        let (d, row_scaled) = match cover {
            Cover::Given(d) => (Some(d), false),
            Cover::RowScaled => (None, true),
            Cover::FromOptions => match &self.options.covering {
                Covering::Ones => (None, false),
                Covering::RowScaled => (None, true),
                Covering::Custom(d) => (Some(d.as_slice()), false),
            },
        };
        if let Some(d) = d {
            if d.len() != n {
                return Err(LcpError::DimensionMismatch {
                    what: "covering vector d",
                    expected: n,
                    found: d.len(),
                });
            }
            if d.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
                return Err(LcpError::InvalidOption {
                    name: "covering",
                    reason: "every entry must be finite and > 0".to_string(),
                });
            }
        }
        out.reset(n, Method::Lemke);
        let ws = &mut self.ws;
        ws.prepare(n);
        lcp.copy_q(&mut ws.q);
        ws.row_scaled = row_scaled;
        match d {
            Some(d) => ws.d.copy_from_slice(d),
            None => ws.d.fill(1.0),
        }
        if ws.q.iter().all(|&v| v >= 0.0) {
            lcp.copy_m_row_major(&mut ws.m_rows);
            out.residual = finish_row_major(&ws.m_rows, n, &ws.q, &out.z, &mut out.w);
            out.status = status_for(out.residual, self.options.tolerance, Status::NumericalFailure);
            return Ok(());
        }
        ws.init_tableau(lcp);
        let (end, pivots) = ws.pivot_loop(&self.options);
        out.iterations = pivots;
        let tol = self.options.tolerance;
        match end {
            End::Complementary => {
                // The tableau's own basic values first: accepted when their residual
                // passes, which costs one product M z (n^2 multiply-adds).
                ws.tableau_candidate(out, tol, Status::NumericalFailure);
                if out.status == Status::Solved {
                    return Ok(());
                }
                // Otherwise re-solve the basis by LU (with refinement) and keep the
                // better of the two candidates.
                std::mem::swap(&mut out.z, &mut ws.z_tab);
                std::mem::swap(&mut out.w, &mut ws.w_tab);
                let tab_residual = out.residual;
                ws.fill_m_rows();
                if ws.resolve_basis(out, tol) {
                    return Ok(());
                }
                if !(out.residual.relative <= tab_residual.relative) {
                    std::mem::swap(&mut out.z, &mut ws.z_tab);
                    std::mem::swap(&mut out.w, &mut ws.w_tab);
                    out.residual = tab_residual;
                }
                out.status = Status::NumericalFailure;
            }
            End::Ray => ws.tableau_candidate(out, tol, Status::RayTermination),
            End::Limit => ws.tableau_candidate(out, tol, Status::IterationLimit),
        }
        Ok(())
    }

    /// Solves the complementary basis that a guess of z implies, without pivoting:
    /// α = { i : guess_i > 0 } (z basic there, w elsewhere), `M_αα z_α = −q_α` by LU
    /// (with one step of iterative refinement when needed), z_i = 0 off α. Accepted, with
    /// status [`Status::Solved`] and method [`Method::WarmBasis`], only when z ≥ 0 and
    /// [`Residual::relative`] of (z, M z + q) is within the tolerance; returns whether it
    /// was.
    ///
    /// In a time-stepper the contacts keep their state (closed, sticking, sliding one way)
    /// over many steps, so the previous step's z names the new step's basis most of the
    /// time, and one small solve replaces the pivots.
    pub(crate) fn solve_guessed_basis(
        &mut self,
        lcp: LcpRef<'_>,
        guess: &[f64],
        out: &mut Solution,
    ) -> bool {
        let n = lcp.n();
        out.reset(n, Method::WarmBasis);
        let ws = &mut self.ws;
        ws.prepare(n);
        lcp.copy_m_row_major(&mut ws.m_rows);
        lcp.copy_q(&mut ws.q);
        ws.alpha.clear();
        for (i, &g) in guess.iter().enumerate() {
            if g > 0.0 {
                ws.alpha.push(i);
            }
        }
        let tol = self.options.tolerance;
        // A basic value that comes out negative is clamped to zero, and the residual then
        // rejects the candidate.
        let k = ws.alpha.len();
        if k <= TINY_MAX {
            let (m, alpha) = (&ws.m_rows, &ws.alpha);
            for (t, &i) in alpha.iter().enumerate() {
                ws.rhs[t] = -ws.q[i];
            }
            if solve_tiny(k, |r, c| m[alpha[r] * n + alpha[c]], &mut ws.rhs) {
                ws.scatter(out);
                if out.residual.relative <= tol {
                    out.status = Status::Solved;
                    return true;
                }
            }
        }
        // The equilibrated LU with refinement, for larger or harder bases.
        ws.solve_alpha(out, tol)
    }
}

/// Tableau rows are padded to a multiple of this many entries, so that the row update
/// runs in whole blocks with no remainder loop.
const LANES: usize = 4;

/// n + 2 (n + 1 non-basic columns and q̄) rounded up to a multiple of [`LANES`].
#[inline]
fn padded_width(n: usize) -> usize {
    (n + 2).div_ceil(LANES) * LANES
}

/// `y += f x` for rows of equal length, a multiple of [`LANES`] (blocks of four the
/// compiler turns into packed multiply-adds).
#[inline]
fn axpy(f: f64, x: &[f64], y: &mut [f64]) {
    let len = y.len().min(x.len());
    let (x, y) = (&x[..len], &mut y[..len]);
    for j in 0..len {
        y[j] += f * x[j];
    }
}

/// `max(a, b)` as one compare (`maxsd`); a NaN in `b` is ignored, unlike `f64::max` it
/// is not special-cased. Used on magnitudes of finite data and tableau entries, where a
/// NaN can only come from a failed pivot sequence, which the residual check rejects.
#[inline]
fn fmax(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

/// `max(x, 0)`, with NaN mapped to 0.
#[inline]
fn positive_part(x: f64) -> f64 {
    if x > 0.0 { x } else { 0.0 }
}

fn status_for(r: Residual, tol: f64, otherwise: Status) -> Status {
    if r.relative <= tol { Status::Solved } else { otherwise }
}

impl Workspace {
    fn prepare(&mut self, n: usize) {
        // Every buffer's size is a function of n alone.
        if self.prepared == Some(n) {
            return;
        }
        self.prepared = Some(n);
        self.n = n;
        self.m_cols.resize(n * n, 0.0);
        self.m_rows.resize(n * n, 0.0);
        self.rscale.resize(n, 0.0);
        self.abs.resize(n, 0.0);
        self.q.resize(n, 0.0);
        self.d.resize(n, 1.0);
        self.width = padded_width(n);
        self.tab.resize(n * self.width, 0.0);
        self.basic.resize(n, NONE);
        self.nonbasic.resize(n + 1, NONE);
        self.row_of.resize(2 * n + 1, NONE);
        self.col_of.resize(2 * n + 1, NONE);
        self.rhs.resize(n, 0.0);
        self.acol.resize(n, 0.0);
        self.cval.resize(n, 0.0);
        self.z_alt.resize(n, 0.0);
        self.w_alt.resize(n, 0.0);
        self.z_tab.resize(n, 0.0);
        self.w_tab.resize(n, 0.0);
        if self.ties.capacity() < n {
            self.ties.reserve(n);
        }
        if self.alpha.capacity() < n {
            self.alpha.reserve(n);
        }
        self.lu.reserve(n);
    }

    /// Tableau `x_B = q̄ + T x_N` for the basis {w}: `T = [M | d]`, `q̄ = q`.
    /// Variables: `w_i = i`, `z_i = n + i`, `z_0 = 2 n`.
    ///
    /// Each row is scaled by a power of two r_i near `1 / max_j |M_ij|` (exact in floating
    /// point). Scaling row i of (M, d, q) by r_i > 0 only scales w_i, so the pivot sequence
    /// is the same in exact arithmetic, while the relative pivot tolerance and the tie
    /// tests become independent of the magnitudes of the rows.
    ///
    /// With [`Covering::RowScaled`] the column of z_0 holds ones in the scaled rows.
    ///
    /// M is read once, column by column as it is stored: each column goes to the
    /// column-major copy (which the residual reads; the row-major copy is made only if the
    /// LU fallback runs) and unscaled into its tableau column, while the row maxima are
    /// taken; each row is then scaled in place.
    fn init_tableau(&mut self, lcp: LcpRef<'_>) {
        let n = self.n;
        let width = self.width;
        let m = lcp.m();
        let tab = &mut self.tab[..n * width];
        let rscale = &mut self.rscale[..n];
        rscale.fill(0.0);
        for (j, dst) in self.m_cols[..n * n].chunks_exact_mut(n).enumerate() {
            let col = m.col(j);
            if let Some(src) = col.try_as_col_major().map(|c| c.as_slice()) {
                for (i, ((d, big), &v)) in
                    dst.iter_mut().zip(rscale.iter_mut()).zip(src).enumerate()
                {
                    *d = v;
                    *big = fmax(*big, v.abs());
                    tab[i * width + j] = v;
                }
            } else {
                for (i, (d, big)) in dst.iter_mut().zip(rscale.iter_mut()).enumerate() {
                    let v = col[i];
                    *d = v;
                    *big = fmax(*big, v.abs());
                    tab[i * width + j] = v;
                }
            }
        }
        for i in 0..n {
            let big = self.rscale[i];
            let r = if big > 0.0 { pow2_inverse(big) } else { 1.0 };
            self.rscale[i] = r;
            let row = &mut self.tab[i * width..(i + 1) * width];
            for v in row[..n].iter_mut() {
                *v *= r;
            }
            row[n] = if self.row_scaled { 1.0 } else { self.d[i] * r };
            row[n + 1] = self.q[i] * r;
            row[n + 2..].fill(0.0);
            self.basic[i] = i;
            self.row_of[i] = i;
            self.col_of[i] = NONE;
        }
        for j in 0..n {
            self.nonbasic[j] = n + j;
            self.col_of[n + j] = j;
            self.row_of[n + j] = NONE;
        }
        self.nonbasic[n] = 2 * n;
        self.col_of[2 * n] = n;
        self.row_of[2 * n] = NONE;
    }

    fn pivot_loop(&mut self, opts: &LemkeOptions) -> (End, usize) {
        let n = self.n;
        let z0 = 2 * n;
        // First pivot: z_0 enters and the row with the most negative q_i / d_i leaves.
        let Some(r) = self.select_row(n, true, opts) else {
            return (End::Ray, 0);
        };
        let mut leaving = self.pivot(r, n);
        let mut pivots = 1;
        loop {
            if leaving == z0 {
                return (End::Complementary, pivots);
            }
            if pivots >= opts.max_pivots {
                return (End::Limit, pivots);
            }
            let entering = if leaving < n { leaving + n } else { leaving - n };
            let s = self.col_of[entering];
            let Some(r) = self.select_row(s, false, opts) else {
                return (End::Ray, pivots);
            };
            leaving = self.pivot(r, s);
            pivots += 1;
        }
    }

    /// Entry `j` of row `i` of `B^{-1}`, read from the condensed tableau: the column of
    /// a non-basic `w_j` holds `-B^{-1} e_j`, and a basic `w_j` in row k has
    /// `B^{-1} e_j = e_k`.
    #[inline]
    fn binv(&self, i: usize, j: usize) -> f64 {
        let r = self.row_of[j];
        if r != NONE {
            if r == i { 1.0 } else { 0.0 }
        } else {
            -self.tab[i * self.width + self.col_of[j]]
        }
    }

    /// The lexicographic ratio test for entering column `s`. In the first step
    /// (`initial`), every row takes part with `a_i = d_i`; afterwards the rows with
    /// `T_is < 0` take part with `a_i = -T_is`.
    fn select_row(&mut self, s: usize, initial: bool, opts: &LemkeOptions) -> Option<usize> {
        let n = self.n;
        let width = self.width;
        let sign = if initial { 1.0 } else { -1.0 };
        let tab = &self.tab[..n * width];
        let (acol, cval) = (&mut self.acol[..n], &mut self.cval[..n]);
        let mut colmax = 0.0f64;
        let mut cmax = 0.0f64;
        for (i, row) in tab.chunks_exact(width).enumerate() {
            let (a, c) = (sign * row[s], row[n + 1]);
            acol[i] = a;
            cval[i] = c;
            colmax = fmax(colmax, a.abs());
            cmax = fmax(cmax, c.abs());
        }
        let ptol = opts.pivot_tolerance * colmax;
        // Minimum ratio c_i / a_i over a_i > ptol, compared without dividing.
        let mut best = NONE;
        let (mut cb, mut ab) = (f64::INFINITY, 1.0);
        for (i, (&a, &c)) in acol.iter().zip(cval.iter()).enumerate() {
            if a > ptol && c * ab < cb * a {
                best = i;
                cb = c;
                ab = a;
            }
        }
        if best == NONE {
            return None;
        }
        // Rows whose ratio ties with the minimum within the tie tolerance: counted first,
        // listed (and broken lexicographically) only when there are two or more.
        let theta = cb / ab;
        let eps = opts.tie_tolerance * fmax(cmax, f64::MIN_POSITIVE);
        let tied = |a: f64, c: f64| a > ptol && c - theta * a <= eps;
        let count: usize =
            acol.iter().zip(cval.iter()).map(|(&a, &c)| usize::from(tied(a, c))).sum();
        if count <= 1 {
            return Some(best);
        }
        self.ties.clear();
        for (i, (&a, &c)) in acol.iter().zip(cval.iter()).enumerate() {
            if tied(a, c) {
                self.ties.push(i);
            }
        }
        if !initial {
            let z0 = 2 * n;
            if let Some(&r) = self.ties.iter().find(|&&i| self.basic[i] == z0) {
                return Some(r);
            }
        }
        let mut pick = self.ties[0];
        for t in 1..self.ties.len() {
            let i = self.ties[t];
            if self.lex_less(i, self.acol[i], pick, self.acol[pick]) {
                pick = i;
            }
        }
        Some(pick)
    }

    /// `true` when row i of `B^{-1}` divided by `ai` is lexicographically smaller than
    /// row k divided by `ak`.
    fn lex_less(&self, i: usize, ai: f64, k: usize, ak: f64) -> bool {
        for j in 0..self.n {
            let x = self.binv(i, j) / ai;
            let y = self.binv(k, j) / ak;
            if (x - y).abs() <= 1e-9 * x.abs().max(y.abs()) {
                continue;
            }
            return x < y;
        }
        false
    }

    /// Exchanges the basic variable of row r with the non-basic variable of column s and
    /// returns the variable that left the basis.
    fn pivot(&mut self, r: usize, s: usize) -> usize {
        // Widths up to 32 (n <= 30) get a kernel of fixed row length, which the compiler
        // unrolls into whole packed multiply-adds with no loop or bounds checks.
        match self.width {
            4 => self.pivot_rows::<4>(r, s),
            8 => self.pivot_rows::<8>(r, s),
            12 => self.pivot_rows::<12>(r, s),
            16 => self.pivot_rows::<16>(r, s),
            20 => self.pivot_rows::<20>(r, s),
            24 => self.pivot_rows::<24>(r, s),
            28 => self.pivot_rows::<28>(r, s),
            32 => self.pivot_rows::<32>(r, s),
            _ => self.pivot_rows::<0>(r, s),
        }
        let leaving = self.basic[r];
        let entering = self.nonbasic[s];
        self.basic[r] = entering;
        self.row_of[entering] = r;
        self.col_of[entering] = NONE;
        self.nonbasic[s] = leaving;
        self.col_of[leaving] = s;
        self.row_of[leaving] = NONE;
        leaving
    }

    /// The row operations of a pivot on (r, s) for rows of length `W` (0: `self.width`).
    #[inline(always)]
    fn pivot_rows<const W: usize>(&mut self, r: usize, s: usize) {
        let n = self.n;
        let width = if W == 0 { self.width } else { W };
        let (before, rest) = self.tab[..n * width].split_at_mut(r * width);
        let (row_r, after) = rest.split_at_mut(width);
        let inv = 1.0 / row_r[s];
        for v in row_r.iter_mut() {
            *v *= -inv;
        }
        row_r[s] = inv;
        let row_r: &[f64] = row_r;
        for rows in [before, after] {
            for row in rows.chunks_exact_mut(width) {
                let f = row[s];
                if f != 0.0 {
                    row[s] = 0.0;
                    axpy(f, row_r, row);
                }
            }
        }
    }

    /// Fills the row-major copy of M from the column-major one, for the LU re-solve.
    fn fill_m_rows(&mut self) {
        let n = self.n;
        for (j, col) in self.m_cols[..n * n].chunks_exact(n).enumerate() {
            for (i, v) in col.iter().enumerate() {
                self.m_rows[i * n + j] = *v;
            }
        }
    }

    /// Re-solves the complementary basis directly and accepts it if its residual passes.
    fn resolve_basis(&mut self, out: &mut Solution, tol: f64) -> bool {
        let n = self.n;
        self.alpha.clear();
        for i in 0..n {
            if self.row_of[n + i] != NONE {
                self.alpha.push(i);
            }
        }
        let solved = self.solve_alpha(out, tol);
        out.method = Method::Lemke;
        solved
    }

    /// Solves `M_αα z_α = −q_α` for the basis in `alpha` (z_i = 0 off α) by LU, with a
    /// step of iterative refinement when the residual is above [`REFINE_ABOVE`], and
    /// returns whether the result passes `tol`; `out` holds it (status `Solved` if so).
    fn solve_alpha(&mut self, out: &mut Solution, tol: f64) -> bool {
        let n = self.n;
        let k = self.alpha.len();
        let (m, alpha) = (&self.m_rows, &self.alpha);
        if !self.lu.factor_with(k, |i, j| m[alpha[i] * n + alpha[j]]) {
            return false;
        }
        for (t, &i) in self.alpha.iter().enumerate() {
            self.rhs[t] = -self.q[i];
        }
        self.lu.solve(&mut self.rhs);
        self.scatter(out);
        if out.residual.relative > REFINE_ABOVE {
            let before = out.residual;
            std::mem::swap(&mut out.z, &mut self.w_alt);
            refine(
                &mut self.lu,
                &self.m_rows,
                n,
                &self.alpha,
                &self.alpha,
                &self.q,
                &mut self.rhs,
                &mut self.z_alt,
            );
            self.scatter(out);
            if !(out.residual.relative < before.relative) {
                std::mem::swap(&mut out.z, &mut self.w_alt);
                out.residual = finish_row_major(&self.m_rows, n, &self.q, &out.z, &mut out.w);
            }
        }
        if out.residual.relative <= tol {
            out.status = Status::Solved;
            true
        } else {
            false
        }
    }

    /// z = the basic solution in `rhs` (clamped at 0), w = M z + q, and its residual.
    fn scatter(&mut self, out: &mut Solution) {
        out.z.fill(0.0);
        for (t, &i) in self.alpha.iter().enumerate() {
            out.z[i] = positive_part(self.rhs[t]);
        }
        // z is zero off the (ascending) basis: the sparse product gives the dense one's w.
        out.residual =
            finish_row_major_sparse(&self.m_rows, self.n, &self.q, &out.z, &self.alpha, &mut out.w);
    }

    /// Uses the basic values of the tableau as z (clamped at 0); keeps the better of it and
    /// any candidate already in `out`.
    fn tableau_candidate(&mut self, out: &mut Solution, tol: f64, otherwise: Status) {
        let n = self.n;
        let width = self.width;
        self.alpha.clear();
        for i in 0..n {
            let r = self.row_of[n + i];
            self.z_alt[i] = if r != NONE {
                self.alpha.push(i);
                positive_part(self.tab[r * width + n + 1])
            } else {
                0.0
            };
        }
        let res = finish_col_major_sparse(
            &self.m_cols,
            n,
            &self.q,
            &self.z_alt,
            &self.alpha,
            &mut self.w_alt,
            &mut self.abs,
        );
        if !(out.residual.relative <= res.relative) {
            std::mem::swap(&mut out.z, &mut self.z_alt);
            std::mem::swap(&mut out.w, &mut self.w_alt);
            out.residual = res;
        }
        out.status = status_for(out.residual, tol, otherwise);
    }
}

impl Solver for Lemke {
    fn solve_into(
        &mut self,
        lcp: LcpRef<'_>,
        warm_start: Option<&[f64]>,
        out: &mut Solution,
    ) -> Result<(), LcpError> {
        check_warm_start(lcp.n(), warm_start)?;
        self.solve_covering(lcp, Cover::FromOptions, out)
    }
}
