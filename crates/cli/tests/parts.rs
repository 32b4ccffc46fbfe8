//! Sweep parts name their sweep; merge refuses mixed, incomplete and damaged sets; an
//! interrupted sweep resumes without running its finished members again; shards of enormous
//! grids are enumerated lazily.

use std::path::{Path, PathBuf};

use anyhow::{Result, ensure};
use moreau_cli::CliError;
use moreau_cli::grid::{Axis, Shard};
use moreau_cli::parts::{merge, read_part};
use moreau_cli::simulate::partial_path;
use moreau_cli::sweep::{SweepOptions, run};

fn options(eps: &str, shard: Option<&str>) -> Result<SweepOptions> {
    let axes = vec![Axis::parse(&format!("eps_n={eps}"))?, Axis::parse("t_end=0.5,1")?];
    let mut o = SweepOptions::new("ball", axes);
    o.shard = shard.map(Shard::parse).transpose()?;
    Ok(o)
}

fn parts(dir: &Path, eps: &str, n: usize, tag: &str) -> Result<Vec<PathBuf>> {
    (1..=n)
        .map(|k| {
            let p = dir.join(format!("{tag}{k}.csv"));
            run(&options(eps, Some(&format!("{k}/{n}")))?, &p)?;
            Ok(p)
        })
        .collect()
}

fn cli_error(e: &anyhow::Error) -> Option<&CliError> {
    e.chain().find_map(|c| c.downcast_ref::<CliError>())
}

#[test]
fn merge_refuses_parts_of_other_sweeps() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let a = parts(dir.path(), "0.1,0.3,0.5", 2, "a")?;
    let b = parts(dir.path(), "0.15,0.3,0.55", 2, "b")?;
    let out = dir.path().join("m.csv");
    assert_eq!(merge(&out, &a)?, 6);
    // Same size, same columns, other values: refused, naming the part.
    let e = merge(&out, &[&a[0], &b[1]]).expect_err("mixed");
    ensure!(
        matches!(cli_error(&e), Some(CliError::MixedParts { part, .. }) if *part == b[1]),
        "{e:#}"
    );
    // Another scene (a scene file with another mass) is another sweep too.
    let scene = dir.path().join("heavy.toml");
    let mut heavy = moreau_models::Scene::report(moreau_models::ModelKind::Ball);
    heavy.set("m", "2")?;
    std::fs::write(&scene, heavy.to_toml_string()?)?;
    let mut o = options("0.1,0.3,0.5", Some("2/2"))?;
    o.scene = Some(scene);
    let c = dir.path().join("c2.csv");
    run(&o, &c)?;
    let e = merge(&out, &[&a[0], &c]).expect_err("other scene");
    ensure!(matches!(cli_error(&e), Some(CliError::MixedParts { .. })), "{e:#}");
    // A CSV without the identity line is not a part.
    let plain = dir.path().join("plain.csv");
    std::fs::write(&plain, "member,members,x,check\n0,1,a,00000000\n")?;
    let e = format!("{:#}", merge(&out, &[&plain]).expect_err("plain"));
    ensure!(e.contains("plain.csv") && e.contains("sweep"), "{e}");
    Ok(())
}

#[test]
fn merge_refuses_incomplete_sets() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let a = parts(dir.path(), "0.1,0.3,0.5", 3, "a")?;
    let out = dir.path().join("m.csv");
    let e = merge(&out, &a[..2]).expect_err("missing shard");
    let text = format!("{e:#}");
    // Shard 3/3 holds members 2 and 5.
    ensure!(matches!(cli_error(&e), Some(CliError::MissingMembers { .. })), "{text}");
    ensure!(text.contains("2, 5"), "{text}");
    // Only empty shards: 6 members, shards 7/8 and 8/8 hold none; every member is missing.
    let empty = parts(dir.path(), "0.1,0.3,0.5", 8, "e")?;
    ensure!(read_part(&empty[7], false)?.rows.is_empty());
    let e = format!("{:#}", merge(&out, &empty[6..]).expect_err("empty"));
    ensure!(e.contains("0, 1, 2, 3, 4, 5"), "{e}");
    // A part that lacks a member of its own shard (a run killed early) is named.
    let cut = dir.path().join("cut.csv");
    let text = std::fs::read_to_string(&a[0])?;
    let lines: Vec<&str> = text.lines().collect();
    std::fs::write(&cut, format!("{}\n", lines[..lines.len() - 1].join("\n")))?;
    let e = format!("{:#}", merge(&out, &[&cut, &a[1], &a[2]]).expect_err("short part"));
    ensure!(e.contains("cut.csv") && e.contains("members missing: 3"), "{e}");
    Ok(())
}

#[test]
fn merge_names_a_part_given_twice_and_a_shard_held_twice() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let a = parts(dir.path(), "0.1,0.3,0.5", 3, "a")?;
    let out = dir.path().join("m.csv");
    // The same file under another spelling of its path.
    let again = dir.path().join(".").join("a1.csv");
    let e = merge(&out, &[&a[0], &a[1], &a[2], &again]).expect_err("a part given twice");
    let text = format!("{e:#}");
    ensure!(matches!(cli_error(&e), Some(CliError::MixedParts { .. })), "{text}");
    ensure!(text.contains("is given twice (also as ") && text.contains("a1.csv)"), "{text}");
    // A copy of a shard is another file holding the same members.
    let copy = dir.path().join("copy.csv");
    std::fs::copy(&a[0], &copy)?;
    let e = format!("{:#}", merge(&out, &[&a[0], &a[1], &a[2], &copy]).expect_err("a copy"));
    ensure!(e.contains("copy.csv: member 0 is also in ") && e.contains("a1.csv"), "{e}");
    ensure!(!out.exists());
    Ok(())
}

#[test]
fn a_part_with_crlf_line_ends_merges_as_it_was() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let a = parts(dir.path(), "0.1,0.3,0.5", 2, "a")?;
    let out = dir.path().join("m.csv");
    merge(&out, &a)?;
    let crlf = dir.path().join("crlf.csv");
    std::fs::write(&crlf, std::fs::read_to_string(&a[1])?.replace('\n', "\r\n"))?;
    let again = dir.path().join("m-crlf.csv");
    ensure!(merge(&again, &[&a[0], &crlf])? == 6);
    ensure!(std::fs::read(&again)? == std::fs::read(&out)?, "the merged files differ");
    // Alone, or first, it is read alike.
    ensure!(read_part(&crlf, false)?.header == read_part(&a[1], false)?.header);
    ensure!(merge(&again, &[&crlf, &a[0]])? == 6);
    Ok(())
}

#[test]
fn merge_refuses_damaged_parts() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let a = parts(dir.path(), "0.1,0.3,0.5", 2, "a")?;
    let out = dir.path().join("m.csv");
    let text = std::fs::read_to_string(&a[1])?;
    // The last row cut off at every length: a few cells fewer, or inside a cell.
    let body = text.trim_end_matches('\n');
    let last_start = body.rfind('\n').map_or(0, |i| i + 1);
    for cut in (last_start + 2..body.len()).step_by(7) {
        std::fs::write(&a[1], &body[..cut])?;
        let e = merge(&out, &a).expect_err("cut");
        ensure!(
            matches!(
                cli_error(&e),
                Some(CliError::DamagedPart { part, line: 5, .. }) if *part == a[1]
            ),
            "cut at {cut}: {e:#}"
        );
    }
    // An altered number in a middle row.
    let altered = text.replacen(",ok,", ",ok ,", 1);
    std::fs::write(&a[1], altered)?;
    ensure!(merge(&out, &a).is_err());
    Ok(())
}

#[test]
fn an_interrupted_sweep_resumes_without_rerunning_its_members() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let o = options("0.1,0.3,0.5", None)?;
    let full = dir.path().join("full.csv");
    assert_eq!(run(&o, &full)?.ran, 6);
    // An interruption: three rows written, the fourth cut off inside.
    let out = dir.path().join("out.csv");
    let text = std::fs::read_to_string(&full)?;
    let lines: Vec<&str> = text.lines().collect();
    let partial = format!("{}\n{}\n", lines[..5].join("\n"), &lines[5][..lines[5].len() / 2]);
    std::fs::write(partial_path(&out), &partial)?;
    // Without --resume the unfinished run is not overwritten.
    let e = format!("{:#}", run(&o, &out).expect_err("no resume"));
    ensure!(e.contains("--resume"), "{e}");
    // Another sweep does not resume it.
    let other = SweepOptions { resume: true, ..options("0.1,0.3,0.6", None)? };
    ensure!(run(&other, &out).is_err());
    let s = run(&SweepOptions { resume: true, ..o.clone() }, &out)?;
    ensure!(s.ran == 3 && s.rows == 6 && s.dropped_damaged_row, "{s:?}");
    let strip = |t: &str| -> Vec<String> {
        // Without wall_seconds and the check, which covers it.
        t.lines()
            .map(|l| {
                let cells: Vec<&str> = l.split(',').collect();
                if cells.len() < 4 { l.to_owned() } else { cells[..cells.len() - 5].join(",") }
            })
            .collect()
    };
    ensure!(strip(&std::fs::read_to_string(&out)?) == strip(&text));
    ensure!(!partial_path(&out).exists());
    // Resuming a finished part runs nothing.
    let again = run(&SweepOptions { resume: true, ..options("0.1,0.3,0.5", None)? }, &out)?;
    ensure!(again.ran == 0 && again.rows == 6, "{again:?}");
    // Cut between two rows, nothing is dropped; the command says when a row was.
    let clean = format!("{}\n", lines[..5].join("\n"));
    std::fs::write(partial_path(&out), &clean)?;
    std::fs::remove_file(&out)?;
    let s = run(&SweepOptions { resume: true, ..o.clone() }, &out)?;
    ensure!(s.ran == 3 && !s.dropped_damaged_row, "{s:?}");
    std::fs::write(partial_path(&out), &partial)?;
    std::fs::remove_file(&out)?;
    let resumed = std::process::Command::new(env!("CARGO_BIN_EXE_moreau"))
        .args(["sweep", "ball", "--set", "eps_n=0.1,0.3,0.5", "--set", "t_end=0.5,1"])
        .args(["--resume", "--out"])
        .arg(&out)
        .output()?;
    let stderr = String::from_utf8_lossy(&resumed.stderr);
    ensure!(stderr.contains("last row was damaged"), "{stderr}");
    Ok(())
}

/// Six axes of 1000 equal values each over the ball's keys: 10^18 members.
fn enormous_grid() -> Result<Vec<Axis>> {
    let many = |key: &str, v: &str| Axis::parse(&format!("{key}={}", vec![v; 1000].join(",")));
    Ok(vec![
        many("eps_n", "0.5")?,
        many("init.y0", "1")?,
        many("m", "1")?,
        many("g", "9.81")?,
        many("t_end", "0.01")?,
        many("dt", "0.001")?,
    ])
}

#[test]
fn a_shard_of_an_enormous_grid_runs_only_its_members() -> Result<()> {
    // Six axes of 1000 values: 10^18 members, never listed; shard 1/(5·10^17) holds two.
    let axes = enormous_grid()?;
    let mut o = SweepOptions::new("ball", axes);
    o.shard = Some(Shard { k: 1, n: 500_000_000_000_000_000 });
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("s.csv");
    let s = run(&o, &out)?;
    ensure!(s.rows == 2, "{s:?}");
    let part = read_part(&out, false)?;
    ensure!(part.header.members == 1_000_000_000_000_000_000);
    let members: Vec<u64> = part.rows.iter().map(|(i, _)| *i).collect();
    ensure!(members == [0, 500_000_000_000_000_000], "{members:?}");
    Ok(())
}

/// A merge of parts holding a diverged member writes every row and ends as `sweep` does on the
/// same rows: exit status 1 with `CliError::MembersFailed`'s count.
#[test]
fn a_merge_with_a_diverged_member_writes_every_row_and_fails_as_the_sweep() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let d = dir.path();
    let moreau = |args: &[&str]| -> Result<std::process::Output> {
        Ok(std::process::Command::new(env!("CARGO_BIN_EXE_moreau"))
            .current_dir(d)
            .args(args)
            .output()?)
    };
    // dt = 1e-2 is above the woodpecker's stability limit: member 1 diverges.
    let sweep_args = ["sweep", "woodpecker", "--set", "dt=1e-4,1e-2", "--set", "t_end=0.02"];
    let whole = moreau(&[&sweep_args[..], &["--out", "whole.csv"]].concat())?;
    ensure!(whole.status.code() == Some(1), "{:?}", whole.status);
    for k in 1..=2 {
        let shard = format!("{k}/2");
        let out = format!("part{k}.csv");
        moreau(&[&sweep_args[..], &["--shard", &shard, "--out", &out]].concat())?;
    }
    let merged = moreau(&["merge", "--out", "merged.csv", "part1.csv", "part2.csv"])?;
    let (stdout, stderr) =
        (String::from_utf8_lossy(&merged.stdout), String::from_utf8_lossy(&merged.stderr));
    ensure!(merged.status.code() == whole.status.code(), "{:?}: {stderr}", merged.status);
    ensure!(
        stdout.contains("merged 2 members") && stdout.contains("1 diverged, 0 failed"),
        "{stdout}"
    );
    // The sweep's error line (after its warnings), naming the merged file.
    let last = |text: &str| text.lines().last().unwrap_or_default().to_owned();
    let expected = last(&String::from_utf8_lossy(&whole.stderr)).replace("whole.csv", "merged.csv");
    ensure!(last(&stderr) == expected && stderr.starts_with("error: "), "{stderr} vs {expected}");
    let text = std::fs::read_to_string(d.join("merged.csv"))?;
    let rows: Vec<&str> = text.lines().skip(2).collect();
    ensure!(rows.len() == 2 && rows[1].contains(",diverged,"), "{text}");
    Ok(())
}

/// The members of a `CliError::MissingMembers`.
fn missing_members(e: &anyhow::Error) -> Option<String> {
    match cli_error(e) {
        Some(CliError::MissingMembers { members, .. }) => Some(members.clone()),
        _ => None,
    }
}

/// Merging an incomplete set of parts of an enormous sweep is refused at once, its missing
/// members counted from the rows held rather than enumerated (10^18 of them here).
#[test]
fn an_incomplete_merge_of_an_enormous_grid_is_refused_at_once() -> Result<()> {
    let axes = enormous_grid()?;
    let dir = tempfile::tempdir()?;
    let mut parts = Vec::new();
    for k in 1..=2 {
        let mut o = SweepOptions::new("ball", axes.clone());
        o.shard = Some(Shard { k, n: 500_000_000_000_000_000 });
        let p = dir.path().join(format!("s{k}.csv"));
        ensure!(run(&o, &p)?.rows == 2);
        parts.push(p);
    }
    let out = dir.path().join("merged.csv");
    let (tx, rx) = std::sync::mpsc::channel();
    let (o, p) = (out.clone(), parts.clone());
    std::thread::spawn(move || {
        let _ = tx.send(merge(&o, &p).map_err(|e| (format!("{e:#}"), missing_members(&e))));
    });
    let result = rx
        .recv_timeout(std::time::Duration::from_secs(60))
        .map_err(|_| anyhow::anyhow!("the merge still runs after 60 s"))?;
    let Err((message, Some(members))) = result else {
        anyhow::bail!("expected the missing members, got {result:?}");
    };
    ensure!(
        members.starts_with("2, 3, 4, ")
            && members.contains(" ... (999999999999999996 in all) of 1000000000000000000"),
        "{message}"
    );
    ensure!(!out.exists());

    // A part that lacks members of its shard (a shard of 5·10^17 members, one row) says how
    // many without listing them.
    let text = std::fs::read_to_string(&parts[0])?;
    let lines: Vec<&str> = text.lines().collect();
    let head = lines[0].replace("shard 1/500000000000000000", "shard 1/2");
    std::fs::write(&parts[0], format!("{head}\n{}\n{}\n", lines[1], lines[2]))?;
    let (tx, rx) = std::sync::mpsc::channel();
    let p = parts[0].clone();
    std::thread::spawn(move || {
        let _ = tx.send(merge(&out, &[p]).map_err(|e| missing_members(&e)));
    });
    let result = rx
        .recv_timeout(std::time::Duration::from_secs(60))
        .map_err(|_| anyhow::anyhow!("the merge still runs after 60 s"))?;
    let Err(Some(members)) = result else {
        anyhow::bail!("expected the missing members, got {result:?}");
    };
    ensure!(
        members.starts_with("2, 4, 6, ")
            && members.contains(" ... (499999999999999999 in all) of its shard 1/2"),
        "{members}"
    );
    Ok(())
}

/// A sweep run without `--resume` over an `OUT.partial` leaves it as it is, and advises
/// `--resume` only when that would continue it: for this sweep's unfinished run, not for
/// another sweep's or for a record that `simulate` left.
#[test]
fn a_sweep_over_an_unfinished_file_advises_resume_only_for_its_own() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let full = dir.path().join("full.csv");
    run(&options("0.1,0.3", None)?, &full)?;
    let text = std::fs::read_to_string(&full)?;
    let own: String = text.lines().take(3).map(|l| format!("{l}\n")).collect();
    let out = dir.path().join("out.csv");
    let partial = partial_path(&out);
    let record = "t,y,v,PN1,PT1,A1,T,V,dissipated\n0,1,0,0,0,0,0,8.829,0\n";
    for (content, other, advice) in [
        (own.as_str(), options("0.1,0.3", None)?, "pass --resume to continue it"),
        (own.as_str(), options("0.1,0.4", None)?, "which --resume would not continue"),
        (record, options("0.1,0.3", None)?, "is not an unfinished run of a sweep"),
    ] {
        std::fs::write(&partial, content)?;
        let e = run(&other, &out).expect_err("an unfinished file");
        let message = format!("{e:#}");
        ensure!(message.contains(advice), "{message}");
        ensure!(message.contains(&partial.display().to_string()), "{message}");
        ensure!(std::fs::read_to_string(&partial)? == content && !out.exists());
        // The advice holds: --resume continues this sweep's run and refuses the others.
        let resumed = run(&SweepOptions { resume: true, ..other }, &out);
        ensure!(resumed.is_ok() == advice.starts_with("pass"), "{advice}: {resumed:?}");
        let _ = std::fs::remove_file(&out);
    }
    Ok(())
}
