//! The report's mechanisms declared as scene files (`scenes/bodies/`) against their
//! hand-derived models at the same Δt: the ball's first impact, the woodpecker's period, the
//! slider-crank's crank speed and the cam's first impact, with the joints' drift and the
//! contacts' penetration of the declared runs.

use std::ops::ControlFlow;

use moreau_models::{ModelKind, ModelParams, Scene};
use moreau_stepper::StepReport;

const BALL: &str = include_str!("../../../scenes/bodies/ball.toml");
const WOODPECKER: &str = include_str!("../../../scenes/bodies/woodpecker.toml");
const SLIDER_CRANK: &str = include_str!("../../../scenes/bodies/slider-crank.toml");
const CAM: &str = include_str!("../../../scenes/bodies/cam.toml");

/// What a run leaves for the comparisons: per step, t, q, u and the sum of the normal
/// impulses of the contacts in `watch` (all when empty); over the run, the largest joint drift
/// and penetration of the step reports.
#[derive(Default)]
struct Run {
    t: Vec<f64>,
    q: Vec<Vec<f64>>,
    u: Vec<Vec<f64>>,
    p_n: Vec<f64>,
    drift: f64,
    penetration: f64,
}

fn run(scene: &Scene, watch: &[usize]) -> Run {
    let mut r = Run::default();
    let mut observe = |s: &StepReport<'_>| {
        r.t.push(s.t);
        r.q.push(s.q.to_vec());
        r.u.push(s.u.to_vec());
        let p = s
            .contacts
            .iter()
            .enumerate()
            .filter(|(i, _)| watch.is_empty() || watch.contains(i))
            .map(|(_, c)| c.p_n)
            .sum();
        r.p_n.push(p);
        r.drift = r.drift.max(s.joint_drift);
        r.penetration = r.penetration.max(s.penetration);
        ControlFlow::Continue(())
    };
    scene.run_with(&mut observe).unwrap();
    r
}

/// The steps at which the watched contacts start to carry an impulse.
fn onsets(r: &Run) -> Vec<usize> {
    (1..r.t.len()).filter(|&k| r.p_n[k] > 0.0 && r.p_n[k - 1] == 0.0).collect()
}

fn declared(text: &str) -> Scene {
    let scene = Scene::from_toml_str(text).unwrap();
    assert_eq!(scene.kind(), ModelKind::Declared);
    scene
}

#[test]
fn the_declared_ball_gives_the_first_impact_of_table_8_2() {
    let mut hand = Scene::report(ModelKind::Ball);
    let mut ball = declared(BALL);
    assert_eq!(ball.dt, hand.dt);
    hand.t_end = 1.0;
    ball.t_end = 1.0;
    let (h, d) = (run(&hand, &[]), run(&ball, &[]));
    let (kh, kd) = (onsets(&h)[0], onsets(&d)[0]);
    // Table 8.2: the first impact's impulse Λ_N = 7.99 N s in the step whose midpoint is
    // t = 0.4285 s; both models find it in that step.
    for (r, k) in [(&h, kh), (&d, kd)] {
        let midpoint = r.t[k] - 0.5 * hand.dt;
        assert!((midpoint - 0.4285).abs() < 1e-9, "impact at t_M = {midpoint}");
        assert!((r.p_n[k] - 7.99).abs() < 5e-3, "Λ_N = {}", r.p_n[k]);
    }
    // The free ball's y is the hand model's y to round-off, its x and θ stay at zero.
    assert!((h.p_n[kh] - d.p_n[kd]).abs() < 1e-9);
    for k in 0..h.t.len() {
        assert!((h.q[k][0] - d.q[k][1]).abs() < 1e-9 && (h.u[k][0] - d.u[k][1]).abs() < 1e-9);
        assert!(d.q[k][0].abs() < 1e-12 && d.q[k][2].abs() < 1e-12);
    }
    // The only penetration is the one the impact's step leaves (6.2e-4 m, under v1 Δt/2 =
    // 2.1e-3 m); the ball has no joint.
    assert!(d.penetration < 7e-4 && d.drift == 0.0, "{} {}", d.penetration, d.drift);
}

/// Mean time between the beak's impacts after the first three.
fn beak_period(r: &Run) -> f64 {
    let hits: Vec<f64> = onsets(r).iter().map(|&k| r.t[k]).collect();
    let p: Vec<f64> = hits.windows(2).map(|w| w[1] - w[0]).skip(3).collect();
    assert!(p.len() >= 5, "{hits:?}");
    p.iter().sum::<f64>() / p.len() as f64
}

/// The woodpecker with its angles scaled by `scale`: the clearance r_M − r_O, the beak's gap
/// at φ_S = 0, the initial angles and rates, v0 and g. The linearised hand model scales with
/// them but for l_S in the beak's tangential direction (its period goes from 0.1464 s to
/// 0.1415 s); the declared one, with the exact rotations, tends to it as scale → 0. Returns
/// both periods.
fn scaled_woodpecker_periods(scale: f64, projection: bool) -> (f64, f64) {
    use moreau_kinematics::Shape;
    let (r_o, h_m, l_m, l_g, h_s) = (0.0025, 0.0058, 0.01, 0.015, 0.02);
    let r_m = r_o + 0.0006 * scale;
    let l_s = l_m + l_g - r_o - 0.0024 * scale;
    let (pm, ps, v, ws, g) =
        (-0.1036 * scale, -0.2788 * scale, -0.3411 * scale, -7.4583 * scale, 9.81 * scale);
    let mut hand = Scene::report(ModelKind::Woodpecker);
    hand.t_end = 1.5;
    for (k, x) in [
        ("r_m", r_m),
        ("l_s", l_s),
        ("init.phi_m", pm),
        ("init.phi_s", ps),
        ("init.omega_s", ws),
        ("init.v", v),
        ("g", g),
    ] {
        hand.set(k, &x.to_string()).unwrap();
    }
    let mut d = declared(WOODPECKER);
    d.t_end = 1.5;
    d.projection = projection;
    let ModelParams::Declared(spec) = &mut d.params else { unreachable!() };
    spec.gravity = [0.0, -g];
    let sleeve = &mut spec.bodies[1];
    sleeve.angle = pm;
    sleeve.velocity = [0.0, v];
    sleeve.shapes[0] = Shape::Disk { center: [r_m, -h_m], radius: 0.0 };
    sleeve.shapes[1] = Shape::Disk { center: [r_m, h_m], radius: 0.0 };
    let bird = &mut spec.bodies[2];
    bird.angle = ps;
    bird.position = [l_m * pm.cos() + l_g * ps.cos(), l_m * pm.sin() + l_g * ps.sin()];
    bird.velocity = [-ws * l_g * ps.sin(), v + ws * l_g * ps.cos()];
    bird.omega = ws;
    bird.shapes[0] = Shape::Disk { center: [-l_s, h_s], radius: 0.0 };
    (beak_period(&run(&hand, &[0])), beak_period(&run(&d, &[0])))
}

#[test]
fn the_declared_woodpecker_has_the_hand_models_cycle_up_to_its_small_angles() {
    let mut hand = Scene::report(ModelKind::Woodpecker);
    let mut bird = declared(WOODPECKER);
    assert_eq!(bird.dt, hand.dt);
    hand.t_end = 1.5;
    bird.t_end = 1.5;
    let (h, d) = (run(&hand, &[0]), run(&bird, &[0]));
    let (ph, pd) = (beak_period(&h), beak_period(&d));
    let rel = (pd - ph) / ph;
    eprintln!(
        "woodpecker period: hand {ph:.5} s, declared {pd:.5} s ({:+.2} %), drift {:.1e} m, \
         penetration {:.1e} m",
        100.0 * rel,
        d.drift,
        d.penetration
    );
    // Both settle on a cycle of one beak impact each period. The declared toy turns its
    // bodies exactly; the hand model linearises angles of up to 0.4 rad, and its period is
    // about 10 % longer: 0.1464 s against 0.1308 s (0.1310 s without the projection). With
    // the projection the exact figure moves by a few per cent with round-off, since the
    // resting sleeve edge still lifts off and recloses at times.
    assert!((-0.12..-0.05).contains(&rel), "{ph} {pd}");
    // Measured: drift 4.9e-8 m; penetration 1.6e-5 m, the report's initial state, whose
    // lower edge is that deep in the pole with the exact rotations.
    assert!(d.drift < 1e-7 && d.penetration < 2e-5, "{} {}", d.drift, d.penetration);
    // The difference is the linearisation: with every angle scaled down, the two periods
    // tend to each other. Measured without the projection: -10.5 % at scale 1, -2.5 % at
    // 0.1 and -0.28 % at 0.01, where the hand model's sin x ~ x holds to 3e-6 of x.
    let errors: Vec<f64> = [1.0, 0.1, 0.01]
        .iter()
        .map(|&scale| {
            let (h, d) = scaled_woodpecker_periods(scale, false);
            eprintln!("scale {scale}: {h:.5} s vs {d:.5} s ({:+.2} %)", 100.0 * (d - h) / h);
            (d - h).abs() / h
        })
        .collect();
    assert!(errors[1] < errors[0] / 3.0 && errors[2] < errors[1] / 4.0, "{errors:?}");
    assert!(errors[2] < 0.005, "{errors:?}");
}

/// The crank speed interpolated at crank angle `angle`, from coordinate `j` and velocity `l`
/// (the crank turns one way, so its angle grows with the steps).
fn speed_at(r: &Run, j: usize, l: usize, angle: f64) -> f64 {
    let k = r.q.partition_point(|q| q[j] < angle).max(1);
    let s = (angle - r.q[k - 1][j]) / (r.q[k][j] - r.q[k - 1][j]);
    r.u[k - 1][l] + s * (r.u[k][l] - r.u[k - 1][l])
}

/// The hand-derived and the declared slider-crank over their two revolutions at time step
/// `dt`: the range of the hand model's crank speed, the largest and the root-mean-square
/// difference of the two crank speeds at 4,000 crank angles, how often each run's corners
/// close, and the declared run's drift and penetration.
struct CrankComparison {
    range: f64,
    worst: f64,
    rms: f64,
    hand_onsets: usize,
    declared_onsets: usize,
    drift: f64,
    penetration: f64,
}

fn compare_slider_cranks(dt: f64) -> CrankComparison {
    let mut hand = Scene::report(ModelKind::SliderCrank);
    let mut crank = declared(SLIDER_CRANK);
    assert_eq!(crank.dt, hand.dt);
    hand.dt = dt;
    crank.dt = dt;
    let (h, d) = (run(&hand, &[]), run(&crank, &[]));
    let w: Vec<f64> = h.u.iter().map(|u| u[0]).collect();
    let range = w.iter().fold(f64::NEG_INFINITY, |m, &x| m.max(x))
        - w.iter().fold(f64::INFINITY, |m, &x| m.min(x));
    // The crank speed as a function of the crank angle over two revolutions (the declared
    // crank is the second body: θ1 = q[2], ω1 = u[2]).
    let n = 4000;
    let differences: Vec<f64> = (1..n)
        .map(|i| 4.0 * std::f64::consts::PI * i as f64 / n as f64)
        .map(|a| (speed_at(&h, 0, 0, a) - speed_at(&d, 2, 2, a)).abs())
        .collect();
    let c = CrankComparison {
        range,
        worst: differences.iter().fold(0.0, |m, &x| m.max(x)),
        rms: (differences.iter().map(|x| x * x).sum::<f64>() / differences.len() as f64).sqrt(),
        hand_onsets: onsets(&h).len(),
        declared_onsets: onsets(&d).len(),
        drift: d.drift,
        penetration: d.penetration,
    };
    eprintln!(
        "slider-crank at dt = {dt:e}: crank speed range {range:.2} rad/s, largest difference \
         {:.3} rad/s ({:.2} % of the range), root mean square {:.3} rad/s ({:.3} %), corners \
         closing {} (hand) and {} (declared) times, drift {:.1e} m, penetration {:.1e} m",
        c.worst,
        100.0 * c.worst / range,
        c.rms,
        100.0 * c.rms / range,
        c.hand_onsets,
        c.declared_onsets,
        c.drift,
        c.penetration
    );
    c
}

#[test]
fn the_declared_slider_crank_follows_the_hand_models_crank_speed() {
    let at = compare_slider_cranks(Scene::report(ModelKind::SliderCrank).dt);
    let fine = compare_slider_cranks(2.5e-6);
    // The hand model's corners chatter while the slider slides along a face of the guide: in
    // its minimal coordinates a corner's gap is curved in q (through sin θ1 and sin θ2), so a
    // corner held at γ_N = 0 at the midpoint leaves the face within the step, flies and
    // strikes again (430 closings over the two revolutions at Δt = 1e-5 s, 1,635 at 2.5e-6).
    // In maximal coordinates that gap is linear in the slider's y, the curvature is in the
    // joints, and the corners stay closed (52 and 66 closings). The runs part by the
    // slider's velocity at the last bounce of each chatter (1.6 mm/s when the slider leaves
    // the upper face at t = 15.5 ms, Δt = 1e-5 s) and meet as Δt falls: there the hand
    // model's vertical speed is -2.5, -0.66, -1.28, -1.18, -0.99 mm/s at Δt = 1e-5, 5e-6,
    // 2.5e-6, 1.25e-6, 6.25e-7 s, the declared one's -0.882 mm/s at each.
    assert!(at.hand_onsets > 4 * at.declared_onsets, "{} {}", at.hand_onsets, at.declared_onsets);
    // Measured: root-mean-square difference 0.30 % of the 86 rad/s range at Δt = 1e-5 s,
    // 0.080 % at 2.5e-6 s; the largest, 2.0 % and 1.8 %, is a sample between the two runs'
    // velocity jumps at an impact that they place a few microseconds apart.
    assert!(at.range > 80.0 && at.worst < 0.025 * at.range, "{} of {}", at.worst, at.range);
    assert!(at.rms < 0.004 * at.range && fine.rms < at.rms / 3.0, "{} {}", at.rms, fine.rms);
    // Measured: drift 3.2e-8 m, penetration 3.1e-6 m (the hand model's corners reach
    // 1.7e-5 m).
    assert!(at.drift < 1e-7 && at.penetration < 5e-6, "{} {}", at.drift, at.penetration);
}

#[test]
fn the_declared_cam_first_hits_when_the_hand_model_does() {
    let hand = Scene::report(ModelKind::Cam);
    let cam = declared(CAM);
    assert_eq!(cam.dt, hand.dt);
    let (h, d) = (run(&hand, &[]), run(&cam, &[]));
    let (kh, kd) = (onsets(&h)[0], onsets(&d)[0]);
    eprintln!("cam: first impact at {} s (hand), {} s (declared)", h.t[kh], d.t[kd]);
    assert_eq!(h.t[kh], d.t[kd]);
    assert!((h.t[kh] - 0.0033).abs() < 1e-9);
    // The follower's height is R_b + y; its lift follows the hand model's over three lobes
    // within the profile's chord error and the steps' penetration.
    let worst = (0..h.t.len()).map(|k| (h.q[k][0] + 0.003 - d.q[k][1]).abs()).fold(0.0, f64::max);
    eprintln!("cam: largest difference of the lift {worst:.1e} m, drift {:.1e} m", d.drift);
    assert!(worst < 1e-4, "{worst}");
    // Measured: no drift (the prismatic joint is linear), penetration 4.2e-4 m at the first
    // impact (8 m/s over half a step).
    assert!(d.drift < 1e-12 && d.penetration < 5e-4, "{} {}", d.drift, d.penetration);
}

#[test]
fn the_declared_ball_is_the_hand_model_over_the_reports_ten_seconds() {
    // Declared as the report's scheme (the scene turns the projection off), the ball on its
    // half-plane is the hand model to the bit: the same 58 impacts in 10 s, the same heights.
    let hand = Scene::report(ModelKind::Ball);
    let ball = declared(BALL);
    assert!(!ball.projection);
    assert_eq!(ball.t_end, hand.t_end);
    let (h, d) = (run(&hand, &[]), run(&ball, &[]));
    assert_eq!(h.t.len(), 10_000);
    assert_eq!(onsets(&h).len(), 58);
    assert_eq!(onsets(&d), onsets(&h));
    for k in 0..h.t.len() {
        assert_eq!((d.q[k][1], d.u[k][1]), (h.q[k][0], h.u[k][0]), "step {k}");
    }
}
