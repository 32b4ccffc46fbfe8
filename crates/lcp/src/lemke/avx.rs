//! The AVX copies of Lemke's kernels that the compiler does not vectorise well by itself.
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
    let e = _mm256_min_epi32(_mm256_max_epi32(e, _mm256_set1_epi64x(23)), _mm256_set1_epi64x(2023));
    let r =
        _mm256_castsi256_pd(_mm256_slli_epi64::<52>(_mm256_sub_epi64(_mm256_set1_epi64x(2046), e)));
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
        bad = _mm256_add_pd(bad, _mm256_add_pd(_mm256_mul_pd(zi, zero), _mm256_mul_pd(wi, zero)));
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
pub(super) fn pivot_loop<const H: usize>(ws: &mut Workspace, opts: &LemkeOptions) -> (End, usize) {
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
pub(super) fn ratio(a: &[Chunk], c: &[Chunk], sign: f64, pivot_rel: f64, tie_rel: f64) -> Ratio {
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
