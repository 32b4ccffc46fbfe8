//! Once warm, the declared woodpecker and slider-crank (`scenes/bodies/`) step without touching
//! the heap, counted per thread.

use moreau_models::Scene;
use moreau_testsupport::{CountingAllocator, allocations_in};

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

/// Steps the scene for `warm` seconds, then counts the allocations and the closed contacts of
/// the steps up to `until`.
fn allocations(text: &str, warm: f64, until: f64) -> (usize, usize) {
    let scene = Scene::from_toml_str(text).unwrap();
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
