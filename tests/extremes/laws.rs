//! Restitution and friction at their bounds: ε_N = 0 and 1, μ = 0 and 10³.

use super::*;

#[test]
fn ball_with_eps_0_rests_from_the_first_impact() {
    let dt = 1e-3;
    let s = scene(ModelKind::Ball, &[("eps_n", "0".into()), ("t_end", "1.0".into())]);
    let (_, r, _) = run(&s);
    let v1 = (2.0 * G * 0.9f64).sqrt();
    let first = r.p_n.iter().position(|p| p[0] > 0.0).expect("an impact");
    // ξ_N = γ_N(+) = 0: the velocity is exactly zero from the impact on, the position frozen,
    // and each later step carries the weight's impulse m g Δt.
    for k in first..r.len() {
        assert_eq!(r.u[k][0], 0.0, "row {k}");
        assert_eq!(r.q[k][0], r.q[first][0]);
    }
    for k in first + 1..r.len() {
        assert!((r.p_n[k][0] - G * dt).abs() <= 1e-15, "P_N = {}", r.p_n[k][0]);
    }
    // The previous midpoint was open, so q_A > R − Δt|u_A|/2 and q_E = q_M > R − Δt|u_A|.
    let pen = 0.1 - r.q[first][0];
    let u_a = r.u[first - 1][0].abs();
    assert!(pen > 0.0 && pen <= u_a * dt * (1.0 + 1e-12), "penetration {pen}");
    row(
        "ball ε_N = 0, Δt = 1e-3",
        "rests from the first impact: u = 0 exactly, P_N = m g Δt",
        &format!("penetration {pen:.3e} m = {:.3} v₁Δt", pen / (v1 * dt)),
    );
}

#[test]
fn ball_with_eps_1_keeps_its_energy() {
    let s = scene(ModelKind::Ball, &[("eps_n", "1".into())]);
    let (m, r, summary) = run(&s);
    assert_eq!(summary.steps, 10_000);
    let e = r.total_energy();
    let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / e[0];
    // Free flight is exact for constant gravity, and the impact step reverses u and leaves
    // q_E = q_A: energy is kept to round-off.
    assert!(drift < 1e-12, "relative energy drift {drift}");
    let apexes: Vec<f64> = (1..r.len() - 1)
        .filter(|&k| r.u[k - 1][0] > 0.0 && r.u[k][0] <= 0.0)
        .map(|k| r.q[k][0])
        .collect();
    assert!(apexes.len() >= 5);
    for y in &apexes {
        assert!((y - 1.0).abs() < 1e-4, "apex {y}");
    }
    let pen = deepest_penetration(&m, &r);
    let v1 = (2.0 * G * 0.9f64).sqrt();
    assert!(pen <= 0.5 * v1 * 1e-3);
    row(
        "ball ε_N = 1, Δt = 1e-3, 10 s",
        "bounces back to y₀ every time",
        &format!(
            "|ΔE|/E₀ = {drift:.1e}, apex error {:.1e} m",
            apexes.iter().map(|y| (y - 1.0).abs()).fold(0.0, f64::max)
        ),
    );
}

#[test]
fn woodpecker_with_eps_0_and_1_gains_energy_only_through_friction() {
    let mut gains = Vec::new();
    for (eps, mu) in [(0.0, 0.3), (1.0, 0.0), (1.0, 0.3)] {
        let s = scene(ModelKind::Woodpecker, &[("eps_n", eps.to_string()), ("mu", mu.to_string())]);
        let (m, r, _) = run(&s);
        assert!(record_is_finite(&r));
        let scale = energy_scale(&r);
        let gain = energy_gain(&r) / scale;
        let pen = deepest_penetration(&m, &r);
        // The sleeve edges and the beak move at most at |v| + r_M|ω_M| + ... ≈ 1 m/s here.
        assert!(pen < 1.0 * s.dt, "penetration {pen}");
        row(
            &format!("woodpecker ε_N = {eps}, μ = {mu}"),
            "runs 1 s",
            &format!(
                "max (E − E₀)/E₀ = {gain:.2e}, impulse energy input {:.2e} J, penetration {pen:.2e} m",
                impulse_energy_input(&r)
            ),
        );
        gains.push(gain);
    }
    // ε_N = 0: energy never grows. ε_N = 1 without friction: kept to the scheme's error.
    assert!(gains[0] <= 1e-12, "eps 0 gain {}", gains[0]);
    // (The spring's energy oscillates by O((ω Δt)²) in the explicit midpoint scheme, with
    // ω Δt ≈ 0.05 here.)
    assert!(gains[1] <= 1e-3, "eps 1, mu 0 gain {}", gains[1]);
    // ε_N = 1 with friction (ε_T = 0): a sticking impact changes the kinetic energy by
    // ½ P_T γ_T(−), whose sign Newton's law does not fix; the toy is pumped up the pole.
    assert!(gains[2] > 1.0, "eps 1, mu 0.3 gain {}", gains[2]);
}

#[test]
fn slider_crank_with_eps_0_and_1_never_gains_energy() {
    let p = SliderCrankParams::report();
    for eps in [0.0, 1.0] {
        let mut s = scene(ModelKind::SliderCrank, &[("eps_n", eps.to_string())]);
        s.t_end = 0.05;
        let (m, r, _) = run(&s);
        assert!(record_is_finite(&r));
        let gain = energy_gain(&r) / energy_scale(&r);
        let pen = deepest_penetration(&m, &r);
        assert!(gain <= 1e-12, "eps {eps}: gain {gain}");
        assert!(pen <= p.l1 * p.init.w1 * s.dt, "eps {eps}: penetration {pen}");
        let e = r.total_energy();
        row(
            &format!("slider-crank ε_N = {eps}, 0.05 s"),
            "energy never grows",
            &format!(
                "E_end/E₀ = {:.4}, penetration {pen:.2e} m = {:.3} l₁ω₁Δt",
                e[e.len() - 1] / e[0],
                pen / (p.l1 * p.init.w1 * s.dt)
            ),
        );
    }
}

#[test]
fn cam_with_eps_0_and_1_penetrates_by_at_most_the_closing_speed_times_dt() {
    for eps in [0.0, 1.0] {
        let s = scene(ModelKind::Cam, &[("eps_n", eps.to_string())]);
        let (m, r, _) = run(&s);
        assert!(record_is_finite(&r));
        let AnyModel::Cam(cam) = &m else { unreachable!() };
        let p = cam.params();
        // Closing speed bound: the follower's largest speed plus the cam's largest lift rate
        // 2 H ω / β.
        let v_max = r.u.iter().map(|u| u[0].abs()).fold(0.0, f64::max);
        let bound = (v_max + 2.0 * p.stroke * p.omega / p.beta) * s.dt;
        let pen = deepest_penetration(&m, &r);
        assert!(pen <= bound, "eps {eps}: penetration {pen} > {bound}");
        row(
            &format!("cam ε_N = {eps}, Δt = 1e-4"),
            "driven; penetration within closing speed × Δt",
            &format!("penetration {pen:.2e} m = {:.2} of the bound", pen / bound),
        );
    }
}

// ---------------------------------------------------------------------------------------
// μ = 0 and 10³

#[test]
fn painleve_rod_with_mu_0_slides_freely_and_with_mu_1000_pivots_on_its_end() {
    // μ = 0: no horizontal force, x = x₀ + ẋ₀ t exactly.
    let s = scene(ModelKind::Painleve, &[("mu", "0".into())]);
    let (_, r, _) = run(&s);
    let err = (0..r.len()).map(|k| (r.q[k][0] - (-r.t[k])).abs()).fold(0.0, f64::max);
    assert!(err < 1e-12, "x error {err}");
    assert!(energy_gain(&r) <= 1e-12 * energy_scale(&r));
    row(
        "Painlevé μ = 0",
        "slides freely until flat",
        &format!("max |x − (x₀ + ẋ₀t)| = {err:.1e} m"),
    );

    // μ = 10³: the end sticks at the first step and the rod falls pivoting about it.
    for dt in [1e-3, 1e-4] {
        let mut s = scene(ModelKind::Painleve, &[("mu", "1000".into())]);
        s.dt = dt;
        let (m, r, _) = run(&s);
        let AnyModel::Painleve(rod) = &m else { unreachable!() };
        let end = |k: usize| rod.lower_end(&r.q[k])[0];
        assert_eq!(r.state[1][0], ContactState::Stick);
        // The end moves by ẋ Δt/2 in the half step before the impulse acts.
        let start = end(0);
        assert!((end(1) - (start - 0.5 * dt)).abs() < dt * dt, "end after step 1: {}", end(1));
        let drift = (1..r.len()).map(|k| (end(k) - end(1)).abs()).fold(0.0, f64::max);
        // While sticking, γ_T = w_T(q_M)ᵀ u_E = 0 at the midpoint only: the end creeps by
        // O(Δt²) per step, O(Δt) over the fall.
        assert!(drift < 2.0 * dt, "dt {dt}: end drift {drift}");
        assert!(energy_gain(&r) <= 1e-12 * energy_scale(&r));
        row(
            &format!("Painlevé μ = 10³, Δt = {dt:.0e}"),
            "end sticks at step 1, rod pivots flat",
            &format!("end drift while sticking {drift:.2e} m = {:.2} Δt·(1 m/s)", drift / dt),
        );
    }
}

#[test]
fn woodpecker_with_mu_0_falls_with_gravity_and_with_mu_1000_locks() {
    // μ = 0: the contacts' w_N have no y-component, so the vertical momentum
    // p_y = (m_S + m_M) v + m_S l_M ω_M + m_S l_G ω_S obeys dp_y/dt = −(m_S + m_M) g exactly.
    let s = scene(ModelKind::Woodpecker, &[("mu", "0".into())]);
    let (m, r, _) = run(&s);
    let AnyModel::Woodpecker(w) = &m else { unreachable!() };
    let p = w.params();
    let p_y = |u: &[f64]| (p.m_s + p.m_m) * u[0] + p.m_s * p.l_m * u[1] + p.m_s * p.l_g * u[2];
    let err = (0..r.len())
        .map(|k| (p_y(&r.u[k]) - (p_y(&r.u[0]) - (p.m_s + p.m_m) * G * r.t[k])).abs())
        .fold(0.0, f64::max);
    let scale = (p.m_s + p.m_m) * G * s.t_end;
    assert!(err < 1e-12 * scale.max(1.0) * 1e3, "p_y error {err}");
    row(
        "woodpecker μ = 0",
        "falls: p_y = p_y0 − (m_S+m_M) g t",
        &format!("max error {err:.1e} N s"),
    );

    let s = scene(ModelKind::Woodpecker, &[("mu", "1000".into())]);
    let (m, r, _) = run(&s);
    assert!(record_is_finite(&r));
    assert!(energy_gain(&r) <= 1e-12 * energy_scale(&r));
    let drop = r.q[0][0] - r.q[r.len() - 1][0];
    let pen = deepest_penetration(&m, &r);
    // With the friction report's μ = 0.3 the sleeve slides 0.14 m down in 1 s; with μ = 10³
    // it is held, and drops only in the short flights between sticking phases.
    let free_fall = 0.5 * G + 0.3411;
    assert!(drop < 0.05 * free_fall, "drop {drop}");
    row(
        "woodpecker μ = 10³",
        "sleeve mostly locked",
        &format!(
            "drop {drop:.3e} m in 1 s ({:.1}% of free fall), penetration {pen:.1e} m",
            100.0 * drop / free_fall
        ),
    );
}

#[test]
fn slider_crank_with_mu_0_and_1000() {
    for mu in [0.0, 1000.0] {
        let mut s = scene(ModelKind::SliderCrank, &[("mu", mu.to_string())]);
        s.t_end = 0.05;
        let (m, r, _) = run(&s);
        assert!(record_is_finite(&r));
        let gain = energy_gain(&r) / energy_scale(&r);
        assert!(gain <= 1e-12, "mu {mu}: gain {gain}");
        let e = r.total_energy();
        let pen = deepest_penetration(&m, &r);
        row(
            &format!("slider-crank μ = {mu}, 0.05 s"),
            if mu == 0.0 { "runs, energy never grows" } else { "jams: friction stops the crank" },
            &format!(
                "E_end/E₀ = {:.4}, penetration {pen:.2e} m, impulse energy input {:.2e} J",
                e[e.len() - 1] / e[0],
                impulse_energy_input(&r)
            ),
        );
        if mu > 1.0 {
            assert!(e[e.len() - 1] < 0.01 * e[0], "a jammed crank keeps little energy");
        }
    }
}
