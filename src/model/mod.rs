//! The chain model: beads with Hertz-like contacts.
//!
//! Implements the paper's potential (eq. 1) `V = a δⁿ`, the overlap in displacement form (eq. 6)
//! `δ_{i,i+1} = (Δ_{i,i+1} + u_i − u_{i+1})₊` and the equation of motion (eq. 7)
//!
//! ```text
//! m_i ü_i = W_i + n_{i-1,i} a_{i-1,i} δ_{i-1,i}^{n-1} − n_{i,i+1} a_{i,i+1} δ_{i,i+1}^{n-1}
//! ```
//!
//! Contact `c` joins beads `c` and `c+1` (there are `N−1` contacts). Optional rigid walls act
//! on bead 0 (`δ_L = (Δ_L − u_0)₊`) and bead `N−1` (`δ_R = (Δ_R + u_{N−1})₊`).
//!
//! Effects are *declared*: `precompression` and `field` are `Option`s, and the force kernels are
//! monomorphised on whether they are present (`const` generics), so a scene without them runs a
//! loop that has no precompression or field code in it at all.
//!
//! All kernels work on a contiguous *range* of beads `lo..lo+m` so that the same code serves the
//! whole chain (dense engine) and a single contact cluster (hybrid engine). Contacts leaving the
//! range are ignored, except walls, which act when the range contains the chain end.

pub mod collision;
pub mod damped;
mod energy;
mod forces;
pub mod law;
pub mod profile;
pub mod restitution;

pub use damped::{Damping, DampingLaw};
use serde::{Deserialize, Serialize};

/// A rigid wall at one end of the chain.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Wall {
    /// Contact exponent `n` of the bead–wall contact.
    pub exponent: f64,
    /// Prefactor `a` of the bead–wall contact.
    pub prefactor: f64,
    /// Precompression `Δ` of the bead–wall contact (overlap at `u = 0`; negative = initial gap).
    pub precompression: f64,
    /// `Some(e)`: a hard wall (instantaneous reflection with restitution `e`; `exponent` and
    /// `prefactor` unused), only for the hybrid engine.
    pub restitution: Option<f64>,
}

/// Hard contacts: the `n → ∞` limit of the power law, instantaneous collisions with a
/// coefficient of restitution (hybrid engine only).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HardContacts {
    /// Per contact (`N−1`): `Some(e)` for a hard contact with restitution `e ∈ [0, 1]`, `None`
    /// for a soft (power-law) contact.
    pub restitution: Vec<Option<f64>>,
    /// Collapse interval `t_c` (Luding & McNamara's "TC model"): between free beads, an
    /// inelastic collision less than `t_c` after the previous one of the same contact, or one
    /// whose separating speed is below `|δ̈|·t_c`, makes the contact a resting (sticking) one;
    /// a collision with a bead in a cluster is elastic within `t_c` and separates at least at
    /// `|δ̈|·t_c`. Default: [`Scales::collapse_interval`].
    pub collapse_interval: f64,
}

/// Plain, serializable description of a chain (the resolved scene physics). The default is
/// the empty chain, without walls, precompression, field, hard contacts or damping.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Chain {
    /// Bead masses `m_i`, length `N`.
    pub mass: Vec<f64>,
    /// Contact exponents `n_{i,i+1}`, length `N−1`.
    pub exponent: Vec<f64>,
    /// Contact prefactors `a_{i,i+1}`, length `N−1`.
    pub prefactor: Vec<f64>,
    /// Precompression `Δ_{i,i+1}` per contact (length `N−1`), if the scene declares it.
    pub precompression: Option<Vec<f64>>,
    /// Constant external force `W_i` per bead (length `N`), if the scene declares a field.
    pub field: Option<Vec<f64>>,
    /// Wall at the left end (acts on bead 0).
    pub left_wall: Option<Wall>,
    /// Wall at the right end (acts on bead `N−1`).
    pub right_wall: Option<Wall>,
    /// Hard contacts, if the scene declares any.
    pub hard: Option<HardContacts>,
    /// Dissipative contact law and coefficients, if the scene declares damping (see
    /// [`law`]); `None` is the paper's conservative power law.
    pub damping: Option<Damping>,
}

/// Floor of the overlap at which the stiffness of an `n < 2` contact is evaluated for the
/// Newton matrix, relative to the largest overlap of the integrated range (see
/// [`Chain::accel_stiffness`]).
///
/// For `1 < n < 2` the contact stiffness `k = n (n−1) a δ^{n−2}` is unbounded as `δ → 0⁺`. Ahead
/// of a wave the overlaps fall off super-exponentially (each contact transmits `δ^{n−1}` of the
/// previous one), so a chain alternating n = 1.5 / 2.5 has n = 1.5 contacts at `δ ~ 1e-60` and
/// below, whose `k` was so large that Radau's Newton matrix treated them as rigid and the step
/// size fell to rounding level ("step size 6e-26 too small at t = 1e-10"). Their forces are at
/// most `(floor/δ_max)^{n−1}` of the wave's, so the Newton iteration converges with the stiffness
/// at `floor`; the right-hand side stays exact, so the solution is unchanged. Step counts were
/// flat for floors 1e-2 … 1e-10 and doubled at 1e-14 (10-bead n = 1.5/2.5 chain, paper units).
/// The dense engine stays slow on such chains (every closing/opening of an `n < 2` contact is a
/// square-root kink the error control must resolve); the hybrid engine handles them by events.
pub const JACOBIAN_FLOOR: f64 = 1e-6;

/// `δ^{n−2}` for `δ > 0`, with the common half-integer exponents (n = 2, 2.5, 3, 3.5, 4) done by
/// `sqrt`/multiplications instead of `powf` (about 5× cheaper; the branch is well predicted).
#[inline(always)]
pub fn pow_nm2(delta: f64, n: f64) -> f64 {
    let k = 2.0 * (n - 2.0);
    if k == 1.0 {
        delta.sqrt()
    } else if k == 2.0 {
        delta
    } else if k == 3.0 {
        delta * delta.sqrt()
    } else if k == 4.0 {
        delta * delta
    } else if k == 0.0 {
        1.0
    } else {
        delta.powf(n - 2.0)
    }
}

/// Force and stiffness of one power-law contact at overlap `delta` (≤ 0 means open).
///
/// Returns `(F, k)` with `F = n a δ^{n−1}` and `k = dF/dδ = n (n−1) a δ^{n−2}`; one `powf`.
#[inline(always)]
pub fn contact_force_stiffness(n: f64, a: f64, delta: f64) -> (f64, f64) {
    if delta > 0.0 {
        let p = pow_nm2(delta, n);
        let na = n * a;
        (na * p * delta, na * (n - 1.0) * p)
    } else {
        (0.0, 0.0)
    }
}

/// Force only, `n a δ^{n−1}` (0 for an open contact).
#[inline(always)]
pub fn contact_force(n: f64, a: f64, delta: f64) -> f64 {
    if delta > 0.0 {
        n * a * pow_nm2(delta, n) * delta
    } else {
        0.0
    }
}

/// Potential `a δⁿ` of one contact (0 for an open contact).
#[inline(always)]
pub fn contact_potential(n: f64, a: f64, delta: f64) -> f64 {
    if delta > 0.0 {
        a * delta.powf(n)
    } else {
        0.0
    }
}

impl Chain {
    /// Number of beads `N`.
    pub fn len(&self) -> usize {
        self.mass.len()
    }

    /// True when the chain has no beads (never true for a validated chain).
    pub fn is_empty(&self) -> bool {
        self.mass.is_empty()
    }

    /// Is contact `c` hard? (`Some(e)` with its restitution.)
    #[inline]
    pub fn hard_restitution(&self, c: usize) -> Option<f64> {
        self.hard.as_ref().and_then(|h| h.restitution[c])
    }

    /// Does the chain have any hard contact or hard wall?
    pub fn has_hard(&self) -> bool {
        self.hard.is_some()
            || self
                .left_wall
                .as_ref()
                .is_some_and(|w| w.restitution.is_some())
            || self
                .right_wall
                .as_ref()
                .is_some_and(|w| w.restitution.is_some())
    }

    /// Does the chain lose energy, so that runs report the dissipated energy `E_d` with every
    /// frame? Damped contacts ([`Chain::is_dissipative`]) lose it continuously; hard contacts and
    /// hard walls lose `½ μ (w² − s²)` per collision (restitution `e < 1`, and a collision that
    /// becomes a resting contact at any `e`; `src/engine/hybrid/hard.rs`).
    pub fn loses_energy(&self) -> bool {
        self.is_dissipative() || self.has_hard()
    }

    /// The chain's free fall in its field, which the engines integrate relative to: its
    /// acceleration `g = Σ W_i / Σ m_i` and the chain with the field less its common part,
    /// `W_i − m_i g` (`None` where that is 0 for every bead, a uniform field such as gravity:
    /// then the relative motion is computed with the very numbers of the chain without field).
    /// With `u = ½ g t² + w` the contact forces, which depend on differences only, are those of
    /// `w`, and the error weights follow the beads' motion relative to the falling chain, not
    /// the common velocity `g t` (20 free beads, g = 100, rtol 1e-8: relative motion off by
    /// 2.5e-4 in the dense engine, 1.6e-7 in the hybrid one). `(0, None)` without a field, and
    /// with walls (their forces depend on the absolute position, and they stop the common fall).
    pub fn free_fall(&self) -> (f64, Option<Chain>) {
        let Some(w) = &self.field else {
            return (0.0, None);
        };
        if self.left_wall.is_some() || self.right_wall.is_some() {
            return (0.0, None);
        }
        let uniform = w[0] / self.mass[0];
        let mut g = uniform;
        if w.iter().zip(&self.mass).any(|(wi, mi)| wi - mi * g != 0.0) {
            g = w.iter().sum::<f64>() / self.mass.iter().sum::<f64>();
        }
        if g == 0.0 {
            return (0.0, None);
        }
        let rest: Vec<f64> = w
            .iter()
            .zip(&self.mass)
            .map(|(wi, mi)| wi - mi * g)
            .collect();
        let field = rest.iter().any(|x| *x != 0.0).then_some(rest);
        (
            g,
            Some(Chain {
                field,
                ..self.clone()
            }),
        )
    }

    /// Overlap of contact `c` (between beads `c` and `c+1`) for displacements `ui`, `uj`.
    #[inline(always)]
    pub fn overlap(&self, c: usize, ui: f64, uj: f64) -> f64 {
        match &self.precompression {
            Some(d) => d[c] + ui - uj,
            None => ui - uj,
        }
    }

    /// Accelerations `a = f(u)` of beads `lo..lo+u.len()` (paper eq. 7).
    /// Two passes (forces, then accelerations; `forces.rs`), compiled for AVX2 where the
    /// processor has it: bit-identical to the one-pass [`Self::accel_one_pass`].
    pub fn accel(&self, lo: usize, u: &[f64], acc: &mut [f64]) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: `accel_avx2` requires AVX2, which the processor was just checked to have.
            return unsafe { self.accel_avx2(lo, u, acc) };
        }
        self.accel_dispatch(lo, u, acc)
    }

    /// The one-pass force loop [`Self::accel`] replaced, kept as the reference its results are
    /// tested against (bit for bit).
    pub fn accel_one_pass(&self, lo: usize, u: &[f64], acc: &mut [f64]) {
        match (self.precompression.is_some(), self.field.is_some()) {
            (false, false) => self.kernel::<false, false, false>(lo, u, acc, &mut []),
            (true, false) => self.kernel::<true, false, false>(lo, u, acc, &mut []),
            (false, true) => self.kernel::<false, true, false>(lo, u, acc, &mut []),
            (true, true) => self.kernel::<true, true, false>(lo, u, acc, &mut []),
        }
    }

    /// Accelerations plus contact stiffnesses: `k[c] = dF_c/dδ` for the `m−1` contacts inside the
    /// range, and `k[m−1]`, `k[m]` hold the left/right wall stiffness (0 when no wall applies).
    /// `k` must have length `m + 1`. Contacts with `n < 2` whose overlap is below
    /// [`JACOBIAN_FLOOR`] times the largest overlap of the range get the stiffness at that floor
    /// (a regularised Jacobian; the accelerations are exact).
    pub fn accel_stiffness(&self, lo: usize, u: &[f64], acc: &mut [f64], k: &mut [f64]) {
        debug_assert_eq!(k.len(), u.len() + 1);
        match (self.precompression.is_some(), self.field.is_some()) {
            (false, false) => self.kernel::<false, false, true>(lo, u, acc, k),
            (true, false) => self.kernel::<true, false, true>(lo, u, acc, k),
            (false, true) => self.kernel::<false, true, true>(lo, u, acc, k),
            (true, true) => self.kernel::<true, true, true>(lo, u, acc, k),
        }
    }

    /// The force kernel, monomorphised on the declared effects (`PRE`, `FIELD`) and on whether
    /// stiffnesses are wanted (`STIFF`). No allocation; one `powf` per closed contact.
    #[inline(always)]
    fn kernel<const PRE: bool, const FIELD: bool, const STIFF: bool>(
        &self,
        lo: usize,
        u: &[f64],
        acc: &mut [f64],
        k: &mut [f64],
    ) {
        let m = u.len();
        debug_assert_eq!(acc.len(), m);
        if FIELD {
            let w = &self.field.as_ref().expect("field declared")[lo..lo + m];
            acc.copy_from_slice(w);
        } else {
            acc.fill(0.0);
        }
        let n = &self.exponent[lo..lo + m - 1];
        let a = &self.prefactor[lo..lo + m - 1];
        let pre: &[f64] = if PRE {
            &self
                .precompression
                .as_ref()
                .expect("precompression declared")[lo..lo + m - 1]
        } else {
            &[]
        };
        // Largest overlap, and smallest positive overlap of an n < 2 contact (Jacobian floor).
        let (mut d_max, mut d_soft) = (0.0_f64, f64::INFINITY);
        for c in 0..m - 1 {
            let mut delta = u[c] - u[c + 1];
            if PRE {
                delta += pre[c];
            }
            if STIFF {
                let (f, s) = contact_force_stiffness(n[c], a[c], delta);
                acc[c] -= f;
                acc[c + 1] += f;
                k[c] = s;
                d_max = d_max.max(delta);
                if n[c] < 2.0 && delta > 0.0 {
                    d_soft = d_soft.min(delta);
                }
            } else {
                let f = contact_force(n[c], a[c], delta);
                acc[c] -= f;
                acc[c + 1] += f;
            }
        }
        if STIFF && d_soft < JACOBIAN_FLOOR * d_max {
            self.regularise_stiffness::<PRE>(lo, u, JACOBIAN_FLOOR * d_max, k);
        }
        // Walls: O(1) work outside the loop, only when the range holds the chain end.
        let (k_left, k_right) = self.wall_forces(lo, u, acc);
        if STIFF {
            k[m - 1] = k_left;
            k[m] = k_right;
        }
        for (ai, mi) in acc.iter_mut().zip(&self.mass[lo..lo + m]) {
            *ai /= mi;
        }
    }

    /// Adds the wall forces on the end beads of the range `lo..lo+u.len()` (when it holds a chain
    /// end) to `acc`; returns the left and right wall stiffnesses (0 where no wall acts).
    #[inline(always)]
    fn wall_forces(&self, lo: usize, u: &[f64], acc: &mut [f64]) -> (f64, f64) {
        let m = u.len();
        let (mut k_left, mut k_right) = (0.0, 0.0);
        if lo == 0 {
            if let Some(w) = &self.left_wall {
                let (f, s) =
                    contact_force_stiffness(w.exponent, w.prefactor, w.precompression - u[0]);
                acc[0] += f;
                k_left = s;
            }
        }
        if lo + m == self.len() {
            if let Some(w) = self.right_wall.as_ref().filter(|w| w.restitution.is_none()) {
                let (f, s) =
                    contact_force_stiffness(w.exponent, w.prefactor, w.precompression + u[m - 1]);
                acc[m - 1] -= f;
                k_right = s;
            }
        }
        (k_left, k_right)
    }

    /// The regularised Jacobian: every contact with `n < 2` and overlap `0 < δ < floor` gets the
    /// stiffness at `floor`, `n (n−1) a floor^{n−2}`, instead of its unbounded `δ^{n−2}`. Only
    /// the Newton matrix of the implicit method uses `k`; forces stay exact. Cold path.
    #[cold]
    fn regularise_stiffness<const PRE: bool>(
        &self,
        lo: usize,
        u: &[f64],
        floor: f64,
        k: &mut [f64],
    ) {
        for c in 0..u.len() - 1 {
            let (n, a) = (self.exponent[lo + c], self.prefactor[lo + c]);
            let mut delta = u[c] - u[c + 1];
            if PRE {
                delta += self.precompression.as_ref().map_or(0.0, |p| p[lo + c]);
            }
            if n < 2.0 && delta > 0.0 && delta < floor {
                k[c] = contact_force_stiffness(n, a, floor).1;
            }
        }
    }

    /// [`Self::regularise_stiffness`] for either precompression setting.
    fn regularise_any(&self, lo: usize, u: &[f64], floor: f64, k: &mut [f64]) {
        if self.precompression.is_some() {
            self.regularise_stiffness::<true>(lo, u, floor, k)
        } else {
            self.regularise_stiffness::<false>(lo, u, floor, k)
        }
    }

    /// Characteristic scales of a state, used to make tolerances unit-free.
    ///
    /// The velocity scale is the speed every bead would have if the whole energy
    /// `E = KE + contact PE` were kinetic in the lightest bead, `V = sqrt(2E/m_min)`; the length
    /// scale is the overlap at which the softest-reaching contact stores that energy,
    /// `L = max_c (E/a_c)^{1/n_c}` (and at least the largest precompression). Both scale exactly
    /// like the similarity law of a uniform chain (`v → λv` gives `L → λ^{2/n} L`), so a run at
    /// striker speed 1 and one at 1e-7 take the same steps after rescaling. When the state has no
    /// energy (and no field), falls back to `L = V = 1`.
    ///
    /// Per bead, the velocity scale is `V_i = sqrt(2E / max(m_i, m_E))` ([`Scales::bead_velocity`]),
    /// with `m_E` the lightest mass among the beads that hold energy initially (moving, or
    /// touching a compressed contact): a bead heavier than the energy carriers cannot move faster
    /// than `sqrt(2E/m_i)`, and a lighter one is held to the carriers' speed (it reaches about
    /// that speed when pushed, and `rtol·|v_i|` takes over if it goes faster). So neither a light
    /// bead loosens everyone's tolerance (`V` from `m_min` did) nor is it given a tolerance its
    /// speed never reaches. Uniform masses give `V_i = V` bit for bit.
    pub fn scales(&self, u: &[f64], v: &[f64]) -> Scales {
        let mut pe = 0.0;
        // Lightest energy carrier.
        let mut m_e = self
            .mass
            .iter()
            .zip(v)
            .filter(|(m, x)| *m * *x * *x > 0.0)
            .fold(f64::INFINITY, |acc, (m, _)| acc.min(*m));
        for c in 0..self.len() - 1 {
            let p = contact_potential(
                self.exponent[c],
                self.prefactor[c],
                self.overlap(c, u[c], u[c + 1]),
            );
            if p > 0.0 {
                m_e = m_e.min(self.mass[c]).min(self.mass[c + 1]);
            }
            pe += p;
        }
        let e = self.kinetic_energy(v) + pe;
        let m_min = self.mass.iter().cloned().fold(f64::INFINITY, f64::min);
        let mut length: f64 = 0.0;
        if e > 0.0 && e.is_finite() {
            for c in 0..self.len() - 1 {
                length = length.max((e / self.prefactor[c]).powf(1.0 / self.exponent[c]));
            }
        }
        if let Some(p) = &self.precompression {
            length = length.max(p.iter().fold(0.0_f64, |acc, x| acc.max(x.abs())));
        }
        let mut velocity = if e > 0.0 && e.is_finite() {
            (2.0 * e / m_min).sqrt()
        } else {
            0.0
        };
        if length <= 0.0 || !length.is_finite() {
            length = 1.0;
        }
        if velocity <= 0.0 || !velocity.is_finite() {
            // A field (or precompression) without kinetic energy: velocity scale of a fall over L.
            let g = self
                .field
                .as_ref()
                .map(|f| {
                    f.iter()
                        .zip(&self.mass)
                        .fold(0.0_f64, |acc, (w, m)| acc.max((w / m).abs()))
                })
                .unwrap_or(0.0);
            velocity = if g > 0.0 {
                (2.0 * g * length).sqrt()
            } else {
                1.0
            };
        }
        let (energy, mass) = if e > 0.0 && e.is_finite() {
            (e, if m_e.is_finite() { m_e } else { m_min })
        } else {
            (0.0, 0.0)
        };
        Scales {
            length,
            velocity,
            energy,
            mass,
        }
    }
}

/// `|e1 − e0|` relative to the energy scale `scale` (e.g. the largest
/// [`Chain::energy_scale`] reached); the absolute change when `scale` is 0 or not finite (a
/// system with no energy at all), so the result is never NaN or infinite for finite energies.
pub fn relative_energy_change(e0: f64, e1: f64, scale: f64) -> f64 {
    let d = (e1 - e0).abs();
    if scale > 0.0 && scale.is_finite() {
        d / scale
    } else {
        d
    }
}

/// Characteristic length and velocity of a run (see [`Chain::scales`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scales {
    /// Characteristic displacement/overlap.
    pub length: f64,
    /// Characteristic velocity `V = sqrt(2E/m_min)` (of the lightest bead).
    pub velocity: f64,
    /// The energy `E` the per-bead velocity scales come from; 0 when the velocity scale does
    /// not come from the energy (no energy: the field's fall speed, or 1), in which case every
    /// bead has scale `V`.
    #[serde(default)]
    pub energy: f64,
    /// `m_E`, the lightest mass among the beads holding energy initially: bead `i`'s own
    /// velocity scale is `V_i = sqrt(2E/max(m_i, m_E))` ([`Scales::bead_velocity`]).
    #[serde(default)]
    pub mass: f64,
}

/// Default collapse interval of hard contacts, as a fraction of the characteristic time `L/V`.
pub const COLLAPSE_FRACTION: f64 = 1e-6;

impl Scales {
    /// Characteristic time `L / V`.
    pub fn time(&self) -> f64 {
        self.length / self.velocity
    }

    /// Default collapse interval `t_c` of hard contacts and hard walls:
    /// [`COLLAPSE_FRACTION`]` · L/V` of the scene's initial state (not of its end time).
    pub fn collapse_interval(&self) -> f64 {
        COLLAPSE_FRACTION * self.time()
    }

    /// Velocity scale of a bead of mass `m_i`: `sqrt(2E/max(m_i, m_E))` (see
    /// [`Chain::scales`]), computed like `V` so that equal masses give exactly `V`. `V` itself
    /// when `energy` is 0.
    #[inline(always)]
    pub fn bead_velocity(&self, m_i: f64) -> f64 {
        if self.energy > 0.0 {
            (2.0 * self.energy / m_i.max(self.mass)).sqrt()
        } else {
            self.velocity
        }
    }
}

#[cfg(test)]
mod tests;
