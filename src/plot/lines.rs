//! A plain x–y chart of lines and markers with a legend: the figure behind [`super::profile`],
//! [`super::trace`] and [`super::energy`]. A logarithmic y axis is drawn by plotting `log₁₀ y`
//! over whole decades, ticked and labelled at decades ([`super::ticks::log_decades`];
//! non-positive values are left out); linear axes get the common tick format of
//! [`super::ticks::TickFmt`]. A constant series gets a padded range (never zero-width).
//! Series are coloured from [`LINE_COLORS`], every one of which stands out on white.

use super::layout::{draw_axes, draw_legend, safe_range, Layout};
use super::ticks::{log_decades, N_LABELS};
use super::{de, DrawError, Figure};
use plotters::coord::Shift;
use plotters::prelude::*;

/// The colours of successive series (then again from the first): a blue, red, green, orange,
/// purple, teal, brown, magenta, olive and navy, each with a contrast of at least 3:1 against
/// the white background (WCAG 2.1 for graphics; plotters' `Palette99` had yellow third, 1.3:1).
/// Black is left for fits and axes.
pub const LINE_COLORS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(200, 100, 0),
    RGBColor(148, 103, 189),
    RGBColor(0, 128, 128),
    RGBColor(140, 86, 75),
    RGBColor(190, 40, 160),
    RGBColor(128, 128, 0),
    RGBColor(0, 0, 128),
];

/// The colour of series `k` ([`LINE_COLORS`], cyclically).
pub fn line_color(k: usize) -> RGBColor {
    LINE_COLORS[k % LINE_COLORS.len()]
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// Joined by a line.
    Line,
    /// Separate circles.
    Markers,
    /// A dashed black line (fits).
    Fit,
}

/// One series.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend text.
    pub name: String,
    /// Points, in drawing order.
    pub points: Vec<(f64, f64)>,
    /// Drawing style.
    pub style: Style,
}

/// A chart of several series.
#[derive(Clone, Debug, PartialEq)]
pub struct LineChart {
    /// Title.
    pub title: String,
    /// x axis description.
    pub x_desc: String,
    /// y axis description.
    pub y_desc: String,
    /// The series (colours by position).
    pub series: Vec<Series>,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// The x axis exactly, not padded around the data (a time axis: from the first to the last
    /// frame, no negative time; one frame interval around a single frame).
    pub x_span: Option<(f64, f64)>,
    /// Image size.
    pub size: (u32, u32),
}

impl LineChart {
    /// The y value as plotted (log₁₀ on a log axis; `None` when not drawable).
    fn ty(&self, y: f64) -> Option<f64> {
        if !y.is_finite() {
            None
        } else if self.log_y {
            (y > 0.0).then(|| y.log10())
        } else {
            Some(y)
        }
    }

    /// Points of a series as plotted.
    fn plotted(&self, s: &Series) -> Vec<(f64, f64)> {
        s.points
            .iter()
            .filter(|p| p.0.is_finite())
            .filter_map(|&(x, y)| self.ty(y).map(|y| (x, y)))
            .collect()
    }

    /// Axis ranges with a 5 % margin (unit ranges around a single value; `x_span` as given).
    fn ranges(&self) -> ((f64, f64), (f64, f64)) {
        let (mut x0, mut x1, mut y0, mut y1) = (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        );
        for s in &self.series {
            for (x, y) in self.plotted(s) {
                x0 = x0.min(x);
                x1 = x1.max(x);
                y0 = y0.min(y);
                y1 = y1.max(y);
            }
        }
        let pad = |lo: f64, hi: f64, frac: f64| {
            if !lo.is_finite() {
                (0.0, 1.0)
            } else if hi <= lo {
                let d = if lo == 0.0 { 1.0 } else { lo.abs() * 0.1 };
                (lo - d, hi + d)
            } else {
                let d = (hi - lo) * frac;
                (lo - d, hi + d)
            }
        };
        let x = self
            .x_span
            .filter(|(a, b)| a.is_finite() && b.is_finite() && b > a)
            .unwrap_or_else(|| pad(x0, x1, 0.02));
        (x, pad(y0, y1, 0.06))
    }
}

impl LineChart {
    /// The y range and number of labels: the decades of the data on a log axis (not of the
    /// padded range; 1e-9 decade of rounding slack), else the padded range `y0..y1`.
    fn y_axis(&self, y0: f64, y1: f64) -> ((f64, f64), usize) {
        if self.log_y {
            let (lo, hi) = self
                .series
                .iter()
                .flat_map(|s| self.plotted(s))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), (_, y)| {
                    (a.min(y), b.max(y))
                });
            log_decades(lo + 1e-9, hi - 1e-9)
        } else {
            (safe_range(y0, y1), N_LABELS)
        }
    }
}

impl Figure for LineChart {
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
        let lay = Layout::new(self.size, false);
        let ((x0, x1), (y0, y1)) = self.ranges();
        let (x0, x1) = safe_range(x0, x1);
        let ((y0, y1), ny) = self.y_axis(y0, y1);
        let mut chart = lay
            .chart(root)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(de)?;
        let desc = (self.x_desc.as_str(), self.y_desc.as_str());
        draw_axes(&mut chart, desc, true, self.log_y.then_some(ny), text)?;
        for (k, s) in self.series.iter().enumerate() {
            let pts = self.plotted(s);
            let color = match s.style {
                Style::Fit => BLACK.to_rgba(),
                Style::Line | Style::Markers => line_color(k).to_rgba(),
            };
            let series = match s.style {
                Style::Line => chart.draw_series(LineSeries::new(pts, color.stroke_width(2))),
                Style::Markers => {
                    chart.draw_series(pts.into_iter().map(|p| Circle::new(p, 3, color.filled())))
                }
                Style::Fit => {
                    chart.draw_series(DashedLineSeries::new(pts, 8, 5, color.stroke_width(2)))
                }
            }
            .map_err(de)?;
            if text {
                series.label(s.name.clone()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            }
        }
        if text && !self.series.is_empty() {
            draw_legend(&mut chart)?;
        }
        lay.title(root, &self.title, text)
    }
}
