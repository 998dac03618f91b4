//! Solitary-wave width against the exponent `n` (paper Sec. 2, Fig. 2): the run that measures
//! it. The continuum prediction `λ_c(n)` and the profile fit are [`crate::analysis::wavelength`].
//!
//! **Discrete measurement.** A uniform chain (`a = m = 1`, striker `v = 1`; for one exponent the
//! wave's shape in bead units does not depend on `a`, `m`, `v₀`, only its time scale) is run until
//! the wave has passed two probe beads `j1 < j2` far from the striker. A lattice solitary wave is a
//! function of `j − c t`, so the velocity trace of one bead, with time converted to beads by the
//! measured time per bead `τ`, samples the whole profile `f(ξ)` finely. From it:
//! - `λ_fit`: least-squares fit of `cos^{2/(n−2)}(π ξ/λ)` (peak and centre from the trace, `λ`
//!   free) — the discrete wavelength compared with `λ_c`;
//! - the full width at half maximum against the continuum's, and the width above 0.1 % of the
//!   peak (the paper's wave definition, Sec. 3.2) against the continuum's;
//! - the paper's bead count: beads above 0.1 % of the peak in frames where the leading peak is
//!   within ±5 beads of `j1` (mean over those frames).

use super::paper::PaperError;
use crate::analysis::wave::{leading_pulse, WaveOptions};
use crate::analysis::wavelength::{
    continuum_wavelength, continuum_width_above, fit_wavelength, peak_of, trace_profile,
    width_above,
};
use crate::engine::{self, Control, EngineError, Observer, RunConfig};
use crate::scene::{self, Engine};
use std::path::Path;
use std::time::Instant;

/// Observer: traces of the probe beads, bead counts near `j1`, stop after the wave passed `j2`.
struct Probe {
    beads: [usize; 4],
    t: Vec<f64>,
    v: [Vec<f64>; 4],
    counts: Vec<usize>,
    opts: WaveOptions,
    stop_at: usize,
    stop: bool,
}

impl Observer for Probe {
    fn frame(&mut self, t: f64, _u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        self.t.push(t);
        for (k, &b) in self.beads.iter().enumerate() {
            self.v[k].push(v[b]);
        }
        if let Some(p) = leading_pulse(v, &self.opts) {
            if p.peak_bead.abs_diff(self.beads[1]) <= 5 {
                self.counts.push(p.width());
            }
            self.stop |= p.peak_bead >= self.stop_at;
        }
        Ok(())
    }
    fn control(&mut self, _t: f64) -> Control {
        Control::stop_if(self.stop)
    }
}

/// One measured wavelength (all widths in bead diameters).
#[derive(Clone, Debug, PartialEq)]
pub struct WavelengthResult {
    /// Exponent.
    pub n: f64,
    /// Continuum `λ_c(n)`.
    pub lambda_c: f64,
    /// Fitted `λ` at probe `j1` and at `j2` (formation check: they agree once formed).
    pub lambda_fit: (f64, f64),
    /// RMS residual of the fit at `j1` (relative to the peak).
    pub fit_rms: f64,
    /// FWHM of the discrete profile at `j1` and of the continuum.
    pub fwhm: (f64, f64),
    /// Width above 0.1 % of the peak of the discrete profile at `j1` and of the continuum.
    pub width_01: (f64, f64),
    /// Mean number of beads above 0.1 % of the peak (paper's rule) in frames with the peak near
    /// `j1`.
    pub count_01: f64,
    /// Measured time per bead (computer units, `a = m = v₀ = 1`).
    pub tau: f64,
    /// Probe beads.
    pub probes: (usize, usize),
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// Measures the discrete wave width for exponent `n` in a uniform chain of `beads` beads
/// (probes at `beads/2` and `3 beads/4`), engine `engine`, Radau, `rtol`, `atol = rtol/100`,
/// frames every `dt` time units.
pub fn measure_wavelength(
    n: f64,
    beads: usize,
    engine: Engine,
    rtol: f64,
    dt: f64,
) -> Result<WavelengthResult, PaperError> {
    let (j1, j2) = (beads / 2, 3 * beads / 4);
    let text = format!(
        "[scene]\nname = \"wavelength\"\n[chain]\nbeads = {beads}\nexponent = {n}\n[initial]\n\
         striker = 1.0\n[run]\nuntil = {:e}\nevery = {dt:e}\n",
        20.0 * beads as f64 + 100.0
    );
    let sc = scene::parse_str(&text, Path::new("."), "generated wavelength scene")?;
    let mut cfg = RunConfig::from_scene(&sc);
    cfg.engine = engine;
    cfg.rtol = rtol;
    cfg.atol = rtol / 100.0;
    let mut obs = Probe {
        beads: [j1 - 5, j1, j1 + 5, j2],
        t: Vec::new(),
        v: Default::default(),
        counts: Vec::new(),
        opts: WaveOptions::default(),
        stop_at: (j2 + 15).min(beads - 3),
        stop: false,
    };
    let t0 = Instant::now();
    engine::run_to_stop(&sc, &cfg, &mut obs)?;
    let seconds = t0.elapsed().as_secs_f64();
    let no = || PaperError::NoWave(n);
    let (ta, _) = peak_of(&obs.t, &obs.v[0]).ok_or_else(no)?;
    let (tb, _) = peak_of(&obs.t, &obs.v[2]).ok_or_else(no)?;
    let tau = (tb - ta) / 10.0;
    if tau.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(no());
    }
    let p1 = trace_profile(&obs.t, &obs.v[1], tau).ok_or_else(no)?;
    let p2 = trace_profile(&obs.t, &obs.v[3], tau).ok_or_else(no)?;
    let (l1, rms) = fit_wavelength(&p1, n);
    let (l2, _) = fit_wavelength(&p2, n);
    let count_01 = if obs.counts.is_empty() {
        f64::NAN
    } else {
        obs.counts.iter().sum::<usize>() as f64 / obs.counts.len() as f64
    };
    Ok(WavelengthResult {
        n,
        lambda_c: continuum_wavelength(n),
        lambda_fit: (l1, l2),
        fit_rms: rms,
        fwhm: (width_above(&p1, 0.5), continuum_width_above(n, 0.5)),
        width_01: (width_above(&p1, 1e-3), continuum_width_above(n, 1e-3)),
        count_01,
        tau,
        probes: (j1, j2),
        seconds,
    })
}
