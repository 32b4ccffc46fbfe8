//! Declared mechanisms written in other units: lengths from micrometres to kilometres and
//! masses from milligrams to kilotonnes give the same motion, measured in the mechanism's own
//! scales.

use moreau_models::Scene;

/// The pendulum striking a wall of `scenes/bodies/pendulum-wall.toml` with lengths times `s`,
/// masses times `m` (times of √s, so that g stays 9.81), with the position projection.
fn pendulum(s: f64, m: f64) -> String {
    let r = s.sqrt();
    let (x, y) = (0.479425538604203 * s, 0.8775825618903728 * s);
    format!(
        r#"
dt = {dt}
t_end = {t_end}
gravity = [0.0, -9.81]
[[bodies]]
name = "wall"
type = "fixed"
position = [0.0, 0.0]
shapes = [{{ type = "half_plane", point = [{wall}, 0.0], normal = [-1.0, 0.0] }}]
[[bodies]]
name = "bob"
type = "dynamic"
mass = {mass}
inertia = {inertia}
position = [{px}, {py}]
shapes = [{{ type = "disk", center = [0.0, 0.0], radius = {radius} }}]
[[joints]]
type = "revolute"
name = "hinge"
body_a = "ground"
anchor_a = [0.0, 0.0]
body_b = "bob"
anchor_b = [{x}, {y}]
[[contacts]]
name = "hit"
body_a = "wall"
body_b = "bob"
eps_n = 0.8
eps_t = 0.0
mu = 0.0
"#,
        dt = 1e-4 * r,
        t_end = 0.8 * r,
        wall = 0.05 * s,
        mass = m,
        inertia = 0.00125 * m * s * s,
        px = -x,
        py = -y,
        radius = 0.05 * s,
    )
}

/// The bob's state after each step in the unit mechanism's scales: (x, y)/s, θ, (vx, vy)/√s,
/// ω √s, and its largest impulse over m √s.
fn pendulum_run(s: f64, m: f64) -> (Vec<[f64; 6]>, f64) {
    let scene = Scene::from_toml_str(&pendulum(s, m)).unwrap();
    let mut stepper = scene.stepper().unwrap();
    let (mut states, mut impulse) = (Vec::new(), 0.0f64);
    for _ in 0..8000 {
        let report = stepper.step().unwrap();
        impulse = report.contacts.iter().fold(impulse, |p, c| p.max(c.p_n));
        let (q, u) = (stepper.q(), stepper.u());
        let r = s.sqrt();
        states.push([q[0] / s, q[1] / s, q[2], u[0] / r, u[1] / r, u[2] * r]);
    }
    (states, impulse / (m * s.sqrt()))
}

#[test]
fn a_pendulum_striking_a_wall_moves_alike_in_any_unit_of_length_and_mass() {
    let (reference, impulse) = pendulum_run(1.0, 1.0);
    // It strikes the wall within the run.
    assert!(impulse > 0.1, "{impulse}");
    for (s, m) in [(1e-6, 1.0), (1e-3, 1e-6), (1e3, 1e6), (1e6, 1e-3)] {
        let (states, scaled) = pendulum_run(s, m);
        let worst = reference
            .iter()
            .zip(&states)
            .flat_map(|(a, b)| a.iter().zip(b).map(|(x, y)| (x - y).abs()))
            .fold(0.0f64, f64::max);
        assert!(worst < 1e-11, "lengths × {s:e}, masses × {m:e}: {worst:e}");
        assert!((scaled - impulse).abs() < 1e-11 * impulse, "{s:e}, {m:e}: {scaled} {impulse}");
    }
}
