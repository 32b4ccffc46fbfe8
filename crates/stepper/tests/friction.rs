//! Coulomb friction against closed forms: a block on an incline and one braking on a floor.

use moreau_stepper::{ContactState, SolverChoice, Stepper, StepperOptions};
use moreau_testsupport::{Block, G};

/// Distance, speed along the slope and final contact state after `t_end`. The active-set
/// threshold of 1e-12 m keeps round-off from opening the contact (see the test below).
fn slide(alpha: f64, mu: f64, solver: SolverChoice, t_end: f64) -> (f64, f64, ContactState) {
    slide_with(alpha, mu, solver, t_end, 1e-12)
}

fn slide_with(
    alpha: f64,
    mu: f64,
    solver: SolverChoice,
    t_end: f64,
    gap_tol: f64,
) -> (f64, f64, ContactState) {
    let block = Block::new(alpha, mu);
    let opts = StepperOptions::new(1e-3).with_solver(solver).with_gap_tolerance(gap_tol);
    let mut s = Stepper::new(block, &[0.0, 0.0], &[0.0, 0.0], 0.0, opts).unwrap();
    let mut state = ContactState::Open;
    s.run_until(t_end, &mut |r: &moreau_stepper::StepReport<'_>| {
        state = r.contacts[0].state;
        std::ops::ControlFlow::Continue(())
    })
    .unwrap();
    let (sn, cs) = alpha.sin_cos();
    let (q, u) = (s.q(), s.u());
    // Distance and speed along the slope (down-slope positive).
    (-(q[0] * cs + q[1] * sn), -(u[0] * cs + u[1] * sn), state)
}

#[test]
fn block_sticks_when_tan_alpha_is_at_most_mu() {
    for solver in [SolverChoice::Auto, SolverChoice::Lemke, SolverChoice::pgs_default()] {
        for (alpha, mu) in [(0.2, 0.3), (0.29, 0.3), (0.3f64.atan() - 1e-6, 0.3)] {
            let (d, v, state) = slide(alpha, mu, solver, 1.0);
            // PGS stops at its tolerance of 1e-10 per step; the pivoting solvers are exact.
            let tol = if matches!(solver, SolverChoice::Pgs { .. }) { 1e-7 } else { 1e-12 };
            assert!(d.abs() < tol && v.abs() < tol, "{solver:?} α = {alpha}: d = {d}, v = {v}");
            assert_eq!(state, ContactState::Stick);
        }
    }
}

#[test]
fn block_slides_with_the_coulomb_acceleration() {
    for solver in [SolverChoice::Auto, SolverChoice::Lemke, SolverChoice::pgs_default()] {
        for (alpha, mu) in [(0.5, 0.3), (0.8, 0.1), (0.4, 0.0)] {
            let t = 1.0;
            let (d, v, state) = slide(alpha, mu, solver, t);
            let a = G * (alpha.sin() - mu * alpha.cos());
            // The midpoint rule integrates a constant acceleration exactly.
            assert!((v - a * t).abs() < 1e-9 * (1.0 + a), "{solver:?}: v = {v}, a t = {}", a * t);
            assert!((d - 0.5 * a * t * t).abs() < 1e-9, "{solver:?}: d = {d}");
            assert_eq!(state, ContactState::Slip);
        }
    }
}

#[test]
fn block_launched_on_a_floor_stops_at_v2_over_2_mu_g() {
    let (mu, v0) = (0.4, 3.0);
    let exact = v0 * v0 / (2.0 * mu * G);
    for dt in [1e-3, 1e-4] {
        let block = Block::new(0.0, mu);
        let mut s =
            Stepper::new(block, &[0.0, 0.0], &[v0, 0.0], 0.0, StepperOptions::new(dt)).unwrap();
        let r = s.record_until(1.5).unwrap();
        let last = r.len() - 1;
        assert!(r.u[last][0].abs() < 1e-12, "still moving: {}", r.u[last][0]);
        assert!((r.q[last][0] - exact).abs() <= v0 * dt, "dt = {dt}: {} vs {exact}", r.q[last][0]);
        // Deceleration is μ g while sliding: speed after 0.5 s.
        let k = (0.5 / dt).round() as usize;
        assert!((r.u[k][0] - (v0 - mu * G * 0.5)).abs() < 1e-9);
        assert_eq!(r.state[last][0], ContactState::Stick);
        // The work of friction equals the kinetic energy lost: m v0² / 2.
        let lost = r.kinetic[0] - r.kinetic[last];
        assert!((lost - 2.0 * v0 * v0 / 2.0).abs() < 1e-9);
    }
}

#[test]
fn without_a_gap_threshold_round_off_costs_at_most_a_few_free_steps() {
    // The scheme as written: a midpoint gap of +1e-22 m opens the contact for one step, in
    // which the block falls freely. The error stays of the order of g Δt per such step.
    let dt = 1e-3;
    for (alpha, mu) in [(0.2, 0.3), (0.5, 0.3)] {
        let (d, v, _) = slide_with(alpha, mu, SolverChoice::Auto, 1.0, 0.0);
        let a = G * (alpha.sin() - mu * alpha.cos()).max(0.0);
        assert!((v - a).abs() <= 3.0 * G * dt, "α = {alpha}: v = {v}, exact {a}");
        assert!((d - 0.5 * a).abs() <= 3.0 * G * dt, "α = {alpha}: d = {d}, exact {}", 0.5 * a);
    }
}
