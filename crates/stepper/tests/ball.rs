//! The bouncing ball against its closed-form solution (docs/theory.md §7.1).

use moreau_stepper::{Record, Stepper, StepperOptions};
use moreau_testsupport::{Ball, G};

const Y0: f64 = 1.0;

fn run(eps: f64, dt: f64, t_end: f64) -> Record {
    let mut s = Stepper::new(Ball::new(eps), &[Y0], &[0.0], 0.0, StepperOptions::new(dt)).unwrap();
    s.record_until(t_end).unwrap()
}

/// Closed-form impact times t_k and the accumulation time t_∞ (docs/theory.md §7.1).
fn closed_form(eps: f64, k: usize) -> (Vec<f64>, f64) {
    let h = Y0 - 0.1;
    let t1 = (2.0 * h / G).sqrt();
    let v1 = (2.0 * G * h).sqrt();
    let mut t = vec![t1];
    for j in 1..k {
        let last = t[j - 1];
        t.push(last + 2.0 * eps.powi(j as i32) * v1 / G);
    }
    (t, t1 * (1.0 + eps) / (1.0 - eps))
}

/// Impact instants of a record: the midpoints of the steps that start a contact phase.
fn impacts(r: &Record, dt: f64) -> Vec<f64> {
    let mut out = Vec::new();
    for k in 1..r.len() {
        if r.p_n[k][0] > 0.0 && r.p_n[k - 1][0] == 0.0 {
            out.push(r.t[k] - 0.5 * dt);
        }
    }
    out
}

/// Apex heights between successive impacts.
fn apexes(r: &Record) -> Vec<f64> {
    let mut out = Vec::new();
    let mut best: Option<f64> = None;
    let first = (1..r.len()).find(|&k| r.p_n[k][0] > 0.0).unwrap_or(r.len());
    for k in first..r.len() {
        if r.p_n[k][0] > 0.0 {
            if let Some(b) = best.take() {
                out.push(b);
            }
        } else if r.q[k][0] > 0.1 && r.u[k - 1][0] >= 0.0 {
            best = Some(best.map_or(r.q[k][0], |b: f64| b.max(r.q[k][0])));
        }
    }
    out
}

/// Time after which every step carries an impulse (the ball rests).
fn rest_time(r: &Record, dt: f64) -> f64 {
    let last_free = (1..r.len()).rev().find(|&k| r.p_n[k][0] == 0.0).unwrap();
    r.t[last_free + 1] - 0.5 * dt
}

#[test]
fn impact_times_match_the_closed_form_within_one_step() {
    for dt in [1e-3, 1e-4] {
        let r = run(0.9, dt, 3.0);
        let (t_ref, _) = closed_form(0.9, 4);
        let t_sim = impacts(&r, dt);
        assert!(t_sim.len() >= 4, "found {} impacts", t_sim.len());
        for k in 0..4 {
            // The first instant is off by at most one step. Each impact then starts its
            // flight from the velocity at the start of its step (off by up to g Δt) and from
            // a penetration of up to v Δt / 2: each flight is off by at most 3 Δt.
            let bound = (1.0 + 3.0 * k as f64) * dt;
            assert!(
                (t_sim[k] - t_ref[k]).abs() <= bound,
                "dt = {dt}, impact {k}: {} vs {}",
                t_sim[k],
                t_ref[k]
            );
        }
    }
}

#[test]
fn first_impact_velocity_and_impulse_follow_newtons_law() {
    let dt = 1e-3;
    let r = run(0.9, dt, 1.0);
    let k = (1..r.len()).find(|&k| r.p_n[k][0] > 0.0).unwrap();
    let (v_pre, v_post) = (r.u[k - 1][0], r.u[k][0]);
    // Over the impact step: v_E = −ε v_A exactly, so P_N = m (v_E − v_A) + m g Δt.
    assert!((v_post + 0.9 * v_pre).abs() < 1e-12);
    assert!((r.p_n[k][0] - (v_post - v_pre + G * dt)).abs() < 1e-12);
    let v1 = (2.0 * G * 0.9f64).sqrt();
    assert!((v_pre + v1).abs() <= G * dt);
}

#[test]
fn apex_heights_converge_with_first_order() {
    let eps: f64 = 0.9;
    let v1 = (2.0 * G * 0.9f64).sqrt();
    let exact: Vec<f64> = (1..=3).map(|k| 0.1 + (eps.powi(k) * v1).powi(2) / (2.0 * G)).collect();
    let dts = [4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4];
    let errors: Vec<f64> = dts
        .iter()
        .map(|&dt| {
            let a = apexes(&run(eps, dt, 3.0));
            (0..3).map(|k| (a[k] - exact[k]).abs()).fold(0.0, f64::max)
        })
        .collect();
    for (dt, e) in dts.iter().zip(&errors) {
        assert!(*e <= 3.0 * v1 * dt, "dt = {dt}: apex error {e}");
    }
    // Least-squares slope of log(error) against log(dt).
    let x: Vec<f64> = dts.iter().map(|d| d.ln()).collect();
    let y: Vec<f64> = errors.iter().map(|e| e.ln()).collect();
    let (mx, my) = (x.iter().sum::<f64>() / 5.0, y.iter().sum::<f64>() / 5.0);
    let slope = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum::<f64>()
        / x.iter().map(|a| (a - mx).powi(2)).sum::<f64>();
    assert!((0.8..=1.3).contains(&slope), "observed order {slope}, errors {errors:?}");
}

#[test]
fn rest_time_converges_to_the_accumulation_point() {
    let eps = 0.9;
    let (_, t_inf) = closed_form(eps, 1);
    let mut previous = f64::INFINITY;
    for dt in [1e-3, 1e-4] {
        let r = run(eps, dt, 10.0);
        let err = (rest_time(&r, dt) - t_inf).abs();
        // The discrete ball stops once a bounce lasts less than about a step; the lost
        // geometric tail is about 2Δt/(1 − ε), plus one step per bounce of drift.
        assert!(err <= 60.0 * dt, "dt = {dt}: rest time error {err}");
        assert!(err < previous);
        previous = err;
        // At rest every step carries P_N = m g Δt and v stays zero.
        let last = r.len() - 1;
        assert!((r.p_n[last][0] - G * dt).abs() < 1e-12);
        assert!(r.u[last][0].abs() < 1e-12);
    }
}

#[test]
fn perfectly_elastic_ball_keeps_its_energy_over_1e5_steps() {
    let dt = 1e-4;
    let r = run(1.0, dt, 10.0);
    assert_eq!(r.len(), 100_001);
    let e = r.total_energy();
    let e0 = e[0];
    let v1 = (2.0 * G * 0.9f64).sqrt();
    // Flight is integrated exactly; an impact can shift the energy by at most the work of
    // gravity over the penetration, m g v Δt.
    let drift = e.iter().map(|x| (x - e0).abs()).fold(0.0, f64::max);
    assert!(drift <= G * v1 * dt, "energy drift {drift}");
    // And it still bounces: about 10 s / (2 t1) impacts.
    let n = impacts(&r, dt).len();
    assert!((11..=12).contains(&n), "{n} impacts");
}

#[test]
fn energy_balance_of_each_step_is_the_work_of_the_impulse() {
    // With constant M and gravity, q_E − q_A = Δt (u_A + u_E)/2 makes the discrete energy
    // change exactly ΔE = (u_A + u_E) P_N / 2; an impact (u_E = −ε u_A, u_A < 0) loses energy.
    for eps in [0.0, 0.5, 0.9, 1.0] {
        let dt = 1e-3;
        let r = run(eps, dt, 5.0);
        let e = r.total_energy();
        for k in 1..e.len() {
            let work = 0.5 * (r.u[k - 1][0] + r.u[k][0]) * r.p_n[k][0];
            assert!((e[k] - e[k - 1] - work).abs() < 1e-12, "eps = {eps}, step {k}");
        }
        // Over the run, energy never exceeds the initial one by more than m g v Δt.
        let v1 = (2.0 * G * 0.9f64).sqrt();
        let gain = e.iter().map(|x| x - e[0]).fold(f64::NEG_INFINITY, f64::max);
        assert!(gain <= G * v1 * dt, "eps = {eps}: energy gain {gain}");
        if eps < 1.0 {
            assert!(e[e.len() - 1] < e[0] - 0.5, "eps = {eps}: the ball should have settled");
            // The dissipation is minus the impulses' work P_N (u_A + u_E) / 2, which is the
            // midpoint rule's change of energy under gravity: over the run it is the energy
            // lost, at every row, and the resting ball (u_A = u_E = 0) adds nothing to it.
            for (k, d) in r.cumulative_dissipation.iter().enumerate() {
                let lost = e[0] - e[k];
                assert!((d - lost).abs() < 1e-12, "eps = {eps}, row {k}: {d} {lost}");
            }
            let dissipated = r.cumulative_dissipation[e.len() - 1];
            assert!(dissipated > 0.0);
        }
    }
}

#[test]
fn every_solver_gives_the_same_bouncing_ball() {
    // The scalar LCP has one solution; the closed form of the default path, Lemke, PGS and
    // enumeration must all find it.
    use moreau_stepper::SolverChoice;
    let reference = run(0.7, 1e-3, 3.0);
    for solver in [SolverChoice::Lemke, SolverChoice::pgs_default(), SolverChoice::Enumeration] {
        let opts = StepperOptions::new(1e-3).with_solver(solver);
        let mut s = Stepper::new(Ball::new(0.7), &[Y0], &[0.0], 0.0, opts).unwrap();
        let r = s.record_until(3.0).unwrap();
        // PGS's update z − (Az + b)/A rounds differently from −b/A; near the accumulation
        // point (t_∞ = 2.43 s) such round-off decides whether a bounce lasts one more step,
        // so PGS is compared before it.
        let rows = if matches!(solver, SolverChoice::Pgs { .. }) { 2000 } else { r.len() };
        for k in 0..rows {
            assert!((r.q[k][0] - reference.q[k][0]).abs() < 1e-12, "{solver:?}, row {k}");
            assert!((r.p_n[k][0] - reference.p_n[k][0]).abs() < 1e-12, "{solver:?}, row {k}");
        }
    }
}

#[test]
fn impacts_of_the_record_match_the_closed_form_speeds() {
    // Each impact k of the closed form arrives at v_k = ε^(k−1) sqrt(2 g H) and leaves at
    // −ε times that. The scheme's γ_N,A is the velocity at the start of the impact step,
    // within g Δt of the closed form's for the first impact and within k g Δt (one step's
    // gravity per flight) for the later ones; γ_N,E = −ε_N γ_N,A holds to round-off, as
    // Newton's law with one frictionless contact and a constant w_N says.
    for (eps, dt) in [(0.9, 1e-3), (0.7, 1e-4), (0.0, 1e-3)] {
        let r = run(eps, dt, 3.0);
        let v1 = (2.0 * G * (Y0 - 0.1)).sqrt();
        let (t_ref, _) = closed_form(eps, 3);
        let hard = r.impacts.iter().filter(|i| i.gamma_n_before < -10.0 * G * dt);
        let n_checked = hard.clone().count();
        assert!(n_checked >= if eps > 0.0 { 3 } else { 1 }, "ε = {eps}: {n_checked} impacts");
        for (k, i) in hard.take(3).enumerate() {
            let v_k = -v1 * eps.powi(k as i32);
            assert_eq!(i.contact, 0);
            assert!(
                (i.gamma_n_before - v_k).abs() <= (k + 1) as f64 * G * dt,
                "ε = {eps}, impact {k}: γ_N before {} vs {v_k}",
                i.gamma_n_before
            );
            assert!((i.gamma_n_after + eps * i.gamma_n_before).abs() < 1e-12);
            // P_N = m (γ_N,E − ũ) with ũ = γ_N,A − g Δt and m = 1.
            assert!((i.p_n - (i.gamma_n_after - i.gamma_n_before + G * dt)).abs() < 1e-12);
            assert!((i.t - 0.5 * dt - t_ref[k]).abs() <= (1.0 + 3.0 * k as f64) * dt);
        }
        // Persistent contact is no impact: after the ball comes to rest nothing is listed,
        // and every listed impact starts a contact phase of the record.
        for i in &r.impacts {
            let k = r.t.iter().position(|&t| t == i.t).unwrap();
            assert!(r.p_n[k][0] > 0.0 && r.p_n[k - 1][0] == 0.0, "ε = {eps}, step {}", i.step);
        }
        let phases = (1..r.len()).filter(|&k| r.p_n[k][0] > 0.0 && r.p_n[k - 1][0] == 0.0);
        assert_eq!(phases.count(), r.impacts.len(), "ε = {eps}");
    }
}
