//! Output-size estimate of a run, checked before anything is written (issue 11, item 13).
//!
//! A run writes one FRAME section per output time `0, every, 2·every, …, until` (see
//! [`crate::engine::RunConfig::frame_time`]): at most `⌊until/every⌋ + 2` frames, each
//! `16` (section header) `+ 16 + 16 N` (number, time, `u`, `v`) bytes plus `16` bytes of INDEX.
//! The HEADER holds the resolved scene (about eight arrays of `N` numbers). The event log is
//! not counted (it is not known in advance). With an [output selection](super::select) a frame
//! holds `8 M F` bytes of values instead of `16 N` ([`output_bytes_estimate_values`]). [`DEFAULT_MAX_OUTPUT_BYTES`] is the limit `run`,
//! `resume` and `sweep` (per run, frames kept in memory) apply unless told otherwise.

use super::{PREAMBLE_LEN, SECTION_HEADER_LEN};

/// Default limit of the estimated output of one run: 10 GiB.
pub const DEFAULT_MAX_OUTPUT_BYTES: u64 = 10 << 30;

/// Upper bound on the frames a run from `t0` to `until` writes with interval `every`
/// (`None`: first and last frame only). Infinite when `every` is tiny against `until`.
pub fn frame_count_estimate(t0: f64, until: f64, every: Option<f64>) -> f64 {
    match every {
        Some(dt) if dt > 0.0 => ((until - t0).max(0.0) / dt).floor() + 2.0,
        _ => 2.0,
    }
}

/// Exact number of frames a whole run to `until` writes (times `k·every` below `until`, then
/// `until` itself, as [`crate::engine::RunConfig::frame_time`]; first and last without
/// `every`). `f64`: the count may exceed `u64`.
pub fn frame_count(until: f64, every: Option<f64>) -> f64 {
    match every {
        None => {
            if until > 0.0 {
                2.0
            } else {
                1.0
            }
        }
        Some(dt) => {
            let q = (until.max(0.0) / dt).ceil();
            if q.is_nan() || q >= 1e15 {
                return q + 1.0; // beyond exact integer steps: any cap is exceeded anyway
            }
            // The last frame is the first k whose k·dt reaches until, in the engines' arithmetic
            // (`engine::reaches_until`).
            let reaches = |k: u64| crate::engine::reaches_until(k as f64 * dt, until);
            let mut k = q as u64;
            while k > 0 && reaches(k - 1) {
                k -= 1;
            }
            while !reaches(k) {
                k += 1;
            }
            k as f64 + 1.0
        }
    }
}

/// Estimated bytes of a snapshot of `n_beads` beads and `frames` frames (`f64`: the estimate
/// may exceed `u64::MAX`).
pub fn output_bytes_estimate(n_beads: usize, frames: f64) -> f64 {
    output_bytes_estimate_values(n_beads, 2.0 * n_beads as f64, frames)
}

/// [`output_bytes_estimate`] for frames storing `values` numbers each (an output selection of
/// `M` beads and `F` fields stores `M·F`; every bead and both fields `2 N`).
pub fn output_bytes_estimate_values(n_beads: usize, values: f64, frames: f64) -> f64 {
    let n = n_beads as f64;
    let per_frame = (SECTION_HEADER_LEN as f64) + 16.0 + 8.0 * values + 16.0;
    let fixed = PREAMBLE_LEN as f64 + 4096.0 + 64.0 * n + 5.0 * SECTION_HEADER_LEN as f64;
    fixed + frames * per_frame
}

/// A byte count for messages: `12.3 GiB`, `512.0 MiB`, `1.5e+300 bytes` beyond exbibytes.
pub fn human_bytes(b: f64) -> String {
    const UNITS: [&str; 7] = ["bytes", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"];
    if !b.is_finite() || b >= 1024f64.powi(7) {
        return format!("{b:.1e} bytes");
    }
    let mut x = b;
    let mut u = 0;
    while x >= 1024.0 && u + 1 < UNITS.len() {
        x /= 1024.0;
        u += 1;
    }
    if u == 0 {
        format!("{b} bytes")
    } else {
        format!("{x:.1} {}", UNITS[u])
    }
}

/// A frame count for messages: an integer below 10^15, else `2.000e300` form.
pub fn count_text(x: f64) -> String {
    if x.is_finite() && x < 1e15 {
        format!("{x:.0}")
    } else {
        format!("{x:.3e}")
    }
}

/// A number as `{}` in `1e-5 ≤ |x| < 1e16`, else as `{:e}` (`1e300`, not 301 digits).
pub fn short(x: f64) -> String {
    if x == 0.0 || (1e-5..1e16).contains(&x.abs()) {
        x.to_string()
    } else {
        format!("{x:e}")
    }
}

/// A time `x` in computer units that was given in seconds, as the CLI's and Python's refusals
/// show it: `1.0000e-4 s = 110.40913187338107 computer units` (`beta`: the time unit in s).
pub fn seconds_then_units(x: f64, beta: f64) -> String {
    format!("{:.4e} s = {} computer units", x * beta, short(x))
}

/// A run's estimated output above its limit ([`check_output_size`]): the caller words the
/// message with its own option names (the CLI's `--every`, Python's `every=`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutputTooLarge {
    /// Estimated bytes ([`output_bytes_estimate_values`]).
    pub bytes: f64,
    /// Estimated frames ([`frame_count_estimate`] plus the frames written before).
    pub frames: f64,
}

/// The size rule of `run`, `resume`, `sweep` and Python's `run()`: a run of `n_beads` beads
/// (frames of `values` stored numbers) from `t0` to `until` with interval `every`, after
/// `frames_before` frames already written, is refused when its estimated output is above
/// `limit` bytes.
pub fn check_output_size(
    (n_beads, values): (usize, u64),
    (t0, until, every): (f64, f64, Option<f64>),
    frames_before: usize,
    limit: u64,
) -> Result<(), OutputTooLarge> {
    let frames = frame_count_estimate(t0, until, every) + frames_before as f64;
    let bytes = output_bytes_estimate_values(n_beads, values as f64, frames);
    if bytes > limit as f64 {
        return Err(OutputTooLarge { bytes, frames });
    }
    Ok(())
}

/// A run that would write more frames than its `frames_max` cap ([`check_frames_max`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TooManyFrames {
    /// Frames the run would write ([`frame_count`]).
    pub count: f64,
    /// The cap.
    pub frames_max: u64,
    /// The smallest `every` with which the run fits the cap.
    pub every_that_fits: f64,
}

/// The `frames_max` rule of `run`, `resume` and Python's `run()`: a run to `until` with
/// interval `every` that would write more than `frames_max` frames is refused (never thinned).
pub fn check_frames_max(
    frames_max: Option<u64>,
    until: f64,
    every: Option<f64>,
) -> Result<(), TooManyFrames> {
    let Some(k) = frames_max else {
        return Ok(());
    };
    let count = frame_count(until, every);
    if count <= k as f64 {
        return Ok(());
    }
    Err(TooManyFrames {
        count,
        frames_max: k,
        every_that_fits: every_that_fits(until, k),
    })
}

/// The smallest `every` (to f64 rounding) with which a run to `until` writes at most `k ≥ 2`
/// frames: `until/(k−1)`, stepped up by ulps until [`frame_count`] agrees.
fn every_that_fits(until: f64, k: u64) -> f64 {
    let mut dt = until / k.saturating_sub(1).max(1) as f64;
    for _ in 0..64 {
        if frame_count(until, Some(dt)) <= k as f64 {
            break;
        }
        dt = f64::from_bits(dt.to_bits() + 1);
    }
    dt
}

/// The latest end time (to a few ulps) at which a run with interval `every` writes at most
/// `k ≥ 2` frames: `(k−1)·every`, stepped down by ulps until [`frame_count`] agrees (`resume`,
/// whose interval and cap are fixed, advises it).
pub fn until_that_fits(every: f64, k: u64) -> f64 {
    let mut until = k.saturating_sub(1).max(1) as f64 * every;
    for _ in 0..64 {
        if frame_count(until, Some(every)) <= k as f64 {
            break;
        }
        until = f64::from_bits(until.to_bits() - 1);
    }
    until
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_max_refusal_names_count_and_every_that_fits() {
        assert!(check_frames_max(None, 20.0, Some(1.0)).is_ok());
        assert!(check_frames_max(Some(21), 20.0, Some(1.0)).is_ok());
        let e = check_frames_max(Some(5), 20.0, Some(1.0)).unwrap_err();
        assert_eq!(e.count, 21.0);
        assert_eq!(e.every_that_fits, 5.0);
        assert!(frame_count(20.0, Some(e.every_that_fits)) <= 5.0);
    }

    #[test]
    fn until_that_fits_is_the_last_end_time_within_the_cap() {
        for (every, k) in [(5.0, 600), (0.1, 11), (0.3, 7), (1e-3, 1001)] {
            let t = until_that_fits(every, k);
            assert!(frame_count(t, Some(every)) <= k as f64, "{every} {k}");
            // a relative 1e-12 later writes one frame more (within 16 ulps, a time that reaches
            // the last frame's `k·every` still ends on it: `engine::reaches_until`)
            assert!(
                frame_count(t * (1.0 + 1e-12), Some(every)) > k as f64,
                "{every} {k}"
            );
        }
        assert_eq!(until_that_fits(5.0, 600), 2995.0);
    }

    #[test]
    fn output_size_refusal_above_limit_only() {
        // 2 beads, first and last frame: far below 1 MiB; 1e6 frames of 1000 beads: above.
        assert!(check_output_size((2, 4), (0.0, 1.0, None), 0, 1 << 20).is_ok());
        let e = check_output_size((1000, 2000), (0.0, 1e6, Some(1.0)), 0, 1 << 30).unwrap_err();
        assert_eq!(e.frames, 1e6 + 2.0);
        assert!(e.bytes > 1.6e10, "{}", e.bytes);
    }
}
