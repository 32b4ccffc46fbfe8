//! The planar frictional-contact problem: W by 2x2 blocks, q, μ, and bilateral rows.

use faer::MatRef;

use super::chunks;
use crate::{LcpError, MAX_ENTRY};

/// Relative tolerance of the symmetry and semidefiniteness test of the diagonal blocks.
///
/// A diagonal block `[a b; c d]` with scale `s = max(|a|, |b|, |c|, |d|)` is accepted when
/// `|b - c| <= τ s`, `a >= -τ s`, `d >= -τ s` and `a d - ((b + c) / 2)² >= -τ s²`, with
/// τ = 1e-5. Siconos' granular-flow problems print W with six significant digits, so their
/// blocks are symmetric only to a few units in 1e-6 of their scale; τ accepts them and
/// still rejects any block that is unsymmetric or indefinite by more than rounding to six
/// digits explains.
pub const PSD_TOLERANCE: f64 = 1e-5;

/// The parts of a planar frictional-contact problem, borrowed from the caller's buffers,
/// for [`Fc2dRef::from_parts`].
///
/// The unknowns are grouped: groups `0..n_contacts` are the contacts (two rows each, the
/// normal row then the tangential row, the order of Siconos' FC2D files), the groups after
/// them are bilateral (equality) constraints of one or two rows each. Group `g` owns the
/// rows `group_start[g]..group_start[g + 1]` of W, q, r and u.
///
/// W is stored by blocks in block compressed sparse row form: the blocks of group row `g`
/// are `blocks[row_ptr[g]..row_ptr[g + 1]]`, in columns `col[...]` (strictly increasing,
/// the diagonal block always present). A block is `[W_00, W_01, W_10, W_11]` (row-major)
/// between the rows of its row group and the columns of its column group; the entries a
/// one-row group does not have are stored as zeros.
#[derive(Clone, Copy, Debug)]
pub struct Fc2dParts<'a> {
    /// Number of contacts n_c.
    pub n_contacts: usize,
    /// First row of each group and, last, the number of rows (`2 n_c + n_b`). Contacts
    /// start at `2 i`; a bilateral group has one or two rows.
    pub group_start: &'a [usize],
    /// Block row pointers, one per group plus one.
    pub row_ptr: &'a [usize],
    /// Block column (group) of each stored block.
    pub col: &'a [u32],
    /// The stored blocks, row-major; entries finite and at most
    /// [`MAX_ENTRY`](crate::MAX_ENTRY) in magnitude.
    pub blocks: &'a [[f64; 4]],
    /// q, one entry per row; finite and at most [`MAX_ENTRY`](crate::MAX_ENTRY) in
    /// magnitude.
    pub q: &'a [f64],
    /// μ, one per contact, in `[0, MAX_ENTRY]`.
    pub mu: &'a [f64],
}

/// A validated planar frictional-contact problem (FC2D), borrowed: the form the solvers
/// take.
///
/// Find r and u = W r + q such that each contact i satisfies Signorini's law
/// `0 <= r_N,i ⊥ u_N,i >= 0` and Coulomb's law `|r_T,i| <= μ_i r_N,i`, with
/// `r_T,i = -μ_i r_N,i sign(u_T,i)` when `u_T,i != 0`, and each bilateral row b has
/// `u_b = 0` with a free multiplier r_b. See [`Fc2dParts`] for the layout.
#[derive(Clone, Copy, Debug)]
pub struct Fc2dRef<'a> {
    parts: Fc2dParts<'a>,
}

/// A validated planar frictional-contact problem (FC2D) that owns its data; see
/// [`Fc2dRef`] for the problem and [`Fc2dParts`] for the layout. The default is the problem
/// without contacts or bilateral rows.
#[derive(Clone, Debug, PartialEq)]
pub struct Fc2d {
    n_contacts: usize,
    group_start: Vec<usize>,
    row_ptr: Vec<usize>,
    col: Vec<u32>,
    blocks: Vec<[f64; 4]>,
    q: Vec<f64>,
    mu: Vec<f64>,
}

impl Default for Fc2d {
    /// The problem without contacts or bilateral rows (one group start and one row pointer,
    /// both 0), which every solver solves with r empty.
    fn default() -> Self {
        Fc2d {
            n_contacts: 0,
            group_start: vec![0],
            row_ptr: vec![0],
            col: Vec::new(),
            blocks: Vec::new(),
            q: Vec::new(),
            mu: Vec::new(),
        }
    }
}

fn structure(message: String) -> LcpError {
    LcpError::Structure(message)
}

/// Checks the symmetry and semidefiniteness of a diagonal block (see [`PSD_TOLERANCE`]).
fn check_diagonal(
    b: &[f64; 4],
    size: usize,
    what: &'static str,
    index: usize,
) -> Result<(), LcpError> {
    let [a, w01, w10, d] = *b;
    let s = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let tol = PSD_TOLERANCE * s;
    let fail = |reason: String| Err(LcpError::NotPositiveSemidefinite { what, index, reason });
    if a < -tol {
        return fail(format!("W_00 = {a:e} < 0"));
    }
    if size == 1 {
        return Ok(());
    }
    if (w01 - w10).abs() > tol {
        return fail(format!(
            "W_01 = {w01:e} and W_10 = {w10:e} differ by more than {PSD_TOLERANCE:e} of {s:e}"
        ));
    }
    if d < -tol {
        return fail(format!("W_11 = {d:e} < 0"));
    }
    let off = 0.5 * (w01 + w10);
    let det = a * d - off * off;
    if det < -PSD_TOLERANCE * s * s {
        return fail(format!("determinant {det:e} < 0"));
    }
    Ok(())
}

impl<'a> Fc2dRef<'a> {
    /// Validates the parts and wraps them, without allocating.
    ///
    /// # Errors
    /// [`LcpError::Structure`] for inconsistent group starts, row pointers or columns, a
    /// missing diagonal block or a nonzero entry outside a one-row group;
    /// [`LcpError::DimensionMismatch`] for the lengths of q or μ; [`LcpError::NonFinite`];
    /// [`LcpError::OutOfRange`] naming an entry of W, q or μ above
    /// [`MAX_ENTRY`](crate::MAX_ENTRY) in magnitude (the range the LCP solvers take, so
    /// that products of two entries stay finite); [`LcpError::NegativeFriction`];
    /// [`LcpError::NotPositiveSemidefinite`] for a diagonal block (see [`PSD_TOLERANCE`]).
    pub fn from_parts(parts: Fc2dParts<'a>) -> Result<Self, LcpError> {
        let Fc2dParts { n_contacts, group_start, row_ptr, col, blocks, q, mu } = parts;
        if group_start.len() <= n_contacts {
            return Err(structure(format!(
                "{} group starts for {n_contacts} contacts",
                group_start.len()
            )));
        }
        let groups = group_start.len() - 1;
        if group_start[0] != 0 {
            return Err(structure("the first group must start at row 0".into()));
        }
        for g in 0..groups {
            let size = group_start[g + 1].wrapping_sub(group_start[g]);
            let ok = if g < n_contacts { size == 2 } else { size == 1 || size == 2 };
            if !ok {
                let (start, end) = (group_start[g], group_start[g + 1]);
                let rows =
                    if end >= start { format!("{size}") } else { format!("-{}", start - end) };
                return Err(structure(format!(
                    "group {g} has {rows} rows, from {start} to {end} (contacts have 2, \
                     bilateral groups 1 or 2)"
                )));
            }
        }
        if groups > u32::MAX as usize {
            return Err(structure(format!("{groups} groups exceed the u32 column indices")));
        }
        let rows = group_start[groups];
        if row_ptr.len() != groups + 1 || row_ptr[0] != 0 {
            return Err(structure(format!(
                "{} row pointers for {groups} groups (need {} starting at 0)",
                row_ptr.len(),
                groups + 1
            )));
        }
        if row_ptr[groups] != col.len() || col.len() != blocks.len() {
            return Err(structure(format!(
                "row pointers end at {}, with {} column indices and {} blocks",
                row_ptr[groups],
                col.len(),
                blocks.len()
            )));
        }
        if let Some(g) = (0..groups).find(|&g| row_ptr[g] > row_ptr[g + 1]) {
            return Err(structure(format!("row pointers decrease at group {g}")));
        }
        // The block rows, in chunks of groups on rayon's pool for a large problem; the first
        // error in group order is the one returned, as a plain loop would.
        let block_rows = |range: std::ops::Range<usize>| -> Result<(), LcpError> {
            let mut poison = 0.0;
            for g in range {
                let mut big = 0.0f64;
                let mut diagonal = None;
                let mut previous: Option<u32> = None;
                let row_size = group_start[g + 1] - group_start[g];
                for k in row_ptr[g]..row_ptr[g + 1] {
                    let j = col[k];
                    if previous.is_some_and(|p| j <= p) || j as usize >= groups {
                        return Err(structure(format!(
                            "block columns of group {g} must increase and stay below {groups}, found {j}"
                        )));
                    }
                    previous = Some(j);
                    let b = &blocks[k];
                    for v in b {
                        poison += v * 0.0;
                        big = big.max(v.abs());
                    }
                    let j = j as usize;
                    let col_size = group_start[j + 1] - group_start[j];
                    let padding = (row_size == 1 && (b[2] != 0.0 || b[3] != 0.0))
                        || (col_size == 1 && (b[1] != 0.0 || b[3] != 0.0));
                    if padding {
                        return Err(structure(format!(
                            "block ({g}, {j}) has an entry outside its {row_size} x {col_size} size"
                        )));
                    }
                    if j == g {
                        diagonal = Some(k);
                    }
                }
                let Some(d) = diagonal else {
                    return Err(structure(format!("group {g} has no diagonal block")));
                };
                if poison != 0.0 {
                    return Err(first_non_finite_block(row_ptr, col, blocks, group_start));
                }
                if big > MAX_ENTRY {
                    return Err(first_out_of_range_block(g, row_ptr, col, blocks, group_start));
                }
                let (what, index) = if g < n_contacts {
                    ("contact", g)
                } else {
                    ("bilateral group", g - n_contacts)
                };
                check_diagonal(&blocks[d], row_size, what, index)?;
            }
            Ok(())
        };
        chunks::reduce(0..groups, &block_rows, &|a, b| a.and(b))?;
        if q.len() != rows {
            return Err(LcpError::DimensionMismatch { what: "q", expected: rows, found: q.len() });
        }
        if mu.len() != n_contacts {
            return Err(LcpError::DimensionMismatch {
                what: "μ",
                expected: n_contacts,
                found: mu.len(),
            });
        }
        if let Some(i) = q.iter().position(|v| !v.is_finite()) {
            return Err(LcpError::NonFinite { what: "q", index: (i, 0) });
        }
        if let Some(i) = q.iter().position(|v| v.abs() > MAX_ENTRY) {
            return Err(LcpError::OutOfRange { what: "q", index: (i, 0), value: q[i] });
        }
        for (i, &m) in mu.iter().enumerate() {
            if !m.is_finite() {
                return Err(LcpError::NonFinite { what: "μ", index: (i, 0) });
            }
            if m < 0.0 {
                return Err(LcpError::NegativeFriction { contact: i, mu: m });
            }
            if m > MAX_ENTRY {
                return Err(LcpError::OutOfRange { what: "μ", index: (i, 0), value: m });
            }
        }
        Ok(Fc2dRef { parts })
    }

    /// The parts of the problem.
    pub fn parts(&self) -> Fc2dParts<'a> {
        self.parts
    }

    /// Number of contacts n_c.
    pub fn n_contacts(&self) -> usize {
        self.parts.n_contacts
    }

    /// Number of groups (contacts, then bilateral groups).
    pub fn n_groups(&self) -> usize {
        self.parts.group_start.len() - 1
    }

    /// Number of bilateral rows n_b.
    pub fn n_bilateral(&self) -> usize {
        self.n_rows() - 2 * self.parts.n_contacts
    }

    /// Number of rows of W: `2 n_c + n_b`.
    pub fn n_rows(&self) -> usize {
        self.parts.group_start[self.n_groups()]
    }

    /// Number of stored 2x2 blocks.
    pub fn n_blocks(&self) -> usize {
        self.parts.blocks.len()
    }

    /// q.
    pub fn q(&self) -> &'a [f64] {
        self.parts.q
    }

    /// μ, one per contact.
    pub fn mu(&self) -> &'a [f64] {
        self.parts.mu
    }

    /// `‖q‖∞`.
    pub fn q_norm_inf(&self) -> f64 {
        self.parts.q.iter().fold(0.0f64, |m, v| m.max(v.abs()))
    }

    /// `start + Σ_j W_gj r_j`, the two rows of group g's block row applied to r (in the
    /// problem's row layout) and added to `start` block by block; the second entry is
    /// meaningless for a one-row group.
    #[inline]
    pub(crate) fn row_product(&self, g: usize, r: &[f64], start: [f64; 2]) -> [f64; 2] {
        let p = &self.parts;
        let gs = p.group_start;
        let [mut u0, mut u1] = start;
        for k in p.row_ptr[g]..p.row_ptr[g + 1] {
            let j = p.col[k] as usize;
            let b = &p.blocks[k];
            let r0 = r[gs[j]];
            // A one-row column group has zeros in its second block column.
            let r1 = if gs[j + 1] - gs[j] == 2 { r[gs[j] + 1] } else { 0.0 };
            u0 += b[0] * r0 + b[1] * r1;
            u1 += b[2] * r0 + b[3] * r1;
        }
        [u0, u1]
    }

    /// Group g's rows of |W| |r| (the second entry meaningless for a one-row group): the
    /// magnitude of the terms that [`Self::row_product`] sums, which sets its round-off.
    #[inline]
    pub(crate) fn row_magnitude(&self, g: usize, r: &[f64]) -> [f64; 2] {
        let p = &self.parts;
        let gs = p.group_start;
        let [mut m0, mut m1] = [0.0f64; 2];
        for k in p.row_ptr[g]..p.row_ptr[g + 1] {
            let j = p.col[k] as usize;
            let b = &p.blocks[k];
            let r0 = r[gs[j]].abs();
            let r1 = if gs[j + 1] - gs[j] == 2 { r[gs[j] + 1].abs() } else { 0.0 };
            m0 += b[0].abs() * r0 + b[1].abs() * r1;
            m1 += b[2].abs() * r0 + b[3].abs() * r1;
        }
        [m0, m1]
    }

    /// Computes `u = W r + q` (both of length `n_rows`).
    ///
    /// # Panics
    /// If `r` or `u` has the wrong length.
    pub fn velocity(&self, r: &[f64], u: &mut [f64]) {
        let p = &self.parts;
        let n = self.n_rows();
        assert!(r.len() == n && u.len() == n, "r and u must have {n} entries");
        let gs = p.group_start;
        // Each group's rows from its own block row: in chunks of groups on rayon's pool for a
        // large problem, the same bits either way.
        let rows = |groups: std::ops::Range<usize>, u: &mut [f64]| {
            let base = gs[groups.start];
            for g in groups {
                let [u0, u1] = self.row_product(g, r, [0.0; 2]);
                u[gs[g] - base] = u0 + p.q[gs[g]];
                if gs[g + 1] - gs[g] == 2 {
                    u[gs[g] + 1 - base] = u1 + p.q[gs[g] + 1];
                }
            }
        };
        chunks::for_rows(gs, 0..self.n_groups(), u, &rows);
    }

    /// W as a dense `n_rows x n_rows` column-major array (for small problems and tests).
    pub fn to_dense(&self) -> Vec<f64> {
        let mut w = Vec::new();
        self.dense_into(&mut w);
        w
    }

    /// [`Self::to_dense`] into `w`, whose buffer is kept: no allocation once it has held a
    /// problem of this size.
    pub(crate) fn dense_into(&self, w: &mut Vec<f64>) {
        let n = self.n_rows();
        w.clear();
        w.resize(n * n, 0.0);
        self.for_each_entry(|i, j, v| w[i + j * n] += v);
    }

    /// Calls `f(row, column, value)` for each stored entry of W (padding of one-row groups
    /// skipped).
    pub fn for_each_entry(&self, mut f: impl FnMut(usize, usize, f64)) {
        let p = &self.parts;
        let gs = p.group_start;
        for g in 0..self.n_groups() {
            let rs = gs[g + 1] - gs[g];
            for k in p.row_ptr[g]..p.row_ptr[g + 1] {
                let j = p.col[k] as usize;
                let cs = gs[j + 1] - gs[j];
                let b = &p.blocks[k];
                for a in 0..rs {
                    for c in 0..cs {
                        f(gs[g] + a, gs[j] + c, b[2 * a + c]);
                    }
                }
            }
        }
    }

    /// Copies the problem into an owned [`Fc2d`].
    pub fn to_owned(&self) -> Fc2d {
        let p = &self.parts;
        Fc2d {
            n_contacts: p.n_contacts,
            group_start: p.group_start.to_vec(),
            row_ptr: p.row_ptr.to_vec(),
            col: p.col.to_vec(),
            blocks: p.blocks.to_vec(),
            q: p.q.to_vec(),
            mu: p.mu.to_vec(),
        }
    }
}

/// The error naming the first non-finite entry of W.
#[cold]
fn first_non_finite_block(
    row_ptr: &[usize],
    col: &[u32],
    blocks: &[[f64; 4]],
    group_start: &[usize],
) -> LcpError {
    for g in 0..row_ptr.len() - 1 {
        for k in row_ptr[g]..row_ptr[g + 1] {
            if let Some(e) = blocks[k].iter().position(|v| !v.is_finite()) {
                let j = col[k] as usize;
                return LcpError::NonFinite {
                    what: "W",
                    index: (group_start[g] + e / 2, group_start[j] + e % 2),
                };
            }
        }
    }
    LcpError::NonFinite { what: "W", index: (0, 0) }
}

/// The error naming the first entry of group g's block row of W (block by block, each row
/// by row) above [`MAX_ENTRY`] in magnitude; the padding of one-row groups is zero.
#[cold]
fn first_out_of_range_block(
    g: usize,
    row_ptr: &[usize],
    col: &[u32],
    blocks: &[[f64; 4]],
    group_start: &[usize],
) -> LcpError {
    for k in row_ptr[g]..row_ptr[g + 1] {
        if let Some(e) = blocks[k].iter().position(|v| v.abs() > MAX_ENTRY) {
            let j = col[k] as usize;
            return LcpError::OutOfRange {
                what: "W",
                index: (group_start[g] + e / 2, group_start[j] + e % 2),
                value: blocks[k][e],
            };
        }
    }
    LcpError::OutOfRange { what: "W", index: (group_start[g], group_start[g]), value: f64::NAN }
}

impl Fc2d {
    /// Wraps owned parts after validating them as [`Fc2dRef::from_parts`] does.
    ///
    /// # Errors
    /// As [`Fc2dRef::from_parts`].
    fn validated(self) -> Result<Fc2d, LcpError> {
        self.parts_unchecked().validate()?;
        Ok(self)
    }

    fn parts_unchecked(&self) -> Fc2dParts<'_> {
        Fc2dParts {
            n_contacts: self.n_contacts,
            group_start: &self.group_start,
            row_ptr: &self.row_ptr,
            col: &self.col,
            blocks: &self.blocks,
            q: &self.q,
            mu: &self.mu,
        }
    }

    /// A problem of contacts only from a dense W (`2 n_c x 2 n_c`), q and μ; a block is
    /// stored when one of its entries is nonzero (diagonal blocks always).
    ///
    /// # Errors
    /// [`LcpError::DimensionMismatch`] when W is not square (`columns of W`) or not
    /// `2 n_c x 2 n_c` for `n_c = μ.len()` (`rows of W`), and the errors of
    /// [`Fc2dRef::from_parts`].
    pub fn from_dense(w: MatRef<'_, f64>, q: &[f64], mu: &[f64]) -> Result<Fc2d, LcpError> {
        let mut problem = Fc2d::default();
        problem.set_dense(w, q, mu)?;
        Ok(problem)
    }

    /// Replaces the problem by the one of [`Fc2d::from_dense`], reusing this problem's
    /// buffers: no allocation once they are large enough. On error the problem is left
    /// empty (no contacts).
    ///
    /// # Errors
    /// As [`Fc2d::from_dense`].
    pub fn set_dense(&mut self, w: MatRef<'_, f64>, q: &[f64], mu: &[f64]) -> Result<(), LcpError> {
        let n_c = mu.len();
        self.clear();
        if w.nrows() != w.ncols() {
            return Err(LcpError::DimensionMismatch {
                what: "columns of W",
                expected: w.nrows(),
                found: w.ncols(),
            });
        }
        if w.nrows() != 2 * n_c {
            return Err(LcpError::DimensionMismatch {
                what: "rows of W (2 per friction coefficient μ)",
                expected: 2 * n_c,
                found: w.nrows(),
            });
        }
        self.n_contacts = n_c;
        self.group_start.extend((1..=n_c).map(|g| 2 * g));
        for i in 0..n_c {
            for j in 0..n_c {
                let b = [
                    w[(2 * i, 2 * j)],
                    w[(2 * i, 2 * j + 1)],
                    w[(2 * i + 1, 2 * j)],
                    w[(2 * i + 1, 2 * j + 1)],
                ];
                if i == j || b.iter().any(|v| *v != 0.0) {
                    self.col.push(j as u32);
                    self.blocks.push(b);
                }
            }
            self.row_ptr.push(self.col.len());
        }
        self.q.extend_from_slice(q);
        self.mu.extend_from_slice(mu);
        if let Err(e) = self.parts_unchecked().validate() {
            self.clear();
            return Err(e);
        }
        Ok(())
    }

    /// Empties the problem (no contacts), keeping its buffers.
    fn clear(&mut self) {
        self.n_contacts = 0;
        self.group_start.clear();
        self.group_start.push(0);
        self.row_ptr.clear();
        self.row_ptr.push(0);
        self.col.clear();
        self.blocks.clear();
        self.q.clear();
        self.mu.clear();
    }

    /// The borrowed view that the solvers take.
    pub fn view(&self) -> Fc2dRef<'_> {
        Fc2dRef { parts: self.parts_unchecked() }
    }

    /// Number of contacts n_c.
    pub fn n_contacts(&self) -> usize {
        self.n_contacts
    }

    /// Number of rows `2 n_c + n_b`.
    pub fn n_rows(&self) -> usize {
        self.q.len()
    }

    /// Number of groups (contacts, then bilateral groups).
    pub fn n_groups(&self) -> usize {
        self.view().n_groups()
    }

    /// Number of bilateral rows n_b.
    pub fn n_bilateral(&self) -> usize {
        self.n_rows() - 2 * self.n_contacts
    }

    /// Number of stored blocks.
    pub fn n_blocks(&self) -> usize {
        self.blocks.len()
    }

    /// q.
    pub fn q(&self) -> &[f64] {
        &self.q
    }

    /// μ.
    pub fn mu(&self) -> &[f64] {
        &self.mu
    }
}

impl Fc2dParts<'_> {
    fn validate(self) -> Result<(), LcpError> {
        Fc2dRef::from_parts(self).map(|_| ())
    }
}

/// Assembles an [`Fc2d`] from blocks or scalar entries in any order; duplicates add up.
///
/// ```
/// use moreau_lcp::fc2d::Fc2dBuilder;
///
/// # fn main() -> Result<(), moreau_lcp::LcpError> {
/// // Two contacts coupled through a shared body, and one bilateral row.
/// let mut b = Fc2dBuilder::new(2);
/// let joint = b.bilateral_group(1);
/// b.add_block(0, 0, [2.0, 0.5, 0.5, 1.0]);
/// b.add_block(1, 1, [2.0, 0.0, 0.0, 1.0]);
/// b.add_block(0, 1, [0.3, 0.0, 0.0, 0.1]);
/// b.add_block(1, 0, [0.3, 0.0, 0.0, 0.1]);
/// b.add_entry(4, 4, 1.0); // the bilateral row is row 4, its group is `joint`
/// b.add_entry(4, 0, 0.2);
/// b.add_entry(0, 4, 0.2);
/// let problem = b.build(&[-1.0, 0.0, 1.0, 0.0, 0.5], &[0.3, 0.3])?;
/// assert_eq!((problem.n_contacts(), problem.n_rows(), joint), (2, 5, 2));
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct Fc2dBuilder {
    n_contacts: usize,
    group_start: Vec<usize>,
    /// `(row group, column group, block)`, as given (checked by [`Fc2dBuilder::build`]).
    entries: Vec<(usize, usize, [f64; 4])>,
    /// The first entry `(i, j)` given to [`Fc2dBuilder::add_entry`] outside the rows then
    /// declared, and their number then (reported by [`Fc2dBuilder::build`]).
    misplaced: Option<(usize, usize, usize)>,
}

impl Default for Fc2dBuilder {
    /// A builder without contacts: [`Fc2dBuilder::new`]`(0)`.
    fn default() -> Self {
        Fc2dBuilder::new(0)
    }
}

impl Fc2dBuilder {
    /// A builder for `n_contacts` contacts (groups `0..n_contacts`, rows `0..2 n_c`).
    pub fn new(n_contacts: usize) -> Self {
        Fc2dBuilder {
            n_contacts,
            group_start: (0..=n_contacts).map(|g| 2 * g).collect(),
            entries: Vec::new(),
            misplaced: None,
        }
    }

    /// Adds a bilateral group of `rows` rows (1 or 2, other values are reported by
    /// [`Fc2dBuilder::build`]) after the existing groups; returns its group index.
    pub fn bilateral_group(&mut self, rows: usize) -> usize {
        let last = *self.group_start.last().unwrap_or(&0);
        self.group_start.push(last.saturating_add(rows));
        self.group_start.len() - 2
    }

    /// Adds a 2x2 block `[W_00, W_01, W_10, W_11]` between group `row` and group `col`
    /// (groups outside those declared are reported by [`Fc2dBuilder::build`]).
    pub fn add_block(&mut self, row: usize, col: usize, block: [f64; 4]) {
        self.entries.push((row, col, block));
    }

    /// Adds `value` to the entry W_ij (rows and columns numbered as in q) of the rows of the
    /// groups declared so far (an entry outside them is reported by [`Fc2dBuilder::build`]).
    pub fn add_entry(&mut self, i: usize, j: usize, value: f64) {
        match (self.locate(i), self.locate(j)) {
            (Some((gi, a)), Some((gj, c))) => {
                let mut block = [0.0; 4];
                block[2 * a + c] = value;
                self.entries.push((gi, gj, block));
            }
            _ => {
                let rows = *self.group_start.last().unwrap_or(&0);
                self.misplaced.get_or_insert((i, j, rows));
            }
        }
    }

    /// The group of `row` and the row's place in it (0 or 1), if a declared group has it.
    fn locate(&self, row: usize) -> Option<(usize, usize)> {
        let g = self.group_start.partition_point(|&s| s <= row);
        (g >= 1 && g < self.group_start.len()).then(|| (g - 1, row - self.group_start[g - 1]))
    }

    /// Builds the problem with q (one entry per row) and μ (one per contact); missing
    /// diagonal blocks are stored as zeros.
    ///
    /// # Errors
    /// As [`Fc2dRef::from_parts`]; a block outside the groups, or an entry outside the rows
    /// declared when it was added, gives [`LcpError::Structure`] naming it.
    pub fn build(&self, q: &[f64], mu: &[f64]) -> Result<Fc2d, LcpError> {
        if let Some((i, j, rows)) = self.misplaced {
            return Err(structure(format!(
                "entry ({i}, {j}) is outside the {rows} rows of the groups declared when it \
                 was added"
            )));
        }
        let groups = self.group_start.len() - 1;
        if groups > u32::MAX as usize {
            return Err(structure(format!("{groups} groups exceed the u32 column indices")));
        }
        if let Some(&(i, j, _)) = self.entries.iter().find(|(i, j, _)| *i >= groups || *j >= groups)
        {
            return Err(structure(format!("block ({i}, {j}) outside the {groups} groups")));
        }
        let mut entries = self.entries.clone();
        entries.extend((0..groups).map(|g| (g, g, [0.0; 4])));
        entries.sort_by_key(|&(i, j, _)| (i, j));
        let mut row_ptr = vec![0; groups + 1];
        let mut col: Vec<u32> = Vec::with_capacity(entries.len());
        let mut blocks: Vec<[f64; 4]> = Vec::with_capacity(entries.len());
        let mut last: Option<(usize, usize)> = None;
        for (i, j, b) in entries {
            if last == Some((i, j)) {
                let dst = blocks.last_mut().expect("a block was pushed for this key");
                for (d, s) in dst.iter_mut().zip(b) {
                    *d += s;
                }
            } else {
                // j < groups <= u32::MAX, checked above.
                col.push(j as u32);
                blocks.push(b);
                row_ptr[i + 1] += 1;
                last = Some((i, j));
            }
        }
        for g in 0..groups {
            row_ptr[g + 1] += row_ptr[g];
        }
        Fc2d {
            n_contacts: self.n_contacts,
            group_start: self.group_start.clone(),
            row_ptr,
            col,
            blocks,
            q: q.to_vec(),
            mu: mu.to_vec(),
        }
        .validated()
    }
}
