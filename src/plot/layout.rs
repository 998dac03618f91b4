//! Fixed figure geometry (so the plot area's pixels are known before drawing: raster cells are
//! blitted there, and tests can find a data point's pixel), the title and the colour bar.

use super::font::FAMILY;
use super::ticks::{decade_label, TickFmt, N_LABELS};
use super::{de, DrawError};
use plotters::chart::MeshStyle;
use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::{CoordTranslate, Shift};
use plotters::element::BitMapElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Margins and label areas of a figure, in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Image size.
    pub size: (u32, u32),
    /// Space above the plot area (title).
    pub top: u32,
    /// Left margin before the y labels.
    pub left: u32,
    /// Bottom margin below the x labels.
    pub bottom: u32,
    /// Space right of the plot area (colour bar, or a margin).
    pub right: u32,
    /// Height of the x label area.
    pub x_label: u32,
    /// Width of the y label area.
    pub y_label: u32,
}

/// Width of the colour-bar strip right of the plot area.
pub const COLORBAR_STRIP: u32 = 130;

impl Layout {
    /// The standard layout of `size`, with room for a colour bar when `colorbar`.
    pub fn new(size: (u32, u32), colorbar: bool) -> Self {
        Layout {
            size,
            top: 45,
            left: 10,
            bottom: 10,
            right: if colorbar { COLORBAR_STRIP } else { 25 },
            x_label: 50,
            y_label: 85,
        }
    }

    /// Plot area `(x0, y0, width, height)` in pixels (at least 1×1).
    pub fn plot_rect(&self) -> (i32, i32, u32, u32) {
        let (w, h) = self.size;
        let x0 = self.left + self.y_label;
        let y0 = self.top;
        let pw = w.saturating_sub(x0 + self.right).max(1);
        let ph = h.saturating_sub(y0 + self.bottom + self.x_label).max(1);
        (x0 as i32, y0 as i32, pw, ph)
    }

    /// A chart builder on `root` whose plot area is [`Self::plot_rect`].
    pub fn chart<'a, 'b, DB: DrawingBackend>(
        &self,
        root: &'a DrawingArea<DB, Shift>,
    ) -> ChartBuilder<'a, 'b, DB> {
        let mut b = ChartBuilder::on(root);
        b.margin_top(self.top)
            .margin_left(self.left)
            .margin_bottom(self.bottom)
            .margin_right(self.right)
            .x_label_area_size(self.x_label)
            .y_label_area_size(self.y_label);
        b
    }

    /// Checks that plotters placed the plot area where [`Self::plot_rect`] says.
    pub fn check(&self, x: std::ops::Range<i32>, y: std::ops::Range<i32>) -> Result<(), DrawError> {
        let (x0, y0, pw, ph) = self.plot_rect();
        // plotters' ranges are half-open or inclusive depending on the version: allow 1 px
        let ok = (x.start - x0).abs() <= 1
            && (y.start - y0).abs() <= 1
            && ((x.end - x.start) - pw as i32).abs() <= 1
            && ((y.end - y.start) - ph as i32).abs() <= 1;
        if ok {
            Ok(())
        } else {
            Err(DrawError::Layout {
                x,
                y,
                expected: (x0, pw, y0, ph),
            })
        }
    }

    /// Draws the title above the plot area.
    pub fn title<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        title: &str,
        text: bool,
    ) -> Result<(), DrawError>
    where
        DB::ErrorType: 'static,
    {
        if !text {
            return Ok(());
        }
        let (x0, _, pw, _) = self.plot_rect();
        let style = TextStyle::from((FAMILY, 18).into_font())
            .pos(Pos::new(HPos::Center, VPos::Center))
            .color(&BLACK);
        root.draw(&Text::new(
            title.to_string(),
            (x0 + pw as i32 / 2, self.top as i32 / 2),
            style,
        ))
        .map_err(de)
    }

    /// Draws a vertical colour bar in the right strip, level with the plot area: `color(s)` for
    /// `s` from 0 (bottom) to 1 (top), `ticks` as `(s, label)`, and `label` above the bar (lines split at `\n`).
    pub fn colorbar<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        color: &dyn Fn(f64) -> RGBColor,
        ticks: &[(f64, String)],
        label: &str,
        text: bool,
    ) -> Result<(), DrawError>
    where
        DB::ErrorType: 'static,
    {
        let (x0, y0, pw, ph) = self.plot_rect();
        let bx = x0 + pw as i32 + 20;
        let bw: u32 = 18;
        let mut buf = vec![0u8; (bw * ph) as usize * 3];
        for row in 0..ph {
            let s = if ph > 1 {
                1.0 - row as f64 / (ph - 1) as f64
            } else {
                0.5
            };
            let c = color(s);
            for col in 0..bw {
                let k = ((row * bw + col) * 3) as usize;
                buf[k..k + 3].copy_from_slice(&[c.0, c.1, c.2]);
            }
        }
        if let Some(el) = BitMapElement::with_owned_buffer((bx, y0), (bw, ph), buf) {
            root.draw(&el).map_err(de)?;
        }
        root.draw(&Rectangle::new(
            [(bx, y0), (bx + bw as i32, y0 + ph as i32)],
            BLACK.stroke_width(1),
        ))
        .map_err(de)?;
        let style = TextStyle::from((FAMILY, 13).into_font())
            .pos(Pos::new(HPos::Left, VPos::Center))
            .color(&BLACK);
        for (s, lab) in ticks {
            let y = y0 + ((1.0 - s.clamp(0.0, 1.0)) * (ph.max(2) - 1) as f64).round() as i32;
            root.draw(&PathElement::new(
                vec![(bx + bw as i32, y), (bx + bw as i32 + 5, y)],
                BLACK.stroke_width(1),
            ))
            .map_err(de)?;
            if text {
                root.draw(&Text::new(
                    lab.clone(),
                    (bx + bw as i32 + 8, y),
                    style.clone(),
                ))
                .map_err(de)?;
            }
        }
        if text {
            let st = TextStyle::from((FAMILY, 14).into_font())
                .pos(Pos::new(HPos::Left, VPos::Bottom))
                .color(&BLACK);
            // one text line per `\n`, the last just above the bar
            for (k, line) in label.lines().rev().enumerate() {
                let y = y0 - 6 - 15 * k as i32;
                root.draw(&Text::new(line.to_string(), (bx - 10, y), st.clone()))
                    .map_err(de)?;
            }
        }
        Ok(())
    }
}

/// An axis range plotters can tick: finite, `lo < hi`, and `hi − lo` finite. plotters' tick
/// search loops forever on an infinite span (a snapshot or CSV holding ±1e308 gives
/// `hi − lo = inf`), so ends are clamped to ±`f64::MAX / 4` (points beyond are clipped).
pub fn safe_range(lo: f64, hi: f64) -> (f64, f64) {
    const M: f64 = f64::MAX / 4.0;
    if lo.is_nan() || hi.is_nan() {
        return (0.0, 1.0);
    }
    let (lo, hi) = (lo.clamp(-M, M), hi.clamp(-M, M));
    if hi > lo {
        return (lo, hi);
    }
    let d = if lo == 0.0 { 1.0 } else { lo.abs() * 0.1 };
    (lo - d, hi + d)
}

/// [`num_label`] of an axis tick on an axis spanning `span`: a tick within rounding of zero
/// (|x| < 1e-9 · span, e.g. `-1.1e-16` from summing steps of 0.1) is labelled `0`.
pub fn tick_label(x: f64, span: f64) -> String {
    if x.abs() < 1e-9 * span.abs() {
        "0".into()
    } else {
        num_label(x)
    }
}

/// Compact number label: `0`, plain decimals for moderate magnitudes, else `1.5e-7`.
pub fn num_label(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let a = x.abs();
    if (1e-2..1e5).contains(&a) {
        let s = format!("{x:.3}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    } else {
        let s = format!("{x:.2e}");
        // 1.50e-7 -> 1.5e-7
        match s.split_once('e') {
            Some((m, e)) => {
                let m = if m.contains('.') {
                    m.trim_end_matches('0').trim_end_matches('.')
                } else {
                    m
                };
                format!("{m}e{e}")
            }
            None => s,
        }
    }
}

/// A tick-label formatter of an `f64` axis.
pub type TickFormatter = dyn Fn(&f64) -> String;

/// Labels a chart's mesh and draws it: the axis descriptions `desc` and tick formatters `fmt`
/// in the plots' font where text is drawn, no tick labels where it is not (the mesh's tick
/// counts and grid are set by the caller).
pub fn label_and_draw_mesh<'b, X, Y, DB>(
    mesh: &mut MeshStyle<'_, 'b, X, Y, DB>,
    desc: (&str, &str),
    fmt: (&'b TickFormatter, &'b TickFormatter),
    text: bool,
) -> Result<(), DrawError>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    DB: DrawingBackend,
    DB::ErrorType: 'static,
{
    if text {
        mesh.x_desc(desc.0)
            .y_desc(desc.1)
            .x_label_formatter(fmt.0)
            .y_label_formatter(fmt.1)
            .label_style((FAMILY, 14))
            .axis_desc_style((FAMILY, 16));
    } else {
        mesh.x_labels(0).y_labels(0);
    }
    mesh.draw().map_err(de)
}

/// Draws the axes of a chart on `f64` ranges: [`N_LABELS`] ticks an axis, each axis's labels in
/// one [`TickFmt`] (y in decades, [`decade_label`], where `y_decades` gives its tick count),
/// light grey grid lines where `grid` (none otherwise), as [`label_and_draw_mesh`] with `desc`.
pub fn draw_axes<DB>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    desc: (&str, &str),
    grid: bool,
    y_decades: Option<usize>,
    text: bool,
) -> Result<(), DrawError>
where
    DB: DrawingBackend,
    DB::ErrorType: 'static,
{
    let (x, y, ny) = (
        chart.x_range(),
        chart.y_range(),
        y_decades.unwrap_or(N_LABELS),
    );
    let (xf, yf) = (
        TickFmt::axis(x.start, x.end, N_LABELS),
        TickFmt::axis(y.start, y.end, ny),
    );
    let xfmt = move |x: &f64| xf.label(*x);
    let yfmt = move |y: &f64| match y_decades {
        Some(_) => decade_label(*y),
        None => yf.label(*y),
    };
    let mut mesh = chart.configure_mesh();
    if grid {
        mesh.light_line_style(RGBColor(235, 235, 235));
    } else {
        mesh.disable_mesh();
    }
    mesh.x_labels(N_LABELS).y_labels(ny);
    label_and_draw_mesh(&mut mesh, desc, (&xfmt, &yfmt), text)
}

/// Draws the legend of a chart's labelled series in its upper right corner.
pub fn draw_legend<'a, DB, CT>(chart: &mut ChartContext<'a, DB, CT>) -> Result<(), DrawError>
where
    DB: DrawingBackend + 'a,
    DB::ErrorType: 'static,
    CT: CoordTranslate,
{
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font((FAMILY, 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(de)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels() {
        assert_eq!(num_label(0.0), "0");
        assert_eq!(num_label(2.5), "2.5");
        assert_eq!(tick_label(-1.11e-16, 1.0), "0");
        assert_eq!(tick_label(4.96e-15, 1e-14), "4.96e-15");
        assert_eq!(num_label(1500.0), "1500");
        assert_eq!(num_label(12000.0), "12000");
        assert_eq!(num_label(2.0e5), "2e5");
        assert_eq!(num_label(-9.96e-8), "-9.96e-8");
        assert_eq!(num_label(1e-4), "1e-4");
    }

    #[test]
    fn plot_rect_fits() {
        let l = Layout::new((900, 700), true);
        let (x0, y0, w, h) = l.plot_rect();
        assert_eq!((x0, y0), (95, 45));
        assert_eq!(x0 as u32 + w + COLORBAR_STRIP, 900);
        assert_eq!(y0 as u32 + h + 60, 700);
    }
}
