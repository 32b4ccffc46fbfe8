//! Reading a [`Record`]: impact onsets, crossings, interpolated velocities, finiteness,
//! energy gain and penetration; and the path of a shipped scene file.

use std::path::{Path, PathBuf};

use moreau_kinematics::ContactKinematics;
use moreau_stepper::Record;

/// Rows at which contact `i` starts to carry an impulse (P_N > 0 after a row with P_N = 0).
pub fn onsets(r: &Record, i: usize) -> Vec<usize> {
    (1..r.len()).filter(|&k| r.p_n[k][i] > 0.0 && r.p_n[k - 1][i] == 0.0).collect()
}

/// Times at which coordinate `j` crosses `value` upwards, by linear interpolation between rows.
pub fn up_crossings(r: &Record, j: usize, value: f64) -> Vec<f64> {
    (1..r.len())
        .filter_map(|k| {
            let (a, b) = (r.q[k - 1][j] - value, r.q[k][j] - value);
            (a < 0.0 && b >= 0.0).then(|| r.t[k - 1] + (-a) / (b - a) * (r.t[k] - r.t[k - 1]))
        })
        .collect()
}

/// Velocity `l` interpolated linearly at the first instant coordinate `j` reaches `value`
/// from below; `None` if it never does.
pub fn velocity_at(r: &Record, j: usize, value: f64, l: usize) -> Option<f64> {
    let k = (1..r.len()).find(|&k| r.q[k - 1][j] < value && r.q[k][j] >= value)?;
    let s = (value - r.q[k - 1][j]) / (r.q[k][j] - r.q[k - 1][j]);
    Some(r.u[k - 1][l] + s * (r.u[k][l] - r.u[k - 1][l]))
}

/// Whether every number of a record (state, impulses of contacts and joints, energies) is
/// finite.
pub fn record_is_finite(r: &Record) -> bool {
    let rows = r.q.iter().chain(&r.u).chain(&r.p_n).chain(&r.p_t).chain(&r.joint_impulses);
    rows.flatten().all(|x| x.is_finite())
        && r.kinetic
            .iter()
            .chain(&r.potential)
            .chain(&r.cumulative_dissipation)
            .all(|x| x.is_finite())
}

/// Largest penetration max(0, −g_N) over every contact and row of a record of `k`'s
/// motion (m).
pub fn deepest_penetration<K: ContactKinematics + ?Sized>(k: &K, r: &Record) -> f64 {
    let mut pen = 0.0f64;
    for row in 0..r.len() {
        for i in 0..k.num_contacts() {
            pen = pen.max(-k.normal_gap(i, &r.q[row], r.t[row]));
        }
    }
    pen
}

/// Largest increase of the total energy over its initial value, max_k (E_k − E_0) (J).
pub fn energy_gain(r: &Record) -> f64 {
    let e = r.total_energy();
    e.iter().map(|x| x - e[0]).fold(f64::NEG_INFINITY, f64::max)
}

/// Path of a scene file shipped in the repository's `scenes/` folder.
pub fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Ball, Chain, G};
    use moreau_stepper::{Stepper, StepperOptions};

    /// The ball dropped from rest with ε_N = 1: its first impact is at t₁ = sqrt(2 h / g),
    /// it rises through half its drop height at sqrt(2 g h / 2) and never above its start;
    /// the record stays finite, never gains more energy than the midpoint rule's O(Δt) and
    /// penetrates at most one step's fall.
    #[test]
    fn a_bouncing_ball_reads_as_its_closed_form() {
        let dt = 1e-4;
        let mut s =
            Stepper::new(Ball::new(1.0), &[0.6], &[0.0], 0.0, StepperOptions::new(dt)).unwrap();
        let r = s.record_until(0.5).unwrap();
        let t1 = (2.0 * 0.5 / G).sqrt();
        let first = onsets(&r, 0);
        assert_eq!(first.len(), 1);
        // The impulse acts in the first step whose midpoint lies past t₁; its row is that
        // step's end, between Δt/2 and 3Δt/2 after t₁.
        let late = r.t[first[0]] - t1;
        assert!(0.5 * dt < late && late <= 1.5 * dt, "{late}");
        let up = up_crossings(&r, 0, 0.3);
        assert_eq!(up.len(), 1);
        let v_up = velocity_at(&r, 0, 0.3, 0).unwrap();
        assert!((v_up - (2.0 * G * 0.3).sqrt()).abs() < 1e-2, "{v_up}");
        assert!(velocity_at(&r, 0, 0.7, 0).is_none());
        assert!(record_is_finite(&r));
        assert!(energy_gain(&r) < 1e-2, "{}", energy_gain(&r));
        let pen = deepest_penetration(&Ball::new(1.0), &r);
        assert!((0.0..=(2.0 * G * 0.5).sqrt() * dt).contains(&pen), "{pen}");
    }

    #[test]
    fn non_finite_records_are_caught() {
        let chain = Chain::new(vec![1.0, 1.0], 0.5, 1.0);
        let mut s =
            Stepper::new(chain, &[0.0, 2.0], &[1.0, 0.0], 0.0, StepperOptions::new(1e-3)).unwrap();
        let mut r = s.record_until(0.01).unwrap();
        assert!(record_is_finite(&r));
        let mut impulses = r.clone();
        impulses.p_t.push(&[f64::NAN]);
        assert!(!record_is_finite(&impulses));
        r.kinetic[3] = f64::INFINITY;
        assert!(!record_is_finite(&r));
    }

    #[test]
    fn scene_paths_point_into_the_shipped_scenes() {
        let dir = scene_path("");
        assert!(dir.is_dir(), "{}", dir.display());
    }
}
