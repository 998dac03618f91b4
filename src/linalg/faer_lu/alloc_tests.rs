//! The counting-allocator proof of "no allocation after `pattern`" (see the parent's docs).

use super::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct CountingAlloc;

thread_local! {
    static ALLOCS: Cell<usize> = const { Cell::new(0) };
}

fn bump() {
    // `try_with` because the allocator may run during thread-local teardown.
    let _ = ALLOCS.try_with(|n| n.set(n.get() + 1));
}

// SAFETY: forwards every call unchanged to the system allocator.
unsafe impl GlobalAlloc for CountingAlloc {
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
static GLOBAL: CountingAlloc = CountingAlloc;

fn allocs() -> usize {
    ALLOCS.with(|n| n.get())
}

#[test]
fn factorize_and_solve_do_not_allocate_after_pattern() {
    let mut rng = ChaCha8Rng::seed_from_u64(15);
    for m in [1usize, 2, 3, 10, 1000] {
        let mut s = FaerLu::<f64>::new();
        let before = allocs();
        s.pattern(m);
        // The counter works: `pattern` allocates (CSC arrays, symbolic, scratch).
        assert!(allocs() > before, "m={m}: counting allocator saw nothing");
        let mut b = vec![0.0; m];
        let mut n_ok = 0;
        for _ in 0..50 {
            // Indefinite random matrices: many row interchanges, worst-case fill.
            let d: Vec<f64> = (0..m).map(|_| rng.random_range(-3.0..3.0)).collect();
            let e: Vec<f64> = (0..m - 1).map(|_| rng.random_range(-3.0..3.0)).collect();
            b.fill(1.0);
            let before = allocs();
            if s.factorize(&d, &e).is_ok() {
                s.solve_in_place(&mut b);
                n_ok += 1;
            }
            assert_eq!(allocs() - before, 0, "m={m}: factorize/solve allocated");
        }
        assert!(
            n_ok > 40,
            "m={m}: only {n_ok}/50 random matrices factorized"
        );
        // Fill stays tridiagonal-LU-like: L ≤ 2m, U ≤ 3m entries.
        let nnz = s.lu.l_factor_unsorted().compute_nnz() + s.lu.u_factor_unsorted().compute_nnz();
        assert!(nnz <= 5 * m, "m={m}: nnz(L)+nnz(U) = {nnz}");
    }
}
