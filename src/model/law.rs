//! Contact laws: the force a contact exerts as a function of its overlap `δ` and overlap rate
//! `δ̇` (one small struct per law, after lumol's `energy/functions.rs`).
//!
//! Every law has the elastic part of the paper (eq. 1): `V = a δⁿ`, `F_el = n a δⁿ⁻¹`,
//! `k = F_el' = n (n−1) a δⁿ⁻²`. The dissipative laws add a force along `δ̇`:
//!
//! - [`Power`]: `F = F_el` (conservative; the paper's model and the default).
//! - [`Viscoelastic`]: `F = F_el + A·F_el'(δ)·δ̇`, Kuwabara & Kono (1987) and Brilliantov,
//!   Spahn, Hertzsch & Pöschel, Phys. Rev. E 53, 5382 (1996), eq. (12), there for Hertz
//!   (`n = 5/2`: `F = k_H (δ^{3/2} + (3/2) A δ^{1/2} δ̇)`), here for any exponent. `A` (a time)
//!   is the dissipative constant of the material.
//! - [`LinearDashpot`]: `F = F_el + c·δ̇`, the DEM spring–dashpot (Cundall & Strack 1979) with
//!   damping coefficient `c` (force per velocity).
//!
//! A contact never pulls: the force is clipped at 0 (`F = max(0, F_el + F_damp)`), so while the
//! beads separate fast enough the force vanishes before `δ` does (Schwager & Pöschel, Granular
//! Matter 9, 465 (2007)). Open contacts (`δ ≤ 0`) exert nothing.
//!
//! **Energy.** The beads lose energy at the rate `P = (F − F_el)·δ̇ ≥ 0` (with the clipped `F`:
//! the damping force where it acts, `−F_el δ̇` while clipped, when `δ̇ < 0`), so
//! `E_kin + Σ a δⁿ + E_dissipated` is conserved, with `E_dissipated = ∫ P dt`.

/// A contact law: force and Jacobian at overlap `delta > 0` and overlap rate `rate`.
pub trait ContactLaw: Copy {
    /// Whether the law conserves energy (no velocity dependence).
    const CONSERVATIVE: bool;
    /// `(F, ∂F/∂δ, ∂F/∂δ̇, P)` for `delta > 0`: the clipped force, its derivatives (0 where it
    /// is clipped) and the dissipated power `P = (F − F_el)·δ̇`. `delta ≤ 0` gives zeros.
    fn eval(&self, delta: f64, rate: f64) -> Eval;
    /// Potential energy `a δⁿ` of the elastic part (0 for `delta ≤ 0`).
    fn potential(&self, delta: f64) -> f64;
}

/// A contact law evaluated at one state.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Eval {
    /// Force `F ≥ 0` (pushing the beads apart).
    pub force: f64,
    /// `∂F/∂δ`.
    pub d_delta: f64,
    /// `∂F/∂δ̇`.
    pub d_rate: f64,
    /// Dissipated power `(F − F_el)·δ̇ ≥ 0`.
    pub power: f64,
}

/// The elastic part: `(F_el, k = F_el')` of `V = a δⁿ` at `delta > 0`, via
/// [`super::contact_force_stiffness`].
#[inline(always)]
fn elastic(n: f64, a: f64, delta: f64) -> (f64, f64) {
    super::contact_force_stiffness(n, a, delta)
}

/// A contact at exactly zero overlap that is closing (`δ = 0`, `δ̇ > 0`) already feels its
/// damping force (the limit `δ → 0⁺`): a dashpot then starts without a jump at a cluster's
/// first instant. `(F_el, k)` there: `(0, 2a)` for `n = 2`, `(0, 0)` otherwise (for `n < 2` the
/// limit is infinite; such contacts get no damping at first touch).
#[inline(always)]
fn touching(n: f64, a: f64, delta: f64, rate: f64) -> Option<(f64, f64)> {
    if delta > 0.0 {
        Some(elastic(n, a, delta))
    } else if delta == 0.0 && rate > 0.0 {
        Some((0.0, if n == 2.0 { 2.0 * a } else { 0.0 }))
    } else {
        None
    }
}

/// Clips `F = F_el + F_d` at 0 and assembles the result (derivatives vanish where clipped).
#[inline(always)]
fn clipped(f_el: f64, f_d: f64, rate: f64, d_delta: f64, d_rate: f64) -> Eval {
    let f = f_el + f_d;
    if f > 0.0 {
        Eval {
            force: f,
            d_delta,
            d_rate,
            power: f_d * rate,
        }
    } else {
        Eval {
            force: 0.0,
            d_delta: 0.0,
            d_rate: 0.0,
            power: -f_el * rate,
        }
    }
}

/// The paper's law `V = a δⁿ` (conservative).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Power {
    /// Exponent `n`.
    pub n: f64,
    /// Prefactor `a`.
    pub a: f64,
}

impl ContactLaw for Power {
    const CONSERVATIVE: bool = true;
    #[inline(always)]
    fn eval(&self, delta: f64, _rate: f64) -> Eval {
        let (force, d_delta) = elastic(self.n, self.a, delta);
        Eval {
            force,
            d_delta,
            d_rate: 0.0,
            power: 0.0,
        }
    }
    fn potential(&self, delta: f64) -> f64 {
        super::contact_potential(self.n, self.a, delta)
    }
}

/// Viscoelastic (Kuwabara–Kono) law `F = F_el + A F_el'(δ) δ̇`, clipped at 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viscoelastic {
    /// Exponent `n`.
    pub n: f64,
    /// Prefactor `a`.
    pub a: f64,
    /// Dissipative constant `A` (a time).
    pub tau: f64,
}

impl ContactLaw for Viscoelastic {
    const CONSERVATIVE: bool = false;
    #[inline(always)]
    fn eval(&self, delta: f64, rate: f64) -> Eval {
        let Some((f_el, k)) = touching(self.n, self.a, delta, rate) else {
            return Eval::default();
        };
        // k' = (n−2) k / δ, so ∂(A k δ̇)/∂δ = A (n−2) k δ̇ / δ (taken as k at δ = 0).
        let d_delta = if delta > 0.0 {
            k + self.tau * (self.n - 2.0) * k * rate / delta
        } else {
            k
        };
        clipped(f_el, self.tau * k * rate, rate, d_delta, self.tau * k)
    }
    fn potential(&self, delta: f64) -> f64 {
        super::contact_potential(self.n, self.a, delta)
    }
}

/// Spring–dashpot law `F = F_el + c δ̇`, clipped at 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearDashpot {
    /// Exponent `n`.
    pub n: f64,
    /// Prefactor `a`.
    pub a: f64,
    /// Damping coefficient `c` (force per overlap rate).
    pub c: f64,
}

impl ContactLaw for LinearDashpot {
    const CONSERVATIVE: bool = false;
    #[inline(always)]
    fn eval(&self, delta: f64, rate: f64) -> Eval {
        let Some((f_el, k)) = touching(self.n, self.a, delta, rate) else {
            return Eval::default();
        };
        clipped(f_el, self.c * rate, rate, k, self.c)
    }
    fn potential(&self, delta: f64) -> f64 {
        super::contact_potential(self.n, self.a, delta)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Central difference of `f` at `x` with step `h`.
    fn diff(f: impl Fn(f64) -> f64, x: f64, h: f64) -> f64 {
        (f(x + h) - f(x - h)) / (2.0 * h)
    }

    type Named = (
        &'static str,
        Box<dyn Fn(f64, f64) -> Eval>,
        Box<dyn Fn(f64) -> f64>,
    );

    fn laws() -> Vec<Named> {
        let p = Power { n: 2.5, a: 0.7 };
        let v = Viscoelastic {
            n: 2.5,
            a: 0.7,
            tau: 0.3,
        };
        let d = LinearDashpot {
            n: 3.0,
            a: 0.7,
            c: 0.2,
        };
        vec![
            (
                "power",
                Box::new(move |x, r| p.eval(x, r)),
                Box::new(move |x| p.potential(x)),
            ),
            (
                "visco",
                Box::new(move |x, r| v.eval(x, r)),
                Box::new(move |x| v.potential(x)),
            ),
            (
                "dashpot",
                Box::new(move |x, r| d.eval(x, r)),
                Box::new(move |x| d.potential(x)),
            ),
        ]
    }

    #[test]
    fn elastic_force_is_minus_the_energy_gradient_at_zero_rate() {
        // At δ̇ = 0 every law's force is dV/dδ (rel 1e-8, abs 1e-12).
        for (name, f, v) in laws() {
            for &x in &[0.05, 0.3, 1.2] {
                let fd = diff(&v, x, 1e-6);
                let got = f(x, 0.0).force;
                assert!(
                    (got - fd).abs() <= 1e-8 * fd.abs() + 1e-12,
                    "{name} δ={x}: {got} vs {fd}"
                );
            }
        }
    }

    #[test]
    fn jacobians_match_finite_differences() {
        // Unclipped states (δ̇ > 0, or small negative): ∂F/∂δ and ∂F/∂δ̇ to rel 1e-6, abs 1e-10.
        for (name, f, _) in laws() {
            for &(x, r) in &[(0.3, 0.5), (0.8, -0.1), (1.2, 0.0)] {
                let e = f(x, r);
                let dd = diff(|y| f(y, r).force, x, 1e-6);
                let dr = diff(|s| f(x, s).force, r, 1e-6);
                assert!(
                    (e.d_delta - dd).abs() <= 1e-6 * dd.abs() + 1e-10,
                    "{name} ∂δ {x},{r}: {} vs {dd}",
                    e.d_delta
                );
                assert!(
                    (e.d_rate - dr).abs() <= 1e-6 * dr.abs() + 1e-10,
                    "{name} ∂δ̇ {x},{r}: {} vs {dr}",
                    e.d_rate
                );
            }
        }
    }

    #[test]
    fn power_balance_holds_and_dissipation_is_never_negative() {
        // P = (F − F_el)·δ̇ ≥ 0 everywhere, including the clipped region (abs 1e-15).
        for (name, f, v) in laws() {
            for &x in &[1e-4, 0.1, 0.9] {
                for &r in &[-50.0, -1.0, -0.01, 0.0, 0.3, 4.0] {
                    let e = f(x, r);
                    let f_el = diff(&v, x, 1e-7 * x);
                    assert!(e.force >= 0.0, "{name}: pulls");
                    assert!(e.power >= -1e-15, "{name} δ={x} δ̇={r}: P = {}", e.power);
                    let p = (e.force - f_el) * r;
                    assert!(
                        (e.power - p).abs() <= 1e-5 * (p.abs() + f_el.abs() * r.abs()) + 1e-12,
                        "{name}: {} vs {p}",
                        e.power
                    );
                }
            }
        }
    }

    #[test]
    fn clipped_contact_exerts_no_force_before_the_overlap_closes() {
        // Separating fast at small overlap: F_el + damping < 0 → F = 0, derivatives 0.
        let v = Viscoelastic {
            n: 2.5,
            a: 1.0,
            tau: 0.5,
        };
        let e = v.eval(0.01, -1.0);
        assert_eq!((e.force, e.d_delta, e.d_rate), (0.0, 0.0, 0.0));
        let d = LinearDashpot {
            n: 2.5,
            a: 1.0,
            c: 0.5,
        };
        assert_eq!(d.eval(0.01, -1.0).force, 0.0);
        assert_eq!(d.eval(-0.01, 5.0), Eval::default());
    }

    #[test]
    fn zero_damping_is_the_power_law_bit_for_bit() {
        let p = Power { n: 2.5, a: 0.4 };
        let v = Viscoelastic {
            n: 2.5,
            a: 0.4,
            tau: 0.0,
        };
        let d = LinearDashpot {
            n: 2.5,
            a: 0.4,
            c: 0.0,
        };
        for &(x, r) in &[(0.3, 0.2), (1e-9, -3.0), (2.0, 7.0)] {
            let e = p.eval(x, r);
            for o in [v.eval(x, r), d.eval(x, r)] {
                assert_eq!(o.force.to_bits(), e.force.to_bits());
                assert_eq!(o.d_delta.to_bits(), e.d_delta.to_bits());
                assert_eq!(o.power, 0.0);
            }
        }
    }
}
