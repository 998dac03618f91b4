//! faer sparse LU for the symmetric tridiagonal Newton systems of the Radau reduction
//! (paper appendix, eq. A.3; see [`super`] for the reduction to `(μ² M + h² L(k)) x = r`).
//!
//! Lifecycle (see [`TridiagSolver`]):
//! - [`TridiagSolver::pattern`] builds the tridiagonal CSC sparsity pattern, runs faer's symbolic
//!   analysis ([`factorize_symbolic_lu`], COLAMD column ordering) **once**, allocates the scratch
//!   stack for both numeric factorization and solve, and runs two warm-up numeric factorizations
//!   (one without and one with a row interchange at every step) so that faer's factor storage
//!   already has the capacity that later factorizations need. Called again (a renewed
//!   integrator), it does all this for another size, and for the same size only forgets the
//!   last factorization (what it would build is what it has);
//! - [`TridiagSolver::factorize`] writes `d`, `e` into the existing value array and runs faer's
//!   numeric simplicial LU with partial pivoting, then checks every pivot (`U` diagonal);
//! - [`TridiagSolver::solve_in_place`] applies the row permutation and the two triangular solves
//!   using the preallocated scratch.
//!
//! # Where faer allocates
//! - `factorize_symbolic_lu` allocates its own scratch and the column permutation (only in
//!   `pattern`).
//! - The simplicial numeric LU stores `L`/`U` in `Vec`s that it grows on demand and never shrinks
//!   (`resize_vec` in faer's `sparse/linalg/lu.rs`). After the warm-ups, a factorization only
//!   allocates if its pivot sequence produces more fill than any earlier one (a one-time growth).
//!   Everything else (dense work vector, marks, DFS stack, row permutation) comes from our
//!   [`MemBuffer`] or from buffers reused across calls. A counting-allocator test checks that
//!   `factorize` + `solve_in_place` allocate nothing on random indefinite matrices (heavy
//!   pivoting); the fill stays at `nnz(L) + nnz(U) ≤ 5m` (COLAMD keeps the natural order
//!   almost everywhere on a tridiagonal pattern).
//!
//! # Performance
//! Always slower than [`super::direct::DirectSweep`] on these matrices (3–16×, see
//! [`super::resolve_auto`]): the sweep needs no pivoting, no permutations and no index
//! indirection.
//!
//! # Why the simplicial module directly, not `NumericLu`/`LuRef`
//! [`faer::sparse::linalg::lu::NumericLu`] hides its factors, and faer's partial pivoting accepts
//! a zero (or NaN) pivot without error (it only fails when *no* candidate row exists). To report
//! zero and non-finite pivots as [`SingularMatrix`] we need the `U` diagonal, which
//! [`SimplicialLu::u_factor_unsorted`] exposes. The symbolic side is exactly what
//! `NumericLu` would use: [`factorize_symbolic_lu`] forced to the simplicial variant (a
//! tridiagonal matrix has no dense supernodes), and its column permutation.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::perm::Perm;
use faer::sparse::linalg::lu::simplicial::{
    factorize_simplicial_numeric_lu, factorize_simplicial_numeric_lu_scratch,
    solve_in_place_scratch, SimplicialLu,
};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuSymbolicParams, SymbolicLu};
use faer::sparse::linalg::{LuError, SupernodalThreshold};
use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use faer::traits::ComplexField;
use faer::{Conj, MatMut, Par};

use super::{Scalar, SingularMatrix, TridiagSolver};

/// Row permutation storage: raw buffers while no valid factorization exists, a validated
/// [`Perm`] after a successful one (validation happens once per factorization, not per solve,
/// and moves the buffers without allocating).
#[derive(Debug)]
enum RowPerm {
    Raw(Box<[usize]>, Box<[usize]>),
    Valid(Perm<usize>),
}

impl RowPerm {
    fn take_arrays(&mut self) -> (Box<[usize]>, Box<[usize]>) {
        let empty = RowPerm::Raw(Box::default(), Box::default());
        match std::mem::replace(self, empty) {
            RowPerm::Raw(f, i) => (f, i),
            RowPerm::Valid(p) => p.into_arrays(),
        }
    }
}

/// faer sparse LU solver for symmetric tridiagonal systems `tridiag(e, d, e) x = b`.
///
/// Works for `f64` (symmetric positive definite Newton matrix) and
/// [`num_complex::Complex64`] (= `faer::c64`, complex symmetric Newton matrix); the complex
/// system is solved as `A x = b` without conjugation.
pub struct FaerLu<T> {
    m: usize,
    /// Tridiagonal matrix in CSC form; the pattern is fixed in `pattern`, values per factorize.
    a: Option<SparseColMat<usize, T>>,
    symbolic: Option<SymbolicLu<usize>>,
    lu: SimplicialLu<usize, T>,
    row_perm: RowPerm,
    mem: MemBuffer,
}

impl<T> std::fmt::Debug for FaerLu<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FaerLu")
            .field("m", &self.m)
            .field("factorized", &matches!(self.row_perm, RowPerm::Valid(_)))
            .finish_non_exhaustive()
    }
}

impl<T: Scalar + ComplexField> Default for FaerLu<T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Scalar + ComplexField> FaerLu<T> {
    /// An empty solver; call [`TridiagSolver::pattern`] before use.
    pub fn new() -> Self {
        Self {
            m: 0,
            a: None,
            symbolic: None,
            lu: SimplicialLu::new(),
            row_perm: RowPerm::Raw(Box::default(), Box::default()),
            mem: MemBuffer::new(StackReq::EMPTY),
        }
    }

    /// Writes `d`, `e` into the CSC values (column `j` holds rows `j−1, j, j+1`).
    fn write_values(a: &mut SparseColMat<usize, T>, d: &[T], e: &[T]) {
        let m = d.len();
        let val = a.val_mut();
        let mut p = 0;
        for j in 0..m {
            if j > 0 {
                val[p] = e[j - 1];
                p += 1;
            }
            val[p] = d[j];
            p += 1;
            if j + 1 < m {
                val[p] = e[j];
                p += 1;
            }
        }
    }

    /// Numeric factorization of the values currently in `self.a`.
    fn factorize_current(&mut self) -> Result<(), SingularMatrix> {
        let (mut fwd, mut inv) = self.row_perm.take_arrays();
        let (Some(a), Some(symbolic)) = (self.a.as_ref(), self.symbolic.as_ref()) else {
            self.row_perm = RowPerm::Raw(fwd, inv);
            return Err(SingularMatrix { row: 0 });
        };
        let res = factorize_simplicial_numeric_lu(
            &mut fwd,
            &mut inv,
            &mut self.lu,
            a.as_ref(),
            symbolic.col_perm(),
            MemStack::new(&mut self.mem),
        );
        match res {
            Ok(()) => {}
            Err(LuError::SymbolicSingular { index }) => {
                self.row_perm = RowPerm::Raw(fwd, inv);
                return Err(SingularMatrix { row: index });
            }
            Err(LuError::Generic(_)) => {
                self.row_perm = RowPerm::Raw(fwd, inv);
                return Err(SingularMatrix { row: 0 });
            }
        }
        // faer accepts zero / NaN pivots; the pivot of step j is the last entry of U's column j.
        let u = self.lu.u_factor_unsorted();
        for j in 0..self.m {
            let usable = u.val_of_col(j).last().is_some_and(|p| p.is_usable_pivot());
            if !usable {
                self.row_perm = RowPerm::Raw(fwd, inv);
                return Err(SingularMatrix { row: j });
            }
        }
        self.row_perm = RowPerm::Valid(Perm::new_checked(fwd, inv, self.m));
        Ok(())
    }
}

impl<T: Scalar + ComplexField> TridiagSolver<T> for FaerLu<T> {
    fn pattern(&mut self, m: usize) {
        if m == self.m && self.a.is_some() && self.symbolic.is_some() {
            // The same size again (a renewed integrator, `crate::integrate::Integrator::renew`):
            // the pattern, its symbolic analysis and the buffers are those this would build,
            // and a factorization reads none of the last one's numbers; only that last
            // factorization is forgotten, as a new solver has none.
            let (f, i) = self.row_perm.take_arrays();
            self.row_perm = RowPerm::Raw(f, i);
            return;
        }
        self.m = m;
        self.a = None;
        self.symbolic = None;
        self.lu = SimplicialLu::new();
        self.row_perm = RowPerm::Raw(vec![0; m].into_boxed_slice(), vec![0; m].into_boxed_slice());
        self.mem = MemBuffer::new(StackReq::EMPTY);
        if m == 0 {
            return;
        }
        let nnz = 3 * m - 2;
        let mut col_ptr = Vec::with_capacity(m + 1);
        let mut row_idx = Vec::with_capacity(nnz);
        col_ptr.push(0usize);
        for j in 0..m {
            if j > 0 {
                row_idx.push(j - 1);
            }
            row_idx.push(j);
            if j + 1 < m {
                row_idx.push(j + 1);
            }
            col_ptr.push(row_idx.len());
        }
        let sym = SymbolicSparseColMat::new_checked(m, m, col_ptr, None, row_idx);
        let params = LuSymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
            ..Default::default()
        };
        // A tridiagonal pattern is structurally nonsingular; faer only fails here on OOM, in
        // which case `symbolic` stays `None` and every factorize reports `SingularMatrix`.
        self.symbolic = factorize_symbolic_lu(sym.as_ref(), params).ok();
        self.a = Some(SparseColMat::new(sym, vec![T::zero(); nnz]));
        self.mem = MemBuffer::new(StackReq::or(
            factorize_simplicial_numeric_lu_scratch::<usize, T>(m, m),
            solve_in_place_scratch::<usize, T>(m, 1, Par::Seq),
        ));
        // Warm-ups (see module docs): diagonally dominant, then |e| > |d| (a row swap per step).
        for (dv, ev) in [(4.0, 1.0), (1.0, 3.0)] {
            if let Some(a) = self.a.as_mut() {
                let d = vec![T::from_real(dv); m];
                let e = vec![T::from_real(ev); m - 1];
                Self::write_values(a, &d, &e);
            }
            // The warm-up matrices are nonsingular; a failure would only leave the buffers
            // smaller, which later factorizations handle by growing them.
            let _ = self.factorize_current();
        }
        let (f, i) = self.row_perm.take_arrays();
        self.row_perm = RowPerm::Raw(f, i);
    }

    fn factorize(&mut self, d: &[T], e: &[T]) -> Result<(), SingularMatrix> {
        let m = d.len();
        debug_assert_eq!(m, self.m, "factorize size differs from pattern size");
        debug_assert_eq!(e.len() + 1, m.max(1));
        if m == 0 {
            return Ok(());
        }
        match self.a.as_mut() {
            Some(a) if m == self.m && e.len() + 1 == m => Self::write_values(a, d, e),
            _ => {
                let (f, i) = self.row_perm.take_arrays();
                self.row_perm = RowPerm::Raw(f, i);
                return Err(SingularMatrix { row: 0 });
            }
        }
        self.factorize_current()
    }

    fn solve_in_place(&mut self, b: &mut [T]) {
        let m = b.len();
        debug_assert_eq!(m, self.m);
        if m == 0 {
            return;
        }
        let (RowPerm::Valid(perm), Some(symbolic)) = (&self.row_perm, self.symbolic.as_ref())
        else {
            debug_assert!(false, "solve_in_place without a successful factorize");
            return;
        };
        let rhs = MatMut::from_column_major_slice_mut(b, m, 1);
        self.lu.solve_in_place_with_conj(
            perm.as_ref(),
            symbolic.col_perm(),
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut self.mem),
        );
    }
}

#[cfg(test)]
mod tests;

/// Proves the "no allocation after `pattern`" claim of the module docs: a thread-local counting
/// allocator (only in this crate's unit-test binary; counts are per thread, so parallel tests do
/// not interfere).
#[cfg(test)]
mod alloc_tests;
