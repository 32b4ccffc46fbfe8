//! Step sizes from 1e-7 to 5e-2 s.

use super::*;

/// Step sizes of the sweeps, with the horizon that keeps each run within 20 000 steps.
const STEPS: [f64; 7] = [1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 5e-2];

#[test]
fn ball_at_every_step_size_hits_the_floor_on_time_and_penetrates_by_less_than_v_dt() {
    let eps = 0.9;
    for dt in STEPS {
        // Drop height H such that the first impact comes after at most 8000 steps.
        let t1_target = (8000.0 * dt).min(0.4284);
        let h = 0.5 * G * t1_target * t1_target;
        let t1 = (2.0 * h / G).sqrt();
        let v1 = G * t1;
        let s = scene(
            ModelKind::Ball,
            &[("init.y0", (0.1 + h).to_string()), ("t_end", (2.5 * t1).to_string())],
        );
        let mut s = s;
        s.dt = dt;
        let (m, r, summary) = run(&s);
        assert!(summary.steps <= 20_001);
        assert!(record_is_finite(&r));
        let k = r.p_n.iter().position(|p| p[0] > 0.0).expect("an impact");
        // The impact step is the first whose midpoint q_A + Δt/2 u_A lies at or below the
        // floor: t₁ lies within (t_E − 3Δt/2, t_E − Δt/2] up to the g Δt²/8 by which the
        // linear midpoint overshoots the true one.
        let late = (r.t[k] - t1) / dt;
        assert!((0.5 - 1e-6..=1.5 + 1e-6).contains(&late), "dt {dt}: impact at {}", r.t[k]);
        // Newton's law on the one contact: u_E = −ε_N u_A.
        let (u_a, u_e) = (r.u[k - 1][0], r.u[k][0]);
        assert!((u_e + eps * u_a).abs() <= 1e-12 * v1, "dt {dt}: {u_e} vs {}", -eps * u_a);
        // The previous midpoint was open (q_A > R − Δt|u_A|/2), so q_M > R − Δt|u_A| and
        // q_E = q_M + Δt u_E/2 > R − Δt|u_A|(1 − ε_N/2).
        let pen = deepest_penetration(&m, &r);
        let bound = u_a.abs() * dt * (1.0 - 0.5 * eps);
        assert!(pen <= bound * (1.0 + 1e-9) + 1e-15, "dt {dt}: penetration {pen}");
        row(
            &format!("ball Δt = {dt:.0e}, H = {h:.2e} m"),
            "impact within Δt of t₁; u_E = −ε_N u_A",
            &format!("t_E − t₁ = {late:.2} Δt, penetration {:.3} v₁Δt", pen / (v1 * dt)),
        );
    }
}

/// Runs `kind`'s report scene at step `dt` for `horizon` (or the scene's own stop rule),
/// returning the outcome as numbers or the error.
fn sweep_run(kind: ModelKind, dt: f64, horizon: f64) -> Result<(AnyModel, Record), ModelError> {
    let mut s = Scene::report(kind);
    s.dt = dt;
    s.t_end = horizon.min(s.t_end);
    run_with(&s, false, 0.0).map(|(m, r, _)| (m, r))
}

/// Horizon of a run at step dt: at most 10 000 steps and at most 1 s.
fn horizon(dt: f64) -> f64 {
    (1e4 * dt).min(1.0)
}

#[test]
fn woodpecker_step_sizes_stable_below_the_spring_limit_and_diverging_above() {
    let dt_crit = woodpecker_critical_step(&WoodpeckerParams::report());
    // ω = sqrt(c_φ vᵀM⁻¹v) ≈ 458 rad/s for the report's sleeve and bird: Δt_crit ≈ 4.4 ms.
    assert!((4e-3..5e-3).contains(&dt_crit), "critical step {dt_crit}");
    for dt in STEPS {
        let (m, r) = sweep_run(ModelKind::Woodpecker, dt, horizon(dt)).unwrap();
        assert!(record_is_finite(&r), "dt {dt}: NaN");
        let gain = energy_gain(&r) / energy_scale(&r);
        let pen = deepest_penetration(&m, &r);
        if dt < dt_crit {
            assert!(gain <= 1e-12, "dt {dt}: energy gain {gain}");
            // The report's initial state already penetrates by 8.8e-7 m at contact 2.
            assert!(pen <= 8.8e-7 + 1.0 * dt, "dt {dt}: penetration {pen}");
        } else {
            // Above the limit the spring mode grows by orders of magnitude each step.
            assert!(gain > 1e6, "dt {dt}: energy gain {gain}");
        }
        row(
            &format!("woodpecker Δt = {dt:.0e}"),
            if dt < dt_crit { "stable" } else { "diverges: Δt > Δt_crit = 2/ω" },
            &format!(
                "max (E − E₀)/E₀ = {gain:.2e}, penetration {pen:.2e} m (Δt_crit = {dt_crit:.2e} s)"
            ),
        );
    }
}

#[test]
fn cam_step_sizes_stable_below_the_spring_limit_and_diverging_above() {
    let p = moreau::models::CamParams::report();
    let dt_crit = 2.0 / (p.ks / p.m).sqrt();
    for dt in STEPS {
        // At least 4 ms: the follower released at the up-dead point meets the cam after 3 ms.
        let (m, r) = sweep_run(ModelKind::Cam, dt, horizon(dt).max(4e-3)).unwrap();
        assert!(record_is_finite(&r), "dt {dt}: NaN");
        let pen = deepest_penetration(&m, &r);
        let v_max = r.u.iter().map(|u| u[0].abs()).fold(0.0, f64::max);
        if dt < dt_crit {
            // The follower's speed stays below the spring's amplitude bound ω_s (H + g/ω_s²)
            // plus the cam's lift rate.
            let omega_s = (p.ks / p.m).sqrt();
            let lift_rate = 2.0 * p.stroke * p.omega / p.beta;
            assert!(
                v_max <= omega_s * (p.stroke + G / (omega_s * omega_s)) + 2.0 * lift_rate,
                "dt {dt}: v {v_max}"
            );
            assert!(pen <= (v_max + lift_rate) * dt, "dt {dt}: penetration {pen}");
        } else {
            assert!(v_max > 1e6, "dt {dt}: v {v_max}");
        }
        row(
            &format!("cam Δt = {dt:.0e}"),
            if dt < dt_crit { "stable" } else { "diverges: Δt > Δt_crit = 2/√(K_s/m)" },
            &format!(
                "max |v| = {v_max:.2e} m/s, penetration {pen:.2e} m (Δt_crit = {dt_crit:.2e} s)"
            ),
        );
    }
}

#[test]
fn painleve_step_sizes_penetrate_by_g_dt_squared() {
    for dt in STEPS {
        let (m, r) = sweep_run(ModelKind::Painleve, dt, horizon(dt)).unwrap();
        assert!(record_is_finite(&r), "dt {dt}: NaN");
        assert!(energy_gain(&r) <= 1e-12 * energy_scale(&r), "dt {dt}");
        let pen = deepest_penetration(&m, &r);
        // After the first step the rod's rotation leaves the gap positive by O(Δt²ω²) (2e-12 m
        // at Δt = 1e-3); the next midpoint is open, the rod falls freely by g Δt²/2 for one
        // step, and the following midpoint lies g Δt² deep, where γ_N = 0 then keeps it.
        assert!(pen <= G * dt * dt * (1.0 + 1e-6) + 1e-14, "dt {dt}: penetration {pen}");
        row(
            &format!("Painlevé μ = 0.3, Δt = {dt:.0e}"),
            "slides; energy never grows",
            &format!("penetration {pen:.3e} m = {:.3} g Δt²", pen / (G * dt * dt)),
        );
    }
    // The gap's second-order drift keeps growing while the contact is closed (1.6e-11 m
    // after two steps, 2.9e-10 m after five), so no fixed active-set threshold keeps the
    // contact closed; the position projection does, and removes the penetration.
    let mut s = Scene::report(ModelKind::Painleve);
    s.dt = 1e-3;
    let (m, plain, _) = run_with(&s, false, 1e-9).unwrap();
    let (_, projected, _) = run_with(&s, true, 0.0).unwrap();
    let (pen, pen_proj) = (deepest_penetration(&m, &plain), deepest_penetration(&m, &projected));
    assert!(pen > 0.9 * G * 1e-6, "threshold run penetration {pen}");
    assert!(pen_proj <= 1e-15, "projected penetration {pen_proj}");
    assert!(energy_gain(&projected) <= 1e-12 * energy_scale(&projected));
    row(
        "Painlevé μ = 0.3, Δt = 1e-3",
        "gap tolerance 1e-9 m / projection",
        &format!("penetration {pen:.2e} m / {pen_proj:.1e} m"),
    );
}

#[test]
fn slider_crank_step_sizes() {
    let p = SliderCrankParams::report();
    for dt in STEPS {
        let (m, r) = sweep_run(ModelKind::SliderCrank, dt, horizon(dt)).unwrap();
        assert!(record_is_finite(&r), "dt {dt}: NaN");
        let gain = energy_gain(&r) / energy_scale(&r);
        let pen = deepest_penetration(&m, &r);
        // The crank turns ω₁Δt per step; while that is small the run is sound.
        let turn = p.init.w1 * dt;
        if turn <= 0.15 {
            assert!(gain <= 1e-12, "dt {dt}: gain {gain}");
            assert!(pen <= p.l1 * p.init.w1 * dt, "dt {dt}: penetration {pen}");
        }
        row(
            &format!("slider-crank Δt = {dt:.0e} (ω₁Δt = {turn:.1e} rad)"),
            if turn <= 0.15 {
                "sound"
            } else {
                "finite but meaningless: the crank turns too far per step"
            },
            &format!(
                "max (E − E₀)/E₀ = {gain:.2e}, penetration {pen:.2e} m = {:.2} l₁ω₁Δt",
                pen / (p.l1 * p.init.w1 * dt)
            ),
        );
    }
}
