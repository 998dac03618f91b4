//! Damping coefficients from a measured coefficient of restitution.
//!
//! A head-on collision of two beads (reduced mass `μ`, contact `V = a δⁿ`, impact speed `v`)
//! becomes parameter-free in the units `T = (μ v^{2−n}/(n a))^{1/n}` (time) and `v T` (length):
//! with `δ = v T x`, `t = T s`,
//!
//! ```text
//! x'' = −max(0, x^{n−1} + y (n−1) x^{n−2} x')   (viscoelastic, y = A/T)
//! x'' = −max(0, x^{n−1} + y x')                 (linear dashpot, y = c T/μ)
//! ```
//!
//! with `x(0) = 0`, `x'(0) = 1`, and the restitution `e = −x'` when the force has ended. So
//! `e` depends on `y` only ([`restitution_of`]); [`dimensionless_coefficient`] inverts it by
//! bisection (one solve per exponent), and [`coefficient`] scales it back per contact. For
//! Hertz (`n = 5/2`) this reproduces the known scaling `1 − e ∝ A v^{1/5}` at small damping
//! (Schwager & Pöschel, Phys. Rev. E 57, 650 (1998)), since `y = A/T ∝ v^{1/5}`.
//!
//! The collision is integrated with classical RK4 at step `1e-4` (in units of `T`), the end of
//! the contact located by step halving; the result is accurate to about `1e-10` in `e` (tested
//! against the closed-form linear dashpot).

use super::DampingLaw;

/// RK4 step of the dimensionless collision.
const DT: f64 = 1e-4;
/// Give up (no end of contact) after this dimensionless time.
const T_MAX: f64 = 1e3;

/// The clipped dimensionless force at `(x, p)`.
/// At `x = 0` a closing contact already feels its damping (as in [`super::law`]).
fn force(law: DampingLaw, n: f64, y: f64, x: f64, p: f64) -> f64 {
    if x < 0.0 || (x == 0.0 && p <= 0.0) {
        return 0.0;
    }
    let f = match law {
        DampingLaw::Viscoelastic => x.powf(n - 2.0) * (x + y * (n - 1.0) * p),
        DampingLaw::LinearDashpot => x.powf(n - 1.0) + y * p,
    };
    f.max(0.0)
}

/// One RK4 step of size `dt` from `(x, p)`.
fn rk4(law: DampingLaw, n: f64, y: f64, (x, p): (f64, f64), dt: f64) -> (f64, f64) {
    let acc = |x: f64, p: f64| -force(law, n, y, x, p);
    let (k1x, k1p) = (p, acc(x, p));
    let (k2x, k2p) = (
        p + 0.5 * dt * k1p,
        acc(x + 0.5 * dt * k1x, p + 0.5 * dt * k1p),
    );
    let (k3x, k3p) = (
        p + 0.5 * dt * k2p,
        acc(x + 0.5 * dt * k2x, p + 0.5 * dt * k2p),
    );
    let (k4x, k4p) = (p + dt * k3p, acc(x + dt * k3x, p + dt * k3p));
    (
        x + dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x),
        p + dt / 6.0 * (k1p + 2.0 * k2p + 2.0 * k3p + k4p),
    )
}

/// Restitution of the dimensionless collision with coefficient `y ≥ 0`. RK4 at step [`DT`];
/// the step that ends the contact (overlap gone, or separating with the force clipped, after
/// which nothing changes `p`) is refined by halving down to `1e-13`, so the kink where the
/// force ends costs no accuracy.
pub fn restitution_of(law: DampingLaw, n: f64, y: f64) -> f64 {
    let ended = |(x, p): (f64, f64)| x <= 0.0 || (p < 0.0 && force(law, n, y, x, p) == 0.0);
    let (mut s, mut t, mut dt) = ((0.0_f64, 1.0_f64), 0.0, DT);
    while t < T_MAX {
        let next = rk4(law, n, y, s, dt);
        if !ended(next) {
            s = next;
            t += dt;
        } else if dt > 1e-13 {
            dt *= 0.5;
        } else {
            return -next.1;
        }
    }
    f64::NAN
}

/// The `y` with [`restitution_of`]`(law, n, y) = e` (`e ∈ (0, 1]`), by bisection on `log y`.
/// NaN when `e` cannot be reached (below `e` at `y = 1e6`).
pub fn dimensionless_coefficient(law: DampingLaw, n: f64, e: f64) -> f64 {
    if e >= 1.0 {
        return 0.0;
    }
    let (mut lo, mut hi) = (1e-12_f64, 1.0_f64);
    while restitution_of(law, n, hi) > e {
        hi *= 4.0;
        if hi > 1e6 {
            return f64::NAN;
        }
    }
    for _ in 0..60 {
        let mid = (lo * hi).sqrt();
        if restitution_of(law, n, mid) > e {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi / lo < 1.0 + 1e-12 {
            break;
        }
    }
    (lo * hi).sqrt()
}

/// The contact's coefficient (`A` or `c`) for dimensionless `y`, exponent `n`, prefactor `a`,
/// reduced mass `mu` and impact speed `v`.
pub fn coefficient(law: DampingLaw, n: f64, a: f64, mu: f64, v: f64, y: f64) -> f64 {
    let t = (mu * v.powf(2.0 - n) / (n * a)).powf(1.0 / n);
    match law {
        DampingLaw::Viscoelastic => y * t,
        DampingLaw::LinearDashpot => y * mu / t,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Closed form for the clipped linear dashpot (n = 2: x'' + y x' + x = 0 while the force
    /// `x + y x'` is positive): `x = e^{−βs} sin(ωs)/ω`, β = y/2, ω = sqrt(1 − β²); the contact
    /// ends at the first root of `x + y x'`, found by bisection on the exact solution.
    fn dashpot_exact(y: f64) -> f64 {
        let b = y / 2.0;
        let w = (1.0 - b * b).sqrt();
        let x = |s: f64| (-b * s).exp() * (w * s).sin() / w;
        let p = |s: f64| (-b * s).exp() * ((w * s).cos() - b / w * (w * s).sin());
        let g = |s: f64| x(s) + y * p(s);
        let (mut lo, mut hi) = (std::f64::consts::FRAC_PI_2 / w, std::f64::consts::PI / w);
        assert!(g(lo) > 0.0 && g(hi) < 0.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if g(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        -p(0.5 * (lo + hi))
    }

    #[test]
    fn linear_dashpot_restitution_matches_the_closed_form() {
        for y in [0.01, 0.1, 0.5, 1.0] {
            let got = restitution_of(DampingLaw::LinearDashpot, 2.0, y);
            let want = dashpot_exact(y);
            // abs 1e-9 (RK4 at step 1e-4, the end of contact located by halving)
            assert!((got - want).abs() <= 1e-9, "y = {y}: {got} vs {want}");
        }
    }

    #[test]
    fn no_damping_is_elastic_and_inversion_round_trips() {
        for law in [DampingLaw::Viscoelastic, DampingLaw::LinearDashpot] {
            let e0 = restitution_of(law, 2.5, 0.0);
            assert!((e0 - 1.0).abs() <= 1e-8, "{law:?}: e(0) = {e0}");
            for e in [0.95, 0.7, 0.3] {
                let y = dimensionless_coefficient(law, 2.5, e);
                let back = restitution_of(law, 2.5, y);
                assert!(
                    (back - e).abs() <= 1e-9,
                    "{law:?} e={e}: y={y} gives {back}"
                );
            }
        }
    }

    #[test]
    fn coefficient_scales_with_the_collision_time() {
        // Hertz: T ∝ v^{-1/5}, so A(v) for fixed y grows as v^{-1/5} (rel 1e-12).
        let a1 = coefficient(DampingLaw::Viscoelastic, 2.5, 1.0, 0.5, 1.0, 0.1);
        let a2 = coefficient(DampingLaw::Viscoelastic, 2.5, 1.0, 0.5, 32.0, 0.1);
        assert!((a1 / a2 - 2.0).abs() <= 1e-12, "{}", a1 / a2);
    }
}
