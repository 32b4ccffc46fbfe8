//! Parameter grids for sweeps: `--set key=v1,v2` options (`--set +key=w1,w2` taking its
//! values with the axis before) and the members listed in a file (`--members FILE`), their
//! Cartesian product enumerated lazily, shards, and the progress display of a batch of runs.

use std::io::IsTerminal;
use std::sync::Mutex;

use anyhow::{Context, Result};

use crate::error::CliError;

/// One swept parameter: a scene key and the values it takes (as written on the command line).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Axis {
    /// Scene key, e.g. `eps_n`.
    pub key: String,
    /// Values, e.g. `["0.1", "0.4"]`.
    pub values: Vec<String>,
    /// Whether the axis takes its values with the axis before it (`+key=...`): member by
    /// member, the i-th value of one with the i-th of the other, so that two keys that
    /// describe one parameter (a pendulum's release angle, its bob's position and
    /// orientation) vary together instead of multiplying the grid.
    pub linked: bool,
}

impl Axis {
    /// Parses `key=v1,v2,...`, splitting the values at the commas outside brackets, braces
    /// and quotes only, so that an array or a table is one value
    /// (`gravity=[0,-9.81],[0,-1.62]` has two); `+key=v1,v2,...` is an axis
    /// [`linked`](Self::linked) to the one before.
    ///
    /// # Errors
    /// [`CliError::BadOption`] naming `--set` and the text, when there is no `=`, the key is
    /// empty, a value is empty or a bracket, brace or quote is left open.
    pub fn parse(text: &str) -> Result<Self> {
        let bad = |reason: &str| CliError::BadOption {
            option: "--set",
            text: text.to_owned(),
            reason: reason.to_owned(),
        };
        let Some((key, values)) = text.split_once('=') else {
            return Err(bad("expected key=value[,value...]").into());
        };
        let key = key.trim();
        let (key, linked) = match key.strip_prefix('+') {
            Some(rest) => (rest.trim_start(), true),
            None => (key, false),
        };
        if key.is_empty() {
            return Err(bad("the key is empty").into());
        }
        let values: Vec<String> = top_level_split(values)
            .map_err(|e| bad(&e))?
            .into_iter()
            .map(|v| v.trim().to_owned())
            .collect();
        if let Some(i) = values.iter().position(String::is_empty) {
            return Err(bad(&format!("value {} of {} is empty", i + 1, values.len())).into());
        }
        Ok(Self { key: key.to_owned(), values, linked })
    }

    /// The axis as `--set` takes it: `key=v1,v2,...`, or `+key=...` when it is linked.
    pub fn text(&self) -> String {
        format!("{}{}={}", if self.linked { "+" } else { "" }, self.key, self.values.join(","))
    }
}

/// `values` split at its commas outside `[]`, `{}` and quotes (`"…"`, `'…'`, a backslash
/// escaping the next character in double quotes).
fn top_level_split(values: &str) -> Result<Vec<&str>, String> {
    let (mut parts, mut start, mut depth) = (Vec::new(), 0, 0usize);
    let (mut quote, mut escaped) = (None::<char>, false);
    for (i, c) in values.char_indices() {
        if let Some(q) = quote {
            if escaped {
                escaped = false;
            } else if c == '\\' && q == '"' {
                escaped = true;
            } else if c == q {
                quote = None;
            }
            continue;
        }
        match c {
            '"' | '\'' => quote = Some(c),
            '[' | '{' => depth += 1,
            ']' | '}' => {
                depth = depth
                    .checked_sub(1)
                    .ok_or_else(|| format!("`{c}` closes no bracket or brace"))?;
            }
            ',' if depth == 0 => {
                parts.push(&values[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    if quote.is_some() {
        return Err("a quote is left open".into());
    }
    if depth != 0 {
        return Err("a bracket or brace is left open".into());
    }
    parts.push(&values[start..]);
    Ok(parts)
}

/// The axes of a file that lists a sweep's members (`--members FILE`): a CSV file whose header
/// row names scene keys and whose other rows give one member's values each, in the columns'
/// order. The columns become axes taking their values together (the first one plain, the
/// others [`linked`](Axis::linked) to it), so that the file's rows are members in its order and
/// further `--set` axes multiply them. Fields are trimmed; a value holding a comma (an array,
/// `[0, -9.81]`) is quoted as CSV quotes it; lines starting with `#` are comments.
///
/// # Errors
/// [`CliError::BadOption`] naming `--members` and the file: unreadable, not CSV, an empty key
/// in the header, a row with another number of fields than the header, an empty value, or no
/// member at all.
pub fn members_file_axes(path: &std::path::Path) -> Result<Vec<Axis>> {
    let bad = |reason: String| CliError::BadOption {
        option: "--members",
        text: path.display().to_string(),
        reason,
    };
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .flexible(true)
        .from_path(path)
        .map_err(|e| bad(e.to_string()))?;
    let keys = reader.headers().map_err(|e| bad(e.to_string()))?.clone();
    if let Some(k) = keys.iter().position(str::is_empty) {
        return Err(bad(format!("column {} of the header names no key", k + 1)).into());
    }
    let mut axes: Vec<Axis> = keys
        .iter()
        .enumerate()
        .map(|(k, key)| Axis { key: key.to_owned(), values: Vec::new(), linked: k > 0 })
        .collect();
    for row in reader.records() {
        let row = row.map_err(|e| bad(e.to_string()))?;
        let line = row.position().map_or(0, csv::Position::line);
        if row.len() != keys.len() {
            // The CSV reader takes a quote as one only at a field's first character.
            let hint = if row.len() > keys.len() {
                " (a value holding a comma is quoted, the quote straight after the comma before \
                 it: a,\"[0, -9.81]\")"
            } else {
                ""
            };
            return Err(bad(format!(
                "line {line} has {} fields, and the header names {} keys{hint}",
                row.len(),
                keys.len()
            ))
            .into());
        }
        for (axis, value) in axes.iter_mut().zip(&row) {
            if value.is_empty() {
                return Err(bad(format!("line {line} gives `{}` no value", axis.key)).into());
            }
            axis.values.push(value.to_owned());
        }
    }
    if axes.first().is_none_or(|a| a.values.is_empty()) {
        return Err(
            bad("lists no member: a header row of keys, then a row per member".into()).into()
        );
    }
    Ok(axes)
}

/// A sweep's members: the Cartesian product of its axes, first axis outermost, an axis
/// [`linked`](Axis::linked) to the one before taking its values with it, enumerated lazily
/// (member i → one value per group of linked axes by mixed radix), so that no list of members
/// is ever built.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Grid {
    axes: Vec<Axis>,
    len: u64,
}

impl Grid {
    /// The grid of `axes`.
    ///
    /// # Errors
    /// [`CliError::BadOption`] naming `--set` when the first axis is linked (there is no axis
    /// before it) or a linked axis has another number of values than the axis it is linked
    /// to; and when the number of members does not fit in 64 bits.
    pub fn new(axes: Vec<Axis>) -> Result<Self> {
        let mut len: u64 = 1;
        let mut head: Option<&Axis> = None;
        for a in &axes {
            let bad =
                |reason: String| CliError::BadOption { option: "--set", text: a.text(), reason };
            match (a.linked, head) {
                (false, _) => {
                    head = Some(a);
                    len = len
                        .checked_mul(a.values.len() as u64)
                        .with_context(|| format!("the sweep has more than {} members", u64::MAX))?;
                }
                (true, None) => {
                    return Err(bad(format!(
                        "`+{}` takes its values with the --set before it, and there is none",
                        a.key
                    ))
                    .into());
                }
                (true, Some(h)) if h.values.len() != a.values.len() => {
                    let count = |n: usize| match n {
                        1 => "1 value".to_owned(),
                        n => format!("{n} values"),
                    };
                    return Err(bad(format!(
                        "has {}, and `{}`, with which it takes them, has {}",
                        count(a.values.len()),
                        h.key,
                        count(h.values.len())
                    ))
                    .into());
                }
                (true, Some(_)) => {}
            }
        }
        Ok(Self { axes, len })
    }

    /// The axes.
    pub fn axes(&self) -> &[Axis] {
        &self.axes
    }

    /// Number of members (the product of the axes' lengths).
    pub fn len(&self) -> u64 {
        self.len
    }

    /// Whether the grid has no member (an axis without values).
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Member `i` (< [`Self::len`]): one `(key, value)` per axis, in the axes' order.
    pub fn member(&self, i: u64) -> Vec<(String, String)> {
        let mut index = vec![0; self.axes.len()];
        let mut rest = i;
        // From the last axis back: a linked axis takes the index of the axis its group starts
        // with, which alone counts in the radix.
        let mut group_end = self.axes.len();
        for k in (0..self.axes.len()).rev() {
            if self.axes[k].linked {
                continue;
            }
            let n = self.axes[k].values.len() as u64;
            index[k..group_end].fill((rest % n) as usize);
            rest /= n;
            group_end = k;
        }
        self.axes.iter().zip(index).map(|(a, j)| (a.key.clone(), a.values[j].clone())).collect()
    }
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
    /// [`CliError::BadOption`] naming `--shard` and the text, when it is not of that form.
    pub fn parse(text: &str) -> Result<Self> {
        let bad = |reason: String| CliError::BadOption {
            option: "--shard",
            text: text.to_owned(),
            reason,
        };
        let (k, n) = text.split_once('/').ok_or_else(|| bad("expected K/N".into()))?;
        let number = |x: &str, what: &str| {
            x.trim().parse::<usize>().map_err(|e| bad(format!("{what} '{}': {e}", x.trim())))
        };
        let (k, n) = (number(k, "K")?, number(n, "N")?);
        if !(n >= 1 && (1..=n).contains(&k)) {
            return Err(bad("needs 1 <= K <= N".into()).into());
        }
        Ok(Self { k, n })
    }

    /// Whether member `i` belongs to this part (interleaved: i mod N = K − 1).
    pub fn contains(&self, i: u64) -> bool {
        i % self.n as u64 == self.k as u64 - 1
    }

    /// The members of this part out of `total`, in order, without building a list.
    pub fn members(&self, total: u64) -> impl Iterator<Item = u64> + use<> {
        (self.k as u64 - 1..total).step_by(self.n)
    }

    /// The number of members of this part out of `total`.
    pub fn count(&self, total: u64) -> u64 {
        let first = self.k as u64 - 1;
        if total <= first { 0 } else { (total - first).div_ceil(self.n as u64) }
    }

    /// The whole sweep as one part.
    pub fn all() -> Self {
        Self { k: 1, n: 1 }
    }
}

/// Progress of a batch of runs: a bar on a terminal; plain lines otherwise, or nothing.
pub struct Progress {
    bar: Option<indicatif::ProgressBar>,
    done: Mutex<usize>,
    total: usize,
    what: String,
    /// Whether plain lines are written when standard error is not a terminal.
    lines: bool,
}

impl Progress {
    /// Progress over `total` items described as `what`: a bar on a terminal, a line per item
    /// otherwise.
    pub fn new(total: usize, what: &str) -> Self {
        Self::with_lines(total, what, true)
    }

    /// Progress over `total` items described as `what`: a bar on a terminal, nothing
    /// otherwise (a log is not filled with a line per item).
    pub fn on_terminal(total: usize, what: &str) -> Self {
        Self::with_lines(total, what, false)
    }

    fn with_lines(total: usize, what: &str, lines: bool) -> Self {
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
        Self { bar, done: Mutex::new(0), total, what: what.to_owned(), lines }
    }

    /// Marks one item done, with a short note.
    pub fn tick(&self, note: &str) {
        let mut done = self.done.lock().unwrap_or_else(|e| e.into_inner());
        *done += 1;
        match &self.bar {
            Some(bar) => bar.inc(1),
            None if self.lines => {
                eprintln!("{}: {}/{} done ({note})", self.what, *done, self.total)
            }
            None => {}
        }
    }

    /// Ends the progress display, leaving the bar.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish();
        }
    }

    /// Ends the progress display, removing the bar.
    pub fn clear(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
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
        let p = Grid::new(vec![a.clone(), b])?;
        assert_eq!(p.len(), 6);
        assert_eq!(p.member(0), vec![("eps_n".into(), "0.1".into()), ("dt".into(), "1e-3".into())]);
        assert_eq!(p.member(4), vec![("eps_n".into(), "0.4".into()), ("dt".into(), "1e-4".into())]);
        assert_eq!(p.member(5), vec![("eps_n".into(), "0.4".into()), ("dt".into(), "1e-5".into())]);
        assert!(Axis::parse("eps_n").is_err());
        assert!(Axis::parse("=1").is_err());
        assert!(Axis::parse("x=1,,2").is_err());
        // Commas inside arrays, tables and quotes do not split the values.
        let g = Axis::parse("gravity=[0,-9.81], [0, -1.62]")?;
        assert_eq!(g.values, vec!["[0,-9.81]", "[0, -1.62]"]);
        assert_eq!(Axis::parse("gravity=[0,-9.81]")?.values, vec!["[0,-9.81]"]);
        let t = Axis::parse(r#"x={a = [1, 2], b = "p,q"},'r,s',"t\",u""#)?;
        assert_eq!(t.values, vec![r#"{a = [1, 2], b = "p,q"}"#, "'r,s'", r#""t\",u""#]);
        assert!(Axis::parse("gravity=[0,-9.81").is_err());
        assert!(Axis::parse("gravity=0,-9.81]").is_err());
        assert!(Axis::parse("name=\"a,b").is_err());
        assert!(!a.linked && Axis::parse("+theta=1,2")?.linked);
        assert_eq!(Axis::parse(" + theta = 1, 2")?.text(), "+theta=1,2");
        assert!(Axis::parse("+=1").is_err());
        assert_eq!(Grid::new(Vec::new())?.len(), 1);
        // 40 axes of 3 values: 3^40 ≈ 1.2e19 members, never listed; member i by mixed radix.
        let big = Grid::new(
            (0..40).map(|k| Axis::parse(&format!("k{k}=0,1,2"))).collect::<Result<_>>()?,
        )?;
        assert_eq!(big.len(), 3u64.pow(40));
        let last = big.member(big.len() - 1);
        assert!(last.iter().all(|(_, v)| v == "2"));
        let m = big.member(5); // 5 = 1·3 + 2 in the last two axes
        assert_eq!((m[38].1.as_str(), m[39].1.as_str()), ("1", "2"));
        assert!(
            Grid::new((0..41).map(|k| Axis::parse(&format!("k{k}=0,1,2"))).collect::<Result<_>>()?)
                .is_err()
        );
        Ok(())
    }

    #[test]
    fn linked_axes_take_their_values_together() -> Result<()> {
        let axes = ["a=1,2,3", "+b=x,y,z", "c=p,q", "+d=P,Q", "+e=0,1"];
        let grid = Grid::new(axes.iter().map(|t| Axis::parse(t)).collect::<Result<_>>()?)?;
        assert_eq!(grid.len(), 6);
        let values = |i| grid.member(i).into_iter().map(|(_, v)| v).collect::<Vec<_>>().concat();
        let members: Vec<String> = (0..6).map(values).collect();
        assert_eq!(members, ["1xpP0", "1xqQ1", "2ypP0", "2yqQ1", "3zpP0", "3zqQ1"]);
        let keys: Vec<String> = grid.member(0).into_iter().map(|(k, _)| k).collect();
        assert_eq!(keys, ["a", "b", "c", "d", "e"]);

        let refusal = |axes: &[&str]| {
            let axes = axes.iter().map(|t| Axis::parse(t)).collect::<Result<_>>().unwrap();
            Grid::new(axes).unwrap_err().to_string()
        };
        assert_eq!(
            refusal(&["+b=1,2"]),
            "--set +b=1,2: `+b` takes its values with the --set before it, and there is none"
        );
        assert_eq!(
            refusal(&["a=1,2,3", "+b=x,y"]),
            "--set +b=x,y: has 2 values, and `a`, with which it takes them, has 3 values"
        );
        Ok(())
    }

    #[test]
    fn a_members_file_lists_members_in_its_order() -> Result<()> {
        let dir = std::env::temp_dir().join(format!("moreau-members-{}", std::process::id()));
        std::fs::create_dir_all(&dir)?;
        let file = |name: &str, text: &str| -> Result<std::path::PathBuf> {
            let path = dir.join(name);
            std::fs::write(&path, text)?;
            Ok(path)
        };
        let path = file(
            "ok.csv",
            "# three releases\nbodies.bob.position, mu\n\"[-0.29, -0.95]\", 0.1\n\"[0,-1]\",0.3\n\
             \"[-0.47,-0.87]\" , 0.5\n",
        )?;
        let mut axes = members_file_axes(&path)?;
        assert_eq!(axes.len(), 2);
        assert_eq!(axes[0].values, ["[-0.29, -0.95]", "[0,-1]", "[-0.47,-0.87]"]);
        assert_eq!(axes[1].values, ["0.1", "0.3", "0.5"]);
        assert!(!axes[0].linked && axes[1].linked);
        // With an axis of --set after them: the file's rows outermost, 3 × 2 members.
        axes.push(Axis::parse("eps_n=0,1")?);
        let grid = Grid::new(axes)?;
        assert_eq!(grid.len(), 6);
        let values = |i| grid.member(i).into_iter().map(|(_, v)| v).collect::<Vec<_>>();
        assert_eq!(values(3), ["[0,-1]", "0.3", "1"]);
        assert_eq!(values(4), ["[-0.47,-0.87]", "0.5", "0"]);

        let refusal = |name: &str, text: &str| -> Result<String> {
            Ok(members_file_axes(&file(name, text)?).unwrap_err().to_string())
        };
        let at = |name: &str| dir.join(name).display().to_string();
        assert_eq!(
            refusal("ragged.csv", "mu,eps_n\n0.1,0.5\n0.2\n")?,
            format!(
                "--members {}: line 3 has 1 fields, and the header names 2 keys",
                at("ragged.csv")
            )
        );
        assert_eq!(
            refusal("spaced_quote.csv", "mu,gravity\n0.1, \"[0, -9.81]\"\n")?,
            format!(
                "--members {}: line 2 has 3 fields, and the header names 2 keys (a value \
                 holding a comma is quoted, the quote straight after the comma before it: \
                 a,\"[0, -9.81]\")",
                at("spaced_quote.csv")
            )
        );
        assert_eq!(
            refusal("empty_value.csv", "mu,eps_n\n0.1,\n")?,
            format!("--members {}: line 2 gives `eps_n` no value", at("empty_value.csv"))
        );
        assert_eq!(
            refusal("no_key.csv", "mu,,eps_n\n0.1,1,2\n")?,
            format!("--members {}: column 2 of the header names no key", at("no_key.csv"))
        );
        assert!(
            refusal("header_only.csv", "mu\n")?
                .ends_with("lists no member: a header row of keys, then a row per member")
        );
        assert!(refusal("nothing.csv", "")?.contains("lists no member"));
        let missing = members_file_axes(&dir.join("missing.csv")).unwrap_err().to_string();
        assert!(missing.starts_with(&format!("--members {}: ", at("missing.csv"))), "{missing}");
        std::fs::remove_dir_all(&dir)?;
        Ok(())
    }

    #[test]
    fn shards_partition_the_members() -> Result<()> {
        let shards: Vec<Shard> =
            (1..=3).map(|k| Shard::parse(&format!("{k}/3"))).collect::<Result<_>>()?;
        for i in 0..20 {
            assert_eq!(shards.iter().filter(|s| s.contains(i)).count(), 1);
        }
        for total in 0..8 {
            for s in &shards {
                let m: Vec<u64> = s.members(total).collect();
                assert_eq!(m.len() as u64, s.count(total));
                assert!(m.iter().all(|&i| s.contains(i) && i < total));
            }
        }
        // A shard of a huge sweep is enumerated lazily.
        let s = Shard::parse("7/1000000")?;
        assert_eq!(s.members(1_600_000_000).nth(2), Some(2_000_006));
        assert_eq!(s.count(1_600_000_000), 1600);
        assert!(Shard::parse("0/3").is_err());
        assert!(Shard::parse("4/3").is_err());
        assert!(Shard::parse("1-3").is_err());
        Ok(())
    }
}
