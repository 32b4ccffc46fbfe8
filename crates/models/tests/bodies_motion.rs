//! Driven bodies' motions: the closed form of `oscillate`, and the build's refusal of motions
//! that are not finite, whose pose jumps, or whose stated rates are not the pose's
//! derivatives, each error naming the field.

use std::f64::consts::{FRAC_PI_2, PI};

use moreau_kinematics::Shape;
use moreau_models::ModelError;
use moreau_models::bodies::{
    BodySpec, ContactSpec, DrivenState, Motion, Multibody, MultibodyBuilder, SystemSpec,
};

/// A driven table with `motion` at reference pose ([0.1, −0.05], 0.2) and a disk above it.
fn table(motion: Motion) -> Result<Multibody, ModelError> {
    let mut b = MultibodyBuilder::new([0.0, -9.81]);
    b.add_body(BodySpec::driven("table", [0.1, -0.05], 0.2, motion).with_shape(Shape::Polygon {
        vertices: vec![[-1.0, -0.05], [1.0, -0.05], [1.0, 0.05], [-1.0, 0.05]],
    }));
    b.add_body(
        BodySpec::dynamic("ball", 1.0, 0.005, [0.0, 0.5], 0.0)
            .with_shape(Shape::Disk { center: [0.0, 0.0], radius: 0.1 }),
    );
    b.add_contact(ContactSpec {
        name: "rest".into(),
        body_a: "table".into(),
        shape_a: 0,
        body_b: "ball".into(),
        shape_b: 0,
        eps_n: 0.0,
        eps_t: 0.0,
        mu: 0.5,
        margin: None,
    });
    b.build()
}

/// The field named by an `InvalidParameter`.
fn refused_field(result: Result<Multibody, ModelError>) -> String {
    match result {
        Err(ModelError::InvalidParameter { field, .. }) => field,
        Err(e) => panic!("expected an invalid parameter, got {e}"),
        Ok(_) => panic!("expected the motion to be refused"),
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-15 * (1.0 + b.abs())
}

#[test]
fn oscillate_is_p0_plus_a_sin_omega_t_plus_phase_per_axis() {
    let (a, omega) = ([0.02, 0.03], 6.0 * PI);
    let quarter = FRAC_PI_2 / omega; // a quarter of the period 2π/Ω
    let pose0 = [0.1, -0.05, 0.2];
    // Phase 0 (the default): at the centre p₀ moving at A Ω; a quarter period later at
    // p₀ + A, at rest.
    let m = Motion::Oscillate { amplitude: a, omega, phase: [0.0, 0.0] };
    let s = m.state(pose0, 0.0);
    assert_eq!(s.pose, pose0);
    assert_eq!(s.velocity, [a[0] * omega, a[1] * omega]);
    assert_eq!(s.omega, 0.0);
    let s = m.state(pose0, quarter);
    for i in 0..2 {
        assert!(close(s.pose[i], pose0[i] + a[i]), "{:?}", s.pose);
        assert!(s.velocity[i].abs() <= 1e-15 * a[i] * omega, "{:?}", s.velocity);
    }
    assert_eq!(s.pose[2], pose0[2]);
    // Phase π/2 on x only: x starts at rest at p₀ + A and is back at the centre, moving at
    // −A Ω, a quarter period later; y keeps phase 0.
    let m = Motion::Oscillate { amplitude: a, omega, phase: [FRAC_PI_2, 0.0] };
    let s = m.state(pose0, 0.0);
    assert!(close(s.pose[0], pose0[0] + a[0]) && s.velocity[0].abs() <= 1e-15 * a[0] * omega);
    assert_eq!((s.pose[1], s.velocity[1]), (pose0[1], a[1] * omega));
    let s = m.state(pose0, quarter);
    assert!(close(s.pose[0], pose0[0]) && close(s.velocity[0], -a[0] * omega), "{s:?}");
    // The built body is where the motion says.
    let mb = table(Motion::Oscillate { amplitude: a, omega, phase: [0.0, 0.0] }).unwrap();
    let (q0, _) = mb.initial_state();
    assert_eq!(mb.body_poses(&q0, 0.0)[0], pose0);
    let p = mb.body_poses(&q0, quarter)[0];
    assert!(close(p[0], pose0[0] + a[0]) && close(p[1], pose0[1] + a[1]), "{p:?}");
}

#[test]
fn the_closed_forms_pass_the_build_even_when_fast() {
    for motion in [
        Motion::Rotate { pivot: [0.3, 0.1], omega: 2e4, phase: 0.2 },
        Motion::Oscillate { amplitude: [0.01, 0.02], omega: 2e4, phase: [0.3, 1.0] },
        Motion::Linear { velocity: [3.0, -1.0], omega: 5.0 },
    ] {
        table(motion).unwrap();
    }
}

#[test]
fn a_closed_form_that_is_not_finite_is_refused_naming_its_parameter() {
    let m = Motion::Oscillate { amplitude: [0.01, f64::NAN], omega: 1.0, phase: [0.0; 2] };
    assert_eq!(refused_field(table(m)), "bodies.table.motion.amplitude.1");
    // Finite parameters whose pose overflows within the sampled times.
    let m = Motion::Linear { velocity: [f64::MAX, 0.0], omega: 0.0 };
    assert_eq!(refused_field(table(m)), "bodies.table.motion.pose.0");
    // Read from a scene file.
    let text = "gravity = [0.0, -9.81]\n\
        [[bodies]]\nname = \"table\"\ntype = \"driven\"\nposition = [0.0, 0.0]\n\
        motion = { kind = \"oscillate\", amplitude = [0.02, 0.0], omega = inf }\n";
    let spec: SystemSpec = toml::from_str(text).unwrap();
    assert_eq!(refused_field(spec.build()), "bodies.table.motion.omega");
}

/// A closure moving along x as p(t), with the rate v(t).
fn along_x(p: fn(f64) -> f64, v: fn(f64) -> f64) -> Motion {
    Motion::custom(move |t| DrivenState {
        pose: [p(t), 0.0, 0.0],
        velocity: [v(t), 0.0],
        omega: 0.0,
    })
}

#[test]
fn a_closure_whose_velocity_is_the_rate_of_its_pose_passes() {
    // Smooth, fast (ω = 3000 rad/s), and with a kink: the rate may jump, the pose may not.
    table(along_x(|t| 0.01 * (3000.0 * t).sin(), |t| 30.0 * (3000.0 * t).cos())).unwrap();
    table(along_x(|t| (t - 0.5).max(0.0), |t| if t < 0.5 { 0.0 } else { 1.0 })).unwrap();
    table(along_x(|t| (t - 0.5).max(0.0), |t| if t <= 0.5 { 0.0 } else { 1.0 })).unwrap();
    // Turning fast about its origin, θ unwrapped.
    table(Motion::custom(|t| DrivenState {
        pose: [0.0, 0.0, 500.0 * t],
        velocity: [0.0; 2],
        omega: 500.0,
    }))
    .unwrap();
}

#[test]
fn the_closed_forms_as_closures_pass_the_check_of_their_rates() {
    let pose0 = [0.1, -0.05, 0.2];
    for omega in [0.3, 1.0, 100.0, 3000.0] {
        for form in [
            Motion::Rotate { pivot: [0.3, 0.1], omega, phase: 0.2 },
            Motion::Oscillate { amplitude: [0.01, 0.02], omega, phase: [0.3, 1.0] },
            Motion::Linear { velocity: [3.0, -1.0], omega },
        ] {
            let closure = Motion::custom(move |t| form.state(pose0, t));
            table(closure).unwrap();
        }
    }
}

#[test]
fn a_closure_whose_velocity_contradicts_its_pose_is_refused_naming_the_rate() {
    // Twice the rate of its pose; at rest while moving; the wrong sign.
    for motion in [
        along_x(|t| 0.2 * t, |_| 0.4),
        along_x(|t| 0.01 * (3.0 * t).sin(), |_| 0.0),
        along_x(|t| -0.1 * t, |_| 0.1),
    ] {
        assert_eq!(refused_field(table(motion)), "bodies.table.motion.velocity.0");
    }
    // An angular rate in degrees per second.
    let m = Motion::custom(|t| DrivenState {
        pose: [0.0, 0.0, 2.0 * t],
        velocity: [0.0; 2],
        omega: 2.0f64.to_degrees(),
    });
    assert_eq!(refused_field(table(m)), "bodies.table.motion.omega");
}

#[test]
fn a_closure_whose_pose_jumps_is_refused_naming_the_rate() {
    // Sampled data held between samples (a staircase) with the slope of the data as velocity:
    // the pose jumps at every sample.
    let m = along_x(|t| 0.1 * (t / 0.25).floor() * 0.25, |_| 0.1);
    assert_eq!(refused_field(table(m)), "bodies.table.motion.velocity.0");
    // A jump of 1 µm between the sampled times.
    let m = along_x(|t| 0.1 * t + if t > 0.5f64.sqrt() { 1e-6 } else { 0.0 }, |_| 0.1);
    assert_eq!(refused_field(table(m)), "bodies.table.motion.velocity.0");
    // A jump at t = 0.
    let m = along_x(|t| if t > 0.0 { 0.01 } else { 0.0 }, |_| 0.0);
    assert_eq!(refused_field(table(m)), "bodies.table.motion.velocity.0");
    // An angle wrapped to (−π, π]: it jumps by 2π.
    let m = Motion::custom(|t| {
        let theta = (2.0 * t + PI).rem_euclid(2.0 * PI) - PI;
        DrivenState { pose: [0.0, 0.0, theta], velocity: [0.0; 2], omega: 2.0 }
    });
    assert_eq!(refused_field(table(m)), "bodies.table.motion.omega");
}

#[test]
fn a_closure_that_is_not_finite_is_refused_naming_the_component() {
    let m = Motion::custom(|t| DrivenState {
        pose: [0.0, if t > 2.0 { f64::NAN } else { 0.0 }, 0.0],
        velocity: [0.0; 2],
        omega: 0.0,
    });
    assert_eq!(refused_field(table(m)), "bodies.table.motion.pose.1");
    let m = Motion::custom(|_| DrivenState {
        pose: [0.0; 3],
        velocity: [0.0, f64::INFINITY],
        omega: 0.0,
    });
    assert_eq!(refused_field(table(m)), "bodies.table.motion.velocity.1");
}
