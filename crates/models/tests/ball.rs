//! The bouncing ball against its closed form (docs/theory.md §7.1).

use moreau_models::*;
use moreau_testsupport::onsets;

fn run(eps_n: f64, dt: f64, t_end: f64) -> Simulation {
    let mut scene = Scene::report(ModelKind::Ball);
    scene.dt = dt;
    scene.t_end = t_end;
    scene.set("eps_n", &eps_n.to_string()).unwrap();
    scene.run().unwrap()
}

#[test]
fn impact_times_follow_the_closed_form_within_a_few_steps() {
    let p = BallParams::report();
    let mut worst = Vec::new();
    for dt in [1e-3, 2.5e-4] {
        let sim = run(0.9, dt, 4.0);
        let hits = onsets(&sim.record, 0);
        let mut w = 0.0f64;
        for k in 1..=6 {
            let err = (sim.record.t[hits[k - 1]] - p.impact_time(k)).abs();
            // Each impact is found at most one step late and the delays add up.
            assert!(err <= (k as f64 + 1.0) * dt, "dt {dt}, impact {k}: error {err}");
            w = w.max(err);
        }
        worst.push(w);
    }
    assert!(worst[1] < worst[0] / 2.0, "errors do not shrink with dt: {worst:?}");
}

#[test]
fn first_impact_has_the_closed_form_impulse_and_rebound() {
    let p = BallParams::report();
    let dt = 1e-3;
    let sim = run(0.9, dt, 1.0);
    let r = &sim.record;
    let k = onsets(r, 0)[0];
    let v1 = p.first_impact_speed();
    let (u_a, u_e, p_n) = (r.u[k - 1][0], r.u[k][0], r.p_n[k][0]);
    // One frictionless contact with a constant w_N: Newton's law u_E = −ε_N u_A and the
    // momentum balance P_N = m (u_E − u_A) + m g Δt hold to round-off over the impact step.
    assert!((u_e + p.eps_n * u_a).abs() < 1e-12 * u_a.abs(), "{u_a} → {u_e}");
    let momentum = p.m * (u_e - u_a) + p.m * p.g * dt;
    assert!((p_n - momentum).abs() < 1e-12 * p_n, "P_N = {p_n} vs {momentum}");
    // The step starts before the floor is reached, within a step's gain g Δt of −v1.
    assert!((u_a + v1).abs() <= p.g * dt, "approach {u_a} vs {}", -v1);
    assert!(u_a < 0.0 && u_e > 0.0);
}

/// Time after which the ball rests (v = 0 and y = R from then on).
fn rest_time(sim: &Simulation) -> f64 {
    let r = &sim.record;
    let k = (0..r.len()).rev().find(|&k| r.u[k][0].abs() > 1e-9).unwrap();
    r.t[k + 1]
}

#[test]
fn ball_comes_to_rest_at_the_accumulation_time() {
    let mut errors = Vec::new();
    for (eps, dt) in [(0.9, 1e-3), (0.9, 2.5e-4), (0.7, 1e-3)] {
        let p = BallParams { eps_n: eps, ..BallParams::report() };
        let sim = run(eps, dt, 10.0);
        let err = (rest_time(&sim) - p.accumulation_time()).abs();
        // About N = ln(g Δt / (2 v1)) / ln ε_N bounces last longer than a step, each found at
        // most a step late (and left a step late); the shorter ones, which the steps do not
        // resolve, last Δt/(1 − ε_N) together.
        let n = ((p.g * dt / (2.0 * p.first_impact_speed())).ln() / eps.ln()).ceil();
        let bound = 2.0 * (n + 1.0) * dt + dt / (1.0 - eps);
        assert!(err <= bound, "eps {eps} dt {dt}: rest error {err}, bound {bound}");
        errors.push(err);
        // At rest the ball sits on the floor: the midpoint rule leaves at most one step's
        // penetration g Δt² behind.
        let y_end = sim.record.q.last().unwrap()[0];
        assert!((y_end - p.r).abs() <= p.first_impact_speed() * dt);
    }
    assert!(errors[1] < errors[0] / 2.0, "{errors:?}");
}

#[test]
fn energy_is_conserved_in_flight_and_lost_only_at_impacts() {
    let p = BallParams::report();
    let sim = run(1.0, 1e-3, 3.0);
    let r = &sim.record;
    let e = r.total_energy();
    let e0 = p.m * p.g * (p.init.y0 - p.r);
    assert!((e[0] - e0).abs() < 1e-12);
    // ε_N = 1: each impact restores the speed, the energy stays within a step's worth of
    // potential energy m g v1 Δt of the start.
    for x in &e {
        assert!((x - e0).abs() <= p.m * p.g * p.first_impact_speed() * 1e-3 * 2.0, "{x} vs {e0}");
    }
    let eps = 0.5;
    let lossy = run(eps, 1e-3, 3.0);
    // The dissipation is the impulses' work: kinetic + potential + dissipation is the
    // energy at the start, at every row. Impacts remove energy; only where the ball, resting,
    // moves slower than g Δt does the midpoint rule's impact law give some back (a contact
    // closed at q_M while u_A points away from it gets u_E = −ε_N u_A), at most ½ m (g Δt)².
    let (r, dt) = (&lossy.record, 1e-3);
    let d = &r.cumulative_dissipation;
    for (k, (e, d)) in r.total_energy().iter().zip(d).enumerate() {
        assert!((e + d - e0).abs() < 1e-12, "row {k}: {e} + {d} vs {e0}");
    }
    for (k, w) in d.windows(2).enumerate() {
        if w[1] < w[0] {
            assert!(r.u[k][0].abs() < p.g * dt, "row {k}: {}", r.u[k][0]);
            assert!(w[0] - w[1] <= 0.5 * p.m * (p.g * dt).powi(2), "row {k}: {w:?}");
        }
    }
    let e = lossy.record.total_energy();
    // After the first impact only ε_N² of the kinetic energy is left.
    let k = onsets(&lossy.record, 0)[0];
    let expected = eps * eps * e0;
    // Flight under constant gravity keeps the energy exactly, so the impact step starts
    // from E0 with a speed v ≤ v1 + g Δt at a height a = y_A − R within v Δt/2 of the
    // floor, and ends with u_E = −ε_N u_A at y_M − R + ε_N v Δt/2: its energy is ε_N² E0
    // + m g (a (1 − ε_N²) − (1 − ε_N) v Δt/2), off by at most (1 − ε_N)(2 + ε_N)/2 m g v Δt.
    let (a, v) = (r.q[k - 1][0] - p.r, -r.u[k - 1][0]);
    let shift = p.m * p.g * (a * (1.0 - eps * eps) - (1.0 - eps) * v * dt / 2.0);
    assert!(
        (e[k + 1] - expected - shift).abs() < 1e-12 * e0,
        "{} vs {expected} + {shift}",
        e[k + 1]
    );
    let bound =
        (1.0 - eps) * (2.0 + eps) / 2.0 * p.m * p.g * (p.first_impact_speed() + p.g * dt) * dt;
    assert!((e[k + 1] - expected).abs() <= bound, "{} vs {expected}, bound {bound}", e[k + 1]);
}
