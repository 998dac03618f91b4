//! The scaled profile and its placement: fixed point and advance–delay residuals, grid
//! convergence, the virial identity `∫W² = ∫Sⁿ`, scaling of speed and energy, placement.

use super::*;

const EXPONENTS: [f64; 5] = [2.1, 2.5, 3.0, 4.0, 8.0];

/// Fixed point `S = K ∗ S^p` to round-off (relative 1e-14 of max S), the advance–delay equation
/// `S'' = Δ₂ S^p` to the round-off of a spectral second derivative (relative 5e-12 of max |S''|:
/// ε·(πM)² ≈ 2e-12), and the virial identity `∫W² = ∫Sⁿ` (relative 1e-13).
#[test]
fn profile_solves_the_travelling_wave_equation() {
    for n in EXPONENTS {
        let p = UnitProfile::compute(n).unwrap();
        assert!(
            p.residual < 4e-15,
            "n {n}: fixed-point residual {:e}",
            p.residual
        );
        let ad = p.advance_delay_residual();
        assert!(ad < 5e-12, "n {n}: advance-delay residual {ad:e}");
        let (w2, sn) = p.virial_integrals();
        assert!((w2 / sn - 1.0).abs() < 1e-13, "n {n}: ∫W² {w2} vs ∫Sⁿ {sn}");
        // Peak of S at ξ = 0, of W at ξ = 1/2 (bead centre): neighbours lower.
        assert!(p.s_at(0.0) > p.s_at(0.03125) && p.w_at(0.5) > p.w_at(0.46875));
        assert!(p.w_at(0.5) > p.w_at(0.53125));
    }
}

/// The profile does not depend on the grid: the chosen `M` against `2M` on twice the period,
/// at quarter-bead offsets, absolute 1e-13 (profiles of order 1).
#[test]
fn grid_converged() {
    for n in [2.1, 3.0, 8.0] {
        let p = UnitProfile::compute(n).unwrap();
        let fine = solve(n, 2 * p.period, 2 * p.per_bead);
        for k in -48..=48 {
            let x = k as f64 * 0.25;
            assert!((p.s_at(x) - fine.s_at(x)).abs() < 1e-13, "n {n}: S({x})");
            assert!((p.w_at(x) - fine.w_at(x)).abs() < 1e-13, "n {n}: W({x})");
        }
    }
}

/// Scaling symmetry: `c ∝ v_m^{(n−2)/n}`, `λ ∝ c^{2/(n−2)}`, `E = κ m v_m²` (relative 1e-12),
/// and `with_energy` inverts `energy` (relative 1e-12).
#[test]
fn speed_amplitude_and_energy_scale() {
    for n in EXPONENTS {
        let p = UnitProfile::compute(n).unwrap();
        let w1 = Wave::with_peak_velocity(p.clone(), 2.0, 0.3, 1.0).unwrap();
        let w2 = Wave::with_peak_velocity(p.clone(), 2.0, 0.3, 1e3).unwrap();
        let rc = w2.speed / w1.speed / 1e3_f64.powf((n - 2.0) / n);
        let rl = w2.scale / w1.scale / (w2.speed / w1.speed).powf(2.0 / (n - 2.0));
        assert!(
            (rc - 1.0).abs() < 1e-12 && (rl - 1.0).abs() < 1e-12,
            "n {n}: {rc} {rl}"
        );
        assert!(
            (w2.energy() / w1.energy() / 1e6 - 1.0).abs() < 1e-12,
            "n {n}"
        );
        // Peak velocity of the placed wave is v_m, speed c solves m c² λ^{2−n} = n a.
        assert!((w1.velocity(0.0) - 1.0).abs() < 1e-12, "n {n}");
        let lhs = 2.0 * w1.speed.powi(2) * w1.scale.powf(2.0 - n);
        assert!((lhs / (n * 0.3) - 1.0).abs() < 1e-12, "n {n}: {lhs}");
        let we = Wave::with_energy(p, 2.0, 0.3, w2.energy()).unwrap();
        assert!((we.peak_velocity / 1e3 - 1.0).abs() < 1e-12, "n {n}");
    }
    assert!(UnitProfile::compute(2.0).is_err() && UnitProfile::compute(1.5).is_err());
}

/// Placement: contact overlaps `u_k − u_{k+1}` equal `λ S(k + 1/2 − K)` (absolute 1e-15 of λ),
/// beads ahead at rest and unshifted, beads behind shifted by `Σ r`; a left-moving wave is the
/// mirror image (`u_{K+x} = −u_{K−x}` exactly).
#[test]
fn placement_builds_the_overlaps() {
    let p = UnitProfile::compute(3.0).unwrap();
    let w = Wave::with_peak_velocity(p, 1.0, 1.0, 0.5).unwrap();
    let (nb, at) = (40, 20);
    let right = w.place(at, Direction::Right, nb).unwrap();
    let left = w.place(at, Direction::Left, nb).unwrap();
    let (mut u, mut v) = (vec![0.0; nb], vec![0.0; nb]);
    right.add_to(&mut u, &mut v);
    for k in 0..nb - 1 {
        let r = w.overlap(k as f64 + 0.5 - at as f64);
        assert!((u[k] - u[k + 1] - r).abs() < 1e-15 * w.scale, "contact {k}");
    }
    assert!(u[nb - 1] == 0.0 && v[nb - 1] == 0.0 && v[0] == 0.0 && u[0] == right.behind);
    assert_eq!(v[at], w.velocity(0.0));
    let (mut ul, mut vl) = (vec![0.0; nb], vec![0.0; nb]);
    left.add_to(&mut ul, &mut vl);
    for x in 0..=at - 1 {
        assert_eq!(ul[at + x], -u[at - x], "bead {}", at + x);
        assert_eq!(vl[at + x], -v[at - x], "bead {}", at + x);
    }
    // Too close to an end: refused with the beads it needs.
    let e = w.place(3, Direction::Right, nb).unwrap_err().to_string();
    assert!(e.contains("needs beads"), "{e}");
}

/// Near `n = 2` (wide profile: the period doubles to 128) and at `n = 20` (sharp `S^p`: the grid
/// refines to 256 points per bead): fixed-point residual relative 1e-14, the grid's spectral
/// tail at most 1e-15, and the profile against twice as fine a grid to 1e-13 (absolute, order 1).
#[test]
fn extreme_exponents_converge() {
    for (n, period, per_bead) in [(2.05, 128, 32), (20.0, 32, 256)] {
        let p = UnitProfile::compute(n).unwrap();
        assert_eq!((p.period, p.per_bead), (period, per_bead), "n {n}: grid");
        assert!(
            p.residual < 1e-14 && p.tail <= 1e-15,
            "n {n}: {} {}",
            p.residual,
            p.tail
        );
        let fine = solve(n, p.period, 2 * p.per_bead);
        for k in -40..=40 {
            let x = k as f64 * 0.25;
            assert!((p.w_at(x) - fine.w_at(x)).abs() < 1e-13, "n {n}: W({x})");
        }
    }
}
