//! Parameter grids for sweeps: `--set key=v1,v2` options (`--set +key=w1,w2` taking its
//! values with the axis before), their Cartesian product enumerated lazily, shards, and the
//! progress display of a batch of runs.

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
