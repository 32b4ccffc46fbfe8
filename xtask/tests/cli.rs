//! The `xtask` command's arguments: refused with a message and a non-zero exit before any
//! run, never with a panic.

use std::path::Path;
use std::process::{Command, Output};

fn xtask(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(args)
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join(".."))
        .output()
        .expect("the xtask binary runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Refused with exit code `code` and a message containing `words`, without a panic.
fn refused(args: &[&str], code: i32, words: &str) -> String {
    let o = xtask(args);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(code), "{args:?}: {err}");
    assert!(err.contains(words), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    err
}

#[test]
fn zero_worker_threads_are_refused() {
    for command in ["reproduce", "tradeoff"] {
        refused(&[command, "--jobs", "0", "--quick"], 2, "--jobs");
    }
}

#[test]
fn an_output_that_is_a_file_is_refused_before_any_run() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let file = dir.path().join("a-file");
    std::fs::write(&file, "not a folder").expect("the file is written");
    let file = file.to_str().expect("a UTF-8 path");
    let under = format!("{file}/sub");
    for args in [
        vec!["scale", "--quick", "--out", file],
        vec!["scale", "--quick", "--out", &under],
        vec!["reproduce", "--quick", "--out", file],
        vec!["tradeoff", "--quick", "--out", file],
        vec!["frames", "ball", "--out", file],
    ] {
        let err = refused(&args, 1, "--out");
        // Nothing was run: the scaling study reports each run as it ends.
        assert!(!err.contains("scale: "), "{args:?} ran: {err}");
    }
    let out = dir.path().join("out");
    let out = out.to_str().expect("a UTF-8 path");
    let err = refused(
        &["scale", "--quick", "--only", "pyramid", "--problems", file, "--out", out],
        1,
        "--problems",
    );
    assert!(err.contains("is a file, not a folder") && !err.contains("scale: "), "{err}");
}

#[test]
fn a_strip_of_more_frames_than_it_can_hold_is_refused() {
    let dir = tempfile::tempdir().expect("a temporary folder");
    let out = dir.path().to_str().expect("a UTF-8 path");
    let set = ["--set", "t_end=0.2", "--out", out];
    refused(&[&["frames", "ball", "--count", "1000000"], &set[..]].concat(), 1, "at most 100");
    let times: Vec<String> = (0..101).map(|k| format!("{}", 0.001 * k as f64)).collect();
    let times = times.join(",");
    refused(&[&["frames", "ball", "--times", &times], &set[..]].concat(), 1, "at most 100");
    // A hundred frames are drawn.
    let o = xtask(&[&["frames", "ball", "--count", "100"], &set[..]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("ball.png").exists());
}

#[test]
fn help_says_what_quick_shrinks() {
    let o = xtask(&["reproduce", "--help"]);
    let help = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success());
    assert!(!help.contains("Shorter horizons"), "{help}");
    assert!(help.contains("the report's figures are the same as in a full run"), "{help}");
}
