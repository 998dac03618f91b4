//! Pulses ("waves") in a velocity profile, their energy (paper eq. 13) and the leading wave.
//!
//! **Detection** (paper Sec. 3.2: "the beads with more than 0.1 % of the peak bead velocity in
//! the wave"). A pulse is a local maximum of `|v_i|` (ties: the lowest index) whose value exceeds
//! `min_peak · max_j |v_j|`; its beads are the maximal interval around the peak where `|v|`
//! exceeds `threshold · |v_peak|` (default 10⁻³, the paper's 0.1 %), has the peak's sign, and does
//! not increase moving away from the peak. The last rule stops a pulse at the valley between two
//! pulses of a multipulse train (the paper's pulses are separated, where it coincides with the
//! plain threshold rule).
//!
//! **Energy** (eq. 13, with ½ on the kinetic part, see the [module docs](super)):
//! `E = Σ_{i=first}^{last} ½ m_i v_i² + Σ_{c=first}^{last−1} a_c δ_c^{n_c}`.
//!
//! **Leading wave**: the right-most pulse moving right (`v > 0`) whose peak is at least
//! `lead_frac · max|v|` of the frame; tracked over frames by [`track_leading`].

use crate::model::{contact_potential, Chain};

/// Detection parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WaveOptions {
    /// Bead threshold relative to the pulse's own peak `|v|` (paper: 0.001).
    pub threshold: f64,
    /// A local maximum is a pulse only if its `|v|` exceeds this fraction of the frame's max `|v|`.
    pub min_peak: f64,
    /// The leading wave must have at least this fraction of the frame's max `|v|`.
    pub lead_frac: f64,
}

impl Default for WaveOptions {
    fn default() -> Self {
        Self {
            threshold: 1e-3,
            min_peak: 1e-3,
            lead_frac: 0.1,
        }
    }
}

/// One pulse of a velocity profile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pulse {
    /// First bead (inclusive).
    pub first: usize,
    /// Last bead (inclusive).
    pub last: usize,
    /// Bead with the largest `|v|`.
    pub peak_bead: usize,
    /// Signed velocity of the peak bead.
    pub peak_velocity: f64,
}

impl Pulse {
    /// Number of beads `s = last − first + 1`.
    pub fn width(&self) -> usize {
        self.last - self.first + 1
    }
}

/// All pulses of a profile, ordered by peak bead.
pub fn detect_pulses(v: &[f64], opts: &WaveOptions) -> Vec<Pulse> {
    let vmax = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut out = Vec::new();
    if vmax == 0.0 || v.is_empty() {
        return out;
    }
    let n = v.len();
    let mut i = 0;
    while i < n {
        let a = v[i].abs();
        let left_ok = i == 0 || v[i - 1].abs() < a;
        let right_ok = i + 1 == n || v[i + 1].abs() <= a;
        if a > opts.min_peak * vmax && left_ok && right_ok {
            let sign = v[i].signum();
            let thr = opts.threshold * a;
            let inside = |j: usize, prev: usize| {
                v[j].signum() == sign && v[j].abs() > thr && v[j].abs() <= v[prev].abs()
            };
            let mut first = i;
            while first > 0 && inside(first - 1, first) {
                first -= 1;
            }
            let mut last = i;
            while last + 1 < n && inside(last + 1, last) {
                last += 1;
            }
            out.push(Pulse {
                first,
                last,
                peak_bead: i,
                peak_velocity: v[i],
            });
            i = last.max(i) + 1;
        } else {
            i += 1;
        }
    }
    out
}

/// The leading wave: right-most right-moving pulse with `|v_peak| ≥ lead_frac · max|v|`.
pub fn leading_pulse(v: &[f64], opts: &WaveOptions) -> Option<Pulse> {
    let vmax = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    detect_pulses(v, opts)
        .into_iter()
        .rev()
        .find(|p| p.peak_velocity > 0.0 && p.peak_velocity >= opts.lead_frac * vmax)
}

/// Energy of beads `first..=last` and of the contacts between them (eq. 13, ½ m v²).
pub fn wave_energy(chain: &Chain, u: &[f64], v: &[f64], first: usize, last: usize) -> f64 {
    let last = last.min(v.len().saturating_sub(1));
    let mut e = 0.0;
    for i in first..=last {
        e += 0.5 * chain.mass[i] * v[i] * v[i];
    }
    for c in first..last {
        let d = chain.overlap(c, u[c], u[c + 1]);
        e += contact_potential(chain.exponent[c], chain.prefactor[c], d);
    }
    e
}

/// Energy of the beads `lo..hi` (half-open) and of the contacts inside that range.
pub fn range_energy(chain: &Chain, u: &[f64], v: &[f64], lo: usize, hi: usize) -> f64 {
    if hi <= lo {
        return 0.0;
    }
    wave_energy(chain, u, v, lo, hi - 1)
}

/// The leading wave in one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackPoint {
    /// Frame time.
    pub t: f64,
    /// The pulse.
    pub pulse: Pulse,
    /// Its energy (eq. 13).
    pub energy: f64,
    /// Energy-weighted centre (in bead indices) of the pulse's kinetic energy.
    pub position: f64,
}

/// The leading wave of every frame that has one (frames as `(t, u, v)`).
pub fn track_leading<'a, I>(chain: &Chain, frames: I, opts: &WaveOptions) -> Vec<TrackPoint>
where
    I: IntoIterator<Item = (f64, &'a [f64], &'a [f64])>,
{
    let mut out = Vec::new();
    for (t, u, v) in frames {
        if let Some(p) = leading_pulse(v, opts) {
            let (mut w, mut wx) = (0.0, 0.0);
            for i in p.first..=p.last {
                let k = chain.mass[i] * v[i] * v[i];
                w += k;
                wx += k * i as f64;
            }
            out.push(TrackPoint {
                t,
                pulse: p,
                energy: wave_energy(chain, u, v, p.first, p.last),
                position: if w > 0.0 { wx / w } else { p.peak_bead as f64 },
            });
        }
    }
    out
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A uniform chain of `n` beads (m = 1, a = 1, exponent `e`).
    pub(crate) fn chain(n: usize, e: f64) -> Chain {
        Chain {
            mass: vec![1.0; n],
            exponent: vec![e; n - 1],
            prefactor: vec![1.0; n - 1],
            ..Chain::default()
        }
    }

    #[test]
    fn detects_two_pulses_split_at_valley_and_threshold() {
        // pulse A: peak 3 at bead 2, beads 1..=5 (bead 5 = 0.01 is above 0.003 and decreasing);
        // pulse B: peak -2 at bead 7, beads 6..=8 (0.0025 > 1e-3 * 2); signs split them.
        let v = [0.0, 1.0, 3.0, 1.0, 0.5, 0.01, -1.0, -2.0, -0.0025, 0.0];
        let p = detect_pulses(&v, &WaveOptions::default());
        assert_eq!(p.len(), 2, "{p:?}");
        assert_eq!((p[0].first, p[0].peak_bead, p[0].last), (1, 2, 5));
        assert_eq!((p[1].first, p[1].peak_bead, p[1].last), (6, 7, 8));
        assert_eq!(p[1].peak_velocity, -2.0);
        assert_eq!(p[1].width(), 3);
        // same sign, valley between two peaks: split at the valley
        let v = [0.0, 2.0, 0.5, 1.0, 0.0];
        let p = detect_pulses(&v, &WaveOptions::default());
        assert_eq!(p.len(), 2, "{p:?}");
        assert_eq!((p[0].first, p[0].last, p[1].first, p[1].last), (1, 2, 2, 3));
    }

    #[test]
    fn threshold_cuts_tail() {
        // peak 1 at bead 3; 0.002 is kept (> 1e-3), 0.0005 is not.
        let v = [0.0005, 0.002, 0.5, 1.0, 0.3, 0.0009];
        let p = detect_pulses(&v, &WaveOptions::default());
        assert_eq!(p.len(), 1);
        assert_eq!((p[0].first, p[0].last), (1, 4));
    }

    #[test]
    fn leading_is_rightmost_large_right_mover() {
        let opts = WaveOptions::default();
        // big pulse at 2, small (5 % of max) pulse at 8: leading = big one (lead_frac 0.1)
        let v = [0.0, 0.5, 1.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.05, 0.0];
        assert_eq!(leading_pulse(&v, &opts).map(|p| p.peak_bead), Some(2));
        // a left mover on the right is ignored
        let v = [0.0, 0.5, 1.0, 0.5, 0.0, 0.0, -0.9, 0.0];
        assert_eq!(leading_pulse(&v, &opts).map(|p| p.peak_bead), Some(2));
        assert_eq!(leading_pulse(&[0.0; 4], &opts), None);
    }

    #[test]
    fn wave_energy_exact() {
        let c = chain(4, 2.0);
        // overlaps: c0 = 0.3-0.1 = 0.2, c1 = 0.1-0 = 0.1, c2 = 0
        let u = [0.3, 0.1, 0.0, 0.0];
        let v = [1.0, 2.0, 0.0, 0.0];
        // kinetic 0.5*(1+4) = 2.5, potential 0.04 + 0.01 = 0.05 (exact up to rounding, 1e-14 abs)
        let e = wave_energy(&c, &u, &v, 0, 3);
        assert!((e - 2.55).abs() < 1e-14, "{e}");
        assert!((wave_energy(&c, &u, &v, 0, 3) - c.energy(&u, &v)).abs() < 1e-14);
        assert!((range_energy(&c, &u, &v, 1, 3) - (2.0 + 0.01)).abs() < 1e-14);
    }

    #[test]
    fn tracks_moving_pulse() {
        let c = chain(10, 2.5);
        let u = vec![0.0; 10];
        let frames: Vec<(f64, Vec<f64>)> = (0..5)
            .map(|k| {
                let mut v = vec![0.0; 10];
                v[2 + k] = 1.0;
                v[3 + k] = 0.5;
                (k as f64, v)
            })
            .collect();
        let tr = track_leading(
            &c,
            frames.iter().map(|(t, v)| (*t, u.as_slice(), v.as_slice())),
            &WaveOptions::default(),
        );
        assert_eq!(tr.len(), 5);
        for (k, p) in tr.iter().enumerate() {
            assert_eq!(p.pulse.peak_bead, 2 + k);
            // energy 0.5*(1 + 0.25) = 0.625; position (1*i + 0.25*(i+1))/1.25 = i + 0.2 (1e-12 abs)
            assert!((p.energy - 0.625).abs() < 1e-14);
            assert!((p.position - (2.2 + k as f64)).abs() < 1e-12);
        }
    }
}
