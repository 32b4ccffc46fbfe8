//! Declared mechanisms of `scenes/bodies/` against what can be computed by hand: a disk set
//! down on a conveyor belt (slip, then rolling), a block on a shaken table (sticking below
//! μ g, slipping above), a double pendulum striking an elastic wall (T + V kept), and a
//! motor-driven four-bar linkage with a revolute clearance joint (the ideal linkage's
//! rocker angle, the pin within its bearing).

use std::f64::consts::PI;

use moreau_models::{Scene, Simulation};

fn scene(text: &str) -> Scene {
    Scene::from_toml_str(text).unwrap()
}

fn run(scene: &Scene) -> Simulation {
    scene.run().unwrap()
}

/// The column of a coordinate or velocity by name.
fn column(sim: &Simulation, name: &str) -> Vec<f64> {
    if let Some(k) = sim.model.coordinate_names().position(name) {
        return sim.record.q.iter().map(|q| q[k]).collect();
    }
    let k = sim.model.velocity_names().position(name).unwrap();
    sim.record.u.iter().map(|u| u[k]).collect()
}

#[test]
fn a_disk_on_a_conveyor_belt_slips_at_mu_g_then_rolls_at_a_third_of_the_belt_speed() {
    let sim = run(&scene(include_str!("../../../scenes/bodies/conveyor.toml")));
    let (mu, g, v_belt, r) = (0.2, 9.81, 1.0, 0.1);
    let t_roll = v_belt / (3.0 * mu * g);
    let (v, omega, y) =
        (column(&sim, "disk.vx"), column(&sim, "disk.omega"), column(&sim, "disk.y"));
    let mut rows = (0, 0);
    for (k, &t) in sim.record.t.iter().enumerate() {
        // Slipping: v = μ g t, ω = 2 μ g t / r; rolling: v = V/3, ω = 2V/(3r). The step that
        // holds t* is between the two.
        let (ve, we) = if t < t_roll - 1e-4 {
            rows.0 += 1;
            (mu * g * t, 2.0 * mu * g * t / r)
        } else if t > t_roll + 1e-4 {
            rows.1 += 1;
            (v_belt / 3.0, 2.0 * v_belt / (3.0 * r))
        } else {
            continue;
        };
        assert!((v[k] - ve).abs() < 1e-12, "t = {t}: v = {} against {ve}", v[k]);
        assert!((omega[k] - we).abs() < 1e-11, "t = {t}: ω = {} against {we}", omega[k]);
        // It stays on the belt's top face.
        assert!((y[k] - r).abs() < 1e-12, "t = {t}: y = {}", y[k]);
    }
    assert_eq!(rows, (170, 331));
    // Rolling needs no friction: the last row's tangential impulse is round-off.
    let p_t = sim.record.p_t.last().unwrap()[0];
    assert!(p_t.abs() < 1e-15, "{p_t}");
}

/// The block's largest displacement relative to the table, and its last one (m).
fn relative_slip(amplitude: f64) -> (f64, f64) {
    let mut s = scene(include_str!("../../../scenes/bodies/shaken-table.toml"));
    s.set("bodies.table.motion.amplitude.0", &amplitude.to_string()).unwrap();
    s.set("bodies.block.position.0", &amplitude.to_string()).unwrap();
    let sim = run(&s);
    let x = column(&sim, "block.x");
    let rel: Vec<f64> = sim
        .record
        .t
        .iter()
        .zip(&x)
        .map(|(t, x)| x - amplitude * (2.0 * PI * t + PI / 2.0).sin())
        .collect();
    (rel.iter().fold(0.0, |m, r| r.abs().max(m)), *rel.last().unwrap())
}

#[test]
fn a_block_on_a_shaken_table_sticks_below_mu_g_and_slips_above() {
    // μ g / Ω² = 0.3 · 9.81 / (2π)² = 0.0746 m.
    let limit = 0.3 * 9.81 / (2.0 * PI).powi(2);
    assert!((limit - 0.07455).abs() < 1e-4);
    for amplitude in [0.05, 0.07] {
        // Sticking: the block follows the table up to the scheme's lag of half a step at the
        // table's largest speed, A Ω Δt / 2, and ends where it started on it.
        let (largest, last) = relative_slip(amplitude);
        let lag = amplitude * 2.0 * PI * 1e-4 / 2.0;
        assert!(largest < 1.01 * lag, "A = {amplitude}: {largest} against {lag}");
        assert!(last.abs() < 1e-8, "A = {amplitude}: {last}");
    }
    for (amplitude, at_least) in [(0.08, 5e-4), (0.1, 1e-2)] {
        let (largest, last) = relative_slip(amplitude);
        assert!(largest > at_least && last.abs() > at_least, "A = {amplitude}: {largest}, {last}");
    }
}

#[test]
fn a_double_pendulum_striking_an_elastic_wall_keeps_its_energy() {
    let base = scene(include_str!("../../../scenes/bodies/double-pendulum-wall.toml"));
    for (projection, tolerance) in [(false, 5e-6), (true, 2e-4)] {
        let mut s = base.clone();
        s.projection = projection;
        let sim = run(&s);
        let r = &sim.record;
        // Both bobs strike the wall. V = m g (y₁ + y₂) at the start, at rest.
        for c in 0..2 {
            assert!(r.p_n.iter().any(|p| p[c] > 0.1), "contact {c}");
        }
        let e0 = r.kinetic[0] + r.potential[0];
        assert!((e0 + 9.81 * (0.8775825618903728 + 1.4991925301610372)).abs() < 1e-12);
        let drift =
            r.kinetic.iter().zip(&r.potential).fold(0.0_f64, |m, (t, v)| m.max((t + v - e0).abs()));
        assert!(drift < tolerance, "projection {projection}: {drift}");
        // No bob's centre passes x = 0 (the wall's face less the radius) by more than the step
        // of an impact at 3 m/s, v Δt / 2, and with the projection not at all.
        let right = ["upper.x", "lower.x"]
            .iter()
            .flat_map(|name| column(&sim, name))
            .fold(f64::NEG_INFINITY, f64::max);
        let allowed = if projection { 1e-12 } else { 1.5e-4 };
        assert!(right < allowed, "projection {projection}: {right}");
    }
}

#[test]
fn a_four_bar_with_a_clearance_joint_follows_the_ideal_linkage() {
    let sim = run(&scene(include_str!("../../../scenes/bodies/four-bar-clearance.toml")));
    let (a, b, c, d) = (0.1, 0.35, 0.3, 0.4);
    // The rocker's angle of the ideal linkage at crank angle θ: the upper intersection of the
    // circles about the crank pin B (radius b) and the rocker's pivot D (radius c).
    let rocker = |theta: f64| {
        let (bx, by) = (a * theta.cos(), a * theta.sin());
        let (dx, dy) = (d - bx, -by);
        let l = dx.hypot(dy);
        let along = (b * b - c * c + l * l) / (2.0 * l);
        let across = (b * b - along * along).sqrt();
        let (cx, cy) = (bx + (along * dx - across * dy) / l, by + (along * dy + across * dx) / l);
        cy.atan2(cx - d)
    };
    let names = ["crank.theta", "coupler.x", "coupler.y", "coupler.theta"];
    let [crank, cx, cy, ct] = names.map(|n| column(&sim, n));
    let [rx, ry, rt] = ["rocker.x", "rocker.y", "rocker.theta"].map(|n| column(&sim, n));
    let (mut angle, mut play) = (0.0_f64, 0.0_f64);
    for (k, &t) in sim.record.t.iter().enumerate() {
        // The motor holds the crank at 2π t.
        assert!((crank[k] - 2.0 * PI * t).abs() < 1e-9, "t = {t}: {}", crank[k]);
        angle = angle.max((rt[k] - rocker(crank[k])).abs());
        let pin = (cx[k] + 0.5 * b * ct[k].cos(), cy[k] + 0.5 * b * ct[k].sin());
        let bearing = (rx[k] + 0.5 * c * rt[k].cos(), ry[k] + 0.5 * c * rt[k].sin());
        play = play.max((pin.0 - bearing.0).hypot(pin.1 - bearing.1));
    }
    // Within the play as the rocker sees it, 1 mm over 0.3 m and some, and not exact.
    assert!(angle < 5e-3 && angle > 1e-4, "{angle}");
    // The pin reaches the bearing's wall and penetrates it by less than 1e-6 m.
    assert!(play > 0.999e-3 && play < 1e-3 + 1e-6, "{play}");
    // The joint's contact works: it closes on most recorded rows.
    let closed = sim.record.p_n.iter().filter(|p| p[0] > 0.0).count();
    assert!(closed > sim.record.t.len() / 2, "{closed}");
}
