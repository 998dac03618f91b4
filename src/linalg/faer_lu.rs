//! faer sparse LU for the symmetric tridiagonal Newton systems of the Radau reduction
//! (paper appendix, eq. A.3; see [`super`] for the reduction to `(μ² M + h² L(k)) x = r`).
//!
//! Lifecycle (see [`TridiagSolver`]):
//! - [`TridiagSolver::pattern`] builds the tridiagonal CSC sparsity pattern, runs faer's symbolic
//!   analysis ([`factorize_symbolic_lu`], COLAMD column ordering) **once**, allocates the scratch
//!   stack for both numeric factorization and solve, and runs two warm-up numeric factorizations
//!   (one without and one with a row interchange at every step) so that faer's factor storage
//!   already has the capacity that later factorizations need;
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
mod tests {
    use super::*;
    use crate::linalg::direct::DirectSweep;
    use crate::linalg::{new_solver, SolverKind};
    use num_complex::Complex64;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Radau-reduced Newton matrix (see [`crate::linalg`]): `d = μ² m_i + h²(k_{i−1} + k_i)`,
    /// `e = −h² k_i`, random masses in `[0.5, 2)` and stiffnesses in `[0, 10)`, free ends.
    fn radau_system<T: Scalar>(mu2: T, h: f64, m: usize, rng: &mut ChaCha8Rng) -> (Vec<T>, Vec<T>) {
        let mass: Vec<f64> = (0..m).map(|_| rng.random_range(0.5..2.0)).collect();
        let k: Vec<f64> = (0..m.saturating_sub(1))
            .map(|_| rng.random_range(0.0..10.0))
            .collect();
        let h2 = h * h;
        let d = (0..m)
            .map(|i| {
                let left = if i > 0 { k[i - 1] } else { 0.0 };
                let right = if i + 1 < m { k[i] } else { 0.0 };
                mu2 * T::from_real(mass[i]) + T::from_real(h2 * (left + right))
            })
            .collect();
        let e = k.iter().map(|&ki| T::from_real(-h2 * ki)).collect();
        (d, e)
    }

    fn matvec<T: Scalar>(d: &[T], e: &[T], x: &[T]) -> Vec<T> {
        let m = d.len();
        (0..m)
            .map(|i| {
                let mut s = d[i] * x[i];
                if i > 0 {
                    s = s + e[i - 1] * x[i - 1];
                }
                if i + 1 < m {
                    s = s + e[i] * x[i + 1];
                }
                s
            })
            .collect()
    }

    fn inf_norm<T: TestScalar>(v: &[T]) -> f64 {
        v.iter().map(|x| x.modulus()).fold(0.0, f64::max)
    }

    /// Solves with both solvers; asserts agreement and a small residual; returns the max
    /// difference relative to ‖x‖∞.
    fn check_against_direct<T: TestScalar>(faer: &mut FaerLu<T>, d: &[T], e: &[T], b: &[T]) -> f64 {
        let m = d.len();
        let mut direct = DirectSweep::<T>::new();
        direct.pattern(m);
        direct
            .factorize(d, e)
            .expect("direct: nonsingular test matrix");
        let mut xd = b.to_vec();
        direct.solve_in_place(&mut xd);
        faer.factorize(d, e).expect("faer: nonsingular test matrix");
        let mut xf = b.to_vec();
        faer.solve_in_place(&mut xf);
        let xnorm = inf_norm(&xd);
        let diff: Vec<T> = xf.iter().zip(&xd).map(|(&a, &b)| a - b).collect();
        let dmax = inf_norm(&diff);
        // Agreement: abs tol 1e-12·‖x‖∞ per component, rel tol 1e-12 (so ≤ 2e-12·‖x‖∞ overall).
        for (i, (a, b)) in xf.iter().zip(&xd).enumerate() {
            let err = (*a - *b).modulus();
            let tol = 1e-12 * xnorm + 1e-12 * b.modulus();
            assert!(
                err <= tol,
                "m={m} i={i}: faer {a:?} vs direct {b:?} (err {err:e}, tol {tol:e})"
            );
        }
        // Residual: ‖A x − b‖∞ ≤ 1e-13·(‖A‖∞‖x‖∞ + ‖b‖∞) (abs 0, rel 1e-13 of that scale).
        let ax = matvec(d, e, &xf);
        let r: Vec<T> = ax.iter().zip(b).map(|(&a, &b)| a - b).collect();
        let anorm = (0..m)
            .map(|i| {
                let mut s = d[i].modulus();
                if i > 0 {
                    s += e[i - 1].modulus();
                }
                if i + 1 < m {
                    s += e[i].modulus();
                }
                s
            })
            .fold(0.0, f64::max);
        let scale = anorm * inf_norm(&xf) + inf_norm(b);
        assert!(
            inf_norm(&r) <= 1e-13 * scale,
            "m={m}: residual {:e} vs scale {scale:e}",
            inf_norm(&r)
        );
        dmax / xnorm.max(f64::MIN_POSITIVE)
    }

    /// Modulus as `f64` for both test scalars.
    trait TestScalar: Scalar + ComplexField {
        fn modulus(self) -> f64;
    }

    impl TestScalar for f64 {
        fn modulus(self) -> f64 {
            self.abs()
        }
    }

    impl TestScalar for Complex64 {
        fn modulus(self) -> f64 {
            self.norm()
        }
    }

    const MU2_REAL: f64 = 3.637_834_252_744_496 * 3.637_834_252_744_496;

    fn mu2_complex() -> Complex64 {
        let mu = Complex64::new(2.681_082_873_627_752, 3.050_430_199_247_41);
        mu * mu
    }

    #[test]
    fn real_spd_agrees_with_direct_sweep() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        for &m in &[1usize, 2, 3, 5, 17, 100, 1000] {
            for &h in &[0.01, 0.3, 3.0] {
                let (d, e) = radau_system(MU2_REAL, h, m, &mut rng);
                let b: Vec<f64> = (0..m).map(|_| rng.random_range(-1.0..1.0)).collect();
                let mut s = FaerLu::<f64>::new();
                s.pattern(m);
                check_against_direct(&mut s, &d, &e, &b);
            }
        }
    }

    #[test]
    fn complex_symmetric_agrees_with_direct_sweep() {
        let mut rng = ChaCha8Rng::seed_from_u64(12);
        for &m in &[1usize, 2, 3, 5, 17, 100, 1000] {
            for &h in &[0.01, 0.3, 3.0] {
                let (d, e) = radau_system(mu2_complex(), h, m, &mut rng);
                let b: Vec<Complex64> = (0..m)
                    .map(|_| {
                        Complex64::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0))
                    })
                    .collect();
                let mut s = FaerLu::<Complex64>::new();
                s.pattern(m);
                check_against_direct(&mut s, &d, &e, &b);
            }
        }
    }

    #[test]
    fn tiny_systems_exact_values() {
        // m = 1: 4 x = 2 → x = 0.5 (abs tol 1e-15, rel 0).
        let mut s = FaerLu::<f64>::new();
        s.pattern(1);
        s.factorize(&[4.0], &[]).expect("nonsingular 1x1");
        let mut b = [2.0];
        s.solve_in_place(&mut b);
        assert!((b[0] - 0.5).abs() <= 1e-15, "{b:?}");
        // m = 2: [[2, 1], [1, 3]] x = [3, 4] → x = [1, 1] (abs tol 1e-15, rel 0).
        s.pattern(2);
        s.factorize(&[2.0, 3.0], &[1.0]).expect("nonsingular 2x2");
        let mut b = [3.0, 4.0];
        s.solve_in_place(&mut b);
        assert!(
            (b[0] - 1.0).abs() <= 1e-15 && (b[1] - 1.0).abs() <= 1e-15,
            "{b:?}"
        );
        // m = 2 needing a row swap: [[0, 1], [1, 0]] x = [5, 7] → x = [7, 5] (abs tol 1e-15).
        s.factorize(&[0.0, 0.0], &[1.0])
            .expect("permutation matrix is nonsingular");
        let mut b = [5.0, 7.0];
        s.solve_in_place(&mut b);
        assert!(
            (b[0] - 7.0).abs() <= 1e-15 && (b[1] - 5.0).abs() <= 1e-15,
            "{b:?}"
        );
    }

    #[test]
    fn singular_and_non_finite_matrices_are_errors() {
        let mut s = FaerLu::<f64>::new();
        s.pattern(1);
        assert!(s.factorize(&[0.0], &[]).is_err(), "zero 1x1");
        assert!(s.factorize(&[f64::NAN], &[]).is_err(), "NaN 1x1");
        s.pattern(2);
        let err = s.factorize(&[1.0, 1.0], &[1.0]).expect_err("rank-1 2x2");
        assert_eq!(err.row, 1);
        s.pattern(4);
        assert!(
            s.factorize(&[2.0, f64::INFINITY, 2.0, 2.0], &[-1.0; 3])
                .is_err(),
            "inf"
        );
        assert!(
            s.factorize(&[2.0; 4], &[-1.0, f64::NAN, -1.0]).is_err(),
            "NaN off-diagonal"
        );
        // Laplacian of a free chain (μ = 0): singular (constant null vector).
        let err = s.factorize(&[1.0, 2.0, 2.0, 1.0], &[-1.0; 3]);
        assert!(err.is_err(), "free-chain Laplacian must be singular");
        // Recovers after an error (abs tol 1e-14 on x = 1 for rows sums 1).
        s.factorize(&[2.0, 3.0, 3.0, 2.0], &[-1.0; 3])
            .expect("nonsingular after error");
        let mut b = [1.0; 4];
        s.solve_in_place(&mut b);
        assert!(b.iter().all(|x| (x - 1.0).abs() <= 1e-14), "{b:?}");

        let mut c = FaerLu::<Complex64>::new();
        c.pattern(2);
        let one = Complex64::new(1.0, 1.0);
        assert!(
            c.factorize(&[one, one], &[one]).is_err(),
            "complex rank-1 2x2"
        );
    }

    #[test]
    fn repeated_factorize_on_same_pattern() {
        let mut rng = ChaCha8Rng::seed_from_u64(13);
        let m = 257;
        let mut s = FaerLu::<Complex64>::new();
        s.pattern(m);
        let mut r = FaerLu::<f64>::new();
        r.pattern(m);
        for round in 0..6 {
            let h = [0.01, 1.0, 0.1, 5.0, 0.5, 0.02][round];
            let (d, e) = radau_system(mu2_complex(), h, m, &mut rng);
            let b: Vec<Complex64> = (0..m)
                .map(|_| Complex64::new(rng.random_range(-1.0..1.0), 0.5))
                .collect();
            check_against_direct(&mut s, &d, &e, &b);
            // Several solves per factorization (Newton iterations).
            let b2: Vec<Complex64> = b.iter().map(|&x| x * Complex64::new(0.0, 2.0)).collect();
            check_against_direct(&mut s, &d, &e, &b2);
            let (d, e) = radau_system(MU2_REAL, h, m, &mut rng);
            let b: Vec<f64> = (0..m).map(|_| rng.random_range(-1.0..1.0)).collect();
            check_against_direct(&mut r, &d, &e, &b);
        }
    }

    #[test]
    fn factory_builds_both_kinds_for_both_scalars() {
        let mut rng = ChaCha8Rng::seed_from_u64(14);
        for kind in [SolverKind::Auto, SolverKind::Direct, SolverKind::Faer] {
            for m in [1usize, 2, 64] {
                let (d, e) = radau_system(MU2_REAL, 0.5, m, &mut rng);
                let x: Vec<f64> = (0..m).map(|i| 1.0 + i as f64).collect();
                let mut b = matvec(&d, &e, &x);
                let mut s = new_solver::<f64>(kind, m);
                s.factorize(&d, &e).expect("SPD");
                s.solve_in_place(&mut b);
                // abs tol 1e-12·‖x‖∞, rel 0.
                assert!(
                    b.iter()
                        .zip(&x)
                        .all(|(a, b)| (a - b).abs() <= 1e-12 * m as f64),
                    "{kind:?}"
                );
                let (d, e) = radau_system(mu2_complex(), 0.5, m, &mut rng);
                let xc: Vec<Complex64> = x.iter().map(|&v| Complex64::new(v, -v)).collect();
                let mut bc = matvec(&d, &e, &xc);
                let mut c = new_solver::<Complex64>(kind, m);
                c.factorize(&d, &e).expect("complex symmetric, Im > 0");
                c.solve_in_place(&mut bc);
                // abs tol 1e-12·‖x‖∞ (‖x‖∞ ≤ √2·m), rel 0.
                assert!(
                    bc.iter()
                        .zip(&xc)
                        .all(|(a, b)| (a - b).norm() <= 2e-12 * m as f64),
                    "{kind:?}"
                );
            }
        }
    }
}

/// Proves the "no allocation after `pattern`" claim of the module docs: a thread-local counting
/// allocator (only in this crate's unit-test binary; counts are per thread, so parallel tests do
/// not interfere).
#[cfg(test)]
mod alloc_tests {
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
            let nnz =
                s.lu.l_factor_unsorted().compute_nnz() + s.lu.u_factor_unsorted().compute_nnz();
            assert!(nnz <= 5 * m, "m={m}: nnz(L)+nnz(U) = {nnz}");
        }
    }
}
