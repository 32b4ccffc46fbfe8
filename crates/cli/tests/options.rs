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
