//! Direct `LDLᵀ` sweep (Thomas algorithm) for symmetric tridiagonal systems, without pivoting.
//!
//! Stable for the two matrices the Radau Newton reduction produces (see [`super`]): symmetric
//! positive definite (real eigenvalue), and complex symmetric with positive definite imaginary
//! part (complex eigenvalue pair). `O(m)` work, no allocation after [`TridiagSolver::pattern`].

use super::{Scalar, SingularMatrix, TridiagSolver};

/// `LDLᵀ` factors: `inv_d[i] = 1/D_i`, `l[i] = e[i-1]/D_{i-1}` (with `l[0]` unused).
#[derive(Clone, Debug, Default)]
pub struct DirectSweep<T: Scalar> {
    inv_d: Vec<T>,
    l: Vec<T>,
}

impl<T: Scalar> DirectSweep<T> {
    /// An empty solver; call [`TridiagSolver::pattern`] before use.
    pub fn new() -> Self {
        Self {
            inv_d: Vec::new(),
            l: Vec::new(),
        }
    }
}

impl<T: Scalar> TridiagSolver<T> for DirectSweep<T> {
    fn pattern(&mut self, m: usize) {
        self.inv_d.clear();
        self.inv_d.resize(m, T::zero());
        self.l.clear();
        self.l.resize(m, T::zero());
    }

    fn factorize(&mut self, d: &[T], e: &[T]) -> Result<(), SingularMatrix> {
        let m = d.len();
        debug_assert_eq!(self.inv_d.len(), m);
        debug_assert_eq!(e.len() + 1, m);
        let one = T::from_real(1.0);
        let mut piv = d[0];
        if !piv.is_usable_pivot() {
            return Err(SingularMatrix { row: 0 });
        }
        self.inv_d[0] = one / piv;
        for i in 1..m {
            let li = e[i - 1] * self.inv_d[i - 1];
            self.l[i] = li;
            piv = d[i] - li * e[i - 1];
            if !piv.is_usable_pivot() {
                return Err(SingularMatrix { row: i });
            }
            self.inv_d[i] = one / piv;
        }
        Ok(())
    }

    fn solve_in_place(&mut self, b: &mut [T]) {
        let m = b.len();
        debug_assert_eq!(self.inv_d.len(), m);
        for i in 1..m {
            let prev = b[i - 1];
            b[i] = b[i] - self.l[i] * prev;
        }
        for i in 0..m {
            b[i] = b[i] * self.inv_d[i];
        }
        for i in (0..m.saturating_sub(1)).rev() {
            let next = b[i + 1];
            b[i] = b[i] - self.l[i + 1] * next;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::tridiag_matvec as matvec;
    use num_complex::Complex64;

    #[test]
    fn complex_symmetric_solve_has_small_residual() {
        let m = 50;
        let mu2 = Complex64::new(-2.1, 16.3);
        let d: Vec<Complex64> = (0..m)
            .map(|i| mu2 * (1.0 + (i % 3) as f64) + Complex64::new(2.0 + i as f64 * 0.01, 0.0))
            .collect();
        let e: Vec<Complex64> = (0..m - 1)
            .map(|i| Complex64::new(-1.0 - 0.02 * i as f64, 0.0))
            .collect();
        let x: Vec<Complex64> = (0..m)
            .map(|i| Complex64::new(i as f64, 1.0 - i as f64 * 0.5))
            .collect();
        let mut b = matvec(&d, &e, &x);
        let mut s = DirectSweep::new();
        s.pattern(m);
        s.factorize(&d, &e).expect("nonsingular");
        s.solve_in_place(&mut b);
        for (xi, bi) in x.iter().zip(&b) {
            // abs 1e-10, rel 1e-12 of |x|
            assert!(
                (xi - bi).norm() <= 1e-10 + 1e-12 * xi.norm(),
                "{xi} vs {bi}"
            );
        }
    }

    #[test]
    fn zero_pivot_is_reported() {
        let mut s = DirectSweep::<f64>::new();
        s.pattern(3);
        let err = s.factorize(&[1.0, 1.0, 2.0], &[1.0, 0.5]).unwrap_err();
        assert_eq!(err.row, 1);
    }
}
