//! Solitary-wave profile against the continuum (paper Sec. 2, Fig. 2): the continuum shape and
//! wavelength, a bead's velocity trace as a profile `f(ξ)`, its widths and the least-squares
//! wavelength. The run that measures them is [`crate::experiments::wavelength`].
//!
//! **Continuum prediction** (Nesterenko's long-wave equation for a force `∝ δ^p`, here
//! `p = n − 1` for the potential `a δⁿ` of eq. 1): the strain, and with it the velocity
//! `v = c ξ` of the travelling wave, is `cos^{2/(p−1)}(π x / λ)` on `|x| < λ/2` and zero outside,
//! with the wavelength (bead diameters)
//!
//! `λ_c(n) = π/(n − 2) · √(n (n − 1) / 6)`
//!
//! (`n = 5/2`: `λ_c = π √(5/2) = 4.97`, Nesterenko's "five beads"; `λ_c → ∞` for `n → 2`,
//! `λ_c → π/√6 = 1.28` for `n → ∞`).

/// Continuum (Nesterenko) wavelength `λ_c(n)` in bead diameters; `NaN` for `n ≤ 2`.
pub fn continuum_wavelength(n: f64) -> f64 {
    if n <= 2.0 {
        return f64::NAN;
    }
    std::f64::consts::PI / (n - 2.0) * (n * (n - 1.0) / 6.0).sqrt()
}

/// Continuum velocity profile with peak 1 at `x = 0` for wavelength `lambda` and exponent `n`.
pub fn continuum_shape(n: f64, lambda: f64, x: f64) -> f64 {
    let phase = std::f64::consts::PI * x / lambda;
    if phase.abs() >= std::f64::consts::FRAC_PI_2 {
        0.0
    } else {
        phase.cos().powf(2.0 / (n - 2.0))
    }
}

/// Width of the continuum profile where it exceeds `frac` of its peak (bead diameters).
pub fn continuum_width_above(n: f64, frac: f64) -> f64 {
    let lambda = continuum_wavelength(n);
    2.0 * lambda / std::f64::consts::PI * frac.powf((n - 2.0) / 2.0).acos()
}

/// A wave profile `f(ξ)` normalised to peak 1 at `ξ = 0` (ξ in beads).
#[derive(Clone, Debug, PartialEq)]
pub struct Profile {
    /// Positions (beads) relative to the peak, increasing.
    pub xi: Vec<f64>,
    /// Values relative to the peak.
    pub f: Vec<f64>,
}

/// Peak of a sampled curve: `(time, value)` by a parabola through the largest sample and its
/// neighbours; `None` if empty or the maximum is not positive.
pub fn peak_of(t: &[f64], v: &[f64]) -> Option<(f64, f64)> {
    let (i, &m) = v.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1))?;
    if m <= 0.0 {
        return None;
    }
    if i == 0 || i + 1 >= v.len() {
        return Some((t[i], m));
    }
    let (a, b, c) = (v[i - 1], m, v[i + 1]);
    let den = a - 2.0 * b + c;
    if den >= 0.0 {
        return Some((t[i], m));
    }
    let s = 0.5 * (a - c) / den; // offset in samples, |s| ≤ 0.5
    let dt = 0.5 * (t[i + 1] - t[i - 1]);
    Some((t[i] + s * dt, b - 0.25 * (a - c) * s))
}

/// Profile from one bead's velocity trace: `ξ = (t_peak − t)/τ` (the front, which reaches the bead
/// first, is at positive ξ).
pub fn trace_profile(t: &[f64], v: &[f64], tau: f64) -> Option<Profile> {
    let (tp, vp) = peak_of(t, v)?;
    let mut pts: Vec<(f64, f64)> = t
        .iter()
        .zip(v)
        .map(|(&ti, &vi)| ((tp - ti) / tau, vi / vp))
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    Some(Profile {
        xi: pts.iter().map(|p| p.0).collect(),
        f: pts.iter().map(|p| p.1).collect(),
    })
}

/// Width of a profile above `frac` (crossings on each side of the peak found by linear
/// interpolation, walking outwards from ξ = 0).
pub fn width_above(p: &Profile, frac: f64) -> f64 {
    let Some(c) = p.xi.iter().position(|&x| x >= 0.0) else {
        return 0.0;
    };
    let cross = |i: usize, j: usize| {
        let (x0, f0, x1, f1) = (p.xi[i], p.f[i], p.xi[j], p.f[j]);
        x0 + (frac - f0) * (x1 - x0) / (f1 - f0)
    };
    let mut right = *p.xi.last().unwrap_or(&0.0);
    for i in c..p.f.len().saturating_sub(1) {
        if p.f[i] >= frac && p.f[i + 1] < frac {
            right = cross(i, i + 1);
            break;
        }
    }
    let mut left = p.xi[0];
    for i in (1..=c).rev() {
        if p.f[i] >= frac && p.f[i - 1] < frac {
            left = cross(i, i - 1);
            break;
        }
    }
    right - left
}

/// Least-squares wavelength: `λ` minimising `Σ (f(ξ) − cos^{2/(n−2)}(π ξ/λ)₊)²` over the samples
/// with `|ξ| < 3 λ_c` (golden section on `ln λ` in `[0.2, 5]·λ_c`). Returns `(λ, rms residual)`.
pub fn fit_wavelength(p: &Profile, n: f64) -> (f64, f64) {
    let lc = continuum_wavelength(n);
    let idx: Vec<usize> = (0..p.xi.len())
        .filter(|&i| p.xi[i].abs() < 3.0 * lc)
        .collect();
    let cost = |lam: f64| {
        idx.iter()
            .map(|&i| (p.f[i] - continuum_shape(n, lam, p.xi[i])).powi(2))
            .sum::<f64>()
    };
    let g = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = ((0.2 * lc).ln(), (5.0 * lc).ln());
    let mut c = b - g * (b - a);
    let mut d = a + g * (b - a);
    let (mut fc, mut fd) = (cost(c.exp()), cost(d.exp()));
    for _ in 0..80 {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = cost(c.exp());
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = cost(d.exp());
        }
    }
    let lam = (0.5 * (a + b)).exp();
    let rms = (cost(lam) / idx.len().max(1) as f64).sqrt();
    (lam, rms)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn continuum_values() {
        // Hertz n = 5/2: λ = 2π √(2.5·1.5/6) = 4.9673 (Nesterenko's ≈ 5 beads), abs 1e-4
        assert!((continuum_wavelength(2.5) - 4.9673).abs() < 1e-4);
        // n = 3: λ = π √1 = π (abs 1e-12)
        assert!((continuum_wavelength(3.0) - std::f64::consts::PI).abs() < 1e-12);
        assert!(continuum_wavelength(2.0).is_nan());
        // n = 4: cos profile (exponent 2/(n−2) = 1), FWHM = 2λ/3 (abs 1e-12)
        let l4 = continuum_wavelength(4.0);
        assert!((continuum_width_above(4.0, 0.5) - 2.0 * l4 / 3.0).abs() < 1e-12);
        // n = 6: cos^½ profile, support width λ (frac → 0)
        assert!((continuum_width_above(6.0, 1e-300) - continuum_wavelength(6.0)).abs() < 1e-9);
    }

    #[test]
    fn fit_recovers_exact_shape_and_widths() {
        // samples of the exact continuum shape with λ = 1.3 λ_c: the fit returns 1.3 λ_c
        // (golden section to ~1e-9 relative; asserted rel 1e-6) and the FWHM within the
        // linear-interpolation error of the 0.01-bead grid (abs 1e-3)
        let n = 3.0;
        let lam = 1.3 * continuum_wavelength(n);
        let xi: Vec<f64> = (-600..=600).map(|i| i as f64 * 0.01).collect();
        let f: Vec<f64> = xi.iter().map(|&x| continuum_shape(n, lam, x)).collect();
        let p = Profile { xi, f };
        let (l, rms) = fit_wavelength(&p, n);
        assert!((l / lam - 1.0).abs() < 1e-6, "{l} vs {lam}");
        assert!(rms < 1e-6);
        let w = width_above(&p, 0.5);
        assert!(
            (w - 1.3 * continuum_width_above(n, 0.5)).abs() < 1e-3,
            "{w}"
        );
    }

    #[test]
    fn trace_profile_maps_time_to_beads() {
        // v(t) = shape((t0 − t)/τ) with τ = 2: the profile is the shape again (peak at ξ = 0)
        let (n, lam, tau, t0) = (4.0, 2.0, 2.0, 10.0);
        let t: Vec<f64> = (0..2000).map(|i| i as f64 * 0.01).collect();
        let v: Vec<f64> = t
            .iter()
            .map(|&ti| 3.0 * continuum_shape(n, lam, (t0 - ti) / tau))
            .collect();
        let p = trace_profile(&t, &v, tau).unwrap();
        let (l, _) = fit_wavelength(&p, n);
        // sampled at 0.005 beads: λ within rel 1e-3
        assert!((l / lam - 1.0).abs() < 1e-3, "{l}");
    }
}
