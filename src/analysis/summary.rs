//! The summary of a run's frames that `beadchain analyze` prints and Python's
//! `beadchain.analyze()` returns: counts, energies, the leading wave's track, speed and decay fit,
//! the incoming wave's energy, fragmentation and the interface split. A pure function of the
//! chain and its frames ([`summarize`]); reading the snapshot is the caller's.
//!
//! - **Energy reference** `E_ref = max(|E0|, S)`, with `S` the gross energy scale of the first
//!   and last frames ([`Chain::energy_scale`]: every part counted positive), the scale `run`
//!   uses for its relative energy change. For a chain with only kinetic and contact energy,
//!   `E_ref = E0`.
//! - **Leading wave**: the right-most right-moving pulse (eq. 13 energy, [`track_leading`]),
//!   tracked per frame.
//! - **Speed**: least-squares slope of its energy-weighted position against time (beads per
//!   unit time), over the frames whose position lies in the fit range `[fit_from, fit_to]`
//!   (defaults: 20, or `k + 10` with an interface `k`, to `N − 10`).
//! - **Decay**: `E/E_ref = a exp(−γ x)` over the same points (Sec. 5.2, eq. 20 ff.), at least
//!   [`MIN_FIT_POINTS`] of them: [`super::decay::decay_fit`], the definition `plot energy`
//!   shares.
//! - **Incoming energy**: the leading wave's energy once developed (position ≥ 10 beads, or
//!   `k/2`), in the last frame before it reaches the interface `k` (the first such frame
//!   without one).
//! - **Final state**: open gaps and fragments ([`fragmentation`]), the steady-state criterion of
//!   appendix A ([`is_steady_state`], relative tolerance [`STEADY_REL`]).
//! - **Interface** `k` (Sec. 3.2, 5.1): the energy split at bead `k` in the final frame, the
//!   largest reflected (left-moving) pulse left of `k` there, and `|v_out/v_in|` over all frames,
//!   given only where the frames resolve both peaks ([`super::VelocityRatio::checked`]).
//!
//! What cannot be computed is an `Err` naming the reason (never a NaN): a fit range that is
//! empty or reversed, too few points, a chain at rest, a leading wave that never develops.

use super::decay::{decay_fit, points_in, too_few, FitError, FitRange};
use super::{
    detect_pulses, energy_split, fragmentation, is_steady_state, track_leading, velocity_ratio,
    wave_energy, ExpFit, Fragmentation, Pulse, RatioError, TrackPoint, VelocityRatio, WaveOptions,
};
use crate::model::Chain;

pub use super::decay::MIN_FIT_POINTS;

/// Relative tolerance of the steady-state criterion applied to the final frame.
pub const STEADY_REL: f64 = 1e-5;

/// One frame: time, displacements `u` and velocities `v` (every bead).
pub type FrameView<'a> = (f64, &'a [f64], &'a [f64]);

/// Settings of [`summarize`]; `Default` is what `beadchain analyze` uses without options.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SummaryOptions {
    /// Interface bead `k` (`1 ≤ k < N`): energy split and velocity ratio; None: no interface.
    pub interface: Option<usize>,
    /// Fit range start (bead position) [default: 20, or `k + 10` with an interface].
    pub fit_from: Option<f64>,
    /// Fit range end [default: `N − 10`].
    pub fit_to: Option<f64>,
}

/// Why [`summarize`] refused its input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SummaryError {
    /// No frame at all.
    #[error("no frame to analyse")]
    NoFrames,
    /// The interface bead is outside `1..N`.
    #[error("interface must be in 1..{n}")]
    Interface {
        /// The bead asked for.
        k: usize,
        /// Number of beads.
        n: usize,
    },
    /// A frame's `u` or `v` does not hold one value per bead.
    #[error("frame {frame}: {field} holds {len} values, the chain has {n} beads")]
    FrameLength {
        /// Frame index.
        frame: usize,
        /// `"u"` or `"v"`.
        field: &'static str,
        /// Values in the frame.
        len: usize,
        /// Number of beads.
        n: usize,
    },
}

/// The leading wave's speed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Speed {
    /// Beads per unit time.
    pub value: f64,
    /// Frames in the fit.
    pub points: usize,
}

/// The interface split (final frame) and the velocity ratio (all frames).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterfaceSplit {
    /// Interface bead.
    pub k: usize,
    /// Time of the final frame.
    pub t: f64,
    /// Energy left of `k` (beads `0..k`, half the straddling contact).
    pub left: f64,
    /// Energy right of `k`.
    pub right: f64,
    /// The largest left-moving pulse left of `k` in the final frame (the reflected wave).
    pub reflected: Option<Pulse>,
    /// Its energy (eq. 13); 0 without one.
    pub reflected_energy: f64,
    /// Largest forward velocity before the interface over all frames.
    pub v_in: f64,
    /// Largest backward speed before the interface over all frames.
    pub v_out: f64,
    /// The two peaks as the frames sampled them ([`VelocityRatio::checked`]).
    pub velocity: VelocityRatio,
}

impl InterfaceSplit {
    /// `left / (left + right)`, None when the total is not positive.
    pub fn left_fraction(&self) -> Option<f64> {
        ratio(self.left, self.left + self.right)
    }

    /// `right / (left + right)`, None when the total is not positive.
    pub fn right_fraction(&self) -> Option<f64> {
        ratio(self.right, self.left + self.right)
    }

    /// `|v_out / v_in|`; an error when there is no incoming velocity or the frames do not
    /// resolve the two peaks ([`VelocityRatio::checked`]).
    pub fn velocity_ratio(&self) -> Result<f64, RatioError> {
        self.velocity.checked()
    }
}

/// Everything [`summarize`] finds (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Number of beads.
    pub n: usize,
    /// Number of frames.
    pub frames: usize,
    /// Time of the first frame.
    pub t_first: f64,
    /// Time of the last frame.
    pub t_last: f64,
    /// Total energy of the first frame.
    pub e0: f64,
    /// Total energy of the last frame.
    pub e_end: f64,
    /// Energy reference `max(|E0|, S)` (0 for a chain at rest).
    pub e_ref: f64,
    /// The leading wave of every frame that has one.
    pub track: Vec<TrackPoint>,
    /// Fit range `(from, to)` in bead positions, defaults applied.
    pub fit_range: (f64, f64),
    /// The decay fit of `E/E_ref`, or why it was not computed.
    pub decay: Result<ExpFit, FitError>,
    /// The leading wave's speed, or why it was not computed.
    pub speed: Result<Speed, FitError>,
    /// The incoming wave's energy, or why it was not computed.
    pub e_in: Result<f64, FitError>,
    /// Gaps and fragments of the final frame.
    pub fragmentation: Fragmentation,
    /// Whether the final frame is a steady state (appendix A).
    pub steady: bool,
    /// The interface split when an interface was given.
    pub interface: Option<InterfaceSplit>,
}

impl Summary {
    /// `|E_end − E0| / E_ref`, None when `E_ref = 0`.
    pub fn relative_change(&self) -> Option<f64> {
        ratio((self.e_end - self.e0).abs(), self.e_ref)
    }

    /// `e / E_ref`, None when `E_ref = 0`.
    pub fn fraction(&self, e: f64) -> Option<f64> {
        ratio(e, self.e_ref)
    }
}

/// `x / d` when `d > 0` (and the result is finite).
pub fn ratio(x: f64, d: f64) -> Option<f64> {
    let r = x / d;
    (d > 0.0 && r.is_finite()).then_some(r)
}

/// The summary of `frames` of `chain` (see the module docs). Errors: no frame, an interface
/// outside `1..N`, a frame without one value per bead.
pub fn summarize(
    chain: &Chain,
    frames: &[FrameView<'_>],
    opts: &SummaryOptions,
) -> Result<Summary, SummaryError> {
    let n = chain.len();
    let (Some(&first), Some(&last)) = (frames.first(), frames.last()) else {
        return Err(SummaryError::NoFrames);
    };
    let k_if = opts.interface.filter(|&k| k >= 1 && k < n);
    if let (Some(k), None) = (opts.interface, k_if) {
        return Err(SummaryError::Interface { k, n });
    }
    for (i, &(_, u, v)) in frames.iter().enumerate() {
        for (field, len) in [("u", u.len()), ("v", v.len())] {
            if len != n {
                return Err(SummaryError::FrameLength {
                    frame: i,
                    field,
                    len,
                    n,
                });
            }
        }
    }
    let wave = WaveOptions::default();
    let (_, u0, v0) = first;
    let (t_last, u1, v1) = last;
    let e0 = chain.energy(u0, v0);
    let e_end = chain.energy(u1, v1);
    let e_ref = e0
        .abs()
        .max(chain.energy_scale(u0, v0).max(chain.energy_scale(u1, v1)));
    let track = track_leading(chain, frames.iter().copied(), &wave);
    let x0 = opts
        .fit_from
        .unwrap_or(k_if.map_or(20.0, |k| k as f64 + 10.0));
    let x1 = opts.fit_to.unwrap_or(n as f64 - 10.0);
    let (decay, speed) = fits(&track, (x0, x1), opts.fit_to.is_some(), e_ref, n);
    Ok(Summary {
        n,
        frames: frames.len(),
        t_first: first.0,
        t_last,
        e0,
        e_end,
        e_ref,
        fit_range: (x0, x1),
        decay,
        speed,
        e_in: incoming_energy(&track, k_if),
        fragmentation: fragmentation(chain, u1, v1, 0.0),
        steady: is_steady_state(chain, u1, v1, STEADY_REL),
        interface: k_if.map(|k| interface(chain, frames, k, &wave)),
        track,
    })
}

/// Incoming-wave energy: the leading wave once developed (position >= 10 beads, or k/2), in
/// the last frame before it reaches the interface `k` (or the first such frame without one).
fn incoming_energy(track: &[TrackPoint], k_if: Option<usize>) -> Result<f64, FitError> {
    let developed = k_if.map_or(10.0, |k| (k as f64 / 2.0).min(10.0));
    let mut before = track
        .iter()
        .filter(|p| p.position >= developed && k_if.is_none_or(|k| p.pulse.last + 2 < k));
    if k_if.is_some() {
        before.next_back()
    } else {
        before.next()
    }
    .map(|p| p.energy)
    .ok_or(FitError::NoIncomingWave {
        developed,
        interface: k_if,
    })
}

/// The energy split at bead `k` in the final frame, the largest reflected pulse, and the
/// velocity ratio over all frames (`frames` not empty).
fn interface(
    chain: &Chain,
    frames: &[FrameView<'_>],
    k: usize,
    wave: &WaveOptions,
) -> InterfaceSplit {
    let (t, u, v) = frames[frames.len() - 1];
    let s = energy_split(chain, u, v, k);
    let vr = velocity_ratio(frames.iter().map(|f| (f.0, f.2)), k, (k / 2).min(20), 3);
    // reflected solitary wave: the largest left-moving pulse left of k in the final frame
    let reflected = detect_pulses(v, wave)
        .into_iter()
        .filter(|p| p.peak_velocity < 0.0 && p.last < k)
        .max_by(|a, b| a.peak_velocity.abs().total_cmp(&b.peak_velocity.abs()));
    InterfaceSplit {
        k,
        t,
        left: s.left,
        right: s.right,
        reflected,
        reflected_energy: reflected.map_or(0.0, |p| wave_energy(chain, u, v, p.first, p.last)),
        v_in: vr.v_in,
        v_out: vr.v_out,
        velocity: vr,
    }
}

/// Why no fit can be made over `[x0, x1]` before looking at the points, if so.
fn range_problem((x0, x1): (f64, f64), to_given: bool, e_ref: f64, n: usize) -> Option<FitError> {
    // comparisons written so that NaN counts as "not ordered" / "not positive"
    let (ordered, end_inside, positive) = (x0 <= x1, x1 >= 0.0, e_ref > 0.0);
    if x0.is_nan() || x1.is_nan() {
        Some(FitError::NotANumber { x0, x1 })
    } else if !ordered && !end_inside && !to_given {
        // the default end `N − 10` of a short chain (an end the user set below 0 makes the
        // range reversed, not the chain's fault)
        Some(FitError::ChainTooShort { n })
    } else if !ordered {
        Some(FitError::Reversed { x0, x1, n })
    } else if !positive {
        Some(FitError::AtRest)
    } else {
        None
    }
}

/// The decay fit and the speed fit over the leading-wave points inside `[x0, x1]`; an error
/// names what could not be computed and why.
fn fits(
    track: &[TrackPoint],
    (x0, x1): (f64, f64),
    to_given: bool,
    e_ref: f64,
    n: usize,
) -> (Result<ExpFit, FitError>, Result<Speed, FitError>) {
    if let Some(w) = range_problem((x0, x1), to_given, e_ref, n) {
        return (Err(w.clone()), Err(w));
    }
    let range = FitRange::inclusive(x0, x1);
    let pts = points_in(track, &range);
    if let Some(w) = too_few(&range, pts.len(), track.len()) {
        return (Err(w.clone()), Err(w));
    }
    let fit = decay_fit(track, &range, e_ref);
    let x: Vec<f64> = pts.iter().map(|p| p.position).collect();
    let t: Vec<f64> = pts.iter().map(|p| p.t).collect();
    let speed = slope(&t, &x).map(|value| Speed {
        value,
        points: pts.len(),
    });
    (fit, speed)
}

/// Least-squares slope of `y` against `x`.
fn slope(x: &[f64], y: &[f64]) -> Result<f64, FitError> {
    let m = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / m, y.iter().sum::<f64>() / m);
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let c = sxy / sxx;
    if sxx > 0.0 && c.is_finite() {
        Ok(c)
    } else {
        Err(FitError::OneTime)
    }
}
