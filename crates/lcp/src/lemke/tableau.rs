//! Lemke's method on the condensed tableau: set-up, ratio test with the lexicographic rule,
//! pivots and the checked candidate.
#![allow(non_snake_case)]

use super::*;

impl Workspace {
    pub(super) fn prepare(&mut self, n: usize) {
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
    pub(super) fn run(
        &mut self,
        lcp: LcpRef<'_>,
        opts: &LemkeOptions,
        out: &mut Solution,
    ) -> (End, usize) {
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
    pub(super) fn run_plain(
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
    pub(super) fn run_avx2(
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
    pub(super) fn run_sized<const H: usize, const AVX: bool>(
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
    pub(super) fn chunks<const H: usize>(&self) -> usize {
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
    pub(super) fn init_tableau<const H: usize, const AVX: bool>(&mut self, lcp: LcpRef<'_>) {
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

    #[allow(unsafe_code)]
    #[inline(always)]
    pub(super) fn pivot_loop<const H: usize, const AVX: bool>(
        &mut self,
        opts: &LemkeOptions,
    ) -> (End, usize) {
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

    /// The ratio test for entering column `s`. In the first step (`initial`), every row
    /// takes part with `a_i = d_i`; afterwards the rows with `T_is < 0` take part with
    /// `a_i = -T_is`. The minimum ratio `θ = min q̄_i / a_i` over `a_i > ptol` and the first
    /// row attaining it are found lane by lane; the rows tied with it within the tie
    /// tolerance are counted, and only when there are two or more does the lexicographic
    /// rule ([`Self::select_tied`]) decide.
    #[allow(unsafe_code)]
    #[inline(always)]
    pub(super) fn select_row<const H: usize, const AVX: bool>(
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
    pub(super) fn pivot<const H: usize>(&mut self, r: usize, s: usize) -> usize {
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
    /// returns whether the result passes `tol`; `out` holds it (status `Solved` if so).
    pub(super) fn solve_alpha(&mut self, out: &mut Solution, tol: f64) -> bool {
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
    /// residual (status left to the caller).
    ///
    /// w is accumulated column by column in ascending order, each row summing its terms
    /// `M_ij z_j` in that order. For heights with a fixed kernel every column takes part
    /// (a non-basic z_j = 0 adds zero), which costs less than branching on the basis; w and
    /// the row sums then stay in registers.
    #[allow(unsafe_code)]
    #[inline(always)]
    pub(super) fn tableau_candidate<const H: usize, const AVX: bool>(
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
