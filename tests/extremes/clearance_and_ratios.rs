//! Clearances down to 1e-6 m, with and without the projection, and mass and inertia
//! ratios of 1e-9.

use super::*;

#[test]
fn slider_crank_small_clearance_drift_and_projection() {
    let p = SliderCrankParams::report();
    let mut pen_over_c = Vec::new();
    for c in [1e-3, 1e-4, 1e-5, 1e-6] {
        let mut s = scene(ModelKind::SliderCrank, &[("c", c.to_string())]);
        // One crank revolution.
        s.stop_at = Some(StopRule { coordinate: "th1".into(), value: 2.0 * PI });
        let (m, plain, _) = run_with(&s, false, 0.0).unwrap();
        let (_, projected, _) = run_with(&s, true, 0.0).unwrap();
        let AnyModel::SliderCrank(sc) = &m else { unreachable!() };
        let y_max = |r: &Record| {
            r.q.iter()
                .flat_map(|q| (0..4).map(|k| sc.normalized_corner(k, q).abs()).collect::<Vec<_>>())
                .fold(0.0, f64::max)
        };
        let pen = deepest_penetration(&m, &plain);
        let pen_proj = deepest_penetration(&m, &projected);
        let (gain, gain_proj) = (
            energy_gain(&plain) / energy_scale(&plain),
            energy_gain(&projected) / energy_scale(&projected),
        );
        // Without projection, the penetration is bounded by the speed scale times Δt, not by
        // the clearance: at c = 1e-6 m the corners sink tens of clearances deep.
        assert!(pen <= p.l1 * p.init.w1 * s.dt, "c {c}: penetration {pen}");
        // With projection, the corners stay in the guide to round-off.
        assert!(pen_proj <= 1e-15, "c {c}: projected penetration {pen_proj}");
        assert!(y_max(&projected) <= 1.0 + 1e-9, "c {c}: |Y| {}", y_max(&projected));
        // Neither run gains energy.
        assert!(gain <= 1e-12 && gain_proj <= 1e-12, "c {c}: gains {gain} {gain_proj}");
        // Both reach θ₁ = 2π at nearly the same time.
        let (t_a, t_b) = (plain.t[plain.len() - 1], projected.t[projected.len() - 1]);
        assert!((t_a - t_b).abs() < 0.01 * t_a, "c {c}: {t_a} vs {t_b}");
        row(
            &format!("slider-crank c = {c:.0e} m, Δt = 1e-5, one revolution"),
            "without / with projection",
            &format!(
                "penetration {pen:.2e} m ({:.2} c) / {pen_proj:.1e} m; max |Y| {:.2} / {:.6}; max (E − E₀)/E₀ {gain:.1e} / {gain_proj:.1e}",
                pen / c,
                y_max(&plain),
                y_max(&projected)
            ),
        );
        pen_over_c.push(pen / c);
    }
    // The drift problem: relative to the clearance, the penetration grows as c shrinks.
    assert!(pen_over_c[3] > 10.0 && pen_over_c[0] < 0.1, "{pen_over_c:?}");
}

// ---------------------------------------------------------------------------------------
// Mass and inertia ratios of 1e-9

#[test]
fn woodpecker_with_a_sleeve_1e9_lighter_than_the_bird() {
    let p = WoodpeckerParams::report();
    let mut s = scene(ModelKind::Woodpecker, &[("m_m", (1e-9 * p.m_s).to_string())]);
    s.t_end = 0.2;
    let light = match &s.params {
        moreau::models::ModelParams::Woodpecker(w) => w.clone(),
        _ => unreachable!(),
    };
    let dt_crit = woodpecker_critical_step(&light);
    assert!(dt_crit > s.dt);
    let (m, r, _) = run(&s);
    assert!(record_is_finite(&r));
    let gain = energy_gain(&r) / energy_scale(&r);
    let pen = deepest_penetration(&m, &r);
    assert!(gain <= 1e-12, "gain {gain}");
    assert!(pen <= 1.0 * s.dt, "penetration {pen}");
    row(
        "woodpecker m_M/m_S = 1e-9, Δt = 1e-4, 0.2 s",
        "runs",
        &format!("max (E − E₀)/E₀ = {gain:.1e}, penetration {pen:.2e} m"),
    );

    // J_M/J_S = 1e-9 as well: the sleeve's rotation on the torsion spring becomes a
    // 1e5 rad/s mode, Δt = 1e-4 s is far above the limit, and the run diverges until the
    // numbers overflow, which ends it with a typed error (not a NaN state, not a panic).
    let mut s = scene(
        ModelKind::Woodpecker,
        &[("m_m", (1e-9 * p.m_s).to_string()), ("j_m", (1e-9 * p.j_s).to_string())],
    );
    s.t_end = 0.2;
    let stiff = match &s.params {
        moreau::models::ModelParams::Woodpecker(w) => w.clone(),
        _ => unreachable!(),
    };
    let dt_crit = woodpecker_critical_step(&stiff);
    assert!(dt_crit < 1e-6, "critical step {dt_crit}");
    let mut stepper = s.stepper().unwrap();
    let mut steps = 0u64;
    let error = loop {
        match stepper.step() {
            Ok(report) => {
                assert!(report.q.iter().chain(report.u).all(|x| !x.is_nan()));
                steps += 1;
                assert!(steps < 2000, "no divergence");
            }
            Err(e) => break e,
        }
    };
    assert!(matches!(error, StepError::NonFinite { .. }), "{error:?}");
    row(
        "woodpecker m_M/m_S = J_M/J_S = 1e-9, Δt = 1e-4",
        "diverges (Δt ≫ Δt_crit), stops with a typed error",
        &format!("Δt_crit = {dt_crit:.2e} s; error after {steps} steps: {error}"),
    );

    // Below the limit the same mechanism runs.
    let mut s = s.clone();
    s.dt = dt_crit / 4.0;
    s.t_end = 5000.0 * s.dt;
    let (m, r, _) = run(&s);
    assert!(record_is_finite(&r));
    let gain = energy_gain(&r) / energy_scale(&r);
    let pen = deepest_penetration(&m, &r);
    assert!(gain <= 1e-9, "gain {gain}");
    row(
        "same, Δt = Δt_crit/4, 5000 steps",
        "runs",
        &format!("max (E − E₀)/E₀ = {gain:.1e}, penetration {pen:.2e} m"),
    );
}

/// Two balls, one colliding with the other at relative speed 1 m/s, one step.
fn two_ball_impact(m1: f64, m2: f64, eps: f64) -> ([f64; 2], [f64; 2]) {
    let chain = Chain::new(vec![m1, m2], 0.5, eps);
    let u0 = [1.0, 0.0];
    let mut s = Stepper::new(chain, &[0.0, 1.0], &u0, 0.0, StepperOptions::new(1e-3)).unwrap();
    let r = s.step().unwrap();
    ([r.u[0], r.u[1]], u0)
}

#[test]
fn two_balls_with_mass_ratio_1e9_follow_the_two_body_impact() {
    for (m1, m2) in [(1.0, 1e-9), (1e-9, 1.0)] {
        for eps in [0.0, 0.5, 1.0] {
            let ([v1, v2], [a1, a2]) = two_ball_impact(m1, m2, eps);
            let total = m1 + m2;
            let p = m1 * a1 + m2 * a2;
            let want1 = (p - m2 * eps * (a1 - a2)) / total;
            let want2 = (p + m1 * eps * (a1 - a2)) / total;
            assert!(
                (v1 - want1).abs() <= 1e-12 * (1.0 + want1.abs()),
                "{m1} {m2} {eps}: v1 {v1} vs {want1}"
            );
            assert!(
                (v2 - want2).abs() <= 1e-12 * (1.0 + want2.abs()),
                "{m1} {m2} {eps}: v2 {v2} vs {want2}"
            );
            let dp = (m1 * v1 + m2 * v2 - p).abs() / p.abs();
            assert!(dp <= 1e-15, "momentum {dp}");
            if eps == 1.0 {
                row(
                    &format!("two balls m₁ = {m1:.0e}, m₂ = {m2:.0e}, ε_N = 1"),
                    "two-body impact closed form",
                    &format!("v = ({v1:.12}, {v2:.12}) m/s; |Δp|/p = {dp:.0e}"),
                );
            }
        }
    }
}
