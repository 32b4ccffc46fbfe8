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
