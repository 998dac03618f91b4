//! The leading wave's decay rate, one definition for `beadchain analyze` (and Python's
//! `analyze()`) and `beadchain plot energy` (issue 36: they used to fit different points and
//! report different rates for one file).
//!
//! **Definition.** Over the frames with a leading wave ([`track_leading`](super::track_leading)),
//! the points `(x, E/E_ref)` with `x` the wave's energy-weighted position in beads
//! ([`TrackPoint::position`]) and `E` its energy (eq. 13), restricted to a range of positions
//! ([`FitRange`], bounds included, or the upper one excluded for the side of an interface left of
//! it), at least [`MIN_FIT_POINTS`] of them, are fitted by `E/E_ref = a exp(−γ x)`
//! ([`fit_exponential`]). `E_ref` only scales `a`: `analyze` divides by its energy reference,
//! `plot energy` by the first frame's energy; `γ` and the point count are the same.
//!
//! `plot energy` used to take the peak bead (an integer) for `x` and `analyze` the
//! energy-weighted position: on the `periodic_decay_2.5_2.555` preset, γ = 2.62279e-2 over 167
//! points against 2.62222e-2 over 166.

use super::{fit_exponential, AnalysisError, ExpFit, TrackPoint};
use std::fmt;

/// Fewest leading-wave points for the speed and decay fits.
pub const MIN_FIT_POINTS: usize = 3;

/// The reason [`Summary::e_in`](super::Summary::e_in) gives when the leading wave never
/// develops (reaches position `developed`) before the interface bead, if there is one.
fn no_incoming_wave(developed: f64, interface: Option<usize>) -> String {
    match interface {
        Some(k) => format!(
            "the leading wave never reaches position {developed} (k/2, at most 10) before the interface bead k = {k}"
        ),
        None => format!("the leading wave never reaches position {developed}"),
    }
}

/// The hint of the fit-range messages of `beadchain analyze` (Python's names it differently).
const RANGE_DEFAULTS: &str = "default: positions 20 (or k + 10) to N - 10; set --fit-from/--fit-to";

/// Why a leading-wave fit (decay, speed) or the incoming energy was not computed (one line).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FitError {
    /// Too few leading-wave points in the range.
    #[error(
        "the leading wave is in positions {range} in {got} of {of} frames with a leading wave, fewer than {}",
        MIN_FIT_POINTS
    )]
    TooFew {
        /// The fit range.
        range: FitRange,
        /// Points in it.
        got: usize,
        /// Frames with a leading wave.
        of: usize,
    },
    /// The least-squares fit failed.
    #[error(transparent)]
    Fit(AnalysisError),
    /// The fit's values are not finite.
    #[error("the log-linear fit is degenerate (all points at one position)")]
    Degenerate,
    /// Every point of the speed fit is at one time.
    #[error("all its frames are at one time")]
    OneTime,
    /// The default range is empty: the chain is too short.
    #[error(
        "the chain has {n} beads, too few for the fit range ({})",
        RANGE_DEFAULTS
    )]
    ChainTooShort {
        /// Beads in the chain.
        n: usize,
    },
    /// The range starts after its end.
    #[error(
        "the fit range starts at position {x0}, after its end {x1} (chain of {n} beads; {})",
        RANGE_DEFAULTS
    )]
    Reversed {
        /// Start of the range.
        x0: f64,
        /// End of the range.
        x1: f64,
        /// Beads in the chain.
        n: usize,
    },
    /// A bound of the range is not a number.
    #[error(
        "the fit range's bounds must be numbers, got {x0} to {x1} ({})",
        RANGE_DEFAULTS
    )]
    NotANumber {
        /// Start of the range.
        x0: f64,
        /// End of the range.
        x1: f64,
    },
    /// Nothing moves.
    #[error("the energy scale is 0 (the chain is at rest)")]
    AtRest,
    /// No incoming wave (before the interface, if there is one).
    #[error("{}", no_incoming_wave(*developed, *interface))]
    NoIncomingWave {
        /// The position from which the wave counts as developed.
        developed: f64,
        /// The interface bead, if one was given.
        interface: Option<usize>,
    },
}

/// A range of leading-wave positions (in beads): `from ≤ x ≤ to`, or `from ≤ x < to` when
/// `to_included` is false.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitRange {
    /// Lowest position (included).
    pub from: f64,
    /// Highest position.
    pub to: f64,
    /// Whether `to` itself is in the range.
    pub to_included: bool,
}

impl FitRange {
    /// `from ≤ x ≤ to`.
    pub fn inclusive(from: f64, to: f64) -> Self {
        Self {
            from,
            to,
            to_included: true,
        }
    }

    /// `from ≤ x < to`.
    pub fn below(from: f64, to: f64) -> Self {
        Self {
            from,
            to,
            to_included: false,
        }
    }

    /// Whether position `x` is in the range.
    pub fn contains(&self, x: f64) -> bool {
        x >= self.from && (x < self.to || (self.to_included && x == self.to))
    }
}

impl fmt::Display for FitRange {
    /// `20 to 140`, or `20 to below 30`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let below = if self.to_included { "" } else { "below " };
        write!(f, "{} to {below}{}", self.from, self.to)
    }
}

/// The points of `track` inside `range`.
pub fn points_in<'a>(track: &'a [TrackPoint], range: &FitRange) -> Vec<&'a TrackPoint> {
    track
        .iter()
        .filter(|p| range.contains(p.position))
        .collect()
}

/// Why a range holds too few points (`got` of the track's `of`), if it does.
pub fn too_few(range: &FitRange, got: usize, of: usize) -> Option<FitError> {
    (got < MIN_FIT_POINTS).then_some(FitError::TooFew {
        range: *range,
        got,
        of,
    })
}

/// The decay fit of the module docs over the points of `track` in `range`, energies divided by
/// `e_ref`; an error names why there is none (too few points, a degenerate fit).
pub fn decay_fit(track: &[TrackPoint], range: &FitRange, e_ref: f64) -> Result<ExpFit, FitError> {
    let pts = points_in(track, range);
    if let Some(w) = too_few(range, pts.len(), track.len()) {
        return Err(w);
    }
    let x: Vec<f64> = pts.iter().map(|p| p.position).collect();
    let e: Vec<f64> = pts.iter().map(|p| p.energy / e_ref).collect();
    let f = fit_exponential(&x, &e).map_err(FitError::Fit)?;
    if [f.a, f.gamma, f.gamma_stderr, f.r2]
        .iter()
        .all(|v| v.is_finite())
    {
        Ok(f)
    } else {
        Err(FitError::Degenerate)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges() {
        let r = FitRange::inclusive(20.0, 30.0);
        assert!(r.contains(20.0) && r.contains(30.0) && !r.contains(30.5));
        assert_eq!(r.to_string(), "20 to 30");
        let r = FitRange::below(20.0, 30.0);
        assert!(r.contains(29.9) && !r.contains(30.0) && !r.contains(19.9));
        assert_eq!(r.to_string(), "20 to below 30");
    }
}
