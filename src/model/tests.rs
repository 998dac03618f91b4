//! Unit tests of the chain model: stiffness against a finite difference of the force, fast
//! powers, Newton's third law, open contacts, the two-pass force kernel against the one-pass.

use super::*;

fn chain3() -> Chain {
    Chain {
        mass: vec![1.0, 2.0, 1.0],
        exponent: vec![2.5, 3.0],
        prefactor: vec![0.4, 0.7],
        ..Chain::default()
    }
}

#[test]
fn stiffness_matches_finite_difference_of_force() {
    let c = chain3();
    let u = [0.3, 0.1, -0.05];
    let mut acc = [0.0; 3];
    let mut k = [0.0; 4];
    c.accel_stiffness(0, &u, &mut acc, &mut k);
    let h = 1e-6;
    let f = |d: f64| contact_force(2.5, 0.4, d);
    let fd = (f(0.2 + h) - f(0.2 - h)) / (2.0 * h);
    assert!(
        (k[0] - fd).abs() <= 1e-7 * fd.abs() + 1e-12,
        "{} vs {}",
        k[0],
        fd
    );
}

#[test]
fn fast_powers_match_powf() {
    for &n in &[2.0, 2.5, 3.0, 3.5, 4.0, 2.7, 10.0] {
        for &d in &[1e-12, 0.3, 1.0, 7.5] {
            let a = pow_nm2(d, n);
            let b = f64::powf(d, n - 2.0);
            // rel 4 ulp
            assert!(
                (a - b).abs() <= 4.0 * f64::EPSILON * b,
                "n={n} d={d}: {a} vs {b}"
            );
        }
    }
}

#[test]
fn forces_are_newton_third_law() {
    let c = chain3();
    let u = [0.3, 0.1, -0.05];
    let mut acc = [0.0; 3];
    c.accel(0, &u, &mut acc);
    let total: f64 = acc.iter().zip(&c.mass).map(|(a, m)| a * m).sum();
    assert!(total.abs() <= 1e-14, "net force {total}");
}

#[test]
fn open_contact_has_no_force() {
    let c = chain3();
    let u = [0.0, 0.5, 1.0];
    let mut acc = [1.0; 3];
    c.accel(0, &u, &mut acc);
    assert_eq!(acc, [0.0, 0.0, 0.0]);
}

/// A chain of `n` beads whose exponents come in runs (long runs of 2.5, 3, 2, 3.5, 4, a run of
/// 2.7, and an alternating 2.5/2.555 stretch), with walls, and precompression and field as asked.
fn mixed_chain(pre: bool, field: bool, rng: &mut impl rand::Rng) -> Chain {
    let mut exponent = Vec::new();
    for (e, len) in [
        (2.5, 9),
        (3.0, 6),
        (2.0, 5),
        (3.5, 4),
        (4.0, 7),
        (2.7, 5),
        (2.5, 3),
    ] {
        exponent.extend(std::iter::repeat_n(e, len));
    }
    exponent.extend((0..8).map(|k| if k % 2 == 0 { 2.5 } else { 2.555 }));
    let n = exponent.len() + 1;
    let wall = |e: f64| Wall {
        exponent: e,
        prefactor: 0.9,
        precompression: 0.01,
        restitution: None,
    };
    Chain {
        mass: (0..n).map(|_| rng.random_range(0.5..2.0)).collect(),
        exponent,
        prefactor: (0..n - 1).map(|_| rng.random_range(0.1..1.0)).collect(),
        precompression: pre.then(|| (0..n - 1).map(|_| rng.random_range(-0.05..0.05)).collect()),
        field: field.then(|| (0..n).map(|_| rng.random_range(-0.1..0.1)).collect()),
        left_wall: Some(wall(2.5)),
        right_wall: Some(wall(3.0)),
        hard: None,
        damping: None,
    }
}

/// The two-pass force kernel of `accel` (`forces.rs`) against the one-pass loop it replaced:
/// bit for bit, on every exponent class, short and long runs, open and closed contacts, walls,
/// with and without precompression and field, on every sub-range (cluster) of the chain.
#[test]
fn two_pass_accel_is_bit_identical_to_one_pass() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    for (pre, field) in [(false, false), (true, false), (false, true), (true, true)] {
        let chain = mixed_chain(pre, field, &mut rng);
        let n = chain.len();
        for _ in 0..20 {
            // about a third of the contacts open; some overlaps tiny or exactly zero
            let mut u = vec![0.0; n];
            for i in 1..n {
                let d: f64 = match rng.random_range(0..6) {
                    0 => 0.0,
                    1 => rng.random_range(1e-300..1e-200),
                    2 | 3 => rng.random_range(-0.1..0.0),
                    _ => rng.random_range(0.0..0.2),
                };
                u[i] = u[i - 1] - d;
            }
            for lo in 0..n {
                for hi in lo + 1..=n {
                    let (mut a1, mut a2) = (vec![0.0; hi - lo], vec![0.0; hi - lo]);
                    chain.accel(lo, &u[lo..hi], &mut a1);
                    chain.accel_one_pass(lo, &u[lo..hi], &mut a2);
                    let (b1, b2): (Vec<u64>, Vec<u64>) = a1
                        .iter()
                        .zip(&a2)
                        .map(|(x, y)| (x.to_bits(), y.to_bits()))
                        .unzip();
                    assert_eq!(b1, b2, "pre {pre} field {field} range {lo}..{hi}");
                }
            }
        }
    }
}
