//! Once warm, the declared woodpecker and slider-crank (`scenes/bodies/`) step without touching
//! the heap, counted per thread.

use moreau_models::Scene;
use moreau_testsupport::{CountingAllocator, allocations_in};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// Steps the scene for `warm` seconds, then counts the allocations and the closed contacts of
/// the steps up to `until`.
fn allocations(text: &str, warm: f64, until: f64) -> (usize, usize) {
    counted(Scene::from_toml_str(text).unwrap(), warm, until)
}

/// [`allocations`] of a scene already read.
fn counted(scene: Scene, warm: f64, until: f64) -> (usize, usize) {
    let mut stepper = scene.stepper().unwrap();
    while stepper.t() < warm {
        stepper.step().unwrap();
    }
    let mut closed = 0;
    let n = allocations_in(|| {
        while stepper.t() < until {
            let report = stepper.step().unwrap();
            closed += report.contacts.iter().filter(|c| c.active).count();
        }
    });
    (n, closed)
}

#[test]
fn the_declared_woodpecker_steps_without_allocating() {
    // Two cycles after the first two: impacts of the beak, sticking and slipping edges.
    let (n, closed) = allocations(include_str!("../../../scenes/bodies/woodpecker.toml"), 0.3, 0.6);
    assert!(closed > 100, "{closed} closed contacts");
    assert_eq!(n, 0, "{n} allocations in 3000 steps");
}

#[test]
fn the_declared_slider_crank_steps_without_allocating() {
    // Half a revolution with the slider striking and sliding on the guide's lines.
    let (n, closed) =
        allocations(include_str!("../../../scenes/bodies/slider-crank.toml"), 0.01, 0.04);
    assert!(closed > 100, "{closed} closed contacts");
    assert_eq!(n, 0, "{n} allocations in 3000 steps");
}

#[test]
fn the_declared_cam_and_woodpecker_with_detected_contacts_step_without_allocating() {
    // Detected contacts solved island by island: the cam's follower, whose contact with the
    // turning cam opens and closes from one step to the next (two block structures for
    // Newton, and pivoting for the projection through the guide's rows), and the
    // woodpecker's impacts, with the projection.
    for (text, warm, until, least) in [
        (include_str!("../../../scenes/bodies/cam.toml"), 0.2, 0.3, 200),
        (include_str!("../../../scenes/bodies/woodpecker.toml"), 0.3, 0.6, 100),
    ] {
        let mut scene = Scene::from_toml_str(text).unwrap();
        scene.set("contact_set", "detected").unwrap();
        scene.set("projection", "true").unwrap();
        let (n, closed) = counted(scene, warm, until);
        assert!(closed > least, "{closed} closed contacts");
        assert_eq!(n, 0, "{n} allocations once warm");
    }
}

/// A pendulum (a 1 kg disk of radius 5 cm on a 1 m rod hinged at the origin) hanging against
/// a wall that touches it, pressed onto it by gravity tilted towards the wall, with friction:
/// one resting contact and one joint, the contact detected at every step.
const PENDULUM_PRESSED_ON_A_WALL: &str = r#"
dt = 0.0001
t_end = 1.0
gravity = [2.0, -9.81]
contact_set = "detected"

[[bodies]]
name = "wall"
type = "fixed"
position = [0.0, 0.0]
shapes = [{ type = "half_plane", point = [0.05, 0.0], normal = [-1.0, 0.0] }]

[[bodies]]
name = "bob"
type = "dynamic"
mass = 1.0
inertia = 0.00125
position = [0.0, -1.0]
shapes = [{ type = "disk", center = [0.0, 0.0], radius = 0.05 }]

[[joints]]
type = "revolute"
name = "hinge"
body_a = "ground"
anchor_a = [0.0, 0.0]
body_b = "bob"
anchor_b = [0.0, 1.0]

[contacts_auto]
eps_n = 0.0
eps_t = 0.0
mu = 0.3
"#;

#[test]
fn a_pendulum_pressed_on_a_wall_with_detected_contacts_steps_without_allocating() {
    let (n, closed) = allocations(PENDULUM_PRESSED_ON_A_WALL, 0.01, 0.04);
    assert_eq!(closed, 300, "the contact stays closed at every step");
    assert_eq!(n, 0, "{n} allocations in 300 steps");
}
