//! `process` and `finish` never allocate, at any rate and block size: a counting global
//! allocator watches the thread while the analyzer runs.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use pneuma_core::synth;
use pneuma_core::{AnalysisConfig, Analyzer};

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

fn watched<R>(f: impl FnOnce() -> R) -> (R, usize) {
    COUNT.with(|c| c.set(0));
    WATCH.with(|w| w.set(true));
    let r = f();
    WATCH.with(|w| w.set(false));
    (r, COUNT.with(|c| c.get()))
}

#[test]
fn the_counter_sees_allocations() {
    let (_, n) = watched(|| vec![1u8; 100]);
    assert!(n >= 1);
}

#[test]
fn process_never_allocates() {
    for rate in [8_000.0, 22_050.0, 44_100.0, 48_000.0, 192_000.0] {
        let mut x = synth::harmonic_tone(rate, 1.0, 0.5, &[1.0, 0.5, 0.3], |t| 100.0 + 200.0 * t);
        x[1000] = f32::NAN;
        let mut a = Analyzer::new(AnalysisConfig::default()).expect("config");
        a.prepare(rate, 4096).expect("rate");
        let mut frames = 0usize;
        let ((), n) = watched(|| {
            for (i, size) in [1usize, 37, 512, 4096].iter().cycle().enumerate() {
                let start = (i * 1000) % (x.len() - 4096);
                a.process(&x[start..start + size], |_| frames += 1)
                    .expect("prepared");
                if i > 200 {
                    break;
                }
            }
            a.finish(|_| frames += 1).expect("prepared");
            a.reset();
        });
        assert!(frames > 10);
        assert_eq!(n, 0, "{n} allocations at {rate} Hz");
    }
}
