//! The analyses behind the key numbers, on records built by hand.

use std::time::Duration;

use anyhow::{Result, ensure};
use moreau_cli::analysis::cam_lobes;
use moreau_stepper::ContactState::{Open as O, Stick as S};

/// A lobe's rows are those whose step midpoint lies in it, from its start (included) to its
/// end (left out); a lobe that the record does not complete is not reported.
#[test]
fn cam_lobes_take_the_rows_whose_midpoints_they_hold() {
    // Midpoints 0.25, 1.0 (the start of lobe 1) and 2.0 (lobe 2, incomplete at t = 2.5).
    let t = [0.0, 0.5, 1.5, 2.5];
    let phase = [O, O, S, O];
    let gap = [0.1, 0.05, 0.0, 0.01];
    let gamma = [0.0, 0.0, -2.0, 0.0];
    let lobes = cam_lobes(&t, &gap, &phase, &gamma, 1.0, 1e-3);
    let seen: Vec<(usize, f64, usize)> =
        lobes.iter().map(|l| (l.lobe, l.drop_time, l.impacts)).collect();
    assert_eq!(seen, [(0, 0.0, 0), (1, 1.0, 1)]);
    assert_eq!(lobes[1].impact_times, [1.0]);
}

/// A cam that turns through 21 billion lobes over a record of ten rows reports the ten
/// lobes that hold a row, at once: the lobes were visited one by one, each looking through
/// every row, so that a sweep member of the cam at ω = 1e9 rad/s over 500 steps took 45 s in
/// its key numbers.
#[test]
fn cam_lobes_skip_the_lobes_without_rows() -> Result<()> {
    // Steps of 2⁻³ s and lobes of 2⁻³⁴ s: every time is exact, and row k's midpoint
    // (k − 1/2) 2⁻³ s is the start of lobe (k − 1/2) 2³¹, of 1.25 · 2³⁴ lobes in all.
    let t: Vec<f64> = (0..=10).map(|k| f64::from(k) * 0.125).collect();
    let phase = vec![O; 11];
    let gap = vec![0.1; 11];
    let gamma = vec![0.0; 11];
    let period = 2f64.powi(-34);
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(cam_lobes(&t, &gap, &phase, &gamma, period, 1e-3));
    });
    let lobes = rx.recv_timeout(Duration::from_secs(60))?;
    let numbers: Vec<usize> = lobes.iter().map(|l| l.lobe).collect();
    let expected: Vec<usize> = (1..=10).map(|k| (2 * k - 1) << 30).collect();
    ensure!(numbers == expected, "{numbers:?} vs {expected:?}");
    let drops: Vec<f64> = lobes.iter().map(|l| l.drop_time).collect();
    let mids: Vec<f64> = (1..=10).map(|k| (f64::from(k) - 0.5) * 0.125).collect();
    ensure!(drops == mids, "{drops:?}");
    ensure!(lobes.iter().all(|l| l.impacts == 0 && l.time_to_contact.is_none()));
    Ok(())
}
