//! The ideal slider-crank: analytic derivatives against finite differences, the reduced mass
//! against the 3-DOF model's M, and conservation of energy.

use moreau_models::*;
use moreau_stepper::Mechanism;
use moreau_testsupport::SplitMix64;

#[test]
fn reduced_mass_and_potential_derivatives_match_finite_differences() {
    let ideal = SliderCrankIdeal::new(SliderCrankIdealParams::report()).unwrap();
    let mut rng = SplitMix64::new(7);
    for _ in 0..40 {
        let th = rng.uniform(-7.0, 7.0);
        let h = 1e-6;
        let dm = (ideal.reduced_mass(th + h) - ideal.reduced_mass(th - h)) / (2.0 * h);
        let dv = (ideal.potential(th + h) - ideal.potential(th - h)) / (2.0 * h);
        assert!((ideal.reduced_mass_derivative(th) - dm).abs() < 1e-8, "th1 = {th}");
        assert!((ideal.potential_derivative(th) - dv).abs() < 1e-7, "th1 = {th}");
        let dth2 = (ideal.rod_angle(th + h) - ideal.rod_angle(th - h)) / (2.0 * h);
        assert!((ideal.rod_ratio(th) - dth2).abs() < 1e-8);
        // h = −½ M_r' ω² − V'.
        let w = rng.uniform(-200.0, 200.0);
        let mut force = [0.0];
        ideal.forces(&[th], &[w], 0.0, &mut force);
        let expected = -0.5 * dm * w * w - dv;
        assert!((force[0] - expected).abs() < 1e-6 * (1.0 + expected.abs()));
    }
}

#[test]
fn reduced_mass_is_the_clearance_models_mass_along_the_ideal_motion() {
    let params = SliderCrankParams::report();
    let full = SliderCrank::new(params.clone()).unwrap();
    let ideal = SliderCrankIdeal::new(params.ideal()).unwrap();
    for k in 0..24 {
        let th1 = k as f64 * 0.3;
        let th2 = ideal.rod_angle(th1);
        // The ideal constraint keeps the slider on y3 = 0.
        assert!(full.slider_center(&[th1, th2, 0.0])[1].abs() < 1e-15);
        let mut m = [0.0; 9];
        full.mass_matrix(&[th1, th2, 0.0], 0.0, &mut m);
        let kk = ideal.rod_ratio(th1);
        let projected = m[0] + 2.0 * m[1] * kk + m[4] * kk * kk;
        assert!((ideal.reduced_mass(th1) - projected).abs() < 1e-15 * projected.max(1.0) * 10.0);
        let mut v = [0.0];
        ideal.mass_matrix(&[th1], 0.0, &mut v);
        assert_eq!(v[0], ideal.reduced_mass(th1));
        let v3 = full.potential_energy(&[th1, th2, 0.0], 0.0).unwrap();
        assert!((ideal.potential(th1) - v3).abs() < 1e-15);
    }
}

fn relative_energy_drift(dt: f64) -> f64 {
    let mut scene = Scene::report(ModelKind::SliderCrankIdeal);
    scene.dt = dt;
    let sim = scene.run().unwrap();
    let r = &sim.record;
    assert!(*r.q.last().unwrap().first().unwrap() >= 4.0 * std::f64::consts::PI);
    let e = r.total_energy();
    let ideal = match &sim.model {
        AnyModel::SliderCrankIdeal(m) => m.clone(),
        other => panic!("wrong model {:?}", other.kind()),
    };
    // The record's energy is the model's E = ½ M_r ω1² + V.
    assert!((e[0] - ideal.energy(r.q[0][0], r.u[0][0])).abs() < 1e-12);
    e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / e[0]
}

#[test]
fn ideal_slider_crank_conserves_energy_to_first_order_in_dt() {
    let coarse = relative_energy_drift(1e-4);
    let fine = relative_energy_drift(1e-5);
    eprintln!(
        "relative energy drift over two revolutions: dt 1e-4: {coarse:.3e}, dt 1e-5: {fine:.3e}"
    );
    // Moreau's midpoint rule is first order: ten times smaller steps, about ten times less drift.
    assert!(fine < coarse / 5.0, "{fine} vs {coarse}");
    // The drift per unit of ω1 Δt stays of order one (ω1 ≈ 150 rad/s, 2 revolutions).
    assert!(fine < 150.0 * 1e-5 * 10.0);
}
