//! Rheonomic contacts, frictionless rows, simultaneous impacts and input validation.

use std::ops::ControlFlow;

use moreau_setvalued::ContactLaw;
use moreau_stepper::{SolverChoice, StepError, StepReport, Stepper, StepperOptions};
use moreau_testsupport::{Ball, Block, G, Rod};

#[test]
fn moving_floor_reverses_the_relative_velocity_at_impact() {
    // A floor oscillating as A sin(Ω t) meets the falling ball; Newton's law acts on the
    // relative velocity γ_N = v − ẏ_floor, with ẏ_floor taken at the step's midpoint.
    for eps in [0.0, 0.5, 1.0] {
        let mut ball = Ball::new(eps);
        ball.amplitude = 0.05;
        ball.omega = 20.0;
        let floor = ball.clone();
        let dt = 1e-4;
        let mut s = Stepper::new(ball, &[0.6], &[0.0], 0.0, StepperOptions::new(dt)).unwrap();
        let mut checked = 0;
        let mut v_a = 0.0;
        s.run_until(1.0, &mut |r: &StepReport<'_>| {
            let c = r.contacts[0];
            if c.p_n > 0.0 {
                let t_m = r.t - 0.5 * dt;
                let w_hat = -floor.floor(t_m).1;
                let gamma_a = v_a + w_hat;
                let gamma_e = r.u[0] + w_hat;
                assert!((c.gamma_n - gamma_e).abs() < 1e-12);
                assert!(
                    (gamma_e + eps * gamma_a).abs() < 1e-12,
                    "ε = {eps}: {gamma_e} vs {gamma_a}"
                );
                checked += 1;
            }
            v_a = r.u[0];
            ControlFlow::Continue(())
        })
        .unwrap();
        assert!(checked > 0);
    }
}

#[test]
fn floor_moving_up_lifts_a_resting_ball() {
    // A floor rising at constant speed V (A sin Ωt with tiny Ω ≈ V t): the plastic ball rides
    // on it with v = V.
    let mut ball = Ball::new(0.0);
    ball.amplitude = 1.0;
    ball.omega = 0.01;
    let mut s = Stepper::new(ball, &[0.1], &[0.0], 0.0, StepperOptions::new(1e-3)).unwrap();
    let r = s.record_until(0.5).unwrap();
    let last = r.len() - 1;
    let v_floor = 0.01 * (0.01f64 * 0.4995).cos();
    assert!((r.u[last][0] - v_floor).abs() < 1e-9);
    // Each step's impulse carries gravity plus the floor's acceleration (≈ 0).
    assert!((r.p_n[last][0] - G * 1e-3).abs() < 1e-6);
}

#[test]
fn frictionless_contacts_give_the_same_trajectory_with_or_without_friction_rows() {
    // A rod falling at an angle, so its ends hit with a tangential velocity.
    for solver in [SolverChoice::Auto, SolverChoice::Lemke] {
        let rod = Rod::new(0.5, 0.0);
        let q0 = [0.0, 0.4, 0.3];
        let u0 = [1.0, -1.0, 2.0];
        let base = StepperOptions::new(1e-3).with_solver(solver);
        let mut full = base.clone();
        full.friction_rows_when_frictionless = true;
        let mut a = Stepper::new(rod.clone(), &q0, &u0, 0.0, base).unwrap();
        let mut b = Stepper::new(rod, &q0, &u0, 0.0, full).unwrap();
        let mut sizes = (0, 0);
        for _ in 0..2000 {
            let ra = a.step().unwrap();
            sizes.0 = sizes.0.max(ra.lcp_size);
            let rb = b.step().unwrap();
            sizes.1 = sizes.1.max(rb.lcp_size);
        }
        for k in 0..3 {
            assert!((a.q()[k] - b.q()[k]).abs() < 1e-10, "{solver:?}: q differs");
            assert!((a.u()[k] - b.u()[k]).abs() < 1e-10, "{solver:?}: u differs");
        }
        assert_eq!(sizes, (2, 6), "LCP sizes with normal rows only and with all rows");
    }
}

#[test]
fn rod_landing_flat_hits_with_both_ends_at_once() {
    // Simultaneous plastic impact of both ends: equal impulses, no rotation.
    for mu in [0.0, 0.5] {
        let rod = Rod::new(0.0, mu);
        let mut s =
            Stepper::new(rod, &[0.0, 0.2, 0.0], &[0.3, 0.0, 0.0], 0.0, StepperOptions::new(1e-3))
                .unwrap();
        let mut first = None;
        while first.is_none() {
            let r = s.step().unwrap();
            if r.contacts[0].p_n > 0.0 || r.contacts[1].p_n > 0.0 {
                first = Some((r.contacts[0], r.contacts[1], r.lcp_size, r.u.to_vec()));
            }
        }
        let (c0, c1, size, u) = first.unwrap();
        assert_eq!(size, if mu > 0.0 { 6 } else { 2 });
        assert!((c0.p_n - c1.p_n).abs() < 1e-12 * c0.p_n, "{} vs {}", c0.p_n, c1.p_n);
        assert!(u[1].abs() < 1e-12 && u[2].abs() < 1e-12, "u after impact {u:?}");
        // Friction can stop the sliding (μ P_N > m v_x): the rod sticks; without it, v_x stays.
        let v_x = if mu > 0.0 { 0.0 } else { 0.3 };
        assert!((u[0] - v_x).abs() < 1e-12, "μ = {mu}: v_x = {}", u[0]);
    }
}

#[test]
fn invalid_input_is_rejected_with_typed_errors() {
    let ball = || Ball::new(0.5);
    let err = |r: Result<Stepper<Ball>, StepError>| r.unwrap_err();
    assert!(matches!(
        err(Stepper::new(ball(), &[1.0], &[0.0], 0.0, StepperOptions::new(0.0))),
        StepError::InvalidTimeStep { .. }
    ));
    assert!(matches!(
        err(Stepper::new(ball(), &[1.0], &[0.0], 0.0, StepperOptions::new(-1e-3))),
        StepError::InvalidTimeStep { .. }
    ));
    assert!(matches!(
        err(Stepper::new(ball(), &[1.0], &[0.0], 0.0, StepperOptions::new(f64::NAN))),
        StepError::InvalidTimeStep { .. }
    ));
    assert!(matches!(
        err(Stepper::new(ball(), &[f64::NAN], &[0.0], 0.0, StepperOptions::new(1e-3))),
        StepError::NonFinite { what: "q0", .. }
    ));
    assert!(matches!(
        err(Stepper::new(ball(), &[1.0, 2.0], &[0.0], 0.0, StepperOptions::new(1e-3))),
        StepError::Dimension { what: "q0", expected: 1, found: 2 }
    ));
    let pgs = SolverChoice::Pgs { tolerance: 1e-10, omega: 2.5, max_iterations: 10 };
    assert!(matches!(
        err(Stepper::new(ball(), &[1.0], &[0.0], 0.0, StepperOptions::new(1e-3).with_solver(pgs))),
        StepError::Lcp(_)
    ));
    assert!(ContactLaw::new(1.5, 0.0, 0.1).is_err());
    assert!(ContactLaw::new(0.5, -0.1, 0.1).is_err());
    assert!(ContactLaw::new(0.5, 0.0, -0.1).is_err());
    assert!("simplex".parse::<SolverChoice>().is_err());

    // A mass matrix that is not positive definite stops the first step.
    let mut b = ball();
    b.m = -1.0;
    let mut s = Stepper::new(b, &[1.0], &[0.0], 0.0, StepperOptions::new(1e-3)).unwrap();
    assert!(matches!(s.step().unwrap_err(), StepError::MassNotSpd { .. }));
    // And an end time in the past is refused.
    let mut s = Stepper::new(ball(), &[1.0], &[0.0], 1.0, StepperOptions::new(1e-3)).unwrap();
    assert!(matches!(s.record_until(0.5).unwrap_err(), StepError::EndBeforeStart { .. }));
}

#[test]
fn run_until_takes_whole_steps_without_drift() {
    let mut s = Stepper::new(
        Block::new(0.3, 0.5),
        &[0.0, 0.0],
        &[0.0, 0.0],
        0.0,
        StepperOptions::new(1e-4),
    )
    .unwrap();
    let summary = s.run_until(1.0, &mut |_: &StepReport<'_>| ControlFlow::Continue(())).unwrap();
    assert_eq!(summary.steps, 10_000);
    assert_eq!(s.t(), 1.0);
    // An observer that breaks stops the run.
    let summary = s
        .run_until(2.0, &mut |r: &StepReport<'_>| {
            if r.t >= 1.5 { ControlFlow::Break(()) } else { ControlFlow::Continue(()) }
        })
        .unwrap();
    assert!(summary.stopped_early);
    assert!((s.t() - 1.5).abs() < 1e-12);
}

#[test]
fn projection_removes_the_penetration_and_keeps_energy_from_growing() {
    for eps in [0.0, 0.5, 1.0] {
        let dt = 1e-3;
        let plain = StepperOptions::new(dt);
        let mut projected = plain.clone();
        projected.projection = true;
        let run = |opts: StepperOptions| {
            Stepper::new(Ball::new(eps), &[1.0], &[0.0], 0.0, opts)
                .unwrap()
                .record_until(5.0)
                .unwrap()
        };
        let (a, b) = (run(plain), run(projected));
        let deepest =
            |r: &moreau_stepper::Record| r.q.iter().map(|q| q[0] - 0.1).fold(0.0, f64::min);
        // The scheme as written penetrates by up to v Δt / 2 at an impact (for ε = 1 the end
        // position q_E = q_A of the impact step is outside).
        let v1 = (2.0 * G * 0.9f64).sqrt();
        assert!(deepest(&a) >= -v1 * dt, "eps = {eps}: {}", deepest(&a));
        if eps < 1.0 {
            assert!(deepest(&a) < -1e-5, "eps = {eps}: {}", deepest(&a));
        }
        assert!(deepest(&b) >= -1e-15, "eps = {eps}: projected run penetrates by {}", deepest(&b));
        let e = b.total_energy();
        let gain = e.iter().map(|x| x - e[0]).fold(f64::NEG_INFINITY, f64::max);
        assert!(gain <= 1e-12, "eps = {eps}: projected energy grows by {gain}");
        // The lift out of the floor, m g δy per correction, is counted apart from the
        // impulses' dissipation: with it, T + V + dissipated − projected stays at E₀.
        let last = b.len() - 1;
        let projected = b.cumulative_projection[last];
        let balance = |r: &moreau_stepper::Record, k: usize| {
            e[0] - (r.kinetic[k] + r.potential[k] + r.cumulative_dissipation[k])
                + r.cumulative_projection[k]
        };
        let worst = (0..b.len()).map(|k| balance(&b, k).abs()).fold(0.0, f64::max);
        assert!(worst <= 1e-12, "eps = {eps}: T + V + dissipated − projected departs by {worst:e}");
        assert!(a.cumulative_projection.iter().all(|&p| p == 0.0));
        if eps < 1.0 {
            // Each impact's penetration, at most v Δt at the impact's speed v (deepest
            // above), lifted by m g (m = 1 kg): the impacts' speeds v₁ εᵏ sum to v₁ / (1 − ε).
            let bound = G * dt * v1 / (1.0 - eps);
            assert!(projected > 0.1 * bound && projected <= bound, "eps = {eps}: {projected:e}");
        }
    }
}

#[test]
fn last_lcp_exposes_the_assembled_problem() {
    let mut s = Stepper::new(
        Rod::new(0.0, 0.5),
        &[0.0, 0.2, 0.0],
        &[0.3, 0.0, 0.0],
        0.0,
        StepperOptions::new(1e-3),
    )
    .unwrap();
    assert!(s.last_lcp().is_none());
    loop {
        let r = s.step().unwrap();
        if r.contacts[0].p_n > 0.0 {
            break;
        }
    }
    let lcp = s.last_lcp().expect("the impact step solved an LCP").to_owned();
    assert_eq!(lcp.n(), 6);
    // The ξ_L block of eq. 7.41: rows 4-5 are (2μ, −I, 0).
    assert_eq!(lcp.m()[(4, 0)], 1.0);
    assert_eq!(lcp.m()[(4, 2)], -1.0);
    assert_eq!(lcp.m()[(4, 4)], 0.0);
    let mut sol = moreau_lcp::Solution::new();
    use moreau_lcp::Solver;
    moreau_lcp::Enumeration::default().solve_into(lcp.view(), None, &mut sol).unwrap();
    assert!(sol.is_solved());
}

/// f free particles (unit masses) on a line above a floor, each with its own contact, whose
/// force or gap turns bad once t passes `t_bad`.
#[derive(Clone, Debug)]
struct Faulty {
    f: usize,
    laws: Vec<ContactLaw>,
    t_bad: f64,
    bad_h: f64,
    bad_gap: f64,
}

impl moreau_kinematics::ContactKinematics for Faulty {
    fn num_coordinates(&self) -> usize {
        self.f
    }
    fn num_contacts(&self) -> usize {
        self.f
    }
    fn normal_gap(&self, i: usize, q: &[f64], t: f64) -> f64 {
        if t > self.t_bad && i + 1 == self.f { self.bad_gap } else { q[i] }
    }
    fn contact(
        &self,
        i: usize,
        q: &[f64],
        t: f64,
        w_n: &mut [f64],
        w_t: &mut [f64],
    ) -> moreau_kinematics::ContactPoint {
        w_n.fill(0.0);
        w_t.fill(0.0);
        w_n[i] = 1.0;
        moreau_kinematics::ContactPoint {
            g_n: self.normal_gap(i, q, t),
            g_t: 0.0,
            w_n_hat: 0.0,
            w_t_hat: 0.0,
        }
    }
}

impl moreau_stepper::Mechanism for Faulty {
    fn laws(&self) -> &[ContactLaw] {
        &self.laws
    }
    fn mass_matrix(&self, _q: &[f64], _t: f64, m: &mut [f64]) {
        m.fill(0.0);
        for i in 0..self.f {
            m[i + i * self.f] = 1.0;
        }
    }
    fn forces(&self, _q: &[f64], _u: &[f64], t: f64, h: &mut [f64]) {
        h.fill(-G);
        if t > self.t_bad {
            h[self.f - 1] = self.bad_h;
        }
    }
    fn constant_mass_matrix(&self) -> bool {
        true
    }
}

#[test]
fn non_finite_values_are_named_and_leave_the_state_at_the_start_of_the_step() {
    // f = 1 and 3 take the stepper's fixed-order path, f = 6 the general one. The last
    // particle starts on the floor (its contact is active) or above it (it is not).
    for f in [1, 3, 6] {
        for (bad_h, bad_gap, on_floor, v0, what) in [
            (f64::NAN, 1.0, false, 0.0, "h"),
            (f64::NAN, 0.0, true, 0.0, "h"),
            (f64::INFINITY, 1.0, false, 0.0, "h"),
            (-G, f64::NAN, false, 0.0, "g_N"),
            (-G, f64::INFINITY, false, 0.0, "g_N"),
            (-G, f64::NEG_INFINITY, false, 0.0, "g_N"),
            // Finite forces and velocities whose sum is past the range of f64.
            (f64::MAX, 1.0, false, f64::MAX, "u"),
        ] {
            let laws = vec![ContactLaw::frictionless(0.5).unwrap(); f];
            let model = Faulty { f, laws, t_bad: 0.0102, bad_h, bad_gap };
            let mut q0 = vec![1.0; f];
            if on_floor {
                q0[f - 1] = 0.0;
            }
            let options = StepperOptions::new(1e-3);
            let mut u0 = vec![0.0; f];
            u0[f - 1] = v0;
            let mut s = Stepper::new(model, &q0, &u0, 0.0, options).unwrap();
            s.run_until(0.01, &mut |_: &StepReport<'_>| ControlFlow::Continue(())).unwrap();
            let (t, q, u, steps) = (s.t(), s.q().to_vec(), s.u().to_vec(), s.steps());
            let error = s.step().unwrap_err();
            let case = format!("f = {f}, h = {bad_h}, g = {bad_gap}");
            match error {
                StepError::NonFinite { what: w, index, .. } => {
                    assert_eq!(w, what, "{case}");
                    assert_eq!(index, f - 1, "{case}");
                }
                e => panic!("{case}: {e:?}"),
            }
            assert_eq!((s.t(), s.q(), s.u(), s.steps()), (t, &q[..], &u[..], steps), "{case}");
        }
    }
}
