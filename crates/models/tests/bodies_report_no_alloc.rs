//! Once warm, the declared woodpecker and slider-crank (`scenes/bodies/`) step without touching
//! the heap, counted per thread.
#![allow(unsafe_code)] // A counting global allocator needs `unsafe impl GlobalAlloc`.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use moreau_models::Scene;

struct Counting;

thread_local! {
    /// Allocations made by this thread (the harness allocates on its own threads).
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Steps the scene for `warm` seconds, then counts the allocations and the closed contacts of
/// the steps up to `until`.
fn allocations(text: &str, warm: f64, until: f64) -> (usize, usize) {
    let scene = Scene::from_toml_str(text).unwrap();
    let mut stepper = scene.stepper().unwrap();
    while stepper.t() < warm {
        stepper.step().unwrap();
    }
    let before = ALLOCATIONS.with(Cell::get);
    let mut closed = 0;
    while stepper.t() < until {
        let report = stepper.step().unwrap();
        closed += report.contacts.iter().filter(|c| c.active).count();
    }
    (ALLOCATIONS.with(Cell::get) - before, closed)
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
