//! A bad value of an option is refused naming the option as it was typed: `--dt NaN`, not the
//! scene key it sets.

use std::process::Command;

use anyhow::{Result, ensure};

/// `moreau simulate ball` with `args`, which must fail; its standard error.
fn refused(args: &[&str]) -> Result<String> {
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("ball.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_moreau"))
        .args(["simulate", "ball", "--out"])
        .arg(&out)
        .args(args)
        .output()?;
    ensure!(o.status.code() == Some(1), "{args:?}: {:?}", o.status);
    Ok(String::from_utf8(o.stderr)?)
}

#[test]
fn a_bad_dt_or_tf_names_the_option_typed() -> Result<()> {
    for (args, typed) in [
        (&["--dt", "NaN"][..], "error: --dt NaN: "),
        (&["--dt=-1"], "error: --dt -1: "),
        (&["--tf", "inf"], "error: --tf inf: "),
        (&["--set", "dt=NaN"], "error: --set dt=NaN: "),
    ] {
        let stderr = refused(args)?;
        ensure!(stderr.starts_with(typed), "{args:?}: {stderr}");
    }
    Ok(())
}

/// `moreau sweep ball` with `args`, which must be refused; its standard error.
fn sweep_refused(args: &[&str]) -> Result<String> {
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("s.csv");
    let o = Command::new(env!("CARGO_BIN_EXE_moreau"))
        .args(["sweep", "ball", "--out"])
        .arg(&out)
        .args(args)
        .output()?;
    ensure!(o.status.code() == Some(1), "{args:?}: {:?}", o.status);
    ensure!(!out.exists() && std::fs::read_dir(dir.path())?.next().is_none(), "{args:?}");
    Ok(String::from_utf8(o.stderr)?)
}

/// A sweep's `--set` or `--shard` that is not of its form is refused naming the option and
/// its text, and what is wrong (`shard '0/3' needs 1 <= K <= N` and `empty value in ...`
/// named neither option).
#[test]
fn a_bad_sweep_axis_or_shard_names_the_option_typed() -> Result<()> {
    for (args, expected) in [
        (&["--set", "eps_n=0.5,,0.6"][..], "error: --set eps_n=0.5,,0.6: value 2 of 3 is empty\n"),
        (&["--set", "eps_n"], "error: --set eps_n: expected key=value[,value...]\n"),
        (&["--set", "=0.5"], "error: --set =0.5: the key is empty\n"),
        (
            &["--set", "gravity=[0,-1"],
            "error: --set gravity=[0,-1: a bracket or brace is left open\n",
        ),
        (&["--set", "x='a"], "error: --set x='a: a quote is left open\n"),
        (&["--set", "x=]"], "error: --set x=]: `]` closes no bracket or brace\n"),
        (&["--shard", "0/3"], "error: --shard 0/3: needs 1 <= K <= N\n"),
        (&["--shard", "4/3"], "error: --shard 4/3: needs 1 <= K <= N\n"),
        (&["--shard", "1/0"], "error: --shard 1/0: needs 1 <= K <= N\n"),
        (&["--shard", "2"], "error: --shard 2: expected K/N\n"),
        (&["--shard", "a/3"], "error: --shard a/3: K 'a': invalid digit found in string\n"),
    ] {
        let stderr = sweep_refused(args)?;
        ensure!(stderr == expected, "{args:?}: {stderr}");
    }
    Ok(())
}
