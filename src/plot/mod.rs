//! `beadchain plot`: figures of snapshots and result tables, as PNG and SVG (issue 6, "Plots").
//!
//! - [`spacetime`]: space–time velocity map, bead index × time (paper Figs. 4, 6, 10, 13).
//! - [`profile`]: velocity against bead index at chosen times (paper Figs. 4–5).
//! - [`trace`]: velocity against time of chosen beads (paper Figs. 10, 11, 13, 14, bottom panels).
//! - [`energy`]: leading-wave energy (eq. 13) against its peak bead with the fitted exponential
//!   `E = a e^{−γ i}` (paper Sec. 5.2, Fig. 21).
//! - [`map`]: 2-D parameter map (heatmap and level contour) from any CSV (paper Figs. 7, 25), its
//!   axes and colour bar named by [`keys`] (readable names of sweep columns).
//! - [`panels`]: space–time maps side by side with one shared colour scale.
//! - [`animate`]: animated GIF of velocity (or displacement, kinetic energy) along the chain,
//!   one frame per snapshot frame, fixed axes.
//!
//! Axes: [`units`] (computer units, or SI for physical scenes), [`ticks`] (readable tick
//! labels, decades on log axes), [`cmap`] (named colour maps).
//!
//! Shared here: the output rule ([`output_paths`]: `X.png`, `X.svg`, or a base name without
//! extension for both), the [`Figure`] trait every plot implements, in-memory rendering
//! ([`render_svg`], [`render_rgb`]) and atomic writing ([`write_figure`]: everything is rendered
//! first, then each file goes through a temporary sibling renamed into place, so a failure
//! leaves no output). Text uses the run-time font of [`font`]; without one, figures are drawn
//! without text. Rendering is deterministic: the same input gives the same bytes.

pub mod animate;
pub mod cmap;
pub mod colormap;
pub mod contour;
pub mod csvtable;
pub mod dispersion;
pub mod energy;
pub mod font;
pub mod keys;
pub mod layout;
pub mod lines;
pub mod map;
pub mod panels;
pub mod profile;
pub mod select;
pub mod spacetime;
pub mod svgimage;
pub mod ticks;
pub mod trace;
pub mod units;

use crate::snapshot::SnapshotError;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

pub use animate::{AnimateOptions, Animation, Field};
pub use cmap::Cmap;
pub use energy::{EnergyOptions, EnergyPlot, SideFit};
pub use map::{Map, MapOptions};
pub use panels::Panels;
pub use profile::{Profile, ProfileOptions};
pub use select::{bead_list, BeadRange, RangeError, TimeRange};
pub use spacetime::{Scale, Spacetime, SpacetimeOptions};
pub use trace::{Trace, TraceOptions};
pub use units::{AxisUnits, Labels, Units};

/// Errors of the plot commands. Every message is one line naming the file, column, bead or time.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// Reading the snapshot failed (missing, not a snapshot, corrupt).
    #[error(transparent)]
    Snapshot(#[from] SnapshotError),
    /// A bad selection or option (bead range, bead index, time, extension).
    #[error("{0}")]
    Input(String),
    /// A CSV problem (missing column, unreadable file, bad row).
    #[error("{}: {msg}", path.display())]
    Csv {
        /// The CSV file.
        path: PathBuf,
        /// What is wrong.
        msg: String,
    },
    /// plotters failed to draw or a PNG could not be encoded.
    #[error("drawing the {format} failed: {source}")]
    Draw {
        /// `PNG`, `SVG` or `GIF`.
        format: &'static str,
        /// What failed.
        source: DrawError,
    },
}

/// Why a figure could not be drawn or encoded (the detail of [`PlotError::Draw`]). No variant
/// has a source: the message is the whole story.
#[derive(Debug, thiserror::Error)]
pub enum DrawError {
    /// The plotters backend failed (its message).
    #[error("{0}")]
    Backend(Box<dyn std::error::Error + Send + Sync>),
    /// plotters placed the plot area elsewhere than the layout computed.
    #[error(
        "internal layout mismatch: plot area {x:?} x {y:?}, expected {}+{} x {}+{}",
        expected.0, expected.1, expected.2, expected.3
    )]
    Layout {
        /// Horizontal pixel range plotters used.
        x: std::ops::Range<i32>,
        /// Vertical pixel range plotters used.
        y: std::ops::Range<i32>,
        /// The layout's `(x0, width, y0, height)`.
        expected: (i32, u32, i32, u32),
    },
    /// The SVG's raster images could not be embedded.
    #[error("{0}")]
    Embed(svgimage::EmbedError),
    /// PNG encoding failed.
    #[error("{0}")]
    Png(png::EncodingError),
    /// GIF encoding failed.
    #[error("{0}")]
    Gif(gif::EncodingError),
}

/// Image formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Portable Network Graphics (raster).
    Png,
    /// Scalable Vector Graphics (raster cells embedded as one PNG image).
    Svg,
}

/// The files `--out` names: `X.png` or `X.svg` (case-insensitive) give one file; a path
/// without extension gives `X.png` and `X.svg`; any other extension is an error.
pub fn output_paths(out: &Path) -> Result<Vec<(PathBuf, Format)>, PlotError> {
    match out_extension(out)? {
        None => Ok(vec![
            (out.with_extension("png"), Format::Png),
            (out.with_extension("svg"), Format::Svg),
        ]),
        Some(e) if e == "png" => Ok(vec![(out.to_path_buf(), Format::Png)]),
        Some(e) if e == "svg" => Ok(vec![(out.to_path_buf(), Format::Svg)]),
        Some(e) => Err(PlotError::Input(format!(
            "--out {}: unknown extension .{e} (use .png, .svg, or no extension for both)",
            out.display()
        ))),
    }
}

/// The extension of the file `--out` names, in lower case (an error where it names no file).
pub(crate) fn out_extension(out: &Path) -> Result<Option<String>, PlotError> {
    if out.file_name().is_none() {
        return Err(PlotError::Input(format!(
            "--out {}: not a file name",
            out.display()
        )));
    }
    Ok(out
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase()))
}

/// A figure that can be drawn on any plotters backend.
pub trait Figure {
    /// Image size in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws the whole figure on `root` (which has the size [`Figure::size`]); `text` is false
    /// when no font is available (then nothing textual may be drawn).
    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        text: bool,
    ) -> Result<(), DrawError>
    where
        DB::ErrorType: 'static;
}

/// Converts a plotters error to a [`DrawError`].
pub(crate) fn de<E: std::error::Error + Send + Sync + 'static>(
    e: DrawingAreaErrorKind<E>,
) -> DrawError {
    DrawError::Backend(Box::new(e))
}

/// Renders `fig` as an SVG document (raster cells embedded as PNG images, [`svgimage`]).
pub fn render_svg<F: Figure>(fig: &F) -> Result<String, PlotError> {
    let text = font::font_available();
    let mut s = String::new();
    let images = std::rc::Rc::new(std::cell::RefCell::new(Vec::new()));
    let err = |source| PlotError::Draw {
        format: "SVG",
        source,
    };
    {
        let svg = SVGBackend::with_string(&mut s, fig.size());
        let root = svgimage::SvgImages::new(svg, images.clone()).into_drawing_area();
        fig.draw(&root, text).map_err(err)?;
        root.present().map_err(|e| err(de(e)))?;
    }
    let images = images.borrow();
    svgimage::embed(&s, &images).map_err(|e| err(DrawError::Embed(e)))
}

/// Renders `fig` into an RGB buffer (3 bytes per pixel, rows top to bottom); returns the buffer
/// and its size.
pub fn render_rgb<F: Figure>(fig: &F) -> Result<(Vec<u8>, (u32, u32)), PlotError> {
    let text = font::font_available();
    let (w, h) = fig.size();
    let mut buf = vec![0u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        let err = |source| PlotError::Draw {
            format: "PNG",
            source,
        };
        fig.draw(&root, text).map_err(err)?;
        root.present().map_err(|e| err(de(e)))?;
    }
    Ok((buf, (w, h)))
}

/// Encodes an RGB buffer as PNG bytes.
pub fn encode_png(rgb: &[u8], (w, h): (u32, u32)) -> Result<Vec<u8>, PlotError> {
    let err = |e: png::EncodingError| PlotError::Draw {
        format: "PNG",
        source: DrawError::Png(e),
    };
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Best);
        let mut wr = enc.write_header().map_err(err)?;
        wr.write_image_data(rgb).map_err(err)?;
        wr.finish().map_err(err)?;
    }
    Ok(out)
}

/// Renders `fig` to the file(s) named by `out` (see [`output_paths`]) and returns their paths.
/// All formats are rendered before anything is written; each file is written to a temporary
/// sibling and renamed into place, and files already written are removed if a later one fails.
pub fn write_figure<F: Figure>(fig: &F, out: &Path) -> Result<Vec<PathBuf>, PlotError> {
    let targets = output_paths(out)?;
    let mut rendered = Vec::with_capacity(targets.len());
    for (path, format) in targets {
        let bytes = match format {
            Format::Svg => render_svg(fig)?.into_bytes(),
            Format::Png => {
                let (rgb, size) = render_rgb(fig)?;
                encode_png(&rgb, size)?
            }
        };
        rendered.push((path, bytes));
    }
    let mut written: Vec<PathBuf> = Vec::new();
    for (path, bytes) in rendered {
        let r = crate::snapshot::write_atomically(&path, |w| {
            w.write_all(&bytes).map_err(SnapshotError::Output)
        });
        if let Err(e) = r {
            for p in &written {
                let _ = std::fs::remove_file(p);
            }
            return Err(e.into());
        }
        written.push(path);
    }
    Ok(written)
}

/// Reduces a polyline to at most about `2·bins` points keeping the minimum and maximum `y` of
/// each of `bins` equal-width `x` bins (in `x` order), so narrow pulses stay visible; shorter
/// inputs are returned unchanged. `points` must be sorted by `x`.
pub fn decimate(points: &[(f64, f64)], bins: usize) -> Vec<(f64, f64)> {
    if points.len() <= 2 * bins.max(1) {
        return points.to_vec();
    }
    let (x0, x1) = (points[0].0, points[points.len() - 1].0);
    let width = (x1 - x0) / bins as f64;
    let mut out = Vec::with_capacity(2 * bins + 2);
    let mut start = 0;
    while start < points.len() {
        let b = if width > 0.0 {
            (((points[start].0 - x0) / width) as usize).min(bins - 1)
        } else {
            0
        };
        let mut end = start;
        let (mut lo, mut hi) = (start, start);
        while end < points.len() {
            let bb = if width > 0.0 {
                (((points[end].0 - x0) / width) as usize).min(bins - 1)
            } else {
                0
            };
            if bb != b {
                break;
            }
            if points[end].1 < points[lo].1 {
                lo = end;
            }
            if points[end].1 > points[hi].1 {
                hi = end;
            }
            end += 1;
        }
        let (a, c) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        out.push(points[a]);
        if c != a {
            out.push(points[c]);
        }
        start = end;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn output_paths_by_extension() {
        let p = output_paths(Path::new("dir/fig.png")).unwrap();
        assert_eq!(p, vec![(PathBuf::from("dir/fig.png"), Format::Png)]);
        let p = output_paths(Path::new("fig.SVG")).unwrap();
        assert_eq!(p[0].1, Format::Svg);
        let p = output_paths(Path::new("out/fig")).unwrap();
        assert_eq!(
            p,
            vec![
                (PathBuf::from("out/fig.png"), Format::Png),
                (PathBuf::from("out/fig.svg"), Format::Svg)
            ]
        );
        let e = output_paths(Path::new("fig.jpg")).unwrap_err().to_string();
        assert!(e.contains(".jpg") && e.contains("fig.jpg"), "{e}");
    }

    #[test]
    fn decimate_keeps_extremes() {
        let pts: Vec<(f64, f64)> = (0..1000)
            .map(|i| (i as f64, if i == 517 { 5.0 } else { 0.0 }))
            .collect();
        let d = decimate(&pts, 50);
        assert!(d.len() <= 102, "{}", d.len());
        assert!(d.contains(&(517.0, 5.0)));
        assert!(d.windows(2).all(|w| w[0].0 < w[1].0));
        assert_eq!(decimate(&pts[..10], 50).len(), 10);
    }
}
