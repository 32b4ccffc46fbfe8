//! A scene continued from the end of its run (`Scene::continued`) continues that run: a report
//! model and a declared mechanism (a motor-driven linkage with a clearance joint, a pyramid of
//! generated boxes on detected contacts) run in two halves against one run of the whole, and
//! the start time a driven mechanism needs.

use moreau_models::{ModelError, ModelKind, Scene};
use moreau_stepper::Impulses;

fn scene_file(name: &str) -> Scene {
    let path = format!("{}/../../scenes/{name}", env!("CARGO_MANIFEST_DIR"));
    Scene::from_path(std::path::Path::new(&path)).expect("a valid scene")
}

/// The end state (t, q, u) of a run of `scene`.
fn end(scene: &Scene) -> (f64, Vec<f64>, Vec<f64>) {
    let (t, q, u, _) = end_with_impulses(scene);
    (t, q, u)
}

/// The end state (t, q, u) of a run of `scene` and the impulses of its last step.
fn end_with_impulses(scene: &Scene) -> (f64, Vec<f64>, Vec<f64>, Option<Impulses>) {
    let run = scene.run().expect("the run succeeds");
    let last = run.record.len() - 1;
    let (t, q, u) = (run.record.t[last], &run.record.q[last], &run.record.u[last]);
    (t, q.to_vec(), u.to_vec(), run.impulses)
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// `scene` run to `half` and continued to `2 half` (with the impulses of the first half's
/// last step, or from zero impulses), against one run to `2 half`: the end states' largest
/// difference in q and in u.
fn halves(mut scene: Scene, half: f64, warm: bool) -> (Scene, f64, f64) {
    scene.t_end = half;
    let (t, q, u, impulses) = end_with_impulses(&scene);
    assert!((t - half).abs() < 1e-12, "ends at {t}");
    let impulses = impulses.filter(|_| warm);
    let next = scene.continued(t, &q, &u, impulses).expect("continued");
    assert_eq!((next.t_start, next.t_end), (t, t + half));
    // The continued scene is a scene file like any other.
    let text = next.to_toml_string().unwrap();
    assert_eq!(Scene::from_toml_str(&text).expect("reads back"), next, "{text}");
    let (t2, q2, u2) = end(&next);
    scene.t_end = 2.0 * half;
    let (t1, q1, u1) = end(&scene);
    assert!((t1 - t2).abs() < 1e-12, "{t1} against {t2}");
    (next, max_diff(&q1, &q2), max_diff(&u1, &u2))
}

#[test]
fn a_report_model_continues_its_run() {
    // The ball falls freely for 0.3 s, then 0.3 s more, through its impact at 0.4285 s.
    let (_, dq, du) = halves(Scene::report(ModelKind::Ball), 0.3, true);
    assert!(dq <= 1e-13 && du <= 1e-12, "ball: {dq:e}, {du:e}");
    // The woodpecker's sleeve and bird swing and strike the pole in either half.
    let (_, dq, du) = halves(Scene::report(ModelKind::Woodpecker), 0.05, true);
    assert!(dq <= 1e-12 && du <= 1e-9, "woodpecker: {dq:e}, {du:e}");
}

#[test]
fn a_driven_mechanism_continues_at_its_start_time() {
    // The cam turns with time: its continued scene starts at 0.03 s, where the first half
    // ended, and follows the run of the whole to round-off.
    let (next, dq, du) = halves(Scene::report(ModelKind::Cam), 0.03, true);
    assert!(dq <= 1e-12 && du <= 1e-9, "cam: {dq:e}, {du:e}");
    // The same state taken as the state at t = 0 meets the cam where it was 0.03 s earlier,
    // 0.63 rad back: another run altogether.
    let wrong = Scene { t_start: 0.0, t_end: 0.03, ..next.clone() };
    let (_, q_wrong, _) = end(&wrong);
    let (_, q_right, _) = end(&next);
    let apart = max_diff(&q_wrong, &q_right);
    assert!(apart > 1e-4, "the start time changes the run by {apart:e} m only");
}

#[test]
fn a_linkage_with_a_motor_and_a_clearance_joint_continues_its_run() {
    // The crank turns at 2π rad/s by its motor, θ_crank − angle − Ω t = 0: the continued
    // scene writes the motor's reference angle out and starts at t = 0.05 s, where the
    // crank has turned by 0.1π.
    let scene = scene_file("bodies/four-bar-clearance.toml");
    let (next, dq, du) = halves(scene, 0.05, true);
    // The pin's impacts in its bearing amplify round-off: stepped side by side, the two runs
    // agree to 1.2e-15 m over the first 100 steps and part to 1e-8 m by step 150.
    assert!(dq <= 1e-7 && du <= 3e-5, "four-bar: {dq:e}, {du:e}");
    let mut whole = scene_file("bodies/four-bar-clearance.toml");
    whole.t_end = 0.1;
    let mut straight = whole.stepper().expect("a stepper");
    for _ in 0..500 {
        straight.step().expect("a step");
    }
    let (t, q, u) = (straight.t(), straight.q().to_vec(), straight.u().to_vec());
    let mut continued =
        whole.continued(t, &q, &u, None).expect("continued").stepper().expect("a stepper");
    for k in 0..100 {
        straight.step().expect("a step");
        continued.step().expect("a step");
        let apart =
            max_diff(straight.q(), continued.q()).max(max_diff(straight.u(), continued.u()));
        assert!(apart <= 1e-13, "step {k}: {apart:e}");
    }
    let text = next.to_toml_string().unwrap();
    let doc: toml::Table = toml::from_str(&text).expect("TOML");
    assert_eq!(doc["t_start"].as_float(), Some(0.05), "{text}");
    let motor = doc["joints"]
        .as_array()
        .and_then(|j| j.iter().find(|j| j["name"].as_str() == Some("motor")));
    // The relative angle at t = 0, written out: the crank's, 0.
    assert_eq!(
        motor.and_then(|m| m.get("angle")).and_then(toml::Value::as_float),
        Some(0.0),
        "{text}"
    );
    // Started at t = 0 instead, the motor would ask for the crank at angle 0, 0.1π from
    // where it is: assembly refuses to move it that far.
    let e = Scene { t_start: 0.0, t_end: 0.05, ..next }.build().unwrap_err();
    assert!(e.to_string().contains("correct the position or the joint's anchors"), "{e}");
}

#[test]
fn joint_impulses_follow_their_rows_when_joints_are_listed_in_another_order() {
    // The four-bar's joints' impulses are written by row name; read back with the motor
    // listed first, each row keeps its own impulse, at its new place.
    let mut scene = scene_file("bodies/four-bar-clearance.toml");
    scene.t_end = 0.05;
    let (t, q, u, impulses) = end_with_impulses(&scene);
    let next = scene.continued(t, &q, &u, impulses).expect("continued");
    let text = next.to_toml_string().unwrap();
    assert!(text.contains("joints = [\n    [\"A.Lx\", "), "{text}");
    let mut doc: toml::Table = toml::from_str(&text).unwrap();
    let joints = doc.get_mut("joints").and_then(toml::Value::as_array_mut).unwrap();
    let motor = joints.iter().position(|j| j["name"].as_str() == Some("motor")).unwrap();
    let m = joints.remove(motor);
    joints.insert(0, m);
    let turned = Scene::from_toml_str(&toml::to_string(&doc).unwrap()).expect("reads");
    let rows = |s: &Scene| {
        let Ok(moreau_models::AnyModel::Declared(mb)) = s.build() else { panic!("declared") };
        let values = &s.impulses.as_ref().expect("impulses").joints;
        let mut named: Vec<(String, f64)> =
            mb.bilateral_names().into_iter().zip(values.iter().copied()).collect();
        named.sort_by(|a, b| a.0.cmp(&b.0));
        (mb.bilateral_names(), named)
    };
    let ((order, before), (turned_order, after)) = (rows(&next), rows(&turned));
    assert_ne!(order, turned_order, "the rows moved");
    assert_eq!(before, after);
    assert!(before.iter().any(|(_, l)| *l != 0.0), "{before:?}");
    // A row the mechanism does not have is refused, naming the entry.
    let bad = text.replacen("[\"A.Lx\", ", "[\"A.Lz\", ", 1);
    let e = Scene::from_toml_str(&bad).unwrap_err();
    assert!(matches!(&e, ModelError::BadValue { key, .. } if key == "impulses.joints.0"), "{e:?}");
}

#[test]
fn generated_bodies_become_declared_ones_and_continue_their_run() {
    // A pyramid of 6 boxes (base 3) dropped 2 mm onto the floor, on detected contacts solved
    // by Gauss-Seidel to 1e-10: the halves differ by the second half's first solve, which
    // starts without the reactions of the step before.
    let mut scene = scene_file("scale/pyramid.toml");
    scene.set("fill.box.base", "3").expect("base 3");
    scene.record_every = 1;
    let (_, dq, du) = halves(scene.clone(), 0.2, false);
    assert!(dq <= 1e-9 && du <= 1e-7, "pyramid, cold: {dq:e}, {du:e}");
    assert!(dq > 0.0, "cold, the first solve finds other bits");
    let (next, dq, du) = halves(scene, 0.2, true);
    assert!(dq == 0.0 && du == 0.0, "pyramid, warm: {dq:e}, {du:e}");
    let text = next.to_toml_string().unwrap();
    assert!(!text.contains("[[fill]]"), "{text}");
    let boxes = (0..6).filter(|k| text.contains(&format!("name = \"box{k}\""))).count();
    assert_eq!(boxes, 6, "{text}");
    // The impulses come last, each contact on a line of its own, named by its two shapes
    // and its feature: (name, P_N, P_T). The floor is the first body, box0 its first box.
    let impulses = next.impulses.as_ref().expect("the last step's impulses");
    let tail = &text[text.find("\n[impulses]\ncontacts = [\n").expect("the table")..];
    let rows: Vec<&str> = tail.lines().filter(|l| l.starts_with("    [")).collect();
    assert_eq!(rows.len(), impulses.contacts.len(), "{tail}");
    assert!(rows.len() >= 6, "the boxes rest on the floor and on each other: {tail}");
    let (_, p_n, p_t) = impulses.contacts[0];
    assert_eq!(rows[0], format!("    [\"floor.0/box0.0/0\", {p_n:?}, {p_t:?}],"), "{tail}");
}

/// The pyramid of six boxes settled for 0.2 s, as the scene continued from there.
fn settled_pyramid() -> Scene {
    let mut scene = scene_file("scale/pyramid.toml");
    scene.set("fill.box.base", "3").expect("base 3");
    scene.t_end = 0.2;
    let (t, q, u, impulses) = end_with_impulses(&scene);
    scene.continued(t, &q, &u, impulses).expect("continued")
}

/// `text` with `edit` applied to its list of bodies, read as a scene.
fn with_bodies(text: &str, edit: impl FnOnce(&mut Vec<toml::Value>)) -> Result<Scene, ModelError> {
    let mut doc: toml::Table = toml::from_str(text).expect("TOML");
    edit(doc.get_mut("bodies").and_then(toml::Value::as_array_mut).expect("bodies"));
    Scene::from_toml_str(&toml::to_string(&doc).expect("TOML"))
}

#[test]
fn impulses_follow_their_contacts_when_a_body_comes_before_the_others() {
    // A fixed marker far from the pyramid declared first moves every shape one place on in
    // the list of colliders, and so every contact's identity. The file names the contacts by
    // their shapes: the continued run is the same to the bit with and without the marker.
    let next = settled_pyramid();
    let text = next.to_toml_string().unwrap();
    let marker: toml::Value = toml::from_str::<toml::Table>(
        "name = 'marker'\ntype = 'fixed'\nposition = [100.0, 100.0]\n\
         shapes = [{ type = 'disk', center = [0.0, 0.0], radius = 0.01 }]",
    )
    .unwrap()
    .into();
    let edited = with_bodies(&text, |b| b.insert(0, marker.clone())).expect("reads");
    assert_ne!(edited.impulses, next.impulses, "the identities moved");
    let (_, q1, u1) = end(&next);
    let (_, q2, u2) = end(&edited);
    assert!(q1 == q2 && u1 == u2, "{:e}, {:e}", max_diff(&q1, &q2), max_diff(&u1, &u2));
    // The same file with the impulses by identity, as the scene keeps them in memory, starts
    // the marked pyramid's contacts from other contacts' impulses, and its run departs.
    let by_id = toml::to_string(&next).expect("TOML");
    assert!(by_id.contains("impulses"), "{by_id}");
    let mislabelled = with_bodies(&by_id, |b| b.insert(0, marker)).expect("reads");
    let (_, q3, u3) = end(&mislabelled);
    assert!(max_diff(&q1, &q3) > 0.0 || max_diff(&u1, &u3) > 0.0, "the test can tell");
}

#[test]
fn impulses_follow_their_contacts_through_a_change_that_adds_a_shape() {
    // A second shape on the floor, declared first, far from the pyramid: `Scene::set`
    // renumbers every box's contacts, and the impulses follow them by name, so that the
    // continued run is the same to the bit.
    let next = settled_pyramid();
    let mut edited = next.clone();
    let shapes = "[{ type = 'half_plane', point = [0.0, 0.0], normal = [0.0, 1.0] }, \
                  { type = 'disk', center = [100.0, 100.0], radius = 0.01 }]";
    edited.set("bodies.floor.shapes", shapes).expect("two shapes");
    assert_ne!(edited.impulses, next.impulses, "the identities moved");
    let (a, b) = (next.impulses.as_ref().unwrap(), edited.impulses.as_ref().unwrap());
    assert_eq!(a.contacts.len(), b.contacts.len());
    let (_, q1, u1) = end(&next);
    let (_, q2, u2) = end(&edited);
    assert!(q1 == q2 && u1 == u2, "{:e}, {:e}", max_diff(&q1, &q2), max_diff(&u1, &u2));
    // A change that removes the boxes' floor leaves impulses whose contact is gone.
    let mut gone = next.clone();
    let e = gone.set("bodies.floor.shapes", "[]").unwrap_err();
    assert!(e.to_string().contains("impulses.contacts."), "{e}");
}

#[test]
fn impulses_that_name_a_body_gone_or_turned_round_are_refused() {
    let text = settled_pyramid().to_toml_string().unwrap();
    let name = |b: &toml::Value| b["name"].as_str().unwrap_or("").to_owned();
    // box5 rests on box3 and box4: its contacts' lines remain.
    let e = with_bodies(&text, |b| b.retain(|b| name(b) != "box5")).unwrap_err();
    assert!(
        matches!(&e, ModelError::BadValue { key, .. } if key.starts_with("impulses.contacts."))
    );
    assert!(e.to_string().contains("names the body `box5`, which the scene does not have"), "{e}");
    // box3, which rests on box0, declared before it: the pair's feature would number the
    // points the other way round. (box0 and box1 stand apart: swapped, they still read.)
    let swap = |x: &str, y: &str| {
        with_bodies(&text, |b| {
            let at = |n: &str| b.iter().position(|b| name(b) == n).unwrap();
            let (i, j) = (at(x), at(y));
            b.swap(i, j);
        })
    };
    swap("box0", "box1").expect("no pair turns round");
    let e = swap("box0", "box3").unwrap_err();
    assert!(e.to_string().contains("which the scene now declares after"), "{e}");
    // A name that is not a contact's.
    let bad = text.replacen("\"floor.0/box0.0/0\"", "\"floor/box0.0/0\"", 1);
    let e = Scene::from_toml_str(&bad).unwrap_err();
    assert!(e.to_string().contains("is not a detected contact's name"), "{e}");
}

#[test]
fn a_scene_that_toml_cannot_hold_is_a_typed_error() {
    // TOML's integers stop at 2⁶³ − 1; a contact identity above it cannot be written.
    let scene = Scene {
        impulses: Some(Impulses { contacts: vec![(u64::MAX, 1.0, 0.0)], joints: vec![] }),
        ..Scene::report(ModelKind::Ball)
    };
    let e = scene.to_toml_string().unwrap_err();
    assert!(matches!(e, ModelError::Unwritable { .. }), "{e:?}");
    assert!(e.to_string().starts_with("the scene cannot be written as TOML"), "{e}");
    // One below the limit is written and read back.
    let largest = Scene {
        impulses: Some(Impulses { contacts: vec![(i64::MAX as u64, 1.0, 0.0)], joints: vec![] }),
        ..scene
    };
    let text = largest.to_toml_string().unwrap();
    assert_eq!(Scene::from_toml_str(&text).unwrap(), largest, "{text}");
}

#[test]
fn a_state_of_another_mechanism_is_refused() {
    let scene = Scene::report(ModelKind::Woodpecker);
    let e = scene.continued(0.1, &[0.0; 2], &[0.0; 3], None).unwrap_err();
    assert!(matches!(&e, ModelError::BadValue { key, .. } if key == "q"), "{e:?}");
    assert!(e.to_string().contains("has 2 entries; the model has 3 coordinates"), "{e}");
    let e = scene.continued(0.1, &[0.0; 3], &[0.0, f64::NAN, 0.0], None).unwrap_err();
    assert!(e.to_string().contains("entry 1 is not finite"), "{e}");
    // A start after the end is refused by the scene's own check.
    let late = Scene { t_start: 2.0, ..scene };
    let e = late.validate().unwrap_err();
    assert!(e.to_string().contains("t_end") && e.to_string().contains(">= t_start = 2"), "{e}");
}

#[test]
fn a_stop_rule_the_run_has_met_gives_way_to_a_run_as_long() {
    // Painlevé's rod stops when it lies flat (phi = 0), after 0.669 s.
    let scene = Scene::report(ModelKind::Painleve);
    let (t, q, u, impulses) = end_with_impulses(&scene);
    assert!(t > 0.1 && t < 1.5 && q[2] <= 0.0, "flat at {t}: {q:?}");
    let next = scene.continued(t, &q, &u, impulses.clone()).expect("continued");
    assert_eq!((next.stop_at.as_ref(), next.t_end), (None, 2.0 * t), "{next:?}");
    let (t2, _, _) = end(&next);
    assert!((t2 - 2.0 * t).abs() < 1e-12, "the continued run ends at {t2}");
    // Halfway, the rule is still ahead and kept, with the scene's bound on the run.
    let half = Scene { t_end: 0.1, ..scene.clone() };
    let (t, q, u, impulses) = end_with_impulses(&half);
    let next = half.continued(t, &q, &u, impulses).expect("continued");
    assert_eq!((next.stop_at, next.t_end), (scene.stop_at, 0.2));
}
