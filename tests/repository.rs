//! The repository's documents agree with the repository: every relative link in its Markdown
//! files names a file or directory that exists, and the README's dependency graph names each
//! dependency that each crate's manifest declares.

use std::fs;
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The Markdown files of the repository, outside `target/` and hidden directories.
fn markdown_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if name.starts_with('.') || name == "target" {
            continue;
        }
        if path.is_dir() {
            markdown_files(&path, out);
        } else if name.ends_with(".md") {
            out.push(path);
        }
    }
}

/// The targets of the inline links `[text](target)` of a Markdown text, outside code spans
/// and fenced blocks.
fn link_targets(text: &str) -> Vec<String> {
    let mut targets = Vec::new();
    let mut fenced = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if fenced {
            continue;
        }
        // Drop code spans, whose brackets are not links.
        let mut plain = String::new();
        for (k, part) in line.split('`').enumerate() {
            if k % 2 == 0 {
                plain.push_str(part);
            }
        }
        let mut rest = plain.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(close) = after.find(')') else { break };
            targets.push(after[..close].to_string());
            rest = &after[close..];
        }
    }
    targets
}

#[test]
fn relative_links_name_files_that_exist() {
    let root = root();
    let mut files = Vec::new();
    markdown_files(&root, &mut files);
    assert!(files.len() >= 10, "found only {} Markdown files", files.len());
    let mut checked = 0;
    let mut broken = Vec::new();
    for file in &files {
        let text = fs::read_to_string(file).unwrap();
        for target in link_targets(&text) {
            if target.contains("://") || target.starts_with('#') || target.starts_with("mailto:") {
                continue;
            }
            let path = target.split('#').next().unwrap();
            let resolved = file.parent().unwrap().join(path);
            checked += 1;
            if !resolved.exists() {
                broken.push(format!("{}: {target}", file.strip_prefix(&root).unwrap().display()));
            }
        }
    }
    assert!(checked >= 20, "checked only {checked} relative links");
    assert!(broken.is_empty(), "links to missing files:\n{}", broken.join("\n"));
}

/// The README's bullet for a crate: the list item that starts with the crate's name in
/// backticks, with its continuation lines.
fn graph_bullet<'a>(readme: &'a str, name: &str) -> &'a str {
    let start_marker = format!("- `{name}` ");
    let at = readme
        .find(&start_marker)
        .unwrap_or_else(|| panic!("the README's dependency graph has no item for `{name}`"));
    let rest = &readme[at..];
    let end = rest[2..]
        .find("\n- ")
        .map(|e| e + 2)
        .into_iter()
        .chain(rest.find("\n\n"))
        .min()
        .unwrap_or(rest.len());
    &rest[..end]
}

#[test]
fn dependency_graph_in_the_readme_names_every_declared_dependency() {
    let root = root();
    let readme = fs::read_to_string(root.join("README.md")).unwrap();
    let graph_at = readme
        .find("Architecture invariants (the dependency graph")
        .expect("the README states its dependency graph");
    let graph = &readme[graph_at..];
    // serde and thiserror are stated once for all the library crates and the cli.
    let stated_for_all = ["serde", "thiserror"];
    let manifests = [
        ("moreau-setvalued", "crates/setvalued"),
        ("moreau-lcp", "crates/lcp"),
        ("moreau-kinematics", "crates/kinematics"),
        ("moreau-stepper", "crates/stepper"),
        ("moreau-models", "crates/models"),
        ("moreau-cli", "crates/cli"),
        ("moreau-testsupport", "crates/testsupport"),
        ("xtask", "xtask"),
        ("moreau", "."),
    ];
    let mut missing = Vec::new();
    for (name, dir) in manifests {
        let manifest: toml::Table =
            fs::read_to_string(root.join(dir).join("Cargo.toml")).unwrap().parse().unwrap();
        let bullet = graph_bullet(graph, name);
        let deps = manifest.get("dependencies").and_then(|d| d.as_table());
        for dep in deps.into_iter().flat_map(|d| d.keys()) {
            if stated_for_all.contains(&dep.as_str()) {
                continue;
            }
            let short = dep.strip_prefix("moreau-").unwrap_or(dep);
            if !bullet.contains(short) {
                missing.push(format!("{name} -> {dep}"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "dependencies the README's graph does not name:\n{}",
        missing.join("\n")
    );
}
