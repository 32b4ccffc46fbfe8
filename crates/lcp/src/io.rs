//! Text formats: plain and Siconos numerics' LCP data file.
//!
//! **Plain** (whitespace-separated, `#` starts a comment that runs to the end of the
//! line): n, then M row by row (n^2 numbers), then q (n numbers). Nothing else may follow.
//!
//! **Siconos** (the format of `linearComplementarity_newFromFile` /
//! `linearComplementarity_printInFile` of Siconos numerics, via `NM_new_from_file` /
//! `NM_write_in_file` for the matrix):
//!
//! ```text
//! n
//! storage            (0 = dense; 1 = sparse block and 2 = sparse are not supported)
//! rows
//! columns
//! rows columns       (dense storage repeats the two sizes on one line)
//! M column by column (n^2 numbers: Siconos stores dense matrices column-major and
//!                     writes one column per line)
//! q                  (n numbers)
//! anything else      (a free-text comment, ignored)
//! ```
use std::io::{Read, Write};

use crate::{Lcp, LcpError};

/// Splits text into whitespace-separated tokens with 1-based line numbers.
struct Tokens<'a> {
    lines: std::iter::Enumerate<std::str::Lines<'a>>,
    current: std::str::SplitWhitespace<'a>,
    line: usize,
    comments: bool,
}

impl<'a> Tokens<'a> {
    fn new(text: &'a str, comments: bool) -> Self {
        Tokens {
            lines: text.lines().enumerate(),
            current: "".split_whitespace(),
            line: 0,
            comments,
        }
    }

    fn next_token(&mut self) -> Option<(usize, &'a str)> {
        loop {
            if let Some(t) = self.current.next() {
                return Some((self.line, t));
            }
            let (i, line) = self.lines.next()?;
            self.line = i + 1;
            let line = if self.comments { line.split('#').next().unwrap_or("") } else { line };
            self.current = line.split_whitespace();
        }
    }

    fn number(&mut self, what: &str) -> Result<f64, LcpError> {
        let (line, t) = self.next_token().ok_or_else(|| LcpError::Parse {
            line: self.line,
            message: format!("unexpected end of input, expected {what}"),
        })?;
        t.parse::<f64>().map_err(|_| LcpError::Parse {
            line,
            message: format!("expected a number for {what}, found '{t}'"),
        })
    }

    fn integer(&mut self, what: &str) -> Result<(usize, i64), LcpError> {
        let (line, t) = self.next_token().ok_or_else(|| LcpError::Parse {
            line: self.line,
            message: format!("unexpected end of input, expected {what}"),
        })?;
        let v = t.parse::<i64>().map_err(|_| LcpError::Parse {
            line,
            message: format!("expected an integer for {what}, found '{t}'"),
        })?;
        Ok((line, v))
    }

    fn size(&mut self, what: &str) -> Result<usize, LcpError> {
        let (line, v) = self.integer(what)?;
        if v < 1 {
            return Err(LcpError::Parse {
                line,
                message: format!("{what} must be >= 1, found {v}"),
            });
        }
        usize::try_from(v)
            .map_err(|_| LcpError::Parse { line, message: format!("{what} too large") })
    }
}

/// Refuses sizes whose n^2 entries could not possibly be in the text (guards allocation).
fn check_size(n: usize, text: &str, line: usize) -> Result<(), LcpError> {
    let needed = n.checked_mul(n).and_then(|m| m.checked_add(n));
    match needed {
        Some(k) if k <= text.len() => Ok(()),
        _ => Err(LcpError::Parse {
            line,
            message: format!("n = {n} is larger than the input allows"),
        }),
    }
}

fn parse_plain(text: &str) -> Result<Lcp, LcpError> {
    let mut t = Tokens::new(text, true);
    let n = t.size("the size n")?;
    check_size(n, text, t.line)?;
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            m[i + j * n] = t.number("an entry of M")?;
        }
    }
    let q = (0..n).map(|_| t.number("an entry of q")).collect::<Result<Vec<f64>, _>>()?;
    if let Some((line, tok)) = t.next_token() {
        return Err(LcpError::Parse {
            line,
            message: format!("unexpected data '{tok}' after q (plain format ends with q)"),
        });
    }
    Lcp::from_column_major(n, &m, &q)
}

fn parse_siconos(text: &str) -> Result<Lcp, LcpError> {
    let mut t = Tokens::new(text, false);
    let n = t.size("the size n")?;
    let (_, storage) = t.integer("the storage type")?;
    if storage != 0 {
        return Err(LcpError::UnsupportedStorage { storage });
    }
    let rows = t.size("the number of rows")?;
    let cols = t.size("the number of columns")?;
    let rows2 = t.size("the number of rows (dense header)")?;
    let cols2 = t.size("the number of columns (dense header)")?;
    if rows != rows2 || cols != cols2 {
        return Err(LcpError::Parse {
            line: t.line,
            message: format!("dense header {rows2} x {cols2} disagrees with sizes {rows} x {cols}"),
        });
    }
    if rows != cols {
        return Err(LcpError::NotSquare { rows, cols });
    }
    if rows != n {
        return Err(LcpError::DimensionMismatch {
            what: "Siconos matrix size",
            expected: n,
            found: rows,
        });
    }
    check_size(n, text, t.line)?;
    let m = (0..n * n).map(|_| t.number("an entry of M")).collect::<Result<Vec<f64>, _>>()?;
    let q = (0..n).map(|_| t.number("an entry of q")).collect::<Result<Vec<f64>, _>>()?;
    Lcp::from_column_major(n, &m, &q)
}

/// `true` when the text starts like a Siconos file: n, a storage type, then n n (and, for
/// dense storage, n n again).
fn looks_like_siconos(text: &str) -> bool {
    let tok: Vec<&str> = text.split_whitespace().take(6).collect();
    let int = |i: usize| tok.get(i).and_then(|t| t.parse::<i64>().ok());
    let Some(n) = int(0) else { return false };
    match int(1) {
        Some(0) => (2..6).all(|i| int(i) == Some(n)),
        Some(1 | 2) => int(2) == Some(n) && int(3) == Some(n),
        _ => false,
    }
}

fn write_numbers<W: Write>(w: &mut W, values: impl Iterator<Item = f64>) -> std::io::Result<()> {
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
        writeln!(w, "{n}\n0\n{n}\n{n}\n{n}\t{n}")?;
        for j in 0..n {
            write_numbers(&mut w, (0..n).map(|i| m[(i, j)]))?;
        }
        write_numbers(&mut w, (0..n).map(|i| q[i]))
    }

    /// Reads the plain format.
    ///
    /// # Errors
    /// [`LcpError::Io`], [`LcpError::Parse`] with the line number, or a validation error
    /// of [`Lcp::new`].
    pub fn read_plain<R: Read>(mut r: R) -> Result<Lcp, LcpError> {
        let mut text = String::new();
        r.read_to_string(&mut text)?;
        parse_plain(&text)
    }

    /// Reads a Siconos numerics LCP data file (dense storage only).
    ///
    /// # Errors
    /// [`LcpError::Io`], [`LcpError::Parse`], [`LcpError::UnsupportedStorage`] for sparse
    /// storage, or a validation error of [`Lcp::new`].
    pub fn read_siconos<R: Read>(mut r: R) -> Result<Lcp, LcpError> {
        let mut text = String::new();
        r.read_to_string(&mut text)?;
        parse_siconos(&text)
    }

    /// Reads either format, detecting which: text with exactly 1 + n + n^2 numbers
    /// (comments aside) is plain; text that starts `n storage n n` is Siconos; anything
    /// else is parsed as plain (and its error reported).
    ///
    /// # Errors
    /// As [`Lcp::read_plain`] or [`Lcp::read_siconos`].
    pub fn read_any(text: &str) -> Result<Lcp, LcpError> {
        let plain_count = {
            let mut t = Tokens::new(text, true);
            let mut count = 0usize;
            while t.next_token().is_some() {
                count += 1;
            }
            count
        };
        let first = text.split_whitespace().next().and_then(|t| t.parse::<usize>().ok());
        let is_plain_count = first
            .and_then(|n| n.checked_mul(n).and_then(|m| m.checked_add(n + 1)))
            .is_some_and(|k| k == plain_count);
        if !is_plain_count && looks_like_siconos(text) {
            parse_siconos(text)
        } else {
            parse_plain(text)
        }
    }
}
