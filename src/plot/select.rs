//! Selections in a snapshot: bead ranges and lists, time windows `T0:T1`, frames nearest given
//! times. Every error names the bead or time and the snapshot's extent.
//!
//! **Beads** use the one grammar of `run --beads` ([`parse_beads`], docs in
//! [`crate::scene::selection`]): indices `I`, half-open ranges `A:B` (beads `A` to `B−1`; `A:`
//! to the end, `:B` from bead 0) and stepped ranges `A:B:STEP`, comma-separated. `plot
//! spacetime` and `plot profile` draw one contiguous run of beads ([`BeadRange`]: a selection
//! with gaps is refused); `plot trace` takes any selection ([`bead_list`]).

use super::PlotError;
use crate::scene::selection::parse_beads;
use crate::snapshot::Snapshot;
use std::ops::Range;
use std::str::FromStr;

/// A contiguous bead range in the `--beads` grammar (`A:B` half-open, `A:`, `:B`; absent = all).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BeadRange {
    /// The `--beads` text; `None` for every bead.
    spec: Option<String>,
}

/// A `--beads` or `--t` value that is not a range (one line, without the option name).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RangeError {
    /// No `:` in the value.
    #[error("`{0}` is not a range A:B")]
    NotRange(String),
    /// An empty `--beads` value.
    #[error("empty selection: give a range A:B (beads A to B-1)")]
    EmptyBeads,
    /// An end of a time window that is not a finite number.
    #[error("`{end}` in `{range}` is not a finite time")]
    NotTime {
        /// The end as given.
        end: String,
        /// The whole value.
        range: String,
    },
}

/// Splits `A:B` into optional halves.
fn halves(s: &str) -> Result<(Option<&str>, Option<&str>), RangeError> {
    let (a, b) = s
        .split_once(':')
        .ok_or_else(|| RangeError::NotRange(s.to_string()))?;
    fn opt(x: &str) -> Option<&str> {
        let x = x.trim();
        (!x.is_empty()).then_some(x)
    }
    Ok((opt(a), opt(b)))
}

impl FromStr for BeadRange {
    type Err = RangeError;
    /// Keeps the text; it is checked against the chain in [`BeadRange::resolve`] (the bead
    /// count is known only there).
    fn from_str(s: &str) -> Result<Self, RangeError> {
        if s.trim().is_empty() {
            return Err(RangeError::EmptyBeads);
        }
        Ok(BeadRange {
            spec: Some(s.trim().to_string()),
        })
    }
}

/// The beads `spec` selects in a chain of `n` beads (the `--beads` grammar), in increasing
/// order; errors name `--beads`.
pub fn bead_list(spec: &str, n: usize) -> Result<Vec<usize>, PlotError> {
    match parse_beads(spec, n as u64) {
        Ok(Some(list)) => Ok(list.into_iter().map(|b| b as usize).collect()),
        Ok(None) => Ok((0..n).collect()),
        Err(e) => Err(PlotError::Input(format!("--beads {spec}: {e}"))),
    }
}

impl BeadRange {
    /// The inclusive range `(first, last)` in a chain of `n` beads; a selection that is empty,
    /// beyond the chain or not one contiguous range is an error naming it.
    pub fn resolve(&self, n: usize) -> Result<(usize, usize), PlotError> {
        if n == 0 {
            return Err(PlotError::Input("the snapshot has no beads".into()));
        }
        let Some(spec) = &self.spec else {
            return Ok((0, n - 1));
        };
        let list = bead_list(spec, n)?;
        let (first, last) = (list[0], list[list.len() - 1]);
        if last - first + 1 != list.len() {
            return Err(PlotError::Input(format!(
                "--beads {spec}: this plot needs one contiguous range A:B (beads A to B-1), \
                 not a list or a stepped range"
            )));
        }
        Ok((first, last))
    }
}

/// Time window `T0:T1` (either end optional), inclusive.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TimeRange {
    /// Start (default: the first frame).
    pub t0: Option<f64>,
    /// End (default: the last frame).
    pub t1: Option<f64>,
}

impl FromStr for TimeRange {
    type Err = RangeError;
    fn from_str(s: &str) -> Result<Self, RangeError> {
        let (a, b) = halves(s)?;
        let time = |x: &str| match x.parse::<f64>() {
            Ok(t) if t.is_finite() => Ok(t),
            _ => Err(RangeError::NotTime {
                end: x.to_string(),
                range: s.to_string(),
            }),
        };
        Ok(TimeRange {
            t0: a.map(time).transpose()?,
            t1: b.map(time).transpose()?,
        })
    }
}

/// The run's time span as text, for messages.
fn span(times: &[f64]) -> String {
    match (times.first(), times.last()) {
        (Some(a), Some(b)) => format!("frames at t = {a} .. {b}"),
        _ => "no frames".into(),
    }
}

/// Fails when the snapshot has no frame.
pub fn require_frames(snap: &Snapshot) -> Result<(), PlotError> {
    if snap.frame_count() == 0 {
        return Err(PlotError::Input(format!(
            "{}: the snapshot holds no frame",
            snap.path().display()
        )));
    }
    Ok(())
}

impl TimeRange {
    /// Indices of the frames with `t0 ≤ t ≤ t1` (frame times ascending; an end within 16 ulp of
    /// the run's times of a frame takes it in). A window outside the run, reversed, or holding
    /// no frame is an error naming the times and the run's span.
    pub fn frames(&self, times: &[f64]) -> Result<Range<usize>, PlotError> {
        let (first, last) = match (times.first(), times.last()) {
            (Some(&a), Some(&b)) => (a, b),
            _ => return Err(PlotError::Input("the snapshot holds no frame".into())),
        };
        let t0 = self.t0.unwrap_or(first);
        let t1 = self.t1.unwrap_or(last);
        let text = format!(
            "--t {}:{}",
            self.t0.map_or(String::new(), |t| t.to_string()),
            self.t1.map_or(String::new(), |t| t.to_string())
        );
        if t0 > t1 {
            return Err(PlotError::Input(format!("{text} is empty (T0 > T1)")));
        }
        // a frame stored at k·every carries rounding (0.7000000000000001, 4.9999999999999996e-5
        // s): within 16 ulp of the run's times of an end, it is at that end (closed interval)
        let slack = 16.0 * f64::EPSILON * first.abs().max(last.abs());
        if t0 > last + slack || t1 < first - slack {
            return Err(PlotError::Input(format!(
                "{text} is outside the run ({})",
                span(times)
            )));
        }
        let lo = times.partition_point(|&t| t < t0 - slack);
        let hi = times.partition_point(|&t| t <= t1 + slack);
        if lo >= hi {
            return Err(PlotError::Input(format!(
                "{text} holds no frame ({})",
                span(times)
            )));
        }
        Ok(lo..hi)
    }
}

/// Index of the frame nearest `t` (ties: the earlier); a time outside the run is an error.
pub fn nearest_frame(times: &[f64], t: f64) -> Result<usize, PlotError> {
    let (first, last) = match (times.first(), times.last()) {
        (Some(&a), Some(&b)) => (a, b),
        _ => return Err(PlotError::Input("the snapshot holds no frame".into())),
    };
    // the slack of TimeRange::frames: a frame stored with rounding is at the run's end
    let slack = 16.0 * f64::EPSILON * first.abs().max(last.abs());
    if !t.is_finite() || t < first - slack || t > last + slack {
        return Err(PlotError::Input(format!(
            "time {t} is outside the run ({})",
            span(times)
        )));
    }
    let k = times.partition_point(|&x| x < t);
    if k == 0 {
        return Ok(0);
    }
    if k >= times.len() {
        return Ok(times.len() - 1);
    }
    Ok(if t - times[k - 1] <= times[k] - t {
        k - 1
    } else {
        k
    })
}

/// Checks a bead list against a chain of `n` beads.
pub fn check_beads(beads: &[usize], n: usize) -> Result<(), PlotError> {
    if beads.is_empty() {
        return Err(PlotError::Input("--beads: no bead given".into()));
    }
    if let Some(&b) = beads.iter().find(|&&b| b >= n) {
        return Err(PlotError::Input(format!(
            "--beads: bead {b} is out of range (the chain has {n} beads, 0..={})",
            n.saturating_sub(1)
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bead_ranges() {
        // half-open, as `run --beads`
        let r: BeadRange = "3:7".parse().unwrap();
        assert_eq!(r.resolve(10).unwrap(), (3, 6));
        let r: BeadRange = "3:".parse().unwrap();
        assert_eq!(r.resolve(10).unwrap(), (3, 9));
        let r: BeadRange = ":".parse().unwrap();
        assert_eq!(r.resolve(10).unwrap(), (0, 9));
        let r: BeadRange = "0:10".parse().unwrap();
        assert_eq!(r.resolve(10).unwrap(), (0, 9));
        assert_eq!(BeadRange::default().resolve(10).unwrap(), (0, 9));
        let e = "3:12"
            .parse::<BeadRange>()
            .unwrap()
            .resolve(10)
            .unwrap_err();
        assert!(
            e.to_string().contains("range '3:12' is out of range"),
            "{e}"
        );
        let e = "7:3".parse::<BeadRange>().unwrap().resolve(10).unwrap_err();
        assert!(e.to_string().contains("selects no bead"), "{e}");
        let e = "x:3".parse::<BeadRange>().unwrap().resolve(10).unwrap_err();
        assert!(e.to_string().contains("'x:3'"), "{e}");
        let e = "0:10:2".parse::<BeadRange>().unwrap().resolve(10);
        assert!(e.unwrap_err().to_string().contains("contiguous"));
        assert!("".parse::<BeadRange>().is_err());
        assert_eq!(bead_list("1,5:7", 10).unwrap(), [1, 5, 6]);
    }

    #[test]
    fn time_windows_and_nearest() {
        let times = [0.0, 1.0, 2.0, 3.0];
        let w: TimeRange = "0.5:2".parse().unwrap();
        assert_eq!(w.frames(&times).unwrap(), 1..3);
        assert_eq!(TimeRange::default().frames(&times).unwrap(), 0..4);
        let e = "5:6"
            .parse::<TimeRange>()
            .unwrap()
            .frames(&times)
            .unwrap_err();
        assert!(e.to_string().contains("outside the run"), "{e}");
        let e = "1.2:1.8"
            .parse::<TimeRange>()
            .unwrap()
            .frames(&times)
            .unwrap_err();
        assert!(e.to_string().contains("no frame"), "{e}");
        assert!("2:1".parse::<TimeRange>().unwrap().frames(&times).is_err());
        assert_eq!(nearest_frame(&times, 1.4).unwrap(), 1);
        assert_eq!(nearest_frame(&times, 1.6).unwrap(), 2);
        assert_eq!(nearest_frame(&times, 3.0).unwrap(), 3);
        assert!(nearest_frame(&times, 3.5).is_err());
        assert!(nearest_frame(&times, -0.1).is_err());
        assert!(check_beads(&[1, 12], 10)
            .unwrap_err()
            .to_string()
            .contains("bead 12"));
    }
}
