//! Text formats: plain and Siconos numerics' LCP data file, Siconos' FC2D and global FC2D
//! files, and the matrix storages they share.
//!
//! **Plain** (whitespace-separated, `#` starts a comment that runs to the end of the
//! line): n, then M row by row (n^2 numbers), then q (n numbers). Nothing else may follow
//! ([`LcpError::TrailingData`]).
//!
//! **Siconos** (the format of `linearComplementarity_newFromFile` /
//! `linearComplementarity_printInFile` of Siconos numerics):
//!
//! ```text
//! n
//! M                  (a NumericsMatrix: storage type, rows, columns, then the storage's
//!                     layout, see below; dense, sparse block and sparse are read)
//! q                  (n numbers)
//! anything else      (a free-text comment, ignored; it may not start with a number, which
//!                     would be data beyond the announced sizes)
//! ```
//!
//! The matrix storages are described in the `numerics` module; the FC2D files in `fc2d`.

use std::io::{Read, Write};

use crate::{Lcp, LcpError};

mod fc2d;
mod numerics;
mod tokens;

pub use fc2d::{Gfc2d, Reduced, SiconosStorage};
pub(crate) use numerics::write_numbers;
use tokens::{Tokens, Trailer, check_count};

fn parse_plain(text: &str) -> Result<Lcp, LcpError> {
    let mut t = Tokens::new(text, true);
    let n = t.size("the size n")?;
    let Some(values) = n.checked_mul(n).and_then(|m| m.checked_add(n)) else {
        return Err(t.error(format!(
            "the size n = {n} announces n² + n values, more than the input can hold"
        )));
    };
    check_count(values, text.len(), t.line)?;
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            m[i + j * n] = t.number("an entry of M")?;
        }
    }
    let q = (0..n).map(|_| t.number("an entry of q")).collect::<Result<Vec<f64>, _>>()?;
    t.end("q", Trailer::Nothing)?;
    Lcp::from_column_major(n, &m, &q)
}

fn parse_siconos(text: &str) -> Result<Lcp, LcpError> {
    let mut t = Tokens::new(text, false);
    let n = t.size("the size n")?;
    let m = numerics::read_matrix(&mut t, text.len(), |rows, cols| {
        if rows != cols {
            Err(LcpError::NotSquare { rows, cols })
        } else if rows != n {
            Err(LcpError::DimensionMismatch {
                what: "Siconos matrix size",
                expected: n,
                found: rows,
            })
        } else {
            Ok(())
        }
    })?;
    let q = (0..n).map(|_| t.number("an entry of q")).collect::<Result<Vec<f64>, _>>()?;
    t.end("q", Trailer::Comment)?;
    Lcp::from_column_major(n, &m.to_column_major(), &q)
}

impl Lcp {
    /// Writes the plain format (n, M row by row, q), one row of M per line; numbers
    /// are written in the shortest form that reads back exactly.
    ///
    /// # Errors
    /// Any error of the writer.
    pub fn write_plain<W: Write>(&self, mut w: W) -> std::io::Result<()> {
        let (m, q, n) = (self.m(), self.q(), self.n());
        writeln!(w, "{n}")?;
        for i in 0..n {
            write_numbers(&mut w, (0..n).map(|j| m[(i, j)]))?;
        }
        write_numbers(&mut w, (0..n).map(|i| q[i]))
    }

    /// Writes the Siconos numerics LCP data file with dense storage (see the module
    /// documentation of the format), M one column per line.
    ///
    /// # Errors
    /// Any error of the writer.
    pub fn write_siconos<W: Write>(&self, mut w: W) -> std::io::Result<()> {
        let (m, q, n) = (self.m(), self.q(), self.n());
        writeln!(w, "{n}")?;
        let column_major: Vec<f64> = (0..n * n).map(|k| m[(k % n, k / n)]).collect();
        numerics::write_dense(&mut w, n, n, &column_major)?;
        write_numbers(&mut w, (0..n).map(|i| q[i]))
    }

    /// Reads the plain format.
    ///
    /// # Errors
    /// [`LcpError::Io`], [`LcpError::Parse`] with the line number,
    /// [`LcpError::TrailingData`] for data after q, or a validation error of [`Lcp::new`].
    pub fn read_plain<R: Read>(mut r: R) -> Result<Lcp, LcpError> {
        let mut text = String::new();
        r.read_to_string(&mut text)?;
        parse_plain(&text)
    }

    /// Reads a Siconos numerics LCP data file (dense, sparse block or sparse storage).
    ///
    /// # Errors
    /// [`LcpError::Io`], [`LcpError::Parse`], [`LcpError::UnsupportedStorage`] for an
    /// unknown storage type, [`LcpError::NotSquare`], [`LcpError::TrailingData`] (with the
    /// line) for a number after q (a comment may follow it), or a validation error of
    /// [`Lcp::new`].
    pub fn read_siconos<R: Read>(mut r: R) -> Result<Lcp, LcpError> {
        let mut text = String::new();
        r.read_to_string(&mut text)?;
        parse_siconos(&text)
    }

    /// Reads either format: the text is parsed as plain and as Siconos; a text that is
    /// valid plain (exactly n, n^2 and n numbers, nothing after) is plain, else a valid
    /// Siconos text is Siconos.
    ///
    /// # Errors
    /// When the text has the plain layout but its data fail validation ([`Lcp::new`]: a
    /// non-finite entry or one out of range) and it is no Siconos file either, that
    /// validation error, since the format was recognised; otherwise
    /// [`LcpError::UnknownFormat`] with the reason of each format when neither parses.
    pub fn read_any(text: &str) -> Result<Lcp, LcpError> {
        let plain = match parse_plain(text) {
            Ok(lcp) => return Ok(lcp),
            Err(e) => e,
        };
        parse_siconos(text).map_err(|siconos| match plain {
            LcpError::NonFinite { .. } | LcpError::OutOfRange { .. } => plain,
            _ => LcpError::UnknownFormat { plain: Box::new(plain), siconos: Box::new(siconos) },
        })
    }
}
