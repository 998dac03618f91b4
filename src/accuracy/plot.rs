//! The work–precision plot: error against wall time on log–log axes, one line per
//! engine/method (points joined in the order of the tolerance list), drawn with `plotters` as SVG
//! and PNG. The method sets the colour ([`crate::plot::lines::line_color`]: auto, radau5, dop853,
//! verlet), the engine the line: hybrid solid with round markers, dense dashed with square ones;
//! lines and legend swatches are 3 px wide, so every pair reads apart (issue 36).
//!
//! Text (title, axis labels, legend) needs a TrueType font: `plotters` is built with its
//! `ab_glyph` renderer (no system font discovery), and the font file is read at run time from
//! `$BEADCHAIN_FONT` or the first of [`FONT_CANDIDATES`] that exists (see [`crate::plot::font`]).
//! Without one the plots are drawn without any text (lines and markers only; the CSV holds the
//! numbers) and [`render_plots`] says so.

use super::AccuracyReport;
use crate::integrate::Method;
use crate::names::Named;
use crate::plot::layout::{draw_legend, label_and_draw_mesh};
use crate::plot::lines::line_color;
use crate::plot::{de, DrawError};
use crate::scene::Engine;
use plotters::coord::Shift;
use plotters::prelude::*;

pub use crate::plot::font::FONT_CANDIDATES;
use crate::plot::font::{font_available, FAMILY};

/// One line of the plot.
struct Line {
    name: String,
    engine: Engine,
    method: Method,
    points: Vec<(f64, f64)>,
}

/// Width of lines and legend swatches, in pixels.
const WIDTH: u32 = 3;

/// The colour of a method's lines (both engines).
fn method_color(m: Method) -> RGBAColor {
    let k = match m {
        Method::Auto => 0,
        Method::Radau5 => 1,
        Method::Dop853 => 2,
        Method::Verlet => 3,
    };
    line_color(k).to_rgba()
}

/// Successful runs with a positive error and wall time, grouped by engine/method (row order).
fn lines(report: &AccuracyReport) -> Vec<Line> {
    let mut out: Vec<Line> = Vec::new();
    for r in &report.rows {
        let usable = r.failure.is_none()
            && r.error > 0.0
            && r.error.is_finite()
            && r.wall_seconds > 0.0
            && r.wall_seconds.is_finite();
        if !usable {
            continue;
        }
        let name = format!("{} {}", r.engine.name(), r.method.name());
        match out.iter_mut().find(|l| l.name == name) {
            Some(l) => l.points.push((r.wall_seconds, r.error)),
            None => out.push(Line {
                name,
                engine: r.engine,
                method: r.method,
                points: vec![(r.wall_seconds, r.error)],
            }),
        }
    }
    out
}

/// Log-axis range covering `xs` with a margin (a fixed range when empty).
fn range(xs: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = xs.fold((f64::INFINITY, 0.0_f64), |(a, b), x| (a.min(x), b.max(x)));
    if lo.is_finite() && hi > 0.0 {
        (lo / 2.0, hi * 2.0)
    } else {
        (1e-3, 1.0)
    }
}

/// Draws the chart on `root`.
fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    report: &AccuracyReport,
    text: bool,
) -> Result<(), DrawError>
where
    DB::ErrorType: 'static,
{
    let err = de::<DB::ErrorType>;
    root.fill(&WHITE).map_err(err)?;
    let data = lines(report);
    let (x0, x1) = range(data.iter().flat_map(|l| l.points.iter().map(|p| p.0)));
    let (y0, y1) = range(data.iter().flat_map(|l| l.points.iter().map(|p| p.1)));
    let mut builder = ChartBuilder::on(root);
    builder.margin(20);
    if text {
        builder
            .caption(
                format!(
                    "{} ({} beads, t = {}): error vs wall time",
                    report.scene, report.beads, report.until
                ),
                (FAMILY, 22),
            )
            .x_label_area_size(50)
            .y_label_area_size(80);
    }
    let mut chart = builder
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(err)?;
    let fmt = |x: &f64| format!("{x:.0e}");
    label_and_draw_mesh(
        &mut chart.configure_mesh(),
        (
            "wall time [s] (median)",
            "error vs reference, max(err_u, err_v)",
        ),
        (&fmt, &fmt),
        text,
    )?;
    for l in &data {
        draw_line(&mut chart, l, text)?;
    }
    if text {
        draw_legend(&mut chart)?;
    }
    root.present().map_err(err)?;
    Ok(())
}

/// One method's line on the chart: solid with circles for the hybrid engine, dashed with
/// squares for the dense one (and its legend swatch where text is drawn).
fn draw_line<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>,
    l: &Line,
    text: bool,
) -> Result<(), DrawError>
where
    DB::ErrorType: 'static,
{
    let err = de::<DB::ErrorType>;
    let color = method_color(l.method);
    let line = color.stroke_width(WIDTH);
    let pts = l.points.iter().copied();
    if l.engine == Engine::Dense {
        let series = chart
            .draw_series(DashedLineSeries::new(pts, 10, 6, line))
            .map_err(err)?;
        if text {
            series.label(l.name.clone()).legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (7, 0)], line)
                    + PathElement::new(vec![(13, 0), (20, 0)], line)
                    + Rectangle::new([(6, -4), (14, 4)], color.filled())
            });
        }
        chart
            .draw_series(
                l.points.iter().map(|&p| {
                    EmptyElement::at(p) + Rectangle::new([(-4, -4), (4, 4)], color.filled())
                }),
            )
            .map_err(err)?;
    } else {
        let series = chart.draw_series(LineSeries::new(pts, line)).map_err(err)?;
        if text {
            series.label(l.name.clone()).legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (20, 0)], line)
                    + Circle::new((10, 0), 5, color.filled())
            });
        }
        chart
            .draw_series(l.points.iter().map(|&p| Circle::new(p, 5, color.filled())))
            .map_err(err)?;
    }
    Ok(())
}

/// The SVG text and PNG bytes of the plot, and whether text was drawn (a font was found);
/// nothing is written ([`super::report`] writes them with the CSV, all or none).
pub fn render_plots(report: &AccuracyReport) -> Result<(String, Vec<u8>, bool), String> {
    let text = font_available();
    let size = (900, 650);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        draw(&root, report, text).map_err(|e| format!("svg: {e}"))?;
    }
    // rendered in memory and encoded with the `png` crate (plotters' own file encoder needs the
    // `image` crate, left out of the build: see Cargo.toml)
    let mut buf = vec![0u8; size.0 as usize * size.1 as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        draw(&root, report, text).map_err(|e| format!("png: {e}"))?;
    }
    let png = crate::plot::encode_png(&buf, size).map_err(|e| format!("png: {e}"))?;
    Ok((svg, png, text))
}
