//! The force kernel of dissipative chains: accelerations `ü = f(u, u̇)` with the contact laws of
//! [`super::law`] (`F(δ, δ̇)` per contact, `δ̇_{i,i+1} = u̇_i − u̇_{i+1}`), the Jacobian blocks
//! `∂F/∂δ` and `∂F/∂δ̇` for the implicit method, and the dissipated power
//! `P = Σ_c (F_c − F_el,c)·δ̇_c` (the right-hand side of the energy balance
//! `d(E_kin + E_pot)/dt = −P`).
//!
//! Only scenes that declare damping run this kernel ([`Chain::damping`] is `Some`); the
//! conservative kernel of the paper's model stays as it was, so power-law results are unchanged
//! bit for bit.

use super::law::{ContactLaw, LinearDashpot, Viscoelastic};
use super::{Chain, JACOBIAN_FLOOR};
use serde::{Deserialize, Serialize};

/// Which dissipative law the contacts follow (see [`super::law`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum DampingLaw {
    /// `F = F_el + A F_el'(δ) δ̇` (Kuwabara–Kono); the coefficient is `A` (a time).
    Viscoelastic,
    /// `F = F_el + c δ̇`; the coefficient is `c` (force per velocity).
    LinearDashpot,
}

impl DampingLaw {
    /// The name used in scene files (`[chain] law = "..."`).
    pub fn name(self) -> &'static str {
        match self {
            DampingLaw::Viscoelastic => "viscoelastic",
            DampingLaw::LinearDashpot => "linear_dashpot",
        }
    }
}

/// Dissipation of a chain: one law for every contact and wall, a coefficient each.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Damping {
    /// The law.
    pub law: DampingLaw,
    /// Coefficient per contact (`N−1`): `A` or `c`, ≥ 0.
    pub contact: Vec<f64>,
    /// Coefficient of the left wall contact (unused without a soft left wall).
    pub left_wall: f64,
    /// Coefficient of the right wall contact (unused without a soft right wall).
    pub right_wall: f64,
}

/// Where the kernel writes: accelerations (may be empty: power only) and, when `STIFF`, the
/// Jacobian blocks `kd = ∂F/∂δ`, `kv = ∂F/∂δ̇` (layout of [`Chain::accel_stiffness`]).
struct Out<'a> {
    acc: &'a mut [f64],
    kd: &'a mut [f64],
    kv: &'a mut [f64],
}

impl Chain {
    /// Is any contact or wall dissipative?
    pub fn is_dissipative(&self) -> bool {
        self.damping.is_some()
    }

    /// Accelerations `f(u, v)` of beads `lo..lo+u.len()`; returns the dissipated power of the
    /// range's contacts (and walls at the chain ends). A conservative chain gives
    /// [`Chain::accel`] and 0.
    pub fn accel_v(&self, lo: usize, u: &[f64], v: &[f64], acc: &mut [f64]) -> f64 {
        match &self.damping {
            None => {
                self.accel(lo, u, acc);
                0.0
            }
            Some(d) => self.damped::<false>(
                d,
                lo,
                u,
                v,
                Out {
                    acc,
                    kd: &mut [],
                    kv: &mut [],
                },
            ),
        }
    }

    /// The force of damped contact `c` at overlap `delta > 0` and rate `rate` before its clip
    /// at 0 (`F_el + F_d`, [`super::law`]): negative where the law clips it. `None` for a
    /// conservative chain or `delta ≤ 0`.
    pub fn unclipped_force(&self, c: usize, delta: f64, rate: f64) -> Option<f64> {
        let d = self.damping.as_ref()?;
        unclipped(
            d.law,
            (self.exponent[c], self.prefactor[c]),
            d.contact[c],
            delta,
            rate,
        )
    }

    /// [`Self::unclipped_force`] of the soft wall at `side` (0 left, 1 right) at its overlap
    /// `delta` and rate `rate`; `None` also where that wall is not soft.
    pub fn unclipped_wall_force(&self, side: u8, delta: f64, rate: f64) -> Option<f64> {
        let d = self.damping.as_ref()?;
        let (w, g) = if side == 0 {
            (self.left_wall.as_ref(), d.left_wall)
        } else {
            (self.right_wall.as_ref(), d.right_wall)
        };
        let w = w.filter(|w| w.restitution.is_none())?;
        unclipped(d.law, (w.exponent, w.prefactor), g, delta, rate)
    }

    /// [`Chain::accel_v`] plus the Jacobian blocks: `kd[c] = ∂F_c/∂δ`, `kv[c] = ∂F_c/∂δ̇` for
    /// the range's contacts, `[m−1]`/`[m]` the left/right wall (each of length `m + 1`). A
    /// conservative chain leaves `kv` untouched.
    pub fn accel_stiffness_v(
        &self,
        lo: usize,
        u: &[f64],
        v: &[f64],
        acc: &mut [f64],
        kd: &mut [f64],
        kv: &mut [f64],
    ) -> f64 {
        match &self.damping {
            None => {
                self.accel_stiffness(lo, u, acc, kd);
                0.0
            }
            Some(d) => self.damped::<true>(d, lo, u, v, Out { acc, kd, kv }),
        }
    }

    fn damped<const STIFF: bool>(
        &self,
        d: &Damping,
        lo: usize,
        u: &[f64],
        v: &[f64],
        out: Out,
    ) -> f64 {
        match d.law {
            DampingLaw::Viscoelastic => {
                self.damped_kernel::<_, STIFF>(d, lo, u, v, out, |n, a, g| Viscoelastic {
                    n,
                    a,
                    tau: g,
                })
            }
            DampingLaw::LinearDashpot => {
                self.damped_kernel::<_, STIFF>(d, lo, u, v, out, |n, a, g| LinearDashpot {
                    n,
                    a,
                    c: g,
                })
            }
        }
    }

    /// The kernel, generic over the law (`make(n, a, coefficient)`). No allocation.
    fn damped_kernel<L: ContactLaw, const STIFF: bool>(
        &self,
        d: &Damping,
        lo: usize,
        u: &[f64],
        v: &[f64],
        out: Out,
        make: impl Fn(f64, f64, f64) -> L,
    ) -> f64 {
        let m = u.len();
        let Out { acc, kd, kv } = out;
        let with_acc = !acc.is_empty();
        if with_acc {
            match &self.field {
                Some(w) => acc.copy_from_slice(&w[lo..lo + m]),
                None => acc.fill(0.0),
            }
        }
        let pre = self.precompression.as_deref();
        let mut power = 0.0;
        let (mut d_max, mut d_soft) = (0.0_f64, f64::INFINITY);
        for c in 0..m - 1 {
            let g = lo + c;
            // same rounding as the conservative kernel: (u_c − u_{c+1}) + Δ
            let delta = match pre {
                Some(p) => u[c] - u[c + 1] + p[g],
                None => u[c] - u[c + 1],
            };
            let e = make(self.exponent[g], self.prefactor[g], d.contact[g])
                .eval(delta, v[c] - v[c + 1]);
            power += e.power;
            if with_acc {
                acc[c] -= e.force;
                acc[c + 1] += e.force;
            }
            if STIFF {
                kd[c] = e.d_delta;
                kv[c] = e.d_rate;
                d_max = d_max.max(delta);
                if self.exponent[g] < 2.0 && delta > 0.0 {
                    d_soft = d_soft.min(delta);
                }
            }
        }
        if STIFF {
            if d_soft < JACOBIAN_FLOOR * d_max {
                self.regularise_any(lo, u, JACOBIAN_FLOOR * d_max, kd);
            }
            kd[m - 1..=m].fill(0.0);
            kv[m - 1..=m].fill(0.0);
        }
        let walls = Out {
            acc: &mut *acc,
            kd: &mut *kd,
            kv: &mut *kv,
        };
        power = self.damped_walls::<L, STIFF>(d, lo, u, v, walls, &make, power);
        if with_acc {
            for (ai, mi) in acc.iter_mut().zip(&self.mass[lo..lo + m]) {
                *ai /= mi;
            }
        }
        power
    }

    /// The soft walls' terms of [`Self::damped_kernel`] at the chain's ends (when `lo..lo + m`
    /// holds them), added to `power` in order (left, then right) and returned.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn damped_walls<L: ContactLaw, const STIFF: bool>(
        &self,
        d: &Damping,
        lo: usize,
        u: &[f64],
        v: &[f64],
        out: Out,
        make: &impl Fn(f64, f64, f64) -> L,
        mut power: f64,
    ) -> f64 {
        let m = u.len();
        let Out { acc, kd, kv } = out;
        let with_acc = !acc.is_empty();
        if lo == 0 {
            if let Some(w) = self.left_wall.as_ref().filter(|w| w.restitution.is_none()) {
                let e =
                    make(w.exponent, w.prefactor, d.left_wall).eval(w.precompression - u[0], -v[0]);
                power += e.power;
                if with_acc {
                    acc[0] += e.force;
                }
                if STIFF {
                    kd[m - 1] = e.d_delta;
                    kv[m - 1] = e.d_rate;
                }
            }
        }
        if lo + m == self.len() {
            if let Some(w) = self.right_wall.as_ref().filter(|w| w.restitution.is_none()) {
                let e = make(w.exponent, w.prefactor, d.right_wall)
                    .eval(w.precompression + u[m - 1], v[m - 1]);
                power += e.power;
                if with_acc {
                    acc[m - 1] -= e.force;
                }
                if STIFF {
                    kd[m] = e.d_delta;
                    kv[m] = e.d_rate;
                }
            }
        }
        power
    }
}

/// `F_el + F_d` of law `law` with exponent and prefactor `(n, a)` and coefficient `g` at
/// overlap `delta > 0` and rate `rate` (`None` for `delta ≤ 0`).
fn unclipped(law: DampingLaw, (n, a): (f64, f64), g: f64, delta: f64, rate: f64) -> Option<f64> {
    if delta.is_nan() || delta <= 0.0 {
        return None;
    }
    let (f_el, k) = super::contact_force_stiffness(n, a, delta);
    Some(match law {
        DampingLaw::Viscoelastic => f_el + g * k * rate,
        DampingLaw::LinearDashpot => f_el + g * rate,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Wall;

    fn chain(law: DampingLaw, g: f64) -> Chain {
        Chain {
            mass: vec![1.0, 2.0, 1.5, 1.0],
            exponent: vec![2.5, 3.0, 2.5],
            prefactor: vec![0.4, 0.7, 1.1],
            precompression: Some(vec![0.01, 0.0, 0.02]),
            field: Some(vec![0.1, 0.0, -0.2, 0.0]),
            left_wall: Some(Wall {
                exponent: 2.5,
                prefactor: 1.0,
                precompression: 0.05,
                restitution: None,
            }),
            right_wall: None,
            hard: None,
            damping: Some(Damping {
                law,
                contact: vec![g; 3],
                left_wall: g,
                right_wall: g,
            }),
        }
    }

    const U: [f64; 4] = [0.02, -0.1, -0.05, -0.3];
    const V: [f64; 4] = [0.3, 0.1, -0.4, 0.2];

    #[test]
    fn zero_damping_gives_the_conservative_accelerations_bit_for_bit() {
        for law in [DampingLaw::Viscoelastic, DampingLaw::LinearDashpot] {
            let c = chain(law, 0.0);
            let mut plain = c.clone();
            plain.damping = None;
            let (mut a, mut b) = ([0.0; 4], [0.0; 4]);
            let p = c.accel_v(0, &U, &V, &mut a);
            plain.accel(0, &U, &mut b);
            assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits), "{law:?}");
            assert_eq!(p, 0.0);
        }
    }

    #[test]
    fn damped_forces_obey_newtons_third_law_and_the_power_balance() {
        // Σ m a = Σ W + wall force; −Σ F·v over the contacts = P + d(PE)/dt (rel 1e-12).
        for law in [DampingLaw::Viscoelastic, DampingLaw::LinearDashpot] {
            let c = chain(law, 0.3);
            let mut a = [0.0; 4];
            let p = c.accel_v(0, &U, &V, &mut a);
            assert!(p > 0.0, "{law:?}: P = {p}");
            // Power of all forces on the beads = dKE/dt; field power Σ W v; dPE_el/dt by
            // a finite difference along the velocity.
            let de_kin: f64 = (0..4).map(|i| c.mass[i] * a[i] * V[i]).sum();
            let field: f64 = c
                .field
                .as_ref()
                .unwrap()
                .iter()
                .zip(V)
                .map(|(w, v)| w * v)
                .sum();
            let h = 1e-7;
            let up: Vec<f64> = U.iter().zip(V).map(|(u, v)| u + h * v).collect();
            let um: Vec<f64> = U.iter().zip(V).map(|(u, v)| u - h * v).collect();
            let pe = |x: &[f64]| {
                c.potential_energy(x)
                    + c.field
                        .as_ref()
                        .unwrap()
                        .iter()
                        .zip(x)
                        .map(|(w, y)| w * y)
                        .sum::<f64>()
            };
            let de_pot = (pe(&up) - pe(&um)) / (2.0 * h);
            let balance = de_kin + de_pot - field + p;
            assert!(
                balance.abs() <= 1e-7 * (p + de_kin.abs()),
                "{law:?}: {balance}"
            );
        }
    }

    #[test]
    fn damped_jacobian_matches_finite_differences_of_the_accelerations() {
        for law in [DampingLaw::Viscoelastic, DampingLaw::LinearDashpot] {
            let c = chain(law, 0.3);
            let (mut a, mut kd, mut kv) = ([0.0; 4], [0.0; 5], [0.0; 5]);
            c.accel_stiffness_v(0, &U, &V, &mut a, &mut kd, &mut kv);
            // Contact 1 (beads 1, 2): ∂(m_2 a_2)/∂v_1 = kv[1]; ∂(m_2 a_2)/∂u_1 = kd[1].
            let h = 1e-7;
            let f2 = |u: &[f64], v: &[f64]| {
                let mut a = [0.0; 4];
                c.accel_v(0, u, v, &mut a);
                c.mass[2] * a[2]
            };
            let (mut vp, mut vm) = (V, V);
            vp[1] += h;
            vm[1] -= h;
            let dv = (f2(&U, &vp) - f2(&U, &vm)) / (2.0 * h);
            let (mut up, mut um) = (U, U);
            up[1] += h;
            um[1] -= h;
            let du = (f2(&up, &V) - f2(&um, &V)) / (2.0 * h);
            assert!(
                (kv[1] - dv).abs() <= 1e-6 * dv.abs() + 1e-9,
                "{law:?} kv {} vs {dv}",
                kv[1]
            );
            assert!(
                (kd[1] - du).abs() <= 1e-6 * du.abs() + 1e-9,
                "{law:?} kd {} vs {du}",
                kd[1]
            );
        }
    }
}
