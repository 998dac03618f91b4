//! Periodic chains with the windowed tracker ([`crate::analysis::window`]): paper Sec. 4, Figs. 10–14.
//!
//! Exponents alternate `n_a, n_b, n_a, …` from contact 0 (contact `c` joins beads `c` and
//! `c + 1`, so the `n_a` pairs are beads `(2j, 2j + 1)`), Table 1 steel beads in the paper's units
//! (eqs. 3–4, 10–11), striker 0.11 m/s on bead 0 (eq. 8).
//!
//! - [`periodic_window_run`]: one watched run; [`windowed_gamma`] the decay rate of the window
//!   energy (Fig. 12); [`retention`] the energy the window keeps between two front positions;
//!   [`breathing`] the period of the confined waves' peak oscillation (Figs. 13–14);
//!   [`pairing`] the velocity mismatch of the `n_a`- and `n_b`-joined bead pairs (Fig. 10).
//! - [`run_observer`]: any observer on a generated scene with the hybrid (or dense) engine.

use super::paper::{physical_scene, time_per_bead, PaperError};
use crate::analysis::window::{
    dominant_periods, leader_changes, pair_mismatch, windowed_decay, WindowWatch,
};
use crate::analysis::ExpFit;
use crate::engine::{self, Observer, RunConfig};
use crate::scene::{Engine, Scene};
use std::time::Instant;

/// Window widths (beads) recorded by every periodic run; index 1 (12 beads) is the main one.
pub const WIDTHS: [usize; 3] = [8, 12, 20];

/// Runs `scene` with `engine` (Radau, `rtol`, `atol = rtol/100`) under `obs` until the scene's
/// end or the observer's stop; returns the wall time in seconds.
pub fn run_observer(
    scene: &Scene,
    engine: Engine,
    rtol: f64,
    obs: &mut dyn Observer,
) -> Result<f64, PaperError> {
    let mut cfg = RunConfig::from_scene(scene);
    cfg.engine = engine;
    cfg.rtol = rtol;
    cfg.atol = rtol / 100.0;
    let t0 = Instant::now();
    engine::run_to_stop(scene, &cfg, obs)?;
    Ok(t0.elapsed().as_secs_f64())
}

/// A watched periodic run.
pub struct PeriodicRun {
    /// Exponent of the even contacts.
    pub na: f64,
    /// Exponent of the odd contacts.
    pub nb: f64,
    /// Chain length.
    pub beads: usize,
    /// Time per bead of the slower uniform medium (probe).
    pub tb: f64,
    /// The observer with its track (and traces, if asked for).
    pub watch: WindowWatch,
    /// Wall time of the run (s).
    pub seconds: f64,
}

/// Runs the periodic chain `n_a/n_b` of `beads` beads with frames `tb/frames_per_bead` apart,
/// recording [`WIDTHS`] and, if `traces` is `Some((lo, hi))`, the velocities of beads `lo..hi`;
/// stops when the front reaches bead `beads − 10`.
pub fn periodic_window_run(
    na: f64,
    nb: f64,
    beads: usize,
    frames_per_bead: f64,
    traces: Option<(usize, usize)>,
    engine: Engine,
) -> Result<PeriodicRun, PaperError> {
    let tb = time_per_bead(na)?.max(time_per_bead(nb)?);
    let ex = if na == nb {
        format!("{na}")
    } else {
        format!("{{ alternate = [{na}, {nb}] }}")
    };
    let sc = physical_scene(beads, &ex, 0, tb * beads as f64 * 4.0, tb / frames_per_bead)?;
    let mut watch = WindowWatch::new(sc.chain.clone(), &WIDTHS, beads.saturating_sub(10));
    if let Some((lo, hi)) = traces {
        watch = watch.with_traces(lo.min(beads), hi.min(beads));
    }
    let seconds = run_observer(&sc, engine, 1e-8, &mut watch)?;
    Ok(PeriodicRun {
        na,
        nb,
        beads,
        tb,
        watch,
        seconds,
    })
}

/// Decay rate of the window energy of width `WIDTHS[wi]`: `E0` when the front passes bead 15,
/// fit over fronts `25..=beads − 10`.
pub fn windowed_gamma(run: &PeriodicRun, wi: usize) -> Result<ExpFit, PaperError> {
    windowed_decay(&run.watch.track, wi, 15, 25, run.beads.saturating_sub(10))
        .map_err(|_| PaperError::NoWave(run.tb))
}

/// Window energy (width `WIDTHS[wi]`) when the front first reaches `to`, over its value when the
/// front first reaches `from`.
pub fn retention(run: &PeriodicRun, wi: usize, from: usize, to: usize) -> Option<f64> {
    let at = |b: usize| {
        run.watch
            .track
            .iter()
            .find(|p| p.front >= b)
            .and_then(|p| p.energy.get(wi).copied())
    };
    Some(at(to)? / at(from)?)
}

/// Breathing of a confined wave (Figs. 13–14).
#[derive(Clone, Debug, PartialEq)]
pub struct Breathing {
    /// Front speed (beads per time unit), least squares over the analysed frames.
    pub speed: f64,
    /// Strongest periods of the window's peak velocity normalised by `√E_window` (widest
    /// window), in beads travelled, with relative power.
    pub peak_periods: Vec<(f64, f64)>,
    /// Strongest periods of the lag `front − peak bead` (beads travelled, relative power).
    pub lag_periods: Vec<(f64, f64)>,
    /// Range (max − min) over mean of the shape measure `|v_peak|/√E_window` over all frames.
    pub shape_range: f64,
    /// The same measure sampled once per lattice period (the first frame at each new even
    /// front): relative standard deviation (0 for a wave that repeats itself every 2 beads).
    pub strobe_rel_sd: f64,
    /// Strongest periods (4–100 beads) of the stroboscopic series (a slower modulation).
    pub strobe_periods: Vec<(f64, f64)>,
    /// Number of frames analysed.
    pub frames: usize,
}

/// Breathing analysis over the frames with `from ≤ front ≤ to`: periods 0.8–60 beads of the
/// frame series, 4–100 beads of the once-per-lattice-period series.
pub fn breathing(run: &PeriodicRun, from: usize, to: usize) -> Option<Breathing> {
    let pts: Vec<_> = run
        .watch
        .track
        .iter()
        .filter(|p| p.front >= from && p.front <= to)
        .collect();
    if pts.len() < 16 {
        return None;
    }
    let t: Vec<f64> = pts.iter().map(|p| p.t).collect();
    let f: Vec<f64> = pts.iter().map(|p| p.front as f64).collect();
    let n = t.len() as f64;
    let (tm, fm) = (t.iter().sum::<f64>() / n, f.iter().sum::<f64>() / n);
    let stt: f64 = t.iter().map(|x| (x - tm).powi(2)).sum();
    let stf: f64 = t.iter().zip(&f).map(|(a, b)| (a - tm) * (b - fm)).sum();
    let speed = stf / stt;
    // positions in beads travelled: x = speed · t (smooth, unlike the integer front)
    let x: Vec<f64> = t.iter().map(|ti| speed * ti).collect();
    let wl = WIDTHS.len() - 1;
    let peak: Vec<f64> = pts
        .iter()
        .map(|p| p.peak_velocity.abs() / p.energy[wl].max(f64::MIN_POSITIVE).sqrt())
        .collect();
    let lag: Vec<f64> = pts.iter().map(|p| (p.front - p.peak_bead) as f64).collect();
    let mean = peak.iter().sum::<f64>() / n;
    let (lo, hi) = peak
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| {
            (a.min(y), b.max(y))
        });
    let (mut sx, mut sy) = (Vec::new(), Vec::new());
    for i in 1..pts.len() {
        if pts[i].front != pts[i - 1].front && pts[i].front % 2 == 0 {
            sx.push(pts[i].front as f64);
            sy.push(peak[i]);
        }
    }
    let sm = sy.iter().sum::<f64>() / sy.len().max(1) as f64;
    let ssd = (sy.iter().map(|y| (y - sm).powi(2)).sum::<f64>() / sy.len().max(2) as f64).sqrt();
    Some(Breathing {
        speed,
        peak_periods: dominant_periods(&x, &peak, 0.8, 60.0, 3),
        lag_periods: dominant_periods(&x, &lag, 0.8, 60.0, 3),
        frames: pts.len(),
        shape_range: (hi - lo) / mean,
        strobe_rel_sd: ssd / sm,
        strobe_periods: dominant_periods(&sx, &sy, 4.0, 100.0, 3),
    })
}

/// Pairwise motion (Fig. 10) over the traced beads: for the `n_a`-joined pairs `(2j, 2j+1)` and
/// the `n_b`-joined pairs `(2j+1, 2j+2)` inside the trace range, the median over pairs of the
/// largest mismatch `|v_i − v_j| / peak` while either bead is above `frac` of the pair's peak,
/// and the worst pair. Returns `((median_a, worst_a), (median_b, worst_b))`.
pub fn pairing(run: &PeriodicRun, frac: f64) -> Option<((f64, f64), (f64, f64))> {
    let (lo, hi) = run.watch.trace_beads;
    let stat = |first: usize| {
        let mut w: Vec<f64> = (first..hi.saturating_sub(1))
            .step_by(2)
            .filter(|&i| i >= lo)
            .filter_map(|i| pair_mismatch(&run.watch.trace(i), &run.watch.trace(i + 1), frac))
            .map(|m| m.0)
            .collect();
        if w.is_empty() {
            return None;
        }
        w.sort_by(f64::total_cmp);
        Some((w[w.len() / 2], w[w.len() - 1]))
    };
    let a0 = lo + lo % 2; // first even bead
    Some((stat(a0)?, stat(a0 + 1)?))
}

/// Median over the traced `n_a` pairs `(2j, 2j+1)` of [`leader_changes`] (frames above `frac`
/// of the pair's peak, hysteresis `hyst`).
pub fn pair_leader_changes(run: &PeriodicRun, frac: f64, hyst: f64) -> Option<usize> {
    let (lo, hi) = run.watch.trace_beads;
    let mut c: Vec<usize> = (lo + lo % 2..hi.saturating_sub(1))
        .step_by(2)
        .filter_map(|i| leader_changes(&run.watch.trace(i), &run.watch.trace(i + 1), frac, hyst))
        .collect();
    if c.is_empty() {
        return None;
    }
    c.sort_unstable();
    Some(c[c.len() / 2])
}
