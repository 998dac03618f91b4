//! Impurity examples and collective impurity beads (paper Sec. 5.1, Figs. 16 and 17).
//!
//! - [`census`]: the pulses of a frame with their peak velocity relative to the incoming peak and
//!   their share of the energy (eq. 13 with ½, see the [module docs](super)), classified as
//!   reflected (moving left, peak in `2..k`: beads 0–1 carry the striker's rebound, present in a
//!   uniform chain too), transmitted (moving right, peak beyond the impurity) or other.
//! - [`impurity_example`]: Fig. 16 (`s = 1`, `n = 3.0`, `n_imp = 3.5` and `2.5`).
//! - [`collective_impurity`]: Fig. 17 (`n = 4`, `s = 1`, `δn = −0.25` vs `−1.5`): how far the
//!   `s + 1` impurity beads `k..=k+s` are from moving as one body while they carry the wave —
//!   the largest velocity spread `max_j v_j − min_j v_j` over the frames where the fastest
//!   impurity bead exceeds 10 % of `v_in`, relative to `v_in`; and their peak common velocity
//!   against the two-body value `2/(s+2) · v_in` of a bead `m` hitting a body `(s+1) m` at rest.

use super::paper::{physical_scene, run_watched, time_per_bead, PaperError};
use super::timings::Window;
use crate::analysis::wave::{detect_pulses, wave_energy, WaveOptions};
use crate::engine::{self, RunConfig};
use crate::model::Chain;
use crate::scene::Engine;
use std::time::Instant;

/// Where a pulse is going.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PulseKind {
    /// Moving left, peak in `2..k`.
    Reflected,
    /// Moving right, peak beyond the impurity/interface.
    Transmitted,
    /// Anything else (striker rebound, beads at the impurity).
    Other,
}

/// One pulse of a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PulseRow {
    /// Peak bead.
    pub peak_bead: usize,
    /// First and last bead.
    pub span: (usize, usize),
    /// Peak velocity over `v_in`.
    pub v_rel: f64,
    /// Energy share (of the chain's total energy).
    pub energy: f64,
    /// Classification.
    pub kind: PulseKind,
}

/// Pulses of frame `(u, v)` with `|v_peak| > min_rel · v_in`; `k`: first impurity/interface
/// bead, `right`: last bead of the impurity (pulses beyond it are transmitted).
pub fn census(
    chain: &Chain,
    u: &[f64],
    v: &[f64],
    v_in: f64,
    k: usize,
    right: usize,
    min_rel: f64,
) -> Vec<PulseRow> {
    let total = chain.energy(u, v);
    detect_pulses(v, &WaveOptions::default())
        .into_iter()
        .filter(|p| p.peak_velocity.abs() > min_rel * v_in)
        .map(|p| {
            let kind = if p.peak_velocity < 0.0 && p.peak_bead >= 2 && p.peak_bead < k {
                PulseKind::Reflected
            } else if p.peak_velocity > 0.0 && p.peak_bead > right {
                PulseKind::Transmitted
            } else {
                PulseKind::Other
            };
            PulseRow {
                peak_bead: p.peak_bead,
                span: (p.first, p.last),
                v_rel: p.peak_velocity / v_in,
                energy: wave_energy(chain, u, v, p.first, p.last) / total,
                kind,
            }
        })
        .collect()
}

/// Total energy share of the pulses of one kind.
pub fn share(rows: &[PulseRow], kind: PulseKind) -> f64 {
    rows.iter()
        .filter(|r| r.kind == kind)
        .map(|r| r.energy)
        .sum()
}

/// Result of [`impurity_example`].
#[derive(Clone, Debug)]
pub struct ImpurityExample {
    /// Pulses of the stop frame above 1 % of `v_in`.
    pub pulses: Vec<PulseRow>,
    /// Incoming peak velocity (largest forward velocity of beads 20..k−3).
    pub v_in: f64,
    /// Stop time (leading wave at `stop_at`).
    pub t_stop: f64,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// Impurity of `s` contacts with exponent `n_imp` from contact `k` in a physical chain of
/// `beads` beads of exponent `n` (hybrid, Radau, `rtol = 1e-8`); pulses when the leading wave
/// reaches bead `stop_at` (e.g. `k + 40`: the reflected pulse is still inside the chain;
/// `beads − 12`: the transmitted train has separated).
pub fn impurity_example(
    n: f64,
    s: usize,
    n_imp: f64,
    beads: usize,
    k: usize,
    stop_at: usize,
) -> Result<ImpurityExample, PaperError> {
    let t0 = Instant::now();
    let tau = time_per_bead(n)?.max(time_per_bead(n_imp)?);
    let ex = format!("{{ base = {n}, impurity = {{ at = {k}, s = {s}, value = {n_imp} }} }}");
    let sc = physical_scene(beads, &ex, 0, tau * beads as f64 * 40.0, tau / 5.0)?;
    let (w, _) = run_watched(&sc, k, stop_at, 1e-8)?;
    let (t, u, v) = &w.last;
    Ok(ImpurityExample {
        pulses: census(&sc.chain, u, v, w.velocity().v_in, k, k + s, 0.01),
        v_in: w.velocity().v_in,
        t_stop: *t,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

/// Result of [`collective_impurity`].
#[derive(Clone, Debug, PartialEq)]
pub struct Collective {
    /// Largest velocity spread among the impurity beads over `v_in`, while they carry the wave.
    pub max_spread: f64,
    /// Mean of that spread over the same frames, over `v_in`.
    pub mean_spread: f64,
    /// Largest velocity of any impurity bead over `v_in`.
    pub peak: f64,
    /// The two-body value `2/(s+2)` (bead `m` on a body `(s+1) m` at rest).
    pub two_body: f64,
    /// Frames in the window.
    pub frames: usize,
    /// Duration of the window over the time per bead of `n`.
    pub duration_beads: f64,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// Impurity beads `k..=k+s` of an `s`-contact impurity with exponent `n + dn` at contact `k` in
/// a physical chain of `beads` beads (frames `τ/50` apart, `τ` of the slower medium).
pub fn collective_impurity(
    n: f64,
    s: usize,
    dn: f64,
    beads: usize,
    k: usize,
) -> Result<Collective, PaperError> {
    let t0 = Instant::now();
    let ni = n + dn;
    let (ta, tb) = (time_per_bead(n)?, time_per_bead(ni)?);
    let tau = ta.max(tb);
    let ex = format!("{{ base = {n}, impurity = {{ at = {k}, s = {s}, value = {ni} }} }}");
    let probe = physical_scene(beads, &ex, 0, tau * beads as f64 * 40.0, tau / 5.0)?;
    let (w, _) = run_watched(&probe, k, beads.saturating_sub(12), 1e-8)?;
    let sc = physical_scene(beads, &ex, 0, w.last.0.max(tau), tau / 50.0)?;
    let mut cfg = RunConfig::from_scene(&sc);
    cfg.engine = Engine::Hybrid;
    cfg.rtol = 1e-8;
    cfg.atol = 1e-10;
    let mut win = Window::new(sc.chain.clone(), (k, k + 1), (k, k + s + 1), k - 10);
    engine::run_to_stop(&sc, &cfg, &mut win)?;
    let v_in = win.v_in;
    let (mut max_spread, mut sum, mut count, mut peak) = (0.0f64, 0.0, 0usize, 0.0f64);
    let (mut first, mut last) = (f64::NAN, f64::NAN);
    for f in 0..win.t.len() {
        let (lo, hi) = win
            .vel
            .iter()
            .map(|x| x[f])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
        peak = peak.max(hi);
        if hi.max(-lo) > 0.1 * v_in {
            max_spread = max_spread.max(hi - lo);
            sum += hi - lo;
            count += 1;
            if first.is_nan() {
                first = win.t[f];
            }
            last = win.t[f];
        }
    }
    Ok(Collective {
        max_spread: max_spread / v_in,
        mean_spread: sum / count.max(1) as f64 / v_in,
        peak: peak / v_in,
        two_body: 2.0 / (s as f64 + 2.0),
        frames: count,
        duration_beads: (last - first) / ta,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::wave::tests::chain;

    #[test]
    fn census_classifies_and_shares() {
        let c = chain(20, 2.0);
        let u = vec![0.0; 20];
        let mut v = vec![0.0; 20];
        v[1] = -0.2; // striker rebound: other
        v[7] = -1.0; // reflected (peak 7 < k = 10)
        v[15] = 2.0; // transmitted (15 > right = 11)
        let rows = census(&c, &u, &v, 2.0, 10, 11, 0.01);
        assert_eq!(rows.len(), 3);
        assert_eq!(rows[0].kind, PulseKind::Other);
        assert_eq!(rows[1].kind, PulseKind::Reflected);
        assert_eq!(rows[2].kind, PulseKind::Transmitted);
        // energies ½v²: 0.02, 0.5, 2 of 2.52 (exact to rounding, abs 1e-12)
        assert!((share(&rows, PulseKind::Reflected) - 0.5 / 2.52).abs() < 1e-12);
        assert!((rows[2].v_rel - 1.0).abs() < 1e-12);
    }
}
