//! Lemke's complementary pivoting method with lexicographic degeneracy resolution.
#![allow(non_snake_case)]

mod kernels;
mod tableau;

use serde::{Deserialize, Serialize};

use kernels::{Isa, LANES};

use crate::dense::{Lu, TINY_MAX, refine, solve_tiny};
use crate::error::rules;
use crate::solution::{Chunk, check_warm_start, finish_row_major, finish_sparse, residual_of_zero};
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
///
/// The enum is `#[non_exhaustive]`, as the solvers' options are, so that other covering
/// vectors can be added without breaking callers; a `match` outside this crate needs a
/// wildcard arm:
///
/// ```compile_fail,E0004
/// fn name(covering: &moreau_lcp::Covering) -> &'static str {
///     match covering {
///         moreau_lcp::Covering::Ones => "ones",
///         moreau_lcp::Covering::RowScaled => "row scaled",
///         moreau_lcp::Covering::Custom(_) => "custom",
///     }
/// }
/// ```
#[non_exhaustive]
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

/// Options of [`Lemke`]: the default, changed field by field with the `with_*` setters
/// (or by assigning the fields of a default value).
///
/// ```
/// use moreau_lcp::{Lemke, LemkeOptions};
///
/// # fn main() -> Result<(), moreau_lcp::LcpError> {
/// let options = LemkeOptions::default().with_max_pivots(1000).with_tolerance(1e-10);
/// assert_eq!((options.max_pivots, options.tolerance), (1000, 1e-10));
/// let solver = Lemke::new(options)?;
/// # let _ = solver;
/// # Ok(())
/// # }
/// ```
///
/// The struct is `#[non_exhaustive]`, so that fields added later keep their defaults in
/// callers' code; a struct literal does not compile outside this crate:
///
/// ```compile_fail,E0639
/// let options = moreau_lcp::LemkeOptions { max_pivots: 1000, ..Default::default() };
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[non_exhaustive]
pub struct LemkeOptions {
    /// Largest number of pivots before giving up with [`Status::IterationLimit`].
    /// Default 131072 = 2^17, enough for Murty's n = 16 problem (2^16 - 1 pivots);
    /// Murty's problem of size n needs 2^n - 1.
    pub max_pivots: usize,
    /// Acceptance tolerance on [`Residual::relative`] of the final z (dimensionless), in
    /// (0, 1). Default 1e-9, the robust recipe of the step LCP.
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

with_setters!(LemkeOptions {
    with_max_pivots => max_pivots: usize,
    with_tolerance => tolerance: f64,
    with_pivot_tolerance => pivot_tolerance: f64,
    with_tie_tolerance => tie_tolerance: f64,
    with_covering => covering: Covering,
});

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
        rules::relative_tolerance(self.tolerance)?;
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
/// the tied rows it leaves at once. In floating point, round-off in the ratio test can still
/// bring back a basis; the pivots would then go round the same bases up to the limit, so a
/// basis seen again (found by a hash of the basic set, Brent's cycle detection) ends the
/// method with [`Status::NumericalFailure`].
///
/// **Scale.** The tableau's rows are equilibrated by powers of two, and its covering column
/// is brought to their scale by a power of two when it is more than 2^20 away from it (the
/// covering vector c d, the same pivots in exact arithmetic), so that (M, q) scaled by any
/// s > 0 is solved with the pivots of (M, q).
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
/// multiple of four rows, is pivoted over a preallocated buffer: about n (n + 2)
/// multiply-adds per pivot, four rows per operation. The set-up, ratio test, pivot and
/// residual are each written once over four-lane vectors and compiled twice, for AVX2
/// (chosen at run time when the processor has it) and as portable code; both give the same
/// results bit for bit (no FMA, reductions whose result does not depend on the order).
/// Accepting the tableau's own z costs one product with M; the LU re-solve runs only when
/// that z fails the residual test. Warm starts are checked and ignored.
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
    /// The instruction set of the kernels (detected on the first solve).
    isa: Isa,
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
    /// A basis came back: round-off made the pivots cycle.
    Cycle,
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
            End::Cycle => out.status = status_for(out.residual, tol, Status::NumericalFailure),
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

/// The bookkeeping arrays (`basic`, `nonbasic`, `row_of`, `col_of`) hold at least this
/// many entries, a power of two above the 2 n + 1 <= 65 variables of the fixed heights
/// (n <= 32).
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

/// n rounded up to a multiple of [`LANES`].
#[inline]
fn padded_height(n: usize) -> usize {
    n.div_ceil(LANES) * LANES
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

    /// The kernels compiled for AVX2 and in portable code give the same pivots, z, w and
    /// residual, bit for bit, on SPD, non-symmetric and degenerate problems of sizes 1 to
    /// 40 (fixed-size and run-time-size kernels), with both covering vectors.
    #[test]
    fn avx2_and_portable_kernels_agree_bit_for_bit() {
        if !Isa::detect().is_wide() {
            // A pass here would claim an agreement that was never checked.
            assert!(
                std::env::var_os("MOREAU_LCP_ALLOW_NO_SIMD").is_some(),
                "this processor lacks AVX2 (x86-64-v3: AVX, AVX2, FMA, BMI1/2, LZCNT), so \
                 the AVX2 compilation of Lemke's kernels cannot be compared with the portable \
                 one; set MOREAU_LCP_ALLOW_NO_SIMD=1 to skip the comparison on such a machine"
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
                    plain.ws.isa = Isa::Portable;
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
