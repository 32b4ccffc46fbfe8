//! `--set` keys that name no entry of a scene: the level of the scene's tree where they leave
//! it, the keys of that level (the optional fields a table leaves out included) and the key
//! meant; and the optional fields left out, which are keys.

use moreau_models::*;
use moreau_testsupport::scene_path;

/// The scene file `name` of `scenes/`.
fn scene(name: &str) -> Scene {
    Scene::from_path(&scene_path(name)).unwrap()
}

/// The parts of the refusal of `key` on `scene`, which must be an unknown key and leave the
/// scene unchanged: (level, name, valid keys, suggestion).
fn unknown(scene: &Scene, key: &str) -> (String, String, Vec<String>, Option<String>) {
    let mut changed = scene.clone();
    let error = changed.set(key, "1").expect_err(key);
    assert_eq!(&changed, scene, "{key}");
    // The same refusal from the resolution of the key alone, worded from its parts.
    assert_eq!(scene.targets(key).expect_err(key).to_string(), error.to_string());
    match error {
        ModelError::UnknownKey { key: k, level, name, valid, suggestion } => {
            assert_eq!(k, key);
            let text = unknown_key_text(key, &level, &name, &valid, suggestion.as_deref());
            assert_eq!(
                text,
                ModelError::UnknownKey {
                    key: k,
                    level: level.clone(),
                    name: name.clone(),
                    valid: valid.clone(),
                    suggestion: suggestion.clone(),
                }
                .to_string()
            );
            (level, name, valid, suggestion)
        }
        other => panic!("{key}: {other:?}"),
    }
}

#[test]
fn a_misspelt_body_name_leaves_the_tree_at_the_bodies() {
    let ball = scene("bodies/ball.toml");
    let (level, name, valid, suggestion) = unknown(&ball, "bodies.bal.mass");
    assert_eq!((level.as_str(), name.as_str()), ("bodies", "bal"));
    assert_eq!(valid, ["floor", "ball"]);
    assert_eq!(suggestion.as_deref(), Some("bodies.ball.mass"));
    // An index past the last element is no element either.
    let (level, name, valid, suggestion) = unknown(&ball, "bodies.2.mass");
    assert_eq!((level.as_str(), name.as_str(), suggestion), ("bodies", "2", None));
    assert_eq!(valid, ["floor", "ball"]);
}

#[test]
fn a_misspelt_body_field_lists_the_fields_of_a_body_left_out_ones_included() {
    let ball = scene("bodies/ball.toml");
    for key in ["bodies.ball.masss", "bodies.1.masss"] {
        let (level, name, valid, suggestion) = unknown(&ball, key);
        let at = key.strip_suffix(".masss").unwrap();
        assert_eq!((level.as_str(), name.as_str()), (at, "masss"));
        assert_eq!(suggestion, Some(format!("{at}.mass")));
        // Every field of a body, in its declared order, whether the ball gives it or not.
        assert_eq!(
            valid,
            [
                "name",
                "type",
                "mass",
                "inertia",
                "center_of_mass",
                "density",
                "position",
                "angle",
                "velocity",
                "omega",
                "motion",
                "shapes",
                "group",
                "mask"
            ]
        );
    }
    // Deeper: a shape's fields, after its tag; an array's indices; a value has no keys.
    let (level, _, valid, suggestion) = unknown(&ball, "bodies.ball.shapes.0.radiuss");
    assert_eq!(
        (level.as_str(), valid),
        (
            "bodies.ball.shapes.0",
            vec!["type", "center", "radius"].into_iter().map(String::from).collect()
        )
    );
    assert_eq!(suggestion.as_deref(), Some("bodies.ball.shapes.0.radius"));
    let (level, _, valid, _) = unknown(&ball, "gravity.2");
    assert_eq!((level.as_str(), valid), ("gravity", vec!["0".to_owned(), "1".to_owned()]));
    let (level, _, valid, _) = unknown(&ball, "dt.x");
    assert_eq!((level.as_str(), valid), ("dt", Vec::<String>::new()));
}

#[test]
fn an_optional_field_left_out_is_a_key() {
    let mut ball = scene("bodies/ball.toml");
    assert!(!ball.keys().iter().any(|k| k == "bodies.ball.density"));
    // `density` is a key: the body's own rule refuses it next to a mass, by name.
    match ball.clone().set("bodies.ball.density", "31.8") {
        Err(ModelError::BadValue { key, reason, .. }) => {
            assert_eq!(key, "bodies.ball.density");
            assert!(reason.contains("not instead"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    // Without the mass and inertia it takes the density alone.
    let text = std::fs::read_to_string(scene_path("bodies/ball.toml")).unwrap();
    let text = text.replace("mass = 1.0", "").replace("inertia = 0.004", "density = 10.0");
    let mut by_density = Scene::from_toml_str(&text).unwrap();
    by_density.set("bodies.ball.density", "31.8").unwrap();
    let ModelParams::Declared(spec) = &by_density.params else { panic!("not declared") };
    assert_eq!(spec.bodies[1].density, Some(31.8));
    ball.set("bodies.ball.center_of_mass", "[0.0, 0.001]").unwrap();
    ball.set("inexact_residual", "1e-6").unwrap();
    let ModelParams::Declared(spec) = &ball.params else { panic!("not declared") };
    assert_eq!(spec.bodies[1].center_of_mass, Some([0.0, 0.001]));
    assert_eq!(ball.inexact_residual, 1e-6);
    assert_eq!(ball.targets("bodies.1.density").unwrap(), ["bodies.ball.density"]);
    // A joint's angle, which the prismatic guide of the cam leaves out.
    let mut cam = scene("bodies/cam.toml");
    let (_, _, valid, suggestion) = unknown(&cam, "joints.guide.angel");
    assert!(valid.iter().any(|k| k == "angle"), "{valid:?}");
    assert_eq!(valid[0], "type", "the tag comes first: {valid:?}");
    assert_eq!(suggestion.as_deref(), Some("joints.guide.angle"));
    cam.set("joints.guide.angle", "0.0").unwrap();
    // The report's models take the fields that their scene leaves out too.
    let mut report = scene("ball.toml");
    assert!(!report.projection);
    report.set("projection", "true").unwrap();
    assert!(report.projection);
}

#[test]
fn a_part_below_a_field_left_out_is_unknown() {
    let ball = scene("bodies/ball.toml");
    let key = "bodies.ball.motion.kind";
    let (level, name, valid, suggestion) = unknown(&ball, key);
    assert_eq!((level.as_str(), name.as_str(), suggestion), ("bodies.ball", "motion", None));
    assert!(valid.iter().any(|k| k == "motion"));
    let message = ball.targets(key).unwrap_err().to_string();
    assert!(message.contains("set `bodies.ball.motion` whole"), "{message}");
    let (level, name, _, _) = unknown(&scene("ball.toml"), "stop_at.value");
    assert_eq!((level.as_str(), name.as_str()), ("", "stop_at"));
}

#[test]
fn a_misspelt_top_level_key_of_a_report_model() {
    let ball = scene("ball.toml");
    let (level, name, valid, suggestion) = unknown(&ball, "eps_nn");
    assert_eq!((level.as_str(), name.as_str()), ("", "eps_nn"));
    assert_eq!(suggestion.as_deref(), Some("eps_n"));
    // The scene's keys, with the fields it leaves out, then the parameters' keys.
    assert_eq!(
        valid,
        [
            "solver",
            "dt",
            "record_every",
            "t_end",
            "t_start",
            "stop_at",
            "projection",
            "inexact_residual",
            "impulses",
            "eps_n",
            "g",
            "init.v0",
            "init.y0",
            "m",
            "r"
        ]
    );
    let (_, _, _, suggestion) = unknown(&ball, "params.eps_nn");
    assert_eq!(suggestion.as_deref(), Some("eps_n"));
    let (_, name, _, suggestion) = unknown(&ball, "initt.y0");
    assert_eq!((name.as_str(), suggestion.as_deref()), ("initt", Some("init.y0")));
    let (level, name, valid, suggestion) = unknown(&ball, "init.y00");
    assert_eq!((level.as_str(), name.as_str()), ("init", "y00"));
    assert_eq!(valid, ["y0", "v0"]);
    assert_eq!(suggestion.as_deref(), Some("init.y0"));
    // The model is chosen by the scene file, not set.
    let (_, name, _, _) = unknown(&ball, "model");
    assert_eq!(name, "model");
    unknown(&ball, "params.model");
}

#[test]
fn a_misspelt_top_level_key_of_a_declared_scene() {
    for file in ["bodies/ball.toml", "bodies/pendulum-wall.toml", "bodies/stack.toml"] {
        let declared = scene(file);
        let (level, name, valid, suggestion) = unknown(&declared, "gravty");
        assert_eq!((level.as_str(), name.as_str()), ("", "gravty"), "{file}");
        assert_eq!(suggestion.as_deref(), Some("gravity"), "{file}");
        // Every field of a declared scene, those the file leaves out included.
        assert_eq!(
            valid,
            [
                "dt",
                "t_start",
                "t_end",
                "record_every",
                "solver",
                "stop_at",
                "projection",
                "inexact_residual",
                "gravity",
                "bodies",
                "joints",
                "forces",
                "contacts",
                "contacts_auto",
                "contact_set",
                "fill",
                "impulses"
            ],
            "{file}"
        );
        let (_, _, _, suggestion) = unknown(&declared, "zzz");
        assert_eq!(suggestion, None, "{file}");
    }
}

#[test]
fn a_value_out_of_range_is_told_as_given() {
    // A pyramid of base 0 is refused with the 0 it was given.
    let mut pyramid = scene("scale/pyramid.toml");
    let e = pyramid.set("fill.box.base", "0").expect_err("base 0").to_string();
    assert!(
        e.contains("bad value `0` for `fill.box.base`") && e.contains("needs `base` >= 1"),
        "{e}"
    );
    // A Gauss-Seidel tolerance out of its range names the option once.
    let mut ball = Scene::report(ModelKind::Ball);
    ball.set("solver", "pgs").unwrap();
    let e = ball.set("solver.tolerance", "2").expect_err("tolerance 2").to_string();
    assert!(e.ends_with("solver.tolerance must be in (0, 1)"), "{e}");
}
