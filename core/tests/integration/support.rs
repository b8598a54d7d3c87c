//! Shared by the integration tests that prove "no allocation": a counting global allocator that
//! counts allocations and reallocations on threads that asked to be watched.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use pneuma_core::engine::Engine;

struct Counting;

thread_local! {
    static WATCH: Cell<bool> = const { Cell::new(false) };
    static COUNT: Cell<usize> = const { Cell::new(0) };
}

// SAFETY: defers to the system allocator; only counts calls on a watched thread.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if WATCH.with(|w| w.get()) {
            COUNT.with(|c| c.set(c.get() + 1));
        }
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if WATCH.with(|w| w.get()) {
            COUNT.with(|c| c.set(c.get() + 1));
        }
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// Runs `f` on this thread while counting its allocations; returns its result and the count.
pub fn watched<R>(f: impl FnOnce() -> R) -> (R, usize) {
    COUNT.with(|c| c.set(0));
    WATCH.with(|w| w.set(true));
    let r = f();
    WATCH.with(|w| w.set(false));
    (r, COUNT.with(|c| c.get()))
}

/// Streams `x` (mono) through `engine` in blocks of 1000 samples as a host does, taking the
/// breaths as they finish, then runs `after` on it, all watched: the breaths taken and the
/// allocations made.
pub fn streamed_watched(
    engine: &mut Engine,
    x: &[f32],
    after: impl FnOnce(&mut Engine),
) -> (usize, usize) {
    let mut buf = x.to_vec();
    let mut breaths = 0;
    let ((), n) = watched(|| {
        for chunk in buf.chunks_mut(1000) {
            engine.process(&mut [chunk], &mut |_, _| {});
            engine.take_breaths(|_| breaths += 1);
        }
        after(engine);
    });
    (breaths, n)
}
