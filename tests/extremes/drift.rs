//! Drift in persistent contact, the projection, step LCPs without a solution, and the
//! energy error's order in Δt.

use super::*;

/// A slider-crank's start with the crank, rod and slider in line (all angles 0), the crank
/// turning at w1 and the rod at the rate the slider's guide gives it, −l₁/l₂ w1.
fn flat_start(l1: f64, l2: f64, w1: f64) -> moreau::models::SliderCrankInit {
    moreau::models::SliderCrankInit { th1: 0.0, th2: 0.0, th3: 0.0, w1, w2: -l1 / l2 * w1, w3: 0.0 }
}

/// A slider-crank with a short rod (l₂ = 1.5 l₁) and a thin slider, μ = ε_N = 0, whose upper
/// corners slide along the guide for a long stretch of the crank's turn.
fn short_rod_slider_crank() -> SliderCrankParams {
    let (l1, w1) = (0.05, -161.95);
    let l2 = 1.5 * l1;
    SliderCrankParams {
        l1,
        l2,
        a: 0.0197,
        b: 0.005,
        c: 1.39e-4,
        eps_n: 0.0,
        eps_t: 0.0,
        mu: 0.0,
        init: flat_start(l1, l2, w1),
        ..SliderCrankParams::report()
    }
}

#[test]
fn persistent_contact_drifts_into_the_guide_in_proportion_to_dt() {
    // In persistent contact the LCP keeps γ_N = 0 at each midpoint, but the corner's path is
    // curved: each step adds O(g̈_N Δt²) of penetration, which accumulates over the contact's
    // duration to O(Δt). Nothing in the scheme as written pulls it back.
    let p = short_rod_slider_crank();
    let mut pens = Vec::new();
    for dt in [1e-4, 5e-5] {
        let mut s = Scene::report(ModelKind::SliderCrank);
        s.params = moreau::models::ModelParams::SliderCrank(p.clone());
        s.stop_at = None;
        s.dt = dt;
        s.t_end = 0.03;
        let (m, plain, _) = run_with(&s, false, 0.0).unwrap();
        let (_, projected, _) = run_with(&s, true, 0.0).unwrap();
        let (pen, pen_proj) =
            (deepest_penetration(&m, &plain), deepest_penetration(&m, &projected));
        assert!(record_is_finite(&plain) && record_is_finite(&projected));
        // Far beyond one step's worth: the largest normal speed times Δt is about 1e-4 m.
        assert!(pen > 2.0 * p.c, "dt {dt}: penetration {pen}");
        assert!(pen_proj <= 1e-15, "dt {dt}: projected penetration {pen_proj}");
        row(
            &format!("short-rod slider-crank, c = 1.39e-4 m, Δt = {dt:.0e}"),
            "upper corners slide: drift without / with projection",
            &format!("penetration {pen:.3e} m ({:.1} c) / {pen_proj:.1e} m", pen / p.c),
        );
        pens.push(pen);
    }
    let ratio = pens[0] / pens[1];
    assert!((1.6..2.4).contains(&ratio), "halving Δt divides the drift by {ratio}");
}

#[test]
fn projection_over_all_corners_frees_a_slider_turned_in_the_guide() {
    // A slider turned far beyond c/(2a) (a fuzz case). Projecting only the corner that
    // penetrates (corner 4) along M⁻¹w_N would turn the slider and push corner 3, on the same
    // face, in; the stepper therefore projects over all four corners at once, which frees
    // both.
    let (l1, rod, w1) = (0.10761667052134372, 2.675893235669823, 164.71652101770627);
    let l2 = rod * l1;
    let rep = SliderCrankParams::report();
    let p = SliderCrankParams {
        l1,
        l2,
        a: 0.04131659969911525,
        b: 0.030740557392355858,
        c: 2.7777503855992243e-5,
        m1: rep.m1 * 0.7646035050932377,
        m2: rep.m2 * 1.3402709924606528,
        m3: rep.m3 * 1.5841968000758027,
        j2: rep.j2 * 0.8239706328329293,
        eps_n: 0.0,
        eps_t: 0.0,
        mu: 1.744512096813874,
        init: flat_start(l1, l2, w1),
        ..rep
    };
    let model = moreau::models::ModelParams::SliderCrank(p.clone()).build().unwrap();
    let (q0, u0) = model.initial_state();
    let mut options = StepperOptions::new(1e-4);
    options.projection = true;
    let mut stepper = Stepper::new(model, &q0, &u0, 0.0, options).unwrap();
    let (mut pen, mut turn) = (0.0f64, 0.0f64);
    for _ in 0..300 {
        stepper.step().unwrap();
        let m = stepper.mechanism();
        let worst = (0..4).map(|i| -m.normal_gap(i, stepper.q(), stepper.t())).fold(0.0, f64::max);
        pen = pen.max(worst);
        turn = turn.max(stepper.q()[2].abs());
    }
    // The slider turns until it binds in the guide, at about c/(2a) (where a sin θ + b cos θ
    // = b + c/2), and no further: without projection the penetration let it turn five times
    // as far ...
    let binding = p.c / (2.0 * p.a);
    assert!(
        turn > 0.5 * binding && turn <= 1.001 * binding,
        "th3 reached {turn}, binding at {binding}"
    );
    // ... and no corner is left inside the guide at the end of any step.
    assert!(pen <= 1e-12 * p.c, "penetration {pen} after projection");
    row(
        "slider turned in the guide, projected",
        "no corner inside at step ends",
        &format!("max penetration {pen:.1e} m"),
    );
}

#[test]
fn friction_with_tangential_restitution_can_leave_the_step_lcp_without_solution() {
    // A woodpecker with a longer beak arm (a fuzz case): μ = 1.84 and ε_T = 0.69 at the
    // beak, μ = 0.76 at the lower sleeve edge. At step 142 both are closed and the LCP of
    // eq. 7.41 (size 6) has no solution: Lemke ends on a ray and complete enumeration proves
    // it. The stepper stops with a typed error that carries the instance. With ε_T = 0 the
    // same toy runs. The LCPs before it have several solutions (μ > 1): Lemke's method picks
    // the ones that lead there, while Auto's warm start keeps the previous contact mode and
    // steers clear, so the run uses Lemke.
    let f = [1.0, 1.0, 1.0, 1.473838299104488, 0.5579096273671389, 1.0, 1.8382186540343675];
    let rep = WoodpeckerParams::report();
    let make = |eps_t: f64| WoodpeckerParams {
        l_m: rep.l_m * f[3],
        l_g: rep.l_g * f[4],
        l_s: rep.l_s * f[6],
        j_s: rep.j_s * 0.9846034045927093,
        beak: moreau::models::LawParams::new(0.0, eps_t, 1.839702639234597),
        lower: moreau::models::LawParams::new(0.0, 0.0, 0.7583672515045705),
        upper: moreau::models::LawParams::new(0.0, 0.0, 0.0),
        ..rep.clone()
    };
    let mut s = Scene::report(ModelKind::Woodpecker);
    s.dt = 0.00011159184942331329;
    s.t_end = 300.0 * s.dt;
    s.solver = SolverChoice::Lemke;
    s.params = moreau::models::ModelParams::Woodpecker(make(0.6923390041536567));
    let error = s.run().unwrap_err();
    let ModelError::Step(StepError::LcpFailed { step, status, lcp, q, u, .. }) = error else {
        panic!("expected LcpFailed, got {error}");
    };
    // Lemke alone ends on a ray; Auto (down to enumeration) certifies that there is no
    // solution.
    assert_eq!(status, moreau::lcp::Status::RayTermination);
    assert_eq!(lcp.n(), 6);
    assert!(q.iter().chain(&u).all(|x| x.is_finite()));
    let all = moreau::lcp::Enumeration::default().solve_all(lcp.view()).unwrap();
    assert!(all.is_empty());
    use moreau::lcp::Solver;
    let auto = moreau::lcp::Auto::default().solve(&lcp).unwrap();
    assert_eq!(auto.status, moreau::lcp::Status::NoSolution);
    s.params = moreau::models::ModelParams::Woodpecker(make(0.0));
    let sim = s.run().unwrap();
    assert!(record_is_finite(&sim.record));
    row(
        "woodpecker variant, beak μ = 1.84, ε_T = 0.69",
        "step LCP without solution: typed error LcpFailed with the instance (Lemke: ray; Auto: NoSolution)",
        &format!(
            "step {step}, n = 6; enumeration: 0 solutions, Lemke: ray; with ε_T = 0 runs {} steps",
            sim.steps
        ),
    );
}

#[test]
fn ideal_slider_crank_energy_error_is_first_order_in_dt() {
    // Without contacts the report's ideal slider-crank is conservative. The scheme takes the
    // centrifugal terms of h at u_A, so it is first order for them: the energy error over two
    // revolutions falls linearly with Δt (by 4 for Δt / 4), and it is a loss.
    let mut losses = Vec::new();
    for dt in [4e-5, 1e-5] {
        let mut s = Scene::report(ModelKind::SliderCrankIdeal);
        s.dt = dt;
        let (_, r, _) = run(&s);
        let e = r.total_energy();
        let gain = e.iter().map(|x| x - e[0]).fold(f64::NEG_INFINITY, f64::max);
        assert!(gain <= 1e-12 * e[0], "dt {dt}: energy gain {gain}");
        let loss = (e[0] - e[e.len() - 1]) / e[0];
        row(
            &format!("ideal slider-crank, two revolutions, Δt = {dt:.0e}"),
            "energy lost by the scheme",
            &format!("(E₀ − E_end)/E₀ = {loss:.3e}"),
        );
        losses.push(loss);
    }
    let ratio = losses[0] / losses[1];
    assert!((3.0..5.5).contains(&ratio), "first order: ratio {ratio}");
}
