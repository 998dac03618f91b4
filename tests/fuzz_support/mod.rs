//! Shared machinery of `tests/fuzz_scenes.rs` and `tests/fuzz_snapshots.rs`: the seeded,
//! time-boxed proptest driver and an
//! allocation probe (a counting global allocator, per thread).
//!
//! Environment:
//! - `BEADCHAIN_FUZZ_CASES`: cases per target, default [`DEFAULT_CASES`]; `large` runs batches
//!   of [`BATCH`] cases until `BEADCHAIN_FUZZ_SECONDS` (default 330) have passed per target.
//! - `BEADCHAIN_FUZZ_SEED`: base seed (u64, default [`DEFAULT_SEED`]). Batch `b` of a target
//!   uses the 32-byte ChaCha seed `(base + b, target tag)`, so every run is reproducible and a
//!   failure message names the batch seed to replay it with.
#![allow(dead_code)]

use proptest::strategy::Strategy;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::fmt::Debug;
use std::time::{Duration, Instant};

/// Cases per target when `BEADCHAIN_FUZZ_CASES` is unset (keeps CI fast).
pub const DEFAULT_CASES: u64 = 200;
/// Cases per batch in time-boxed (`large`) mode.
pub const BATCH: u64 = 2000;
/// Base seed when `BEADCHAIN_FUZZ_SEED` is unset.
pub const DEFAULT_SEED: u64 = 0x5EED_BEAD;

/// How much fuzzing to do, from the environment.
#[derive(Clone, Copy, Debug)]
pub enum Budget {
    /// Exactly this many cases (one batch).
    Cases(u64),
    /// Batches of [`BATCH`] cases until this much time has passed.
    Time(Duration),
}

/// Reads `BEADCHAIN_FUZZ_CASES` / `BEADCHAIN_FUZZ_SECONDS`.
pub fn budget() -> Budget {
    match std::env::var("BEADCHAIN_FUZZ_CASES") {
        Ok(s) if s.trim() == "large" => {
            let secs = std::env::var("BEADCHAIN_FUZZ_SECONDS")
                .ok()
                .and_then(|s| s.trim().parse::<u64>().ok())
                .unwrap_or(330);
            Budget::Time(Duration::from_secs(secs))
        }
        Ok(s) => Budget::Cases(s.trim().parse().unwrap_or(DEFAULT_CASES)),
        Err(_) => Budget::Cases(DEFAULT_CASES),
    }
}

/// Reads `BEADCHAIN_FUZZ_SEED`.
pub fn base_seed() -> u64 {
    std::env::var("BEADCHAIN_FUZZ_SEED")
        .ok()
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or(DEFAULT_SEED)
}

/// Runs `test` on values of `strategy` under the budget; panics with the (shrunk) failing
/// input and the batch seed on the first failure. Returns the number of cases run.
pub fn fuzz<S, F>(target: &str, strategy: S, test: F) -> u64
where
    S: Strategy,
    S::Value: Debug,
    F: Fn(S::Value) -> Result<(), TestCaseError>,
{
    let start = Instant::now();
    let budget = budget();
    let tag = target.bytes().fold(0u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    });
    let mut total = 0u64;
    let mut batch = 0u64;
    loop {
        let cases = match budget {
            Budget::Cases(n) => n,
            Budget::Time(_) => BATCH,
        };
        let seed = base_seed().wrapping_add(batch);
        let mut bytes = [0u8; 32];
        bytes[..8].copy_from_slice(&seed.to_le_bytes());
        bytes[8..16].copy_from_slice(&tag.to_le_bytes());
        let config = Config {
            cases: u32::try_from(cases).unwrap_or(u32::MAX),
            failure_persistence: None,
            rng_algorithm: RngAlgorithm::ChaCha,
            max_shrink_iters: 2000,
            ..Config::default()
        };
        let mut runner =
            TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &bytes));
        if let Err(e) = runner.run(&strategy, &test) {
            panic!(
                "{target}: fuzz failure in batch {batch} (BEADCHAIN_FUZZ_SEED={seed} replays it \
                 as batch 0): {e}"
            );
        }
        total += cases;
        batch += 1;
        match budget {
            Budget::Cases(_) => break,
            Budget::Time(d) if start.elapsed() >= d => break,
            Budget::Time(_) => {}
        }
    }
    println!(
        "fuzz {target}: {total} cases in {} batches, {:.1} s ({:.0} cases/s)",
        batch,
        start.elapsed().as_secs_f64(),
        total as f64 / start.elapsed().as_secs_f64().max(1e-9)
    );
    total
}

/// Global allocator that records, per thread, the largest single allocation requested.
pub struct CountingAlloc;

thread_local! {
    static LARGEST: Cell<usize> = const { Cell::new(0) };
}

fn note(size: usize) {
    // `try_with`: the slot may be gone while a thread is being torn down.
    let _ = LARGEST.try_with(|c| {
        if size > c.get() {
            c.set(size);
        }
    });
}

// SAFETY: every method forwards to the system allocator with the caller's arguments unchanged;
// the only extra work is a thread-local `Cell` update, which does not allocate.
unsafe impl GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note(layout.size());
        System.alloc_zeroed(layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note(new_size);
        System.realloc(ptr, layout, new_size)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
}

/// Resets this thread's largest-allocation record and returns the previous value.
pub fn reset_largest_alloc() -> usize {
    LARGEST.with(|c| c.replace(0))
}

/// Largest single allocation on this thread since the last reset (bytes).
pub fn largest_alloc() -> usize {
    LARGEST.with(|c| c.get())
}
