//! The mistakes a scene's author makes are refused by the field at fault, down to the field
//! of a shape, of a driven motion or of an automatic contact's override, with that field's
//! value and what is wrong.

use moreau_models::{ModelError, Scene};

/// A disk dropped on a table shaken vertically, with automatic contacts besides.
const SCENE: &str = r#"
dt = 0.001
t_end = 0.01
gravity = [0.0, -9.81]

[[bodies]]
name = "table"
type = "driven"
position = [0.0, 0.0]
motion = { kind = "oscillate", amplitude = [0.0, 0.01], omega = 30.0 }
shapes = [{ type = "polygon", vertices = [[-1.0, -0.1], [1.0, -0.1], [1.0, 0.0], [-1.0, 0.0]] }]

[[bodies]]
name = "disk"
type = "dynamic"
mass = 0.5
inertia = 0.0025
position = [0.0, 0.3]
shapes = [{ type = "disk", center = [0.0, 0.0], radius = 0.1 }]

[[bodies]]
name = "box"
type = "dynamic"
mass = 1.0
inertia = 0.01
position = [0.5, 0.3]
shapes = [{ type = "polygon", vertices = [[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]] }]

[[contacts]]
name = "hit"
body_a = "table"
body_b = "disk"
eps_n = 0.5
eps_t = 0.0
mu = 0.0

[contacts_auto]
eps_n = 0.5
eps_t = 0.0
mu = 0.2
overrides = [{ bodies = ["table", "box"], eps_n = 0.1, eps_t = 0.0, mu = 0.0 }]
"#;

fn refusal(from: &str, to: &str) -> ModelError {
    assert!(SCENE.contains(from), "{from}");
    Scene::from_toml_str(&SCENE.replacen(from, to, 1)).unwrap_err()
}

/// The field and the message of a refusal of the scene's reading.
fn parse(from: &str, to: &str) -> (Option<String>, String) {
    match refusal(from, to) {
        ModelError::Parse { field, message, .. } => (field, message.trim().to_owned()),
        other => panic!("{to}: {other:?}"),
    }
}

#[test]
fn the_scene_reads() {
    Scene::from_toml_str(SCENE).unwrap();
}

#[test]
fn a_shape_out_of_range_names_its_field_and_value() {
    assert_eq!(
        refusal("radius = 0.1", "radius = -0.1").to_string(),
        "invalid parameter `bodies.disk.shapes.0.radius` = -0.1: must be finite and >= 0"
    );
    let square = "[[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]]";
    assert_eq!(
        refusal(square, "[[-0.1, -0.1], [-0.1, 0.1], [0.1, 0.1], [0.1, -0.1]]").to_string(),
        "bad value `[[-0.1, -0.1], [-0.1, 0.1], [0.1, 0.1], [0.1, -0.1]]` for \
         `bodies.box.shapes.0.vertices`: the vertices run clockwise; a polygon lists them \
         counter-clockwise: [[0.1, -0.1], [0.1, 0.1], [-0.1, 0.1], [-0.1, -0.1]]"
    );
    let dented =
        refusal(square, "[[-0.1, -0.1], [0.1, -0.1], [0.0, 0.0], [0.1, 0.1], [-0.1, 0.1]]");
    match dented {
        ModelError::BadValue { key, value, reason } => {
            assert_eq!(
                (key.as_str(), value.as_str()),
                ("bodies.box.shapes.0.vertices.2", "[0, 0]")
            );
            assert!(
                reason.starts_with("the polygon turns clockwise or goes straight on"),
                "{reason}"
            );
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_bad_type_inside_a_shape_or_a_motion_names_the_field() {
    let cases = [
        (
            "radius = 0.1",
            "radius = \"big\"",
            "bodies.disk.shapes.0.radius",
            "invalid type: string \"big\", expected f64",
        ),
        (
            "center = [0.0, 0.0]",
            "center = [0.0]",
            "bodies.disk.shapes.0.center",
            "invalid length 1, expected an array of length 2",
        ),
        (
            "type = \"disk\"",
            "type = \"circle\"",
            "bodies.disk.shapes.0.type",
            "unknown variant `circle`",
        ),
        (
            "omega = 30.0",
            "omega = \"fast\"",
            "bodies.table.motion.omega",
            "invalid type: string \"fast\", expected f64",
        ),
        (
            "omega = 30.0",
            "omega = 30.0, phase = 1.0",
            "bodies.table.motion.phase",
            "expected an array of length 2",
        ),
        (
            "kind = \"oscillate\"",
            "kind = \"oscilate\"",
            "bodies.table.motion.kind",
            "unknown variant `oscilate`",
        ),
        (
            "eps_n = 0.1,",
            "eps_n = \"x\",",
            "contacts_auto.overrides.0.eps_n",
            "invalid type: string \"x\", expected f64",
        ),
        (
            "[\"table\", \"box\"]",
            "[\"table\"]",
            "contacts_auto.overrides.0.bodies",
            "invalid length 1, expected an array of length 2",
        ),
        (
            "[1.0, 0.0], [-1.0, 0.0]]",
            "[1.0], [-1.0, 0.0]]",
            "bodies.table.shapes.0.vertices.2",
            "invalid length 1",
        ),
    ];
    for (from, to, at, why) in cases {
        let (field, message) = parse(from, to);
        assert_eq!(field.as_deref(), Some(at), "{to}: {message}");
        assert!(message.contains(why), "{to}: {message}");
    }
}

/// A missing field is named by the table that lacks it; one missing from the top level,
/// which has no name, by the message alone, where the reader's position named the first key.
#[test]
fn a_missing_field_is_named_by_the_table_that_lacks_it() {
    let cases = [
        (", radius = 0.1", "", Some("bodies.disk.shapes.0"), "missing field `radius`"),
        ("{ type = \"disk\", ", "{ ", Some("bodies.disk.shapes.0"), "missing field `type`"),
        ("mu = 0.2\n", "", Some("contacts_auto"), "missing field `mu`"),
        ("gravity = [0.0, -9.81]\n", "", None, "missing field `gravity`"),
        ("dt = 0.001\n", "", None, "missing field `dt`"),
    ];
    for (from, to, at, why) in cases {
        let (field, message) = parse(from, to);
        assert_eq!(field.as_deref(), at, "{from}: {message}");
        assert_eq!(message, why);
    }
    let message = refusal("gravity = [0.0, -9.81]\n", "").to_string();
    assert_eq!(message, "invalid scene: missing field `gravity`");
}

#[test]
fn a_contact_with_a_shape_its_body_lacks_counts_the_shapes() {
    assert_eq!(
        refusal("mu = 0.0\n", "mu = 0.0\nshape_b = 1\n").to_string(),
        "bad value `1` for `contacts.hit.shape_b`: body `disk` has one shape, shape 0"
    );
}

#[test]
fn a_stop_rule_on_no_coordinate_names_the_mechanism() {
    let e = refusal(
        "t_end = 0.01\n",
        "t_end = 0.01\nstop_at = { coordinate = \"disk.z\", value = 0.0 }\n",
    );
    assert_eq!(
        e.to_string(),
        "bad value `disk.z` for `stop_at.coordinate`: not a coordinate of the declared \
         mechanism; accepted: disk.x, disk.y, disk.theta, box.x, box.y, box.theta"
    );
}
