//! A solitary wave of given peak velocity (or energy) on a uniform chain (mass `m`, prefactor
//! `a`), and its placement on a chain: the formulas are in the parent module's docs.

use super::{SolitaryError, UnitProfile};
use std::ops::RangeInclusive;

/// Direction of travel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Towards increasing bead index (`c > 0`).
    Right,
    /// Towards decreasing bead index (the mirror image `u_{K+x} → −u_{K−x}`).
    Left,
}

/// A solitary wave: the scaled profile with its speed `c` and amplitude scale `λ`.
#[derive(Clone, Debug)]
pub struct Wave {
    /// Bead mass `m`.
    pub mass: f64,
    /// Contact prefactor `a`.
    pub prefactor: f64,
    /// Speed `c` in bead spacings per unit time.
    pub speed: f64,
    /// `λ = (m c² / (n a))^{1/(n−2)}`: the overlap is `λ S`.
    pub scale: f64,
    /// Peak bead velocity `v_m` (the centre bead's velocity at placement).
    pub peak_velocity: f64,
    /// The scaled profile of the exponent.
    pub profile: UnitProfile,
}

impl Wave {
    /// The wave of peak velocity `v_m > 0`: `c = [(v_m / W(1/2)) (n a / m)^{1/(n−2)}]^{(n−2)/n}`.
    pub fn with_peak_velocity(
        profile: UnitProfile,
        mass: f64,
        prefactor: f64,
        v_m: f64,
    ) -> Result<Self, SolitaryError> {
        if !(v_m.is_finite() && v_m > 0.0) {
            return Err(SolitaryError::PeakVelocity(v_m));
        }
        let n = profile.exponent;
        let wm = profile.w_at(0.5);
        // In logarithms, so that v_m over many decades and n near 2 stay in range.
        let ln_c = (n - 2.0) / n * ((v_m / wm).ln() + (n * prefactor / mass).ln() / (n - 2.0));
        let speed = ln_c.exp();
        let scale = ((2.0 * ln_c + (mass / (n * prefactor)).ln()) / (n - 2.0)).exp();
        Ok(Self {
            mass,
            prefactor,
            speed,
            scale,
            peak_velocity: v_m,
            profile,
        })
    }

    /// The wave of energy `E > 0`: `v_m = sqrt(E / (κ(n) m))`.
    pub fn with_energy(
        profile: UnitProfile,
        mass: f64,
        prefactor: f64,
        energy: f64,
    ) -> Result<Self, SolitaryError> {
        if !(energy.is_finite() && energy > 0.0) {
            return Err(SolitaryError::Energy(energy));
        }
        let v_m = (energy / (profile.energy_constant() * mass)).sqrt();
        Self::with_peak_velocity(profile, mass, prefactor, v_m)
    }

    /// Contact exponent `n`.
    pub fn exponent(&self) -> f64 {
        self.profile.exponent
    }

    /// Total energy `E = κ(n) m v_m²`.
    pub fn energy(&self) -> f64 {
        self.profile.energy_constant() * self.mass * self.peak_velocity.powi(2)
    }

    /// `⟨kinetic⟩ / ⟨total⟩` over a period: `n / (n + 2)` (virial theorem, module docs).
    pub fn kinetic_fraction(&self) -> f64 {
        let n = self.exponent();
        n / (n + 2.0)
    }

    /// Overlap `λ S(y)` of the contact at offset `y` from the centre bead (contacts sit at
    /// half-integer `y`; positive `y` is ahead of a right-moving wave).
    pub fn overlap(&self, y: f64) -> f64 {
        self.scale * self.profile.s_at(y)
    }

    /// Velocity `c λ W(x + 1/2)` of the bead at offset `x` ahead of the centre bead (right-moving).
    pub fn velocity(&self, x: f64) -> f64 {
        self.speed * self.scale * self.profile.w_at(x + 0.5)
    }

    /// The beads `u`, `v` of the wave centred at bead `at` of a chain of `nb` beads; fails where
    /// the support (and the contacts on its two sides) does not fit in the chain.
    pub fn place(&self, at: usize, dir: Direction, nb: usize) -> Result<Placement, SolitaryError> {
        let b = self.profile.support;
        if at < b + 1 || at + b + 2 > nb {
            return Err(SolitaryError::DoesNotFit {
                first: at as i64 - b as i64 - 1,
                last: at + b + 1,
                support: b,
                n: self.exponent(),
                chain_last: nb - 1,
            });
        }
        let (lo, hi) = (at - b, at + b);
        // Right-moving: u_k = Σ_{j=k}^{hi} r_j (beads ahead unshifted), D for the beads behind.
        let r: Vec<f64> = (lo - 1..=hi)
            .map(|j| self.overlap(j as f64 + 0.5 - at as f64))
            .collect();
        let mut u = vec![0.0; hi - lo + 1];
        let mut acc = 0.0;
        for k in (lo..=hi).rev() {
            acc += r[k + 1 - lo];
            u[k - lo] = acc;
        }
        let behind = acc + r[0];
        let v: Vec<f64> = (lo..=hi)
            .map(|k| self.velocity(k as f64 - at as f64))
            .collect();
        Ok(match dir {
            Direction::Right => Placement {
                lo,
                hi,
                u,
                v,
                behind,
                direction: dir,
            },
            Direction::Left => Placement {
                lo,
                hi,
                u: u.iter().rev().map(|x| -x).collect(),
                v: v.iter().rev().map(|x| -x).collect(),
                behind: -behind,
                direction: dir,
            },
        })
    }
}

/// A placed wave: `u`, `v` of beads `lo..=hi`, and the shift of every bead behind it.
#[derive(Clone, Debug, PartialEq)]
pub struct Placement {
    /// First bead of the support.
    pub lo: usize,
    /// Last bead of the support.
    pub hi: usize,
    /// Displacements of beads `lo..=hi`.
    pub u: Vec<f64>,
    /// Velocities of beads `lo..=hi`.
    pub v: Vec<f64>,
    /// Displacement of every bead behind the wave (`Σ r`, negative for a left-moving wave).
    pub behind: f64,
    /// Direction of travel.
    pub direction: Direction,
}

impl Placement {
    /// Beads whose mass the wave feels (the support and one bead on either side).
    pub fn beads(&self) -> RangeInclusive<usize> {
        self.lo - 1..=self.hi + 1
    }

    /// Contacts the wave compresses (the support's and the two at its ends).
    pub fn contacts(&self) -> RangeInclusive<usize> {
        self.lo - 1..=self.hi
    }

    /// Adds the wave to `u0`, `v0` (superposition with the chain's other initial state).
    pub fn add_to(&self, u0: &mut [f64], v0: &mut [f64]) {
        for k in self.lo..=self.hi {
            u0[k] += self.u[k - self.lo];
            v0[k] += self.v[k - self.lo];
        }
        let behind = match self.direction {
            Direction::Right => 0..self.lo,
            Direction::Left => self.hi + 1..u0.len(),
        };
        for k in behind {
            u0[k] += self.behind;
        }
    }
}
