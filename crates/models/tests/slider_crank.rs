//! The slider-crank with a clearance joint (docs/theory.md §7.3): penetration, symmetry, and
//! convergence to the ideal slider-crank as the clearance shrinks.

use moreau_kinematics::ContactKinematics;
use moreau_models::*;
use moreau_testsupport::velocity_at;
use std::f64::consts::PI;

fn run(c: f64, dt: f64) -> Simulation {
    let mut scene = Scene::report(ModelKind::SliderCrank);
    scene.set("c", &c.to_string()).unwrap();
    scene.dt = dt;
    scene.run().unwrap()
}

/// Largest penetration −g_N over the record.
fn penetration(sim: &Simulation) -> f64 {
    let (r, m) = (&sim.record, &sim.model);
    let mut pen = 0.0f64;
    for k in 0..r.len() {
        for i in 0..m.num_contacts() {
            pen = pen.max(-m.normal_gap(i, &r.q[k], r.t[k]));
        }
    }
    pen
}

#[test]
fn corner_penetration_is_proportional_to_dt() {
    let p = SliderCrankParams::report();
    let mut pens = Vec::new();
    for dt in [1e-5, 4e-5] {
        let sim = run(p.c, dt);
        let pen = penetration(&sim);
        // The speed scale of the mechanism is the crank tip's l1 ω1(0); no corner moves into the
        // guide faster, and without gap stabilisation the penetration stays of order speed · Δt.
        let bound = p.l1 * p.init.w1 * dt;
        eprintln!("slider-crank dt {dt}: largest penetration {pen:.3e} m (bound {bound:.3e} m)");
        assert!(pen > 0.0 && pen <= bound, "dt {dt}: penetration {pen} > {bound}");
        pens.push(pen);
        // The run ends on the step that reaches θ1 = 4π.
        let r = &sim.record;
        let n = r.len();
        assert!(r.q[n - 1][0] >= 4.0 * PI && r.q[n - 2][0] < 4.0 * PI);
    }
    // Four times the step, about four times the penetration.
    let ratio = pens[1] / pens[0];
    assert!((3.0..=5.0).contains(&ratio), "penetration ratio {ratio}");
}

#[test]
fn slider_stays_parallel_to_the_guide() {
    let sim = run(1e-3, 1e-5);
    let r = &sim.record;
    let th3 = r.q.iter().map(|q| q[2].abs()).fold(0.0, f64::max);
    let w3 = r.u.iter().map(|u| u[2].abs()).fold(0.0, f64::max);
    eprintln!("slider-crank symmetry: max |th3| = {th3:.2e} rad, max |w3| = {w3:.2e} rad/s");
    assert!(th3 < 1e-12 && w3 < 1e-9);
    // Corners on one face move alike.
    let AnyModel::SliderCrank(sc) = &sim.model else { panic!("wrong model") };
    for q in r.q.iter().step_by(97) {
        assert!((sc.normalized_corner(0, q) - sc.normalized_corner(1, q)).abs() < 1e-9);
        assert!((sc.normalized_corner(2, q) - sc.normalized_corner(3, q)).abs() < 1e-9);
    }
    // The slider hits the guide: impulses occur on both faces.
    assert!(r.p_n.iter().any(|p| p[0] > 0.0) && r.p_n.iter().any(|p| p[2] > 0.0));
}

#[test]
fn crank_speed_converges_to_the_ideal_as_the_clearance_shrinks() {
    let ideal = Scene::report(ModelKind::SliderCrankIdeal).run().unwrap();
    let angles: Vec<f64> = (1..16).map(|k| k as f64 * PI / 4.0).collect();
    let reference: Vec<f64> =
        angles.iter().map(|&a| velocity_at(&ideal.record, 0, a, 0).unwrap()).collect();
    let mut errors = Vec::new();
    for c in [1e-3, 1e-4, 1e-5] {
        let sim = run(c, 1e-5);
        let err = angles
            .iter()
            .zip(&reference)
            .map(|(&a, w)| (velocity_at(&sim.record, 0, a, 0).unwrap() - w).abs())
            .fold(0.0, f64::max);
        errors.push(err);
    }
    eprintln!(
        "slider-crank: largest |w1 - w1_ideal| at fixed crank angles for c = 1e-3, 1e-4, 1e-5: {errors:?}"
    );
    assert!(errors[1] < errors[0] && errors[2] < errors[1], "{errors:?}");
}

#[test]
fn one_guide_surface_can_be_left_out() {
    let mut scene = Scene::report(ModelKind::SliderCrank);
    scene.set("upper_surface", "false").unwrap();
    scene.t_end = 0.002;
    let sim = scene.run().unwrap();
    assert_eq!(sim.model.contact_names().len(), 2);
    assert!(sim.record.lcp_size.iter().all(|&s| s <= 6));
}
