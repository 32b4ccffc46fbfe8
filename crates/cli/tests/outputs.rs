//! The output files of `simulate`, `sweep`, `merge` and `solve`: never an input of the run or
//! another of its outputs, written through a symbolic link, never over a file that is not a
//! regular file, locked while a run writes them, and without the files an earlier run left.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, ensure};
use moreau_cli::CliError;
use moreau_cli::grid::Axis;
use moreau_cli::output::{LockOwner, lock_path};
use moreau_cli::parts::merge;
use moreau_cli::simulate::{SimulateOptions, partial_path, run_to_csv};
use moreau_cli::sweep::{SweepOptions, run as sweep};
use moreau_lcp::Lcp;

fn pendulum() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies/pendulum-wall.toml")
}

fn cli_error(e: &anyhow::Error) -> Option<&CliError> {
    e.chain().find_map(|c| c.downcast_ref::<CliError>())
}

/// The pendulum's scene copied to `dir/name`, run for 10 ms.
fn scene_in(dir: &Path, name: &str) -> Result<(PathBuf, SimulateOptions)> {
    let path = dir.join(name);
    std::fs::copy(pendulum(), &path)?;
    let options =
        SimulateOptions { scene: Some(path.clone()), tf: Some(0.01), ..Default::default() };
    Ok((path, options))
}

/// A ball sweep of two short members.
fn ball_sweep(eps: &str) -> Result<SweepOptions> {
    let axes = vec![Axis::parse(&format!("eps_n={eps}"))?, Axis::parse("t_end=0.05")?];
    Ok(SweepOptions::new("ball", axes))
}

/// An LCP of three rows with a solution, written in Siconos' format to `path`.
fn lcp_file(path: &Path) -> Result<()> {
    let rows = vec![vec![4.0, 1.0, 0.0], vec![1.0, 3.0, 1.0], vec![0.0, 1.0, 2.0]];
    Lcp::from_rows(&rows, &[-4.0, 2.0, -4.0])?.write_siconos(std::fs::File::create(path)?)?;
    Ok(())
}

/// Whether `e` is the output error for `path` and its reason contains `needle`.
fn refused(e: &anyhow::Error, path: &Path, needle: &str) -> bool {
    matches!(cli_error(e), Some(CliError::Output { path: p, reason }) if p == path && reason.contains(needle))
}

/// The names of the files in `dir`, sorted.
fn listing(dir: &Path) -> Result<Vec<String>> {
    let mut names: Vec<String> = std::fs::read_dir(dir)?
        .map(|e| Ok(e?.file_name().to_string_lossy().into_owned()))
        .collect::<Result<_>>()?;
    names.sort();
    Ok(names)
}

#[test]
fn an_output_that_is_an_input_or_another_output_is_refused() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let d = dir.path();
    let (scene, options) = scene_in(d, "s.toml")?;
    let original = std::fs::read(&scene)?;
    // The scene file itself, by its name, through `.` and `..`, or through a symbolic link.
    std::fs::create_dir(d.join("sub"))?;
    std::os::unix::fs::symlink("s.toml", d.join("alias.toml"))?;
    for out in [scene.clone(), d.join("./sub/../s.toml"), d.join("alias.toml")] {
        let e = run_to_csv(&options, &out, &mut |_| {}).expect_err("simulate over its scene");
        ensure!(refused(&e, &out, "s.toml"), "{}: {e:#}", out.display());
        let e = sweep(&SweepOptions::scene(&scene, vec![Axis::parse("t_end=0.01")?]), &out)
            .expect_err("sweep over its scene");
        ensure!(refused(&e, &out, "is the input"), "{e:#}");
        let contacts = SimulateOptions { contacts: Some(out.clone()), ..options.clone() };
        let e = run_to_csv(&contacts, &d.join("r.csv"), &mut |_| {}).expect_err("contacts");
        ensure!(refused(&e, &out, "is the input"), "{e:#}");
    }
    // An output whose unfinished file would be the scene.
    let (partial_scene, options_p) = scene_in(d, "p.csv.partial")?;
    let e = run_to_csv(&options_p, &d.join("p.csv"), &mut |_| {}).expect_err("partial");
    ensure!(refused(&e, &d.join("p.csv"), "would be written first"), "{e:#}");
    ensure!(std::fs::read(&partial_scene)? == original);
    std::fs::remove_file(&partial_scene)?;
    // The record and the contacts in one file, named two ways.
    let both = SimulateOptions { contacts: Some(d.join("./s.csv")), ..options.clone() };
    let e = run_to_csv(&both, &d.join("s.csv"), &mut |_| {}).expect_err("one file");
    ensure!(refused(&e, &d.join("./s.csv"), "the same file as the output"), "{e:#}");
    ensure!(std::fs::read(&scene)? == original, "the scene was changed");
    ensure!(listing(d)? == ["alias.toml", "s.toml", "sub"], "{:?}", listing(d)?);
    // `solve` over its problem file, `merge` over one of its parts.
    let problem = d.join("p.dat");
    lcp_file(&problem)?;
    let text = std::fs::read(&problem)?;
    let e = moreau_cli::solve::run(&problem, None, None, None, Some(&d.join("./p.dat")))
        .expect_err("solve over its problem");
    ensure!(refused(&e, &d.join("./p.dat"), "p.dat"), "{e:#}");
    ensure!(std::fs::read(&problem)? == text, "the problem was changed");
    let part = d.join("k.csv");
    sweep(&ball_sweep("0.1,0.3")?, &part)?;
    let text = std::fs::read(&part)?;
    let e = merge(&d.join("sub/../k.csv"), &[&part]).expect_err("merge over its part");
    ensure!(refused(&e, &d.join("sub/../k.csv"), "k.csv"), "{e:#}");
    ensure!(std::fs::read(&part)? == text, "the part was changed");
    Ok(())
}

#[test]
fn a_symbolic_link_is_written_through_and_a_fifo_is_refused() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let d = dir.path();
    let (_, options) = scene_in(d, "s.toml")?;
    std::fs::create_dir(d.join("real"))?;
    let target = d.join("real/target.csv");
    std::fs::write(&target, "old\n")?;
    let link = d.join("link.csv");
    std::os::unix::fs::symlink("real/target.csv", &link)?;
    let done = run_to_csv(&options, &link, &mut |_| {})?;
    ensure!(std::fs::symlink_metadata(&link)?.file_type().is_symlink(), "the link was replaced");
    ensure!(std::fs::read_link(&link)? == Path::new("real/target.csv"));
    let text = std::fs::read_to_string(&target)?;
    ensure!(text.starts_with("t,bob.x,") && text.lines().count() as u64 == done.rows + 1, "{text}");
    ensure!(listing(d)? == ["link.csv", "real", "s.toml"], "{:?}", listing(d)?);
    ensure!(listing(&d.join("real"))? == ["target.csv"], "{:?}", listing(&d.join("real"))?);
    // A sweep and a merge through a link to a file that does not exist yet create it.
    let (part, merged) = (d.join("part.csv"), d.join("merged.csv"));
    std::os::unix::fs::symlink("real/part.csv", &part)?;
    std::os::unix::fs::symlink("real/merged.csv", &merged)?;
    sweep(&ball_sweep("0.1,0.3")?, &part)?;
    merge(&merged, &[&part])?;
    ensure!(listing(&d.join("real"))? == ["merged.csv", "part.csv", "target.csv"]);
    for link in [&part, &merged] {
        ensure!(std::fs::symlink_metadata(link)?.file_type().is_symlink());
    }
    // A folder, and a FIFO, are not replaced.
    let e = run_to_csv(&options, &d.join("real"), &mut |_| {}).expect_err("folder");
    ensure!(refused(&e, &d.join("real"), "a folder"), "{e:#}");
    let fifo = d.join("fifo");
    match std::process::Command::new("mkfifo").arg(&fifo).status() {
        Ok(status) if status.success() => {
            use std::os::unix::fs::FileTypeExt;
            let e = run_to_csv(&options, &fifo, &mut |_| {}).expect_err("fifo");
            ensure!(refused(&e, &fifo, "a FIFO"), "{e:#}");
            ensure!(std::fs::symlink_metadata(&fifo)?.file_type().is_fifo(), "replaced");
            ensure!(!partial_path(&fifo).exists() && !lock_path(&fifo).exists());
        }
        _ => println!("mkfifo is not available: the FIFO is not tried"),
    }
    Ok(())
}

#[test]
fn a_locked_output_is_refused_and_left_as_it_is() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let d = dir.path();
    let (_, options) = scene_in(d, "s.toml")?;
    let out = d.join("out.csv");
    let (partial, lock) = (partial_path(&out), lock_path(&out));
    std::fs::write(&out, "old\n")?;
    std::fs::write(&partial, "unfinished\n")?;
    std::fs::write(&lock, "4242\n")?;
    let locked = |e: &anyhow::Error| {
        matches!(cli_error(e), Some(CliError::Locked { lock: l, holder, .. }) if *l == lock && holder == "4242")
            && format!("{e:#}").contains("remove")
    };
    let e = run_to_csv(&options, &out, &mut |_| {}).expect_err("simulate");
    ensure!(locked(&e), "{e:#}");
    let e =
        sweep(&SweepOptions { resume: true, ..ball_sweep("0.1,0.3")? }, &out).expect_err("sweep");
    ensure!(locked(&e), "{e:#}");
    let problem = d.join("p.dat");
    lcp_file(&problem)?;
    let e = moreau_cli::solve::run(&problem, None, None, None, Some(&out)).expect_err("solve");
    ensure!(locked(&e), "{e:#}");
    let e = merge(&out, &[d.join("k.csv")]).expect_err("merge");
    ensure!(locked(&e), "{e:#}");
    ensure!(std::fs::read_to_string(&out)? == "old\n");
    ensure!(std::fs::read_to_string(&partial)? == "unfinished\n");
    ensure!(std::fs::read_to_string(&lock)? == "4242\n");
    // Without the lock each writer runs, and leaves no lock behind, failing or not.
    std::fs::remove_file(&lock)?;
    std::fs::remove_file(&partial)?;
    run_to_csv(&options, &out, &mut |_| {})?;
    ensure!(!lock.exists());
    // The woodpecker's step of 10 ms lies above its stability limit.
    let diverging = SimulateOptions {
        model: Some("woodpecker".into()),
        dt: Some(1e-2),
        ..SimulateOptions::default()
    };
    ensure!(run_to_csv(&diverging, &out, &mut |_| {}).is_err());
    ensure!(!lock.exists() && partial.exists());
    std::fs::remove_file(&partial)?;
    let part = d.join("k.csv");
    sweep(&ball_sweep("0.1,0.3")?, &part)?;
    merge(&out, &[&part])?;
    moreau_cli::solve::run(&problem, None, None, None, Some(&d.join("z.csv")))?;
    ensure!(listing(d)? == ["k.csv", "out.csv", "p.dat", "s.toml", "z.csv"], "{:?}", listing(d)?);
    Ok(())
}

#[test]
fn resuming_over_a_finished_sweep_keeps_it() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("k.csv");
    let first = sweep(&ball_sweep("0.1,0.3")?, &out)?;
    ensure!(first.ran == 2 && !first.finished_before);
    let text = std::fs::read(&out)?;
    // Another sweep's --resume is refused, and the file kept.
    let other = SweepOptions { resume: true, ..ball_sweep("0.2,0.4")? };
    let e = sweep(&other, &out).expect_err("another sweep");
    let message = format!("{e:#}");
    ensure!(
        matches!(cli_error(&e), Some(CliError::MixedParts { part, .. }) if *part == out),
        "{message}"
    );
    ensure!(message.contains("another sweep") && message.contains("--resume"), "{message}");
    ensure!(std::fs::read(&out)? == text, "the finished sweep was changed");
    // The same sweep's --resume finds nothing left to run.
    let same = sweep(&SweepOptions { resume: true, ..ball_sweep("0.1,0.3")? }, &out)?;
    ensure!(same.finished_before && same.ran == 0 && same.rows == 2, "{same:?}");
    ensure!(std::fs::read(&out)? == text, "the finished sweep was changed");
    // The command says so.
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_moreau"))
        .args(["sweep", "ball", "--set", "eps_n=0.1,0.3", "--set", "t_end=0.05", "--resume"])
        .arg("--out")
        .arg(&out)
        .output()?;
    let stdout = String::from_utf8_lossy(&o.stdout);
    ensure!(o.status.success() && stdout.contains("nothing is left to run"), "{stdout}");
    ensure!(std::fs::read(&out)? == text, "the finished sweep was changed");
    Ok(())
}

#[test]
fn a_new_sweep_removes_the_problems_of_an_earlier_ones_members() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let d = dir.path();
    let out = d.join("k.csv");
    for name in [
        "k.csv.member-1.failed.dat",
        "k.csv.member-12.failed.dat",
        "k.csv.member-x.failed.dat",
        "other.csv.member-1.failed.dat",
    ] {
        std::fs::write(d.join(name), "3\n")?;
    }
    let s = sweep(&ball_sweep("0.1,0.3")?, &out)?;
    ensure!(s.failed == 0 && s.diverged == 0);
    let names = listing(d)?;
    ensure!(
        names == ["k.csv", "k.csv.member-x.failed.dat", "other.csv.member-1.failed.dat"],
        "{names:?}"
    );
    // A resumed sweep keeps those of its finished members.
    let kept = d.join("k.csv.member-1.failed.dat");
    std::fs::write(&kept, "3\n")?;
    let text = std::fs::read_to_string(&out)?;
    let lines: Vec<&str> = text.lines().collect();
    std::fs::write(partial_path(&out), format!("{}\n", lines[..3].join("\n")))?;
    let s = sweep(&SweepOptions { resume: true, ..ball_sweep("0.1,0.3")? }, &out)?;
    ensure!(s.ran == 1 && kept.exists(), "{s:?}");
    Ok(())
}

#[test]
fn the_folder_of_an_output_must_exist() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let (_, options) = scene_in(dir.path(), "s.toml")?;
    let out = dir.path().join("no/such/x.csv");
    let e = run_to_csv(&options, &out, &mut |_| {}).expect_err("no folder");
    ensure!(refused(&e, &out, "cannot be found"), "{e:#}");
    let text = format!("{e:#}");
    ensure!(text.contains("no/such"), "{text}");
    Ok(())
}

/// `moreau` with `args` under a limit of 2 blocks (1 or 2 KiB) on the size of the files it
/// writes: with `killed`, a write past it kills the process; otherwise it fails, as on a full
/// disk.
fn moreau_limited(args: &[&std::ffi::OsStr], killed: bool) -> Result<std::process::Output> {
    let script = if killed {
        "ulimit -f 2; exec \"$0\" \"$@\""
    } else {
        "trap '' XFSZ; ulimit -f 2; exec \"$0\" \"$@\""
    };
    Ok(std::process::Command::new("sh")
        .args(["-c", script, env!("CARGO_BIN_EXE_moreau")])
        .args(args)
        .output()?)
}

#[test]
fn a_write_stopped_by_a_full_disk_or_a_kill_leaves_the_former_files() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let d = dir.path();
    // A part of 40 members, some 4 KB: more than the limit.
    let eps: Vec<String> = (1..=40).map(|i| format!("{:.2}", f64::from(i) / 100.0)).collect();
    let eps = format!("eps_n={}", eps.join(","));
    let axes = vec![Axis::parse(&eps)?, Axis::parse("t_end=0.05")?];
    let part = d.join("part.csv");
    sweep(&SweepOptions::new("ball", axes), &part)?;
    ensure!(std::fs::metadata(&part)?.len() > 2048);
    let out = d.join("out.csv");
    let former = "a former output\n".repeat(500);
    std::fs::write(&out, &former)?;
    let merge_args = ["merge".as_ref(), "--out".as_ref(), out.as_os_str(), part.as_os_str()];
    // A merge whose write fails ends in an error naming the file, and leaves the output.
    let o = moreau_limited(&merge_args, false)?;
    let stderr = String::from_utf8_lossy(&o.stderr);
    ensure!(o.status.code() == Some(1), "{:?}: {stderr}", o.status);
    ensure!(stderr.contains("out.csv.tmp: cannot be written"), "{stderr}");
    ensure!(stderr.contains("out.csv is left as it was"), "{stderr}");
    ensure!(std::fs::read_to_string(&out)? == former, "the former output was changed");
    ensure!(listing(d)? == ["out.csv", "part.csv"], "{:?}", listing(d)?);
    // A merge killed while writing leaves it too.
    let o = moreau_limited(&merge_args, true)?;
    ensure!(!o.status.success(), "{:?}", o.status);
    ensure!(std::fs::read_to_string(&out)? == former, "the former output was changed");
    // The next merge replaces what the killed one left, its lock included.
    merge(&out, &[&part])?;
    ensure!(std::fs::read(&out)? == std::fs::read(&part)?);
    ensure!(listing(d)? == ["out.csv", "part.csv"], "{:?}", listing(d)?);
    // A resumed sweep whose rewrite of its unfinished rows fails keeps them, and the output.
    let resumed = d.join("resumed.csv");
    std::fs::write(&resumed, &former)?;
    let text = std::fs::read_to_string(&part)?;
    let cut = text[..3000].rfind('\n').context("a line end")? + 1;
    std::fs::write(partial_path(&resumed), &text[..cut])?;
    let resume_args = [
        "sweep".as_ref(),
        "ball".as_ref(),
        "--set".as_ref(),
        eps.as_ref(),
        "--set".as_ref(),
        "t_end=0.05".as_ref(),
        "--resume".as_ref(),
        "--out".as_ref(),
        resumed.as_os_str(),
    ];
    let o = moreau_limited(&resume_args, false)?;
    let stderr = String::from_utf8_lossy(&o.stderr);
    ensure!(o.status.code() == Some(1), "{:?}: {stderr}", o.status);
    ensure!(std::fs::read_to_string(partial_path(&resumed))? == text[..cut], "rows were lost");
    ensure!(std::fs::read_to_string(&resumed)? == former, "the former output was changed");
    Ok(())
}

#[test]
fn a_lock_left_by_a_killed_run_is_taken_over_and_a_running_ones_kept() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let d = dir.path();
    let out = d.join("ball.csv");
    let lock = lock_path(&out);
    let moreau = |tf: &str| {
        let mut c = std::process::Command::new(env!("CARGO_BIN_EXE_moreau"));
        c.args(["simulate", "ball", "--tf", tf, "--out"]).arg(&out);
        c
    };
    // A run of 10^7 steps, killed once it holds its lock.
    let mut long = moreau("10000").stderr(std::process::Stdio::null()).spawn()?;
    let start = std::time::Instant::now();
    while !lock.exists() {
        ensure!(start.elapsed().as_secs() < 60, "the run took no lock");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    long.kill()?;
    long.wait()?;
    let left = LockOwner::parse(&std::fs::read_to_string(&lock)?);
    ensure!(left.pid == Some(long.id()) && left.host.is_some(), "{left:?}");
    // The next run takes the lock over, says so, and removes it at its end.
    let o = moreau("0.05").output()?;
    let stderr = String::from_utf8_lossy(&o.stderr);
    ensure!(o.status.success(), "{stderr}");
    let note = format!("note: took over the lock {} of process {}", lock.display(), long.id());
    ensure!(stderr.contains(&note), "{stderr}");
    ensure!(std::fs::read_to_string(&out)?.lines().count() == 52);
    ensure!(!lock.exists());
    // A lock of a process that runs (this one), or of another host, is kept.
    let running = LockOwner::this_process();
    let elsewhere = LockOwner { host: Some("elsewhere.example".into()), ..left };
    for (owner, why) in [
        (&running, format!("its process {} runs", std::process::id())),
        (&elsewhere, format!("process {} runs on host elsewhere.example", long.id())),
    ] {
        std::fs::write(&lock, owner.text())?;
        let o = moreau("0.05").output()?;
        let stderr = String::from_utf8_lossy(&o.stderr);
        ensure!(o.status.code() == Some(1) && stderr.contains(&why), "{stderr}");
        ensure!(std::fs::read_to_string(&lock)? == owner.text());
    }
    Ok(())
}

/// A run that fails leaves its rows in OUT.partial only: the OUT of an earlier run that
/// succeeded on the same output, which does not describe it, is removed.
#[test]
fn a_failed_run_removes_the_output_of_an_earlier_one() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("w.csv");
    let simulate = |dt: &str| {
        std::process::Command::new(env!("CARGO_BIN_EXE_moreau"))
            .args(["simulate", "woodpecker", "--set", "t_end=0.02", "--dt", dt, "--out"])
            .arg(&out)
            .output()
    };
    let o = simulate("1e-4")?;
    ensure!(o.status.success() && out.exists(), "{}", String::from_utf8_lossy(&o.stderr));
    // Δt = 1e-2 is above the woodpecker's stability limit: the run diverges.
    let o = simulate("1e-2")?;
    let stderr = String::from_utf8_lossy(&o.stderr);
    ensure!(o.status.code() == Some(1) && stderr.contains("diverged"), "{stderr}");
    ensure!(!out.exists(), "the former output is left beside the failed run's rows");
    ensure!(partial_path(&out).exists(), "{stderr}");
    Ok(())
}
