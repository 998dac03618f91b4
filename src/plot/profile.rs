//! Velocity profiles `v_i` against bead index `i` at chosen times (paper Figs. 4–5): one line per
//! time, taken from the frame nearest that time (the legend gives the frame's own time).

use super::layout::Layout;
use super::lines::{LineChart, Series, Style};
use super::select::{nearest_frame, require_frames, BeadRange};
use super::units::{AxisUnits, Units};
use super::{decimate, PlotError};
use crate::snapshot::{Frame, Snapshot};

/// What to draw.
#[derive(Clone, Debug, PartialEq)]
pub struct ProfileOptions {
    /// Times (in `units`); each picks the nearest frame (must lie within the run).
    pub times: Vec<f64>,
    /// Axis units (and the unit of `times`).
    pub units: Units,
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
    let un = AxisUnits::of(&snap.header().scene, opts.units, snap.path())?;
    // the times are in the axis units: frames are picked by their displayed times
    let times: Vec<f64> = snap.frame_times().iter().map(|t| t * un.time).collect();
    let ks = opts
        .times
        .iter()
        .map(|&t| {
            nearest_frame(&times, t)
                .map_err(|e| PlotError::Input(format!("{}: --times: {e}", snap.path().display())))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let (_, _, pw, _) = Layout::new(opts.size, false).plot_rect();
    let mut f = Frame::default();
    let mut series = Vec::with_capacity(ks.len());
    for k in ks {
        snap.read_frame_into(k, &mut f)?;
        let pts: Vec<(f64, f64)> = (a..=b).map(|i| (i as f64, f.v[i] * un.velocity)).collect();
        let t = f.t * un.time;
        series.push(Series {
            name: match opts.units {
                // six significant digits (the frame number identifies it exactly)
                Units::Computer => format!("t = {} (frame {k})", sig6(t)),
                Units::Si => format!("t = {t:.4e} s (frame {k})"),
            },
            points: decimate(&pts, pw as usize),
            style: Style::Line,
        });
    }
    Ok(LineChart {
        title: format!("{}: velocity profiles", snap.header().scene.name),
        x_desc: "bead index i".into(),
        y_desc: un.velocity_label(),
        series,
        log_y: false,
        x_span: None,
        size: opts.size,
    })
}

/// `x` rounded to six significant digits, printed shortest (`993.682`, `20`).
fn sig6(x: f64) -> String {
    let r: f64 = format!("{x:.5e}").parse().unwrap_or(x);
    format!("{r}")
}
