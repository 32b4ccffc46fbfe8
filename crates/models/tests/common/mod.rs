//! Helpers shared by the model tests.
#![allow(dead_code)]

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

/// Velocity `l` interpolated linearly at the first instant coordinate `j` reaches `value`.
pub fn velocity_at(r: &Record, j: usize, value: f64, l: usize) -> Option<f64> {
    let k = (1..r.len()).find(|&k| r.q[k - 1][j] < value && r.q[k][j] >= value)?;
    let s = (value - r.q[k - 1][j]) / (r.q[k][j] - r.q[k - 1][j]);
    Some(r.u[k - 1][l] + s * (r.u[k][l] - r.u[k - 1][l]))
}

/// Path of a scene file shipped in the repository's `scenes/` folder.
pub fn scene_path(name: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name)
}
