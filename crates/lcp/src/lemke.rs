//! Lemke's complementary pivoting method with lexicographic degeneracy resolution.
#![allow(non_snake_case)]

use serde::{Deserialize, Serialize};

use crate::dense::{Lu, TINY_MAX, pow2_inverse, refine, solve_tiny};
use crate::solution::{
    Chunk, check_warm_start, finish_row_major, finish_sparse, hmax, residual_chunks,
    residual_of_zero,
};
use crate::{LcpError, LcpRef, Method, Residual, Solution, Solver, Status};

const NONE: usize = usize::MAX;

/// Basic values of the final tableau at or below this fraction of `‖z‖∞` are retried as
/// zero when the tableau's z fails the residual test (about 45 units of round-off).
const ROUND_OFF_ZERO: f64 = 1e-14;

/// Above this relative residual the re-solved basis gets a step of iterative refinement.
const REFINE_ABOVE: f64 = 1e-14;

/// A tableau z whose relative residual passes the tolerance but exceeds this is compared
/// with the LU re-solve of its basis (with refinement), and the better of the two is kept.
const TABLEAU_ACCURATE: f64 = 1e-12;

/// Relative residual of a warm basis' small solve above which the basis is taken as wrong
/// (a contact that changed state), without the equilibrated LU re-solve, which only removes
/// round-off. On the report's scenes every failed warm basis is above 1e-2 (most near 1).
const WRONG_BASIS: f64 = 1e-3;

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
/// (`Status::Solved`) only when [`Residual::relative`] `<= tolerance`. Otherwise the same
/// basis is tried with basic values at or below 1e-14 ‖z‖∞ taken as zero (round-off in a
/// degenerate basic variable), and failing that the basic part is re-solved directly,
/// `M_αα z_α = -q_α` with an LU factorisation and one step of iterative refinement, and
/// checked the same way; failing all, the best candidate is returned with
/// [`Status::NumericalFailure`].
///
/// **Cost.** A condensed n x (n + 2) tableau (rows: basic variables, columns: the n + 1
/// non-basic variables and q̄), stored column by column with each column padded to a
/// multiple of four rows, is pivoted by plain loops over a preallocated buffer: about
/// n (n + 2) multiply-adds per pivot, four rows per operation. The set-up, pivots and
/// residual also have a copy compiled for AVX2, chosen at run time when the processor has
/// it; both copies give the same results bit for bit (no FMA, the same order of
/// operations). Accepting the tableau's own z costs one product with M; the LU re-solve
/// runs only when that z fails the residual test. Warm starts are checked and ignored.
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
    /// Column height of the tableau: n rounded up to a multiple of [`LANES`] (the padding
    /// rows stay zero).
    h: usize,
    /// Chunks per column, `h / LANES`.
    nb: usize,
    /// Whether the AVX2 copy of the kernels runs (detected on the first solve).
    avx: bool,
    row_scaled: bool,
    /// The tie tolerance of the solve in progress ([`LemkeOptions::tie_tolerance`]).
    tie_rel: f64,
    /// M column-major and unscaled, each column padded to h rows: the residual reads it.
    m_cols: Vec<Chunk>,
    /// M row-major, filled only for the LU paths (warm basis, re-solve fallback).
    m_rows: Vec<f64>,
    /// The columns of M in `alpha`, each of n rows: the warm basis' small solve and every
    /// residual of a basis read them.
    basis_cols: Vec<f64>,
    /// q padded to h rows.
    q_pad: Vec<Chunk>,
    /// Three columns of scratch for the kernels of run-time height (n > 32).
    scratch: Vec<Chunk>,
    /// The row mask of a pivot, for the kernels of run-time height.
    keep: Vec<[u64; LANES]>,
    q: Vec<f64>,
    d: Vec<f64>,
    /// The condensed tableau, column-major: n + 2 columns of h rows.
    tab: Vec<Chunk>,
    basic: Vec<usize>,
    nonbasic: Vec<usize>,
    row_of: Vec<usize>,
    col_of: Vec<usize>,
    ties: Vec<usize>,
    alpha: Vec<usize>,
    rhs: Vec<f64>,
    z_alt: Vec<f64>,
    w_alt: Vec<f64>,
    /// Scratch of the row sums `Σ_j |M_ij z_j|` of a sparse residual.
    row_abs: Vec<f64>,
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
        out.prepare(n, Method::Lemke);
        let ws = &mut self.ws;
        ws.prepare(n);
        lcp.copy_q(&mut ws.q);
        ws.row_scaled = row_scaled;
        match d {
            Some(d) => ws.d.copy_from_slice(d),
            None if row_scaled => {}
            None => ws.d.fill(1.0),
        }
        if ws.q.iter().all(|&v| v >= 0.0) {
            out.z.fill(0.0);
            out.w.copy_from_slice(&ws.q);
            out.residual = residual_of_zero(&ws.q);
            out.status = status_for(out.residual, self.options.tolerance, Status::NumericalFailure);
            return Ok(());
        }
        // Set-up, pivots, and the tableau's own basic values as z: accepted when their
        // residual passes, which costs one product M z.
        let (end, pivots) = ws.run(lcp, &self.options, out);
        out.iterations = pivots;
        let tol = self.options.tolerance;
        match end {
            End::Complementary => {
                out.status = status_for(out.residual, tol, Status::NumericalFailure);
                if out.status == Status::Solved && out.residual.relative <= TABLEAU_ACCURATE {
                    return Ok(());
                }
                // Otherwise (a failed or merely passing tableau z, as pivots on a nearly
                // singular basis give) re-solve the basis by LU with refinement and keep the
                // better of the two candidates.
                std::mem::swap(&mut out.z, &mut ws.z_tab);
                std::mem::swap(&mut out.w, &mut ws.w_tab);
                let tab_residual = out.residual;
                ws.fill_m_rows();
                ws.resolve_basis(out, tol);
                if !(out.residual.relative <= tab_residual.relative) {
                    std::mem::swap(&mut out.z, &mut ws.z_tab);
                    std::mem::swap(&mut out.w, &mut ws.w_tab);
                    out.residual = tab_residual;
                }
                out.method = Method::Lemke;
                out.status = status_for(out.residual, tol, Status::NumericalFailure);
            }
            End::Ray => out.status = status_for(out.residual, tol, Status::RayTermination),
            End::Limit => out.status = status_for(out.residual, tol, Status::IterationLimit),
        }
        if !out.is_solved() {
            out.drop_non_finite(&ws.q);
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
            // Only the basis' columns of M are read: their rows in the basis for the solve,
            // all their rows for w = M z + q (z is zero off the basis).
            lcp.copy_columns(&ws.alpha, &mut ws.basis_cols);
            let (cols, alpha) = (&ws.basis_cols, &ws.alpha);
            for (t, &i) in alpha.iter().enumerate() {
                ws.rhs[t] = -ws.q[i];
            }
            if solve_tiny(k, |r, c| cols[c * n + alpha[r]], &mut ws.rhs) {
                ws.set_basic_z(out);
                out.residual = finish_sparse(
                    &cols[..k * n],
                    n,
                    &ws.q,
                    &out.z,
                    alpha,
                    &mut out.w,
                    &mut ws.row_abs,
                );
                if out.residual.relative <= tol {
                    out.status = Status::Solved;
                    return true;
                }
                if out.residual.relative > WRONG_BASIS {
                    // A sign pattern that is wrong, not round-off: re-solving the same basis
                    // more accurately cannot pass (Lemke's method runs next).
                    return false;
                }
            }
        }
        // The equilibrated LU with refinement, for larger or harder bases.
        lcp.copy_m_row_major(&mut ws.m_rows);
        ws.solve_alpha(out, tol)
    }
}

/// Tableau columns are padded to a multiple of this many rows (one [`Chunk`]), so that the
/// kernels run in whole chunks with no remainder loop; the padding rows stay zero.
const LANES: usize = 4;

/// Column heights up to this (n <= 32) get kernels of fixed size (const generics), which
/// the compiler unrolls and whose accumulators it keeps in registers.
const FIXED_MAX: usize = 32;

/// Chunks per column at [`FIXED_MAX`]: the size of the kernels' local arrays.
const MAX_CHUNKS: usize = FIXED_MAX / LANES;

/// The bookkeeping arrays (`basic`, `nonbasic`, `row_of`, `col_of`) hold at least this
/// many entries, a power of two above the 2 n + 1 <= 65 variables of the fixed heights.
const IDX: usize = 128;

/// 0, 1, 2, ...: the initial bookkeeping of the fixed heights is copied from it.
static IOTA: [usize; IDX] = {
    let mut v = [0; IDX];
    let mut i = 0;
    while i < IDX {
        v[i] = i;
        i += 1;
    }
    v
};

/// Row masks of a pivot for the fixed heights: `KEEP[FIXED_MAX - 1 - r + i]` is zero for
/// i = r and all ones otherwise, so the window from `FIXED_MAX - 1 - r` holds the masks of
/// rows 0, 1, ... (all bits set but in row r).
static KEEP: [u64; 2 * FIXED_MAX] = {
    let mut k = [u64::MAX; 2 * FIXED_MAX];
    k[FIXED_MAX - 1] = 0;
    k
};

/// n rounded up to a multiple of [`LANES`].
#[inline]
fn padded_height(n: usize) -> usize {
    n.div_ceil(LANES) * LANES
}

/// Whether this processor runs AVX and AVX2 instructions (the wider copy of the kernels).
fn avx2_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx") && std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Chunk b of `src`, zero past its end.
#[inline(always)]
fn load_chunk(src: &[f64], b: usize) -> Chunk {
    let i = b * LANES;
    match src.get(i..i + LANES) {
        Some(c) => [c[0], c[1], c[2], c[3]],
        None => {
            let mut c = [0.0; LANES];
            for (l, v) in c.iter_mut().enumerate() {
                if let Some(&x) = src.get(i + l) {
                    *v = x;
                }
            }
            c
        }
    }
}

/// `max(a, b)` as one compare (`maxsd`); a NaN in `b` is ignored, unlike `f64::max` it
/// is not special-cased. Used on magnitudes of finite data and tableau entries, where a
/// NaN can only come from a failed pivot sequence, which the residual check rejects.
#[inline(always)]
fn fmax(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

/// `min(a, b)` as one compare (`minsd`), NaN in `b` ignored.
#[inline(always)]
fn fmin(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}

/// `max(x, 0)`, with NaN mapped to 0.
#[inline]
fn positive_part(x: f64) -> f64 {
    if x > 0.0 { x } else { 0.0 }
}

fn status_for(r: Residual, tol: f64, otherwise: Status) -> Status {
    if r.relative <= tol { Status::Solved } else { otherwise }
}

/// Calls `$ws.$f::<H, AVX>(...)` with H the workspace's column height when it has a
/// kernel of fixed size, H = 0 (run-time height) otherwise.
macro_rules! by_height {
    ($ws:ident . $f:ident :: <$avx:literal> ( $($a:expr),* )) => {
        match $ws.h {
            4 => $ws.$f::<4, $avx>($($a),*),
            8 => $ws.$f::<8, $avx>($($a),*),
            12 => $ws.$f::<12, $avx>($($a),*),
            16 => $ws.$f::<16, $avx>($($a),*),
            20 => $ws.$f::<20, $avx>($($a),*),
            24 => $ws.$f::<24, $avx>($($a),*),
            28 => $ws.$f::<28, $avx>($($a),*),
            32 => $ws.$f::<32, $avx>($($a),*),
            _ => $ws.$f::<0, $avx>($($a),*),
        }
    };
}

/// How the ratio test's first pass ended.
enum Ratio {
    /// One row attains the minimum ratio and no other ties with it.
    Row(usize),
    /// Two or more rows tie within the tolerance: the lexicographic rule decides.
    Tied { ptol: f64, theta: f64, eps: f64 },
    /// No finite ratio (no blocking row, or ratios beyond the range of f64).
    NoFinite,
}

/// Rows with a set bit among the four bits of `m`.
const POP4: [u8; 16] = [0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4];

/// The first pass of the ratio test on the entering column `a` (times `sign`) and q̄ `c`
/// (chunks of four rows, padding rows zero): `ptol = pivot_rel · max |a_i|`, θ = the
/// smallest `c_i / a_i` over `a_i > ptol`, the first row attaining it, and the count of
/// rows with `a_i > ptol` and `c_i − θ a_i <= eps`, `eps = tie_rel · max(max |c_i|, MIN_POSITIVE)`.
///
/// Maxima and minima are taken lane by lane (lane = row mod 4) and then over the lanes in
/// the order of [`hmax`]-like trees that [`avx::ratio`] follows too, with the same
/// comparisons, so both give the same result bit for bit.
#[inline(always)]
fn ratio_portable(a: &[Chunk], c: &[Chunk], sign: f64, pivot_rel: f64, tie_rel: f64) -> Ratio {
    let c = &c[..a.len()];
    let mut amax = [0.0f64; LANES];
    let mut cmax = [0.0f64; LANES];
    for (ac, cc) in a.iter().zip(c) {
        for l in 0..LANES {
            amax[l] = fmax(amax[l], ac[l].abs());
            cmax[l] = fmax(cmax[l], cc[l].abs());
        }
    }
    let ptol = pivot_rel * hmax(amax);
    let mut rmin = [f64::INFINITY; LANES];
    for (ac, cc) in a.iter().zip(c) {
        for l in 0..LANES {
            let ai = sign * ac[l];
            let ratio = if ai > ptol { cc[l] / ai } else { f64::INFINITY };
            rmin[l] = fmin(rmin[l], ratio);
        }
    }
    let theta = hmin(rmin);
    if !(theta < f64::INFINITY) {
        return Ratio::NoFinite;
    }
    let eps = tie_rel * fmax(hmax(cmax), f64::MIN_POSITIVE);
    let mut first = NONE;
    let mut count = 0usize;
    for (b, (ac, cc)) in a.iter().zip(c).enumerate() {
        for l in 0..LANES {
            let ai = sign * ac[l];
            let valid = ai > ptol;
            if first == NONE && valid && cc[l] / ai == theta {
                first = b * LANES + l;
            }
            count += usize::from(valid && cc[l] - theta * ai <= eps);
        }
    }
    if count <= 1 { Ratio::Row(first) } else { Ratio::Tied { ptol, theta, eps } }
}

/// `min` over the four lanes of a chunk in the tree `min(min(a0, a2), min(a1, a3))`, by
/// [`fmin`].
#[inline(always)]
fn hmin(a: Chunk) -> f64 {
    fmin(fmin(a[0], a[2]), fmin(a[1], a[3]))
}

/// The AVX copies of kernels that the compiler does not vectorise well by itself.
#[cfg(target_arch = "x86_64")]
mod avx {
    #![allow(unsafe_code)]

    use std::arch::x86_64::*;

    use super::{End, IDX, LANES, LemkeOptions, NONE, POP4, Ratio, Workspace};
    use crate::solution::Chunk;

    /// Loads a chunk.
    #[inline]
    #[target_feature(enable = "avx,avx2")]
    fn load(c: &Chunk) -> __m256d {
        // SAFETY: `c` refers to four consecutive initialised f64 (32 bytes); the load is
        // unaligned, so it has no alignment requirement.
        unsafe { _mm256_loadu_pd(c.as_ptr()) }
    }

    /// `max` over the lanes: `max(max(a0, a2), max(a1, a3))`, each `max(x, y)` = `y > x ?
    /// y : x` as in the portable `fmax(x, y)` (`_mm_max_pd(y, x)` returns its second
    /// operand unless the first is greater).
    #[inline]
    #[target_feature(enable = "avx,avx2")]
    fn hmax(v: __m256d) -> f64 {
        let lo = _mm256_castpd256_pd128(v);
        let hi = _mm256_extractf128_pd::<1>(v);
        let t = _mm_max_pd(hi, lo);
        let t1 = _mm_unpackhi_pd(t, t);
        _mm_cvtsd_f64(_mm_max_sd(t1, t))
    }

    /// `min` over the lanes, as [`super::hmin`].
    #[inline]
    #[target_feature(enable = "avx,avx2")]
    fn hmin(v: __m256d) -> f64 {
        let lo = _mm256_castpd256_pd128(v);
        let hi = _mm256_extractf128_pd::<1>(v);
        let t = _mm_min_pd(hi, lo);
        let t1 = _mm_unpackhi_pd(t, t);
        _mm_cvtsd_f64(_mm_min_sd(t1, t))
    }

    /// Stores a chunk.
    #[inline]
    #[target_feature(enable = "avx,avx2")]
    fn store(c: &mut Chunk, v: __m256d) {
        // SAFETY: `c` refers to four consecutive f64 (32 writable bytes); the store is
        // unaligned, so it has no alignment requirement.
        unsafe { _mm256_storeu_pd(c.as_mut_ptr(), v) }
    }

    /// Lane masks of a partial chunk: the four from `TAIL[4 - k]` select the first k lanes.
    static TAIL: [i64; 8] = [-1, -1, -1, -1, 0, 0, 0, 0];

    /// The lane masks of the chunks of a column of n rows: every lane of a whole chunk,
    /// the first n mod 4 of a partial one, none past it.
    #[inline]
    #[target_feature(enable = "avx,avx2")]
    fn row_masks<const H: usize>(n: usize) -> [__m256i; super::MAX_CHUNKS] {
        let mut m = [_mm256_setzero_si256(); super::MAX_CHUNKS];
        for b in 0..H / LANES {
            let k = n.saturating_sub(b * LANES).min(LANES);
            // SAFETY: the subslice holds four i64; the load is unaligned.
            m[b] = unsafe { _mm256_loadu_si256(TAIL[LANES - k..][..LANES].as_ptr().cast()) };
        }
        m
    }

    /// Chunk b of `src` (length n), zero past its end, as [`super::load_chunk`]; `mask`:
    /// chunk b's entry of [`row_masks`] for n.
    #[inline]
    #[target_feature(enable = "avx,avx2")]
    fn load_rows(src: &[f64], b: usize, mask: __m256i) -> __m256d {
        // SAFETY: the mask selects the lanes 4 b + l < n = src.len() only, and a masked
        // load reads no other lane (the address of a chunk past the end is not accessed).
        unsafe { _mm256_maskload_pd(src.as_ptr().wrapping_add(b * LANES), mask) }
    }

    /// Stores the lanes of chunk b of `v` that `mask` (chunk b's entry of [`row_masks`] for
    /// n = dst.len()) selects into `dst`.
    #[inline]
    #[target_feature(enable = "avx,avx2")]
    fn store_rows(dst: &mut [f64], b: usize, mask: __m256i, v: __m256d) {
        // SAFETY: the mask selects the lanes 4 b + l < dst.len() only, and a masked store
        // writes no other lane (the address of a chunk past the end is not accessed).
        unsafe { _mm256_maskstore_pd(dst.as_mut_ptr().wrapping_add(b * LANES), mask, v) }
    }

    /// Per lane `x > 0 ? pow2_inverse(x) : 1` (see `dense::pow2_inverse`): `2^(1023 - E)`
    /// for the biased exponent E of x clamped to [23, 2023], built in the exponent bits.
    #[inline]
    #[target_feature(enable = "avx,avx2")]
    fn row_scale(x: __m256d) -> __m256d {
        let e = _mm256_and_si256(
            _mm256_srli_epi64::<52>(_mm256_castpd_si256(x)),
            _mm256_set1_epi64x(0x7ff),
        );
        // The exponents fit in the low 32 bits of each lane (high halves zero), so the
        // 32-bit clamps act on them alone.
        let e =
            _mm256_min_epi32(_mm256_max_epi32(e, _mm256_set1_epi64x(23)), _mm256_set1_epi64x(2023));
        let r = _mm256_castsi256_pd(_mm256_slli_epi64::<52>(_mm256_sub_epi64(
            _mm256_set1_epi64x(2046),
            e,
        )));
        let positive = _mm256_cmp_pd::<_CMP_GT_OQ>(x, _mm256_setzero_pd());
        _mm256_blendv_pd(_mm256_set1_pd(1.0), r, positive)
    }

    /// `Workspace::init_tableau`'s column work for heights `H` of a fixed kernel (column
    /// j of M in `col(j)`, length n): the padded copy into `m_cols`, the row scales from
    /// the row maxima, the scaled columns, d (or ones) and q into the tableau, q into
    /// `q_pad`; the same values as the portable loops.
    #[inline]
    #[target_feature(enable = "avx,avx2")]
    pub(super) fn init_columns<'a, const H: usize>(
        n: usize,
        col: impl Fn(usize) -> &'a [f64],
        m_cols: &mut [Chunk],
        tab: &mut [Chunk],
        d: &[f64],
        row_scaled: bool,
        q: &[f64],
        q_pad: &mut [Chunk],
    ) {
        let nb = H / LANES;
        let abs = _mm256_castsi256_pd(_mm256_set1_epi64x(i64::MAX));
        let mut big = [_mm256_setzero_pd(); super::MAX_CHUNKS];
        let masks = row_masks::<H>(n);
        let (d, q) = (&d[..n], &q[..n]);
        for (j, dst) in m_cols[..n * nb].chunks_exact_mut(nb).enumerate() {
            let src = &col(j)[..n];
            for b in 0..nb {
                let v = load_rows(src, b, masks[b]);
                store(&mut dst[b], v);
                big[b] = _mm256_max_pd(_mm256_and_pd(v, abs), big[b]);
            }
        }
        let mut r = [_mm256_setzero_pd(); super::MAX_CHUNKS];
        for b in 0..nb {
            r[b] = row_scale(big[b]);
        }
        let (t_m, t_rest) = tab[..(n + 2) * nb].split_at_mut(n * nb);
        for (dst, src) in t_m.chunks_exact_mut(nb).zip(m_cols.chunks_exact(nb)) {
            for b in 0..nb {
                store(&mut dst[b], _mm256_mul_pd(load(&src[b]), r[b]));
            }
        }
        let (t_d, t_q) = t_rest.split_at_mut(nb);
        for b in 0..nb {
            let dv = if row_scaled {
                _mm256_and_pd(_mm256_set1_pd(1.0), _mm256_castsi256_pd(masks[b]))
            } else {
                _mm256_mul_pd(load_rows(d, b, masks[b]), r[b])
            };
            store(&mut t_d[b], dv);
            let qv = load_rows(q, b, masks[b]);
            store(&mut q_pad[b], qv);
            store(&mut t_q[b], _mm256_mul_pd(qv, r[b]));
        }
    }

    /// `x ≤ 0 → 0`, `s > 0 → x / s`, otherwise `+∞`, per lane (the residual's ratio).
    #[inline]
    #[target_feature(enable = "avx,avx2")]
    fn ratio_lanes(x: __m256d, s: __m256d) -> __m256d {
        let zero = _mm256_setzero_pd();
        let q = _mm256_blendv_pd(
            _mm256_set1_pd(f64::INFINITY),
            _mm256_div_pd(x, s),
            _mm256_cmp_pd::<_CMP_GT_OQ>(s, zero),
        );
        _mm256_blendv_pd(q, zero, _mm256_cmp_pd::<_CMP_LE_OQ>(x, zero))
    }

    /// `Workspace::tableau_candidate` for heights `H` of a fixed kernel: z from the basic
    /// values (`row_of_z[j]`: the row of z_j, or not below n), `w = M z + q` column by
    /// column with the row sums of `|M_ij z_j|`, and the residual as
    /// `solution::residual_chunks` computes it, lane by lane in the same order. Writes z
    /// and w (length n).
    #[inline]
    #[target_feature(enable = "avx,avx2")]
    pub(super) fn candidate<const H: usize>(
        n: usize,
        m_cols: &[Chunk],
        q_pad: &[Chunk],
        qbar: &[f64],
        row_of_z: &[usize],
        zero_below: f64,
        z_out: &mut [f64],
        w_out: &mut [f64],
    ) -> crate::Residual {
        let nb = H / LANES;
        let zero = _mm256_setzero_pd();
        let abs_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(i64::MAX));
        let mut w = [zero; super::MAX_CHUNKS];
        let mut a = [zero; super::MAX_CHUNKS];
        let mut z = [zero; super::MAX_CHUNKS];
        let mut qv = [zero; super::MAX_CHUNKS];
        for b in 0..nb {
            qv[b] = load(&q_pad[b]);
            w[b] = qv[b];
        }
        // z_j by column into `zs` (zero for the non-basic and the padding rows).
        let mut zs = [[0.0; LANES]; super::MAX_CHUNKS];
        for (j, col) in m_cols[..n * nb].chunks_exact(nb).enumerate() {
            let r = row_of_z[j];
            let v = qbar[if r < n { r } else { 0 }];
            let zj = if r < n && v > zero_below { v } else { 0.0 };
            zs.as_flattened_mut()[j % super::FIXED_MAX] = zj;
            let zv = _mm256_set1_pd(zj);
            for b in 0..nb {
                let t = _mm256_mul_pd(load(&col[b]), zv);
                w[b] = _mm256_add_pd(w[b], t);
                a[b] = _mm256_add_pd(a[b], _mm256_and_pd(t, abs_mask));
            }
        }
        for b in 0..nb {
            z[b] = load(&zs[b]);
        }
        let mut zm = zero;
        for b in 0..nb {
            zm = _mm256_max_pd(_mm256_and_pd(z[b], abs_mask), zm);
        }
        let z_max = hmax(zm);
        let zmv = _mm256_set1_pd(z_max);
        let (mut q_max, mut natural, mut compl) = (zero, zero, zero);
        let (mut z_violation, mut w_violation, mut relative, mut bad) = (zero, zero, zero, zero);
        for b in 0..nb {
            let (qi, zi, wi, ai) = (qv[b], z[b], w[b], a[b]);
            bad =
                _mm256_add_pd(bad, _mm256_add_pd(_mm256_mul_pd(zi, zero), _mm256_mul_pd(wi, zero)));
            let qa = _mm256_and_pd(qi, abs_mask);
            q_max = _mm256_max_pd(qa, q_max);
            natural = _mm256_max_pd(_mm256_and_pd(_mm256_min_pd(zi, wi), abs_mask), natural);
            compl = _mm256_max_pd(_mm256_and_pd(_mm256_mul_pd(zi, wi), abs_mask), compl);
            let (nz, nw) = (_mm256_sub_pd(zero, zi), _mm256_sub_pd(zero, wi));
            z_violation = _mm256_max_pd(nz, z_violation);
            w_violation = _mm256_max_pd(nw, w_violation);
            let s = _mm256_max_pd(ai, qa);
            let w_rel = ratio_lanes(nw, s);
            let wp = ratio_lanes(wi, s);
            let zr = _mm256_div_pd(zi, zmv);
            let both = _mm256_and_pd(
                _mm256_cmp_pd::<_CMP_GT_OQ>(zi, zero),
                _mm256_cmp_pd::<_CMP_GT_OQ>(wi, zero),
            );
            let c = _mm256_and_pd(_mm256_min_pd(zr, wp), both);
            relative = _mm256_max_pd(_mm256_max_pd(c, w_rel), relative);
        }
        let masks = row_masks::<H>(n);
        let (z_out, w_out) = (&mut z_out[..n], &mut w_out[..n]);
        for b in 0..nb {
            store_rows(z_out, b, masks[b], z[b]);
            store_rows(w_out, b, masks[b], w[b]);
        }
        let mut bads = [0.0; LANES];
        store(&mut bads, bad);
        crate::solution::residual_from_maxima(
            hmax(q_max),
            z_max,
            hmax(natural),
            hmax(compl),
            hmax(z_violation),
            hmax(w_violation),
            hmax(relative),
            bads.iter().all(|&v| v == 0.0),
        )
    }

    /// [`super::ratio_portable`] for heights `H` of a fixed kernel (`a`, `c`: at least
    /// H / 4 chunks), with the same result: the entering column and q̄ are loaded once, the
    /// divisions `c_i / a_i` start while the maxima are reduced, and the rows attaining θ
    /// and tied with it come out as bit masks over all rows.
    #[inline]
    #[target_feature(enable = "avx,avx2")]
    fn ratio_fixed<const H: usize>(
        a: &[Chunk],
        c: &[Chunk],
        sign: f64,
        pivot_rel: f64,
        tie_rel: f64,
    ) -> Ratio {
        let nb = H / LANES;
        let (a, c) = (&a[..nb], &c[..nb]);
        let zero = _mm256_setzero_pd();
        let abs = _mm256_castsi256_pd(_mm256_set1_epi64x(i64::MAX));
        let vsign = _mm256_set1_pd(sign);
        let (mut av, mut cv, mut q) =
            ([zero; super::MAX_CHUNKS], [zero; super::MAX_CHUNKS], [zero; super::MAX_CHUNKS]);
        let (mut amax, mut cmax) = (zero, zero);
        for b in 0..nb {
            let (x, y) = (load(&a[b]), load(&c[b]));
            amax = _mm256_max_pd(_mm256_and_pd(x, abs), amax);
            cmax = _mm256_max_pd(_mm256_and_pd(y, abs), cmax);
            av[b] = _mm256_mul_pd(vsign, x);
            cv[b] = y;
            q[b] = _mm256_div_pd(y, av[b]);
        }
        // The rows with a_i > 0 first, which does not wait for the tolerance: they are the
        // rows with a_i > ptol unless some 0 < a_i <= ptol, which is checked aside.
        let inf = _mm256_set1_pd(f64::INFINITY);
        let mut valid = [zero; super::MAX_CHUNKS];
        let mut ratios = [zero; super::MAX_CHUNKS];
        let mut rmin = inf;
        for b in 0..nb {
            valid[b] = _mm256_cmp_pd::<_CMP_GT_OQ>(av[b], zero);
            ratios[b] = _mm256_blendv_pd(inf, q[b], valid[b]);
            rmin = _mm256_min_pd(ratios[b], rmin);
        }
        let ptol = pivot_rel * hmax(amax);
        let vptol = _mm256_set1_pd(ptol);
        let mut small = _mm256_setzero_pd();
        for b in 0..nb {
            let big = _mm256_cmp_pd::<_CMP_GT_OQ>(av[b], vptol);
            small = _mm256_or_pd(small, _mm256_andnot_pd(big, valid[b]));
        }
        if _mm256_movemask_pd(small) != 0 {
            rmin = inf;
            for b in 0..nb {
                valid[b] = _mm256_cmp_pd::<_CMP_GT_OQ>(av[b], vptol);
                ratios[b] = _mm256_blendv_pd(inf, q[b], valid[b]);
                rmin = _mm256_min_pd(ratios[b], rmin);
            }
        }
        let q = ratios;
        let theta = hmin(rmin);
        if !(theta < f64::INFINITY) {
            return Ratio::NoFinite;
        }
        let eps = tie_rel * super::fmax(hmax(cmax), f64::MIN_POSITIVE);
        let (vtheta, veps) = (_mm256_set1_pd(theta), _mm256_set1_pd(eps));
        // Bit i: row i attains θ (only valid rows can: the others hold +∞), row i ties.
        let (mut at, mut tied) = (0u32, 0u32);
        for b in 0..nb {
            let hit = _mm256_cmp_pd::<_CMP_EQ_OQ>(q[b], vtheta);
            let gap = _mm256_sub_pd(cv[b], _mm256_mul_pd(vtheta, av[b]));
            let tie = _mm256_and_pd(valid[b], _mm256_cmp_pd::<_CMP_LE_OQ>(gap, veps));
            at |= (_mm256_movemask_pd(hit) as u32) << (LANES * b);
            tied |= (_mm256_movemask_pd(tie) as u32) << (LANES * b);
        }
        if tied & tied.wrapping_sub(1) == 0 {
            // At most one row ties; θ is attained, so `at` has a bit.
            Ratio::Row(at.trailing_zeros() as usize)
        } else {
            Ratio::Tied { ptol, theta, eps }
        }
    }

    /// `Workspace::pivot_loop` for heights `H` of a fixed kernel: ratio tests by
    /// [`ratio_fixed`] and the pivots' column updates in line, with the same results as
    /// the portable loop. The bookkeeping arrays hold at least [`super::IDX`] entries and are indexed
    /// modulo that length (all indices are below 2 n + 1 <= 65), which needs no bounds
    /// checks.
    #[inline(never)]
    #[target_feature(enable = "avx,avx2")]
    pub(super) fn pivot_loop<const H: usize>(
        ws: &mut Workspace,
        opts: &LemkeOptions,
    ) -> (End, usize) {
        const M: usize = IDX - 1;
        let n = ws.n;
        let nb = H / LANES;
        let z0 = 2 * n;
        let (pr, tr) = (opts.pivot_tolerance, opts.tie_tolerance);
        let zero = _mm256_setzero_pd();
        let one = _mm256_set1_pd(1.0);
        let sign0 = _mm256_set1_pd(-0.0);
        // First pivot: z_0 enters (column n) and every row takes part with a_i = d_i.
        let mut s = n;
        let mut pivots = 0usize;
        loop {
            let initial = pivots == 0;
            let sign = if initial { 1.0 } else { -1.0 };
            let tab = &ws.tab[..(n + 2) * nb];
            let r = match ratio_fixed::<H>(&tab[s * nb..], &tab[(n + 1) * nb..], sign, pr, tr) {
                Ratio::Row(r) => r,
                Ratio::Tied { ptol, theta, eps } => ws.select_tied(s, initial, ptol, theta, eps),
                Ratio::NoFinite => match ws.select_row_exact(s, initial, opts) {
                    Some(r) => r,
                    None => return (End::Ray, pivots),
                },
            };
            let leaving = ws.basic[..IDX][r & M];
            let last = leaving == z0;
            // The pivot (`Workspace::pivot`): the columns from `first` (all n + 2, or q̄
            // alone when z_0 leaves) become `(x & keep) + ρ v` with `ρ = −(x_r inv)`, then
            // column s becomes `v inv`.
            let r = r & (super::FIXED_MAX - 1);
            let (rb, rl) = (r / LANES, r % LANES);
            let window = &super::KEEP[super::FIXED_MAX - 1 - r..][..super::FIXED_MAX];
            let tab = &mut ws.tab[..(n + 2) * nb];
            let u = &tab[s * nb..][..nb];
            let inv = 1.0 / u[rb][rl];
            let vinv = _mm256_set1_pd(inv);
            let (mut keep, mut v) = ([zero; super::MAX_CHUNKS], [zero; super::MAX_CHUNKS]);
            for b in 0..nb {
                // SAFETY: the window holds FIXED_MAX >= 4 (b + 1) masks; unaligned load.
                keep[b] = unsafe { _mm256_loadu_pd(window.as_ptr().add(b * LANES).cast()) };
                v[b] = _mm256_blendv_pd(one, load(&u[b]), keep[b]);
            }
            let first = if last { n + 1 } else { 0 };
            for col in tab[first * nb..].chunks_exact_mut(nb) {
                let rho = _mm256_xor_pd(_mm256_mul_pd(_mm256_set1_pd(col[rb][rl]), vinv), sign0);
                for b in 0..nb {
                    let x = _mm256_and_pd(load(&col[b]), keep[b]);
                    store(&mut col[b], _mm256_add_pd(x, _mm256_mul_pd(rho, v[b])));
                }
            }
            if !last {
                for (b, c) in tab[s * nb..][..nb].iter_mut().enumerate() {
                    store(c, _mm256_mul_pd(v[b], vinv));
                }
            }
            ws.exchange::<H>(r, s);
            pivots += 1;
            if last {
                return (End::Complementary, pivots);
            }
            if pivots >= opts.max_pivots {
                return (End::Limit, pivots);
            }
            let next = if leaving < n { leaving + n } else { leaving - n };
            s = ws.col_of[..IDX][next & M];
        }
    }

    /// [`super::ratio_portable`] in 256-bit operations, with the same result.
    #[inline]
    #[target_feature(enable = "avx,avx2")]
    pub(super) fn ratio(
        a: &[Chunk],
        c: &[Chunk],
        sign: f64,
        pivot_rel: f64,
        tie_rel: f64,
    ) -> Ratio {
        let c = &c[..a.len()];
        let abs = _mm256_castsi256_pd(_mm256_set1_epi64x(i64::MAX));
        let mut amax = _mm256_setzero_pd();
        let mut cmax = _mm256_setzero_pd();
        for (ac, cc) in a.iter().zip(c) {
            amax = _mm256_max_pd(_mm256_and_pd(load(ac), abs), amax);
            cmax = _mm256_max_pd(_mm256_and_pd(load(cc), abs), cmax);
        }
        let ptol = pivot_rel * hmax(amax);
        let vsign = _mm256_set1_pd(sign);
        let vptol = _mm256_set1_pd(ptol);
        let inf = _mm256_set1_pd(f64::INFINITY);
        let mut rmin = inf;
        for (ac, cc) in a.iter().zip(c) {
            let ai = _mm256_mul_pd(vsign, load(ac));
            let valid = _mm256_cmp_pd::<_CMP_GT_OQ>(ai, vptol);
            let ratio = _mm256_blendv_pd(inf, _mm256_div_pd(load(cc), ai), valid);
            rmin = _mm256_min_pd(ratio, rmin);
        }
        let theta = hmin(rmin);
        if !(theta < f64::INFINITY) {
            return Ratio::NoFinite;
        }
        let eps = tie_rel * super::fmax(hmax(cmax), f64::MIN_POSITIVE);
        let vtheta = _mm256_set1_pd(theta);
        let veps = _mm256_set1_pd(eps);
        let mut first = NONE;
        let mut count = 0usize;
        for (b, (ac, cc)) in a.iter().zip(c).enumerate() {
            let ai = _mm256_mul_pd(vsign, load(ac));
            let ci = load(cc);
            let valid = _mm256_cmp_pd::<_CMP_GT_OQ>(ai, vptol);
            let at = _mm256_cmp_pd::<_CMP_EQ_OQ>(_mm256_div_pd(ci, ai), vtheta);
            let gap = _mm256_sub_pd(ci, _mm256_mul_pd(vtheta, ai));
            let tied = _mm256_cmp_pd::<_CMP_LE_OQ>(gap, veps);
            let at = _mm256_movemask_pd(_mm256_and_pd(valid, at)) as u32;
            let tied = _mm256_movemask_pd(_mm256_and_pd(valid, tied)) as usize;
            if first == NONE && at != 0 {
                first = b * LANES + at.trailing_zeros() as usize;
            }
            count += usize::from(POP4[tied & 15]);
        }
        if count <= 1 { Ratio::Row(first) } else { Ratio::Tied { ptol, theta, eps } }
    }
}

impl Workspace {
    fn prepare(&mut self, n: usize) {
        // Every buffer's size is a function of n alone.
        if self.prepared == Some(n) {
            return;
        }
        if self.prepared.is_none() {
            self.avx = avx2_available();
        }
        self.prepared = Some(n);
        self.n = n;
        self.h = padded_height(n);
        self.nb = self.h / LANES;
        let nb = self.nb;
        self.m_cols.resize(n * nb, [0.0; LANES]);
        self.m_rows.resize(n * n, 0.0);
        self.basis_cols.resize(n * n, 0.0);
        self.q_pad.resize(nb, [0.0; LANES]);
        self.scratch.resize(3 * nb, [0.0; LANES]);
        self.keep.resize(nb, [0; LANES]);
        self.q.resize(n, 0.0);
        self.d.resize(n, 1.0);
        self.tab.resize((n + 2) * nb, [0.0; LANES]);
        // At least IDX entries each: the kernels of fixed height index them modulo IDX.
        let idx = (2 * n + 1).max(IDX);
        self.basic.resize(idx, NONE);
        self.nonbasic.resize(idx, NONE);
        self.row_of.resize(idx, NONE);
        self.col_of.resize(idx, NONE);
        self.rhs.resize(n, 0.0);
        self.z_alt.resize(n, 0.0);
        self.w_alt.resize(n, 0.0);
        self.row_abs.resize(n, 0.0);
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

    /// Set-up, pivoting and the tableau's candidate (into `out`), with the kernels compiled
    /// for AVX2 when the processor has it. Returns how the pivoting ended and the pivots.
    #[allow(unsafe_code)]
    fn run(&mut self, lcp: LcpRef<'_>, opts: &LemkeOptions, out: &mut Solution) -> (End, usize) {
        self.tie_rel = opts.tie_tolerance;
        #[cfg(target_arch = "x86_64")]
        if self.avx {
            // SAFETY: `self.avx` is set only by `avx2_available`, which detected AVX and
            // AVX2 on this processor; `run_avx2` needs nothing else.
            return unsafe { self.run_avx2(lcp, opts, out) };
        }
        self.run_plain(lcp, opts, out)
    }

    /// [`Self::run_sized`] for the baseline target.
    fn run_plain(
        &mut self,
        lcp: LcpRef<'_>,
        opts: &LemkeOptions,
        out: &mut Solution,
    ) -> (End, usize) {
        by_height!(self.run_sized::<false>(lcp, opts, out))
    }

    /// [`Self::run_sized`] compiled with 256-bit AVX instructions. Multiplications and
    /// additions stay separate (no FMA), so every result is bit for bit that of the
    /// baseline copy.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx,avx2")]
    fn run_avx2(
        &mut self,
        lcp: LcpRef<'_>,
        opts: &LemkeOptions,
        out: &mut Solution,
    ) -> (End, usize) {
        by_height!(self.run_sized::<true>(lcp, opts, out))
    }

    /// The body of [`Self::run`] for columns of H rows (H = 0: `self.h`, any height), with
    /// the AVX kernels when `AVX` (only inside [`Self::run_avx2`]).
    #[inline(always)]
    fn run_sized<const H: usize, const AVX: bool>(
        &mut self,
        lcp: LcpRef<'_>,
        opts: &LemkeOptions,
        out: &mut Solution,
    ) -> (End, usize) {
        self.init_tableau::<H, AVX>(lcp);
        let ended = self.pivot_loop::<H, AVX>(opts);
        self.tableau_candidate::<H, AVX>(out, 0.0);
        if matches!(ended.0, End::Complementary) && !(out.residual.relative <= opts.tolerance) {
            // A degenerate basic variable that should be zero but holds round-off (z_j of
            // order 1e-16 ‖z‖∞) makes the rows where it is the only term fail the
            // residual test; the same basis with such values zeroed is tried before the LU
            // re-solve.
            let z_max = out.z.iter().fold(0.0, |a, &v| fmax(a, v));
            let first = out.residual;
            std::mem::swap(&mut out.z, &mut self.z_tab);
            std::mem::swap(&mut out.w, &mut self.w_tab);
            self.tableau_candidate::<H, AVX>(out, ROUND_OFF_ZERO * z_max);
            if !(out.residual.relative < first.relative) {
                std::mem::swap(&mut out.z, &mut self.z_tab);
                std::mem::swap(&mut out.w, &mut self.w_tab);
                out.residual = first;
            }
        }
        ended
    }

    /// Chunks per column: H / [`LANES`], or `self.nb` for H = 0.
    #[inline(always)]
    fn chunks<const H: usize>(&self) -> usize {
        if H == 0 { self.nb } else { H / LANES }
    }

    /// Tableau `x_B = q̄ + T x_N` for the basis {w}: `T = [M | d]`, `q̄ = q`, stored
    /// column by column (n + 2 columns of h rows: the n + 1 non-basic variables, then q̄).
    /// Variables: `w_i = i`, `z_i = n + i`, `z_0 = 2 n`.
    ///
    /// Each row is scaled by a power of two r_i near `1 / max_j |M_ij|` (exact in floating
    /// point). Scaling row i of (M, d, q) by r_i > 0 only scales w_i, so the pivot sequence
    /// is the same in exact arithmetic, while the relative pivot tolerance and the tie
    /// tests become independent of the magnitudes of the rows.
    ///
    /// With [`Covering::RowScaled`] the column of z_0 holds ones in the scaled rows.
    ///
    /// M is read once, column by column as it is stored, into the unscaled padded copy
    /// (which the residual reads) while the row maxima are taken; the tableau's columns
    /// are then the copy's times the row scales.
    #[allow(unsafe_code)]
    #[inline(always)]
    fn init_tableau<const H: usize, const AVX: bool>(&mut self, lcp: LcpRef<'_>) {
        let n = self.n;
        let nb = self.chunks::<H>();
        let m = lcp.m();
        #[cfg(target_arch = "x86_64")]
        if AVX
            && H != 0
            && let Some(mc) = m.try_as_col_major()
        {
            // SAFETY: AVX is true only in the copy that `Workspace::run` calls after
            // detecting AVX and AVX2 on this processor.
            unsafe {
                avx::init_columns::<H>(
                    n,
                    |j| mc.col(j).as_slice(),
                    &mut self.m_cols,
                    &mut self.tab,
                    &self.d,
                    self.row_scaled,
                    &self.q,
                    &mut self.q_pad,
                );
            }
            self.init_basis::<H>();
            return;
        }
        let mut local = [[0.0; LANES]; MAX_CHUNKS];
        let big: &mut [Chunk] = if H == 0 {
            let big = &mut self.scratch[..nb];
            big.fill([0.0; LANES]);
            big
        } else {
            &mut local[..nb]
        };
        let m_cols = &mut self.m_cols[..n * nb];
        if let Some(mc) = m.try_as_col_major() {
            for (j, dst) in m_cols.chunks_exact_mut(nb).enumerate() {
                let src = mc.col(j).as_slice();
                for b in 0..nb {
                    let c = load_chunk(src, b);
                    dst[b] = c;
                    for l in 0..LANES {
                        big[b][l] = fmax(big[b][l], c[l].abs());
                    }
                }
            }
        } else {
            for (j, dst) in m_cols.chunks_exact_mut(nb).enumerate() {
                let col = m.col(j);
                let dst = dst.as_flattened_mut();
                dst.fill(0.0);
                for i in 0..n {
                    dst[i] = col[i];
                }
                for (b, c) in dst.as_chunks::<LANES>().0.iter().enumerate() {
                    for l in 0..LANES {
                        big[b][l] = fmax(big[b][l], c[l].abs());
                    }
                }
            }
        }
        // The row scales (1 for a zero row and the padding).
        for c in big.iter_mut() {
            for v in c.iter_mut() {
                *v = if *v > 0.0 { pow2_inverse(*v) } else { 1.0 };
            }
        }
        let r: &[Chunk] = big;
        let tab = &mut self.tab[..(n + 2) * nb];
        let (t_m, t_rest) = tab.split_at_mut(n * nb);
        for (dst, src) in t_m.chunks_exact_mut(nb).zip(m_cols.chunks_exact(nb)) {
            for b in 0..nb {
                for l in 0..LANES {
                    dst[b][l] = src[b][l] * r[b][l];
                }
            }
        }
        let (t_d, t_q) = t_rest.split_at_mut(nb);
        for b in 0..nb {
            let d = load_chunk(&self.d, b);
            let q = load_chunk(&self.q, b);
            self.q_pad[b] = q;
            for l in 0..LANES {
                t_d[b][l] = if self.row_scaled {
                    if b * LANES + l < n { 1.0 } else { 0.0 }
                } else {
                    d[l] * r[b][l]
                };
                t_q[b][l] = q[l] * r[b][l];
            }
        }
        self.init_basis::<H>();
    }

    /// The basis {w}: `w_i` basic in row i, `z_j` non-basic in column j, `z_0` in
    /// column n.
    #[inline(always)]
    fn init_basis<const H: usize>(&mut self) {
        let n = self.n;
        if H != 0 {
            // Copies of fixed length H or H + 1 (the arrays hold IDX >= n + H + 1 entries;
            // what they write past 2 n + 1 is never read).
            self.basic[..H].copy_from_slice(&IOTA[..H]);
            self.nonbasic[..H + 1].copy_from_slice(&IOTA[n..n + H + 1]);
            self.row_of[..H].copy_from_slice(&IOTA[..H]);
            self.row_of[n..n + H + 1].fill(NONE);
            self.col_of[..H].fill(NONE);
            self.col_of[n..n + H + 1].copy_from_slice(&IOTA[..H + 1]);
            return;
        }
        for (i, v) in self.basic[..n].iter_mut().enumerate() {
            *v = i;
        }
        let (w_rows, z_rows) = self.row_of[..2 * n + 1].split_at_mut(n);
        for (i, v) in w_rows.iter_mut().enumerate() {
            *v = i;
        }
        z_rows.fill(NONE);
        let (w_cols, z_cols) = self.col_of[..2 * n + 1].split_at_mut(n);
        w_cols.fill(NONE);
        for (j, v) in z_cols.iter_mut().enumerate() {
            *v = j;
        }
        for (j, v) in self.nonbasic[..n + 1].iter_mut().enumerate() {
            *v = n + j;
        }
    }

    #[allow(unsafe_code)]
    #[inline(always)]
    fn pivot_loop<const H: usize, const AVX: bool>(&mut self, opts: &LemkeOptions) -> (End, usize) {
        #[cfg(target_arch = "x86_64")]
        if AVX && H != 0 {
            // SAFETY: AVX is true only in the copy that `Workspace::run` calls after
            // detecting AVX and AVX2 on this processor.
            return unsafe { avx::pivot_loop::<H>(self, opts) };
        }
        let n = self.n;
        let z0 = 2 * n;
        // First pivot: z_0 enters and the row with the most negative q_i / d_i leaves.
        let Some(r) = self.select_row::<H, AVX>(n, true, opts) else {
            return (End::Ray, 0);
        };
        let mut leaving = self.pivot::<H>(r, n);
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
            let Some(r) = self.select_row::<H, AVX>(s, false, opts) else {
                return (End::Ray, pivots);
            };
            leaving = self.pivot::<H>(r, s);
            pivots += 1;
        }
    }

    /// Entry `(i, c)` of the tableau (column c, row i).
    #[inline]
    fn entry(&self, i: usize, c: usize) -> f64 {
        self.tab[c * self.nb + i / LANES][i % LANES]
    }

    /// Entry `j` of row `i` of `B^{-1}`, read from the condensed tableau: the column of
    /// a non-basic `w_j` holds `-B^{-1} e_j`, and a basic `w_j` in row k has
    /// `B^{-1} e_j = e_k`.
    #[inline]
    fn binv(&self, i: usize, j: usize) -> f64 {
        let r = self.row_of[j];
        if r != NONE { if r == i { 1.0 } else { 0.0 } } else { -self.entry(i, self.col_of[j]) }
    }

    /// The ratio test for entering column `s`. In the first step (`initial`), every row
    /// takes part with `a_i = d_i`; afterwards the rows with `T_is < 0` take part with
    /// `a_i = -T_is`. The minimum ratio `θ = min q̄_i / a_i` over `a_i > ptol` and the first
    /// row attaining it are found lane by lane; the rows tied with it within the tie
    /// tolerance are counted, and only when there are two or more does the lexicographic
    /// rule ([`Self::select_tied`]) decide.
    #[allow(unsafe_code)]
    #[inline(always)]
    fn select_row<const H: usize, const AVX: bool>(
        &mut self,
        s: usize,
        initial: bool,
        opts: &LemkeOptions,
    ) -> Option<usize> {
        let n = self.n;
        let nb = self.chunks::<H>();
        let sign = if initial { 1.0 } else { -1.0 };
        let a = &self.tab[s * nb..(s + 1) * nb];
        let c = &self.tab[(n + 1) * nb..(n + 2) * nb];
        let (pr, tr) = (opts.pivot_tolerance, opts.tie_tolerance);
        #[cfg(target_arch = "x86_64")]
        let first = if AVX {
            // SAFETY: AVX is true only in the copy that `Workspace::run` calls after
            // detecting AVX and AVX2 on this processor.
            unsafe { avx::ratio(a, c, sign, pr, tr) }
        } else {
            ratio_portable(a, c, sign, pr, tr)
        };
        #[cfg(not(target_arch = "x86_64"))]
        let first = ratio_portable(a, c, sign, pr, tr);
        match first {
            Ratio::Row(r) => Some(r),
            Ratio::Tied { ptol, theta, eps } => {
                Some(self.select_tied(s, initial, ptol, theta, eps))
            }
            Ratio::NoFinite => self.select_row_exact(s, initial, opts),
        }
    }

    /// The ratio test row by row, comparing ratios without dividing: for the rare case of
    /// no finite ratio in [`Self::select_row`] (a ray, or ratios beyond the range of f64).
    #[inline(never)]
    fn select_row_exact(&mut self, s: usize, initial: bool, opts: &LemkeOptions) -> Option<usize> {
        let n = self.n;
        let sign = if initial { 1.0 } else { -1.0 };
        let mut colmax = 0.0f64;
        let mut cmax = 0.0f64;
        for i in 0..n {
            colmax = fmax(colmax, self.entry(i, s).abs());
            cmax = fmax(cmax, self.entry(i, n + 1).abs());
        }
        let ptol = opts.pivot_tolerance * colmax;
        let mut best = NONE;
        let (mut cb, mut ab) = (f64::INFINITY, 1.0);
        for i in 0..n {
            let (a, c) = (sign * self.entry(i, s), self.entry(i, n + 1));
            if a > ptol && c * ab < cb * a {
                best = i;
                cb = c;
                ab = a;
            }
        }
        if best == NONE {
            return None;
        }
        let theta = cb / ab;
        let eps = opts.tie_tolerance * fmax(cmax, f64::MIN_POSITIVE);
        Some(self.select_tied(s, initial, ptol, theta, eps))
    }

    /// Among the rows with `a_i > ptol` and `q̄_i − θ a_i <= eps`: z_0's row if it is one
    /// of them (after the first step), otherwise the row whose row of `[q̄ | B^{-1}]`
    /// divided by `a_i` is lexicographically smallest (q̄_i / a_i tie, so `B^{-1}` decides).
    ///
    /// The comparison runs column by column over the tied rows, as the ratio test does on
    /// q̄: in column j the smallest `β_ij / a_i` (β = B^{-1}) is found, and the rows with
    /// `(β_ij / a_i − min) a_i <= tie_rel · max_i |β_ij|` stay tied; the others drop out.
    /// The tolerance is relative to the column's largest entry, not to the two values
    /// compared: pivots leave round-off of order 1e-15 in entries that are exactly zero,
    /// and a comparison of two such entries by their own size would let that round-off
    /// pick the row, which breaks the rule's guarantee (no basis repeats) and let the
    /// method cycle. Rows that stay tied over all n columns (which needs a nearly singular
    /// basis) are decided by the largest `a_i`, the most stable pivot.
    #[inline(never)]
    fn select_tied(&mut self, s: usize, initial: bool, ptol: f64, theta: f64, eps: f64) -> usize {
        let n = self.n;
        let sign = if initial { 1.0 } else { -1.0 };
        self.ties.clear();
        for i in 0..n {
            let a = sign * self.entry(i, s);
            if a > ptol && self.entry(i, n + 1) - theta * a <= eps {
                self.ties.push(i);
            }
        }
        if !initial {
            let z0 = 2 * n;
            if let Some(&r) = self.ties.iter().find(|&&i| self.basic[i] == z0) {
                return r;
            }
        }
        let mut ties = std::mem::take(&mut self.ties);
        for j in 0..n {
            if ties.len() <= 1 {
                break;
            }
            let scale = match self.col_of[j] {
                NONE => 1.0,
                c => (0..n).fold(0.0, |m, i| fmax(m, self.entry(i, c).abs())),
            };
            let tol = self.tie_rel * scale;
            let key = |i: usize| self.binv(i, j) / (sign * self.entry(i, s));
            let least = ties.iter().fold(f64::INFINITY, |m, &i| fmin(m, key(i)));
            ties.retain(|&i| (key(i) - least) * (sign * self.entry(i, s)) <= tol);
        }
        let mut pick = ties[0];
        for &i in &ties[1..] {
            if sign * self.entry(i, s) > sign * self.entry(pick, s) {
                pick = i;
            }
        }
        self.ties = ties;
        pick
    }

    /// Exchanges the basic variable of row r with the non-basic variable of column s and
    /// returns the variable that left the basis.
    ///
    /// With `inv = 1 / T_rs`, every other column j gets `ρ_j = −(T_rj inv)` in row r and
    /// `T_ij + T_is ρ_j` in the other rows, and column s becomes `T_is inv` with `inv` in
    /// row r (the leaving variable's column): the operations, and so the roundings, of the
    /// row update `row_i += T_is · row_r / (−T_rs)`. Row r is selected by bit masks
    /// (from [`KEEP`] for the fixed heights), not by a compare per lane, which the
    /// compiler would turn into branches on r, nor by a scalar store into a chunk that the
    /// next kernel reads whole. All columns, s included, go through one loop; column s is
    /// then overwritten with `v inv` (v: column s with 1 in row r).
    ///
    /// When z_0 leaves, the pivot ends the method and only q̄ (the basic values) is read
    /// afterwards, so only q̄ is updated.
    #[inline(always)]
    fn pivot<const H: usize>(&mut self, r: usize, s: usize) -> usize {
        let n = self.n;
        let nb = self.chunks::<H>();
        let leaving = self.basic[r];
        let last = leaving == 2 * n;
        // The columns to update: all n + 2, or q̄ alone in the last pivot.
        let (first_col, ncols) = if last { (n + 1, 1) } else { (0, n + 2) };
        let tab = &mut self.tab[..(n + 2) * nb];
        let inv = 1.0 / tab[s * nb + r / LANES][r % LANES];
        // Bit masks that clear row r.
        let mut local_keep = [[0u64; LANES]; MAX_CHUNKS];
        let keep: &[[u64; LANES]] = if H == 0 {
            let keep = &mut self.keep[..nb];
            for b in 0..nb {
                for l in 0..LANES {
                    keep[b][l] = if b * LANES + l == r { 0 } else { u64::MAX };
                }
            }
            keep
        } else {
            let window = &KEEP[FIXED_MAX - 1 - r..][..H];
            for b in 0..nb {
                for l in 0..LANES {
                    local_keep[b][l] = window[b * LANES + l];
                }
            }
            &local_keep[..nb]
        };
        // v: column s with 1 in row r, so that row r of each column receives ρ_j itself.
        let mut local = [[0.0; LANES]; MAX_CHUNKS];
        let v: &mut [Chunk] = if H == 0 { &mut self.scratch[..nb] } else { &mut local[..nb] };
        let one = 1.0f64.to_bits();
        let u = &tab[s * nb..(s + 1) * nb];
        for b in 0..nb {
            for l in 0..LANES {
                let k = keep[b][l];
                v[b][l] = f64::from_bits((u[b][l].to_bits() & k) | (one & !k));
            }
        }
        let v: &[Chunk] = v;
        update_columns::<H>(
            &mut tab[first_col * nb..(first_col + ncols) * nb],
            v,
            keep,
            nb,
            r,
            inv,
        );
        if !last {
            for (b, c) in tab[s * nb..(s + 1) * nb].iter_mut().enumerate() {
                for l in 0..LANES {
                    c[l] = v[b][l] * inv;
                }
            }
        }
        self.exchange::<H>(r, s);
        leaving
    }

    /// The bookkeeping of a pivot: the basic variable of row r and the non-basic variable
    /// of column s change places. For the fixed heights (`H > 0`) the arrays hold at least
    /// [`IDX`] entries and every index is below 2 n + 1 <= 65, so they are indexed modulo
    /// `IDX` within their first `IDX` entries, which needs no bounds checks.
    #[inline(always)]
    fn exchange<const H: usize>(&mut self, r: usize, s: usize) {
        let (len, m) = if H != 0 { (IDX, IDX - 1) } else { (self.basic.len(), usize::MAX) };
        let basic = &mut self.basic[..len];
        let nonbasic = &mut self.nonbasic[..len];
        let row_of = &mut self.row_of[..len];
        let col_of = &mut self.col_of[..len];
        let leaving = basic[r & m];
        let entering = nonbasic[s & m];
        basic[r & m] = entering;
        row_of[entering & m] = r;
        col_of[entering & m] = NONE;
        nonbasic[s & m] = leaving;
        col_of[leaving & m] = s;
        row_of[leaving & m] = NONE;
    }

    /// Fills the row-major copy of M from the column-major one, for the LU re-solve.
    fn fill_m_rows(&mut self) {
        let n = self.n;
        let nb = self.nb;
        for (j, col) in self.m_cols[..n * nb].chunks_exact(nb).enumerate() {
            for (i, v) in col.as_flattened()[..n].iter().enumerate() {
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

    /// z = the basic solution in `rhs` (clamped at 0), zero off the basis.
    fn set_basic_z(&self, out: &mut Solution) {
        out.z.fill(0.0);
        for (t, &i) in self.alpha.iter().enumerate() {
            out.z[i] = positive_part(self.rhs[t]);
        }
    }

    /// z = the basic solution in `rhs` (clamped at 0), w = M z + q, and its residual.
    fn scatter(&mut self, out: &mut Solution) {
        self.set_basic_z(out);
        // The basis' columns of M from its row-major copy, as the warm basis has them.
        let (n, k) = (self.n, self.alpha.len());
        for (col, &j) in self.basis_cols.chunks_exact_mut(n).zip(&self.alpha) {
            for (i, v) in col.iter_mut().enumerate() {
                *v = self.m_rows[i * n + j];
            }
        }
        out.residual = finish_sparse(
            &self.basis_cols[..k * n],
            n,
            &self.q,
            &out.z,
            &self.alpha,
            &mut out.w,
            &mut self.row_abs,
        );
    }

    /// Writes the basic values of the tableau as z into `out` (values at or below
    /// `zero_below` taken as 0; `zero_below = 0` clamps at 0), with `w = M z + q` and its
    /// residual (status left to the caller).
    ///
    /// w is accumulated column by column in ascending order, each row summing its terms
    /// `M_ij z_j` in that order. For heights with a fixed kernel every column takes part
    /// (a non-basic z_j = 0 adds zero), which costs less than branching on the basis; w and
    /// the row sums then stay in registers.
    #[allow(unsafe_code)]
    #[inline(always)]
    fn tableau_candidate<const H: usize, const AVX: bool>(
        &mut self,
        out: &mut Solution,
        zero_below: f64,
    ) {
        let n = self.n;
        let nb = self.chunks::<H>();
        #[cfg(target_arch = "x86_64")]
        if AVX && H != 0 {
            // SAFETY: AVX is true only in the copy that `Workspace::run` calls after
            // detecting AVX and AVX2 on this processor.
            out.residual = unsafe {
                avx::candidate::<H>(
                    n,
                    &self.m_cols,
                    &self.q_pad,
                    self.tab[(n + 1) * nb..(n + 2) * nb].as_flattened(),
                    &self.row_of[n..2 * n],
                    zero_below,
                    &mut out.z,
                    &mut out.w,
                )
            };
            return;
        }
        let mut lz = [[0.0; LANES]; MAX_CHUNKS];
        let mut lw = [[0.0; LANES]; MAX_CHUNKS];
        let mut la = [[0.0; LANES]; MAX_CHUNKS];
        let (z, w, abs): (&mut [Chunk], &mut [Chunk], &mut [Chunk]) = if H == 0 {
            let (z, rest) = self.scratch[..3 * nb].split_at_mut(nb);
            let (w, abs) = rest.split_at_mut(nb);
            z.fill([0.0; LANES]);
            abs.fill([0.0; LANES]);
            (z, w, abs)
        } else {
            (&mut lz[..nb], &mut lw[..nb], &mut la[..nb])
        };
        let q = &self.q_pad[..nb];
        w.copy_from_slice(q);
        let qbar = self.tab[(n + 1) * nb..(n + 2) * nb].as_flattened();
        for (j, col) in self.m_cols[..n * nb].chunks_exact(nb).enumerate() {
            let r = self.row_of[n + j];
            if H == 0 && r == NONE {
                continue;
            }
            let v = qbar[if r < n { r } else { 0 }];
            let zj = if r < n && v > zero_below { v } else { 0.0 };
            for b in 0..nb {
                for l in 0..LANES {
                    let t = col[b][l] * zj;
                    w[b][l] += t;
                    abs[b][l] += t.abs();
                    z[b][l] = if b * LANES + l == j { zj } else { z[b][l] };
                }
            }
        }
        out.residual = residual_chunks(q, z, w, abs);
        out.z.copy_from_slice(&z.as_flattened()[..n]);
        out.w.copy_from_slice(&w.as_flattened()[..n]);
    }
}

/// The column updates of a pivot in row r with `inv = 1 / T_rs`: every column x of `cols`
/// (columns of `nb` chunks) becomes `x + ρ v` with `ρ = −(x_r inv)` and x_r cleared first
/// (`keep`: all bits set but in row r; `v`: the pivot column with 1 in row r).
#[inline(always)]
fn update_columns<const H: usize>(
    cols: &mut [Chunk],
    v: &[Chunk],
    keep: &[[u64; LANES]],
    nb: usize,
    r: usize,
    inv: f64,
) {
    let (v, keep) = (&v[..nb], &keep[..nb]);
    let (rb, rl) = (r / LANES, r % LANES);
    for col in cols.chunks_exact_mut(nb) {
        let x_r = col[rb][rl];
        // Large problems skip the columns with a zero in the pivot row (unchanged); the
        // kernels of fixed size update them too rather than branch.
        if H == 0 && x_r == 0.0 {
            continue;
        }
        let rho = -(x_r * inv);
        for b in 0..nb {
            for l in 0..LANES {
                let x = f64::from_bits(col[b][l].to_bits() & keep[b][l]);
                col[b][l] = x + rho * v[b][l];
            }
        }
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

#[cfg(test)]
mod tests {
    use faer::Mat;

    use super::*;
    use crate::Lcp;

    /// A number uniformly distributed in [-1, 1) from the shared test generator.
    fn uniform(rng: &mut moreau_testsupport::SplitMix64) -> f64 {
        rng.uniform(-1.0, 1.0)
    }

    /// The AVX2 and the baseline copies of the kernels give the same pivots, z, w and
    /// residual, bit for bit, on SPD, non-symmetric and degenerate problems of sizes 1 to
    /// 40 (fixed-size and run-time-size kernels), with both covering vectors.
    #[test]
    fn avx2_and_baseline_kernels_agree_bit_for_bit() {
        if !avx2_available() {
            // A pass here would claim an agreement that was never checked.
            assert!(
                std::env::var_os("MOREAU_LCP_ALLOW_NO_SIMD").is_some(),
                "this processor has no AVX2, so the AVX2 copy of Lemke's kernels cannot be \
                 compared with the baseline copy; set MOREAU_LCP_ALLOW_NO_SIMD=1 to skip the \
                 comparison on such a machine"
            );
            eprintln!("skipped: no AVX2 on this processor (MOREAU_LCP_ALLOW_NO_SIMD is set)");
            return;
        }
        let mut state = moreau_testsupport::SplitMix64::new(7);
        let mut fast = Lemke::default();
        let mut plain = Lemke::default();
        let (mut a, mut b) = (Solution::new(), Solution::new());
        for n in (1..=40).chain([3, 9, 9, 12, 30]) {
            for trial in 0..6 {
                let r = Mat::from_fn(n, n, |_, _| uniform(&mut state));
                let m = if trial % 2 == 0 {
                    let mut m = &r * r.transpose() * (1.0 / n as f64);
                    for i in 0..n {
                        m[(i, i)] += 0.05;
                    }
                    m
                } else {
                    r
                };
                let q = faer::Col::from_fn(n, |i| {
                    let v = uniform(&mut state);
                    if trial >= 4 && i % 3 == 0 { 0.0 } else { v }
                });
                let lcp = Lcp::new(m, q).expect("valid problem");
                for cover in [Cover::FromOptions, Cover::RowScaled] {
                    let cover2 = match cover {
                        Cover::FromOptions => Cover::FromOptions,
                        _ => Cover::RowScaled,
                    };
                    fast.solve_covering(lcp.view(), cover, &mut a).expect("valid");
                    plain.ws.prepare(n);
                    plain.ws.avx = false;
                    plain.solve_covering(lcp.view(), cover2, &mut b).expect("valid");
                    assert_eq!(a.status, b.status, "n = {n}, trial {trial}");
                    assert_eq!(a.iterations, b.iterations, "n = {n}, trial {trial}");
                    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                    assert_eq!(bits(&a.z), bits(&b.z), "n = {n}, trial {trial}");
                    assert_eq!(bits(&a.w), bits(&b.w), "n = {n}, trial {trial}");
                    assert_eq!(a.residual.relative.to_bits(), b.residual.relative.to_bits());
                }
            }
        }
    }
}
