//! Unit tests of the chain model: stiffness against a finite difference of the force, fast
//! powers, Newton's third law, open contacts.

use super::*;

fn chain3() -> Chain {
    Chain {
        mass: vec![1.0, 2.0, 1.0],
        exponent: vec![2.5, 3.0],
        prefactor: vec![0.4, 0.7],
        precompression: None,
        field: None,
        left_wall: None,
        right_wall: None,
        hard: None,
        damping: None,
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
