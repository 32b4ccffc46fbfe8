//! Parameter grids for sweeps: `--set key=v1,v2` options, their Cartesian product, shards,
//! and merging the CSV parts of a sharded sweep.

use std::collections::BTreeSet;
use std::io::IsTerminal;
use std::path::Path;
use std::sync::Mutex;

use anyhow::{Context, Result, bail, ensure};

/// One swept parameter: a scene key and the values it takes (as written on the command line).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Axis {
    /// Scene key, e.g. `eps_n`.
    pub key: String,
    /// Values, e.g. `["0.1", "0.4"]`.
    pub values: Vec<String>,
}

impl Axis {
    /// Parses `key=v1,v2,...`.
    ///
    /// # Errors
    /// When there is no `=`, the key is empty or a value is empty.
    pub fn parse(text: &str) -> Result<Self> {
        let Some((key, values)) = text.split_once('=') else {
            bail!("expected key=value[,value...], got '{text}'");
        };
        let key = key.trim();
        ensure!(!key.is_empty(), "empty key in '{text}'");
        let values: Vec<String> = values.split(',').map(|v| v.trim().to_owned()).collect();
        ensure!(values.iter().all(|v| !v.is_empty()), "empty value in '{text}'");
        Ok(Self { key: key.to_owned(), values })
    }
}

/// The members of the Cartesian product of `axes`, first axis outermost: member i assigns
/// one value to every key.
pub fn product(axes: &[Axis]) -> Vec<Vec<(String, String)>> {
    let mut members: Vec<Vec<(String, String)>> = vec![Vec::new()];
    for axis in axes {
        members = members
            .into_iter()
            .flat_map(|m| {
                axis.values.iter().map(move |v| {
                    let mut m = m.clone();
                    m.push((axis.key.clone(), v.clone()));
                    m
                })
            })
            .collect();
    }
    members
}

/// Part K of N of a sharded sweep (K is 1-based).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which part, 1..=N.
    pub k: usize,
    /// Number of parts.
    pub n: usize,
}

impl Shard {
    /// Parses `K/N` with 1 ≤ K ≤ N.
    ///
    /// # Errors
    /// When the text is not of that form.
    pub fn parse(text: &str) -> Result<Self> {
        let (k, n) = text.split_once('/').with_context(|| format!("expected K/N, got '{text}'"))?;
        let k: usize = k.trim().parse().with_context(|| format!("shard K in '{text}'"))?;
        let n: usize = n.trim().parse().with_context(|| format!("shard N in '{text}'"))?;
        ensure!(n >= 1 && (1..=n).contains(&k), "shard '{text}' needs 1 <= K <= N");
        Ok(Self { k, n })
    }

    /// Whether member `i` belongs to this part (interleaved: i mod N = K − 1).
    pub fn contains(&self, i: usize) -> bool {
        i % self.n == self.k - 1
    }
}

/// Joins the CSV parts of a sharded sweep into `out`, sorted by member index.
///
/// The first column must be `member` and the second `members` (the sweep's size). Checks
/// that all headers agree, that no member appears twice and that none is missing.
///
/// # Errors
/// On unreadable files, disagreeing headers, duplicated or missing members.
pub fn merge(out: &Path, parts: &[impl AsRef<Path>]) -> Result<usize> {
    ensure!(!parts.is_empty(), "merge needs at least one part");
    let mut header: Option<csv::StringRecord> = None;
    let mut rows: Vec<(usize, csv::StringRecord)> = Vec::new();
    let mut size: Option<usize> = None;
    for part in parts {
        let part = part.as_ref();
        let mut r =
            csv::Reader::from_path(part).with_context(|| format!("reading {}", part.display()))?;
        let h = r.headers()?.clone();
        ensure!(
            h.get(0) == Some("member") && h.get(1) == Some("members"),
            "{}: the first columns must be 'member,members'",
            part.display()
        );
        match &header {
            None => header = Some(h),
            Some(first) => ensure!(
                *first == h,
                "{}: header differs from the first part's\n  first: {}\n  this:  {}",
                part.display(),
                first.iter().collect::<Vec<_>>().join(","),
                h.iter().collect::<Vec<_>>().join(",")
            ),
        }
        for record in r.records() {
            let record = record.with_context(|| format!("reading {}", part.display()))?;
            let i: usize = record[0]
                .parse()
                .with_context(|| format!("{}: member '{}'", part.display(), &record[0]))?;
            let m: usize = record[1]
                .parse()
                .with_context(|| format!("{}: members '{}'", part.display(), &record[1]))?;
            match size {
                None => size = Some(m),
                Some(s) => ensure!(s == m, "{}: sweep size {m} differs from {s}", part.display()),
            }
            rows.push((i, record));
        }
    }
    rows.sort_by_key(|(i, _)| *i);
    let mut seen = BTreeSet::new();
    for (i, _) in &rows {
        ensure!(seen.insert(*i), "member {i} appears more than once");
    }
    let size = size.unwrap_or(0);
    let missing: Vec<usize> = (0..size).filter(|i| !seen.contains(i)).collect();
    ensure!(missing.is_empty(), "members missing from the parts: {missing:?}");
    ensure!(
        rows.last().is_none_or(|(i, _)| *i < size),
        "member index beyond the sweep size {size}"
    );
    let mut w =
        csv::Writer::from_path(out).with_context(|| format!("creating {}", out.display()))?;
    if let Some(h) = &header {
        w.write_record(h)?;
    }
    for (_, record) in &rows {
        w.write_record(record)?;
    }
    w.flush()?;
    Ok(rows.len())
}

/// Progress of a batch of runs: a bar on a terminal, plain lines otherwise.
pub struct Progress {
    bar: Option<indicatif::ProgressBar>,
    done: Mutex<usize>,
    total: usize,
    what: String,
}

impl Progress {
    /// Progress over `total` items described as `what`.
    pub fn new(total: usize, what: &str) -> Self {
        let bar = std::io::stderr().is_terminal().then(|| {
            let bar = indicatif::ProgressBar::new(total as u64);
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{msg} [{bar:40}] {pos}/{len} ({elapsed}, eta {eta})",
            ) {
                bar.set_style(style.progress_chars("=> "));
            }
            bar.set_message(what.to_owned());
            bar
        });
        Self { bar, done: Mutex::new(0), total, what: what.to_owned() }
    }

    /// Marks one item done, with a short note.
    pub fn tick(&self, note: &str) {
        let mut done = self.done.lock().unwrap_or_else(|e| e.into_inner());
        *done += 1;
        match &self.bar {
            Some(bar) => bar.inc(1),
            None => eprintln!("{}: {}/{} done ({note})", self.what, *done, self.total),
        }
    }

    /// Ends the progress display.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_and_product() -> Result<()> {
        let a = Axis::parse("eps_n=0.1, 0.4")?;
        assert_eq!(a.values, vec!["0.1", "0.4"]);
        let b = Axis::parse("dt=1e-3,1e-4,1e-5")?;
        let p = product(&[a, b]);
        assert_eq!(p.len(), 6);
        assert_eq!(p[0], vec![("eps_n".into(), "0.1".into()), ("dt".into(), "1e-3".into())]);
        assert_eq!(p[5], vec![("eps_n".into(), "0.4".into()), ("dt".into(), "1e-5".into())]);
        assert!(Axis::parse("eps_n").is_err());
        assert!(Axis::parse("=1").is_err());
        assert!(Axis::parse("x=1,,2").is_err());
        assert_eq!(product(&[]).len(), 1);
        Ok(())
    }

    #[test]
    fn shards_partition_the_members() -> Result<()> {
        let shards: Vec<Shard> =
            (1..=3).map(|k| Shard::parse(&format!("{k}/3"))).collect::<Result<_>>()?;
        for i in 0..20 {
            assert_eq!(shards.iter().filter(|s| s.contains(i)).count(), 1);
        }
        assert!(Shard::parse("0/3").is_err());
        assert!(Shard::parse("4/3").is_err());
        assert!(Shard::parse("1-3").is_err());
        Ok(())
    }

    fn write(path: &Path, text: &str) -> Result<()> {
        std::fs::write(path, text)?;
        Ok(())
    }

    #[test]
    fn merge_sorts_and_checks() -> Result<()> {
        let dir = tempfile::tempdir()?;
        let p1 = dir.path().join("p1.csv");
        let p2 = dir.path().join("p2.csv");
        write(&p1, "member,members,x\n0,3,a\n2,3,c\n")?;
        write(&p2, "member,members,x\n1,3,b\n")?;
        let out = dir.path().join("all.csv");
        assert_eq!(merge(&out, &[&p1, &p2])?, 3);
        assert_eq!(std::fs::read_to_string(&out)?, "member,members,x\n0,3,a\n1,3,b\n2,3,c\n");
        // Missing member.
        let e = merge(&out, &[&p1]).unwrap_err().to_string();
        assert!(e.contains("missing"), "{e}");
        // Duplicate member.
        let e = merge(&out, &[&p1, &p2, &p2]).unwrap_err().to_string();
        assert!(e.contains("more than once"), "{e}");
        // Header mismatch.
        let p3 = dir.path().join("p3.csv");
        write(&p3, "member,members,y\n1,3,b\n")?;
        let e = merge(&out, &[&p1, &p3]).unwrap_err().to_string();
        assert!(e.contains("header"), "{e}");
        Ok(())
    }
}
