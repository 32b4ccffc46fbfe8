//! Numbers in the CSV files: the shortest text that reads back exactly, with an exponent when
//! that is shorter, written by `simulate`, `sweep` and `solve` and read back by `--resume` and
//! `merge`.

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, ensure};
use moreau_cli::parts::read_part;
use moreau_cli::simulate::partial_path;
use moreau_lcp::Lcp;

fn ball() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies/ball.toml")
}

/// Runs `moreau` with `args` and returns its standard output, or fails with its error.
fn moreau<S: AsRef<OsStr>>(args: &[S]) -> Result<String> {
    let o = Command::new(env!("CARGO_BIN_EXE_moreau")).args(args).output()?;
    let stderr = String::from_utf8_lossy(&o.stderr);
    ensure!(o.status.success(), "{:?}: {stderr}", o.status);
    Ok(String::from_utf8(o.stdout)?)
}

#[test]
fn tiny_numbers_are_written_with_an_exponent_and_read_back() -> Result<()> {
    let dir = tempfile::tempdir()?;
    let d = dir.path();
    let ball = ball();
    // The record of a ball that falls under a gravity of 1e-30 m/s².
    let out = d.join("c.csv");
    let (scene, out_s) = (ball.as_os_str(), out.as_os_str());
    moreau(&[
        "simulate".as_ref(),
        "--scene".as_ref(),
        scene,
        "--set".as_ref(),
        "t_end=0.003".as_ref(),
        "--set".as_ref(),
        "gravity=[0,-1e-30]".as_ref(),
        "--out".as_ref(),
        out_s,
    ])?;
    let text = std::fs::read_to_string(&out)?;
    // The last columns are T = ½ (k 1e-33)², V = m g y = 1e-30, nothing dissipated and
    // nothing projected.
    let expected = "t,ball.x,ball.y,ball.theta,ball.vx,ball.vy,ball.omega,floor.PN,floor.PT,\
                    floor.active,T,V,dissipated,projected\n0,0,1,0,0,0,0,0,0,0,0,1e-30,0,0\n\
                    0.001,0,1,0,0,-1e-33,0,0,0,0,5.0000000000000005e-67,1e-30,0,0\n\
                    0.002,0,1,0,0,-2e-33,0,0,0,0,2.0000000000000002e-66,1e-30,0,0\n\
                    0.003,0,1,0,0,-3e-33,0,0,0,0,4.5000000000000003e-66,1e-30,0,0\n";
    ensure!(text == expected, "{text}");
    // A sweep's key numbers, resumed and merged.
    let part = d.join("part.csv");
    let sweep = |out: &Path, resume: bool| {
        let mut args: Vec<&OsStr> = vec![
            "sweep".as_ref(),
            "--scene".as_ref(),
            scene,
            "--set".as_ref(),
            "gravity.1=-1e-30,-3e-30,-2e-300".as_ref(),
            "--set".as_ref(),
            "t_end=0.003".as_ref(),
            "--out".as_ref(),
            out.as_os_str(),
        ];
        if resume {
            args.push("--resume".as_ref());
        }
        moreau(&args)
    };
    sweep(&part, false)?;
    let read = read_part(&part, false)?;
    let energy = read.columns.iter().position(|c| c == "energy_end").context("energy_end")?;
    let cells: Vec<&str> = read.rows.iter().map(|(_, r)| r[energy].as_str()).collect();
    ensure!(cells == ["1e-30", "3e-30", "2e-300"], "{cells:?}");
    // A resumed sweep keeps the rows it reads, and merge takes them as they are.
    let resumed = d.join("resumed.csv");
    let text = std::fs::read_to_string(&part)?;
    let lines: Vec<&str> = text.lines().collect();
    std::fs::write(partial_path(&resumed), format!("{}\n", lines[..4].join("\n")))?;
    let said = sweep(&resumed, true)?;
    ensure!(said.contains("(1 run now"), "{said}");
    let again = read_part(&resumed, false)?;
    ensure!(again.rows[..2] == read.rows[..2], "{:?}", again.rows);
    ensure!(again.rows[2].1[energy] == "2e-300");
    let merged = d.join("merged.csv");
    moreau(&[OsStr::new("merge"), OsStr::new("--out"), merged.as_os_str(), part.as_os_str()])?;
    ensure!(std::fs::read_to_string(&merged)? == text);
    // The solution of an LCP whose z is 1e-30.
    let problem = d.join("p.dat");
    Lcp::from_rows(&[vec![1.0]], &[-1e-30])?.write_siconos(std::fs::File::create(&problem)?)?;
    let z = d.join("z.csv");
    moreau(&[OsStr::new("solve"), problem.as_os_str(), "--out".as_ref(), z.as_os_str()])?;
    let text = std::fs::read_to_string(&z)?;
    ensure!(text == "i,z,w\n0,1e-30,0\n", "{text}");
    Ok(())
}
