//! Runs of a million steps.

use super::*;

/// What a run of a million ball steps measured.
struct Million {
    /// Largest |E − E₀| (J).
    drift: f64,
    /// Largest E − E₀ (J).
    gain: f64,
    /// Largest one-step increase E_(k+1) − E_k (J).
    step_gain: f64,
    /// Largest penetration R − y (m).
    penetration: f64,
    /// Final y and v.
    y: f64,
    v: f64,
}

/// Runs the ball for 10 s at Δt = 1e-5 (10⁶ steps) with an observer that keeps no record.
fn ball_million(eps: f64) -> Million {
    let s = scene(ModelKind::Ball, &[("eps_n", eps.to_string())]);
    let model = s.build().unwrap();
    let (q0, u0) = model.initial_state();
    let mut stepper = Stepper::new(model, &q0, &u0, 0.0, StepperOptions::new(1e-5)).unwrap();
    let energy = |q: f64, v: f64| 0.5 * v * v + G * (q - 0.1);
    let e0 = energy(q0[0], u0[0]);
    let mut m = Million {
        drift: 0.0,
        gain: f64::NEG_INFINITY,
        step_gain: 0.0,
        penetration: 0.0,
        y: 0.0,
        v: 0.0,
    };
    let mut prev = e0;
    let summary = stepper
        .run_until(10.0, &mut |r: &StepReport<'_>| {
            let (q, v) = (r.q[0], r.u[0]);
            assert!(q.is_finite() && v.is_finite());
            let e = energy(q, v);
            m.drift = m.drift.max((e - e0).abs());
            m.gain = m.gain.max(e - e0);
            m.step_gain = m.step_gain.max(e - prev);
            m.penetration = m.penetration.max(0.1 - q);
            prev = e;
            ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(summary.steps, 1_000_000);
    m.y = stepper.q()[0];
    m.v = stepper.u()[0];
    m
}

#[test]
fn ball_a_million_steps_with_eps_1() {
    let m = ball_million(1.0);
    let e0 = G * 0.9;
    assert!(m.drift < 1e-9 * e0, "drift {}", m.drift);
    assert!(m.penetration <= 0.5 * (2.0 * G * 0.9f64).sqrt() * 1e-5);
    row(
        "ball ε_N = 1, Δt = 1e-5, 10⁶ steps",
        "no NaN, energy kept",
        &format!(
            "max |E − E₀|/E₀ = {:.1e}, largest one-step gain {:.1e} J",
            m.drift / e0,
            m.step_gain
        ),
    );
}

#[test]
fn ball_a_million_steps_with_eps_0_9_comes_to_rest() {
    let eps = 0.9;
    let dt = 1e-5;
    let m = ball_million(eps);
    // Past t_∞ = t₁ (1 + ε)/(1 − ε) ≈ 8.14 s the ball rests on the floor. The energy never
    // exceeds E₀. A single step may add a little: a resting ball moving up at u_A > 0 with
    // its midpoint still in contact leaves with u_E = −ε u_A and q_E − q_A = Δt u_A (1 − ε)/2,
    // a change ½u_A²(ε² − 1) + g Δt u_A (1 − ε)/2 whose largest value, at
    // u_A = g Δt / (2(1 + ε)), is (g Δt)² (1 − ε) / (8 (1 + ε)).
    let bound = (G * dt).powi(2) * (1.0 - eps) / (8.0 * (1.0 + eps));
    // (E₀ = 8.8 J; the flight before the first impact keeps E to round-off, 1e-12 relative.)
    assert!(m.gain <= 1e-11 * G * 0.9, "energy above E0 by {}", m.gain);
    assert!(m.step_gain <= bound * (1.0 + 1e-6), "one-step gain {} > {bound}", m.step_gain);
    let v1 = (2.0 * G * 0.9f64).sqrt();
    assert!(m.penetration <= 0.5 * v1 * dt);
    // The resting position does not drift.
    assert!((m.y - 0.1).abs() <= 0.5 * v1 * dt && m.v.abs() < 1e-9, "y {}, v {}", m.y, m.v);
    row(
        "ball ε_N = 0.9, Δt = 1e-5, 10⁶ steps",
        "rests after t_∞; E ≤ E₀ throughout",
        &format!(
            "largest one-step gain {:.3e} J = {:.3} (gΔt)²(1−ε)/(8(1+ε)); final y − R = {:.2e} m, v = {:.1e} m/s",
            m.step_gain,
            m.step_gain / bound,
            m.y - 0.1,
            m.v
        ),
    );
}
