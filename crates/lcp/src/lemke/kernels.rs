//! The numerical kernels of Lemke's method, each written once and generic over the SIMD
//! instruction set through pulp: the set-up of the tableau, the ratio test, the pivot and
//! the residual of the tableau's candidate.
//!
//! A kernel takes a token as its first argument: a [`Lanes4`], pulp's [`Simd`] with four
//! lanes and the one operation the kernels need beyond it, implemented for the two tokens of
//! [`Isa`] alone. A token of a wide instruction set exists only when pulp detected it on the
//! running processor ([`Isa::detect`]), so a kernel cannot run with instructions the
//! processor lacks. The bookkeeping calls the kernels inside [`Isa::vectorize`], once around
//! a whole solve, so that the pivot loop with every kernel in it is compiled for the token's
//! instruction set as one function. The masked loads and
//! stores of partial vectors are the only `unsafe` code of the crate, here alone.
//!
//! **Layout.** The tableau and the padded copies of M and q are stored column by column in
//! [`Chunk`]s of four rows, each column padded with zero rows to a whole number of chunks.
//! Both tokens used here ([`pulp::x86::V3`]: AVX2, and [`pulp::Scalar256b`]: the same
//! vectors in portable code) hold exactly one chunk per vector, so the kernels run without
//! remainder loops.
//!
//! **Bit for bit.** Every kernel uses only lane-wise additions, multiplications, divisions,
//! comparisons and bit masks (never a fused multiply-add), and reductions by maximum,
//! minimum, a sum of zeros (the finiteness check) or the set of lanes of a mask, whose
//! results do not depend on the order of their terms while the values are finite (a maximum or minimum of +0 and −0 may return
//! either, and every such result only enters a comparison or a difference whose outcome it
//! does not change). Both tokens therefore give the same pivots, z, w and residual bit for
//! bit (the unit test of `lemke` checks it).
//!
//! `H` is the column height when it is one of the fixed heights 4, 8, ..., 32 (the loops
//! then have constant trip counts, which the compiler unrolls, and the kernels' local arrays
//! stay in registers), and 0 for a height known only at run time.
#![allow(unsafe_code)]

use faer::MatRef;
use pulp::{MemMask, Simd, bytemuck};

use crate::Residual;
use crate::solution::{Chunk, residual_from_maxima};

/// Rows per [`Chunk`]: columns are padded to a multiple of this many rows.
pub(super) const LANES: usize = 4;

/// Column heights up to this (n <= 32) have kernels of fixed size.
pub(super) const FIXED_MAX: usize = 32;

/// Chunks per column at [`FIXED_MAX`]: the size of the kernels' local arrays.
const MAX_CHUNKS: usize = FIXED_MAX / LANES;

/// Every bit set, as an f64.
const ALL: f64 = f64::from_bits(u64::MAX);

/// Row masks of a pivot for the fixed heights, as f64 bit patterns: `KEEP[FIXED_MAX - 1 - r
/// + i]` has no bit set for i = r and every bit otherwise, so the window from
/// `FIXED_MAX - 1 - r` holds the masks of rows 0, 1, ... of a pivot in row r.
static KEEP: [f64; 2 * FIXED_MAX] = {
    let mut k = [ALL; 2 * FIXED_MAX];
    k[FIXED_MAX - 1] = 0.0;
    k
};

/// The unit vectors of a pivot for the fixed heights: `UNIT[FIXED_MAX - 1 - r + i]` is 1
/// for i = r and 0 otherwise, so the window from `FIXED_MAX - 1 - r` is e_r.
static UNIT: [f64; 2 * FIXED_MAX] = {
    let mut k = [0.0; 2 * FIXED_MAX];
    k[FIXED_MAX - 1] = 1.0;
    k
};

/// The row numbers of a chunk's lanes, as f64.
static IOTA: Chunk = [0.0, 1.0, 2.0, 3.0];

/// The instruction set of the kernels, detected once per solver (portable until then).
#[derive(Clone, Copy, Debug, Default)]
pub(super) enum Isa {
    /// AVX2 with 256-bit vectors (pulp's x86-64-v3 token, which the processor was found to
    /// support).
    #[cfg(target_arch = "x86_64")]
    V3(pulp::x86::V3),
    /// The same four-lane vectors in portable code, for any processor.
    #[default]
    Portable,
}

impl Isa {
    /// The widest of the two that this processor runs.
    pub(super) fn detect() -> Isa {
        #[cfg(target_arch = "x86_64")]
        if let Some(v3) = pulp::x86::V3::try_new() {
            return Isa::V3(v3);
        }
        Isa::Portable
    }

    /// Whether this is the AVX2 token.
    #[cfg(test)]
    pub(super) fn is_wide(self) -> bool {
        !matches!(self, Isa::Portable)
    }

    /// Runs `op` with this token, compiled for its instruction set: the whole of `op`, with
    /// every `#[inline(always)]` function it calls, becomes one function with the token's
    /// target features.
    #[inline(always)]
    pub(super) fn vectorize<Op: WithLanes>(self, op: Op) -> Op::Output {
        /// `op` with its token, as pulp's target-feature entry calls it (always inlined
        /// into that entry, which a closure would not be).
        struct Run<Op, S>(Op, S);
        impl<Op: WithLanes, S: Lanes4> pulp::NullaryFnOnce for Run<Op, S> {
            type Output = Op::Output;
            #[inline(always)]
            fn call(self) -> Op::Output {
                self.0.run(self.1)
            }
        }
        match self {
            #[cfg(target_arch = "x86_64")]
            Isa::V3(v3) => v3.vectorize(Run(op, v3)),
            Isa::Portable => op.run(pulp::Scalar256b),
        }
    }
}

/// A computation that runs with a four-lane token, for [`Isa::vectorize`].
pub(super) trait WithLanes {
    /// What the computation returns.
    type Output;
    /// Runs the computation with `simd`; it must be `#[inline(always)]` to be compiled for
    /// the token's instruction set.
    fn run<S: Lanes4>(self, simd: S) -> Self::Output;
}

/// The tokens of the kernels: pulp's [`Simd`] with four f64 lanes per vector, and the one
/// operation the kernels need that [`Simd`] lacks. Implemented for the two tokens of
/// [`Isa`] alone.
pub(super) trait Lanes4: Simd {
    /// Bit l set when lane l of `m` is set.
    fn bits(self, m: Self::m64s) -> u32;
}

#[cfg(target_arch = "x86_64")]
impl Lanes4 for pulp::x86::V3 {
    #[inline(always)]
    fn bits(self, m: Self::m64s) -> u32 {
        // The sign bit of each lane: the lanes of a mask are all ones or all zeros.
        let m: std::arch::x86_64::__m256d = bytemuck::cast(self.transmute_u64s_m64s(m));
        self.avx._mm256_movemask_pd(m) as u32
    }
}

impl Lanes4 for pulp::Scalar256b {
    #[inline(always)]
    fn bits(self, m: Self::m64s) -> u32 {
        let m: [u64; LANES] = bytemuck::cast(self.transmute_u64s_m64s(m));
        let mut bits = 0;
        for (l, v) in m.iter().enumerate() {
            bits |= u32::from(*v != 0) << l;
        }
        bits
    }
}

/// The vectors of a slice of chunks (one chunk per vector).
#[inline(always)]
fn vecs<S: Simd>(x: &[Chunk]) -> &[S::f64s] {
    const { assert!(S::F64_LANES == LANES) };
    bytemuck::cast_slice(x)
}

/// [`vecs`] for a mutable slice.
#[inline(always)]
fn vecs_mut<S: Simd>(x: &mut [Chunk]) -> &mut [S::f64s] {
    const { assert!(S::F64_LANES == LANES) };
    bytemuck::cast_slice_mut(x)
}

/// The vectors of a slice of f64 whose length is a multiple of [`LANES`].
#[inline(always)]
fn vecs_f64<S: Simd>(x: &[f64]) -> &[S::f64s] {
    const { assert!(S::F64_LANES == LANES) };
    bytemuck::cast_slice(x)
}

/// `|x|` per lane by clearing the sign bits.
#[inline(always)]
fn abs<S: Simd>(simd: S, x: S::f64s) -> S::f64s {
    simd.and_f64s(x, simd.splat_f64s(f64::from_bits(u64::MAX >> 1)))
}

/// The lane mask of chunk b of a column of n rows: every lane of a whole chunk, the first
/// n mod 4 of a partial one, none past it (lane l holds row 4 b + l, below n when
/// `l < n − 4 b`, compared in f64, where both sides are exact).
#[inline(always)]
fn rows_mask<S: Simd>(simd: S, n: usize, b: usize) -> S::m64s {
    let rest = n as f64 - (b * LANES) as f64;
    simd.less_than_f64s(vecs_f64::<S>(&IOTA)[0], simd.splat_f64s(rest))
}

/// The masks of [`rows_mask`] for the chunks of a fixed height H (none for H = 0), taken
/// once before a kernel's loops.
#[inline(always)]
fn rows_masks<S: Simd, const H: usize>(simd: S, n: usize) -> [S::m64s; MAX_CHUNKS] {
    // 0 < 0 is false in every lane.
    let none = simd.less_than_f64s(simd.splat_f64s(0.0), simd.splat_f64s(0.0));
    let mut masks = [none; MAX_CHUNKS];
    for b in 0..H / LANES {
        masks[b] = rows_mask(simd, n, b);
    }
    masks
}

/// Chunk b of `src`, zero past its end, by a masked load.
///
/// # Safety
/// `mask` must be `rows_mask(simd, src.len(), b)` (or select fewer lanes).
#[inline(always)]
unsafe fn load_rows<S: Simd>(simd: S, src: &[f64], b: usize, mask: S::m64s) -> S::f64s {
    let ptr = src.as_ptr().wrapping_add(b * LANES);
    // SAFETY: the mask selects the lanes 4 b + l < src.len() only (the caller's contract),
    // whose addresses are inside `src`, and a masked load reads no other lane.
    unsafe { simd.mask_load_ptr_f64s(MemMask::new(mask), ptr) }
}

/// Stores the lanes of `v` that hold rows below `dst.len()` into chunk b of `dst`, by a
/// masked store.
///
/// # Safety
/// `mask` must be `rows_mask(simd, dst.len(), b)` (or select fewer lanes).
#[inline(always)]
unsafe fn store_rows<S: Simd>(simd: S, dst: &mut [f64], b: usize, mask: S::m64s, v: S::f64s) {
    let ptr = dst.as_mut_ptr().wrapping_add(b * LANES);
    // SAFETY: the mask selects the lanes 4 b + l < dst.len() only (the caller's contract),
    // whose addresses are inside `dst`, and a masked store writes no other lane.
    unsafe { simd.mask_store_ptr_f64s(MemMask::new(mask), ptr, v) }
}

/// Chunks per column: H / [`LANES`], or `nb` for H = 0.
#[inline(always)]
fn chunks<const H: usize>(nb: usize) -> usize {
    if H == 0 { nb } else { H / LANES }
}

/// `x > 0 ? pow2_inverse(x) : 1` per lane (see `dense::pow2_inverse`): x's exponent bits
/// alone are 2^e (0 for a subnormal x), clamped to [2^-1000, 2^1000] as `pow2_inverse`
/// clamps e, and the inverse of a power of two is exact.
#[inline(always)]
fn row_scale<S: Simd>(simd: S, x: S::f64s) -> S::f64s {
    /// 2^-1000 and 2^1000, the clamps of `pow2_inverse`.
    const LO: f64 = f64::from_bits((1023 - 1000) << 52);
    const HI: f64 = f64::from_bits((1023 + 1000) << 52);
    let exponent = simd.splat_f64s(f64::from_bits(0x7ff << 52));
    let p = simd.and_f64s(x, exponent);
    let p = simd.min_f64s(simd.max_f64s(p, simd.splat_f64s(LO)), simd.splat_f64s(HI));
    let one = simd.splat_f64s(1.0);
    let r = simd.div_f64s(one, p);
    simd.select_f64s(simd.greater_than_f64s(x, simd.splat_f64s(0.0)), r, one)
}

/// The set-up of the tableau for the basis {w}, columns of `nb` chunks (H / 4 for the fixed
/// heights): column j of M is copied into the padded unscaled copy `m_cols` (which the
/// residual reads) while the row maxima `max_j |M_ij|` are taken; each row i then gets the
/// scale r_i, the power of two `pow2_inverse(max_j |M_ij|)` (1 for a zero row and the
/// padding), and the tableau's columns are `r_i M_ij`, the covering column (`r_i d_i`, or
/// ones in the rows for the row-scaled covering) and `r_i q_i`; q is copied to `q_pad`.
/// `scratch` holds `nb` chunks for the run-time heights.
#[inline(always)]
pub(super) fn set_up<S: Lanes4, const H: usize>(
    simd: S,
    m: MatRef<'_, f64>,
    nb: usize,
    m_cols: &mut [Chunk],
    tab: &mut [Chunk],
    d: &[f64],
    row_scaled: bool,
    q: &[f64],
    q_pad: &mut [Chunk],
    scratch: &mut [Chunk],
) {
    let n = m.nrows();
    let nb = chunks::<H>(nb);
    let zero = simd.splat_f64s(0.0);
    let mut local = [[0.0; LANES]; MAX_CHUNKS];
    let big = vecs_mut::<S>(if H == 0 { &mut scratch[..nb] } else { &mut local[..nb] });
    big.fill(zero);
    let m_cols = &mut m_cols[..n * nb];
    let masks = rows_masks::<S, H>(simd, n);
    let mask = |b: usize| if H == 0 { rows_mask(simd, n, b) } else { masks[b] };
    if let Some(mc) = m.try_as_col_major() {
        for (j, dst) in m_cols.chunks_exact_mut(nb).enumerate() {
            let src = &mc.col(j).as_slice()[..n];
            let dst = vecs_mut::<S>(dst);
            for b in 0..nb {
                // SAFETY: `mask(b)` is `rows_mask(n, b)` and `src` has n entries.
                let x = unsafe { load_rows(simd, src, b, mask(b)) };
                dst[b] = x;
                big[b] = simd.max_f64s(abs(simd, x), big[b]);
            }
        }
    } else {
        for (j, dst) in m_cols.chunks_exact_mut(nb).enumerate() {
            let col = m.col(j);
            let flat = dst.as_flattened_mut();
            flat.fill(0.0);
            for i in 0..n {
                flat[i] = col[i];
            }
            for (x, big) in vecs::<S>(dst).iter().zip(big.iter_mut()) {
                *big = simd.max_f64s(abs(simd, *x), *big);
            }
        }
    }
    // The scales, in place of the maxima.
    for v in big.iter_mut() {
        *v = row_scale(simd, *v);
    }
    let r: &[S::f64s] = big;
    let tab = &mut tab[..(n + 2) * nb];
    let (t_m, t_rest) = tab.split_at_mut(n * nb);
    for (dst, src) in t_m.chunks_exact_mut(nb).zip(m_cols.chunks_exact(nb)) {
        let (dst, src) = (vecs_mut::<S>(dst), vecs::<S>(src));
        for b in 0..nb {
            dst[b] = simd.mul_f64s(src[b], r[b]);
        }
    }
    let (t_d, t_q) = t_rest.split_at_mut(nb);
    let (t_d, t_q, q_pad) = (vecs_mut::<S>(t_d), vecs_mut::<S>(t_q), vecs_mut::<S>(q_pad));
    let (d, q) = (&d[..n], &q[..n]);
    let one = simd.splat_f64s(1.0);
    for b in 0..nb {
        // SAFETY: `mask(b)` is `rows_mask(n, b)`, and d and q have n entries.
        let (dv, qv) = unsafe { (load_rows(simd, d, b, mask(b)), load_rows(simd, q, b, mask(b))) };
        // With the row-scaled covering: ones in the rows, zero in the padding.
        t_d[b] =
            if row_scaled { simd.select_f64s(mask(b), one, zero) } else { simd.mul_f64s(dv, r[b]) };
        q_pad[b] = qv;
        t_q[b] = simd.mul_f64s(qv, r[b]);
    }
}

/// How the ratio test's first pass ended.
pub(super) enum Ratio {
    /// One row attains the minimum ratio and no other ties with it.
    Row(usize),
    /// Two or more rows tie within the tolerance: the lexicographic rule decides.
    Tied {
        /// The pivot tolerance `pivot_rel · max |a_i|`.
        ptol: f64,
        /// The minimum ratio θ.
        theta: f64,
        /// The tie tolerance on `q̄_i − θ a_i`.
        eps: f64,
    },
    /// No finite ratio (no blocking row, or ratios beyond the range of f64).
    NoFinite,
}

/// The ratio test's first pass on the entering column `a` (times `sign`) and q̄ `c`
/// (`nb` chunks each, H / 4 for the fixed heights; padding rows zero):
/// `ptol = pivot_rel · max |a_i|`, θ = the smallest `c_i / a_i` over `a_i > ptol`, the
/// first row attaining it, and the count of rows with `a_i > ptol` and
/// `c_i − θ a_i <= eps`, `eps = tie_rel · max(max |c_i|, MIN_POSITIVE)`.
///
/// The first sweep takes the maxima and the minimum ratio over the rows with `a_i > 0`
/// together, so that the divisions do not wait for the pivot tolerance; those are the
/// rows with `a_i > ptol` unless some row has `0 < a_i <= ptol` (the smallest positive a_i
/// is taken too), and only then is the minimum taken again over `a_i > ptol`. The rows
/// attaining θ and the tied rows come out as bit masks, 32 rows at a time.
#[inline(always)]
pub(super) fn ratio<S: Lanes4, const H: usize>(
    simd: S,
    a: &[Chunk],
    c: &[Chunk],
    sign: f64,
    pivot_rel: f64,
    tie_rel: f64,
) -> Ratio {
    let nb = chunks::<H>(a.len());
    let (a, c) = (&vecs::<S>(a)[..nb], &vecs::<S>(c)[..nb]);
    let zero = simd.splat_f64s(0.0);
    let (vsign, inf) = (simd.splat_f64s(sign), simd.splat_f64s(f64::INFINITY));
    let (mut amax, mut cmax, mut amin, mut rmin) = (zero, zero, inf, inf);
    for (&x, &y) in a.iter().zip(c) {
        amax = simd.max_f64s(abs(simd, x), amax);
        cmax = simd.max_f64s(abs(simd, y), cmax);
        let ai = simd.mul_f64s(vsign, x);
        let positive = simd.greater_than_f64s(ai, zero);
        amin = simd.min_f64s(simd.select_f64s(positive, ai, inf), amin);
        rmin = simd.min_f64s(simd.select_f64s(positive, simd.div_f64s(y, ai), inf), rmin);
    }
    let ptol = pivot_rel * simd.reduce_max_f64s(amax);
    let vptol = simd.splat_f64s(ptol);
    if simd.reduce_min_f64s(amin) <= ptol {
        rmin = inf;
        for (&x, &y) in a.iter().zip(c) {
            let ai = simd.mul_f64s(vsign, x);
            let valid = simd.greater_than_f64s(ai, vptol);
            rmin = simd.min_f64s(simd.select_f64s(valid, simd.div_f64s(y, ai), inf), rmin);
        }
    }
    let theta = simd.reduce_min_f64s(rmin);
    if !(theta < f64::INFINITY) {
        return Ratio::NoFinite;
    }
    let eps = tie_rel * fmax(simd.reduce_max_f64s(cmax), f64::MIN_POSITIVE);
    let (vtheta, veps) = (simd.splat_f64s(theta), simd.splat_f64s(eps));
    // The rows attaining θ and the tied rows as bit masks, 32 rows (8 chunks) at a time.
    let (mut first, mut count) = (usize::MAX, 0u32);
    for (g, (a, c)) in a.chunks(GROUP).zip(c.chunks(GROUP)).enumerate() {
        let (mut at, mut tied) = (0u32, 0u32);
        for (b, (&x, &y)) in a.iter().zip(c).enumerate() {
            let ai = simd.mul_f64s(vsign, x);
            let valid = simd.greater_than_f64s(ai, vptol);
            let hit = simd.and_m64s(valid, simd.equal_f64s(simd.div_f64s(y, ai), vtheta));
            let gap = simd.sub_f64s(y, simd.mul_f64s(vtheta, ai));
            let tie = simd.and_m64s(valid, simd.less_than_or_equal_f64s(gap, veps));
            at |= simd.bits(hit) << (LANES * b);
            tied |= simd.bits(tie) << (LANES * b);
        }
        if first == usize::MAX && at != 0 {
            first = g * GROUP * LANES + at.trailing_zeros() as usize;
        }
        count += tied.count_ones();
    }
    if count <= 1 {
        // θ is a minimum over the valid rows, so one of them attains it.
        Ratio::Row(first)
    } else {
        Ratio::Tied { ptol, theta, eps }
    }
}

/// Chunks per group of the ratio test's bit masks (32 rows, the bits of a u32).
const GROUP: usize = 8;

/// The pivot on row r of column s of the tableau `tab` (columns of `nb` chunks, H / 4 for
/// the fixed heights): with `inv = 1 / T_rs` every column x from `first_col` on becomes
/// `(x with x_r cleared) + ρ v`, `ρ = −(x_r inv)`, v = column s with 1 in row r, and column s
/// then becomes `v inv` (unless `last`: z_0 leaves, only q̄ is read afterwards, so
/// `first_col` is q̄'s column and column s is left as it is). These are the operations, and
/// so the roundings, of the row update `row_i += T_is · row_r / (−T_rs)`.
///
/// Row r is cleared by bit masks, not by a compare per lane, which the compiler turns into
/// branches on r, nor by a scalar store into a chunk that the vector loads would wait for;
/// the fixed heights take the masks and e_r from static windows, the run-time heights
/// build them in `scratch` (2 nb chunks), where they also skip the columns with a zero in
/// row r (those do not change).
#[inline(always)]
pub(super) fn pivot<S: Lanes4, const H: usize>(
    simd: S,
    tab: &mut [Chunk],
    nb: usize,
    first_col: usize,
    s: usize,
    r: usize,
    last: bool,
    scratch: &mut [Chunk],
) {
    let nb = chunks::<H>(nb);
    let r = if H == 0 { r } else { r & (FIXED_MAX - 1) };
    let (rb, rl) = (r / LANES, r % LANES);
    let inv = 1.0 / tab[s * nb + rb][rl];
    let mut local_keep = [simd.splat_f64s(0.0); MAX_CHUNKS];
    let mut local_v = [simd.splat_f64s(0.0); MAX_CHUNKS];
    let (keep, v): (&[S::f64s], &[S::f64s]) = if H == 0 {
        let (keep, v) = scratch[..2 * nb].split_at_mut(nb);
        keep.fill([ALL; LANES]);
        keep[rb][rl] = 0.0;
        v.copy_from_slice(&tab[s * nb..(s + 1) * nb]);
        v[rb][rl] = 1.0;
        (vecs::<S>(keep), vecs::<S>(v))
    } else {
        // (u with row r cleared) | e_r.
        let keep = vecs_f64::<S>(&KEEP[FIXED_MAX - 1 - r..][..H]);
        let unit = vecs_f64::<S>(&UNIT[FIXED_MAX - 1 - r..][..H]);
        let u = vecs::<S>(&tab[s * nb..(s + 1) * nb]);
        for b in 0..nb {
            local_keep[b] = keep[b];
            local_v[b] = simd.or_f64s(simd.and_f64s(u[b], keep[b]), unit[b]);
        }
        (&local_keep[..nb], &local_v[..nb])
    };
    for col in tab[first_col * nb..].chunks_exact_mut(nb) {
        let x_r = col[rb][rl];
        if H == 0 && x_r == 0.0 {
            continue;
        }
        let rho = simd.splat_f64s(-(x_r * inv));
        let x = vecs_mut::<S>(col);
        for b in 0..nb {
            x[b] = simd.add_f64s(simd.and_f64s(x[b], keep[b]), simd.mul_f64s(rho, v[b]));
        }
    }
    if !last {
        let vinv = simd.splat_f64s(inv);
        let col = vecs_mut::<S>(&mut tab[s * nb..(s + 1) * nb]);
        for b in 0..nb {
            col[b] = simd.mul_f64s(v[b], vinv);
        }
    }
}

/// The tableau's candidate: z from the basic values (`row_of_z[j]`: the row of z_j in the
/// tableau, or n and above when z_j is not basic; values at or below `zero_below` taken as
/// zero), `w = M z + q` column by column in ascending order with the row sums
/// `Σ_j |M_ij z_j|`, and the residual as the crate's residual defines it, lane by lane.
/// Writes z and w (n entries each) and returns the residual. For the fixed heights every
/// column takes part (a non-basic z_j = 0 adds zero), which costs less than branching on
/// the basis, and w and the row sums stay in registers; for run-time heights the non-basic
/// columns are skipped and `scratch` holds 3 nb chunks.
#[inline(always)]
pub(super) fn candidate<S: Lanes4, const H: usize>(
    simd: S,
    nb: usize,
    m_cols: &[Chunk],
    q_pad: &[Chunk],
    qbar: &[f64],
    row_of_z: &[usize],
    zero_below: f64,
    z_out: &mut [f64],
    w_out: &mut [f64],
    scratch: &mut [Chunk],
) -> Residual {
    let n = z_out.len();
    let nb = chunks::<H>(nb);
    let zero = simd.splat_f64s(0.0);
    let q = &vecs::<S>(q_pad)[..nb];
    let mut lz = [[0.0; LANES]; MAX_CHUNKS];
    let (mut lw, mut la) = ([zero; MAX_CHUNKS], [zero; MAX_CHUNKS]);
    let (z, w, sums): (&mut [Chunk], &mut [S::f64s], &mut [S::f64s]) = if H == 0 {
        let (z, rest) = scratch[..3 * nb].split_at_mut(nb);
        let (w, sums) = rest.split_at_mut(nb);
        z.fill([0.0; LANES]);
        (z, vecs_mut::<S>(w), vecs_mut::<S>(sums))
    } else {
        (&mut lz[..nb], &mut lw[..nb], &mut la[..nb])
    };
    for b in 0..nb {
        w[b] = q[b];
        sums[b] = zero;
    }
    let (qbar, row_of_z) = (&qbar[..n], &row_of_z[..n]);
    for (j, col) in m_cols[..n * nb].chunks_exact(nb).enumerate() {
        let r = row_of_z[j];
        if H == 0 && r >= n {
            continue;
        }
        let v = qbar[if r < n { r } else { 0 }];
        let zj = if r < n && v > zero_below { v } else { 0.0 };
        z.as_flattened_mut()[if H == 0 { j } else { j % FIXED_MAX }] = zj;
        let (zv, col) = (simd.splat_f64s(zj), vecs::<S>(col));
        for b in 0..nb {
            let t = simd.mul_f64s(col[b], zv);
            w[b] = simd.add_f64s(w[b], t);
            sums[b] = simd.add_f64s(sums[b], abs(simd, t));
        }
    }
    let z = &vecs::<S>(z)[..nb];
    let w_out = &mut w_out[..n];
    let masks = rows_masks::<S, H>(simd, n);
    for b in 0..nb {
        let mask = if H == 0 { rows_mask(simd, n, b) } else { masks[b] };
        // SAFETY: `mask` is `rows_mask(n, b)`, and z_out and w_out have n entries.
        unsafe {
            store_rows(simd, z_out, b, mask, z[b]);
            store_rows(simd, w_out, b, mask, w[b]);
        }
    }
    residual_lanes(simd, q, z, w, sums)
}

/// The residual of (z, w) with `w = M z + q` as computed (so `equation` is zero), from
/// chunks of rows (padding rows zero in every argument, which changes no maximum); `sums`
/// holds the row sums `Σ_j |M_ij z_j|`. Each row's terms are those of the crate's residual,
/// taken lane by lane.
#[inline(always)]
fn residual_lanes<S: Simd>(
    simd: S,
    q: &[S::f64s],
    z: &[S::f64s],
    w: &[S::f64s],
    sums: &[S::f64s],
) -> Residual {
    let nb = q.len();
    let (z, w, sums) = (&z[..nb], &w[..nb], &sums[..nb]);
    let zero = simd.splat_f64s(0.0);
    let mut zm = zero;
    for &x in z {
        zm = simd.max_f64s(abs(simd, x), zm);
    }
    let z_max = simd.reduce_max_f64s(zm);
    let (zmv, inf) = (simd.splat_f64s(z_max), simd.splat_f64s(f64::INFINITY));
    // `x ≤ 0 → 0`, `s > 0 → x / s`, otherwise `+∞`, per lane.
    let ratio = |x, s| {
        let q = simd.select_f64s(simd.greater_than_f64s(s, zero), simd.div_f64s(x, s), inf);
        simd.select_f64s(simd.less_than_or_equal_f64s(x, zero), zero, q)
    };
    let (mut q_max, mut natural, mut compl) = (zero, zero, zero);
    let (mut z_violation, mut w_violation, mut relative, mut bad) = (zero, zero, zero, zero);
    for b in 0..nb {
        let (qi, zi, wi, ai) = (q[b], z[b], w[b], sums[b]);
        // Zero while z_i and w_i are finite, NaN otherwise.
        bad = simd.add_f64s(bad, simd.add_f64s(simd.mul_f64s(zi, zero), simd.mul_f64s(wi, zero)));
        let qa = abs(simd, qi);
        q_max = simd.max_f64s(qa, q_max);
        let lesser = simd.select_f64s(simd.less_than_f64s(zi, wi), zi, wi);
        natural = simd.max_f64s(abs(simd, lesser), natural);
        compl = simd.max_f64s(abs(simd, simd.mul_f64s(zi, wi)), compl);
        z_violation = simd.max_f64s(simd.sub_f64s(zero, zi), z_violation);
        w_violation = simd.max_f64s(simd.sub_f64s(zero, wi), w_violation);
        let s = simd.max_f64s(ai, qa);
        let w_rel = ratio(simd.sub_f64s(zero, wi), s);
        let wp = ratio(wi, s);
        // z_i > 0 implies z_max >= z_i > 0.
        let zr = simd.div_f64s(zi, zmv);
        let both =
            simd.and_m64s(simd.greater_than_f64s(zi, zero), simd.greater_than_f64s(wi, zero));
        let least = simd.select_f64s(simd.less_than_f64s(zr, wp), zr, wp);
        let c = simd.select_f64s(both, least, zero);
        relative = simd.max_f64s(simd.max_f64s(c, w_rel), relative);
    }
    residual_from_maxima(
        simd.reduce_max_f64s(q_max),
        z_max,
        simd.reduce_max_f64s(natural),
        simd.reduce_max_f64s(compl),
        simd.reduce_max_f64s(z_violation),
        simd.reduce_max_f64s(w_violation),
        simd.reduce_max_f64s(relative),
        simd.reduce_sum_f64s(bad) == 0.0,
    )
}

/// `max(a, b)` as one compare, a NaN in `b` ignored.
#[inline(always)]
fn fmax(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dense::pow2_inverse;

    /// The lane-wise row scale is `dense::pow2_inverse` bit for bit, clamps included, and 1
    /// for zero.
    #[test]
    fn row_scale_is_pow2_inverse() {
        let simd = pulp::Scalar256b;
        let mut x = 1e-310;
        while x < 1e300 {
            let v = pulp::f64x4(x, 1.5 * x, 0.75 * x, 2.0 * x);
            let r = row_scale(simd, v);
            for (got, v) in [(r.0, v.0), (r.1, v.1), (r.2, v.2), (r.3, v.3)] {
                assert_eq!(got.to_bits(), pow2_inverse(v).to_bits(), "{v:e}");
            }
            x *= 7.3;
        }
        let r = row_scale(simd, pulp::f64x4(0.0, 0.0, 0.0, 0.0));
        assert_eq!((r.0, r.1, r.2, r.3), (1.0, 1.0, 1.0, 1.0));
    }
}
