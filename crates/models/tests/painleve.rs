//! Painlevé's rod (docs/theory.md §7.5): the acceleration-level LCP can have no solution, the
//! velocity-level step always has one.

use moreau_models::*;

#[test]
fn acceleration_lcp_coefficient_follows_the_closed_form() {
    let phi = 2f64.atan();
    // cos φ = 1/√5, sin φ = 2/√5: a = (8 − 6μ)/5 for m = 1, and b = −g at rest.
    for mu in [0.0, 0.3, 1.0, 2.0] {
        let (a, b) = PainleveParams::report_with_mu(mu).acceleration_lcp(phi, 0.0);
        assert!((a - (8.0 - 6.0 * mu) / 5.0).abs() < 1e-14, "mu {mu}: a = {a}");
        assert_eq!(b, -9.81);
    }
    assert!(PainleveParams::report_with_mu(2.0).acceleration_lcp(phi, 0.0).0 < 0.0);
    // a < 0 for some angle only when μ > 4/3.
    let min_a = |mu: f64| {
        (1..1000)
            .map(|k| {
                PainleveParams::report_with_mu(mu).acceleration_lcp(k as f64 * 1.5707e-3, 0.0).0
            })
            .fold(f64::INFINITY, f64::min)
    };
    assert!(min_a(4.0 / 3.0 - 0.01) > 0.0);
    assert!(min_a(4.0 / 3.0 + 0.01) < 0.0);
}

#[test]
fn rod_with_mu_2_stops_sliding_by_a_tangential_impact() {
    let scene = Scene::from_path(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/painleve-mu2.toml"),
    )
    .unwrap();
    let sim = scene.run().unwrap();
    let r = &sim.record;
    assert!(r.p_n.iter().chain(&r.p_t).all(|p| p[0].is_finite()));
    assert!(r.q.iter().chain(&r.u).all(|v| v.iter().all(|x| x.is_finite())));
    let k = r.active.iter().position(|a| a[0]).unwrap();
    let u = &r.u[k];
    // The step's w_T = (−1, 0, −s sin φ) is taken at the midpoint q_M = q_E − Δt/2 u_E.
    let phi_m = r.q[k][2] - 0.5 * scene.dt * u[2];
    let s = 1.0;
    // γ_T = w_Tᵀu after the step: the end no longer slides.
    let gamma_t = -u[0] - s * phi_m.sin() * u[2];
    eprintln!(
        "painleve mu=2: first contact step at t = {}: P_N = {:.4}, P_T = {:.4}, gamma_T after = {gamma_t:.2e}",
        r.t[k], r.p_n[k][0], r.p_t[k][0]
    );
    assert!(gamma_t.abs() < 1e-9);
    assert_eq!(r.state[k][0], moreau_stepper::ContactState::Stick);
    // A finite impulse, far above gravity's impulse over one step m g Δt: a tangential impact.
    assert!(r.p_t[k][0].abs() > 10.0 * 9.81 * scene.dt);
    assert!(r.p_t[k][0].abs() <= 2.0 * r.p_n[k][0] * (1.0 + 1e-9));
    // The rod ends lying flat, which ends the run.
    assert!(r.q.last().unwrap()[2] <= 0.0);
}

#[test]
fn rod_with_mu_0_3_slides() {
    let sim = Scene::report(ModelKind::Painleve).run().unwrap();
    let r = &sim.record;
    let slipping = r.state.iter().filter(|s| s[0] == moreau_stepper::ContactState::Slip).count();
    assert!(slipping > r.len() / 2, "{slipping} of {}", r.len());
    // While slipping, |P_T| = μ P_N.
    for k in 0..r.len() {
        if r.state[k][0] == moreau_stepper::ContactState::Slip {
            assert!((r.p_t[k][0].abs() - 0.3 * r.p_n[k][0]).abs() < 1e-9 * (1.0 + r.p_n[k][0]));
        }
    }
}
