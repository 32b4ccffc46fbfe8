//! Construction validates every parameter once and names the offending field.

use moreau_models::*;

fn field_of(err: ModelError) -> String {
    match err {
        ModelError::InvalidParameter { field, .. } => field,
        other => panic!("expected an invalid parameter, got {other:?}"),
    }
}

#[test]
fn non_positive_or_non_finite_data_are_rejected_with_their_field() {
    assert_eq!(
        field_of(Ball::new(BallParams { m: -1.0, ..BallParams::report() }).unwrap_err()),
        "m"
    );
    assert_eq!(
        field_of(Ball::new(BallParams { r: 0.0, ..BallParams::report() }).unwrap_err()),
        "r"
    );
    let nan_init = BallParams { init: BallInit { y0: f64::NAN, v0: 0.0 }, ..BallParams::report() };
    assert_eq!(field_of(Ball::new(nan_init).unwrap_err()), "init.y0");
    let wp = WoodpeckerParams { j_s: 0.0, ..WoodpeckerParams::report() };
    assert_eq!(field_of(Woodpecker::new(wp).unwrap_err()), "j_s");
    let wp = WoodpeckerParams { r_m: 0.002, ..WoodpeckerParams::report() };
    assert_eq!(field_of(Woodpecker::new(wp).unwrap_err()), "r_m");
    let wp =
        WoodpeckerParams { upper: LawParams::new(0.0, 1.5, 0.3), ..WoodpeckerParams::report() };
    assert_eq!(field_of(Woodpecker::new(wp).unwrap_err()), "upper.eps_t");
    let sc = SliderCrankParams { l1: 0.4, ..SliderCrankParams::report() };
    assert_eq!(field_of(SliderCrank::new(sc).unwrap_err()), "l1");
    let sc = SliderCrankParams { mu: f64::INFINITY, ..SliderCrankParams::report() };
    assert_eq!(field_of(SliderCrank::new(sc).unwrap_err()), "mu");
    let ideal = SliderCrankIdealParams { m3: f64::NAN, ..SliderCrankIdealParams::report() };
    assert_eq!(field_of(SliderCrankIdeal::new(ideal).unwrap_err()), "m3");
    let cam = CamParams { beta: 1.2, ..CamParams::report() };
    assert_eq!(field_of(Cam::new(cam).unwrap_err()), "beta");
    let cam = CamParams { lobes: 0, ..CamParams::report() };
    assert_eq!(field_of(Cam::new(cam).unwrap_err()), "lobes");
    let cam = CamParams { ks: -1.0, ..CamParams::report() };
    assert_eq!(field_of(Cam::new(cam).unwrap_err()), "ks");
    let rod = PainleveParams { mu: -0.1, ..PainleveParams::report() };
    assert_eq!(field_of(PainleveRod::new(rod).unwrap_err()), "mu");
    let rod = PainleveParams { eps_n: 1.01, ..PainleveParams::report() };
    let message = PainleveRod::new(rod).unwrap_err().to_string();
    assert!(message.contains("eps_n") && message.contains("1.01"), "{message}");
}

#[test]
fn report_tables_build_and_boundary_values_are_accepted() {
    for kind in ModelKind::ALL {
        ModelParams::report(kind).build().unwrap();
    }
    // ε = 0 and ε = 1, μ = 0, and a rise over the whole lobe are admissible.
    Ball::new(BallParams { eps_n: 1.0, ..BallParams::report() }).unwrap();
    Ball::new(BallParams { eps_n: 0.0, ..BallParams::report() }).unwrap();
    PainleveRod::new(PainleveParams::report_with_mu(0.0)).unwrap();
    let cam = CamParams { lobes: 3, beta: std::f64::consts::TAU / 3.0, ..CamParams::report() };
    Cam::new(cam).unwrap();
}

#[test]
fn closed_forms_of_the_parameter_tables() {
    let ball = BallParams::report();
    assert!((ball.first_impact_time() - (1.8f64 / 9.81).sqrt()).abs() < 1e-15);
    assert!((ball.accumulation_time() - ball.first_impact_time() * 19.0).abs() < 1e-12);
    assert!(BallParams { eps_n: 1.0, ..ball.clone() }.accumulation_time().is_infinite());
    let cam = CamParams::report();
    assert!((cam.lobe_period() - std::f64::consts::TAU / (6.0 * 20.94)).abs() < 1e-15);
    // Cycloidal rise: s(β) = H at the end of the rise, s = H/2 at its middle.
    let t_mid = cam.beta / 2.0 / cam.omega;
    assert!((cam.lift(t_mid) - cam.stroke / 2.0).abs() < 1e-15);
    assert!((cam.lift(cam.lobe_period() * (1.0 - 1e-9)) - cam.stroke).abs() < 1e-9);
    // Just after the drop the lift starts again from zero.
    assert!(cam.lift(cam.lobe_period() * (1.0 + 1e-9)) < 1e-20);
    let sc = SliderCrankParams::report();
    assert_eq!(sc.guide_width(), 2.0 * 0.025 + 0.001);
    let ideal = sc.ideal();
    assert_eq!((ideal.l1, ideal.init.w1), (sc.l1, sc.init.w1));
    // The report's ω2(0) = −(l1/l2) ω1 keeps the slider's vertical velocity zero.
    assert_eq!(sc.init.w2, -(sc.l1 / sc.l2) * sc.init.w1);
}
