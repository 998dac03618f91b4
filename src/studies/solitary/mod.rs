//! Exact solitary waves of the discrete sonic-vacuum chain (uniform `n > 2`, `a`, `m`, `Δ = 0`).
//!
//! With the overlap `r_k = u_k − u_{k+1}` of contact `k` (paper eq. 6 with `Δ = 0`), eq. 7 gives
//! `m r̈_k = F(r_{k+1}) − 2F(r_k) + F(r_{k−1})`, `F(δ) = n a δ₊^{n−1}`. A wave travelling right,
//! `r_k(t) = R(k − c t)`, solves the advance–delay equation
//!
//! ```text
//! m c² R''(ξ) = F(R(ξ+1)) − 2 F(R(ξ)) + F(R(ξ−1)),   R̂(q) = [4 sin²(q/2) / (m c² q²)] F̂(R)(q)
//! ```
//!
//! (English & Pego, Proc. AMS 133 (2005) 1763; Ahnert & Pikovsky, PRE 79 (2009) 026209).
//! **Scaling.** `R = λ S` with `λ = (m c² / (n a))^{1/(n−2)}` reduces it to the parameter-free
//! `S = K ∗ S^p`, `p = n − 1`, `K̂(q) = sinc²(q/2)` (`K` is the unit hat function), solved once
//! per exponent ([`UnitProfile`]) by Petviashvili's iteration on a periodic grid of `M` points per
//! bead spacing: `S ← μ^γ K ∗ S^p`, `μ = ⟨S, S⟩ / ⟨S, K ∗ S^p⟩`, `γ = p/(p−1)`, which removes the
//! amplitude mode (for `S = ν S*`, `μ^γ ν^p = 1`). `M` is even, so the integer shifts of the
//! advance–delay equation and the half-integer positions of beads are grid points.
//!
//! **Velocities.** `u_k = U(k − ct)` with `m c² U''(ξ) = F(R(ξ−1)) − F(R(ξ))` (eq. 7) and `U → 0`
//! ahead of the wave (beads ahead at rest and unshifted), so
//! `v = −c U'(ξ) = (1/(m c)) ∫_{ξ−1}^{ξ} F(R(s)) ds = c λ W(ξ)`, `W(ξ) = ∫_{ξ−1}^{ξ} S^p ds`
//! (`Ŵ = Ŝ^p · (1 − e^{−iq})/(iq)`). `W` peaks at `ξ = 1/2`: the wave's centre bead `K` has
//! `r_k = λ S(k + 1/2 − K)` on its two sides and velocity `v_m = c λ W(1/2)`, hence
//! `c = [(v_m / W(1/2)) (n a / m)^{1/(n−2)}]^{(n−2)/n}`, i.e. `c ∝ v_m^{(n−2)/n}`.
//!
//! **Energy and virial theorem.** Per period `1/c` the lattice sums average to integrals, so
//! `⟨K⟩ = ½ m c² λ² ∫W²`, `⟨P⟩ = a λⁿ ∫Sⁿ = (m c²/n) λ² ∫Sⁿ`. The wave is a critical point of
//! `𝓛[U] = ½ m c² ∫U'² − a ∫(U(ξ) − U(ξ+1))ⁿ` (its Euler–Lagrange equation is the one above);
//! `d𝓛[(1+ε)U]/dε = 0` gives `2⟨K⟩ = n ⟨P⟩`, so `⟨K⟩/⟨E⟩ = n/(n+2)` and `∫W² = ∫Sⁿ`. The energy
//! is `E = κ(n) m v_m²` with `κ = (½∫W² + ∫Sⁿ/n) / W(1/2)²`, for every `a` and `v_m`.

mod fft;

use fft::fft;
use num_complex::Complex64;
use std::f64::consts::PI;

/// Grid points per bead spacing to start with (even: half-integer offsets are grid points); it
/// doubles while the grid does not resolve `S^p` ([`RESOLVED`]): 32 for n = 2.1 … 3, 64 at
/// n = 8, 256 at n = 20. The round-off of the spectral second derivative in
/// [`UnitProfile::advance_delay_residual`] grows as `M²`.
pub const PER_BEAD: usize = 32;
/// Finest grid tried (steep profiles, large `n`: `S^p` is sharply peaked). It was 256, where
/// the tail of n = 24, 26, 30 stayed at 1.0–1.1e-15, just above [`RESOLVED`], and those waves
/// were refused while n = 21, 22, 28 were not; 1024 resolves them (n up to 40 tried).
const MAX_PER_BEAD: usize = 1024;
/// Largest grid (points) tried when the period doubles (`n` near 2: wide profiles).
const MAX_GRID: usize = 1 << 17;
/// The grid resolves `S^p` when its spectrum over the upper half of the wavenumbers stays below
/// this fraction of its zero mode (no aliasing above round-off).
const RESOLVED: f64 = 1e-15;
/// A bead or contact belongs to the wave's support where its velocity or overlap exceeds this
/// fraction of the peak (below it, the FFT's round-off floor).
pub const SUPPORT_THRESHOLD: f64 = 1e-15;

/// Why a solitary wave cannot be computed or placed (one line).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SolitaryError {
    /// `n <= 2` (or not finite): no solitary wave.
    #[error("solitary waves need a contact exponent n > 2 (got n = {0})")]
    Exponent(f64),
    /// The profile did not converge to round-off.
    #[error(
        "the solitary-wave profile for n = {n} did not converge (residual {residual:.1e}, \
         spectral tail {tail:.1e}, support ±{support} of period {period})"
    )]
    NotConverged {
        /// Contact exponent.
        n: f64,
        /// Residual of the last profile.
        residual: f64,
        /// Its spectral tail.
        tail: f64,
        /// Its support (beads).
        support: usize,
        /// Its period (beads).
        period: usize,
    },
    /// A peak velocity that is not positive and finite.
    #[error("the peak velocity must be > 0 (got {0})")]
    PeakVelocity(f64),
    /// An energy that is not positive and finite.
    #[error("the energy must be > 0 (got {0})")]
    Energy(f64),
    /// The support does not fit in the chain.
    #[error(
        "the wave needs beads {first}..={last} around its centre (support ±{support} beads for \
         n = {n}), but the chain has beads 0..={chain_last}"
    )]
    DoesNotFit {
        /// First bead needed (may be negative).
        first: i64,
        /// Last bead needed.
        last: usize,
        /// Support (beads each side).
        support: usize,
        /// Contact exponent.
        n: f64,
        /// Last bead of the chain.
        chain_last: usize,
    },
}

/// The profile of the scaled equation `S = K ∗ S^p` for one exponent `n`.
#[derive(Clone, Debug)]
pub struct UnitProfile {
    /// Contact exponent `n > 2`.
    pub exponent: f64,
    /// Period of the grid in bead spacings.
    pub period: usize,
    /// Grid points per bead spacing `M`.
    pub per_bead: usize,
    /// `S` on the grid: index `j` is `ξ = j/M` (`j ≥ N/2`: `ξ = (j − N)/M`).
    pub s: Vec<f64>,
    /// `W(ξ) = ∫_{ξ−1}^{ξ} S^p` on the same grid.
    pub w: Vec<f64>,
    /// Spectra of `s` and `w` (forward FFT), for interpolation.
    spectra: [Vec<Complex64>; 2],
    /// Petviashvili iterations used.
    pub iterations: usize,
    /// `max |S − K ∗ S^p| / max S` at the end.
    pub residual: f64,
    /// Largest `|FFT(S^p)|` over the upper half of the wavenumbers, relative to its zero mode:
    /// the grid's resolution of the profile (refined while above [`RESOLVED`]).
    pub tail: f64,
    /// Half-width in bead spacings beyond which `S` and `W` are below [`SUPPORT_THRESHOLD`] of
    /// their peaks.
    pub support: usize,
}

impl UnitProfile {
    /// Solves `S = K ∗ S^p` to round-off; the grid refines until it resolves `S^p`, the period
    /// doubles until the support fits in a quarter of it. Fails for `n ≤ 2` (no solitary wave:
    /// linear or sublinear force) and where that does not converge to round-off.
    pub fn compute(n: f64) -> Result<Self, SolitaryError> {
        if !(n.is_finite() && n > 2.0) {
            return Err(SolitaryError::Exponent(n));
        }
        let (mut period, mut per_bead) = (32, PER_BEAD);
        loop {
            let p = solve(n, period, per_bead);
            if p.tail > RESOLVED && per_bead < MAX_PER_BEAD {
                per_bead *= 2;
            } else if 4 * p.support > period && period * per_bead < MAX_GRID {
                period *= 2;
            } else if p.residual > 1e-13 || p.tail > RESOLVED || 4 * p.support > period {
                return Err(SolitaryError::NotConverged {
                    n,
                    residual: p.residual,
                    tail: p.tail,
                    support: p.support,
                    period: p.period,
                });
            } else {
                return Ok(p);
            }
        }
    }

    fn n_grid(&self) -> usize {
        self.s.len()
    }

    /// Grid index of `ξ` when `ξ·M` is an integer (within 1e-12), else `None`.
    fn index(&self, xi: f64) -> Option<usize> {
        let x = xi * self.per_bead as f64;
        let r = x.round();
        ((x - r).abs() < 1e-12 && r.abs() < (self.n_grid() / 2) as f64)
            .then(|| (r as i64).rem_euclid(self.n_grid() as i64) as usize)
    }

    /// `S(ξ)` (grid value; trigonometric interpolation between grid points; `0` outside the
    /// grid's period, where the profile is below round-off).
    pub fn s_at(&self, xi: f64) -> f64 {
        if xi.abs() >= 0.5 * self.period as f64 {
            return 0.0;
        }
        self.index(xi).map_or_else(
            || interpolate(&self.spectra[0], xi, self.period),
            |j| self.s[j],
        )
    }

    /// `W(ξ)` (as [`Self::s_at`]).
    pub fn w_at(&self, xi: f64) -> f64 {
        if xi.abs() >= 0.5 * self.period as f64 {
            return 0.0;
        }
        self.index(xi).map_or_else(
            || interpolate(&self.spectra[1], xi, self.period),
            |j| self.w[j],
        )
    }

    /// `∫ f` over the period (trapezoid rule: spectrally accurate for periodic smooth `f`).
    fn integral(&self, f: impl Fn(usize) -> f64) -> f64 {
        (0..self.n_grid()).map(f).sum::<f64>() / self.per_bead as f64
    }

    /// `(∫W², ∫Sⁿ)`: equal by the virial theorem.
    pub fn virial_integrals(&self) -> (f64, f64) {
        let n = self.exponent;
        (
            self.integral(|j| self.w[j] * self.w[j]),
            self.integral(|j| self.s[j].max(0.0).powf(n)),
        )
    }

    /// `κ(n) = E / (m v_m²)`.
    pub fn energy_constant(&self) -> f64 {
        let (w2, sn) = self.virial_integrals();
        let wm = self.w_at(0.5);
        (0.5 * w2 + sn / self.exponent) / (wm * wm)
    }

    /// Residual of the advance–delay equation `S'' = Δ₂ S^p` (spectral `S''`, exact integer
    /// shifts on the grid), relative to `max |S''|`.
    pub fn advance_delay_residual(&self) -> f64 {
        let (nn, m) = (self.n_grid(), self.per_bead);
        let mut z: Vec<Complex64> = self.s.iter().map(|x| Complex64::new(*x, 0.0)).collect();
        fft(&mut z, false);
        for (j, zj) in z.iter_mut().enumerate() {
            let q = wavenumber(j, nn, self.period);
            *zj *= -q * q;
        }
        fft(&mut z, true);
        let p = self.exponent - 1.0;
        let g: Vec<f64> = self.s.iter().map(|x| x.max(0.0).powf(p)).collect();
        let (mut res, mut big) = (0.0_f64, 0.0_f64);
        for j in 0..nn {
            let rhs = g[(j + m) % nn] - 2.0 * g[j] + g[(j + nn - m) % nn];
            res = res.max((z[j].re - rhs).abs());
            big = big.max(z[j].re.abs());
        }
        res / big
    }
}

/// Wavenumber `q` of FFT bin `j` on a grid of `nn` points over `period` bead spacings.
fn wavenumber(j: usize, nn: usize, period: usize) -> f64 {
    let jj = if j <= nn / 2 {
        j as f64
    } else {
        j as f64 - nn as f64
    };
    2.0 * PI * jj / period as f64
}

/// `sin(x)/x`.
fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-8 {
        1.0 - x * x / 6.0
    } else {
        x.sin() / x
    }
}

/// Forward FFT of real grid values.
fn spectrum(f: &[f64]) -> Vec<Complex64> {
    let mut z: Vec<Complex64> = f.iter().map(|x| Complex64::new(*x, 0.0)).collect();
    fft(&mut z, false);
    z
}

/// Trigonometric interpolation at `xi` of the grid values whose spectrum is `z` (period
/// `period` bead spacings).
fn interpolate(z: &[Complex64], xi: f64, period: usize) -> f64 {
    let nn = z.len();
    let mut sum = 0.0;
    for (j, zj) in z.iter().enumerate() {
        let q = wavenumber(j, nn, period);
        sum += if j == nn / 2 {
            // The Nyquist bin stands for its ± pair: cos(qξ).
            zj.re * (q * xi).cos()
        } else {
            (zj * Complex64::from_polar(1.0, q * xi)).re
        };
    }
    sum / nn as f64
}

/// Petviashvili's iteration for `S = K ∗ S^p` on a grid of `period` bead spacings.
pub(crate) fn solve(n: f64, period: usize, per_bead: usize) -> UnitProfile {
    let nn = period * per_bead;
    let p = n - 1.0;
    let gamma = p / (p - 1.0);
    let khat: Vec<f64> = (0..nn)
        .map(|j| sinc(0.5 * wavenumber(j, nn, period)).powi(2))
        .collect();
    // Start: a Gaussian of about the continuum wave's width, π p / (√6 (p − 1)) bead spacings.
    let width = PI * p / (6f64.sqrt() * (p - 1.0));
    let mut s: Vec<f64> = (0..nn)
        .map(|j| {
            let xi = wavenumber(j, nn, period) * period as f64 / (2.0 * PI) / per_bead as f64;
            (-(xi / (0.4 * width)).powi(2)).exp()
        })
        .collect();
    let mut z = vec![Complex64::default(); nn];
    let (mut best, mut since_best, mut iterations) = (f64::INFINITY, 0, 0);
    while iterations < 5000 && since_best < 30 {
        iterations += 1;
        let t = apply_kernel(&s, p, &khat, &mut z);
        let num: f64 = s.iter().map(|x| x * x).sum();
        let den: f64 = s.iter().zip(&t).map(|(x, y)| x * y).sum();
        let factor = (num / den).powf(gamma);
        let mut change = 0.0_f64;
        let mut new: Vec<f64> = t.iter().map(|x| factor * x).collect();
        symmetrize(&mut new);
        let peak = new[0];
        for (a, b) in s.iter().zip(&new) {
            change = change.max((a - b).abs() / peak);
        }
        s = new;
        if change < best * 0.999 {
            best = change;
            since_best = 0;
        } else {
            since_best += 1;
        }
    }
    let t = apply_kernel(&s, p, &khat, &mut z);
    let residual = s
        .iter()
        .zip(&t)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
        / s[0];
    let w = velocity_profile(&s, p, period, &mut z);
    let tail = spectral_tail(&s, p);
    let support = support(&s, &w, per_bead);
    UnitProfile {
        exponent: n,
        period,
        per_bead,
        spectra: [spectrum(&s), spectrum(&w)],
        s,
        w,
        iterations,
        residual,
        tail,
        support,
    }
}

/// `max_{|j| ≥ N/4} |ĝ_j| / |ĝ_0|` for `g = S^p`.
fn spectral_tail(s: &[f64], p: f64) -> f64 {
    let g: Vec<f64> = s.iter().map(|x| x.max(0.0).powf(p)).collect();
    let z = spectrum(&g);
    let nn = z.len();
    z[nn / 4..=3 * nn / 4]
        .iter()
        .fold(0.0_f64, |m, c| m.max(c.norm()))
        / z[0].norm()
}

/// `K ∗ S^p` on the grid (`z`: scratch).
fn apply_kernel(s: &[f64], p: f64, khat: &[f64], z: &mut [Complex64]) -> Vec<f64> {
    for (zj, x) in z.iter_mut().zip(s) {
        *zj = Complex64::new(x.max(0.0).powf(p), 0.0);
    }
    fft(z, false);
    for (zj, k) in z.iter_mut().zip(khat) {
        *zj *= k;
    }
    fft(z, true);
    z.iter().map(|c| c.re).collect()
}

/// `W = ∫_{ξ−1}^{ξ} S^p`: multiplier `(1 − e^{−iq})/(iq)` (`1` at `q = 0`, its real part
/// `sin q / q` at the Nyquist bin, so `W` stays real).
fn velocity_profile(s: &[f64], p: f64, period: usize, z: &mut [Complex64]) -> Vec<f64> {
    let nn = s.len();
    for (zj, x) in z.iter_mut().zip(s) {
        *zj = Complex64::new(x.max(0.0).powf(p), 0.0);
    }
    fft(z, false);
    for (j, zj) in z.iter_mut().enumerate() {
        let q = wavenumber(j, nn, period);
        let mult = if j == 0 {
            Complex64::new(1.0, 0.0)
        } else if j == nn / 2 {
            Complex64::new(q.sin() / q, 0.0)
        } else {
            (Complex64::new(1.0, 0.0) - Complex64::from_polar(1.0, -q)) / Complex64::new(0.0, q)
        };
        *zj *= mult;
    }
    fft(z, true);
    z.iter().map(|c| c.re).collect()
}

/// Makes `s` even about `ξ = 0` (`s_j = s_{N−j}`): the translation mode is not excited.
fn symmetrize(s: &mut [f64]) {
    let nn = s.len();
    for j in 1..nn / 2 {
        let m = 0.5 * (s[j] + s[nn - j]);
        s[j] = m;
        s[nn - j] = m;
    }
}

/// Half-width (bead spacings, rounded up) outside which `S` and `W` are below
/// [`SUPPORT_THRESHOLD`] of their peaks.
fn support(s: &[f64], w: &[f64], per_bead: usize) -> usize {
    let nn = s.len();
    let (smax, wmax) = (s[0], w[per_bead / 2]);
    let mut far = 0;
    for j in 0..nn {
        if s[j] > SUPPORT_THRESHOLD * smax || w[j] > SUPPORT_THRESHOLD * wmax {
            let d = if j <= nn / 2 { j } else { nn - j };
            far = far.max(d);
        }
    }
    far.div_ceil(per_bead) + 1
}

pub mod wave;
pub use wave::{Direction, Placement, Wave};

#[cfg(test)]
mod tests;
