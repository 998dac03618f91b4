//! Physical scenes: Hertz spheres from material data, and the paper's rescaling to computer
//! units.
//!
//! ## Material → SI chain (paper eqs. 3–4)
//! - mass `m_i = ρ_i · 4/3 · π R_i³`,
//! - Hertz prefactor of contact `i,i+1`: `a = 2/(5 D) · sqrt(R_i R_{i+1} / (R_i + R_{i+1}))`,
//!   `D = 3/4 [(1−σ_i²)/Y_i + (1−σ_{i+1}²)/Y_{i+1}]` (eq. 4); a wall is a sphere of infinite
//!   radius, so the bead–wall prefactor is `2/(5 D) · sqrt(R)` with the wall's `Y`, `σ`.
//!
//! The prefactor is held at this sphere value for every exponent `n`, as in the paper (§2): the
//! SI number is kept and its unit is read as `kg s⁻² m^{−(n−2)}`.
//!
//! ## Rescaling to computer units (eqs. 10–11)
//! Time is rescaled, `t = β t̃` with `β = sqrt(m0 / (μ n0))`, where `μ = 10^⌊log10 a⌋` is the order
//! of magnitude of the prefactor, `m0` a typical mass and `n0` a typical exponent. Lengths stay in
//! metres. Eq. 11 reads `d²u/dt̃² = (β²/m_i) W_i + (β² μ n ã / m_i) δ^{n−1} …` with `ã = a/μ`; since
//! `β² μ = m0/n0`, this is eq. 7 (`m ü = W + n a δ^{n−1} …`) with
//!
//! | quantity | computer value |
//! |---|---|
//! | mass | `m̃ = m / m0` (1 for a typical bead) |
//! | prefactor | `ã / n0 = a β² / m0 = a / (μ n0)` |
//! | force `W` | `W β² / m0` (gravity: `g̃ = g β²`) |
//! | velocity | `v β` (m per computer time unit) |
//! | time | `t / β` |
//! | energy | `E β² / m0` |
//!
//! Defaults: `m0` = mass of bead 0 (the striker), `n0` = 2.5 (the Hertz exponent the prefactor
//! is computed for; a fixed `n0` keeps one clock for scenes with different exponents), `μ` =
//! order of magnitude of contact 0's prefactor; each can be set in `[units]`. The choice only
//! changes the time unit, never the physics in SI. `time_scale = "si"` skips the rescaling
//! (mass in kg, time in s, prefactor in SI).
//!
//! ## Checking the paper's striker value
//! For the steel beads of Table 1 (R = 4 mm, Y = 2.26·10¹¹ Pa, σ = 0.3, ρ = 7650 kg/m³):
//! `m = 2.0508 g` (Table 1 says 2.05 g: consistent), `D = 6.0398·10⁻¹² Pa⁻¹`,
//! `a = 2.9618·10⁹`, `μ = 10⁹`, `ã = 2.9618`; with `n0 = 2.5`, `β = 9.0572·10⁻⁷ s` and the
//! computer prefactor is `ã/n0 = 1.18471`.
//! The paper states `v⁽⁰⁾ = 1·10⁷` in computer units and "approximately 0.11 m s⁻²" in SI. With
//! velocities scaling as `ṽ = v β`, 0.11 m/s is `9.963·10⁻⁸ ≈ 1·10⁻⁷` computer units, and
//! `1·10⁻⁷` is 0.1104 m/s; `1·10⁷` would be `1.1·10¹³ m/s`. So the printed value has lost the
//! minus sign of its exponent (and the unit should read m s⁻¹): the paper's striker is
//! `v⁽⁰⁾ = 1·10⁻⁷` computer units = 0.110 m/s with `n0 = 2.5` (with `n0 = 3.0` the same 0.11 m/s
//! would be `9.09·10⁻⁸`). Physical scenes therefore take velocities in SI through the `*_si`
//! keys (`striker_si = 0.11`), converted with `β`; plain keys stay in computer units.

/// Default typical exponent `n0` of the paper's time scale (Hertz spheres).
pub const DEFAULT_N0: f64 = 2.5;

/// Density × volume of a sphere: `ρ · 4/3 · π R³` (kg).
pub fn sphere_mass(radius: f64, density: f64) -> f64 {
    density * 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3)
}

/// The dissipative constant `A` (s) of viscoelastic spheres of one material (Brilliantov,
/// Spahn, Hertzsch & Pöschel, Phys. Rev. E 53, 5382 (1996), eq. 24; Pöschel & Schwager,
/// *Computational Granular Dynamics*, 2005, eq. 2.15):
/// `A = (1/3)·(3η₂ − η₁)²/(3η₂ + 2η₁) · (1 − ν²)(1 − 2ν)/(Y ν²)`, with `η₁` the shear and
/// `η₂` the bulk viscosity (Pa·s), `Y` Young's modulus (Pa) and `ν` Poisson's ratio (> 0).
/// The damped Hertz force is then `F = ρ(δ^{3/2} + (3/2) A δ^{1/2} δ̇)` (Kuwabara–Kono).
/// Without viscosity (`η₁ = η₂ = 0`) `A = 0`, the limit along any ray `η → 0`.
pub fn brilliantov_a(young: f64, poisson: f64, shear: f64, bulk: f64) -> f64 {
    if shear == 0.0 && bulk == 0.0 {
        return 0.0;
    }
    let visc = (3.0 * bulk - shear).powi(2) / (3.0 * bulk + 2.0 * shear) / 3.0;
    visc * (1.0 - poisson * poisson) * (1.0 - 2.0 * poisson) / (young * poisson * poisson)
}

/// `D = 3/4 [(1−σ₁²)/Y₁ + (1−σ₂²)/Y₂]` (paper eq. 4), in Pa⁻¹.
pub fn hertz_d(young1: f64, poisson1: f64, young2: f64, poisson2: f64) -> f64 {
    0.75 * ((1.0 - poisson1 * poisson1) / young1 + (1.0 - poisson2 * poisson2) / young2)
}

/// Hertz prefactor of two spheres, `a = 2/(5D) · sqrt(R₁R₂/(R₁+R₂))` (paper eq. 3), SI units.
pub fn hertz_prefactor(r1: f64, r2: f64, d: f64) -> f64 {
    2.0 / (5.0 * d) * (r1 * r2 / (r1 + r2)).sqrt()
}

/// Hertz prefactor of a sphere of radius `r` against a flat wall, `2/(5D) · sqrt(R)`, SI units.
pub fn hertz_wall_prefactor(r: f64, d: f64) -> f64 {
    2.0 / (5.0 * d) * r.sqrt()
}

/// Conversion between SI and computer units of a physical scene.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct UnitScales {
    /// Mass unit `m0` in kg (computer mass = kg / m0).
    pub mass: f64,
    /// Time unit `β` in s (computer time = s / β).
    pub time: f64,
    /// `μ`, the order of magnitude of the prefactor (1 for `time_scale = "si"`).
    pub mu: f64,
    /// `n0`, the typical exponent used in `β` (1 for `time_scale = "si"`).
    pub n0: f64,
}

impl UnitScales {
    /// The paper's scaling (eq. 10): `β = sqrt(m0 / (μ n0))`.
    pub fn paper(m0: f64, mu: f64, n0: f64) -> Self {
        Self {
            mass: m0,
            time: (m0 / (mu * n0)).sqrt(),
            mu,
            n0,
        }
    }

    /// No rescaling: computer units are kg, s, m.
    pub fn si() -> Self {
        Self {
            mass: 1.0,
            time: 1.0,
            mu: 1.0,
            n0: 1.0,
        }
    }

    /// `μ = 10^⌊log10 a⌋`, the order of magnitude of a (positive) prefactor.
    pub fn order_of_magnitude(a: f64) -> f64 {
        10f64.powf(a.log10().floor())
    }

    /// Computer mass of `m` kg.
    pub fn mass(&self, kg: f64) -> f64 {
        kg / self.mass
    }

    /// Computer prefactor of an SI prefactor: `a β² / m0`.
    pub fn prefactor(&self, a: f64) -> f64 {
        a * self.time * self.time / self.mass
    }

    /// Computer force of `w` newtons: `W β² / m0`.
    pub fn force(&self, w: f64) -> f64 {
        w * self.time * self.time / self.mass
    }

    /// Computer acceleration of `g` m/s²: `g β²`.
    pub fn acceleration(&self, g: f64) -> f64 {
        g * self.time * self.time
    }

    /// Computer velocity of `v` m/s: `v β`.
    pub fn velocity(&self, v: f64) -> f64 {
        v * self.time
    }

    /// Computer energy of `e` joules: `E β² / m0` (force × length, lengths unchanged).
    pub fn energy(&self, e: f64) -> f64 {
        e * self.time * self.time / self.mass
    }

    /// Computer time of `t` seconds: `t / β`.
    pub fn time(&self, t: f64) -> f64 {
        t / self.time
    }
}
