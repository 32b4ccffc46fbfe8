//! Contact declarations that a scene would otherwise take without a word: a second explicit
//! contact between the same two shapes, and automatic-contact overrides that no pair takes
//! (a body with itself, two bodies that do not move, a jointed pair, a pair given twice, a
//! pair whose shapes explicit contacts all join, a pair the collision groups exclude).
//! Each is refused naming the field; the laws that are taken are checked on the conveyor
//! belt of `scenes/bodies/conveyor.toml`, where a disk set down on the belt accelerates at
//! μ g while it slips.

use moreau_models::{ModelError, Scene};

const CONVEYOR: &str = include_str!("../../../scenes/bodies/conveyor.toml");

/// The conveyor with its explicit contact replaced by `contacts` (TOML text).
fn conveyor_with(contacts: &str) -> String {
    let head = &CONVEYOR[..CONVEYOR.find("[[contacts]]").unwrap()];
    format!("{head}{contacts}")
}

/// The field a refusal names.
fn field(e: &ModelError) -> &str {
    match e {
        ModelError::BadValue { key, .. } => key,
        ModelError::InvalidParameter { field, .. } => field,
        other => panic!("not a refusal of a field: {other}"),
    }
}

/// The disk's horizontal acceleration over the first 0.05 s, in units of g: μ while it slips
/// (it rolls from t* = V / (3 μ g), 0.068 s at μ = 0.5).
fn slip_acceleration(scene: &Scene) -> f64 {
    let mut scene = scene.clone();
    scene.t_end = 0.05;
    let sim = scene.run().unwrap();
    let (t, u) = (sim.record.t.last().unwrap(), sim.record.u.last().unwrap());
    u[0] / t / 9.81
}

const SECOND: &str = r#"
[[contacts]]
name = "slip"
body_a = "belt"
body_b = "disk"
eps_n = 0.0
eps_t = 0.0
mu = 0.2

[[contacts]]
name = "grip"
body_a = "disk"
body_b = "belt"
eps_n = 0.0
eps_t = 0.0
mu = 0.6
"#;

#[test]
fn a_second_contact_between_the_same_shapes_is_refused() {
    // Both used to be slots of the same point: the disk then slipped at 0.6 g, the second
    // contact's law, under the first one's name.
    let e = Scene::from_toml_str(&conveyor_with(SECOND)).unwrap_err();
    assert_eq!(field(&e), "contacts.grip.body_b", "{e}");
    assert!(e.to_string().contains("contact `slip` is already between these two shapes"), "{e}");
    // One of them alone is the declared law: μ g.
    let one =
        Scene::from_toml_str(&conveyor_with(&SECOND[..SECOND.rfind("[[contacts]]").unwrap()]))
            .unwrap();
    let a = slip_acceleration(&one);
    assert!((a - 0.2).abs() < 1e-9, "{a}");
}

/// The conveyor with automatic contacts at μ = 0.2 and the overrides `overrides`, and a second
/// disk `wheel` pinned to the first by a revolute joint.
fn with_overrides(overrides: &str) -> String {
    let head = &CONVEYOR[..CONVEYOR.find("[[contacts]]").unwrap()];
    format!(
        r#"{head}
[[bodies]]
name = "wheel"
type = "dynamic"
mass = 1.0
inertia = 0.005
position = [1.0, 0.1]
shapes = [{{ type = "disk", center = [0.0, 0.0], radius = 0.1 }}]

[[bodies]]
name = "post"
type = "fixed"
position = [3.0, 1.0]
shapes = [{{ type = "disk", center = [0.0, 0.0], radius = 0.1 }}]

[[joints]]
type = "revolute"
name = "axle"
body_a = "disk"
anchor_a = [1.0, 0.0]
body_b = "wheel"
anchor_b = [0.0, 0.0]

[contacts_auto]
eps_n = 0.0
eps_t = 0.0
mu = 0.2
overrides = [{overrides}]
"#
    )
}

#[test]
fn overrides_that_no_automatic_pair_takes_are_refused() {
    let law = "eps_n = 0.0, eps_t = 0.0, mu = 0.5";
    for (overrides, reason) in [
        // A body with itself.
        (format!(r#"{{ bodies = ["disk", "disk"], {law} }}"#), "a body has no contact with itself"),
        // Two bodies that do not move.
        (format!(r#"{{ bodies = ["belt", "post"], {law} }}"#), "neither body is dynamic"),
        // A jointed pair gets no automatic contacts.
        (format!(r#"{{ bodies = ["wheel", "disk"], {law} }}"#), "a joint connects the two bodies"),
    ] {
        let e = Scene::from_toml_str(&with_overrides(&overrides)).unwrap_err();
        assert_eq!(field(&e), "contacts_auto.overrides.0.bodies.1", "{overrides}: {e}");
        assert!(e.to_string().contains(reason), "{overrides}: {e}");
    }
    // The same pair twice, in either order: the second used to be dropped, the first taken.
    let twice = format!(
        r#"{{ bodies = ["disk", "belt"], {law} }}, {{ bodies = ["belt", "disk"], eps_n = 0.0, eps_t = 0.0, mu = 0.9 }}"#
    );
    let e = Scene::from_toml_str(&with_overrides(&twice)).unwrap_err();
    assert_eq!(field(&e), "contacts_auto.overrides.1.bodies.1", "{e}");
    assert!(e.to_string().contains("contacts_auto.overrides.0 already gives"), "{e}");
    // One override is taken: the disk alone on the belt slips at 0.5 g, not the default 0.2 g.
    let head = &CONVEYOR[..CONVEYOR.find("[[contacts]]").unwrap()];
    let auto = format!(
        "{head}[contacts_auto]\neps_n = 0.0\neps_t = 0.0\nmu = 0.2\n\
         overrides = [{{ bodies = [\"disk\", \"belt\"], {law} }}]\n"
    );
    let scene = Scene::from_toml_str(&auto).unwrap();
    let a = slip_acceleration(&scene);
    assert!((a - 0.5).abs() < 1e-9, "{a}");
}

#[test]
fn set_refuses_an_override_of_a_body_with_itself_and_leaves_the_scene() {
    let once = r#"{ bodies = ["disk", "belt"], eps_n = 0.0, eps_t = 0.0, mu = 0.5 }"#;
    let mut scene = Scene::from_toml_str(&with_overrides(once)).unwrap();
    let before = scene.clone();
    let e = scene.set("contacts_auto.overrides.0.bodies.1", "disk").unwrap_err();
    let ModelError::BadValue { key, .. } = &e else { panic!("{e}") };
    assert_eq!(key, "contacts_auto.overrides.0.bodies.1", "{e}");
    assert!(e.to_string().contains("a body has no contact with itself"), "{e}");
    assert_eq!(scene, before);
}

#[test]
fn overrides_of_pairs_that_explicit_contacts_or_collision_groups_take_away_are_refused() {
    let law = "eps_n = 0.0, eps_t = 0.0, mu = 0.5";
    let auto = format!(
        "[contacts_auto]\neps_n = 0.0\neps_t = 0.0\nmu = 0.2\n\
         overrides = [{{ bodies = [\"disk\", \"belt\"], {law} }}]\n"
    );
    // The explicit contact `slip` joins the disk's only shape to the belt's: the automatic
    // contacts skip that pair of shapes, and the override would not reach it.
    let covered = format!("{CONVEYOR}\n{auto}");
    let e = Scene::from_toml_str(&covered).unwrap_err();
    assert_eq!(field(&e), "contacts_auto.overrides.0.bodies.1", "{e}");
    assert!(e.to_string().contains("explicit contacts already join every shape"), "{e}");
    // Without the override the explicit law holds: μ = 0.2.
    let plain = format!("{CONVEYOR}\n[contacts_auto]\neps_n = 0.0\neps_t = 0.0\nmu = 0.7\n");
    let a = slip_acceleration(&Scene::from_toml_str(&plain).unwrap());
    assert!((a - 0.2).abs() < 1e-9, "{a}");
    // The disk in group 2 and the belt's mask without it: no automatic contact between them.
    let head = &CONVEYOR[..CONVEYOR.find("[[contacts]]").unwrap()];
    let grouped = head
        .replace("name = \"belt\"\n", "name = \"belt\"\nmask = 1\n")
        .replace("name = \"disk\"\n", "name = \"disk\"\ngroup = 2\n");
    assert_ne!(grouped, head);
    let e = Scene::from_toml_str(&format!("{grouped}{auto}")).unwrap_err();
    assert_eq!(field(&e), "contacts_auto.overrides.0.bodies.1", "{e}");
    assert!(e.to_string().contains("collision groups and masks exclude the pair"), "{e}");
}
