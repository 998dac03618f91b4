//! A counting global allocator for the tests that check the heap: live bytes and allocation
//! calls, per thread (tests run in parallel). Included with `#[path]` by the test files that
//! need it (`tests/event_log.rs`, `tests/hot_loop_alloc.rs`), so it is the global allocator of
//! those test binaries only.
#![allow(dead_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// Forwards to the system allocator, counting live bytes, their peak and allocation calls.
pub struct LiveAlloc;

thread_local! {
    /// Live heap bytes of this thread (allocated minus freed).
    pub static LIVE: Cell<isize> = const { Cell::new(0) };
    /// Peak of [`LIVE`] since [`peak_of`] last reset it.
    pub static PEAK: Cell<isize> = const { Cell::new(0) };
    /// Allocation calls (alloc, alloc_zeroed, realloc) of this thread.
    pub static CALLS: Cell<u64> = const { Cell::new(0) };
}

/// Counts an allocation call (alloc, alloc_zeroed or realloc) of this thread.
fn call() {
    let _ = CALLS.try_with(|c| c.set(c.get() + 1));
}

fn add(delta: isize) {
    let _ = LIVE.try_with(|l| {
        let now = l.get() + delta;
        l.set(now);
        let _ = PEAK.try_with(|p| p.set(p.get().max(now)));
    });
}

// SAFETY: every method forwards to the system allocator with the caller's arguments unchanged;
// the extra work is thread-local `Cell` updates, which do not allocate.
unsafe impl GlobalAlloc for LiveAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        call();
        add(layout.size() as isize);
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        call();
        add(layout.size() as isize);
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        call();
        add(new_size as isize - layout.size() as isize);
        System.realloc(ptr, layout, new_size)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        add(-(layout.size() as isize));
        System.dealloc(ptr, layout)
    }
}

#[global_allocator]
static ALLOC: LiveAlloc = LiveAlloc;

/// Peak live heap bytes of this thread while `f` runs, above what was live when it started.
pub fn peak_of<R>(f: impl FnOnce() -> R) -> (R, usize) {
    let base = LIVE.with(|l| l.get());
    PEAK.with(|p| p.set(base));
    let r = f();
    let peak = PEAK.with(|p| p.get()) - base;
    (r, peak.max(0) as usize)
}

/// Allocation calls of this thread while `f` runs, and its result.
pub fn calls_of<R>(f: impl FnOnce() -> R) -> (R, u64) {
    let before = CALLS.with(|c| c.get());
    let r = f();
    (r, CALLS.with(|c| c.get()) - before)
}
