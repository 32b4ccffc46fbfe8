//! A declaration is refused when it says something else than the mechanism it builds: a body
//! named `ground`, the world's reserved name, and positions so far from the joints that
//! assembling them moves a body by more than `MAX_ASSEMBLY_MOVE` of the mechanism's size.

use moreau_kinematics::Shape;
use moreau_models::ModelError;
use moreau_models::bodies::{
    BodySpec, GROUND, JointSpec, MAX_ASSEMBLY_MOVE, Multibody, MultibodyBuilder,
};

/// A bob of radius 0.05 m declared at `position`, hinged to the world at the origin through
/// the anchor [-0.5, 0] on the bob (so assembled at [0.5, 0] when declared near it).
fn pendulum(position: [f64; 2]) -> Result<Multibody, ModelError> {
    let mut b = MultibodyBuilder::new([0.0, -9.81]);
    b.add_body(
        BodySpec::dynamic("bob", 1.0, 1.25e-3, position, 0.0)
            .with_shape(Shape::Disk { center: [0.0, 0.0], radius: 0.05 }),
    );
    b.add_joint(JointSpec::revolute("hinge", GROUND, [0.0, 0.0], "bob", [-0.5, 0.0]));
    b.build()
}

#[test]
fn a_body_named_ground_is_refused_whatever_its_type() {
    for body in [
        BodySpec::dynamic(GROUND, 1.0, 0.1, [0.0, 0.0], 0.0),
        BodySpec::fixed(GROUND, [0.0, 0.0], 0.0),
    ] {
        let mut b = MultibodyBuilder::new([0.0, -9.81]);
        b.add_body(body);
        b.add_body(BodySpec::dynamic("bob", 1.0, 0.1, [0.5, 0.0], 0.0));
        b.add_joint(JointSpec::revolute("hinge", GROUND, [0.0, 0.0], "bob", [-0.5, 0.0]));
        match b.build() {
            Err(ModelError::BadValue { key, value, reason }) => {
                assert_eq!((key.as_str(), value.as_str()), ("bodies.ground.name", "ground"));
                assert!(reason.contains("reserved for the world"), "{reason}");
            }
            other => panic!("expected the name refused, got {:?}", other.map(|_| ())),
        }
    }
}

#[test]
fn a_scene_body_named_ground_is_refused() {
    let text = r#"
dt = 0.001
t_end = 0.01
gravity = [0.0, -9.81]
[[bodies]]
name = "ground"
type = "dynamic"
mass = 1.0
inertia = 0.1
position = [0.0, 0.0]
[[bodies]]
name = "bob"
type = "dynamic"
mass = 1.0
inertia = 0.1
position = [0.5, 0.0]
[[joints]]
type = "revolute"
name = "hinge"
body_a = "ground"
anchor_a = [0.0, 0.0]
body_b = "bob"
anchor_b = [-0.5, 0.0]
"#;
    let e = moreau_models::Scene::from_toml_str(text).and_then(|s| s.build().map(|_| ()));
    match e {
        Err(ModelError::BadValue { key, reason, .. }) => {
            assert_eq!(key, "bodies.ground.name");
            assert!(reason.contains("reserved for the world"), "{reason}");
        }
        other => panic!("expected the name refused, got {other:?}"),
    }
}

#[test]
fn a_position_close_to_the_joint_is_assembled() {
    // 1 mm off, about 1.2 % of the bob's size 0.6 * 0.1 * sqrt(2) = 0.085 m.
    let mb = pendulum([0.5, 0.001]).unwrap();
    let (q0, _) = mb.initial_state();
    // The hinge is closed: the bob's anchor [-0.5, 0] is at the origin.
    let (s, c) = q0[2].sin_cos();
    assert!((q0[0] - 0.5 * c).abs() < 1e-12 && (q0[1] - 0.5 * s).abs() < 1e-12, "{q0:?}");
}

#[test]
fn a_position_far_from_the_joint_is_refused_naming_the_body_and_the_joint() {
    for position in [[3.0, 0.0], [0.4, 0.0]] {
        match pendulum(position) {
            Err(ModelError::BadValue { key, reason, .. }) => {
                assert_eq!(key, "bodies.bob.position");
                assert!(reason.contains("`hinge`"), "{reason}");
                assert!(reason.contains("put the body at [0.5"), "{reason}");
                assert!(reason.contains(&format!("{} %", 100.0 * MAX_ASSEMBLY_MOVE)), "{reason}");
            }
            other => panic!("expected {position:?} refused, got {:?}", other.map(|_| ())),
        }
    }
}

/// A rod of 1 m hinged to the world at its end, with `extra` joints appended.
fn driven_rod(extra: &str) -> Result<Multibody, ModelError> {
    let text = format!(
        r#"
dt = 0.001
t_end = 0.01
gravity = [0.0, -9.81]
[[bodies]]
name = "rod"
type = "dynamic"
mass = 1.0
inertia = 0.0833333333333333
position = [0.5, 0.0]
[[joints]]
type = "revolute"
name = "hinge"
body_a = "ground"
anchor_a = [0.0, 0.0]
body_b = "rod"
anchor_b = [-0.5, 0.0]
{extra}
"#
    );
    match moreau_models::Scene::from_toml_str(&text)?.build()? {
        moreau_models::AnyModel::Declared(mb) => Ok(mb),
        _ => unreachable!("the scene declares its bodies"),
    }
}

const MOTOR: &str = r#"
[[joints]]
type = "motor"
name = "motor"
body_a = "ground"
body_b = "rod"
omega = 6.283185307179586
"#;

const WELD: &str = r#"
[[joints]]
type = "weld"
name = "weld"
body_a = "ground"
anchor_a = [0.0, 0.0]
body_b = "rod"
anchor_b = [-0.5, 0.0]
"#;

/// The joints an error names, and its value.
fn conflict(result: Result<Multibody, ModelError>) -> (String, f64, String) {
    match result {
        Err(ModelError::InvalidParameter { field, value, reason }) => (field, value, reason),
        other => panic!("expected the joints refused, got {:?}", other.map(|_| ())),
    }
}

#[test]
fn a_motor_on_a_welded_pair_is_refused_naming_both_joints() {
    let (field, value, reason) = conflict(driven_rod(&format!("{MOTOR}{WELD}")));
    assert_eq!(field, "joints.motor");
    // The least-squares angular velocity Ω/2 leaves Ω/2 = π on each of the two rows.
    assert!((value - std::f64::consts::PI).abs() < 1e-9, "{value}");
    assert!(reason.contains("`motor`, `weld`") && !reason.contains("`hinge`"), "{reason}");
}

#[test]
fn two_motors_at_different_speeds_are_refused_and_at_one_speed_built() {
    let second = |omega: f64| {
        MOTOR
            .replace("name = \"motor\"", "name = \"second\"")
            .replace("6.283185307179586", &omega.to_string())
    };
    let (field, value, reason) = conflict(driven_rod(&format!("{MOTOR}{}", second(1.0))));
    assert_eq!(field, "joints.motor");
    assert!((value - (2.0 * std::f64::consts::PI - 1.0) / 2.0).abs() < 1e-9, "{value}");
    assert!(reason.contains("`motor`, `second`"), "{reason}");
    // The same speed twice is redundant, not contradictory; so is a weld with a motor at rest.
    driven_rod(&format!("{MOTOR}{}", second(2.0 * std::f64::consts::PI))).unwrap();
    driven_rod(&format!("{}{WELD}", MOTOR.replace("6.283185307179586", "0.0"))).unwrap();
}

#[test]
fn a_body_held_by_a_turning_driven_body_and_by_a_hinge_elsewhere_is_refused() {
    // The driven disk turns about [2, 0]; the rod welded to it must turn about [2, 0] too,
    // which its hinge at the origin does not allow.
    let extra = r#"
[[bodies]]
name = "disk"
type = "driven"
position = [2.0, 0.0]
motion = { kind = "rotate", pivot = [2.0, 0.0], omega = 1.0 }
[[joints]]
type = "weld"
name = "glue"
body_a = "disk"
anchor_a = [-1.0, 0.0]
body_b = "rod"
anchor_b = [0.5, 0.0]
"#;
    let (field, _, reason) = conflict(driven_rod(extra));
    assert!(field == "joints.hinge" || field == "joints.glue", "{field}");
    assert!(reason.contains("`hinge`") && reason.contains("`glue`"), "{reason}");
}
