//! Repeated solves of the same size do not allocate: a counting global allocator.
#![allow(unsafe_code)]

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use common::{Rng, friction, planted, random_spd};
use moreau_lcp::{Auto, Lcp, Lemke, Pgs, Solution, Solver};

struct Counting;

thread_local! {
    // Per thread, because the test harness runs other tests on other threads. A const
    // initialiser without destructor: using it never allocates.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn bump() {
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

// SAFETY: every call is forwarded unchanged to the system allocator; the counter is a
// thread-local cell that does not allocate.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        bump();
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        bump();
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations made by `f` on this thread.
fn allocations(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    f();
    ALLOCATIONS.with(Cell::get) - before
}

fn check(solver: &mut dyn Solver, problems: &[Lcp], warm: bool) {
    let mut out = Solution::new();
    let warm_start = vec![0.5; problems[0].n()];
    let ws = warm.then_some(warm_start.as_slice());
    // Warm-up: the first solve sizes the workspace and the solution.
    solver.solve_into(problems[0].view(), ws, &mut out).unwrap();
    assert!(out.is_solved());
    let count = allocations(|| {
        for p in problems {
            solver.solve_into(p.view(), ws, &mut out).unwrap();
            assert!(out.is_solved());
        }
    });
    assert_eq!(count, 0, "{count} allocations in {} solves", problems.len());
}

#[test]
fn lemke_nine_by_nine_does_not_allocate() {
    let mut rng = Rng::new(31);
    let friction_problems: Vec<Lcp> = (0..20)
        .map(|_| friction(3, 5, &mut rng).lcp)
        .filter(|lcp| Lemke::default().solve(lcp).is_ok_and(|s| s.is_solved()))
        .collect();
    assert!(friction_problems.len() >= 15);
    check(&mut Lemke::default(), &friction_problems, false);
    let spd: Vec<Lcp> =
        (0..20).map(|_| planted(random_spd(9, &mut rng), &mut rng, false).0).collect();
    check(&mut Lemke::default(), &spd, false);
    check(&mut Auto::default(), &friction_problems, false);
}

#[test]
fn pgs_nine_by_nine_does_not_allocate() {
    let mut rng = Rng::new(32);
    let spd: Vec<Lcp> =
        (0..20).map(|_| planted(random_spd(9, &mut rng), &mut rng, false).0).collect();
    check(&mut Pgs::default(), &spd, false);
    check(&mut Pgs::default(), &spd, true);
}

#[test]
fn larger_lemke_solves_do_not_allocate() {
    // n = 40 uses faer's LU for the final basis: its stack is also reused.
    let mut rng = Rng::new(33);
    let spd: Vec<Lcp> =
        (0..5).map(|_| planted(random_spd(40, &mut rng), &mut rng, false).0).collect();
    check(&mut Lemke::default(), &spd, false);
}

#[test]
fn the_counter_sees_allocations() {
    let count = allocations(|| {
        let v: Vec<u64> = std::hint::black_box(vec![1, 2, 3]);
        assert_eq!(v.len(), 3);
    });
    assert!(count >= 1);
}
