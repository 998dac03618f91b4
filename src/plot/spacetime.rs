//! Space–time velocity map (paper Figs. 4, 6, 10, 13): bead index on x, time on y (upwards), one
//! cell per (bead, frame) coloured by the signed velocity with the diverging map of
//! [`super::colormap`], normalised by the largest `|v|` of the selection.
//!
//! **Scales.** Linear: `s = v / max|v|`. Log: `s = sign(v) · (log₁₀(|v|/max|v|) + 4) / 4`,
//! zero below `|v|/max|v| = 10⁻⁴` ([`LOG_FLOOR`]), so the paper's 0.1 % wave threshold (Sec. 3.2)
//! is at `|s| = 1/4` and small reflected/secondary pulses stay visible.
//!
//! **Bounded memory.** Beads and frames are binned onto at most the plot area's pixels
//! (`nx ≤ width`, `ny ≤ height`); each cell keeps the velocity of largest `|v|` among its beads
//! and frames (a narrow pulse is never averaged away). Frames are streamed one at a time into a
//! reused buffer, so memory is `O(nx·ny + N)` whatever the snapshot's size.
//!
//! **Axes.** Time and velocity are in the axis units of [`super::units`] (computer units, or SI
//! for a physical scene). The time axis spans the first to the last selected frame (each frame
//! is the cell centred on its time, so the end cells show half), which keeps a two-frame run on
//! `[t₀, t₁]`; a single frame is drawn over one frame interval (`every`, else one computer time
//! unit) centred on its time.

use super::cmap::Cmap;
use super::colormap::NO_DATA;
use super::layout::{draw_axes, num_label, Layout};
use super::select::{require_frames, BeadRange, TimeRange};
use super::ticks::{colorbar_ticks, TickFmt};
use super::units::{AxisUnits, Units};
use super::{de, DrawError, Figure, PlotError};
use crate::snapshot::{Frame, Snapshot};
use plotters::coord::Shift;
use plotters::element::BitMapElement;
use plotters::prelude::*;

/// Smallest `|v|/max|v|` shown on the log scale.
pub const LOG_FLOOR: f64 = 1e-4;

/// Colour scale of the map.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Scale {
    /// `v / max|v|`.
    #[default]
    Linear,
    /// `sign(v) · log₁₀(|v|/max|v|)`, clipped at [`LOG_FLOOR`].
    Log,
}

/// What to draw.
#[derive(Clone, Debug, PartialEq)]
pub struct SpacetimeOptions {
    /// Beads (inclusive range; default all).
    pub beads: BeadRange,
    /// Time window (default the whole run).
    pub t: TimeRange,
    /// Colour scale.
    pub scale: Scale,
    /// Axis units (and the unit of `t`).
    pub units: Units,
    /// Colour map.
    pub cmap: Cmap,
    /// Room for the colour bar right of the plot (panels but the last have none).
    pub colorbar: bool,
    /// Image size in pixels.
    pub size: (u32, u32),
}

impl Default for SpacetimeOptions {
    fn default() -> Self {
        Self {
            beads: BeadRange::default(),
            t: TimeRange::default(),
            scale: Scale::Linear,
            units: Units::Computer,
            cmap: Cmap::CoolWarm,
            colorbar: true,
            size: (900, 700),
        }
    }
}

/// Cells along one axis: `n` bins whose centres run evenly from `lo` to `hi`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Axis {
    /// Centre of the first cell.
    pub lo: f64,
    /// Centre of the last cell.
    pub hi: f64,
    /// Number of cells.
    pub n: usize,
}

impl Axis {
    /// The cell containing `x` (nearest centre, clamped).
    pub fn bin(&self, x: f64) -> usize {
        if self.n <= 1 || self.hi <= self.lo {
            return 0;
        }
        let k = ((x - self.lo) / (self.hi - self.lo) * (self.n - 1) as f64).round();
        if k.is_nan() || k < 0.0 {
            0
        } else {
            (k as usize).min(self.n - 1)
        }
    }
    /// Outer edges of the first and last cell.
    pub fn edges(&self) -> (f64, f64) {
        let h = if self.n > 1 && self.hi > self.lo {
            (self.hi - self.lo) / (self.n - 1) as f64
        } else {
            1.0
        };
        (self.lo - h / 2.0, self.hi + h / 2.0)
    }
}

/// The time axis: first to last frame, or `t ± pad` for a single frame (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeAxis {
    /// The cells.
    pub cells: Axis,
    /// Half the height of a single frame's cell.
    pub pad: f64,
}

impl TimeAxis {
    /// The drawn extent `(t0, t1)`.
    pub fn extent(&self) -> (f64, f64) {
        let a = self.cells;
        if a.n > 1 && a.hi > a.lo {
            (a.lo, a.hi)
        } else {
            (a.lo - self.pad, a.hi + self.pad)
        }
    }
}

/// A binned space–time velocity map.
#[derive(Clone, Debug, PartialEq)]
pub struct Spacetime {
    /// Title (scene name and scale).
    pub title: String,
    /// x axis label.
    pub x_desc: String,
    /// y axis label.
    pub y_desc: String,
    /// Colour-bar label.
    pub bar_desc: String,
    /// Bead axis (cell centres in bead indices).
    pub x: Axis,
    /// Time axis (cell centres in the axis units).
    pub y: Axis,
    /// Half height of a single frame's cell (see [`TimeAxis`]).
    pub y_pad: f64,
    /// Signed velocity of largest `|v|` per cell, row-major, row 0 = earliest; NaN = no frame.
    pub cells: Vec<f64>,
    /// Largest `|v|` of the selection (the normalisation).
    pub vmax: f64,
    /// Colour scale.
    pub scale: Scale,
    /// Colour map.
    pub cmap: Cmap,
    /// Colour bar drawn.
    pub colorbar: bool,
    /// Image size.
    pub size: (u32, u32),
}

impl Spacetime {
    /// Reads the selected beads and frames of `snap` into a map of at most the plot area's
    /// pixels.
    pub fn from_snapshot(snap: &Snapshot, opts: &SpacetimeOptions) -> Result<Self, PlotError> {
        require_frames(snap)?;
        let n = snap.header().n_beads as usize;
        let (a, b) = opts.beads.resolve(n)?;
        let scene = &snap.header().scene;
        let un = AxisUnits::of(scene, opts.units, snap.path())?;
        // the window is in the axis units: frames are selected by their displayed times
        let times: Vec<f64> = snap.frame_times().iter().map(|t| t * un.time).collect();
        let frames = opts.t.frames(&times)?;
        let (_, _, pw, ph) = Layout::new(opts.size, opts.colorbar).plot_rect();
        let nb = b - a + 1;
        let nf = frames.len();
        let x = Axis {
            lo: a as f64,
            hi: b as f64,
            n: nb.min(pw as usize).max(1),
        };
        let y = Axis {
            lo: times[frames.start],
            hi: times[frames.end - 1],
            n: nf.min(ph as usize).max(1),
        };
        // column of each bead, computed once
        let col: Vec<usize> = (a..=b).map(|i| x.bin(i as f64)).collect();
        let mut cells = vec![f64::NAN; x.n * y.n];
        let mut vmax = 0.0f64;
        let mut f = Frame::default();
        for k in frames {
            snap.read_frame_into(k, &mut f)?;
            let row = y.bin(f.t * un.time);
            let line = &mut cells[row * x.n..(row + 1) * x.n];
            for (j, &v) in f.v[a..=b].iter().enumerate() {
                let v = v * un.velocity;
                let c = &mut line[col[j]];
                if c.is_nan() || v.abs() > c.abs() {
                    *c = v;
                }
                vmax = vmax.max(v.abs());
            }
        }
        let name = &scene.name;
        let log = opts.scale == Scale::Log;
        Ok(Spacetime {
            title: format!(
                "{name}: velocity v(bead, t){}",
                if log { ", log scale" } else { "" }
            ),
            x_desc: "bead index i".into(),
            y_desc: un.time_label(),
            bar_desc: format!("v{}\n({})", if log { ", log" } else { "" }, un.unit("m/s")),
            x,
            y,
            y_pad: 0.5 * scene.run.every.unwrap_or(1.0) * un.time,
            cells,
            vmax,
            scale: opts.scale,
            cmap: opts.cmap,
            colorbar: opts.colorbar,
            size: opts.size,
        })
    }

    /// The normalised value `s ∈ [−1, 1]` of a velocity (see the module docs).
    pub fn normalise(&self, v: f64) -> f64 {
        if v.is_nan() {
            return f64::NAN;
        }
        if self.vmax <= 0.0 {
            return 0.0;
        }
        let r = v / self.vmax;
        match self.scale {
            Scale::Linear => r.clamp(-1.0, 1.0),
            Scale::Log => {
                let a = r.abs();
                if a < LOG_FLOOR {
                    0.0
                } else {
                    r.signum() * ((a.log10() - LOG_FLOOR.log10()) / -LOG_FLOOR.log10()).min(1.0)
                }
            }
        }
    }

    /// The cell value (signed velocity) at bead `bead` and time `t`.
    pub fn cell(&self, bead: f64, t: f64) -> f64 {
        self.cells[self.y.bin(t) * self.x.n + self.x.bin(bead)]
    }

    /// Figure layout.
    pub fn layout(&self) -> Layout {
        Layout::new(self.size, self.colorbar)
    }

    /// The time axis.
    pub fn time_axis(&self) -> TimeAxis {
        TimeAxis {
            cells: self.y,
            pad: self.y_pad,
        }
    }

    /// The colour of a normalised value `s ∈ [−1, 1]`.
    pub fn color(&self, s: f64) -> RGBColor {
        self.cmap.at((s + 1.0) / 2.0)
    }

    /// Pixel `(px, py)` of the image at bead `bead` and time `t` (inside the plot area).
    pub fn pixel(&self, bead: f64, t: f64) -> (u32, u32) {
        let (x0, y0, pw, ph) = self.layout().plot_rect();
        let (ex0, ex1) = self.x.edges();
        let (ey0, ey1) = self.time_axis().extent();
        let fx = ((bead - ex0) / (ex1 - ex0)).clamp(0.0, 1.0);
        let fy = ((ey1 - t) / (ey1 - ey0)).clamp(0.0, 1.0);
        let px = (fx * pw as f64).floor().min(pw as f64 - 1.0) as u32;
        let py = (fy * ph as f64).floor().min(ph as f64 - 1.0) as u32;
        (x0 as u32 + px, y0 as u32 + py)
    }

    /// The plot area as RGB pixels (`pw × ph`), nearest cell per pixel centre.
    fn raster(&self, pw: u32, ph: u32) -> Vec<u8> {
        let (ex0, ex1) = self.x.edges();
        let (ey0, ey1) = self.time_axis().extent();
        let cols: Vec<usize> = (0..pw)
            .map(|p| self.x.bin(ex0 + (p as f64 + 0.5) / pw as f64 * (ex1 - ex0)))
            .collect();
        let mut buf = vec![0u8; (pw * ph) as usize * 3];
        for py in 0..ph {
            let t = ey1 - (py as f64 + 0.5) / ph as f64 * (ey1 - ey0);
            let row = self.y.bin(t);
            let line = &self.cells[row * self.x.n..(row + 1) * self.x.n];
            for (px, &c) in cols.iter().enumerate() {
                let v = line[c];
                let col = if v.is_nan() {
                    NO_DATA
                } else {
                    self.color(self.normalise(v))
                };
                let k = (py as usize * pw as usize + px) * 3;
                buf[k..k + 3].copy_from_slice(&[col.0, col.1, col.2]);
            }
        }
        buf
    }

    /// Colour-bar ticks `(s ∈ [0, 1], label)`.
    fn ticks(&self) -> Vec<(f64, String)> {
        let pos = |s: f64| (s + 1.0) / 2.0;
        if !(self.vmax > 0.0 && self.vmax.is_finite()) {
            // a chain at rest: one colour, one tick
            return vec![(0.5, "0".into())];
        }
        match self.scale {
            Scale::Linear => {
                // round values of v in -max|v| … max|v| (0 among them)
                let t = colorbar_ticks(-self.vmax, self.vmax, false);
                let v: Vec<f64> = t.iter().map(|p| p.1).collect();
                let f = TickFmt::for_values(&v, 2.0 * self.vmax, 1e-9);
                t.iter().map(|&(s, v)| (s, f.label(v))).collect()
            }
            Scale::Log => {
                // each half of the bar runs over |v|/max|v| = 1e-4 … 1 (1e-4 at the centre): the
                // round |v| there (decades), placed on the half; none next to the centre's `0`
                let hi = self.vmax.log10();
                let mut t = vec![(0.5, "0".to_string())];
                for (s, v) in colorbar_ticks(hi - 4.0, hi, true) {
                    if s < 0.1 {
                        continue;
                    }
                    t.push((pos(s), num_label(v)));
                    t.push((pos(-s), num_label(-v)));
                }
                t
            }
        }
    }
}

impl Figure for Spacetime {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        text: bool,
    ) -> Result<(), DrawError>
    where
        DB::ErrorType: 'static,
    {
        root.fill(&WHITE).map_err(de)?;
        let lay = self.layout();
        let (x0, y0, pw, ph) = lay.plot_rect();
        let (ex0, ex1) = self.x.edges();
        let (ey0, ey1) = self.time_axis().extent();
        let mut chart = lay
            .chart(root)
            .build_cartesian_2d(ex0..ex1, ey0..ey1)
            .map_err(de)?;
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        // pixel ranges are absolute; a panel's area starts at its base pixel
        let (bx, by) = root.get_base_pixel();
        lay.check(xr.start - bx..xr.end - bx, yr.start - by..yr.end - by)?;
        if let Some(el) = BitMapElement::with_owned_buffer((x0, y0), (pw, ph), self.raster(pw, ph))
        {
            root.draw(&el).map_err(de)?;
        }
        let desc = (self.x_desc.as_str(), self.y_desc.as_str());
        draw_axes(&mut chart, desc, false, None, text)?;
        lay.title(root, &self.title, text)?;
        if !self.colorbar {
            return Ok(());
        }
        lay.colorbar(
            root,
            &|s| self.cmap.at(s),
            &self.ticks(),
            &self.bar_desc,
            text,
        )
    }
}
