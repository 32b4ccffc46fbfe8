//! Simultaneous impacts, and Painlevé's rod.

use super::*;

#[test]
fn newtons_cradle_of_touching_balls_is_one_simultaneous_impact() {
    // Balls of radius 1/2 at x_i = i touch exactly (g_N = 0), the first moves at v = 1.
    // At the midpoint every contact is closed (g_N ≤ 0), and the LCP acts at once: ξ_1 = 0
    // gives γ_1(+) = ε v, ξ_i = 0 for i > 1 gives γ_i(+) = 0, so balls 2..N leave together as
    // one block: V = (1 + ε) v / N and v_1 = V − ε v, the impact of m on (N − 1) m. Momentum
    // is kept exactly, and for ε = 1 the kinetic energy too, but the experiment's answer
    // (one ball leaves at v, the others rest) is not reproduced.
    for n in 2..=6 {
        for eps in [0.0, 0.5, 1.0] {
            let chain = Chain::new(vec![1.0; n], 0.5, eps);
            let q0: Vec<f64> = (0..n).map(|i| i as f64).collect();
            let mut u0 = vec![0.0; n];
            u0[0] = 1.0;
            let mut s = Stepper::new(chain, &q0, &u0, 0.0, StepperOptions::new(1e-3)).unwrap();
            let lcp_size = s.step().unwrap().lcp_size;
            assert_eq!(lcp_size, n - 1, "every contact enters the LCP");
            for _ in 0..9 {
                s.step().unwrap();
            }
            let u = s.u().to_vec();
            let big_v = (1.0 + eps) / n as f64;
            assert!((u[0] - (big_v - eps)).abs() < 1e-13, "n {n} eps {eps}: v1 {}", u[0]);
            for (i, v) in u.iter().enumerate().skip(1) {
                assert!((v - big_v).abs() < 1e-13, "n {n} eps {eps}: v{} = {v}", i + 1);
            }
            let chain = s.mechanism();
            assert!((chain.momentum(&u) - 1.0).abs() < 1e-14);
            let energy = chain.kinetic(&u) / 0.5;
            // T(+)/T(−) = 1 − (1 − ε²)(N − 1)/N.
            let want = 1.0 - (1.0 - eps * eps) * (n as f64 - 1.0) / n as f64;
            assert!((energy - want).abs() < 1e-13, "n {n} eps {eps}: energy ratio {energy}");
            if n == 5 && eps != 0.5 {
                row(
                    &format!("Newton's cradle, 5 touching balls, ε_N = {eps}"),
                    "one LCP: balls 2-5 leave as a block",
                    &format!(
                        "u = ({:.6}, {:.6} × 4); T⁺/T⁻ = {energy:.15}; |Δp| = {:.0e}",
                        u[0],
                        u[1],
                        (chain.momentum(&u) - 1.0).abs()
                    ),
                );
            }
        }
    }
}

#[test]
fn newtons_cradle_with_small_gaps_passes_the_velocity_down_the_row() {
    // With gaps of 1 mm between the balls, every impact is a two-ball impact of equal masses
    // with ε = 1, which exchanges the velocities: the last ball leaves at v.
    let n = 5;
    let gap = 1e-3;
    let chain = Chain::new(vec![1.0; n], 0.5, 1.0);
    let q0: Vec<f64> = (0..n).map(|i| i as f64 * (1.0 + gap)).collect();
    let mut u0 = vec![0.0; n];
    u0[0] = 1.0;
    let mut s = Stepper::new(chain, &q0, &u0, 0.0, StepperOptions::new(1e-5)).unwrap();
    s.run_until(0.01, &mut |_: &StepReport<'_>| ControlFlow::Continue(())).unwrap();
    let u = s.u().to_vec();
    for v in &u[..n - 1] {
        assert!(v.abs() < 1e-12, "{u:?}");
    }
    assert!((u[n - 1] - 1.0).abs() < 1e-12, "{u:?}");
    row(
        "Newton's cradle, 5 balls 1 mm apart, ε_N = 1",
        "sequential impacts: last ball leaves at v",
        &format!("u = {:?}", u.iter().map(|v| format!("{v:.1e}")).collect::<Vec<_>>()),
    );
}

#[test]
fn rod_landing_flat_on_two_contacts_bounces_without_turning() {
    for eps in [0.0, 0.5, 1.0] {
        for mu in [0.0, 0.5] {
            let rod = Rod::with(1.0, 0.5, G, eps, mu);
            let dt = 1e-3;
            let mut s = Stepper::new(
                rod,
                &[0.0, 0.01, 0.0],
                &[0.0, -1.0, 0.0],
                0.0,
                StepperOptions::new(dt),
            )
            .unwrap();
            let mut impact = None;
            let mut u_before = [0.0; 3];
            for _ in 0..2000 {
                let u_a = [s.u()[0], s.u()[1], s.u()[2]];
                let r = s.step().unwrap();
                if r.contacts.iter().any(|c| c.p_n > 0.0) {
                    impact = Some((r.contacts[0].p_n, r.contacts[1].p_n, [r.u[0], r.u[1], r.u[2]]));
                    u_before = u_a;
                    break;
                }
            }
            let (p1, p2, u) = impact.expect("the rod lands");
            // Both ends close in the same step and take equal impulses; the rod does not turn
            // and bounces with ε_N times its landing speed: u_E = −ε_N u_A.
            assert!((p1 - p2).abs() <= 1e-15 * p1, "eps {eps} mu {mu}: {p1} vs {p2}");
            assert!(u[2].abs() <= 1e-15 && u[0].abs() <= 1e-15, "eps {eps} mu {mu}: {u:?}");
            assert!(
                (u[1] + eps * u_before[1]).abs() < 1e-14,
                "eps {eps}: {} vs {}",
                u[1],
                u_before[1]
            );
            // Impulse balance: 2 P_N = m (u_E − u_A) + m g Δt.
            assert!((2.0 * p1 - (u[1] - u_before[1] + G * dt)).abs() < 1e-14);
            if mu == 0.5 {
                row(
                    &format!("rod landing flat on two contacts, ε_N = {eps}"),
                    "equal impulses, no rotation, u_E = −ε_N u_A",
                    &format!("P_N = {p1:.6} N s each, |ω| = {:.0e} rad/s", u[2].abs()),
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Painlevé's rod

#[test]
fn painleve_rod_first_step_has_a_tangential_impact_exactly_above_mu_4_3() {
    // At φ₀ = atan 2 (m = s = 1), with the end sliding at γ_T = 1 m/s, the step's Delassus
    // matrix is G = [[1.6, 1.2], [1.2, 3.4]]. Sticking (γ_N⁺ = γ_T⁺ = 0) needs
    // G P = (g Δt, −1): P_N = 0.3 + 0.85 g Δt, P_T = −0.4 − 0.3 g Δt, admissible when
    // |P_T| ≤ μ P_N, i.e. μ ≥ 4/3 as Δt → 0: an impulse that does not vanish with Δt (a
    // tangential impact without collision). Sliding (P_T = −μ P_N) gives
    // P_N = g Δt / (1.6 − 1.2 μ) = g Δt / a, the acceleration-level LCP's a > 0.
    for dt in [1e-7, 1e-5, 1e-3] {
        for mu in [0.3, 1.3, 1.4, 2.0, 1000.0] {
            let mut s = Scene::report(ModelKind::Painleve);
            s.params = moreau::models::ModelParams::Painleve(PainleveParams::report_with_mu(mu));
            s.dt = dt;
            let mut stepper = s.stepper().unwrap();
            let r = stepper.step().unwrap();
            let c = r.contacts[0];
            let (p_n_stick, p_t_stick) = (0.3 + 0.85 * G * dt, -0.4 - 0.3 * G * dt);
            if p_t_stick.abs() <= mu * p_n_stick {
                assert_eq!(c.state, ContactState::Stick, "dt {dt} mu {mu}");
                assert!((c.p_n - p_n_stick).abs() < 1e-12, "dt {dt} mu {mu}: P_N {}", c.p_n);
                assert!((c.p_t - p_t_stick).abs() < 1e-12, "dt {dt} mu {mu}: P_T {}", c.p_t);
            } else {
                let a = 1.6 - 1.2 * mu;
                assert_eq!(c.state, ContactState::Slip, "dt {dt} mu {mu}");
                assert!(
                    (c.p_n - G * dt / a).abs() < 1e-12 * (1.0 + c.p_n),
                    "dt {dt} mu {mu}: P_N {}",
                    c.p_n
                );
                assert!((c.p_t + mu * c.p_n).abs() < 1e-12, "dt {dt} mu {mu}: P_T {}", c.p_t);
            }
            if dt == 1e-3 {
                row(
                    &format!("Painlevé first step, μ = {mu}, Δt = 1e-3"),
                    if c.state == ContactState::Stick {
                        "tangential impact, end sticks"
                    } else {
                        "slides, P_N = g Δt / a"
                    },
                    &format!("P_N = {:.6} N s, P_T = {:.6} N s", c.p_n, c.p_t),
                );
            }
        }
    }
}

#[test]
fn painleve_rod_with_mu_2_runs_to_the_end() {
    let s = scene(ModelKind::Painleve, &[("mu", "2".into())]);
    let (m, r, summary) = run(&s);
    assert!(record_is_finite(&r));
    assert!(energy_gain(&r) <= 1e-12 * energy_scale(&r));
    assert!(r.q[r.len() - 1][2] <= 0.0, "lies flat at the end");
    let e = r.total_energy();
    let pen = deepest_penetration(&m, &r);
    assert!(pen <= G * s.dt * s.dt * (1.0 + 1e-9));
    row(
        "Painlevé μ = 2, Δt = 1e-3",
        "sticks at once, falls flat, no LCP failure",
        &format!(
            "{} steps; energy lost {:.3} J of {:.3} J; penetration {pen:.2e} m",
            summary.steps,
            e[0] - e[e.len() - 1],
            e[0]
        ),
    );
}
