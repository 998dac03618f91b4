//! Velocity profiles `v_i` against bead index `i` at chosen times (paper Fig. 4): one line per
//! time, taken from the frame nearest that time (the legend gives the frame's own time).

use super::layout::Layout;
use super::lines::{LineChart, Series, Style};
use super::select::{nearest_frame, require_frames, BeadRange};
use super::{decimate, PlotError};
use crate::snapshot::{Frame, Snapshot};

/// What to draw.
#[derive(Clone, Debug, PartialEq)]
pub struct ProfileOptions {
    /// Times; each picks the nearest frame (must lie within the run).
    pub times: Vec<f64>,
    /// Beads (inclusive range; default all).
    pub beads: BeadRange,
    /// Image size in pixels.
    pub size: (u32, u32),
}

/// Profile figure: a [`LineChart`] of `v` against bead index.
pub type Profile = LineChart;

/// Builds the profile chart of `snap`.
pub fn profile(snap: &Snapshot, opts: &ProfileOptions) -> Result<Profile, PlotError> {
    require_frames(snap)?;
    if opts.times.is_empty() {
        return Err(PlotError::Input("--times: no time given".into()));
    }
    let n = snap.header().n_beads as usize;
    let (a, b) = opts.beads.resolve(n)?;
    let times = snap.frame_times();
    let ks = opts
        .times
        .iter()
        .map(|&t| nearest_frame(times, t))
        .collect::<Result<Vec<_>, _>>()?;
    let (_, _, pw, _) = Layout::new(opts.size, false).plot_rect();
    let mut f = Frame::default();
    let mut series = Vec::with_capacity(ks.len());
    for k in ks {
        snap.read_frame_into(k, &mut f)?;
        let pts: Vec<(f64, f64)> = (a..=b).map(|i| (i as f64, f.v[i])).collect();
        series.push(Series {
            name: format!("t = {} (frame {k})", f.t),
            points: decimate(&pts, pw as usize),
            style: Style::Line,
        });
    }
    Ok(LineChart {
        title: format!("{}: velocity profiles", snap.header().scene.name),
        x_desc: "bead index".into(),
        y_desc: "velocity v".into(),
        series,
        log_y: false,
        size: opts.size,
    })
}
