//! Column tables of numbers written as CSV (header row first) and as Markdown.

use std::path::Path;

use anyhow::{Context, Result, bail};

/// Named numeric columns, possibly of different lengths (short columns are padded with
/// empty cells when written).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    columns: Vec<(String, Vec<f64>)>,
}

impl Table {
    /// Appends a column.
    pub fn push_column(&mut self, name: &str, values: Vec<f64>) {
        self.columns.push((name.to_owned(), values));
    }

    /// Whether a column of that name exists.
    pub fn has_column(&self, name: &str) -> bool {
        self.columns.iter().any(|(n, _)| n == name)
    }

    /// Column names in order.
    pub fn headers(&self) -> Vec<&str> {
        self.columns.iter().map(|(n, _)| n.as_str()).collect()
    }

    /// Number of rows (the length of the longest column).
    pub fn rows(&self) -> usize {
        self.columns.iter().map(|(_, v)| v.len()).max().unwrap_or(0)
    }

    /// The column called `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_slice())
    }

    /// Writes the table as CSV with the header row first; numbers are written as
    /// [`crate::number`] writes them (the shortest text that reads back exactly), so the file
    /// is the same on every run.
    ///
    /// # Errors
    /// When the file cannot be written.
    pub fn write_csv(&self, path: &Path) -> Result<()> {
        let mut w =
            csv::Writer::from_path(path).with_context(|| format!("creating {}", path.display()))?;
        w.write_record(self.headers())?;
        for r in 0..self.rows() {
            w.write_record(
                self.columns
                    .iter()
                    .map(|(_, v)| v.get(r).map_or(String::new(), |&x| crate::number::text(x))),
            )?;
        }
        w.flush()?;
        Ok(())
    }

    /// Reads a CSV written by [`Self::write_csv`] (empty cells end a column).
    ///
    /// # Errors
    /// When the file cannot be read or a cell is not a number.
    pub fn read_csv(path: &Path) -> Result<Self> {
        let mut r =
            csv::Reader::from_path(path).with_context(|| format!("reading {}", path.display()))?;
        let headers: Vec<String> = r.headers()?.iter().map(str::to_owned).collect();
        let mut columns: Vec<(String, Vec<f64>)> =
            headers.into_iter().map(|h| (h, Vec::new())).collect();
        for (line, record) in r.records().enumerate() {
            let record = record?;
            for (c, cell) in record.iter().enumerate() {
                if cell.is_empty() {
                    continue;
                }
                let Some(col) = columns.get_mut(c) else {
                    bail!("row {} has too many cells", line + 2)
                };
                col.1.push(
                    cell.parse()
                        .with_context(|| format!("row {} column {}: '{cell}'", line + 2, c + 1))?,
                );
            }
        }
        Ok(Self { columns })
    }

    /// The table as a Markdown table, each number formatted by `format`.
    pub fn to_markdown(&self, format: impl Fn(usize, f64) -> String) -> String {
        let mut s = String::new();
        s.push_str(&format!("| {} |\n", self.headers().join(" | ")));
        s.push_str(&format!("|{}\n", "---:|".repeat(self.columns.len())));
        for r in 0..self.rows() {
            let cells: Vec<String> = self
                .columns
                .iter()
                .enumerate()
                .map(|(c, (_, v))| v.get(r).map_or(String::new(), |x| format(c, *x)))
                .collect();
            s.push_str(&format!("| {} |\n", cells.join(" | ")));
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_round_trip_with_ragged_columns() -> Result<()> {
        let dir = tempfile::tempdir()?;
        let mut t = Table::default();
        t.push_column("t", vec![0.0, 0.1, 0.2]);
        t.push_column("y", vec![1.0, -2.5e-7]);
        let path = dir.path().join("t.csv");
        t.write_csv(&path)?;
        let text = std::fs::read_to_string(&path)?;
        assert_eq!(text, "t,y\n0,1\n0.1,-2.5e-7\n0.2,\n");
        assert_eq!(Table::read_csv(&path)?, t);
        Ok(())
    }

    #[test]
    fn markdown_has_a_row_per_entry() {
        let mut t = Table::default();
        t.push_column("a", vec![1.0, 2.0]);
        let md = t.to_markdown(|_, x| format!("{x:.1}"));
        assert_eq!(md, "| a |\n|---:|\n| 1.0 |\n| 2.0 |\n");
    }
}
