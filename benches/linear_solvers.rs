//! Factorize + solve time of the two [`TridiagSolver`]s on the Radau-reduced Newton systems
//! (paper appendix, eq. A.3; see `beadchain::linalg`): `d = μ² m_i + h²(k_{i−1} + k_i)`,
//! `e = −h² k_i`, random masses in `[0.5, 2)` and stiffnesses in `[0, 10)` from a seeded
//! ChaCha8 stream, `h = 0.3`, real `μ ≈ 3.64` and complex `μ ≈ 2.68 + 3.05i` (the Radau IIA
//! order-5 eigenvalues). One iteration = one `factorize` + one `solve_in_place` (plus an `m`-long
//! copy of the right-hand side, the same for both solvers).
//!
//! Run: `cargo bench --bench linear_solvers -- --warm-up-time 0.5 --measurement-time 1`.
//! The crossover measured here sets `beadchain::linalg::resolve_auto`.

use std::hint::black_box;

use beadchain::linalg::{
    direct::DirectSweep, faer_lu::FaerLu, Scalar, SolverScalar, TridiagSolver,
};
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use num_complex::Complex64;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const SIZES: [usize; 8] = [2, 4, 8, 32, 128, 1024, 10_000, 100_000];
const H: f64 = 0.3;

fn radau_system<T: Scalar>(mu2: T, m: usize, rng: &mut ChaCha8Rng) -> (Vec<T>, Vec<T>, Vec<T>) {
    let mass: Vec<f64> = (0..m).map(|_| rng.random_range(0.5..2.0)).collect();
    let k: Vec<f64> = (0..m - 1).map(|_| rng.random_range(0.0..10.0)).collect();
    let h2 = H * H;
    let d = (0..m)
        .map(|i| {
            let left = if i > 0 { k[i - 1] } else { 0.0 };
            let right = if i + 1 < m { k[i] } else { 0.0 };
            mu2 * T::from_real(mass[i]) + T::from_real(h2 * (left + right))
        })
        .collect();
    let e = k.iter().map(|&ki| T::from_real(-h2 * ki)).collect();
    let b = (0..m)
        .map(|_| T::from_real(rng.random_range(-1.0..1.0)))
        .collect();
    (d, e, b)
}

fn bench_scalar<T: SolverScalar>(c: &mut Criterion, name: &str, mu2: T) {
    let mut group = c.benchmark_group(name);
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    for &m in &SIZES {
        let (d, e, rhs) = radau_system(mu2, m, &mut rng);
        group.throughput(Throughput::Elements(m as u64));
        let solvers: [(&str, Box<dyn TridiagSolver<T>>); 2] = [
            ("direct", Box::new(DirectSweep::<T>::new())),
            ("faer", Box::new(FaerLu::<T>::new())),
        ];
        for (label, mut s) in solvers {
            s.pattern(m);
            let mut x = rhs.clone();
            group.bench_with_input(BenchmarkId::new(label, m), &m, |bch, _| {
                bch.iter(|| {
                    s.factorize(black_box(&d), black_box(&e))
                        .expect("benchmark matrices are nonsingular");
                    x.copy_from_slice(&rhs);
                    s.solve_in_place(black_box(&mut x));
                    black_box(&x);
                })
            });
        }
    }
    group.finish();
}

fn linear_solvers(c: &mut Criterion) {
    let mu_real = 3.637_834_252_744_496_f64;
    let mu_complex = Complex64::new(2.681_082_873_627_752, 3.050_430_199_247_41);
    bench_scalar(c, "real", mu_real * mu_real);
    bench_scalar(c, "complex", mu_complex * mu_complex);
}

criterion_group!(benches, linear_solvers);
criterion_main!(benches);
