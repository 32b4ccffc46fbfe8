//! A mechanism declared in Rust with the builder: a box on a table shaken sideways, tied to a
//! post by a spring-damper, with a crank driven by a motor sweeping a ball along the table
//! against a stop.
//! Prints the box's and the ball's positions and the contacts closed at a few instants.
//!
//! Run with `cargo run -p moreau-models --example declared`.

use moreau_kinematics::Shape;
use moreau_models::LawParams;
use moreau_models::bodies::{
    AutoContacts, BodySpec, ForceSpec, JointSpec, Motion, MultibodyBuilder,
};
use moreau_stepper::Stepper;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut builder = MultibodyBuilder::new([0.0, -9.81]);
    // The table: a 2 m × 0.1 m slab shaken along x by 2 cm at 3 Hz.
    builder.add_body(
        BodySpec::driven(
            "table",
            [0.0, -0.05],
            0.0,
            Motion::Oscillate {
                amplitude: [0.02, 0.0],
                omega: 6.0 * std::f64::consts::PI,
                phase: [0.0, 0.0],
            },
        )
        .with_shape(Shape::Polygon {
            vertices: vec![[-1.0, -0.05], [1.0, -0.05], [1.0, 0.05], [-1.0, 0.05]],
        }),
    );
    // A stop at the table's right end (solid for x > 0.9 m), where the swept ball strikes.
    builder.add_body(
        BodySpec::fixed("stop", [0.9, 0.0], 0.0)
            .with_shape(Shape::HalfPlane { point: [0.0, 0.0], normal: [-1.0, 0.0] }),
    );
    // A 0.2 m steel-like box (ρ = 50 kg/m² in the plane) resting on it.
    let half = 0.1;
    let block = builder.add_body(BodySpec::with_density("box", 50.0, [0.0, half], 0.0).with_shape(
        Shape::Polygon {
            vertices: vec![[-half, -half], [half, -half], [half, half], [-half, half]],
        },
    ));
    // A ball on the table and a crank turning at 2 rad/s about a fixed axle above it, whose
    // tip sweeps the ball sideways.
    let ball = builder.add_body(
        BodySpec::dynamic("ball", 0.1, 0.1 * 0.05 * 0.05 / 2.0, [0.6, 0.05], 0.0)
            .with_shape(Shape::Disk { center: [0.0, 0.0], radius: 0.05 }),
    );
    builder.add_body(
        BodySpec::dynamic("crank", 0.5, 0.5 * 0.3 * 0.3 / 12.0, [0.35, 0.35], std::f64::consts::PI)
            .with_shape(Shape::Capsule { a: [-0.15, 0.0], b: [0.15, 0.0], radius: 0.01 }),
    );
    builder.add_joint(JointSpec::revolute("axle", "ground", [0.5, 0.35], "crank", [-0.15, 0.0]));
    builder.add_joint(JointSpec::Motor {
        name: "drive".into(),
        body_a: "ground".into(),
        body_b: "crank".into(),
        omega: 2.0,
        angle: None,
    });
    // The box is tied to a post at x = −0.5 m by a spring of 200 N/m, rest length 0.4 m.
    builder.add_force(ForceSpec::Spring {
        name: Some("tie".into()),
        body_a: "ground".into(),
        anchor_a: [-0.5, 0.1],
        body_b: "box".into(),
        anchor_b: [-half, 0.0],
        stiffness: 200.0,
        rest_length: 0.4,
        damping: 2.0,
    });
    builder.auto_contacts(AutoContacts::new(LawParams::new(0.3, 0.0, 0.4)));
    let mechanism = builder.build()?;
    println!("coordinates: {}", mechanism.coordinate_names().join(", "));
    println!("contacts: {}", mechanism.contact_names().join(", "));

    let (q0, u0) = mechanism.initial_state();
    // As a scene file steps it: the projection on, with tolerances relative to its size.
    let options = mechanism.stepper_options(1e-3);
    let mut stepper = Stepper::new(mechanism, &q0, &u0, 0.0, options)?;
    for k in 1..=2000 {
        let report = stepper.step()?;
        let closed = report.contacts.iter().filter(|c| c.active).count();
        if k % 250 == 0 {
            let (t, q) = (stepper.t(), stepper.q());
            let m = stepper.mechanism();
            let (b, d) = (m.pose(block, q, t), m.pose(ball, q, t));
            println!(
                "t = {t:.2} s: box at x = {:+.4} m, ball at ({:+.3}, {:+.3}) m, {closed} contacts closed",
                b[0], d[0], d[1]
            );
        }
    }
    Ok(())
}
