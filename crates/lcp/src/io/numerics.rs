//! Siconos numerics' matrix storages (`NumericsMatrix`), read and written in one place for
//! the LCP, FC2D and global FC2D files.
//!
//! A matrix starts with its storage type and its two sizes, each on its own line:
//!
//! ```text
//! storage            0 = dense, 1 = sparse block (SBM), 2 = sparse (CSparse)
//! rows
//! columns
//! ```
//!
//! **Dense** (0): `rows columns` once more on one line, then the rows x columns entries
//! column by column.
//!
//! **Sparse block** (1): the number of stored blocks; the numbers of block rows and block
//! columns; the cumulative block row sizes (the last equals `rows`) and column sizes; the
//! lengths of the two index arrays (block rows + 1, stored blocks); the block row pointers;
//! the block column of each stored block; then each stored block as its number followed by
//! its entries column by column.
//!
//! **Sparse** (2): the CSparse origin (0 triplet, 1 compressed column, 2 compressed row,
//! 3 half triplet; the header line below decides), a line `CSparse Version ...`, a header
//! line `[triplet:|csr:] R-by-C, nzmax: N nnz: K[, 1-norm: x]`, then for compressed
//! storage each column (row) as `col j : locations a to b` followed by `i : x` for
//! positions a to b, or for triplets K lines `i j : x`. Siconos prints these values with
//! six significant digits.
//!
//! A duplicate entry adds to the earlier one (the CSparse convention for triplets).

use std::io::Write;

use super::tokens::{Tokens, check_count};
use crate::LcpError;

/// A matrix as read from a Siconos file: its sizes, the storage it was read from and its
/// entries `(row, column, value)` in file order (duplicates not yet summed).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct NumericsMatrix {
    pub(crate) rows: usize,
    pub(crate) cols: usize,
    pub(crate) storage: i64,
    pub(crate) entries: Vec<(usize, usize, f64)>,
}

impl NumericsMatrix {
    /// The matrix as a dense column-major array (duplicates summed).
    pub(crate) fn to_column_major(&self) -> Vec<f64> {
        let mut m = vec![0.0; self.rows * self.cols];
        for &(i, j, v) in &self.entries {
            m[i + j * self.rows] += v;
        }
        m
    }
}

/// Reads one `NumericsMatrix` at the tokenizer's position; `check` judges its sizes
/// (rows, columns) before any entry is read, and its parse error at line 0 is given the
/// line of the sizes.
pub(crate) fn read_matrix(
    t: &mut Tokens<'_>,
    text_len: usize,
    check: impl FnOnce(usize, usize) -> Result<(), LcpError>,
) -> Result<NumericsMatrix, LcpError> {
    let (_, storage) = t.integer("the matrix storage type")?;
    if !(0..=2).contains(&storage) {
        return Err(LcpError::UnsupportedStorage { storage });
    }
    let rows = t.count("the number of rows", 0)?;
    let cols = t.count("the number of columns", 0)?;
    // A size refused by `check` is placed on the line that gives it.
    check(rows, cols).map_err(|e| match e {
        LcpError::Parse { line: 0, message } => LcpError::Parse { line: t.line, message },
        other => other,
    })?;
    let entries = match storage {
        0 => read_dense(t, rows, cols, text_len)?,
        1 => read_sparse_block(t, rows, cols, text_len)?,
        _ => read_csparse(t, rows, cols, text_len)?,
    };
    Ok(NumericsMatrix { rows, cols, storage, entries })
}

fn read_dense(
    t: &mut Tokens<'_>,
    rows: usize,
    cols: usize,
    text_len: usize,
) -> Result<Vec<(usize, usize, f64)>, LcpError> {
    let rows2 = t.count("the number of rows (dense header)", 0)?;
    let cols2 = t.count("the number of columns (dense header)", 0)?;
    if rows != rows2 || cols != cols2 {
        return Err(t.error(format!(
            "dense header {rows2} x {cols2} disagrees with sizes {rows} x {cols}"
        )));
    }
    let total = rows.checked_mul(cols).ok_or_else(|| t.error("matrix too large".into()))?;
    check_count(total, text_len, t.line)?;
    let mut entries = Vec::with_capacity(total);
    for j in 0..cols {
        for i in 0..rows {
            entries.push((i, j, t.number("an entry of the matrix")?));
        }
    }
    Ok(entries)
}

/// Reads a list of `count` integers, each at most `max`.
fn index_list(
    t: &mut Tokens<'_>,
    count: usize,
    max: usize,
    what: &str,
    text_len: usize,
) -> Result<Vec<usize>, LcpError> {
    check_count(count, text_len, t.line)?;
    (0..count)
        .map(|_| {
            let (line, v) = t.integer(what)?;
            usize::try_from(v).ok().filter(|&v| v <= max).ok_or_else(|| LcpError::Parse {
                line,
                message: format!("{what} {v} is out of range 0..={max}"),
            })
        })
        .collect()
}

/// Checks that cumulative sizes increase strictly and end at `total`.
fn check_cumulative(
    t: &Tokens<'_>,
    sizes: &[usize],
    total: usize,
    what: &str,
) -> Result<(), LcpError> {
    let mut last = 0;
    for &s in sizes {
        if s <= last {
            return Err(t.error(format!("{what} must increase strictly, found {s} after {last}")));
        }
        last = s;
    }
    if last != total {
        return Err(t.error(format!("{what} end at {last}, the matrix has {total}")));
    }
    Ok(())
}

fn read_sparse_block(
    t: &mut Tokens<'_>,
    rows: usize,
    cols: usize,
    text_len: usize,
) -> Result<Vec<(usize, usize, f64)>, LcpError> {
    let nbblocks = t.count("the number of stored blocks", 0)?;
    if nbblocks == 0 {
        return Ok(Vec::new());
    }
    let block_rows = t.count("the number of block rows", 1)?;
    let block_cols = t.count("the number of block columns", 1)?;
    let row_ends = index_list(t, block_rows, rows, "a cumulative block row size", text_len)?;
    let col_ends = index_list(t, block_cols, cols, "a cumulative block column size", text_len)?;
    check_cumulative(t, &row_ends, rows, "cumulative block row sizes")?;
    check_cumulative(t, &col_ends, cols, "cumulative block column sizes")?;
    let filled1 = t.count("the length of the block row pointers", 1)?;
    let filled2 = t.count("the number of stored blocks (index list)", 0)?;
    if filled2 != nbblocks {
        return Err(t.error(format!("{filled2} block column indices for {nbblocks} blocks")));
    }
    if filled1 > block_rows + 1 {
        return Err(t.error(format!(
            "{filled1} block row pointers for {block_rows} block rows (at most one more)"
        )));
    }
    let row_ptr = index_list(t, filled1, nbblocks, "a block row pointer", text_len)?;
    let col_index = index_list(t, filled2, block_cols - 1, "a block column index", text_len)?;
    if row_ptr.windows(2).any(|w| w[0] > w[1]) || row_ptr.last() != Some(&nbblocks) {
        return Err(t.error(
            "block row pointers must not decrease and must end at the number of blocks".into(),
        ));
    }
    let start = |ends: &[usize], k: usize| if k == 0 { 0 } else { ends[k - 1] };
    let mut entries = Vec::new();
    for br in 0..filled1 - 1 {
        let (r0, r1) = (start(&row_ends, br), row_ends[br]);
        for (b, &bc) in col_index.iter().enumerate().take(row_ptr[br + 1]).skip(row_ptr[br]) {
            let (line, number) = t.integer("a block number")?;
            if number != b as i64 {
                return Err(LcpError::Parse {
                    line,
                    message: format!("block number {number} where block {b} was expected"),
                });
            }
            let (c0, c1) = (start(&col_ends, bc), col_ends[bc]);
            check_count((r1 - r0) * (c1 - c0), text_len, t.line)?;
            for j in c0..c1 {
                for i in r0..r1 {
                    entries.push((i, j, t.number("an entry of a block")?));
                }
            }
        }
    }
    Ok(entries)
}

/// Parses `R-by-C` (with an optional trailing comma).
fn parse_by(t: &Tokens<'_>, token: &str) -> Result<(usize, usize), LcpError> {
    let token = token.trim_end_matches(',');
    let mut parts = token.split("-by-");
    let r = parts.next().and_then(|s| s.parse::<usize>().ok());
    let c = parts.next().and_then(|s| s.parse::<usize>().ok());
    match (r, c, parts.next()) {
        (Some(r), Some(c), None) => Ok((r, c)),
        _ => Err(
            t.error(format!("expected 'ROWS-by-COLUMNS' in the CSparse header, found '{token}'"))
        ),
    }
}

fn read_csparse(
    t: &mut Tokens<'_>,
    rows: usize,
    cols: usize,
    text_len: usize,
) -> Result<Vec<(usize, usize, f64)>, LcpError> {
    let (line, origin) = t.integer("the CSparse origin")?;
    if !(0..=3).contains(&origin) {
        return Err(LcpError::Parse {
            line,
            message: format!("CSparse origin {origin} is not 0, 1, 2 or 3"),
        });
    }
    t.expect("CSparse")?;
    t.skip_rest_of_line();
    let (_, first) = t.token("the CSparse header")?;
    let (kind, by) = match first {
        "triplet:" => (0, t.token("the CSparse sizes")?.1),
        "csr:" => (2, t.token("the CSparse sizes")?.1),
        _ => (1, first),
    };
    let (r, c) = parse_by(t, by)?;
    if (r, c) != (rows, cols) {
        return Err(
            t.error(format!("CSparse header {r}-by-{c} disagrees with sizes {rows} x {cols}"))
        );
    }
    t.expect("nzmax:")?;
    t.token("nzmax")?;
    t.expect("nnz:")?;
    let (line, nnz) = t.token("nnz")?;
    let nnz = nnz.trim_end_matches(',').parse::<usize>().map_err(|_| LcpError::Parse {
        line,
        message: format!("expected the number of entries after 'nnz:', found '{nnz}'"),
    })?;
    t.skip_rest_of_line();
    check_count(nnz, text_len, t.line)?;
    let mut entries = Vec::with_capacity(nnz);
    let bad = |line: usize, what: &str, v: i64, max: usize| LcpError::Parse {
        line,
        message: format!("{what} {v} is out of range 0..{max}"),
    };
    if kind == 0 {
        for _ in 0..nnz {
            let (line, i) = t.integer("a row index")?;
            let (_, j) = t.integer("a column index")?;
            t.expect(":")?;
            let v = t.number("an entry")?;
            let i =
                usize::try_from(i).ok().filter(|&i| i < rows).ok_or(bad(line, "row", i, rows))?;
            let j = usize::try_from(j)
                .ok()
                .filter(|&j| j < cols)
                .ok_or(bad(line, "column", j, cols))?;
            entries.push((i, j, v));
        }
        return Ok(entries);
    }
    let (outer, inner, word) = if kind == 1 { (cols, rows, "col") } else { (rows, cols, "row") };
    let mut next = 0usize;
    for k in 0..outer {
        t.expect(word)?;
        let (line, index) = t.integer("a column number")?;
        if index != k as i64 {
            return Err(LcpError::Parse {
                line,
                message: format!("{word} {index} where {word} {k} was expected"),
            });
        }
        t.expect(":")?;
        t.expect("locations")?;
        let (line, a) = t.integer("the first location")?;
        t.expect("to")?;
        let (_, b) = t.integer("the last location")?;
        if a != next as i64 || b < a - 1 || b >= nnz as i64 {
            return Err(LcpError::Parse {
                line,
                message: format!(
                    "locations {a} to {b} do not continue at {next} within {nnz} entries"
                ),
            });
        }
        for _ in a..=b {
            let (line, i) = t.integer("an index")?;
            t.expect(":")?;
            let v = t.number("an entry")?;
            let i = usize::try_from(i)
                .ok()
                .filter(|&i| i < inner)
                .ok_or(bad(line, "index", i, inner))?;
            entries.push(if kind == 1 { (i, k, v) } else { (k, i, v) });
        }
        next = (b + 1) as usize;
    }
    if next != nnz {
        return Err(t.error(format!("{next} entries listed, the header announces {nnz}")));
    }
    Ok(entries)
}

/// Writes `values` on one line in the shortest form that reads back exactly.
pub(crate) fn write_numbers<W: Write>(
    w: &mut W,
    values: impl Iterator<Item = f64>,
) -> std::io::Result<()> {
    let mut first = true;
    for v in values {
        if !first {
            w.write_all(b" ")?;
        }
        write!(w, "{v:e}")?;
        first = false;
    }
    writeln!(w)
}

/// Writes the header and entries of a dense `NumericsMatrix` (`m` column-major).
pub(crate) fn write_dense<W: Write>(
    w: &mut W,
    rows: usize,
    cols: usize,
    m: &[f64],
) -> std::io::Result<()> {
    writeln!(w, "0\n{rows}\n{cols}\n{rows}\t{cols}")?;
    for j in 0..cols {
        write_numbers(w, m[j * rows..(j + 1) * rows].iter().copied())?;
    }
    Ok(())
}
