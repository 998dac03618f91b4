//! Unit tests of the faer LU: solutions against the direct sweep, singular pivots.

use super::*;
use crate::linalg::direct::DirectSweep;
use crate::linalg::{new_solver, tridiag_matvec as matvec, SolverKind};
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
                .map(|_| Complex64::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)))
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
