//! The reproduction report: one self-contained HTML page and a Markdown twin.
//!
//! Every figure appears with its caption, its image (PNG embedded as a base64 data URI,
//! animations inlined as SVG), the parameters of the simulations behind it, their wall
//! times, and the figure's key numbers.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};
use serde::Serialize;
use serde_json::Value;

pub use crate::runs::RunInfo;

/// One figure or table as the report shows it.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct FigureReport {
    /// Identifier as in the source, e.g. `Fig 8.2`.
    pub id: String,
    /// File stem, e.g. `fig08_02_ball`.
    pub stem: String,
    /// Caption.
    pub caption: String,
    /// Files written for this figure (names relative to the output folder).
    pub files: Vec<String>,
    /// Names of the runs the figure uses.
    pub runs: Vec<String>,
    /// Key numbers of the figure.
    pub key_numbers: Value,
    /// A Markdown table shown in the report (tables only).
    pub markdown: Option<String>,
    /// Wall time spent drawing the figure (s).
    pub draw_seconds: f64,
}

/// Flattens a JSON value into (dotted key, text) rows.
pub fn flatten(value: &Value) -> Vec<(String, String)> {
    fn go(prefix: &str, v: &Value, out: &mut Vec<(String, String)>) {
        let key = |k: &str| if prefix.is_empty() { k.to_owned() } else { format!("{prefix}.{k}") };
        match v {
            Value::Object(map) => map.iter().for_each(|(k, v)| go(&key(k), v, out)),
            Value::Array(items) if items.iter().all(|i| !i.is_object() && !i.is_array()) => {
                let text: Vec<String> = items.iter().map(scalar).collect();
                out.push((prefix.to_owned(), format!("[{}]", text.join(", "))));
            }
            Value::Array(items) => {
                items.iter().enumerate().for_each(|(i, v)| go(&key(&i.to_string()), v, out))
            }
            other => out.push((prefix.to_owned(), scalar(other))),
        }
    }
    let mut out = Vec::new();
    go("", value, &mut out);
    out
}

fn scalar(v: &Value) -> String {
    match v {
        Value::Number(n) => match n.as_f64() {
            Some(x) if n.is_f64() => format_number(x),
            _ => n.to_string(),
        },
        Value::String(s) => s.clone(),
        Value::Null => "—".to_owned(),
        other => other.to_string(),
    }
}

/// A number with six significant digits.
pub fn format_number(x: f64) -> String {
    if x == 0.0 {
        return "0".to_owned();
    }
    let a = x.abs();
    if (1e-3..1e6).contains(&a) {
        let digits = (5 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{x:.digits$}");
        if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_owned() } else { s }
    } else {
        format!("{x:.5e}")
    }
}

/// Standard base64 (RFC 4648) with padding.
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for chunk in bytes.chunks(3) {
        let b = [chunk[0], *chunk.get(1).unwrap_or(&0), *chunk.get(2).unwrap_or(&0)];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for i in 0..4 {
            if i <= chunk.len() {
                s.push(ALPHABET[((n >> (18 - 6 * i)) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}

fn html_escape(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// Everything the report shows.
#[derive(Clone, Debug)]
pub struct Report<'a> {
    /// Page title.
    pub title: &'a str,
    /// Text under the title (how the page was made).
    pub preamble: &'a str,
    /// The figures and tables in registry order.
    pub figures: &'a [FigureReport],
    /// Every simulation run.
    pub runs: &'a [RunInfo],
    /// Total wall time of the reproduction (s).
    pub total_seconds: f64,
}

impl Report<'_> {
    fn run(&self, name: &str) -> Option<&RunInfo> {
        self.runs.iter().find(|r| r.name == name)
    }

    /// Writes `report.html` (self-contained) and `report.md` into `dir`.
    ///
    /// # Errors
    /// When an image cannot be read or a file cannot be written.
    pub fn write(&self, dir: &Path) -> Result<()> {
        let html = self.html(dir)?;
        std::fs::write(dir.join("report.html"), html).context("writing report.html")?;
        std::fs::write(dir.join("report.md"), self.markdown()).context("writing report.md")?;
        Ok(())
    }

    fn html(&self, dir: &Path) -> Result<String> {
        let mut s = String::new();
        let _ = write!(
            s,
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{}</title>\n<style>\n\
             body{{font-family:DejaVu Sans,Helvetica,Arial,sans-serif;max-width:1320px;margin:auto;padding:1em;color:#222}}\n\
             img,svg{{max-width:100%;height:auto;border:1px solid #ddd}}\n\
             table{{border-collapse:collapse;margin:0.5em 0;font-size:0.9em}}\n\
             td,th{{border:1px solid #ccc;padding:2px 8px;text-align:left;vertical-align:top}}\n\
             th{{background:#f3f3f3}} figure{{margin:0}} figcaption{{font-style:italic;margin:0.3em 0}}\n\
             .cols{{display:flex;gap:2em;flex-wrap:wrap}} section{{border-top:2px solid #aaa;margin-top:2em}}\n\
             </style></head><body>\n<h1>{}</h1>\n<p>{}</p>\n",
            html_escape(self.title),
            html_escape(self.title),
            html_escape(self.preamble)
        );
        let _ = writeln!(s, "<h2>Contents</h2><ul>");
        for f in self.figures {
            let _ = writeln!(
                s,
                "<li><a href=\"#{}\">{}</a>: {}</li>",
                f.stem,
                html_escape(&f.id),
                html_escape(&f.caption)
            );
        }
        let _ = writeln!(s, "<li><a href=\"#runs\">Simulation runs and wall times</a></li></ul>");
        for f in self.figures {
            let _ = writeln!(s, "<section id=\"{}\"><h2>{}</h2>", f.stem, html_escape(&f.id));
            let _ = writeln!(s, "<figure>");
            for file in &f.files {
                if file.ends_with(".png") {
                    let bytes =
                        std::fs::read(dir.join(file)).with_context(|| format!("reading {file}"))?;
                    let _ = writeln!(
                        s,
                        "<img alt=\"{}\" src=\"data:image/png;base64,{}\">",
                        html_escape(&f.id),
                        base64(&bytes)
                    );
                } else if file.ends_with("_anim.svg") {
                    let text = std::fs::read_to_string(dir.join(file))
                        .with_context(|| format!("reading {file}"))?;
                    let _ = writeln!(s, "<p>Animation of the motion ({file}):</p>\n{text}");
                }
            }
            let _ = writeln!(
                s,
                "<figcaption>{}: {}</figcaption></figure>",
                html_escape(&f.id),
                html_escape(&f.caption)
            );
            if let Some(md) = &f.markdown {
                let _ = writeln!(s, "{}", markdown_table_to_html(md));
            }
            let _ = writeln!(s, "<div class=\"cols\">");
            let numbers = flatten(&f.key_numbers);
            if !numbers.is_empty() {
                let _ = writeln!(
                    s,
                    "<div><h3>Key numbers</h3><table><tr><th>quantity</th><th>value</th></tr>"
                );
                for (k, v) in numbers {
                    let _ = writeln!(
                        s,
                        "<tr><td>{}</td><td>{}</td></tr>",
                        html_escape(&k),
                        html_escape(&v)
                    );
                }
                let _ = writeln!(s, "</table></div>");
            }
            for name in &f.runs {
                if let Some(run) = self.run(name) {
                    let _ = writeln!(
                        s,
                        "<div><h3>Run <code>{}</code></h3><table><tr><th>parameter</th><th>value</th></tr>",
                        html_escape(&run.name)
                    );
                    for (k, v) in run_rows(run) {
                        let _ = writeln!(
                            s,
                            "<tr><td>{}</td><td>{}</td></tr>",
                            html_escape(&k),
                            html_escape(&v)
                        );
                    }
                    let _ = writeln!(s, "</table></div>");
                }
            }
            let _ = writeln!(s, "</div>");
            let _ = writeln!(
                s,
                "<p>Files: {}. Drawing took {:.2} s.</p></section>",
                f.files
                    .iter()
                    .map(|f| format!("<code>{}</code>", html_escape(f)))
                    .collect::<Vec<_>>()
                    .join(", "),
                f.draw_seconds
            );
        }
        let _ = writeln!(
            s,
            "<section id=\"runs\"><h2>Simulation runs and wall times</h2><table>\n\
             <tr><th>run</th><th>model</th><th>Δt [s]</th><th>t_end [s]</th><th>solver</th><th>steps</th><th>LCP solves</th><th>wall time [s]</th></tr>"
        );
        for r in self.runs {
            let _ = writeln!(
                s,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.3}</td></tr>",
                html_escape(&r.name),
                html_escape(&r.model),
                format_number(r.dt),
                format_number(r.t_end),
                html_escape(&r.solver),
                r.steps,
                r.lcp_solves,
                r.wall_seconds
            );
        }
        let _ = writeln!(
            s,
            "</table><p>Total wall time of the reproduction: {:.2} s.</p></section></body></html>",
            self.total_seconds
        );
        Ok(s)
    }

    fn markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "# {}\n\n{}\n", self.title, self.preamble);
        for f in self.figures {
            let _ = writeln!(s, "## {}\n\n{}\n", f.id, f.caption);
            for file in &f.files {
                if file.ends_with(".png") {
                    let _ = writeln!(s, "![{}]({file})\n", f.id);
                }
            }
            if let Some(md) = &f.markdown {
                let _ = writeln!(s, "{md}");
            }
            let numbers = flatten(&f.key_numbers);
            if !numbers.is_empty() {
                let _ = writeln!(s, "Key numbers:\n\n| quantity | value |\n|---|---|");
                for (k, v) in numbers {
                    let _ = writeln!(s, "| {k} | {v} |");
                }
                s.push('\n');
            }
            for name in &f.runs {
                if let Some(run) = self.run(name) {
                    let _ = writeln!(s, "Run `{}`:\n\n| parameter | value |\n|---|---|", run.name);
                    for (k, v) in run_rows(run) {
                        let _ = writeln!(s, "| {k} | {v} |");
                    }
                    s.push('\n');
                }
            }
            let _ = writeln!(
                s,
                "Files: {}\n",
                f.files.iter().map(|f| format!("`{f}`")).collect::<Vec<_>>().join(", ")
            );
        }
        let _ = writeln!(
            s,
            "## Simulation runs and wall times\n\n| run | model | Δt [s] | t_end [s] | solver | steps | LCP solves | wall time [s] |\n|---|---|---:|---:|---|---:|---:|---:|"
        );
        for r in self.runs {
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | {:.3} |",
                r.name,
                r.model,
                format_number(r.dt),
                format_number(r.t_end),
                r.solver,
                r.steps,
                r.lcp_solves,
                r.wall_seconds
            );
        }
        let _ = writeln!(s, "\nTotal wall time of the reproduction: {:.2} s.", self.total_seconds);
        s
    }
}

fn run_rows(run: &RunInfo) -> Vec<(String, String)> {
    let mut rows = vec![
        ("model".to_owned(), run.model.clone()),
        ("Δt [s]".to_owned(), format_number(run.dt)),
        ("t_end [s]".to_owned(), format_number(run.t_end)),
        ("solver".to_owned(), run.solver.clone()),
    ];
    rows.extend(run.parameters.iter().cloned());
    rows.push(("steps".to_owned(), run.steps.to_string()));
    rows.push(("LCP solves".to_owned(), run.lcp_solves.to_string()));
    rows.push(("wall time [s]".to_owned(), format!("{:.3}", run.wall_seconds)));
    rows
}

/// Converts simple Markdown (paragraphs and tables separated by blank lines) into HTML.
fn markdown_table_to_html(md: &str) -> String {
    let mut s = String::new();
    for block in md.split("\n\n").map(str::trim).filter(|b| !b.is_empty()) {
        if block.lines().all(|l| l.trim_start().starts_with('|')) {
            s.push_str(&one_table_to_html(block));
        } else {
            let _ = write!(s, "<p>{}</p>", html_escape(block));
        }
        s.push('\n');
    }
    s
}

/// The cells of one Markdown table row; `\\|` is a literal bar inside a cell.
fn split_cells(line: &str) -> Vec<String> {
    let trimmed = line.trim();
    let inner = trimmed.strip_prefix('|').unwrap_or(trimmed);
    let inner = inner.strip_suffix('|').unwrap_or(inner);
    let (mut cells, mut cell) = (Vec::new(), String::new());
    let mut chars = inner.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if chars.peek() == Some(&'|') => {
                chars.next();
                cell.push('|');
            }
            '|' => cells.push(std::mem::take(&mut cell)),
            c => cell.push(c),
        }
    }
    cells.push(cell);
    cells.into_iter().map(|c| c.trim().to_owned()).collect()
}

/// Converts one Markdown table (header, rule, rows) into an HTML table.
fn one_table_to_html(md: &str) -> String {
    let mut s = String::from("<table>");
    for (i, line) in md.lines().filter(|l| l.trim_start().starts_with('|')).enumerate() {
        if i == 1 {
            continue;
        }
        let tag = if i == 0 { "th" } else { "td" };
        let cells = split_cells(line);
        s.push_str("<tr>");
        for c in cells {
            let _ = write!(s, "<{tag}>{}</{tag}>", html_escape(&c));
        }
        s.push_str("</tr>\n");
    }
    s.push_str("</table>");
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_matches_rfc4648_vectors() {
        assert_eq!(base64(b""), "");
        assert_eq!(base64(b"f"), "Zg==");
        assert_eq!(base64(b"fo"), "Zm8=");
        assert_eq!(base64(b"foo"), "Zm9v");
        assert_eq!(base64(b"foobar"), "Zm9vYmFy");
    }

    #[test]
    fn flatten_nests_keys() {
        let v = serde_json::json!({"a": {"b": 1.5, "c": [1, 2]}, "d": "x", "e": [{"f": 2}]});
        let rows = flatten(&v);
        assert_eq!(
            rows,
            vec![
                ("a.b".to_owned(), "1.5".to_owned()),
                ("a.c".to_owned(), "[1, 2]".to_owned()),
                ("d".to_owned(), "x".to_owned()),
                ("e.0.f".to_owned(), "2".to_owned()),
            ]
        );
    }

    #[test]
    fn numbers_have_six_significant_digits() {
        assert_eq!(format_number(0.428279), "0.428279");
        assert_eq!(format_number(8.13730123), "8.1373");
        assert_eq!(format_number(1e-4), "1.00000e-4");
        assert_eq!(format_number(150.0), "150");
    }

    #[test]
    fn report_embeds_images_and_tables() -> Result<()> {
        let dir = tempfile::tempdir()?;
        std::fs::write(dir.path().join("a.png"), b"png bytes")?;
        std::fs::write(dir.path().join("a_anim.svg"), "<svg>anim</svg>")?;
        let figures = vec![FigureReport {
            id: "Fig 1".into(),
            stem: "fig01".into(),
            caption: "A <test>".into(),
            files: vec!["a.png".into(), "a_anim.svg".into()],
            runs: vec!["r".into()],
            key_numbers: serde_json::json!({"t1": 0.5}),
            markdown: Some("| a | b |\n|---|---|\n| 1 | 2 |\n".into()),
            draw_seconds: 0.1,
        }];
        let runs = vec![RunInfo {
            name: "r".into(),
            model: "ball".into(),
            dt: 1e-3,
            t_end: 1.0,
            solver: "auto".into(),
            parameters: vec![("m".into(), "1".into())],
            wall_seconds: 0.25,
            steps: 1000,
            lcp_solves: 3,
        }];
        let report = Report {
            title: "R",
            preamble: "p",
            figures: &figures,
            runs: &runs,
            total_seconds: 1.0,
        };
        report.write(dir.path())?;
        let html = std::fs::read_to_string(dir.path().join("report.html"))?;
        assert!(html.contains(&format!("data:image/png;base64,{}", base64(b"png bytes"))));
        assert!(html.contains("<svg>anim</svg>"));
        assert!(html.contains("A &lt;test&gt;"));
        assert!(html.contains("<td>1</td><td>2</td>"));
        assert!(html.contains("<td>t1</td><td>0.5</td>"));
        assert!(html.contains("<td>m</td><td>1</td>"));
        let md = std::fs::read_to_string(dir.path().join("report.md"))?;
        assert!(md.contains("![Fig 1](a.png)"));
        assert!(md.contains("| t1 | 0.5 |"));
        Ok(())
    }

    #[test]
    fn markdown_blocks_become_paragraphs_and_separate_tables() {
        let md =
            "Orders:\n\n| a | b |\n|---|---|\n| 1 | x \\| y |\n\nRuns:\n\n| c |\n|---|\n| 2 |\n";
        let html = markdown_table_to_html(md);
        assert_eq!(html.matches("<table>").count(), 2);
        assert_eq!(html.matches("<p>").count(), 2);
        assert!(html.contains("<tr><td>1</td><td>x | y</td></tr>"), "{html}");
        assert!(html.contains("<tr><th>c</th></tr>\n<tr><td>2</td></tr>"), "{html}");
        assert_eq!(split_cells("| a |  | b\\|c |"), vec!["a", "", "b|c"]);
    }
}
