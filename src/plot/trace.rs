//! Velocity traces `v_i(t)` of chosen beads (paper Figs. 10, 11, 13, 14, bottom panels).

use super::layout::Layout;
use super::lines::{LineChart, Series, Style};
use super::select::{check_beads, require_frames, TimeRange};
use super::units::{AxisUnits, Units};
use super::{decimate, PlotError};
use crate::snapshot::{Frame, Snapshot};

/// What to draw.
#[derive(Clone, Debug, PartialEq)]
pub struct TraceOptions {
    /// Beads, one line each.
    pub beads: Vec<usize>,
    /// Time window in the axis units (default the whole run).
    pub t: TimeRange,
    /// Axis units.
    pub units: Units,
    /// Image size in pixels.
    pub size: (u32, u32),
}

/// Trace figure: a [`LineChart`] of `v` against time.
pub type Trace = LineChart;

/// Builds the trace chart of `snap` (streams the frames; memory grows with frames × beads
/// chosen, not with the chain).
pub fn trace(snap: &Snapshot, opts: &TraceOptions) -> Result<Trace, PlotError> {
    require_frames(snap)?;
    let n = snap.header().n_beads as usize;
    check_beads(&opts.beads, n)?;
    let un = AxisUnits::of(&snap.header().scene, opts.units, snap.path())?;
    // the window is in the axis units: frames are selected by their displayed times
    let times: Vec<f64> = snap.frame_times().iter().map(|t| t * un.time).collect();
    let frames = opts.t.frames(&times)?;
    let x_span = match (times[frames.start], times[frames.end - 1]) {
        (a, b) if b > a => (a, b),
        // one frame: one frame interval around it (as `plot spacetime`)
        (a, _) => {
            let half = 0.5 * snap.header().scene.run.every.unwrap_or(1.0) * un.time;
            (a - half, a + half)
        }
    };
    let mut pts: Vec<Vec<(f64, f64)>> = vec![Vec::with_capacity(frames.len()); opts.beads.len()];
    let mut f = Frame::default();
    for k in frames {
        snap.read_frame_into(k, &mut f)?;
        for (p, &i) in pts.iter_mut().zip(&opts.beads) {
            p.push((f.t * un.time, f.v[i] * un.velocity));
        }
    }
    let (_, _, pw, _) = Layout::new(opts.size, false).plot_rect();
    let series = pts
        .iter()
        .zip(&opts.beads)
        .map(|(p, i)| Series {
            name: format!("bead {i}"),
            points: decimate(p, pw as usize),
            style: Style::Line,
        })
        .collect();
    Ok(LineChart {
        title: format!("{}: bead velocities", snap.header().scene.name),
        x_desc: un.time_label(),
        y_desc: un.velocity_label(),
        series,
        log_y: false,
        x_span: Some(x_span),
        size: opts.size,
    })
}
