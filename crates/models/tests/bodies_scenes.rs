//! Declared scene files: the shipped example runs, scenes round-trip through TOML, `--set`
//! reaches every declared field by its path, and bad input names the field.

use moreau_models::bodies::{BodyType, JointSpec};
use moreau_models::{ModelError, ModelKind, ModelParams, Scene};

fn example() -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/bodies/pendulum-wall.toml");
    Scene::from_path(&path).unwrap()
}

fn spec(scene: &Scene) -> &moreau_models::bodies::SystemSpec {
    match &scene.params {
        ModelParams::Declared(s) => s,
        other => panic!("not declared: {other:?}"),
    }
}

#[test]
fn the_pendulum_wall_scene_runs_and_rebounds_off_the_wall() {
    let mut scene = example();
    assert_eq!(scene.kind(), ModelKind::Declared);
    assert!(scene.projection, "declared scenes project by default");
    scene.t_end = 1.0;
    let sim = scene.run().unwrap();
    assert_eq!(sim.model.coordinate_names().to_vec(), ["bob.x", "bob.y", "bob.theta"]);
    assert_eq!(sim.model.velocity_names().to_vec(), ["bob.vx", "bob.vy", "bob.omega"]);
    assert_eq!(sim.model.contact_names(), ["hit"]);
    // The bob never passes the wall (its centre stays left of x = 0 up to the projection's
    // round-off) and hits it at least once.
    let right = sim.record.q.iter().map(|q| q[0]).fold(f64::NEG_INFINITY, f64::max);
    assert!(right < 1e-9, "{right}");
    assert!(sim.record.p_n.iter().any(|p| p[0] > 0.0));
    // Any declared scene draws: the wall, the bob and its hinge.
    let drawing = sim.model.draw(&sim.record.q[0], 0.0);
    assert!(drawing.bounds().is_some() && !drawing.circles.is_empty());
}

#[test]
fn declared_scenes_round_trip_through_toml() {
    let scene = example();
    let text = scene.to_toml_string().unwrap();
    assert!(text.contains("[[bodies]]") && !text.contains("[params]"), "{text}");
    assert_eq!(Scene::from_toml_str(&text).unwrap(), scene);
    let report = Scene::report(ModelKind::Declared);
    assert_eq!(Scene::from_toml_str(&report.to_toml_string().unwrap()).unwrap(), report);
}

#[test]
fn set_reaches_every_declared_field_by_its_path() {
    let mut scene = example();
    scene.set("bodies.bob.mass", "2").unwrap();
    scene.set("bodies.bob.position.1", "-0.9").unwrap();
    scene.set("contacts.hit.mu", "0.2").unwrap();
    scene.set("gravity.1", "-1.62").unwrap();
    scene.set("joints.hinge.anchor_a", "[0.01, 0.0]").unwrap();
    // Fields the file leaves at their defaults: the initial state is written out, so that
    // an entry of the velocity is a key too.
    assert!(scene.keys().iter().any(|k| k == "bodies.bob.velocity"), "{:?}", scene.keys());
    scene.set("bodies.bob.angle", "0.03").unwrap();
    scene.set("bodies.1.omega", "1.5").unwrap();
    scene.set("bodies.bob.velocity.0", "0.25").unwrap();
    scene.set("projection", "false").unwrap();
    let s = spec(&scene);
    let bob = &s.bodies[1];
    assert_eq!((bob.mass, bob.position[1], bob.angle, bob.omega), (Some(2.0), -0.9, 0.03, 1.5));
    assert_eq!(bob.velocity, [0.25, 0.0]);
    assert_eq!(bob.kind, BodyType::Dynamic);
    assert_eq!((s.contacts[0].mu, s.gravity[1]), (0.2, -1.62));
    assert!(
        matches!(&s.joints[0], JointSpec::Revolute { anchor_a, .. } if *anchor_a == [0.01, 0.0])
    );
    assert!(!scene.projection);
    assert!(scene.keys().iter().any(|k| k == "bodies.bob.mass"), "{:?}", scene.keys());
}

#[test]
fn bad_settings_name_the_path_and_leave_the_scene_alone() {
    let mut scene = example();
    let before = scene.clone();
    match scene.set("bodies.bob.mas", "2") {
        Err(ModelError::UnknownKey { key, level, name, valid, suggestion }) => {
            assert_eq!(
                (key.as_str(), level.as_str(), name.as_str()),
                ("bodies.bob.mas", "bodies.bob", "mas")
            );
            // `mass` and `mask` are one edit away both: no key is obvious.
            assert!(valid.iter().any(|k| k == "mass") && valid.iter().any(|k| k == "mask"));
            assert_eq!(suggestion, None);
        }
        other => panic!("{other:?}"),
    }
    match scene.set("bodies.bob.mass", "-1") {
        Err(ModelError::BadValue { key, reason, .. }) => {
            // The key is named once, by the error itself; the reason says what is wrong.
            assert_eq!(key, "bodies.bob.mass");
            assert!(!reason.contains("bodies.bob.mass") && reason.contains("> 0"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    match scene.set("bodies.nobody.mass", "1") {
        Err(e @ ModelError::UnknownKey { .. }) => {
            let message = e.to_string();
            let ModelError::UnknownKey { key, level, name, valid, suggestion } = e else {
                unreachable!()
            };
            assert_eq!(
                (key.as_str(), level.as_str(), name.as_str()),
                ("bodies.nobody.mass", "bodies", "nobody")
            );
            // The keys of the level are the bodies' names, and none is near enough.
            assert_eq!(valid, ["wall", "bob"]);
            assert_eq!(suggestion, None);
            assert!(message.contains("the keys of `bodies` are wall, bob"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    assert!(scene.set("bodies.bob.position", "[1, 2, 3]").is_err());
    assert_eq!(scene, before);
}

/// The text of `scenes/bodies/pendulum-wall.toml`.
fn pendulum_wall() -> String {
    std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../scenes/bodies/pendulum-wall.toml"),
    )
    .unwrap()
}

#[test]
fn malformed_declared_scenes_name_the_field() {
    let text = pendulum_wall();
    let unknown = text.replace("mass = 1.0", "mas = 1.0");
    match Scene::from_toml_str(&unknown) {
        Err(ModelError::Parse { field, message, .. }) => {
            assert_eq!(field.as_deref(), Some("bodies.bob.mas"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    // A syntax error inside an element of an array of tables names the element.
    match Scene::from_toml_str(&text.replace("mass = 1.0 ", "mass = 1.0, ")) {
        Err(ModelError::Parse { field, message, .. }) => {
            assert_eq!(field.as_deref(), Some("bodies.bob.mass"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    let dangling = text.replace("body_b = \"bob\"\nanchor_b", "body_b = \"bobby\"\nanchor_b");
    match Scene::from_toml_str(&dangling) {
        Err(ModelError::BadValue { key, value, reason }) => {
            assert_eq!((key.as_str(), value.as_str()), ("joints.hinge.body_b", "bobby"));
            // The bodies, then the world apart.
            assert!(reason.ends_with("bodies: wall, bob (or `ground` for the world)"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    let joint_type = text.replace("type = \"revolute\"", "type = \"hinge\"");
    match Scene::from_toml_str(&joint_type) {
        Err(ModelError::Parse { field, .. }) => {
            assert_eq!(field.as_deref(), Some("joints.hinge.type"))
        }
        other => panic!("{other:?}"),
    }
    let no_density_shape =
        text.replace("mass = 1.0", "density = 1.0").replace("inertia = 0.00125", "");
    let scene = Scene::from_toml_str(&no_density_shape).unwrap();
    // From the disk's area: m = ρ π r², I = m r² / 2.
    let model = scene.build().unwrap();
    let moreau_models::AnyModel::Declared(mb) = model else { panic!("declared") };
    let (m, i, c) = mb.mass_properties(1).unwrap();
    let area = std::f64::consts::PI * 0.05 * 0.05;
    assert!((m - area).abs() < 1e-15 && (i - 0.5 * area * 0.0025).abs() < 1e-15 && c == [0.0, 0.0]);
}

#[test]
fn a_dynamic_body_without_its_mass_properties_names_the_field_it_lacks() {
    let text = pendulum_wall();
    let error = |text: String| match Scene::from_toml_str(&text).and_then(|s| s.build()) {
        Err(ModelError::BadValue { key, value, reason }) => (key, value, reason),
        other => panic!("{other:?}"),
    };
    let cases = [
        (
            text.replace("inertia = 0.00125", ""),
            "bodies.bob.inertia",
            "(missing)",
            "`mass` is given",
        ),
        (text.replace("mass = 1.0", ""), "bodies.bob.mass", "(missing)", "`inertia` is given"),
        (
            text.replace("mass = 1.0", "mass = 1.0\ndensity = 2.5"),
            "bodies.bob.density",
            "2.5",
            "not instead",
        ),
        (
            text.replace("mass = 1.0", "").replace("inertia = 0.00125", ""),
            "bodies.bob.mass",
            "(missing)",
            "none is given",
        ),
    ];
    for (text, key, value, why) in cases {
        let (k, v, reason) = error(text);
        assert_eq!((k.as_str(), v.as_str()), (key, value), "{reason}");
        assert!(
            reason.contains(why) && reason.contains("mass and inertia or a density"),
            "{reason}"
        );
    }
    // A point mass (inertia 0) is told what to give instead.
    match Scene::from_toml_str(&text.replace("inertia = 0.00125", "inertia = 0.0"))
        .and_then(|s| s.build())
    {
        Err(ModelError::InvalidParameter { field, reason, .. }) => {
            assert_eq!(field, "bodies.bob.inertia");
            assert!(reason.contains("m r² / 2"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_missing_field_is_named_once() {
    let text = pendulum_wall();
    let no_position = text.replace("position = [0.0, 0.0]  # m\n", "");
    match Scene::from_toml_str(&no_position) {
        Err(ModelError::Parse { field, message, .. }) => {
            assert_eq!(field.as_deref(), Some("bodies.wall"));
            assert_eq!(message.trim(), "missing field `position`");
        }
        other => panic!("{other:?}"),
    }
}

/// Nothing in a scene file is read silently otherwise than written: a misspelled field of a
/// shape or of a load, and an array longer than its field, are refused, each naming the
/// field by its path.
#[test]
fn misspelled_fields_and_long_arrays_are_refused_by_their_path() {
    let text = pendulum_wall();
    let push = "\n[[forces]]\ntype = \"force\"\nname = \"push\"\nbody = \"bob\"\npoint = [0.0, 0.0]\n\
                fx = { amplitude = 5.0, omega = 5.0, offset = 10.0 }\nfy = 0.0\n";
    let with_push = format!("{text}{push}");
    let cases = [
        (
            text.replace("radius = 0.05 }", "radius = 0.05, denisty = 7.0 }"),
            "bodies.bob.shapes.0.denisty",
            "unknown field `denisty`",
        ),
        (text.replace("mass = 1.0 ", "mass = \"1.0\" "), "bodies.bob.mass", "invalid type: string"),
        (
            with_push.replace("offset = 10.0", "ofset = 10.0"),
            "forces.push.fx.ofset",
            "unknown field `ofset`",
        ),
        (
            text.replace(
                "position = [-0.479425538604203, -0.8775825618903728]",
                "position = [-0.479425538604203, -0.8775825618903728, 9.0]",
            ),
            "bodies.bob.position",
            "invalid length 3",
        ),
    ];
    for (text, at, why) in cases {
        match Scene::from_toml_str(&text) {
            Err(ModelError::Parse { field, message, .. }) => {
                assert_eq!(field.as_deref(), Some(at), "{message}");
                assert!(message.contains(why), "{message}");
            }
            other => panic!("{at}: {other:?}"),
        }
    }
    for empty in ["", "# only a comment\n"] {
        let message = Scene::from_toml_str(empty).unwrap_err().to_string();
        assert!(message.contains("the scene is empty"), "{message}");
    }
    let gravity = text.replace("gravity = [0.0, -9.81]", "gravity = [0.0, -9.81, 0.0]");
    let message = Scene::from_toml_str(&gravity).unwrap_err().to_string();
    assert!(message.contains("gravity") && message.contains("invalid length 3"), "{message}");

    // A load's constant and its sine stand for each other under `--set`; a misspelling does
    // not pass there either.
    let mut scene = Scene::from_toml_str(&with_push).unwrap();
    scene.set("forces.push.fx", "2.5").unwrap();
    scene.set("forces.push.fy", "{ amplitude = 1.0, omega = 2.0 }").unwrap();
    assert!(scene.set("forces.push.fy", "{ amplitude = 1.0, omga = 2.0 }").is_err());
    assert!(scene.set("bodies.bob.position", "3").is_err());
    let spec = spec(&scene);
    let moreau_models::bodies::ForceSpec::Force { fx, fy, .. } = &spec.forces[0] else {
        panic!("a force")
    };
    assert_eq!(fx.at(0.3), 2.5);
    assert_eq!(fy.at(0.3), (2.0f64 * 0.3).sin());
}

/// A load on a body that cannot move, and a spring or torsion between a body and itself or
/// between two bodies that cannot move, are refused by the field at fault.
#[test]
fn loads_and_contacts_that_move_nothing_are_refused() {
    let text = pendulum_wall();
    let cases = [
        (
            "type = \"force\"\nbody = \"wall\"\npoint = [0.0, 0.0]\nfx = 1.0\nfy = 0.0",
            "forces.0.body",
            "wall",
        ),
        ("type = \"torque\"\nbody = \"ground\"\ntorque = 1.0", "forces.0.body", "ground"),
        (
            "type = \"spring\"\nbody_a = \"bob\"\nanchor_a = [0.0, 0.0]\nbody_b = \"bob\"\n\
             anchor_b = [0.1, 0.0]\nstiffness = 10.0\nrest_length = 0.0",
            "forces.0.body_b",
            "bob",
        ),
        (
            "type = \"torsion\"\nbody_a = \"wall\"\nbody_b = \"ground\"\nstiffness = 1.0\nrest_angle = 0.0",
            "forces.0.body_b",
            "ground",
        ),
    ];
    for (force, key, value) in cases {
        let text = format!("{text}\n[[forces]]\n{force}\n");
        match Scene::from_toml_str(&text).and_then(|s| s.build()) {
            Err(ModelError::BadValue { key: k, value: v, reason }) => {
                assert_eq!((k.as_str(), v.as_str()), (key, value), "{reason}");
                assert!(reason.contains("nothing") || reason.contains("no force"), "{reason}");
            }
            other => panic!("{force}: {other:?}"),
        }
    }
    // A contact between two bodies that cannot move: its impulse would move nothing, and its
    // step problem would have no solution once they met.
    let post = "[[bodies]]\nname = \"post\"\ntype = \"fixed\"\nposition = [0.5, 0.0]\n\
                shapes = [{ type = \"disk\", center = [0.0, 0.0], radius = 0.1 }]\n\
                [[contacts]]\nname = \"stuck\"\nbody_a = \"wall\"\nbody_b = \"post\"\n\
                eps_n = 0.0\neps_t = 0.0\nmu = 0.0\n";
    match Scene::from_toml_str(&format!("{text}\n{post}")).and_then(|s| s.build()) {
        Err(ModelError::BadValue { key, value, reason }) => {
            assert_eq!((key.as_str(), value.as_str()), ("contacts.stuck.body_b", "post"));
            assert!(reason.contains("dynamic"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
}

/// A mass or inertia whose inverse the step's problem cannot hold (beyond 2^±500) is refused
/// when the scene is built, naming the field that gives it, rather than at the first contact.
#[test]
fn masses_beyond_the_step_problems_range_are_refused_by_their_field() {
    let text = pendulum_wall();
    let cases = [
        (text.replace("mass = 1.0 ", "mass = 1e-300 "), "bodies.bob.mass", "1e-300"),
        (text.replace("inertia = 0.00125", "inertia = 1e200"), "bodies.bob.inertia", "1e200"),
        (
            text.replace("mass = 1.0 ", "density = 1e-160 ").replace("inertia = 0.00125", ""),
            "bodies.bob.density",
            "of 7.8",
        ),
    ];
    for (text, at, shown) in cases {
        match Scene::from_toml_str(&text).and_then(|s| s.build()) {
            Err(e @ ModelError::InvalidParameter { .. }) => {
                let message = e.to_string();
                let ModelError::InvalidParameter { field, .. } = e else { unreachable!() };
                assert_eq!(field, at, "{message}");
                assert!(message.contains(shown) && message.contains("2^500"), "{message}");
            }
            other => panic!("{at}: {other:?}"),
        }
    }
    // 2^±400 still builds.
    let heavy = text
        .replace("mass = 1.0 ", "mass = 1e120 ")
        .replace("inertia = 0.00125", "inertia = 1e118");
    assert!(Scene::from_toml_str(&heavy).and_then(|s| s.build()).is_ok());
}

#[test]
fn a_value_out_of_range_is_refused_once_with_its_reason() {
    let mut scene = Scene::from_toml_str(&pendulum_wall()).unwrap();
    let before = scene.clone();
    let error = scene.set("contacts.hit.eps_n", "1.5").unwrap_err();
    match &error {
        ModelError::BadValue { key, value, reason } => {
            assert_eq!((key.as_str(), value.as_str()), ("contacts.hit.eps_n", "1.5"));
            assert_eq!(reason, "must lie in [0, 1]");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(error.to_string(), "bad value `1.5` for `contacts.hit.eps_n`: must lie in [0, 1]");
    assert_eq!(scene, before);
}
