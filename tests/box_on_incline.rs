//! The mechanism of `examples/box_on_incline` against closed forms: the first impact's speed
//! after a free fall, Newton's law at every impact, Coulomb's sliding acceleration, and the
//! energy that friction takes while the box slides flat.

#[path = "../examples/box_on_incline/mechanism.rs"]
mod mechanism;

use mechanism::{BoxOnIncline, G};
use moreau::kinematics::{FdOptions, SampleOptions, check_jacobians, sample_states};
use moreau::stepper::{Record, Stepper, StepperOptions};

const DT: f64 = 1e-4;
const EPS_N: f64 = 0.3;
const MU: f64 = 0.2;
const Q0: [f64; 3] = [0.0, 0.2, 0.3];

fn setup() -> (BoxOnIncline, Record) {
    let m = BoxOnIncline::new(1.0, 0.1, 0.05, 20f64.to_radians(), MU, EPS_N).unwrap();
    let mut s = Stepper::new(
        m.clone(),
        &Q0,
        &[0.0; 3],
        0.0,
        StepperOptions::new(DT).with_gap_tolerance(1e-12),
    )
    .unwrap();
    let r = s.record_until(1.5).unwrap();
    (m, r)
}

#[test]
fn jacobians_match_the_gaps() {
    let (m, _) = setup();
    let options = SampleOptions { count: 16, q_radius: 1.0, ..SampleOptions::default() };
    let samples = sample_states(&Q0, 0.0, options).unwrap();
    let report = check_jacobians(&m, &samples, FdOptions::default()).unwrap();
    assert!(report.passed(1e-8), "{:?}", report.worst());
}

#[test]
fn first_impact_comes_after_a_free_fall_and_every_impact_obeys_newtons_law() {
    let (m, r) = setup();
    // Released at rest without spin, every point falls along the incline's normal with
    // g cos α: the lowest corner (bottom left, contact 0) arrives at −sqrt(2 g cos α g_N0)
    // after sqrt(2 g_N0 / (g cos α)).
    let (s, c) = Q0[2].sin_cos();
    let gap0 = Q0[1] - m.a * s - m.b * c;
    let g_n = G * m.alpha.cos();
    let first = r.impacts[0];
    assert_eq!(first.contact, 0);
    assert!((first.gamma_n_before + (2.0 * g_n * gap0).sqrt()).abs() <= g_n * DT);
    assert!((first.t - (2.0 * gap0 / g_n).sqrt()).abs() <= DT);
    // Each impact closes a contact with P_N > 0, so ξ_N = γ_N,E + ε_N γ_N,A = 0.
    assert!(r.impacts.len() >= 10, "{} impacts", r.impacts.len());
    for i in &r.impacts {
        assert!(i.gamma_n_before < 0.0 && i.p_n > 0.0);
        assert!((i.gamma_n_after + EPS_N * i.gamma_n_before).abs() < 1e-9, "{i:?}");
        // Coulomb: the tangential impulse is bounded by μ P_N.
        assert!(i.p_t.abs() <= MU * i.p_n * (1.0 + 1e-9), "{i:?}");
    }
    // Both bottom corners are hit, the top ones never.
    assert!(r.impacts.iter().any(|i| i.contact == 1));
    assert!(r.impacts.iter().all(|i| i.contact < 2));
}

#[test]
fn the_box_ends_sliding_flat_with_coulombs_acceleration_and_friction_takes_the_energy() {
    let (m, r) = setup();
    let k1 = r.t.iter().position(|&t| t >= 1.0).unwrap();
    let k2 = r.len() - 1;
    for k in k1..=k2 {
        // Flat on its bottom face, both bottom corners closed and slipping.
        assert!(r.q[k][2].abs() < 1e-6 && (r.q[k][1] - m.b).abs() < 1e-6, "row {k}");
        assert!(r.p_n[k][0] > 0.0 && r.p_n[k][1] > 0.0 && r.p_n[k][2] == 0.0);
    }
    let (t1, t2) = (r.t[k1], r.t[k2]);
    let a = (r.u[k2][0] - r.u[k1][0]) / (t2 - t1);
    let expected = G * (m.alpha.sin() - MU * m.alpha.cos());
    assert!((a - expected).abs() < 1e-6 * expected, "{a} vs {expected}");
    assert!((m.sliding_acceleration() - expected).abs() < 1e-15);
    // With constant M and a potential linear in q, the midpoint rule's energy change over a
    // step is the work of the impulses at the mean velocity; sliding flat, that is
    // −μ P_N ẋ: the energy lost from t1 to t2 is μ m g cos α (x2 − x1) to round-off.
    let e = r.total_energy();
    let friction = MU * m.m * G * m.alpha.cos() * (r.q[k2][0] - r.q[k1][0]);
    assert!(
        ((e[k1] - e[k2]) - friction).abs() < 1e-6 * friction,
        "{} vs {friction}",
        e[k1] - e[k2]
    );
    // The impulses' dissipation over the same window, minus their work, is that energy lost.
    let d = r.cumulative_dissipation[k2] - r.cumulative_dissipation[k1];
    assert!((d - friction).abs() < 1e-6 * friction, "{d} vs {friction}");
}
