//! Every contact of a declared mechanism has a name of its own, so that the record's columns
//! (`<contact>.PN`, ...) are distinct: an explicit contact may not take the name of a
//! clearance joint, whose contacts are named after it.

use moreau_models::{ModelError, Scene};

/// A pendulum hanging from a revolute clearance joint `joint` that strikes a wall through
/// the explicit contact `contact`.
fn scene(joint: &str, contact: &str) -> String {
    format!(
        r#"
dt = 0.0001
t_end = 0.01
gravity = [0.0, -9.81]

[[bodies]]
name = "wall"
type = "fixed"
position = [0.0, 0.0]
shapes = [{{ type = "half_plane", point = [0.05, 0.0], normal = [-1.0, 0.0] }}]

[[bodies]]
name = "bob"
type = "dynamic"
mass = 1.0
inertia = 0.00125
position = [-0.479425538604203, -0.8775825618903728]
shapes = [{{ type = "disk", center = [0.0, 0.0], radius = 0.05 }}]

[[joints]]
type = "revolute_clearance"
name = "{joint}"
body_a = "ground"
anchor_a = [0.0, 0.0]
body_b = "bob"
anchor_b = [0.479425538604203, 0.8775825618903728]
pin_radius = 0.01
bearing_radius = 0.011
eps_n = 0.5
eps_t = 0.0
mu = 0.0

[[contacts]]
name = "{contact}"
body_a = "wall"
body_b = "bob"
eps_n = 0.8
eps_t = 0.0
mu = 0.0
"#
    )
}

#[test]
fn a_contact_named_as_a_clearance_joint_is_refused() {
    let e = Scene::from_toml_str(&scene("hit", "hit")).and_then(|s| s.build().map(|_| ()));
    match e {
        Err(ModelError::BadValue { key, value, reason }) => {
            assert_eq!((key.as_str(), value.as_str()), ("contacts.hit.name", "hit"));
            assert!(reason.contains("clearance joint `hit`"), "{reason}");
        }
        other => panic!("expected the name refused, got {other:?}"),
    }
    // With names of their own, the contacts' names are distinct.
    let model = Scene::from_toml_str(&scene("pin", "hit")).unwrap().build().unwrap();
    let names = model.contact_names();
    assert_eq!(names, ["pin", "hit"]);
}
