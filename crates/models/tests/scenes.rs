//! Scene files: every shipped file loads and runs; malformed files and bad `--set` keys get
//! errors that name the field.

use moreau_models::*;
use moreau_stepper::SolverChoice;
use moreau_testsupport::scene_path;

const FILES: [&str; 8] = [
    "ball.toml",
    "woodpecker.toml",
    "slider-crank.toml",
    "slider-crank-ideal.toml",
    "cam.toml",
    "cam-printed-spring.toml",
    "painleve.toml",
    "painleve-mu2.toml",
];

#[test]
fn every_scene_file_loads_and_runs_one_step() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let mut found: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    found.sort();
    let mut expected: Vec<String> = FILES.iter().map(|s| s.to_string()).collect();
    expected.sort();
    assert_eq!(found, expected);
    for name in FILES {
        let mut scene = Scene::from_path(&scene_path(name)).unwrap();
        scene.t_end = scene.dt;
        let sim = scene.run().unwrap();
        assert_eq!(sim.steps, 1, "{name}");
        assert_eq!(sim.record.len(), 2, "{name}");
    }
}

#[test]
fn shipped_scenes_are_the_reports() {
    let pairs = [
        ("ball.toml", Scene::report(ModelKind::Ball)),
        ("woodpecker.toml", Scene::report(ModelKind::Woodpecker)),
        ("slider-crank.toml", Scene::report(ModelKind::SliderCrank)),
        ("slider-crank-ideal.toml", Scene::report(ModelKind::SliderCrankIdeal)),
        ("cam.toml", Scene::report(ModelKind::Cam)),
        ("painleve.toml", Scene::report(ModelKind::Painleve)),
    ];
    for (name, scene) in pairs {
        assert_eq!(Scene::from_path(&scene_path(name)).unwrap(), scene, "{name}");
    }
    let mut mu2 = Scene::report(ModelKind::Painleve);
    mu2.set("mu", "2.0").unwrap();
    assert_eq!(Scene::from_path(&scene_path("painleve-mu2.toml")).unwrap(), mu2);
    let mut printed = Scene::report(ModelKind::Cam);
    printed.params = ModelParams::Cam(CamParams::as_printed());
    assert_eq!(Scene::from_path(&scene_path("cam-printed-spring.toml")).unwrap(), printed);
}

#[test]
fn scenes_round_trip_through_toml() {
    for kind in ModelKind::ALL {
        let mut scene = Scene::report(kind);
        scene.solver = SolverChoice::pgs_default();
        scene.record_every = 3;
        let text = scene.to_toml_string().unwrap();
        assert_eq!(Scene::from_toml_str(&text).unwrap(), scene, "{kind}:\n{text}");
        assert_eq!(scene.kind(), kind);
    }
}

fn ball_text(extra_top: &str, params_line: &str) -> String {
    format!(
        "dt = 0.001\nt_end = 1.0\n{extra_top}\n[params]\nmodel = \"ball\"\nm = 1.0\nr = 0.1\ng = 9.81\n{params_line}\n"
    )
}

fn parse_error_field(text: &str) -> (Option<String>, String) {
    match Scene::from_toml_str(text) {
        Err(ModelError::Parse { field, message, .. }) => (field, message),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

#[test]
fn malformed_scenes_name_the_bad_field() {
    // Unknown field at the top level.
    let (field, message) = parse_error_field(&ball_text("dtt = 3", "eps_n = 0.9"));
    assert_eq!(field.as_deref(), Some("dtt"));
    assert!(message.contains("dtt"));
    // Unknown field inside the model's parameters.
    let (field, message) = parse_error_field(&ball_text("", "eps_n = 0.9\nbounciness = 2"));
    assert_eq!(field.as_deref(), Some("params.bounciness"));
    assert!(message.contains("bounciness"));
    // Wrong type inside the model's parameters.
    let text = ball_text("", "eps_n = 0.9").replace("m = 1.0", "m = \"heavy\"");
    let (field, message) = parse_error_field(&text);
    assert_eq!(field.as_deref(), Some("params.m"), "{message}");
    // Wrong type in a nested table.
    let text = ball_text("", "eps_n = 0.9\n[params.init]\ny0 = true\nv0 = 0.0");
    let (field, _) = parse_error_field(&text);
    assert_eq!(field.as_deref(), Some("params.init.y0"));
    // Wrong type at the top level.
    let (field, _) =
        parse_error_field(&ball_text("", "eps_n = 0.9").replace("dt = 0.001", "dt = \"small\""));
    assert_eq!(field.as_deref(), Some("dt"));
    // A missing physical parameter.
    let (_, message) = parse_error_field(&ball_text("", ""));
    assert!(message.contains("eps_n"), "{message}");
    // Unknown model.
    let text = ball_text("", "eps_n = 0.9").replace("\"ball\"", "\"balloon\"");
    let err = Scene::from_toml_str(&text).unwrap_err().to_string();
    assert!(err.contains("balloon") && err.contains("woodpecker"), "{err}");
    // Out of range: ε_N = 1.5.
    match Scene::from_toml_str(&ball_text("", "eps_n = 1.5")) {
        Err(ModelError::InvalidParameter { field, value, .. }) => {
            assert_eq!((field.as_str(), value), ("eps_n", 1.5));
        }
        other => panic!("expected an invalid parameter, got {other:?}"),
    }
    // Out of range inside a contact's laws, and a scene field out of range.
    let mut text = std::fs::read_to_string(scene_path("woodpecker.toml")).unwrap();
    text = text.replacen("mu = 0.3", "mu = -0.3", 2);
    let err = Scene::from_toml_str(&text).unwrap_err();
    assert!(err.to_string().contains("beak.mu"), "{err}");
    let err =
        Scene::from_toml_str(&ball_text("", "eps_n = 0.9").replace("dt = 0.001", "dt = -1.0"))
            .unwrap_err();
    assert!(err.to_string().contains("`dt`"), "{err}");
    // The file's path is carried along.
    let dir = std::env::temp_dir().join(format!("moreau-models-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bad.toml");
    std::fs::write(&path, ball_text("dtt = 1", "eps_n = 0.9")).unwrap();
    let err = Scene::from_path(&path).unwrap_err().to_string();
    assert!(err.contains("bad.toml") && err.contains("dtt"), "{err}");
    assert!(matches!(Scene::from_path(&dir.join("missing.toml")), Err(ModelError::Io { .. })));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn set_accepts_scene_and_model_keys() {
    let mut scene = Scene::report(ModelKind::Ball);
    scene.set("eps_n", "0.5").unwrap();
    scene.set("init.v0", "2.0").unwrap();
    scene.set("params.r", "0.2").unwrap();
    scene.set("dt", "0.002").unwrap();
    scene.set("t_end", "3").unwrap();
    scene.set("solver", "lemke").unwrap();
    scene.set("y0", "1.5").unwrap();
    let ModelParams::Ball(p) = &scene.params else { panic!("wrong model") };
    assert_eq!((p.eps_n, p.init.v0, p.r, p.init.y0), (0.5, 2.0, 0.2, 1.5));
    assert_eq!((scene.dt, scene.t_end, scene.solver), (0.002, 3.0, SolverChoice::Lemke));
    scene.set("solver", "pgs").unwrap();
    assert!(scene.keys().contains(&"solver.tolerance".to_string()));
    scene.set("solver.tolerance", "1e-8").unwrap();
    assert!(matches!(scene.solver, SolverChoice::Pgs { tolerance, .. } if tolerance == 1e-8));
    // The scene file's table form, whole.
    scene
        .set("solver", "{ kind = \"pgs\", tolerance = 1e-9, omega = 1.2, max_iterations = 500 }")
        .unwrap();
    assert!(matches!(scene.solver, SolverChoice::Pgs { tolerance, .. } if tolerance == 1e-9));
    let e = scene.set("solver", "{ kind = \"newton\" }").unwrap_err().to_string();
    assert!(e.contains("not a solver table"), "{e}");
    let e = scene.set("solver", "newton").unwrap_err().to_string();
    assert!(e.contains("or a table as in a scene file"), "{e}");

    // A last key part sets every matching key: all three woodpecker contacts.
    let mut wp = Scene::report(ModelKind::Woodpecker);
    wp.set("mu", "0.2").unwrap();
    let ModelParams::Woodpecker(p) = &wp.params else { panic!("wrong model") };
    assert_eq!((p.beak.mu, p.lower.mu, p.upper.mu), (0.2, 0.2, 0.2));
    wp.set("beak.eps_n", "0.7").unwrap();
    let ModelParams::Woodpecker(p) = &wp.params else { panic!("wrong model") };
    assert_eq!((p.beak.eps_n, p.lower.eps_n), (0.7, 0.0));

    let mut sc = Scene::report(ModelKind::SliderCrank);
    sc.set("stop_at.value", "3.5").unwrap();
    assert_eq!(sc.stop_at.as_ref().unwrap().value, 3.5);
}

#[test]
fn set_rejects_unknown_keys_and_bad_values() {
    let mut scene = Scene::report(ModelKind::Ball);
    let before = scene.clone();
    match scene.set("bounciness", "1") {
        Err(ModelError::UnknownKey { key, level, name, valid, suggestion }) => {
            assert_eq!(
                (key.as_str(), level.as_str(), name.as_str()),
                ("bounciness", "", "bounciness")
            );
            assert_eq!(suggestion, None);
            for k in ["dt", "t_end", "solver", "record_every", "eps_n", "m", "init.v0"] {
                assert!(valid.contains(&k.to_string()), "{k} missing from {valid:?}");
            }
            // The fields that the scene leaves out are keys as well; the model is no key.
            assert!(valid.contains(&"projection".to_string()), "{valid:?}");
            assert!(!valid.contains(&"model".to_string()));
        }
        other => panic!("expected an unknown key, got {other:?}"),
    }
    let err = scene.set("nonsense", "1").unwrap_err().to_string();
    assert!(err.contains("eps_n") && err.contains("init.y0"), "{err}");
    for (key, value) in [
        ("eps_n", "1.5"),
        ("eps_n", "lots"),
        ("dt", "0"),
        ("solver", "newton"),
        ("record_every", "-2"),
    ] {
        match scene.set(key, value) {
            Err(ModelError::BadValue { key: k, value: v, .. }) => {
                assert_eq!((k.as_str(), v.as_str()), (key, value))
            }
            other => panic!("{key}={value}: expected a bad value, got {other:?}"),
        }
    }
    assert_eq!(scene, before, "a failed set must leave the scene unchanged");
    // The stepper's rule for `inexact_residual`, [0, 1), is the scene's: refused when set or
    // read, before a run starts.
    for value in ["nan", "-1", "1", "2", "inf"] {
        match scene.set("inexact_residual", value) {
            Err(ModelError::BadValue { key, value: v, reason }) => {
                assert_eq!((key.as_str(), v.as_str()), ("inexact_residual", value));
                assert!(reason.contains("[0, 1)"), "{reason}");
            }
            other => panic!("inexact_residual={value}: expected a bad value, got {other:?}"),
        }
    }
    assert_eq!(scene, before, "a failed set must leave the scene unchanged");
    scene.set("inexact_residual", "1e-4").unwrap();
    let text = scene
        .to_toml_string()
        .unwrap()
        .replace("inexact_residual = 0.0001", "inexact_residual = -0.5");
    match Scene::from_toml_str(&text) {
        Err(ModelError::InvalidParameter { field, .. }) => assert_eq!(field, "inexact_residual"),
        other => panic!("inexact_residual = -0.5: expected it refused, got {other:?}"),
    }
    let mut wp = Scene::report(ModelKind::Woodpecker);
    let err = wp.set("beak_contact", "maybe").unwrap_err().to_string();
    assert!(err.contains("beak_contact"), "{err}");
    let mut sc = Scene::report(ModelKind::SliderCrank);
    let err = sc.set("stop_at.coordinate", "th9").unwrap_err().to_string();
    assert!(err.contains("th9") && err.contains("th1"), "{err}");
}

#[test]
fn model_kinds_and_names() {
    for kind in ModelKind::ALL {
        assert_eq!(kind.to_string().parse::<ModelKind>().unwrap(), kind);
        let model = Scene::report(kind).build().unwrap();
        assert_eq!(model.kind(), kind);
        let (q0, u0) = model.initial_state();
        assert_eq!(q0.len(), model.coordinate_names().len());
        assert_eq!(u0.len(), model.velocity_names().len());
        assert_eq!(model.params(), Scene::report(kind).params);
    }
    let names: Vec<String> = ModelKind::ALL.iter().map(|k| k.to_string()).collect();
    assert_eq!(
        names,
        ["ball", "woodpecker", "slider-crank", "slider-crank-ideal", "cam", "painleve"]
    );
    assert!("pendulum".parse::<ModelKind>().is_err());
    let coords: Vec<&[&str]> = ModelKind::ALL.iter().map(|k| k.coordinate_names()).collect();
    assert_eq!(
        coords,
        [
            &["y"][..],
            &["y", "phiM", "phiS"],
            &["th1", "th2", "th3"],
            &["th1"],
            &["y"],
            &["x", "y", "phi"]
        ]
    );
    let vels: Vec<&[&str]> = ModelKind::ALL.iter().map(|k| k.velocity_names()).collect();
    assert_eq!(
        vels,
        [
            &["v"][..],
            &["v", "omegaM", "omegaS"],
            &["w1", "w2", "w3"],
            &["w1"],
            &["v"],
            &["vx", "vy", "omega"]
        ]
    );
}

#[test]
fn run_with_streams_and_stops_at_the_rule() {
    let mut scene = Scene::report(ModelKind::SliderCrankIdeal);
    scene.set("stop_at.value", "1.0").unwrap();
    let mut last = Vec::new();
    let mut count = 0u64;
    let mut observer = |report: &moreau_stepper::StepReport<'_>| {
        last = report.q.to_vec();
        count += 1;
        std::ops::ControlFlow::Continue(())
    };
    let summary = scene.run_with(&mut observer).unwrap();
    assert_eq!(summary.steps, count);
    assert!(last[0] >= 1.0 && last[0] < 1.0 + 150.0 * scene.dt * 1.5);
}

/// (t, q, u) after each of `steps` steps of a stepper of `model`, by `step` and by
/// `run_until`, as bits.
fn trajectory<M: moreau_stepper::Mechanism + Clone>(
    model: M,
    scene: &Scene,
    steps: usize,
) -> Vec<u64> {
    let (q0, u0) = scene.build().unwrap().initial_state();
    let options = scene.stepper_options();
    let mut by_step =
        moreau_stepper::Stepper::new(model.clone(), &q0, &u0, 0.0, options.clone()).unwrap();
    let mut bits = Vec::new();
    let mut push = |t: f64, q: &[f64], u: &[f64]| {
        bits.push(t.to_bits());
        bits.extend(q.iter().chain(u).map(|v| v.to_bits()));
    };
    for _ in 0..steps {
        let r = by_step.step().unwrap();
        push(r.t, r.q, r.u);
    }
    let mut by_run = moreau_stepper::Stepper::new(model, &q0, &u0, 0.0, options).unwrap();
    let summary = by_run
        .run_until(steps as f64 * scene.dt, &mut |r: &moreau_stepper::StepReport<'_>| {
            push(r.t, r.q, r.u);
            std::ops::ControlFlow::Continue(())
        })
        .unwrap();
    assert_eq!(summary.steps, steps as u64);
    bits
}

#[test]
fn a_scene_built_model_steps_exactly_as_its_concrete_type() {
    // A stepper of `AnyModel` dispatches each call, `Scene::run` steps the model's own type;
    // the trajectories must be the same, bit for bit (a declared mechanism's joints
    // included).
    for kind in ModelKind::ALL.into_iter().chain([ModelKind::Declared]) {
        let scene = Scene::report(kind);
        let steps = 3000;
        let any = trajectory(scene.build().unwrap(), &scene, steps);
        let concrete = match scene.build().unwrap() {
            AnyModel::Ball(m) => trajectory(m, &scene, steps),
            AnyModel::Woodpecker(m) => trajectory(m, &scene, steps),
            AnyModel::SliderCrank(m) => trajectory(m, &scene, steps),
            AnyModel::SliderCrankIdeal(m) => trajectory(m, &scene, steps),
            AnyModel::Cam(m) => trajectory(m, &scene, steps),
            AnyModel::Painleve(m) => trajectory(m, &scene, steps),
            AnyModel::Declared(m) => trajectory(m, &scene, steps),
        };
        assert_eq!(any.len(), 2 * steps * (1 + 2 * scene.build().unwrap().initial_state().0.len()));
        assert!(any == concrete, "{kind}");
    }
}

#[test]
fn the_observer_of_a_scene_built_stepper_sees_the_scene_built_model() {
    struct Kinds(Vec<ModelKind>, Vec<u64>);
    impl moreau_stepper::Observer<AnyModel> for Kinds {
        fn observe(
            &mut self,
            model: &AnyModel,
            r: &moreau_stepper::StepReport<'_>,
        ) -> std::ops::ControlFlow<()> {
            self.0.push(model.kind());
            self.1.extend(r.q.iter().chain(r.u).map(|v| v.to_bits()));
            std::ops::ControlFlow::Continue(())
        }
    }
    let mut scene = Scene::report(ModelKind::Woodpecker);
    scene.t_end = 3000.0 * scene.dt;
    let mut stepper = scene.stepper().unwrap();
    let mut by_stepper = Kinds(Vec::new(), Vec::new());
    stepper.run_until(scene.t_end, &mut by_stepper).unwrap();
    assert_eq!(by_stepper.0, vec![ModelKind::Woodpecker; 3000]);
    // `Scene::run_with` steps the woodpecker's own type and shows the observer the
    // scene-built model, with the same steps.
    let mut by_scene = Kinds(Vec::new(), Vec::new());
    let summary = scene.run_with(&mut by_scene).unwrap();
    assert_eq!(summary.steps, 3000);
    assert_eq!(by_scene.0, by_stepper.0);
    assert!(by_scene.1 == by_stepper.1);
}
