//! Sweeps whose keys vary together: a pendulum released from several angles, its bob's
//! position and the hinge's anchor on it linked (`--set +key=...`), against the closed forms
//! of the pendulum's approach to the wall; the product of the same keys refused, since most
//! of its members open the joint.

use std::path::{Path, PathBuf};
use std::process::Command;

use anyhow::{Context, Result, ensure};
use moreau_cli::CliError;
use moreau_cli::grid::Axis;
use moreau_cli::sweep::{SweepOptions, run as sweep};

fn pendulum() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/bodies/pendulum-wall.toml")
}

fn column(headers: &[String], name: &str) -> Result<usize> {
    headers.iter().position(|h| h == name).with_context(|| format!("no column {name}"))
}

/// Release angles (rad, to the left of the vertical) and their `--set` axes: the bob's
/// position (sin φ0, −cos φ0) and the hinge's anchor on the bob, the hinge seen from the bob.
fn release(angles: &[f64]) -> (String, String) {
    let join = |f: &dyn Fn(f64) -> String| angles.iter().map(|&a| f(a)).collect::<Vec<_>>();
    let position = join(&|a| format!("[{}, {}]", (-a).sin(), -a.cos()));
    let anchor = join(&|a| format!("[{}, {}]", a.sin(), a.cos()));
    (
        format!("bodies.bob.position={}", position.join(",")),
        format!("joints.hinge.anchor_b={}", anchor.join(",")),
    )
}

/// The bob (m = 1 kg, I = 1.25e-3 kg m² about its centre) on a rod of L = 1 m released from
/// φ0: its speed at the bottom, L φ̇ with (m L² + I) φ̇²/2 = m g L (1 − cos φ0), and the time
/// it takes to get there, a quarter of the large-amplitude period, K(sin(φ0/2))/ω0 with
/// ω0² = m g L/(m L² + I) and K(k) = π / (2 AGM(1, sqrt(1 − k²))).
fn closed_form(phi0: f64) -> (f64, f64) {
    let (g, m, l) = (9.81, 1.0, 1.0);
    let j = m * l * l + 1.25e-3;
    let speed = l * (2.0 * m * g * l * (1.0 - phi0.cos()) / j).sqrt();
    let k = (0.5 * phi0).sin();
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..10 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    (speed, std::f64::consts::FRAC_PI_2 / a / (m * g * l / j).sqrt())
}

#[test]
fn linked_keys_release_the_pendulum_from_each_angle() -> Result<()> {
    let angles = [0.3, 0.5, 0.7];
    let (position, anchor) = release(&angles);
    let axes = vec![
        Axis::parse(&position)?,
        Axis::parse(&format!("+{anchor}"))?,
        Axis::parse("contacts.hit.eps_n=0.5,0.8")?,
        Axis::parse("t_end=1")?,
    ];
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("release.csv");
    let summary = sweep(&SweepOptions::scene(&pendulum(), axes), &out)?;
    // Three angles times two restitutions: the linked axis does not multiply the grid.
    assert_eq!((summary.rows, summary.diverged, summary.failed), (6, 0, 0));
    let part = moreau_cli::parts::read_part(&out, false)?;
    let h = &part.columns;
    let keys = [
        "bodies.bob.position",
        "joints.hinge.anchor_b",
        "contacts.hit.eps_n",
        "hit.first_impact_gamma_pre",
        "hit.first_impact_gamma_post",
        "hit.first_impact_t",
    ];
    let at = keys.map(|k| column(h, k));
    let [x0, anchor_b, eps, pre, post, t] = at.map(|c| c.expect("a column of the sweep"));
    let dt = 1e-4;
    for (member, (_, row)) in part.rows.iter().enumerate() {
        let phi0 = angles[member / 2];
        // Each row carries the values of its member, the linked pair from one angle.
        let (p, a) = (&row[x0], &row[anchor_b]);
        ensure!(p.starts_with(&format!("[{}, ", (-phi0).sin())), "member {member}: {p}");
        ensure!(a.starts_with(&format!("[{}, ", phi0.sin())), "member {member}: {a}");
        let get = |j: usize| -> Result<f64> { Ok(row[j].parse::<f64>()?) };
        let (e, before, after, first) = (get(eps)?, get(pre)?, get(post)?, get(t)?);
        ensure!(e == [0.5, 0.8][member % 2], "member {member}: eps_n {e}");
        let (speed, quarter) = closed_form(phi0);
        // The midpoint step errs on the energy by O(Δt²): 7e-9 of the speed at 0.5 rad.
        ensure!((before + speed).abs() < 1e-6 * speed, "φ0 = {phi0}: approach {before} ≠ {speed}");
        ensure!((-after / before - e).abs() < 1e-8, "φ0 = {phi0}: {after} / {before}");
        // The first impact is the midpoint of the first step whose midpoint gap is closed.
        let late = first - quarter;
        ensure!((-1e-7..dt + 1e-7).contains(&late), "φ0 = {phi0}: impact at {first}, {quarter}");
    }
    Ok(())
}

#[test]
fn the_product_of_the_same_keys_opens_the_joint_and_is_refused() -> Result<()> {
    let (position, anchor) = release(&[0.3, 0.5]);
    let axes = vec![Axis::parse(&position)?, Axis::parse(&anchor)?];
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("product.csv");
    let e = sweep(&SweepOptions::scene(&pendulum(), axes), &out).unwrap_err();
    // Member 1 releases the bob from 0.3 rad with the anchor of 0.5 rad: 0.2 m apart.
    let text = format!("{e:#}");
    ensure!(text.contains("correct the position or the joint's anchors"), "{text}");
    ensure!(!out.exists(), "nothing is written for a refused sweep");
    Ok(())
}

#[test]
fn the_command_line_links_a_key_with_a_leading_plus() -> Result<()> {
    let (position, anchor) = release(&[0.3, 0.5]);
    let dir = tempfile::tempdir()?;
    let out = dir.path().join("cli.csv");
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_moreau")).args(args).output();
        out.unwrap_or_else(|e| panic!("cannot start moreau: {e}"))
    };
    let scene = pendulum();
    let scene = scene.to_str().context("a UTF-8 path")?;
    let out_arg = out.to_str().context("a UTF-8 path")?;
    let linked = format!("+{anchor}");
    let base = ["sweep", "--scene", scene, "--set", "t_end=0.2", "--set"];
    let ran = run(&[&base[..], &[position.as_str(), "--set", &linked, "--out", out_arg]].concat());
    ensure!(ran.status.success(), "{}", String::from_utf8_lossy(&ran.stderr));
    let part = moreau_cli::parts::read_part(&out, false)?;
    assert_eq!(part.rows.len(), 2);
    // A linked key with another number of values is refused before anything runs, naming it.
    let short = format!("+{}", anchor.split_once("],").context("two values")?.0) + "]";
    let refused =
        run(&[&base[..], &[position.as_str(), "--set", &short, "--out", out_arg]].concat());
    ensure!(!refused.status.success());
    let stderr = String::from_utf8_lossy(&refused.stderr);
    ensure!(
        stderr.contains("has 1 value, and `bodies.bob.position`, with which it takes them, has 2"),
        "{stderr}"
    );
    let first = Axis::parse(&linked)?;
    let e = moreau_cli::grid::Grid::new(vec![first]).unwrap_err();
    ensure!(matches!(e.downcast_ref::<CliError>(), Some(CliError::BadOption { .. })), "{e}");
    Ok(())
}
