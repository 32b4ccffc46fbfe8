//! Numbers in the CSV files the command writes: each `f64` in the shortest text that reads
//! back as the same number, with an exponent when that is shorter.
//!
//! A number of magnitude in [10⁻³, 10¹⁵), and 0, is written in decimal notation as Rust writes
//! it (`0`, negative zero too, `0.001`, `1`, `0.4285`, `123456`: integers without `.0`); any other is written in
//! decimal or in scientific notation (`-1e-33`, `2.5e-7`, `1e300`), whichever is shorter, the
//! decimal one on a tie. Both are Rust's shortest round-trip digits, so every cell reads back
//! exactly, negative zero as zero (`str::parse::<f64>`, and any CSV reader that takes `1e-33`); the non-finite
//! values are written `NaN`, `inf` and `-inf`. Every CSV writer of the command uses this
//! module: the records of `simulate`, its contacts file, the key numbers of a sweep, the
//! solution of `solve`, and [`crate::table::Table`].

use std::fmt::Write as _;

/// The magnitudes written in decimal notation whatever its length: [10⁻³, 10¹⁵).
const DECIMAL: std::ops::Range<f64> = 1e-3..1e15;

/// Room for the scientific form of any `f64` (`-2.2250738585072014e-308` has 24 bytes).
const SCI_BYTES: usize = 32;

/// The scientific form of a number, kept on the stack.
struct Sci {
    bytes: [u8; SCI_BYTES],
    len: usize,
}

impl std::fmt::Write for Sci {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        let end = self.len + s.len();
        self.bytes.get_mut(self.len..end).ok_or(std::fmt::Error)?.copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

impl Sci {
    /// `x` as Rust's `{:e}` writes it (shortest round-trip digits), when it fits.
    fn of(x: f64) -> Option<Self> {
        let mut sci = Self { bytes: [0; SCI_BYTES], len: 0 };
        write!(sci, "{x:e}").ok()?;
        Some(sci)
    }

    fn as_str(&self) -> &str {
        std::str::from_utf8(&self.bytes[..self.len]).unwrap_or_default()
    }
}

/// The length of the decimal form (`{}`) of the number whose scientific form (`{:e}`) is
/// `sci`: the same digits, placed by the exponent.
fn decimal_len(sci: &str) -> Option<usize> {
    let (sign, unsigned) = match sci.strip_prefix('-') {
        Some(rest) => (1, rest),
        None => (0, sci),
    };
    let (mantissa, exponent) = unsigned.split_once('e')?;
    let exponent: i64 = exponent.parse().ok()?;
    let digits = mantissa.bytes().filter(u8::is_ascii_digit).count() as i64;
    let len = if exponent >= 0 {
        // The digits with zeros up to the units, and a point when digits remain after them.
        let whole = exponent + 1;
        digits.max(whole) + i64::from(digits > whole)
    } else {
        // "0." and −exponent − 1 zeros before the digits.
        2 + (-exponent - 1) + digits
    };
    usize::try_from(sign + len).ok()
}

/// Writes `x` as the module describes.
///
/// # Errors
/// Those of the writer.
pub fn write(w: &mut impl std::io::Write, x: f64) -> std::io::Result<()> {
    if x == 0.0 {
        // Negative zero as well: a cell that reads back as zero is written `0`.
        return w.write_all(b"0");
    }
    if !x.is_finite() || DECIMAL.contains(&x.abs()) {
        return write!(w, "{x}");
    }
    match Sci::of(x) {
        Some(sci) if decimal_len(sci.as_str()).is_some_and(|decimal| sci.len < decimal) => {
            w.write_all(sci.as_str().as_bytes())
        }
        _ => write!(w, "{x}"),
    }
}

/// Writes a comma and `x` ([`write()`]): the next cell of a record.
///
/// # Errors
/// Those of the writer.
pub fn write_next(w: &mut impl std::io::Write, x: f64) -> std::io::Result<()> {
    w.write_all(b",")?;
    write(w, x)
}

/// `x` as the module describes.
pub fn text(x: f64) -> String {
    let mut bytes = Vec::new();
    // Writing to memory does not fail.
    let _ = write(&mut bytes, x);
    String::from_utf8(bytes).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_and_large_numbers_take_an_exponent_and_others_are_as_before() {
        let cases = [
            (0.0, "0"),
            (-0.0, "0"),
            (1.0, "1"),
            (0.001, "0.001"),
            (-0.001, "-0.001"),
            (0.4285, "0.4285"),
            (123456.0, "123456"),
            (1e14, "100000000000000"),
            (-1e-33, "-1e-33"),
            (1e300, "1e300"),
            (2.5e-7, "2.5e-7"),
            (0.0001, "1e-4"),
            (0.000123456789, "1.23456789e-4"),
            (1e15, "1e15"),
            (1234567890123456.0, "1234567890123456"),
            (f64::MIN_POSITIVE, "2.2250738585072014e-308"),
            (-f64::MAX, "-1.7976931348623157e308"),
            (5e-324, "5e-324"),
            (f64::NAN, "NaN"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
        ];
        for (x, expected) in cases {
            assert_eq!(text(x), expected, "{x:e}");
        }
    }

    #[test]
    fn every_number_reads_back_exactly_in_the_shorter_form() {
        // Numbers of every magnitude, from a fixed sequence of bit patterns.
        let mut bits: u64 = 0x9e37_79b9_7f4a_7c15;
        for _ in 0..100_000 {
            bits = bits
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            let x = f64::from_bits(bits);
            if !x.is_finite() {
                continue;
            }
            let written = text(x);
            assert_eq!(written.parse::<f64>().map(f64::to_bits), Ok(x.to_bits()), "{written}");
            let (decimal, sci) = (format!("{x}"), format!("{x:e}"));
            assert_eq!(decimal_len(&sci), Some(decimal.len()), "{sci}");
            assert!(written.len() <= decimal.len(), "{written}");
            if !DECIMAL.contains(&x.abs()) {
                assert_eq!(written.len(), decimal.len().min(sci.len()), "{written}");
            }
        }
    }
}
