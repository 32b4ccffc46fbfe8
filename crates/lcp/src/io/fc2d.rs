//! Siconos' planar frictional-contact files: FC2D (`frictionContact_newFromFile`) and the
//! global form GFC2D (`globalFrictionContact_newFromFile`).
//!
//! FC2D: the dimension (2), the number of contacts n_c, W as a NumericsMatrix
//! (`2 n_c x 2 n_c`, any storage), q (`2 n_c` numbers), μ (n_c numbers). Rows are ordered
//! `(N, T)` per contact. Nothing may follow μ but the flag `0` or `1` alone that Siconos'
//! former writer added (`isComplete`; five files of Siconos' collection end with it).
//!
//! GFC2D: the dimension (2), n_c, M (`n x n`), H (`n x 2 n_c`), q (n numbers), b
//! (`2 n_c` numbers), μ (n_c numbers), for `M v = q + H r` and `u = Hᵀ v + b`. Nothing may
//! follow μ.

use std::io::{Read, Write};

use faer::Col;
use faer::Side;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, Lu};
use faer::sparse::{SparseColMat, Triplet};

use super::numerics::{self, NumericsMatrix, write_numbers};
use super::tokens::{Tokens, Trailer, check_count};
use crate::fc2d::{Fc2d, Fc2dBuilder};
use crate::{LcpError, MAX_ENTRY};

/// The matrix storage used to write W in a Siconos FC2D file.
#[non_exhaustive]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SiconosStorage {
    /// Storage 0: every entry, column by column.
    Dense,
    /// Storage 1: Siconos' sparse block matrix, 2x2 blocks.
    SparseBlock,
    /// Storage 2: CSparse compressed columns.
    Sparse,
}

/// Reads the header of a frictional-contact file: the dimension (2) and n_c.
fn header(t: &mut Tokens<'_>) -> Result<usize, LcpError> {
    let (line, dim) = t.integer("the dimension")?;
    if dim != 2 {
        return Err(LcpError::Parse {
            line,
            message: format!("dimension {dim}: only planar (2) problems are read"),
        });
    }
    t.count("the number of contacts", 0)
}

fn numbers(t: &mut Tokens<'_>, n: usize, what: &str, len: usize) -> Result<Vec<f64>, LcpError> {
    check_count(n, len, t.line)?;
    (0..n).map(|_| t.number(what)).collect()
}

/// A size check for [`numerics::read_matrix`]: the matrix must be `rows x cols`, as `why`
/// says (the counts read before it, which disagree with it otherwise); its error's line is set
/// by the reader.
fn sized(
    what: &'static str,
    rows: usize,
    cols: usize,
    why: String,
) -> impl FnOnce(usize, usize) -> Result<(), LcpError> {
    move |r, c| {
        if (r, c) == (rows, cols) {
            Ok(())
        } else {
            Err(LcpError::Parse {
                line: 0,
                message: format!("{what} is {r} x {c}, expected {rows} x {cols}: {why}"),
            })
        }
    }
}

/// Why W or H has 2 n_c rows or columns: the count of contacts on `line`.
fn per_contact(n_c: usize, line: usize) -> String {
    format!("2 per contact, for n_c = {n_c} announced on line {line}")
}

impl Fc2d {
    /// Reads a Siconos FC2D file (W in dense, sparse block or CSparse storage). Exact
    /// zeros of a dense W are not stored; the entries of a sparse W are, as listed.
    ///
    /// # Errors
    /// [`LcpError::Io`], [`LcpError::Parse`] (with the line), a dimension other than 2,
    /// [`LcpError::UnsupportedStorage`], [`LcpError::TrailingData`] (with the line) for data
    /// after μ other than the flag `0` or `1`, or a validation error of
    /// [`Fc2dRef::from_parts`](crate::fc2d::Fc2dRef::from_parts): among them
    /// [`LcpError::OutOfRange`] naming an entry of W (its row and column), q or μ beyond
    /// [`MAX_ENTRY`](crate::MAX_ENTRY).
    pub fn read_siconos<R: Read>(mut reader: R) -> Result<Fc2d, LcpError> {
        let mut text = String::new();
        reader.read_to_string(&mut text)?;
        let mut t = Tokens::new(&text, false);
        let n_c = header(&mut t)?;
        let why = per_contact(n_c, t.line);
        let w = numerics::read_matrix(&mut t, text.len(), sized("W", 2 * n_c, 2 * n_c, why))?;
        let q = numbers(&mut t, 2 * n_c, "an entry of q", text.len())?;
        let mu = numbers(&mut t, n_c, "a friction coefficient", text.len())?;
        t.end("μ", Trailer::Flag)?;
        let mut builder = Fc2dBuilder::new(n_c);
        for &(i, j, v) in &w.entries {
            if v != 0.0 || w.storage != 0 {
                builder.add_entry(i, j, v);
            }
        }
        builder.build(&q, &mu)
    }

    /// Writes a Siconos FC2D file with W in the given storage; numbers are written in the
    /// shortest form that reads back exactly.
    ///
    /// # Errors
    /// [`LcpError::Io`], or [`LcpError::Structure`] when the problem has bilateral rows
    /// (the format has none).
    pub fn write_siconos<W: Write>(
        &self,
        mut w: W,
        storage: SiconosStorage,
    ) -> Result<(), LcpError> {
        let p = self.view();
        if p.n_bilateral() > 0 {
            return Err(LcpError::Structure("Siconos' FC2D format has no bilateral rows".into()));
        }
        let n_c = p.n_contacts();
        let n = 2 * n_c;
        writeln!(w, "2\n{n_c}")?;
        let parts = p.parts();
        match storage {
            SiconosStorage::Dense => numerics::write_dense(&mut w, n, n, &p.to_dense())?,
            SiconosStorage::SparseBlock => {
                let nb = parts.blocks.len();
                writeln!(w, "1\n{n}\n{n}\n{nb}")?;
                if nb > 0 {
                    writeln!(w, "{n_c}\n{n_c}")?;
                    let ends: Vec<String> = (1..=n_c).map(|g| (2 * g).to_string()).collect();
                    writeln!(w, "{}\n{}", ends.join("\t"), ends.join("\t"))?;
                    writeln!(w, "{}\n{nb}", n_c + 1)?;
                    let list =
                        |v: &mut dyn Iterator<Item = String>| v.collect::<Vec<_>>().join("\t");
                    writeln!(w, "{}", list(&mut parts.row_ptr.iter().map(|x| x.to_string())))?;
                    writeln!(w, "{}", list(&mut parts.col.iter().map(|x| x.to_string())))?;
                    for (k, b) in parts.blocks.iter().enumerate() {
                        writeln!(w, "{k}")?;
                        // Siconos stores each block column by column.
                        for v in [b[0], b[2], b[1], b[3]] {
                            writeln!(w, "{v:e}")?;
                        }
                    }
                }
            }
            SiconosStorage::Sparse => {
                let mut columns: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
                p.for_each_entry(|i, j, v| columns[j].push((i, v)));
                let nnz: usize = columns.iter().map(Vec::len).sum();
                let norm1 = columns
                    .iter()
                    .map(|c| c.iter().map(|(_, v)| v.abs()).sum::<f64>())
                    .fold(0.0, f64::max);
                writeln!(w, "2\n{n}\n{n}\n1")?;
                writeln!(w, "CSparse listing, compressed columns")?;
                writeln!(w, "{n}-by-{n}, nzmax: {nnz} nnz: {nnz}, 1-norm: {norm1:e}")?;
                let mut at = 0;
                for (j, c) in columns.iter().enumerate() {
                    writeln!(w, "    col {j} : locations {at} to {}", (at + c.len()) as i64 - 1)?;
                    for (i, v) in c {
                        writeln!(w, "      {i} : {v:e}")?;
                    }
                    at += c.len();
                }
            }
        }
        write_numbers(&mut w, p.q().iter().copied())?;
        write_numbers(&mut w, p.mu().iter().copied())?;
        Ok(())
    }
}

/// A global planar frictional-contact problem (Siconos' GFC2D): velocities v with
/// `M v = q + H r`, contact velocities `u = Hᵀ v + b`, and Coulomb's and Signorini's laws
/// between r and u per contact.
///
/// [`Gfc2d::reduce`] eliminates v: `u = W r + q_W` with `W = Hᵀ M⁻¹ H` and
/// `q_W = Hᵀ M⁻¹ q + b`, an [`Fc2d`] problem; [`Reduced::global_velocity`] recovers v.
#[derive(Clone, Debug)]
pub struct Gfc2d {
    m: SparseColMat<usize, f64>,
    h: SparseColMat<usize, f64>,
    q: Vec<f64>,
    b: Vec<f64>,
    mu: Vec<f64>,
}

/// The factorisation of M kept to recover the global velocity.
#[derive(Clone, Debug)]
enum Factor {
    Cholesky(Llt<usize, f64>),
    Lu(Box<Lu<usize, f64>>),
}

impl Factor {
    fn solve(&self, rhs: &Col<f64>) -> Col<f64> {
        match self {
            Factor::Cholesky(f) => f.solve(rhs),
            Factor::Lu(f) => f.solve(rhs),
        }
    }
}

/// A global problem reduced to the contact space: the [`Fc2d`] problem in W and q_W, and
/// the factorisation of M that maps reactions back to global velocities.
#[derive(Clone, Debug)]
pub struct Reduced {
    /// The reduced problem `u = W r + q_W`.
    pub problem: Fc2d,
    factor: Factor,
}

fn sparse(m: &NumericsMatrix, what: &str) -> Result<SparseColMat<usize, f64>, LcpError> {
    let triplets: Vec<Triplet<usize, usize, f64>> =
        m.entries.iter().map(|&(i, j, v)| Triplet::new(i, j, v)).collect();
    SparseColMat::try_new_from_triplets(m.rows, m.cols, &triplets)
        .map_err(|e| LcpError::Structure(format!("{what}: {e:?}")))
}

impl Gfc2d {
    /// Reads a Siconos GFC2D file.
    ///
    /// # Errors
    /// [`LcpError::Io`], [`LcpError::Parse`] (with the line), a dimension other than 2,
    /// sizes that do not agree, [`LcpError::TrailingData`] (with the line) for data after μ,
    /// non-finite entries ([`LcpError::NonFinite`]), a negative μ, or an entry of M, H, q, b
    /// or μ beyond [`MAX_ENTRY`](crate::MAX_ENTRY) ([`LcpError::OutOfRange`]).
    pub fn read_siconos<R: Read>(mut reader: R) -> Result<Gfc2d, LcpError> {
        let mut text = String::new();
        reader.read_to_string(&mut text)?;
        let len = text.len();
        let mut t = Tokens::new(&text, false);
        let n_c = header(&mut t)?;
        let contacts_line = t.line;
        let m = numerics::read_matrix(&mut t, len, |r, c| {
            // The mass matrix, not an LCP's M: the error says which.
            if r == c {
                Ok(())
            } else {
                Err(LcpError::DimensionMismatch {
                    what: "columns of the mass matrix M",
                    expected: r,
                    found: c,
                })
            }
        })?;
        let n = m.rows;
        let why = format!("one row per row of M, columns {}", per_contact(n_c, contacts_line));
        let h = numerics::read_matrix(&mut t, len, sized("H", n, 2 * n_c, why))?;
        let q = numbers(&mut t, n, "an entry of q", len)?;
        let b = numbers(&mut t, 2 * n_c, "an entry of b", len)?;
        let mu = numbers(&mut t, n_c, "a friction coefficient", len)?;
        t.end("μ", Trailer::Nothing)?;
        for (what, entries) in [("M", &m.entries), ("H", &h.entries)] {
            if let Some(&(i, j, _)) = entries.iter().find(|e| !e.2.is_finite()) {
                return Err(LcpError::NonFinite { what, index: (i, j) });
            }
        }
        for (what, v) in [("q", &q), ("b", &b), ("μ", &mu)] {
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(LcpError::NonFinite { what, index: (i, 0) });
            }
        }
        if let Some(i) = mu.iter().position(|&x| x < 0.0) {
            return Err(LcpError::NegativeFriction { contact: i, mu: mu[i] });
        }
        for (what, entries) in [("M", &m.entries), ("H", &h.entries)] {
            if let Some(&(i, j, value)) = entries.iter().find(|e| e.2.abs() > MAX_ENTRY) {
                return Err(LcpError::OutOfRange { what, index: (i, j), value });
            }
        }
        for (what, v) in [("q", &q), ("b", &b), ("μ", &mu)] {
            if let Some(i) = v.iter().position(|x| x.abs() > MAX_ENTRY) {
                return Err(LcpError::OutOfRange { what, index: (i, 0), value: v[i] });
            }
        }
        Ok(Gfc2d { m: sparse(&m, "M")?, h: sparse(&h, "H")?, q, b, mu })
    }

    /// Number of contacts n_c.
    pub fn n_contacts(&self) -> usize {
        self.mu.len()
    }

    /// Number of global velocities n.
    pub fn n_velocities(&self) -> usize {
        self.q.len()
    }

    /// M, `n x n`.
    pub fn m(&self) -> &SparseColMat<usize, f64> {
        &self.m
    }

    /// H, `n x 2 n_c`.
    pub fn h(&self) -> &SparseColMat<usize, f64> {
        &self.h
    }

    /// q, the global right-hand side.
    pub fn q(&self) -> &[f64] {
        &self.q
    }

    /// b, the contact velocity offset.
    pub fn b(&self) -> &[f64] {
        &self.b
    }

    /// μ.
    pub fn mu(&self) -> &[f64] {
        &self.mu
    }

    /// Forms the reduced problem with a sparse factorisation of M (Cholesky, or LU when M
    /// is not positive definite): `W = Hᵀ M⁻¹ H` column by column, keeping the structural
    /// nonzeros, and `q_W = Hᵀ M⁻¹ q + b`.
    ///
    /// # Errors
    /// [`LcpError::Singular`] when M cannot be factored, and the validation errors of the
    /// reduced problem.
    pub fn reduce(&self) -> Result<Reduced, LcpError> {
        let factor = match self.m.sp_cholesky(Side::Lower) {
            Ok(f) => Factor::Cholesky(f),
            Err(_) => {
                Factor::Lu(Box::new(self.m.sp_lu().map_err(|_| LcpError::Singular { what: "M" })?))
            }
        };
        let n = self.n_velocities();
        let cols = 2 * self.n_contacts();
        // Hᵀ by columns is H by rows: the rows of H that a column of M⁻¹ H meets.
        let ht = self
            .h
            .transpose()
            .to_col_major()
            .map_err(|e| LcpError::Structure(format!("Hᵀ: {e:?}")))?;
        let mut builder = Fc2dBuilder::new(self.n_contacts());
        let mut rhs = Col::<f64>::zeros(n);
        let mut acc = vec![0.0; cols];
        let mut touched = vec![false; cols];
        let mut list = Vec::new();
        for j in 0..cols {
            rhs.fill(0.0);
            for (i, v) in self.h.row_idx_of_col(j).zip(self.h.val_of_col(j)) {
                rhs[i] += *v;
            }
            let x = factor.solve(&rhs);
            if !x.iter().all(|v| v.is_finite()) {
                return Err(LcpError::Singular { what: "M" });
            }
            // Column j of W is Σ_k x_k (row k of H)ᵀ over the nonzero x_k.
            for k in 0..n {
                let xk = x[k];
                if xk == 0.0 {
                    continue;
                }
                for (i, v) in ht.row_idx_of_col(k).zip(ht.val_of_col(k)) {
                    if !touched[i] {
                        touched[i] = true;
                        list.push(i);
                    }
                    acc[i] += xk * v;
                }
            }
            for &i in &list {
                builder.add_entry(i, j, acc[i]);
                acc[i] = 0.0;
                touched[i] = false;
            }
            list.clear();
        }
        let q = Col::from_fn(n, |i| self.q[i]);
        let x = factor.solve(&q);
        let mut q_w = self.b.clone();
        for (k, &xk) in x.iter().enumerate() {
            for (i, v) in ht.row_idx_of_col(k).zip(ht.val_of_col(k)) {
                q_w[i] += v * xk;
            }
        }
        Ok(Reduced { problem: builder.build(&q_w, &self.mu)?, factor })
    }
}

impl Reduced {
    /// The global velocity `v = M⁻¹ (q + H r)` of the reactions r of the reduced problem.
    ///
    /// # Panics
    /// When r does not have `2 n_c` entries.
    pub fn global_velocity(&self, global: &Gfc2d, r: &[f64]) -> Vec<f64> {
        assert_eq!(r.len(), 2 * global.n_contacts(), "r must have 2 n_c entries");
        let mut rhs = Col::from_fn(global.n_velocities(), |i| global.q[i]);
        for (j, &rj) in r.iter().enumerate() {
            for (i, v) in global.h.row_idx_of_col(j).zip(global.h.val_of_col(j)) {
                rhs[i] += v * rj;
            }
        }
        let v = self.factor.solve(&rhs);
        v.iter().copied().collect()
    }
}
