//! `beadchain plot animate`: an animated GIF of a field along the chain, one frame per chosen
//! snapshot frame (for talks: the solitary wave moving along the chain).
//!
//! Each frame is a line chart of the field (velocity `v`, displacement `u` or kinetic energy
//! `m v²/2`) against bead index, with a marker on the bead of the largest `|value|` and the
//! frame's time in the title. The y limits are fixed over the whole animation (the extremes of
//! every frame shown, zero included, 6 % margin), so the motion is visible.
//!
//! Frames: those in the time window (`--t`), every `K`-th of them (`--every`), then at most
//! `frames_max` (default [`DEFAULT_FRAMES_MAX`]) spread evenly over that list, first and last
//! included ([`pick_frames`]). Each frame is drawn into an RGB buffer by the bitmap backend
//! ([`super::render_rgb`]) and encoded by the `gif` crate with a palette of its own colours
//! (exact up to 256 colours, else the most frequent; [`indexed`]). Only `.gif` is written ([`gif_path`]); the whole file is encoded in memory and then written atomically.

use super::layout::{draw_axes, safe_range, Layout};
use super::lines::line_color;
use super::select::{require_frames, BeadRange, TimeRange};
use super::units::{scene_scales, AxisUnits, Units};
use super::{de, decimate, render_rgb, DrawError, Figure, PlotError};
use crate::snapshot::{Frame, Snapshot};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::collections::HashMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

/// Default cap on the number of frames of an animation.
pub const DEFAULT_FRAMES_MAX: usize = 200;
/// Default frame rate (frames per second).
pub const DEFAULT_FPS: u32 = 20;
/// The frame rates a GIF can hold reasonably (its delays are in 1/100 s).
pub const FPS_RANGE: std::ops::RangeInclusive<u32> = 1..=50;

/// The field drawn against bead index.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Field {
    /// Velocity `v_i`.
    #[default]
    Velocity,
    /// Displacement `u_i`.
    Displacement,
    /// Kinetic energy `m_i v_i² / 2`.
    Energy,
}

/// What to animate.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimateOptions {
    /// The field.
    pub field: Field,
    /// Beads (one contiguous range; default all).
    pub beads: BeadRange,
    /// Time window (in the axis units; default the whole run).
    pub t: TimeRange,
    /// Take every `every`-th frame of the window (at least 1).
    pub every: usize,
    /// At most this many frames (at least 1), spread evenly.
    pub frames_max: usize,
    /// Frames per second.
    pub fps: u32,
    /// Axis units.
    pub units: Units,
    /// Image size in pixels.
    pub size: (u32, u32),
}

/// One frame: its index in the snapshot, its time (axis units) and its points.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimFrame {
    /// Frame index in the snapshot.
    pub k: usize,
    /// Time in the axis units.
    pub t: f64,
    /// `(bead index, value)`, reduced to about two points per pixel column.
    pub points: Vec<(f64, f64)>,
}

/// An animation: fixed axes, and the frames.
#[derive(Clone, Debug, PartialEq)]
pub struct Animation {
    /// Title; each frame appends its time.
    pub title: String,
    /// x axis description.
    pub x_desc: String,
    /// y axis description.
    pub y_desc: String,
    /// x range (the beads, half a bead of margin).
    pub x_range: (f64, f64),
    /// y range, fixed over all frames.
    pub y_range: (f64, f64),
    /// The frames in order.
    pub frames: Vec<AnimFrame>,
    /// Computer units (the title's time format).
    pub units: Units,
    /// Frames per second.
    pub fps: u32,
    /// Image size.
    pub size: (u32, u32),
}

/// The frames of `window`, every `every`-th, then at most `frames_max` of those spread evenly
/// (index `round(j (m − 1) / (frames_max − 1))` of the `m` candidates: first and last kept).
pub fn pick_frames(window: Range<usize>, every: usize, frames_max: usize) -> Vec<usize> {
    let list: Vec<usize> = window.step_by(every.max(1)).collect();
    let (m, fm) = (list.len(), frames_max.max(1));
    if m <= fm {
        return list;
    }
    if fm == 1 {
        return vec![list[0]];
    }
    (0..fm)
        .map(|j| list[(j * (m - 1) + (fm - 1) / 2) / (fm - 1)])
        .collect()
}

/// The `--out` of `plot animate`: `X.gif` (any case) as is, a name without extension gets
/// `.gif`; any other extension (`.mp4` included) is an error naming the option.
pub fn gif_path(out: &Path) -> Result<PathBuf, PlotError> {
    match super::out_extension(out)? {
        None => Ok(out.with_extension("gif")),
        Some(e) if e == "gif" => Ok(out.to_path_buf()),
        Some(e) => Err(PlotError::Input(format!(
            "--out {}: unknown extension .{e} (plot animate writes .gif only; .mp4 and other \
             video formats are not supported)",
            out.display()
        ))),
    }
}

/// The factor from computer units to the axis units, the axis label and the title's word.
fn field_axis(
    field: Field,
    un: &AxisUnits,
    snap: &Snapshot,
) -> Result<(f64, String, &'static str), PlotError> {
    Ok(match field {
        Field::Velocity => (un.velocity, un.velocity_label(), "velocity"),
        // lengths are metres in both systems (docs/scenes.md, "Units")
        Field::Displacement => (
            1.0,
            format!("displacement u ({})", un.unit("m")),
            "displacement",
        ),
        Field::Energy => {
            let factor = match un.units {
                Units::Computer => 1.0,
                // E = Ẽ m0 / β² (the scene is physical: AxisUnits::of checked it)
                Units::Si => {
                    scene_scales(&snap.header().scene).map_or(1.0, |s| s.mass / (s.time * s.time))
                }
            };
            let label = format!("kinetic energy m v²/2 ({})", un.unit("J"));
            (factor, label, "kinetic energy")
        }
    })
}

/// The value of `field` at bead `i` of frame `f` (computer units).
fn value(field: Field, f: &Frame, mass: &[f64], i: usize) -> f64 {
    match field {
        Field::Velocity => f.v[i],
        Field::Displacement => f.u[i],
        Field::Energy => 0.5 * mass[i] * f.v[i] * f.v[i],
    }
}

impl Animation {
    /// Reads the chosen frames of `snap` (see the module docs).
    pub fn from_snapshot(snap: &Snapshot, opts: &AnimateOptions) -> Result<Self, PlotError> {
        require_frames(snap)?;
        if !FPS_RANGE.contains(&opts.fps) {
            return Err(PlotError::Input(format!(
                "--fps {}: must be {}..={} frames per second",
                opts.fps,
                FPS_RANGE.start(),
                FPS_RANGE.end()
            )));
        }
        let scene = &snap.header().scene;
        let (a, b) = opts.beads.resolve(snap.header().n_beads as usize)?;
        let un = AxisUnits::of(scene, opts.units, snap.path())?;
        let (factor, y_desc, word) = field_axis(opts.field, &un, snap)?;
        // the window is in the axis units: frames are selected by their displayed times
        let times: Vec<f64> = snap.frame_times().iter().map(|t| t * un.time).collect();
        let ks = pick_frames(opts.t.frames(&times)?, opts.every, opts.frames_max);
        let (_, _, pw, _) = Layout::new(opts.size, false).plot_rect();
        let mass = &scene.chain.mass;
        let (mut lo, mut hi) = (0.0_f64, 0.0_f64);
        let mut f = Frame::default();
        let mut frames = Vec::with_capacity(ks.len());
        for k in ks {
            snap.read_frame_into(k, &mut f)?;
            let pts: Vec<(f64, f64)> = (a..=b)
                .map(|i| (i as f64, value(opts.field, &f, mass, i) * factor))
                .collect();
            for &(_, y) in pts.iter().filter(|p| p.1.is_finite()) {
                lo = lo.min(y);
                hi = hi.max(y);
            }
            frames.push(AnimFrame {
                k,
                t: f.t * un.time,
                points: decimate(&pts, pw as usize),
            });
        }
        let pad = 0.06 * (hi - lo);
        Ok(Animation {
            title: format!("{}: {word}", scene.name),
            x_desc: "bead index i".into(),
            y_desc,
            x_range: (a as f64 - 0.5, b as f64 + 0.5),
            y_range: safe_range(lo - pad, hi + pad),
            frames,
            units: opts.units,
            fps: opts.fps,
            size: opts.size,
        })
    }

    /// The title of frame `f`: the animation's title and the frame's time.
    pub fn frame_title(&self, f: &AnimFrame) -> String {
        match self.units {
            Units::Computer => format!("{}, t = {} (frame {})", self.title, sig6(f.t), f.k),
            Units::Si => format!("{}, t = {:.4e} s (frame {})", self.title, f.t, f.k),
        }
    }

    /// Encodes every frame as one looping GIF (in memory).
    pub fn encode_gif(&self) -> Result<Vec<u8>, PlotError> {
        let (w, h) = self.size;
        let err = |e: gif::EncodingError| PlotError::Draw {
            format: "GIF",
            source: DrawError::Gif(e),
        };
        let (w16, h16) = match (u16::try_from(w), u16::try_from(h)) {
            (Ok(a), Ok(b)) => (a, b),
            _ => return Err(PlotError::Input(format!("{w}x{h}: too large for a GIF"))),
        };
        // GIF delays are in 1/100 s
        let delay = ((100 + self.fps / 2) / self.fps.max(1)) as u16;
        let mut out = Vec::new();
        {
            let mut enc = gif::Encoder::new(&mut out, w16, h16, &[]).map_err(err)?;
            enc.set_repeat(gif::Repeat::Infinite).map_err(err)?;
            for frame in &self.frames {
                let (rgb, _) = render_rgb(&FramePlot { anim: self, frame })?;
                let mut g = indexed(&rgb, w16, h16);
                g.delay = delay;
                enc.write_frame(&g).map_err(err)?;
            }
        }
        Ok(out)
    }
}

/// The frame with its own palette: its colours exactly when it has at most 256 (the usual case:
/// white, the axes' greys, text anti-aliasing, two line colours); else the 256 most frequent
/// (ties by colour value) and every other colour drawn as its nearest of those.
fn indexed(rgb: &[u8], w: u16, h: u16) -> gif::Frame<'static> {
    let mut counts: HashMap<[u8; 3], u32> = HashMap::new();
    for run in runs(rgb) {
        *counts.entry(run.0).or_insert(0) += run.1;
    }
    let mut colours: Vec<([u8; 3], u32)> = counts.into_iter().collect();
    colours.sort_unstable_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    let kept = &colours[..colours.len().min(256)];
    let mut map: HashMap<[u8; 3], u8> = HashMap::with_capacity(colours.len());
    let mut palette = Vec::with_capacity(kept.len() * 3);
    for (i, (c, _)) in kept.iter().enumerate() {
        map.insert(*c, i as u8);
        palette.extend_from_slice(c);
    }
    for (c, _) in &colours[kept.len()..] {
        let dist =
            |k: &[u8; 3]| -> i32 { (0..3).map(|j| (c[j] as i32 - k[j] as i32).pow(2)).sum() };
        let near = (0..kept.len())
            .min_by_key(|&i| dist(&kept[i].0))
            .unwrap_or(0);
        map.insert(*c, near as u8);
    }
    let mut pixels = Vec::with_capacity(rgb.len() / 3);
    for (c, n) in runs(rgb) {
        let i = map.get(&c).copied().unwrap_or(0);
        pixels.extend(std::iter::repeat_n(i, n as usize));
    }
    gif::Frame::from_palette_pixels(w, h, pixels, palette, None)
}

/// The runs of equal colours of an RGB buffer, `(colour, length)`, in order.
fn runs(rgb: &[u8]) -> impl Iterator<Item = ([u8; 3], u32)> + '_ {
    let mut px = rgb.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).peekable();
    std::iter::from_fn(move || {
        let c = px.next()?;
        let mut n = 1;
        while px.next_if_eq(&c).is_some() {
            n += 1;
        }
        Some((c, n))
    })
}

/// `x` rounded to six significant digits, printed shortest (`993.682`, `20`).
fn sig6(x: f64) -> String {
    let r: f64 = format!("{x:.5e}").parse().unwrap_or(x);
    format!("{r}")
}

/// One frame of an animation as a figure.
pub struct FramePlot<'a> {
    /// The animation (axes, texts).
    pub anim: &'a Animation,
    /// The frame drawn.
    pub frame: &'a AnimFrame,
}

impl FramePlot<'_> {
    /// The point of largest `|value|` (the first of equals), if any.
    pub fn peak(&self) -> Option<(f64, f64)> {
        self.frame.points.iter().filter(|p| p.1.is_finite()).fold(
            None,
            |m: Option<(f64, f64)>, &p| match m {
                Some(q) if q.1.abs() >= p.1.abs() => Some(q),
                _ => Some(p),
            },
        )
    }
}

impl Figure for FramePlot<'_> {
    fn size(&self) -> (u32, u32) {
        self.anim.size
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        text: bool,
    ) -> Result<(), DrawError>
    where
        DB::ErrorType: 'static,
    {
        let a = self.anim;
        root.fill(&WHITE).map_err(de)?;
        let lay = Layout::new(a.size, false);
        let ((x0, x1), (y0, y1)) = (a.x_range, a.y_range);
        let mut chart = lay
            .chart(root)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(de)?;
        draw_axes(&mut chart, (&a.x_desc, &a.y_desc), true, None, text)?;
        let pts = self
            .frame
            .points
            .iter()
            .copied()
            .filter(|p| p.1.is_finite());
        chart
            .draw_series(LineSeries::new(pts, line_color(0).stroke_width(2)))
            .map_err(de)?;
        if let Some(p) = self.peak() {
            chart
                .draw_series(std::iter::once(Circle::new(p, 5, line_color(1).filled())))
                .map_err(de)?;
        }
        lay.title(root, &a.frame_title(self.frame), text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pick_frames_spreads_evenly() {
        assert_eq!(pick_frames(0..5, 1, 200), vec![0, 1, 2, 3, 4]);
        assert_eq!(pick_frames(0..10, 3, 200), vec![0, 3, 6, 9]);
        assert_eq!(pick_frames(0..101, 1, 5), vec![0, 25, 50, 75, 100]);
        assert_eq!(pick_frames(2..9, 1, 1), vec![2]);
        let p = pick_frames(0..1000, 1, 200);
        assert_eq!(p.len(), 200);
        assert_eq!((p[0], p[199]), (0, 999));
        assert!(p.windows(2).all(|w| w[0] < w[1]));
    }

    #[test]
    fn palette_exact_up_to_256_colours_then_nearest() {
        // 300 colours: grey levels 0..=255 once each, then 44 near-reds many times
        let mut rgb = Vec::new();
        for g in 0..=255u8 {
            rgb.extend_from_slice(&[g, g, g]);
        }
        for k in 0..44u8 {
            for _ in 0..10 {
                rgb.extend_from_slice(&[200 + k, 0, 0]);
            }
        }
        let n = rgb.len() / 3;
        let f = indexed(&rgb, n as u16, 1);
        let pal = f.palette.as_ref().expect("local palette");
        assert_eq!(pal.len(), 256 * 3);
        let colour = |p: usize| {
            let i = f.buffer[p] as usize * 3;
            [pal[i], pal[i + 1], pal[i + 2]]
        };
        // every red is kept exactly (the most frequent), greys 0..=211 too (ties by value); a
        // dropped grey is drawn as the nearest kept colour
        assert_eq!(colour(n - 1), [243, 0, 0]);
        assert_eq!(colour(0), [0, 0, 0]);
        assert_eq!(colour(211), [211, 211, 211]);
        assert_eq!(colour(255), [211, 211, 211]);
        let small = indexed(&rgb[..30], 10, 1);
        assert_eq!(small.palette.as_ref().unwrap().len(), 30);
    }

    #[test]
    fn gif_path_rule() {
        assert_eq!(
            gif_path(Path::new("a.GIF")).unwrap(),
            PathBuf::from("a.GIF")
        );
        assert_eq!(
            gif_path(Path::new("d/a")).unwrap(),
            PathBuf::from("d/a.gif")
        );
        let e = gif_path(Path::new("a.mp4")).unwrap_err().to_string();
        assert!(e.starts_with("--out a.mp4: ") && e.contains(".mp4"), "{e}");
    }
}
