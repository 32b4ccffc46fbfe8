//! A counting global allocator for the tests that assert a hot path does not touch the heap.
//!
//! A test binary installs it with
//! `#[global_allocator] static GLOBAL: CountingAllocator = CountingAllocator;` and measures a
//! closure with [`allocations_in`]. The count is kept per thread, because the test harness
//! allocates on its own threads (for instance to report a test that runs long on a loaded
//! machine), which says nothing about the code under test. Allocations and reallocations count;
//! deallocations do not, since freeing memory that was counted when it was taken adds no cost of
//! its own to a loop.
//!
//! This is the one place outside the LCP's kernel module that may write `unsafe`: implementing
//! [`GlobalAlloc`] is an unsafe trait, and every call is passed on unchanged to [`System`].
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

thread_local! {
    // A const initialiser without a destructor: reading or bumping the counter never
    // allocates, so the allocator can use it without recursing into itself.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn record_allocation() {
    // `try_with` because the allocator is still called while thread-locals are torn down.
    let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
}

/// The system allocator, with a per-thread count of allocations and reallocations.
///
/// Install it as the test binary's `#[global_allocator]`; [`allocations_in`] then reports what
/// a closure allocated on the calling thread.
#[derive(Clone, Copy, Debug, Default)]
pub struct CountingAllocator;

// SAFETY: every call is forwarded unchanged to the system allocator; the counter only observes
// and is a thread-local cell that does not allocate.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        record_allocation();
        // SAFETY: the caller's layout is passed on as it came, under the same contract.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `System` through this allocator, with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        record_allocation();
        // SAFETY: `ptr` came from `System` through this allocator, with this layout; the new
        // size is the caller's, under the same contract.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// The number of allocations and reallocations that `f` made on the calling thread.
///
/// # Panics
/// If [`CountingAllocator`] is not the binary's global allocator: a probe allocation made
/// before `f` runs must be counted, so that a missing installation cannot make every count
/// read zero.
pub fn allocations_in(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    drop(std::hint::black_box(Box::new(0_u64)));
    let start = ALLOCATIONS.with(Cell::get);
    assert!(
        start > before,
        "CountingAllocator is not installed: declare \
         `#[global_allocator] static GLOBAL: CountingAllocator = CountingAllocator;`"
    );
    f();
    ALLOCATIONS.with(Cell::get) - start
}

#[cfg(test)]
mod tests {
    use super::*;

    #[global_allocator]
    static GLOBAL: CountingAllocator = CountingAllocator;

    #[test]
    fn the_counter_sees_allocations_and_reallocations() {
        assert_eq!(allocations_in(|| ()), 0);
        let n = allocations_in(|| {
            let mut v: Vec<u64> = std::hint::black_box(Vec::with_capacity(1));
            v.push(1);
            // Growing past the capacity reallocates.
            v.extend_from_slice(&[2, 3, 4, 5]);
            assert_eq!(std::hint::black_box(v).len(), 5);
        });
        assert_eq!(n, 2);
    }

    #[test]
    fn allocations_on_another_thread_are_not_counted() {
        let n = allocations_in(|| {
            std::thread::scope(|s| {
                s.spawn(|| std::hint::black_box(vec![0_u8; 64]).len()).join().unwrap();
            });
        });
        // Spawning a thread allocates on this thread (its handle and name); the 64 bytes
        // taken on the other thread do not show up on top of that.
        let spawn_only = allocations_in(|| {
            std::thread::scope(|s| {
                s.spawn(|| 0_usize).join().unwrap();
            });
        });
        assert_eq!(n, spawn_only);
    }
}
