//! [`Rows`]: a table of rows of one width, stored in one contiguous buffer.

use std::fmt;
use std::ops::Index;

use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A table of rows that all have the same width, such as the q of every recorded step.
///
/// The rows lie one after the other in one buffer, so that appending a row costs no
/// allocation of its own and reading them walks memory in order. Row `k` is `rows[k]`, a
/// slice of [`Self::width`] values; [`Self::iter`] goes through the rows in order. It
/// serialises as a sequence of rows, as `Vec<Vec<T>>` does, and reading back rows of
/// different widths is an error.
///
/// ```
/// use moreau_stepper::Rows;
///
/// let mut q = Rows::new(2);
/// q.push(&[0.0, 1.0]);
/// q.push(&[0.5, 0.9]);
/// assert_eq!((q.len(), q.width()), (2, 2));
/// assert_eq!(q[1], [0.5, 0.9]);
/// assert_eq!(q.iter().map(|r| r[0]).sum::<f64>(), 0.5);
/// assert_eq!(q.column(1).collect::<Vec<_>>(), [1.0, 0.9]);
/// assert_eq!(q.last(), Some(&[0.5, 0.9][..]));
/// ```
#[derive(Clone, PartialEq)]
pub struct Rows<T> {
    width: usize,
    len: usize,
    data: Vec<T>,
}

impl<T> Default for Rows<T> {
    fn default() -> Self {
        Self { width: 0, len: 0, data: Vec::new() }
    }
}

impl<T: Copy> Rows<T> {
    /// An empty table of rows of `width` values.
    pub fn new(width: usize) -> Self {
        Self { width, len: 0, data: Vec::new() }
    }

    /// Appends a row.
    ///
    /// # Panics
    /// When `row` is not [`Self::width`] long: rows of one table have one width.
    pub fn push(&mut self, row: &[T]) {
        assert_eq!(
            row.len(),
            self.width,
            "a row of {} values in a table of width {}",
            row.len(),
            self.width
        );
        self.data.extend_from_slice(row);
        self.len += 1;
    }

    /// Reserves room for `additional` more rows.
    pub fn reserve(&mut self, additional: usize) {
        self.data.reserve(additional.saturating_mul(self.width));
    }
}

impl<T> Rows<T> {
    /// The number of values in each row.
    pub fn width(&self) -> usize {
        self.width
    }

    /// The number of rows.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether there is no row.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Row `k`, or `None` past the last row.
    pub fn get(&self, k: usize) -> Option<&[T]> {
        (k < self.len).then(|| &self.data[k * self.width..][..self.width])
    }

    /// The first row.
    pub fn first(&self) -> Option<&[T]> {
        self.get(0)
    }

    /// The last row.
    pub fn last(&self) -> Option<&[T]> {
        self.len.checked_sub(1).and_then(|k| self.get(k))
    }

    /// The rows in order.
    pub fn iter(&self) -> RowIter<'_, T> {
        RowIter { rows: self, front: 0, back: self.len }
    }

    /// Entry `j` of every row, in order: the time series of one coordinate or contact.
    ///
    /// # Panics
    /// When `j` is not below [`Self::width`].
    pub fn column(&self, j: usize) -> impl ExactSizeIterator<Item = T> + '_
    where
        T: Copy,
    {
        assert!(j < self.width, "column {j} of a table of width {}", self.width);
        self.iter().map(move |row| row[j])
    }

    /// All values, row after row.
    pub fn as_flat(&self) -> &[T] {
        &self.data
    }
}

impl<T> Index<usize> for Rows<T> {
    type Output = [T];

    /// Row `k`.
    ///
    /// # Panics
    /// When `k` is not below [`Rows::len`].
    fn index(&self, k: usize) -> &[T] {
        self.get(k).unwrap_or_else(|| panic!("row {k} of a table of {} rows", self.len))
    }
}

/// The rows of a [`Rows`] in order (also from the back).
#[derive(Clone, Debug)]
pub struct RowIter<'a, T> {
    rows: &'a Rows<T>,
    front: usize,
    back: usize,
}

impl<'a, T> Iterator for RowIter<'a, T> {
    type Item = &'a [T];

    fn next(&mut self) -> Option<&'a [T]> {
        (self.front < self.back).then(|| {
            self.front += 1;
            &self.rows[self.front - 1]
        })
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        let n = self.back - self.front;
        (n, Some(n))
    }
}

impl<T> DoubleEndedIterator for RowIter<'_, T> {
    fn next_back(&mut self) -> Option<Self::Item> {
        (self.front < self.back).then(|| {
            self.back -= 1;
            &self.rows[self.back]
        })
    }
}

impl<T> ExactSizeIterator for RowIter<'_, T> {}

impl<'a, T> IntoIterator for &'a Rows<T> {
    type Item = &'a [T];
    type IntoIter = RowIter<'a, T>;

    fn into_iter(self) -> RowIter<'a, T> {
        self.iter()
    }
}

impl<T: fmt::Debug> fmt::Debug for Rows<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl<T: Serialize> Serialize for Rows<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(self.iter())
    }
}

impl<'de, T: Deserialize<'de> + Copy> Deserialize<'de> for Rows<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let rows = Vec::<Vec<T>>::deserialize(deserializer)?;
        let mut out = Self::new(rows.first().map_or(0, Vec::len));
        out.reserve(rows.len());
        for (k, row) in rows.iter().enumerate() {
            if row.len() != out.width {
                return Err(D::Error::custom(format!(
                    "row {k} has {} values where row 0 has {}",
                    row.len(),
                    out.width
                )));
            }
            out.push(row);
        }
        Ok(out)
    }
}

impl<T: Copy> FromIterator<Vec<T>> for Rows<T> {
    /// Collects rows.
    ///
    /// # Panics
    /// When the rows do not all have the width of the first.
    fn from_iter<I: IntoIterator<Item = Vec<T>>>(iter: I) -> Self {
        let mut iter = iter.into_iter().peekable();
        let mut out = Self::new(iter.peek().map_or(0, Vec::len));
        for row in iter {
            out.push(&row);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_of_width_zero_are_counted() {
        let mut r: Rows<f64> = Rows::new(0);
        r.push(&[]);
        r.push(&[]);
        assert_eq!((r.len(), r.iter().count(), r.last()), (2, 2, Some(&[][..])));
        assert_eq!(r.get(2), None);
    }

    #[test]
    fn iterates_from_both_ends() {
        let r: Rows<u8> = vec![vec![1, 2], vec![3, 4], vec![5, 6]].into_iter().collect();
        let back: Vec<u8> = r.iter().rev().map(|x| x[0]).collect();
        assert_eq!(back, [5, 3, 1]);
        let mut it = r.iter();
        assert_eq!(
            (it.next(), it.next_back(), it.len()),
            (Some(&[1, 2][..]), Some(&[5, 6][..]), 1)
        );
    }

    #[test]
    fn serialises_as_a_list_of_rows_and_refuses_ragged_ones() {
        let r: Rows<f64> = vec![vec![1.0, 2.5], vec![-3.0, 4.0]].into_iter().collect();
        let json = serde_json::to_string(&r).unwrap();
        assert_eq!(json, "[[1.0,2.5],[-3.0,4.0]]");
        assert_eq!(serde_json::from_str::<Rows<f64>>(&json).unwrap(), r);
        let err = serde_json::from_str::<Rows<f64>>("[[1.0,2.0],[3.0]]").unwrap_err();
        assert!(err.to_string().contains("row 1 has 1 values where row 0 has 2"), "{err}");
        let empty = serde_json::from_str::<Rows<f64>>("[]").unwrap();
        assert_eq!((empty.len(), empty.width()), (0, 0));
    }

    #[test]
    #[should_panic(expected = "a row of 1 values in a table of width 2")]
    fn a_row_of_another_width_is_refused() {
        Rows::new(2).push(&[1.0]);
    }
}
