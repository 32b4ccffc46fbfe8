//! The bookkeeping of Lemke's method on the condensed tableau: the basis, the pivot loop
//! around the kernels, the lexicographic rule for tied rows, and the checked candidate with
//! its LU fallback. The numerical kernels (set-up, ratio test, pivot, candidate residual)
//! are in `kernels`.
#![allow(non_snake_case)]

use super::kernels::{self, Isa, LANES, Lanes4, Ratio, WithLanes};
use super::*;
use crate::dense::pow2_inverse;

/// The covering column of the tableau is rescaled when its largest entry lies outside
/// [1 / `COVER_SPAN`, `COVER_SPAN`] (2^20): see [`Workspace::balance_covering`].
const COVER_SPAN: f64 = 1_048_576.0;

impl Workspace {
    pub(super) fn prepare(&mut self, n: usize) {
        // Every buffer's size is a function of n alone.
        if self.prepared == Some(n) {
            return;
        }
        if self.prepared.is_none() {
            self.isa = Isa::detect();
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

    /// Set-up, pivoting and the tableau's candidate (into `out`), with the kernels of the
    /// workspace's token and column height. Returns how the pivoting ended and the pivots.
    pub(super) fn run(
        &mut self,
        lcp: LcpRef<'_>,
        opts: &LemkeOptions,
        out: &mut Solution,
    ) -> (End, usize) {
        self.tie_rel = opts.tie_tolerance;
        let isa = self.isa;
        macro_rules! sized {
            ($h:literal) => {
                isa.vectorize(Sized::<$h> { ws: self, lcp, opts, out })
            };
        }
        match self.h {
            4 => sized!(4),
            8 => sized!(8),
            12 => sized!(12),
            16 => sized!(16),
            20 => sized!(20),
            24 => sized!(24),
            28 => sized!(28),
            32 => sized!(32),
            _ => sized!(0),
        }
    }

    /// The body of [`Self::run`] for columns of H rows (H = 0: `self.h`, any height), with
    /// the kernels of token `simd`. Always inlined, so that it and every kernel are
    /// compiled for the token's instruction set inside [`Isa::vectorize`].
    #[inline(always)]
    fn run_sized<S: Lanes4, const H: usize>(
        &mut self,
        simd: S,
        lcp: LcpRef<'_>,
        opts: &LemkeOptions,
        out: &mut Solution,
    ) -> (End, usize) {
        kernels::set_up::<S, H>(
            simd,
            lcp.m(),
            self.nb,
            &mut self.m_cols,
            &mut self.tab,
            &self.d,
            self.row_scaled,
            &self.q,
            &mut self.q_pad,
            &mut self.scratch,
        );
        if !self.row_scaled {
            self.balance_covering();
        }
        self.init_basis::<H>();
        let ended = self.pivot_loop::<S, H>(simd, opts);
        self.tableau_candidate::<S, H>(simd, out, 0.0);
        if matches!(ended.0, End::Complementary) && !(out.residual.relative <= opts.tolerance) {
            // A degenerate basic variable that should be zero but holds round-off (z_j of
            // order 1e-16 ‖z‖∞) makes the rows where it is the only term fail the
            // residual test; the same basis with such values zeroed is tried before the LU
            // re-solve.
            let z_max = out.z.iter().fold(0.0, |a, &v| fmax(a, v));
            let first = out.residual;
            std::mem::swap(&mut out.z, &mut self.z_tab);
            std::mem::swap(&mut out.w, &mut self.w_tab);
            self.tableau_candidate::<S, H>(simd, out, ROUND_OFF_ZERO * z_max);
            if !(out.residual.relative < first.relative) {
                std::mem::swap(&mut out.z, &mut self.z_tab);
                std::mem::swap(&mut out.w, &mut self.w_tab);
                out.residual = first;
            }
        }
        ended
    }

    /// Brings the covering column of the tableau (z_0's column, `r_i d_i` after the rows'
    /// equilibration) to the scale of M's columns, whose row-equilibrated entries are at most
    /// 2 in magnitude, when its largest entry lies outside [2^-20, 2^20]: the column is
    /// multiplied by the power of two that puts that entry in [1, 2). This is the covering
    /// vector c d for a c > 0, which changes z_0's scale and nothing else: the pivots are the
    /// same in exact arithmetic. Without it, d = 1 on an M of order 1e-12 (or 1e12) leaves
    /// z_0's row, once z_0 is basic, 1e12 times smaller (larger) than the others, below (or
    /// setting) the pivot tolerance of every entering column: the method ended on a secondary
    /// ray, or failed, on positive definite problems scaled by 1e-11 or 1e12.
    fn balance_covering(&mut self) {
        let (n, nb) = (self.n, self.nb);
        let column = &mut self.tab[n * nb..(n + 1) * nb].as_flattened_mut()[..n];
        let big = column.iter().fold(0.0, |m, v| fmax(m, v.abs()));
        if !(1.0 / COVER_SPAN..=COVER_SPAN).contains(&big) {
            let c = pow2_inverse(big);
            for v in column.iter_mut() {
                *v *= c;
            }
        }
    }

    /// Chunks per column: H / [`LANES`], or `self.nb` for H = 0.
    #[inline(always)]
    fn chunks<const H: usize>(&self) -> usize {
        if H == 0 { self.nb } else { H / LANES }
    }

    /// The basis {w}: `w_i` basic in row i, `z_j` non-basic in column j, `z_0` in
    /// column n.
    #[inline(always)]
    pub(super) fn init_basis<const H: usize>(&mut self) {
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

    /// The pivots from the basis {w} until z_0 leaves, a ray or the pivot limit: the first
    /// step brings in z_0 (column n) with every row taking part with `a_i = d_i`; each later
    /// step brings in the complement of the variable that left, with the rows of `T_is < 0`
    /// taking part with `a_i = -T_is`. The ratio test's first pass
    /// ([`kernels::ratio`]) names the row unless two or more rows tie, when the
    /// lexicographic rule ([`Self::select_tied`]) decides, or unless no ratio is finite
    /// ([`Self::select_row_exact`]). The pivot's column updates are [`kernels::pivot`]; the
    /// variables then change places ([`Self::exchange`]). For the fixed heights the
    /// bookkeeping arrays hold at least [`IDX`] entries and are indexed modulo that length
    /// (every index is below 2 n + 1 <= 65), which needs no bounds checks.
    #[inline(always)]
    fn pivot_loop<S: Lanes4, const H: usize>(
        &mut self,
        simd: S,
        opts: &LemkeOptions,
    ) -> (End, usize) {
        let n = self.n;
        let nb = self.chunks::<H>();
        let z0 = 2 * n;
        let (len, m) = if H != 0 { (IDX, IDX - 1) } else { (self.basic.len(), usize::MAX) };
        let (pr, tr) = (opts.pivot_tolerance, opts.tie_tolerance);
        let mut s = n;
        let mut pivots = 0usize;
        // Exact arithmetic never revisits a basis (see `Lemke`), but round-off in the ratio
        // test can, and the pivots then go round the same bases up to the limit: 131,072
        // pivots, 20 ms, on an LCP of 30 rows from a stack of five boxes. Paths longer than
        // 2 n pivots are watched for a basis seen again, out of the loop of shorter ones.
        let mut limit = opts.max_pivots.min(2 * n);
        let mut watch = CycleWatch::default();
        loop {
            let initial = pivots == 0;
            let sign = if initial { 1.0 } else { -1.0 };
            let tab = &self.tab[..(n + 2) * nb];
            let (a, c) = (&tab[s * nb..(s + 1) * nb], &tab[(n + 1) * nb..]);
            let r = match kernels::ratio::<S, H>(simd, a, c, sign, pr, tr) {
                Ratio::Row(r) => r,
                Ratio::Tied { ptol, theta, eps } => self.select_tied(s, initial, ptol, theta, eps),
                Ratio::NoFinite => match self.select_row_exact(s, initial, opts) {
                    Some(r) => r,
                    None => return (End::Ray, pivots),
                },
            };
            let leaving = self.basic[..len][r & m];
            // When z_0 leaves, the method ends and only q̄ (the basic values) is read
            // afterwards, so only q̄ is updated.
            let last = leaving == z0;
            let first_col = if last { n + 1 } else { 0 };
            let tab = &mut self.tab[..(n + 2) * nb];
            kernels::pivot::<S, H>(simd, tab, nb, first_col, s, r, last, &mut self.scratch);
            self.exchange::<H>(r, s);
            pivots += 1;
            if last {
                return (End::Complementary, pivots);
            }
            if pivots >= limit {
                if pivots >= opts.max_pivots {
                    return (End::Limit, pivots);
                }
                if watch.seen_again(&self.basic[..n]) {
                    return (End::Cycle, pivots);
                }
                limit = pivots + 1;
            }
            let entering = if leaving < n { leaving + n } else { leaving - n };
            s = self.col_of[..len][entering & m];
        }
    }

    /// Entry `(i, c)` of the tableau (column c, row i).
    #[inline]
    pub(super) fn entry(&self, i: usize, c: usize) -> f64 {
        self.tab[c * self.nb + i / LANES][i % LANES]
    }

    /// Entry `j` of row `i` of `B^{-1}`, read from the condensed tableau: the column of
    /// a non-basic `w_j` holds `-B^{-1} e_j`, and a basic `w_j` in row k has
    /// `B^{-1} e_j = e_k`.
    #[inline]
    pub(super) fn binv(&self, i: usize, j: usize) -> f64 {
        let r = self.row_of[j];
        if r != NONE { if r == i { 1.0 } else { 0.0 } } else { -self.entry(i, self.col_of[j]) }
    }

    /// The ratio test row by row, comparing ratios without dividing: for the rare case of
    /// no finite ratio in [`kernels::ratio`] (a ray, or ratios beyond the range of f64).
    #[inline(never)]
    pub(super) fn select_row_exact(
        &mut self,
        s: usize,
        initial: bool,
        opts: &LemkeOptions,
    ) -> Option<usize> {
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
    pub(super) fn select_tied(
        &mut self,
        s: usize,
        initial: bool,
        ptol: f64,
        theta: f64,
        eps: f64,
    ) -> usize {
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

    /// The bookkeeping of a pivot: the basic variable of row r and the non-basic variable
    /// of column s change places. For the fixed heights (`H > 0`) the arrays hold at least
    /// [`IDX`] entries and every index is below 2 n + 1 <= 65, so they are indexed modulo
    /// `IDX` within their first `IDX` entries, which needs no bounds checks.
    #[inline(always)]
    pub(super) fn exchange<const H: usize>(&mut self, r: usize, s: usize) {
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
    pub(super) fn fill_m_rows(&mut self) {
        let n = self.n;
        let nb = self.nb;
        for (j, col) in self.m_cols[..n * nb].chunks_exact(nb).enumerate() {
            for (i, v) in col.as_flattened()[..n].iter().enumerate() {
                self.m_rows[i * n + j] = *v;
            }
        }
    }

    /// Re-solves the complementary basis directly and accepts it if its residual passes.
    pub(super) fn resolve_basis(&mut self, out: &mut Solution, tol: f64) -> bool {
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
    /// returns whether the result passes `tol`; `out` holds it (status `Solved` if so). A
    /// basis that cannot be factored leaves `out`'s vectors as they were and its residual
    /// infinite, so that no caller takes them for this basis' solution.
    pub(super) fn solve_alpha(&mut self, out: &mut Solution, tol: f64) -> bool {
        let n = self.n;
        let k = self.alpha.len();
        let (m, alpha) = (&self.m_rows, &self.alpha);
        if !self.lu.factor_with(k, |i, j| m[alpha[i] * n + alpha[j]]) {
            out.residual = Residual::INFINITE;
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
    pub(super) fn set_basic_z(&self, out: &mut Solution) {
        out.z.fill(0.0);
        for (t, &i) in self.alpha.iter().enumerate() {
            out.z[i] = positive_part(self.rhs[t]);
        }
    }

    /// z = the basic solution in `rhs` (clamped at 0), w = M z + q, and its residual.
    pub(super) fn scatter(&mut self, out: &mut Solution) {
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
    /// residual (status left to the caller), by [`kernels::candidate`].
    #[inline(always)]
    fn tableau_candidate<S: Lanes4, const H: usize>(
        &mut self,
        simd: S,
        out: &mut Solution,
        zero_below: f64,
    ) {
        let n = self.n;
        let nb = self.chunks::<H>();
        out.residual = kernels::candidate::<S, H>(
            simd,
            nb,
            &self.m_cols,
            &self.q_pad,
            self.tab[(n + 1) * nb..(n + 2) * nb].as_flattened(),
            &self.row_of[n..2 * n],
            zero_below,
            &mut out.z[..n],
            &mut out.w[..n],
            &mut self.scratch,
        );
    }
}

/// [`Workspace::run_sized`] for columns of H rows, as a computation that
/// [`Isa::vectorize`] compiles for its token.
struct Sized<'w, 'l, 'o, 's, const H: usize> {
    ws: &'w mut Workspace,
    lcp: LcpRef<'l>,
    opts: &'o LemkeOptions,
    out: &'s mut Solution,
}

impl<const H: usize> WithLanes for Sized<'_, '_, '_, '_, H> {
    type Output = (End, usize);

    #[inline(always)]
    fn run<S: Lanes4>(self, simd: S) -> (End, usize) {
        self.ws.run_sized::<S, H>(simd, self.lcp, self.opts, self.out)
    }
}

/// Brent's cycle detection over the bases of a long pivoting path: the hash of the basic
/// set (the XOR of a key per variable) is compared with the one saved at the last power of
/// two of the calls, which finds a cycle within twice its length or start.
#[derive(Default)]
struct CycleWatch {
    saved: Option<u64>,
    since: usize,
    span: usize,
}

impl CycleWatch {
    /// Whether the basis whose basic variables are `basic` is the one saved; saves it when
    /// the span is over.
    #[cold]
    #[inline(never)]
    fn seen_again(&mut self, basic: &[usize]) -> bool {
        let hash = basic.iter().fold(0, |h, &v| h ^ variable_key(v));
        if self.saved == Some(hash) {
            return true;
        }
        self.since += 1;
        if self.since >= self.span {
            (self.saved, self.since, self.span) = (Some(hash), 0, 2 * self.span.max(1));
        }
        false
    }
}

/// A pseudo-random 64-bit key of basis variable `v` (SplitMix64's finaliser), for the hash
/// of a basic set in [`CycleWatch`].
#[inline]
fn variable_key(v: usize) -> u64 {
    let mut x = (v as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}
