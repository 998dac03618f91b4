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
            // The last frame is the first k with k·dt ≥ until, in the engines' arithmetic.
            let mut k = q as u64;
            while k > 0 && (k - 1) as f64 * dt >= until {
                k -= 1;
            }
            while (k as f64 * dt) < until {
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
