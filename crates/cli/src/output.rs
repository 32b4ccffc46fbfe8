//! The files a run writes: CSV records.

/// One CSV record, quoted as the `csv` crate quotes (a field that holds a comma, a double
/// quote or a line end is put in double quotes, its double quotes doubled), without its line
/// end.
///
/// # Errors
/// None in practice: the record is written to memory.
pub fn csv_record<I, S>(fields: I) -> csv::Result<String>
where
    I: IntoIterator<Item = S>,
    S: AsRef<[u8]>,
{
    let mut w =
        csv::WriterBuilder::new().terminator(csv::Terminator::Any(b'\n')).from_writer(Vec::new());
    w.write_record(fields)?;
    let mut bytes = w.into_inner().map_err(|e| csv::Error::from(e.into_error()))?;
    if bytes.last() == Some(&b'\n') {
        bytes.pop();
    }
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_is_quoted_as_the_csv_crate_quotes() -> csv::Result<()> {
        assert_eq!(csv_record(["t", "flo,or.x", "b\"x.y"])?, "t,\"flo,or.x\",\"b\"\"x.y\"");
        assert_eq!(csv_record(["plain"])?, "plain");
        Ok(())
    }
}
