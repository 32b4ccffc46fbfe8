//! The file format of sweep parts, reading them back (for `--resume`), and merging them.
//!
//! A part is a CSV file whose first line is a comment naming the sweep it belongs to, and
//! whose rows each end with a check of their cells:
//!
//! ```text
//! # moreau sweep 1; id 5c0f9a1e33b2d807; model ball; members 6; shard 2/4; moreau 0.1.0
//! member,members,eps_n,dt,...,steps,lcp_solves,inexact_steps,wall_seconds,status,error,check
//! 1,6,0.5,0.002,...,2000,1390,0.0123,ok,,3f2a19c0
//! ```
//!
//! The id is a hash of everything that decides the sweep's numbers: the model, the base scene
//! (all of its entries), the swept keys and their values, the step limit and the program's
//! version. Parts of one sweep share it; [`merge`] refuses parts of different sweeps, parts
//! that lack members of their shard, sets of parts that lack members, and rows that are cut
//! off or altered (their check fails), each time naming the part and the members. Reading the
//! file with pandas needs `comment='#'`.

use std::collections::BTreeSet;
use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use crate::error::CliError;
use crate::grid::Shard;
use crate::output::{self, Output, OutputLock};
use crate::sweep::SweepSummary;

/// Version of the part format; part of the identity line.
pub const FORMAT: u32 = 1;

/// The status of a member: `ok`, `diverged` (the divergence guard stopped it) or `failed`.
pub const STATUSES: [&str; 3] = ["ok", "diverged", "failed"];

/// 64-bit FNV-1a hash.
pub fn fnv64(bytes: &[u8]) -> u64 {
    bytes
        .iter()
        .fold(0xcbf2_9ce4_8422_2325, |h, &b| (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3))
}

/// The check of a row: 32 bits of the hash of its cells, as 8 hex digits.
pub fn row_check<S: AsRef<str>>(cells: &[S]) -> String {
    let mut text = Vec::new();
    for c in cells {
        text.extend_from_slice(c.as_ref().as_bytes());
        text.push(0x1f);
    }
    format!("{:08x}", fnv64(&text) as u32)
}

/// The identity line of a part.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PartHeader {
    /// The sweep's id (16 hex digits).
    pub id: String,
    /// The model's name.
    pub model: String,
    /// The sweep's number of members.
    pub members: u64,
    /// The part of the sweep this file holds.
    pub shard: Shard,
    /// The version of the program that wrote it.
    pub version: String,
}

impl PartHeader {
    /// The comment line (without the newline).
    pub fn line(&self) -> String {
        format!(
            "# moreau sweep {FORMAT}; id {}; model {}; members {}; shard {}/{}; moreau {}",
            self.id, self.model, self.members, self.shard.k, self.shard.n, self.version
        )
    }

    /// Parses the comment line.
    ///
    /// # Errors
    /// When it is not one.
    pub fn parse(line: &str) -> Result<Self, String> {
        let rest = line.strip_prefix(&format!("# moreau sweep {FORMAT}; ")).ok_or(
            "its first line does not name a sweep (is it a part written by `moreau sweep`?)",
        )?;
        let mut fields = std::collections::BTreeMap::new();
        for f in rest.split("; ") {
            let (k, v) = f.split_once(' ').ok_or_else(|| format!("bad identity field '{f}'"))?;
            fields.insert(k, v);
        }
        let get = |k: &str| fields.get(k).copied().ok_or_else(|| format!("identity lacks {k}"));
        Ok(Self {
            id: get("id")?.to_owned(),
            model: get("model")?.to_owned(),
            members: get("members")?.parse().map_err(|_| "bad member count".to_owned())?,
            shard: {
                let shard = get("shard")?;
                Shard::parse(shard)
                    .map_err(|_| format!("bad shard '{shard}' (K/N with 1 <= K <= N)"))?
            },
            version: get("moreau")?.to_owned(),
        })
    }

    /// The same sweep (id, model, size and version) as `other`, whatever the shard.
    pub fn same_sweep(&self, other: &Self) -> bool {
        (&self.id, &self.model, self.members, &self.version)
            == (&other.id, &other.model, other.members, &other.version)
    }
}

/// A part read back: its identity, column names and rows (member index, cells).
#[derive(Clone, Debug)]
pub struct Part {
    /// Where it was read from.
    pub path: PathBuf,
    /// The identity line.
    pub header: PartHeader,
    /// The column names.
    pub columns: Vec<String>,
    /// The rows in file order: member index and all cells.
    pub rows: Vec<(u64, Vec<String>)>,
    /// Whether a damaged last line was dropped (only with `drop_damaged_tail`).
    pub dropped_tail: bool,
}

/// Reads a part, checking every row: its number of cells, its check, its member index (which
/// must belong to the part's shard), its sweep size and its status. With `drop_damaged_tail`,
/// a damaged last line (a run cut off while writing it) is dropped instead of refused.
///
/// # Errors
/// [`CliError::MixedParts`] for a file that is not a part; [`CliError::DamagedPart`] naming
/// the line; an unreadable file.
pub fn read_part(path: &Path, drop_damaged_tail: bool) -> Result<Part> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mixed = |reason: String| CliError::MixedParts { part: path.to_owned(), reason };
    let (first, body) = text.split_once('\n').unwrap_or((&text, ""));
    // A part whose line ends were made CRLF (by an editor or a transfer) reads as it was.
    let first = first.strip_suffix('\r').unwrap_or(first);
    let header = PartHeader::parse(first).map_err(mixed)?;
    let mut reader = csv::ReaderBuilder::new().flexible(true).from_reader(body.as_bytes());
    let columns: Vec<String> = reader.headers()?.iter().map(str::to_owned).collect();
    if columns.first().map(String::as_str) != Some("member")
        || columns.last().map(String::as_str) != Some("check")
    {
        return Err(mixed("its columns must run from 'member' to 'check'".into()).into());
    }
    let records: Vec<_> = reader.records().collect();
    let ends_cleanly = text.ends_with('\n');
    let mut rows = Vec::new();
    let mut dropped_tail = false;
    let mut seen = BTreeSet::new();
    for (j, record) in records.iter().enumerate() {
        let line = j as u64 + 3;
        let is_last = j + 1 == records.len();
        let problem = match record {
            Err(e) => Some(e.to_string()),
            Ok(r) => check_row(r, &columns, &header, is_last && !ends_cleanly).err(),
        };
        match (problem, record) {
            (None, Ok(r)) => {
                let cells: Vec<String> = r.iter().map(str::to_owned).collect();
                let i: u64 = cells[0].parse().unwrap_or(u64::MAX);
                if !seen.insert(i) {
                    let reason = format!("member {i} appears twice");
                    return Err(
                        CliError::DamagedPart { part: path.to_owned(), line, reason }.into()
                    );
                }
                rows.push((i, cells));
            }
            (Some(_), _) if is_last && drop_damaged_tail => dropped_tail = true,
            (Some(reason), _) => {
                return Err(CliError::DamagedPart { part: path.to_owned(), line, reason }.into());
            }
            (None, Err(_)) => unreachable!("an unreadable record is a problem"),
        }
    }
    Ok(Part { path: path.to_owned(), header, columns, rows, dropped_tail })
}

fn check_row(
    r: &csv::StringRecord,
    columns: &[String],
    header: &PartHeader,
    unterminated: bool,
) -> Result<(), String> {
    if r.len() != columns.len() {
        return Err(format!("{} cells where the header has {}", r.len(), columns.len()));
    }
    let cells: Vec<&str> = r.iter().collect();
    let (check, rest) = cells.split_last().ok_or("empty row")?;
    if row_check(rest) != *check {
        return Err("its check does not match its cells (cut off or altered)".into());
    }
    if unterminated {
        return Err("the file ends inside it".into());
    }
    let i: u64 = cells[0].parse().map_err(|_| format!("member '{}'", cells[0]))?;
    if cells[1] != header.members.to_string() {
        return Err(format!("sweep size {} where the part says {}", cells[1], header.members));
    }
    if i >= header.members || !header.shard.contains(i) {
        return Err(format!(
            "member {i} does not belong to shard {}/{} of {} members",
            header.shard.k, header.shard.n, header.members
        ));
    }
    let status = columns.iter().position(|c| c == "status").ok_or("no status column")?;
    if !STATUSES.contains(&cells[status]) {
        return Err(format!("unknown status '{}'", cells[status]));
    }
    Ok(())
}

/// Writes a part: the identity line, the column names and the rows (in the given order),
/// whole or not at all ([`output::replace_file`]: a part that was there keeps its content when
/// the write fails or is killed).
///
/// # Errors
/// [`CliError::Output`] when the file cannot be written.
pub fn write_part(
    path: &Path,
    header: &PartHeader,
    columns: &[String],
    rows: &[Vec<String>],
) -> Result<()> {
    output::replace_file(path, |w| {
        writeln!(w, "{}", header.line())?;
        let mut csv = csv::Writer::from_writer(w);
        csv.write_record(columns)?;
        for row in rows {
            csv.write_record(row)?;
        }
        csv.flush()?;
        Ok(())
    })?;
    Ok(())
}

/// A short list of member indices: all of them up to 20, else the first 20 and a count.
pub fn list_members(members: &[u64]) -> String {
    list_count(members, members.len() as u64)
}

/// The first members of a list of `count` (at most 20 shown), with the count when some are
/// left out.
fn list_count(first: &[u64], count: u64) -> String {
    let shown: Vec<String> = first.iter().take(20).map(u64::to_string).collect();
    if count > shown.len() as u64 {
        format!("{} ... ({count} in all)", shown.join(", "))
    } else {
        shown.join(", ")
    }
}

/// Joins the parts of a sharded sweep into `out`, sorted by member; returns the number of
/// members.
///
/// Every part must belong to the same sweep (its identity line), have the same columns, hold
/// every member of its shard, and be undamaged; together the parts must hold every member of
/// the sweep once. The merged file is a part of shard 1/1. Lines may end in CRLF. `out` must
/// not be one of the parts nor an existing file other than a regular file (a symbolic link is
/// written through to its file), and is locked (`<out>.lock`) while it is written; see
/// [`output`].
///
/// # Errors
/// [`CliError::MixedParts`], [`CliError::MissingMembers`] or [`CliError::DamagedPart`], naming
/// the part and the members; [`CliError::Output`] for an output that is a part or not a
/// regular file; [`CliError::Locked`] for an output another run holds; unreadable or
/// unwritable files.
pub fn merge(out: &Path, parts: &[impl AsRef<Path>]) -> Result<u64> {
    merge_summary(out, parts).map(|s| s.rows)
}

/// [`merge`], returning the merged file's members counted by status (`ran` 0: a merge runs
/// none), so that the command can end as `sweep` does on the same rows.
///
/// # Errors
/// As [`merge`].
pub fn merge_summary(out: &Path, parts: &[impl AsRef<Path>]) -> Result<SweepSummary> {
    anyhow::ensure!(!parts.is_empty(), "merge needs at least one part");
    let out_file = Output::new(out)?;
    let inputs: Vec<&Path> = parts.iter().map(AsRef::as_ref).collect();
    output::check_distinct(&inputs, &[&out_file])?;
    let _lock = OutputLock::acquire(&out_file)?;
    let mut read: Vec<Part> = Vec::new();
    for p in parts {
        let part = read_part(p.as_ref(), false)?;
        if let Some(first) = read.first() {
            let mixed = |reason: String| CliError::MixedParts { part: part.path.clone(), reason };
            if !part.header.same_sweep(&first.header) {
                return Err(mixed(format!(
                    "belongs to sweep {} ({}, {} members, moreau {}), not to sweep {} ({}, {} \
                     members, moreau {}) of {}",
                    part.header.id,
                    part.header.model,
                    part.header.members,
                    part.header.version,
                    first.header.id,
                    first.header.model,
                    first.header.members,
                    first.header.version,
                    first.path.display()
                ))
                .into());
            }
            if part.columns != first.columns {
                return Err(mixed(format!(
                    "its columns differ from those of {}",
                    first.path.display()
                ))
                .into());
            }
        }
        // Every row belongs to the shard (read_part checks it), so the rows are all there
        // when they are as many as the shard's members; the first missing ones are listed
        // without enumerating a shard of an enormous sweep.
        let shard = part.header.shard;
        let absent = shard.count(part.header.members) - part.rows.len() as u64;
        if absent > 0 {
            let have: BTreeSet<u64> = part.rows.iter().map(|(i, _)| *i).collect();
            let first: Vec<u64> =
                shard.members(part.header.members).filter(|i| !have.contains(i)).take(20).collect();
            let members = format!(
                "{} of its shard {}/{} (an unfinished run: continue it with `moreau sweep \
                 --resume`)",
                list_count(&first, absent),
                shard.k,
                shard.n
            );
            return Err(CliError::MissingMembers { part: part.path.clone(), members }.into());
        }
        read.push(part);
    }
    let first = &read[0];
    let total = first.header.members;
    let mut owner: std::collections::BTreeMap<u64, usize> = std::collections::BTreeMap::new();
    for (p, part) in read.iter().enumerate() {
        for (i, _) in &part.rows {
            if let Some(q) = owner.insert(*i, p) {
                let (this, other) = (&part.path, &read[q].path);
                let same = matches!(
                    (std::fs::canonicalize(this), std::fs::canonicalize(other)),
                    (Ok(a), Ok(b)) if a == b
                );
                let reason = if same {
                    format!("is given twice (also as {}); give each part once", other.display())
                } else {
                    format!("member {i} is also in {}", other.display())
                };
                return Err(CliError::MixedParts { part: part.path.clone(), reason }.into());
            }
        }
    }
    // Every member held is below `total` (read_part checks it): the members missing are
    // counted from the members held, and only the first of them are looked for.
    let absent = total - owner.len() as u64;
    if absent > 0 {
        let first: Vec<u64> = (0..total).filter(|i| !owner.contains_key(i)).take(20).collect();
        let members = format!(
            "{} of {total}: no part holds them (a shard not given?)",
            list_count(&first, absent)
        );
        return Err(CliError::MissingMembers { part: PathBuf::from("the parts"), members }.into());
    }
    let header = PartHeader { shard: Shard::all(), ..first.header.clone() };
    let columns = first.columns.clone();
    let mut rows: Vec<(u64, Vec<String>)> = read.into_iter().flat_map(|p| p.rows).collect();
    rows.sort_by_key(|(i, _)| *i);
    let rows: Vec<Vec<String>> = rows.into_iter().map(|(_, r)| r).collect();
    write_part(out_file.target(), &header, &columns, &rows)?;
    Ok(SweepSummary::of_rows(&columns, &rows, 0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identity_line_round_trip() {
        let h = PartHeader {
            id: "0123456789abcdef".into(),
            model: "ball".into(),
            members: 6,
            shard: Shard { k: 2, n: 4 },
            version: "0.1.0".into(),
        };
        assert_eq!(PartHeader::parse(&h.line()), Ok(h));
        assert!(PartHeader::parse("member,members,x").is_err());
    }

    #[test]
    fn row_check_sees_a_cut_cell() {
        let cells = ["0", "6", "0.123456"];
        assert_ne!(row_check(&cells), row_check(&["0", "6", "0.1234"]));
        assert_eq!(row_check(&cells), row_check(&cells.map(str::to_owned)));
    }
}
