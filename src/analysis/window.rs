//! Windowed wave energy: an alternative to leading-pulse tracking for waves whose energy moves
//! between pulses (the breathing confined waves of the periodic chains, paper Sec. 4,
//! Figs. 12–14).
//!
//! - **Front** ([`front_bead`]): the furthest bead to the right whose `|v|` exceeds `frac` (paper:
//!   0.1 %, as for pulses in Sec. 3.2) of the frame's `max |v|`.
//! - **Window energy** ([`window_energy`]): eq. 13 (with ½ on the kinetic part, see the
//!   [module docs](super)) summed over the `width` beads ending at the front,
//!   `front − width + 1 ..= front`, and the contacts between them. A breathing wave whose peak
//!   hops between its beads keeps its whole energy inside the window, where the leading-pulse
//!   rule follows one of its sub-pulses at a time.
//! - [`WindowWatch`]: an engine observer that records the front, the window energies for several
//!   widths, the peak inside the window, and (optionally) velocity traces of a range of beads;
//!   it stops the run when the front reaches a given bead.
//! - [`windowed_decay`]: `E_w/E_0` against the front position, log-linear fit of
//!   `E = a e^{−γ x}` (Sec. 5.2, the fit below Fig. 21) — the paper's decay rate of Fig. 12,
//!   measured on the window.
//! - [`dominant_periods`]: periodogram of the window's peak velocity against the distance the
//!   front travelled, for the breathing period of the confined waves (Figs. 13–14).
//! - [`pair_mismatch`]: how far two beads' velocities differ while a wave passes (the pairwise
//!   collective motion of Fig. 10).

use super::fit::{fit_exponential, ExpFit};
use super::wave::wave_energy;
use super::AnalysisError;
use crate::engine::{Control, EngineError, Observer};
use crate::model::Chain;

/// Furthest bead with `|v| > frac · max|v|` (`None` for a chain at rest).
pub fn front_bead(v: &[f64], frac: f64) -> Option<usize> {
    let vmax = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if vmax <= 0.0 {
        return None;
    }
    v.iter().rposition(|x| x.abs() > frac * vmax)
}

/// Energy of the `width` beads ending at bead `front` (clamped at bead 0) and their contacts.
pub fn window_energy(chain: &Chain, u: &[f64], v: &[f64], front: usize, width: usize) -> f64 {
    if width == 0 || v.is_empty() {
        return 0.0;
    }
    let front = front.min(v.len() - 1);
    wave_energy(chain, u, v, (front + 1).saturating_sub(width), front)
}

/// One frame of a [`WindowWatch`].
#[derive(Clone, Debug, PartialEq)]
pub struct WindowPoint {
    /// Frame time.
    pub t: f64,
    /// Front bead.
    pub front: usize,
    /// Window energies, one per width of [`WindowWatch::widths`].
    pub energy: Vec<f64>,
    /// Bead of the largest `|v|` inside the widest window.
    pub peak_bead: usize,
    /// Its velocity.
    pub peak_velocity: f64,
}

/// Observer recording the front and windowed energies; stops when the front reaches `stop_at`.
pub struct WindowWatch {
    chain: Chain,
    /// Window widths (beads).
    pub widths: Vec<usize>,
    /// Front threshold relative to the frame's `max |v|` (paper: 1e-3).
    pub frac: f64,
    stop_at: usize,
    /// One point per frame that has a front.
    pub track: Vec<WindowPoint>,
    /// Beads `lo..hi` whose velocities are recorded every frame (empty range: none).
    pub trace_beads: (usize, usize),
    /// Flat traces: frame `f`, bead `lo + j` at `traces[f · (hi − lo) + j]`.
    pub traces: Vec<f64>,
    /// Frame times of the traces.
    pub trace_t: Vec<f64>,
    /// Largest velocity each bead reached over the run (for energy-transfer ratios).
    pub vmax: Vec<f64>,
    stop: bool,
}

impl WindowWatch {
    /// A watch with window `widths`, stopping when the front reaches `stop_at`.
    pub fn new(chain: Chain, widths: &[usize], stop_at: usize) -> Self {
        let n = chain.mass.len();
        WindowWatch {
            chain,
            widths: widths.to_vec(),
            frac: 1e-3,
            stop_at,
            track: Vec::new(),
            trace_beads: (0, 0),
            traces: Vec::new(),
            trace_t: Vec::new(),
            vmax: vec![0.0; n],
            stop: false,
        }
    }

    /// Also record the velocities of beads `lo..hi` every frame.
    pub fn with_traces(mut self, lo: usize, hi: usize) -> Self {
        self.trace_beads = (lo, hi.max(lo));
        self
    }

    /// Velocity trace of bead `i` (empty when it was not recorded).
    pub fn trace(&self, i: usize) -> Vec<f64> {
        let (lo, hi) = self.trace_beads;
        if i < lo || i >= hi {
            return Vec::new();
        }
        let w = hi - lo;
        self.traces.chunks_exact(w).map(|f| f[i - lo]).collect()
    }
}

impl Observer for WindowWatch {
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        for (m, x) in self.vmax.iter_mut().zip(v) {
            *m = m.max(*x);
        }
        let (lo, hi) = self.trace_beads;
        if hi > lo && hi <= v.len() {
            self.traces.extend_from_slice(&v[lo..hi]);
            self.trace_t.push(t);
        }
        if let Some(front) = front_bead(v, self.frac) {
            let energy = self
                .widths
                .iter()
                .map(|&w| window_energy(&self.chain, u, v, front, w))
                .collect();
            let wmax = self.widths.iter().copied().max().unwrap_or(1).max(1);
            let first = (front + 1).saturating_sub(wmax);
            let (mut peak_bead, mut peak_velocity) = (front, v[front]);
            for (i, &x) in v.iter().enumerate().take(front + 1).skip(first) {
                if x.abs() > peak_velocity.abs() {
                    peak_bead = i;
                    peak_velocity = x;
                }
            }
            self.track.push(WindowPoint {
                t,
                front,
                energy,
                peak_bead,
                peak_velocity,
            });
            if front >= self.stop_at {
                self.stop = true;
            }
        }
        Ok(())
    }
    fn control(&mut self, _t: f64) -> Control {
        Control::stop_if(self.stop)
    }
}

/// Decay fit of the window energy (width index `wi`): `E/E0` with `E0` the first frame whose
/// front is at least `e0_at`, fitted against the front position over the frames with
/// `from ≤ front ≤ to`.
pub fn windowed_decay(
    track: &[WindowPoint],
    wi: usize,
    e0_at: usize,
    from: usize,
    to: usize,
) -> Result<ExpFit, AnalysisError> {
    let e0 = track
        .iter()
        .find(|p| p.front >= e0_at)
        .and_then(|p| p.energy.get(wi).copied())
        .ok_or_else(|| AnalysisError::NotFound(format!("the front never reached bead {e0_at}")))?;
    let (mut x, mut e) = (Vec::new(), Vec::new());
    for p in track.iter().filter(|p| p.front >= from && p.front <= to) {
        let ei = p
            .energy
            .get(wi)
            .copied()
            .ok_or_else(|| AnalysisError::Length(format!("no window width index {wi}")))?;
        x.push(p.front as f64);
        e.push(ei / e0);
    }
    fit_exponential(&x, &e)
}

/// The `count` strongest local maxima of the periodogram of `y` (sampled at positions `x`,
/// evenly or not) over periods `p_min..=p_max` (in units of `x`, 400 log-spaced trial periods),
/// after removing a linear trend. Returns `(period, relative power)` sorted by power
/// (the strongest has power 1); empty with fewer than 8 samples.
pub fn dominant_periods(
    x: &[f64],
    y: &[f64],
    p_min: f64,
    p_max: f64,
    count: usize,
) -> Vec<(f64, f64)> {
    let n = x.len().min(y.len());
    if n < 8 || !(p_min > 0.0 && p_max > p_min) {
        return Vec::new();
    }
    let nf = n as f64;
    let xm = x[..n].iter().sum::<f64>() / nf;
    let ym = y[..n].iter().sum::<f64>() / nf;
    let sxx: f64 = x[..n].iter().map(|a| (a - xm).powi(2)).sum();
    let slope = if sxx > 0.0 {
        x[..n]
            .iter()
            .zip(&y[..n])
            .map(|(a, b)| (a - xm) * (b - ym))
            .sum::<f64>()
            / sxx
    } else {
        0.0
    };
    let r: Vec<f64> = (0..n).map(|i| y[i] - ym - slope * (x[i] - xm)).collect();
    let trials = 400;
    let power: Vec<(f64, f64)> = (0..trials)
        .map(|k| {
            let p = p_min * (p_max / p_min).powf(k as f64 / (trials - 1) as f64);
            let w = std::f64::consts::TAU / p;
            let (mut c, mut s) = (0.0, 0.0);
            for i in 0..n {
                c += r[i] * (w * x[i]).cos();
                s += r[i] * (w * x[i]).sin();
            }
            (p, c * c + s * s)
        })
        .collect();
    let mut peaks: Vec<(f64, f64)> = (1..trials - 1)
        .filter(|&k| power[k].1 > power[k - 1].1 && power[k].1 >= power[k + 1].1)
        .map(|k| power[k])
        .collect();
    peaks.sort_by(|a, b| b.1.total_cmp(&a.1));
    peaks.truncate(count);
    let top = peaks.first().map_or(1.0, |p| p.1);
    peaks.iter().map(|&(p, w)| (p, w / top)).collect()
}

/// Velocity mismatch of two beads while a wave passes: over the frames where
/// `max(|a|, |b|) ≥ frac · peak` (`peak` = the larger of the two beads' largest `|v|`), the largest
/// `|a − b| / peak` (first value) and its root mean square (second). `None` if neither moves.
pub fn pair_mismatch(a: &[f64], b: &[f64], frac: f64) -> Option<(f64, f64)> {
    let peak = a.iter().chain(b).fold(0.0f64, |m, x| m.max(x.abs()));
    if peak <= 0.0 {
        return None;
    }
    let (mut worst, mut sum, mut k) = (0.0f64, 0.0, 0usize);
    for (x, y) in a.iter().zip(b) {
        if x.abs().max(y.abs()) >= frac * peak {
            let d = (x - y).abs() / peak;
            worst = worst.max(d);
            sum += d * d;
            k += 1;
        }
    }
    (k > 0).then(|| (worst, (sum / k as f64).sqrt()))
}

/// How often the faster of two beads changes while a wave passes (the paper's "the bead with
/// the highest velocity changes three times", Fig. 13): sign changes of `a − b`, counted with
/// hysteresis (only where `|a − b| > hyst · peak`), over the frames where
/// `max(|a|, |b|) ≥ frac · peak`. `None` if neither bead moves.
pub fn leader_changes(a: &[f64], b: &[f64], frac: f64, hyst: f64) -> Option<usize> {
    let peak = a.iter().chain(b).fold(0.0f64, |m, x| m.max(x.abs()));
    if peak <= 0.0 {
        return None;
    }
    let (mut state, mut changes) = (0i8, 0usize);
    for (x, y) in a.iter().zip(b) {
        if x.abs().max(y.abs()) < frac * peak {
            continue;
        }
        let d = x - y;
        let s = if d > hyst * peak {
            1
        } else if d < -hyst * peak {
            -1
        } else {
            0
        };
        if s != 0 {
            if state != 0 && s != state {
                changes += 1;
            }
            state = s;
        }
    }
    Some(changes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::wave::tests::chain;

    #[test]
    fn front_and_window() {
        let v = [0.0, 1.0, 0.5, 0.0011, 0.0009, 0.0];
        // 0.0011 > 1e-3 · 1.0 is the furthest above threshold; 0.0009 is not
        assert_eq!(front_bead(&v, 1e-3), Some(3));
        assert_eq!(front_bead(&[0.0; 3], 1e-3), None);
        let c = chain(6, 2.0);
        let u = [0.0; 6];
        // width 2 ending at 3: beads 2, 3: 0.5·(0.25 + 0.0011²), no overlaps (exact, abs 1e-15)
        let e = window_energy(&c, &u, &v, 3, 2);
        assert!((e - 0.5 * (0.25 + 0.0011f64.powi(2))).abs() < 1e-15);
        // a window wider than the chain start is clamped at bead 0
        let all = window_energy(&c, &u, &v, 3, 50);
        assert!((all - 0.5 * (1.0 + 0.25 + 0.0011f64.powi(2))).abs() < 1e-15);
    }

    #[test]
    fn periodogram_finds_sine() {
        // y = 0.3 x + sin(2π x / 7.5): the trend is removed, the period found within the trial
        // grid's step (400 log-spaced periods over 2..50: relative step 0.8 %, tolerance 2 %)
        let x: Vec<f64> = (0..600).map(|i| i as f64 * 0.25).collect();
        let y: Vec<f64> = x
            .iter()
            .map(|x| 0.3 * x + (std::f64::consts::TAU * x / 7.5).sin())
            .collect();
        let p = dominant_periods(&x, &y, 2.0, 50.0, 3);
        assert!((p[0].0 - 7.5).abs() < 0.02 * 7.5, "{p:?}");
        assert_eq!(p[0].1, 1.0);
    }

    #[test]
    fn pair_mismatch_values() {
        let a = [0.0, 0.5, 1.0, 0.5, 0.0];
        let b = [0.0, 0.4, 1.0, 0.6, 0.001];
        // frames with max ≥ 0.1: 1, 2, 3; diffs 0.1, 0, 0.1 → worst 0.1, rms sqrt(0.02/3)
        let (w, r) = pair_mismatch(&a, &b, 0.1).unwrap();
        assert!((w - 0.1).abs() < 1e-12, "{w}");
        assert!((r - (0.02f64 / 3.0).sqrt()).abs() < 1e-12, "{r}");
        assert!(pair_mismatch(&[0.0], &[0.0], 0.1).is_none());
        // a leads, then b (by 0.3 > 0.05), then a again: 2 changes; the 0.01 wiggle is ignored
        let a = [0.0, 1.0, 0.2, 0.51, 0.8, 0.0];
        let b = [0.0, 0.5, 0.5, 0.50, 0.3, 0.0];
        assert_eq!(leader_changes(&a, &b, 0.1, 0.05), Some(2));
    }
}
