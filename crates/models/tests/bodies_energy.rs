//! The energy balance of declared mechanisms with dampers: the record's dissipation counts the
//! dampers' work with the impulses', so that kinetic plus potential energy plus dissipation
//! stays at its start; the position projection's moves of q are counted apart.

use moreau_models::Scene;

/// A 1 kg disk on a spring-damper (k = 100 N/m, c = `c` N s/m, rest length 0.5 m) to the
/// ground, stretched by 0.1 m along x and released, without gravity, stepped at Δt = 1e-3 s
/// for `t_end`; with `stiffness = 0` a damper alone, the disk started at 1 m/s.
fn oscillator(stiffness: f64, c: f64, t_end: f64) -> Scene {
    let v0 = if stiffness == 0.0 { 1.0 } else { 0.0 };
    let text = format!(
        r#"
dt = 0.001
t_end = {t_end}
gravity = [0.0, 0.0]

[[bodies]]
name = "mass"
type = "dynamic"
mass = 1.0
inertia = 0.01
position = [0.6, 0.0]
velocity = [{v0}, 0.0]
shapes = [{{ type = "disk", center = [0.0, 0.0], radius = 0.05 }}]

[[forces]]
type = "spring"
name = "link"
body_a = "ground"
anchor_a = [0.0, 0.0]
body_b = "mass"
anchor_b = [0.0, 0.0]
stiffness = {stiffness}
rest_length = 0.5
damping = {c}
"#
    );
    Scene::from_toml_str(&text).expect("a valid scene")
}

/// E₀, the largest |T + V + dissipated − projected − E₀| over the record, and the record's
/// last dissipation.
fn balance(scene: &Scene) -> (f64, f64, f64) {
    let run = scene.run().expect("the run succeeds");
    let r = &run.record;
    let e0 = r.kinetic[0] + r.potential[0];
    let drift = (0..r.len())
        .map(|k| {
            let e = r.kinetic[k] + r.potential[k];
            (e + r.cumulative_dissipation[k] - r.cumulative_projection[k] - e0).abs()
        })
        .fold(0.0, f64::max);
    (e0, drift, r.cumulative_dissipation[r.len() - 1])
}

#[test]
fn a_damper_alone_takes_the_energy_the_disk_loses_to_round_off() {
    // h = −c u: the midpoint rule's ½ m (u_E² − u_A²) is the damper's work over the step, so
    // T + dissipated stays at ½ m v₀² = 0.5 J to round-off while the disk slows down.
    let (e0, drift, dissipated) = balance(&oscillator(0.0, 2.0, 1.0));
    assert_eq!(e0, 0.5);
    assert!(drift <= 1e-14, "{drift:e}");
    // The scheme's h at u_A makes each step's u_E = (1 − c Δt) u_A: after 1,000 steps the
    // damper took ½ (1 − 0.998^2000), within 4e-5 J of the continuous 0.5 (1 − e^{−4}).
    let steps = 0.5 * (1.0 - 0.998f64.powi(2000));
    assert!((dissipated - steps).abs() <= 1e-13, "{dissipated} against {steps}");
    let exact = 0.5 * (1.0 - (-4.0f64).exp());
    assert!((dissipated - exact).abs() <= 4e-5, "{dissipated} against {exact}");
}

#[test]
fn a_damped_oscillator_dissipates_its_energy_through_its_damper() {
    // ω = 10 rad/s, ζ = c / (2 √(k m)) = 0.1: over 10 s the amplitude falls by e^{−10}, and
    // the damper has taken nearly all of E₀ = ½ k 0.1² = 0.5 J. The balance holds to the
    // midpoint rule's error on the spring, (ω Δt)² / 4 = 2.5e-5 of E₀.
    let (e0, drift, dissipated) = balance(&oscillator(100.0, 2.0, 10.0));
    assert!((e0 - 0.5).abs() <= 1e-12, "{e0}");
    assert!(drift <= 3e-5 * e0, "{drift:e}");
    assert!((dissipated - e0).abs() <= 3e-5 * e0, "{dissipated} of {e0}");
    // The undamped one dissipates nothing and keeps its energy to the same error.
    let (e0, drift, dissipated) = balance(&oscillator(100.0, 0.0, 10.0));
    assert!(drift <= 3e-5 * e0 && dissipated == 0.0, "{drift:e} {dissipated:e}");
}

/// A wheel spun at 10 rad/s, its spin damped against the ground (c = 0.05 N m s/rad),
/// dropped 0.1 m onto a floor it strikes at ε_N = 0.5 (μ = 0), stepped at Δt = 1e-3 s over
/// 2 s, with or without the position projection.
fn damped_wheel(projection: bool) -> Scene {
    let text = format!(
        r#"
dt = 0.001
t_end = 2.0
gravity = [0.0, -9.81]
projection = {projection}

[[bodies]]
name = "floor"
type = "fixed"
position = [0.0, 0.0]
shapes = [{{ type = "half_plane", point = [0.0, 0.0], normal = [0.0, 1.0] }}]

[[bodies]]
name = "wheel"
type = "dynamic"
mass = 2.0
inertia = 0.01
position = [0.0, 0.2]
omega = 10.0
shapes = [{{ type = "disk", center = [0.0, 0.0], radius = 0.1 }}]

[[forces]]
type = "torsion"
body_a = "ground"
body_b = "wheel"
stiffness = 0.0
rest_angle = 0.0
damping = 0.05

[contacts_auto]
eps_n = 0.5
eps_t = 0.0
mu = 0.0
"#
    );
    Scene::from_toml_str(&text).expect("a valid scene")
}

#[test]
fn a_torsion_damper_and_gravity_balance_with_the_impulses_of_a_floor() {
    // The impacts' and the damper's dissipation together keep T + V + dissipated at its
    // start to round-off.
    let scene = damped_wheel(false);
    let run = scene.run().expect("the run succeeds");
    assert!(!run.record.impacts.is_empty(), "the wheel strikes the floor");
    assert!(run.record.cumulative_projection.iter().all(|&p| p == 0.0));
    let (e0, drift, dissipated) = balance(&scene);
    // ½ I ω² = 0.5 J of spin and m g y = 3.924 J, of which the fall onto the floor gives up
    // 1.962 J, nearly all dissipated by t = 2 s.
    assert!((e0 - (0.5 + 2.0 * 9.81 * 0.2)).abs() <= 1e-12, "{e0}");
    assert!(drift <= 1e-12 * e0, "{drift:e}");
    assert!(dissipated > 0.5 + 0.9 * 2.0 * 9.81 * 0.1, "{dissipated}");
}

#[test]
fn the_projection_s_lift_out_of_the_floor_closes_the_balance() {
    // With the projection, each impact's penetration of O(Δt γ_N) is pushed back out along
    // the normal: the wheel is lifted against gravity, m g δy, which no impulse does.
    // Counted apart, it closes the balance to round-off again.
    let scene = damped_wheel(true);
    let run = scene.run().expect("the run succeeds");
    let r = &run.record;
    let (e0, drift, _) = balance(&scene);
    assert!(drift <= 1e-12 * e0, "{drift:e}");
    let projected = r.cumulative_projection[r.len() - 1];
    // The first impact at γ_N ≈ −1.4 m/s leaves a penetration of about Δt |γ_N| / 2, which
    // the projection lifts out: m g δy of the order of 2 · 9.81 · 7e-4 = 0.014 J, and the
    // later impacts add less. The projection only lifts, so the sum never falls.
    assert!((0.005..0.05).contains(&projected), "{projected}");
    assert!(r.cumulative_projection.windows(2).all(|w| w[1] >= w[0]));
    // Without counting it, T + V + dissipated ends above E₀ by what the projection added.
    let last = r.len() - 1;
    let excess = r.kinetic[last] + r.potential[last] + r.cumulative_dissipation[last] - e0;
    assert!((excess - projected).abs() <= 1e-12 * e0, "{excess} against {projected}");
}
