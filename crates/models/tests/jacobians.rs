//! Finite-difference checks of every contact's w_N, w_T, ŵ_N, ŵ_T, of h = −∂V/∂q at u = 0,
//! and of the mass matrices' symmetry and definiteness.

use moreau_kinematics::{
    ContactKinematics, FdOptions, SampleOptions, assert_consistent, check_jacobians, sample_states,
};
use moreau_models::*;
use moreau_stepper::{Mechanism, check_evaluate};
use nalgebra::DMatrix;

fn samples(model: &AnyModel, t0: f64, q_radius: f64, t_radius: f64) -> Vec<(Vec<f64>, f64)> {
    let (q0, _) = model.initial_state();
    let opts = SampleOptions { count: 12, q_radius, t_radius, seed: 0x00C0_FFEE };
    sample_states(&q0, t0, opts).unwrap()
}

fn all_models() -> Vec<AnyModel> {
    let mut models: Vec<AnyModel> =
        ModelKind::ALL.iter().map(|&k| ModelParams::report(k).build().unwrap()).collect();
    models.push(ModelParams::Cam(CamParams::as_printed()).build().unwrap());
    models.push(ModelParams::Painleve(PainleveParams::report_with_mu(2.0)).build().unwrap());
    models
}

#[test]
fn contact_jacobians_match_finite_differences() {
    for model in all_models() {
        let report = match model.kind() {
            // The cam's lift is smooth inside a rise; sample times in the first lobe's rise.
            ModelKind::Cam => {
                let s = samples(&model, 0.02, 0.005, 0.01);
                check_jacobians(&model, &s, FdOptions::default()).unwrap()
            }
            _ => assert_consistent(&model, &samples(&model, 0.0, 0.1, 0.0), 1e-7).unwrap(),
        };
        assert!(report.passed(1e-7), "{}: {:?}", model.kind(), report.worst());
        assert_eq!(report.contacts.len(), model.num_contacts());
    }
}

#[test]
fn cam_rheonomic_term_is_minus_the_lift_rate() {
    let cam = Cam::new(CamParams::report()).unwrap();
    let (mut w_n, mut w_t) = ([0.0], [0.0]);
    for t in [0.001, 0.013, 0.031, 0.049] {
        let cp = cam.contact(0, &[0.0], t, &mut w_n, &mut w_t);
        let h = 1e-7;
        let fd = (cam.params().lift(t + h) - cam.params().lift(t - h)) / (2.0 * h);
        assert!((cp.w_n_hat + fd).abs() < 1e-6, "t = {t}: {} vs {}", cp.w_n_hat, -fd);
        assert_eq!(w_n[0], 1.0);
    }
    // Closed form: ds/dt at mid-rise (ψ = β/2) is 2 H ω / β.
    let p = cam.params();
    let t_mid = p.beta / 2.0 / p.omega;
    assert!((p.lift_rate(t_mid) - 2.0 * p.stroke * p.omega / p.beta).abs() < 1e-12);
    // After the rise the lift is zero until the drop: β equals the lobe here, so check a
    // shorter rise.
    let short = CamParams { beta: 0.5, ..CamParams::report() };
    assert_eq!(short.lift(0.6 / short.omega), 0.0);
}

#[test]
fn forces_are_minus_the_potential_gradient_at_rest() {
    for model in all_models() {
        let f = model.num_coordinates();
        let t = 0.013;
        for (q, _) in samples(&model, t, 0.05, 0.0) {
            let mut h = vec![0.0; f];
            model.forces(&q, &vec![0.0; f], t, &mut h);
            for j in 0..f {
                let step = 1e-6;
                let (mut qp, mut qm) = (q.clone(), q.clone());
                qp[j] += step;
                qm[j] -= step;
                let dv = (model.potential_energy(&qp, t).unwrap()
                    - model.potential_energy(&qm, t).unwrap())
                    / (2.0 * step);
                let scale = h[j].abs().max(dv.abs()).max(1e-3);
                assert!(
                    (h[j] + dv).abs() <= 1e-6 * scale,
                    "{} h[{j}] = {} but -dV/dq = {}",
                    model.kind(),
                    h[j],
                    -dv
                );
            }
        }
    }
}

#[test]
fn mass_matrices_are_symmetric_positive_definite() {
    for model in all_models() {
        let f = model.num_coordinates();
        for (q, t) in samples(&model, 0.0, 0.5, 0.0) {
            let mut m = vec![0.0; f * f];
            model.mass_matrix(&q, t, &mut m);
            let mat = DMatrix::from_column_slice(f, f, &m);
            assert_eq!(mat, mat.transpose(), "{}", model.kind());
            assert!(mat.cholesky().is_some(), "{} M not SPD at {q:?}", model.kind());
        }
    }
}

#[test]
fn switched_off_contacts_are_not_listed_and_the_rest_keep_their_kinematics() {
    let full = Woodpecker::new(WoodpeckerParams::report()).unwrap();
    let no_beak =
        Woodpecker::new(WoodpeckerParams { beak_contact: false, ..WoodpeckerParams::report() })
            .unwrap();
    assert_eq!((full.num_contacts(), no_beak.num_contacts()), (3, 2));
    assert_eq!(no_beak.laws().len(), 2);
    assert_eq!(no_beak.contact_ids(), &[1, 2]);
    let q = [0.01, -0.05, 0.1];
    for i in 0..2 {
        assert_eq!(no_beak.normal_gap(i, &q, 0.0), full.normal_gap(i + 1, &q, 0.0));
    }
    let lower_only =
        SliderCrank::new(SliderCrankParams { upper_surface: false, ..SliderCrankParams::report() })
            .unwrap();
    assert_eq!(lower_only.num_contacts(), 2);
    assert_eq!(lower_only.corner_ids(), &[2, 3]);
    assert_eq!(lower_only.contact_names(), vec!["corner 3 (lower)", "corner 4 (lower)"]);
    let report = assert_consistent(&lower_only, &[(vec![0.3, -0.1, 0.01], 0.0)], 1e-7).unwrap();
    assert!(report.passed(1e-7));
}

#[test]
fn frictionless_contacts_stay_frictionless() {
    let ball = Ball::new(BallParams::report()).unwrap();
    let cam = Cam::new(CamParams::report()).unwrap();
    assert!(!ball.laws()[0].is_frictional() && !cam.laws()[0].is_frictional());
    let wp = Woodpecker::new(WoodpeckerParams::report()).unwrap();
    assert!(wp.laws().iter().all(|l| l.is_frictional() && l.mu() == 0.3));
    assert_eq!(wp.laws()[0].eps_n(), 0.5);
    let smooth = Woodpecker::new(WoodpeckerParams {
        lower: LawParams::new(0.0, 0.0, 0.0),
        ..WoodpeckerParams::report()
    })
    .unwrap();
    assert!(!smooth.laws()[1].is_frictional());
}

#[test]
fn woodpecker_gaps_match_the_report_at_the_start() {
    // docs/theory.md §7.2: contact 2 is closed at t = 0 with g_N2 = −8.8e-7 m.
    let wp = Woodpecker::new(WoodpeckerParams::report()).unwrap();
    let (q, _) = wp.initial_state();
    let g2 = wp.normal_gap(1, &q, 0.0);
    assert!((g2 + 8.8e-7).abs() < 1e-9, "g_N2 = {g2}");
    // Closed forms: g_N1 = l_M + l_G − l_S − r_O − h_S φ_S, g_N3 = r_M − r_O − h_M φ_M.
    let g1 = 0.0100 + 0.0150 - 0.0201 - 0.0025 - 0.0200 * q[2];
    assert!((wp.normal_gap(0, &q, 0.0) - g1).abs() < 1e-15);
    assert!((wp.normal_gap(2, &q, 0.0) - (0.0006 + 0.0058 * 0.1036)).abs() < 1e-15);
}

#[test]
fn slider_crank_gaps_are_half_the_clearance_at_the_start() {
    let sc = SliderCrank::new(SliderCrankParams::report()).unwrap();
    let (q, _) = sc.initial_state();
    for i in 0..4 {
        assert!((sc.normal_gap(i, &q, 0.0) - 0.0005).abs() < 1e-15);
        let y = sc.normalized_corner(i, &q);
        assert!(y.abs() < 1e-12);
    }
    // Lifting the slider by c/2 makes corners 1 and 2 touch: Y = +1, g_N = 0.
    let th2 = (0.0005f64 / 0.306).asin();
    let lifted = [0.0, th2, 0.0];
    assert!(sc.normal_gap(0, &lifted, 0.0).abs() < 1e-15);
    assert!((sc.normalized_corner(1, &lifted) - 1.0).abs() < 1e-9);
    assert!((sc.normalized_corner(2, &lifted) - 1.0).abs() < 1e-9);
    let [x, y] = sc.slider_portrait(&lifted);
    assert!(
        (y - 1.0).abs() < 1e-9 && (x - (0.153 + 0.306 * th2.cos() - 0.306) / 0.153).abs() < 1e-15
    );
}

#[test]
fn one_evaluation_gives_what_the_separate_calls_give() {
    // `Mechanism::evaluate` (M, h and the gaps at once; the slider-crank shares its sines)
    // against `mass_matrix`, `forces` and `normal_gaps`, and `midpoint_contacts` (the
    // slider-crank's corners reuse the sines kept in the memo) against `contacts`, at sample
    // states with velocities.
    for model in all_models() {
        let f = model.num_coordinates();
        for (k, (q, t)) in samples(&model, 0.02, 0.3, 0.01).into_iter().enumerate() {
            let u: Vec<f64> = (0..f).map(|j| ((k * f + j) as f64).sin() * 20.0).collect();
            let found = check_evaluate(&model, &q, &u, t, 1e-14).unwrap();
            assert_eq!(found, None, "{} at q = {q:?}", model.kind());
        }
    }
}
