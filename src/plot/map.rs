//! 2-D parameter maps from a CSV (the paper's Fig. 7, reflected energy over `(n1, n2)`, and
//! Fig. 25, composite interfaces with their transition contour): a heatmap on the grid of distinct `x` and `y` values (cells centred
//! on the values themselves, edges halfway between neighbours, so uneven spacing is kept), the
//! sequential colour map with a colour bar ticked at round values
//! ([`super::ticks::colorbar_ticks`]), and an optional level line ([`super::contour`]). Axes and
//! colour bar are labelled with the columns' readable names ([`super::keys::readable`]:
//! `exponent n (segment 0)` for `chain.exponent.segments.0.value`).
//!
//! Rows whose `z` is empty or not a number (or not positive with `--log-z`) are skipped with a
//! warning naming the line; rows sharing `(x, y)` are averaged (with a warning); grid points
//! without a row are drawn white. With `--log-z`, colours and the contour use `log₁₀ z`.

use super::cmap::Cmap;
use super::contour::{marching_squares, Segment};
use super::csvtable::Table;
use super::keys::readable;
use super::layout::{draw_axes, draw_legend, num_label, Layout};
use super::ticks::{colorbar_ticks, TickFmt};
use super::{de, DrawError, Figure, PlotError};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// What to draw.
#[derive(Clone, Debug, PartialEq)]
pub struct MapOptions {
    /// x column.
    pub x: String,
    /// y column.
    pub y: String,
    /// Colour (z) column.
    pub z: String,
    /// Colour by `log₁₀ z`.
    pub log_z: bool,
    /// Draw the level line `z = level`.
    pub contour: Option<f64>,
    /// Colour map (default viridis).
    pub cmap: Cmap,
    /// Image size in pixels.
    pub size: (u32, u32),
}

/// A gridded map.
#[derive(Clone, Debug, PartialEq)]
pub struct Map {
    /// Title.
    pub title: String,
    /// Column names `(x, y, z)`.
    pub names: (String, String, String),
    /// x axis label (the x column's readable name unless overridden).
    pub x_desc: String,
    /// y axis label.
    pub y_desc: String,
    /// Colour-bar label (the z column's readable name, `(log scale)` added with `--log-z`).
    pub z_desc: String,
    /// Colour map.
    pub cmap: Cmap,
    /// Distinct x values, ascending.
    pub xs: Vec<f64>,
    /// Distinct y values, ascending.
    pub ys: Vec<f64>,
    /// Values as coloured (`z` or `log₁₀ z`), row-major `[j·nx + i]`, NaN = no data.
    pub z: Vec<f64>,
    /// Log colouring.
    pub log_z: bool,
    /// The level and its line segments.
    pub contour: Option<(f64, Vec<Segment>)>,
    /// Rows skipped or merged, one line each.
    pub warnings: Vec<String>,
    /// Image size.
    pub size: (u32, u32),
}

/// Sorted distinct values.
fn distinct(v: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut d: Vec<f64> = v.collect();
    d.sort_by(f64::total_cmp);
    d.dedup();
    d
}

impl Map {
    /// Reads `path` and grids the chosen columns.
    pub fn from_csv(path: &Path, opts: &MapOptions) -> Result<Map, PlotError> {
        let table = Table::read(path)?;
        let (ix, iy, iz) = (
            table.column(&opts.x, path)?,
            table.column(&opts.y, path)?,
            table.column(&opts.z, path)?,
        );
        let mut warnings = Vec::new();
        let mut points = Vec::with_capacity(table.rows.len());
        let field = |row: &[String], k: usize| row.get(k).map_or("", |s| s.as_str()).to_string();
        for (line, row) in &table.rows {
            let mut xy = [0.0; 2];
            for (slot, (k, name)) in xy.iter_mut().zip([(ix, &opts.x), (iy, &opts.y)]) {
                let s = field(row, k);
                *slot = match s.parse::<f64>() {
                    Ok(v) if v.is_finite() => v,
                    _ => {
                        return Err(PlotError::Csv {
                            path: path.to_path_buf(),
                            msg: format!("line {line}: column `{name}` is `{s}`, not a number"),
                        })
                    }
                };
            }
            let s = field(row, iz);
            match s.parse::<f64>() {
                Ok(z) if z.is_finite() && (!opts.log_z || z > 0.0) => {
                    points.push((xy[0], xy[1], z))
                }
                _ => warnings.push(format!(
                    "{}: line {line}: skipped: column `{}` is `{s}`{}",
                    path.display(),
                    opts.z,
                    if opts.log_z {
                        ", not a positive number (--log-z)"
                    } else {
                        ", not a number"
                    }
                )),
            }
        }
        let mut map = Map::from_points(&points, opts)?;
        map.title = format!(
            "{}: {}",
            readable(&opts.z),
            path.file_name()
                .map_or(String::new(), |f| f.to_string_lossy().into_owned())
        );
        warnings.append(&mut map.warnings);
        map.warnings = warnings;
        if map.xs.is_empty() {
            return Err(PlotError::Csv {
                path: path.to_path_buf(),
                msg: format!("no row with a numeric `{}`", opts.z),
            });
        }
        Ok(map)
    }

    /// Grids points `(x, y, z)` (z as given; `log₁₀` taken here with `log_z`).
    pub fn from_points(points: &[(f64, f64, f64)], opts: &MapOptions) -> Result<Map, PlotError> {
        let xs = distinct(points.iter().map(|p| p.0));
        let ys = distinct(points.iter().map(|p| p.1));
        let (nx, ny) = (xs.len(), ys.len());
        let mut sum = vec![0.0; nx * ny];
        let mut count = vec![0usize; nx * ny];
        for &(x, y, z) in points {
            // both found: the values came from these points
            let i = xs.partition_point(|&v| v < x);
            let j = ys.partition_point(|&v| v < y);
            let z = if opts.log_z { z.log10() } else { z };
            sum[j * nx + i] += z;
            count[j * nx + i] += 1;
        }
        let mut warnings = Vec::new();
        let z: Vec<f64> = sum
            .iter()
            .zip(&count)
            .enumerate()
            .map(|(k, (&s, &c))| {
                if c > 1 {
                    warnings.push(format!(
                        "{} rows at ({} = {}, {} = {}): averaged",
                        c,
                        opts.x,
                        xs[k % nx],
                        opts.y,
                        ys[k / nx]
                    ));
                }
                if c == 0 {
                    f64::NAN
                } else {
                    s / c as f64
                }
            })
            .collect();
        let contour = match opts.contour {
            None => None,
            Some(level) => {
                let l = if opts.log_z {
                    if level <= 0.0 {
                        return Err(PlotError::Input(format!(
                            "--contour {level}: must be positive with --log-z"
                        )));
                    }
                    level.log10()
                } else {
                    level
                };
                Some((level, marching_squares(&xs, &ys, &z, l)))
            }
        };
        let z_desc = if opts.log_z {
            format!("{} (log scale)", readable(&opts.z))
        } else {
            readable(&opts.z)
        };
        Ok(Map {
            title: readable(&opts.z),
            names: (opts.x.clone(), opts.y.clone(), opts.z.clone()),
            x_desc: readable(&opts.x),
            y_desc: readable(&opts.y),
            z_desc,
            cmap: opts.cmap,
            xs,
            ys,
            z,
            log_z: opts.log_z,
            contour,
            warnings,
            size: opts.size,
        })
    }

    /// Range of the finite values (a unit range around a single value).
    fn zrange(&self) -> (f64, f64) {
        let (lo, hi) = self
            .z
            .iter()
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        if !lo.is_finite() {
            (0.0, 1.0)
        } else if hi <= lo {
            (lo - 0.5, hi + 0.5)
        } else {
            (lo, hi)
        }
    }
}

/// Cell edges of sorted centres: halfway between neighbours, ends mirrored (±0.5 for one value).
pub fn edges(c: &[f64]) -> Vec<f64> {
    match c.len() {
        0 => vec![],
        1 => vec![c[0] - 0.5, c[0] + 0.5],
        n => {
            let mut e = Vec::with_capacity(n + 1);
            e.push(c[0] - (c[1] - c[0]) / 2.0);
            for k in 1..n {
                e.push((c[k - 1] + c[k]) / 2.0);
            }
            e.push(c[n - 1] + (c[n - 1] - c[n - 2]) / 2.0);
            e
        }
    }
}

impl Map {
    /// The colour bar's ticks at round values of the coloured range `lo..hi` (`log₁₀ z` with
    /// `--log-z`), as `(place on the bar, label)`.
    pub fn colorbar_ticks(&self, lo: f64, hi: f64) -> Vec<(f64, String)> {
        let ticks = colorbar_ticks(lo, hi, self.log_z);
        if self.log_z {
            return ticks.iter().map(|&(s, v)| (s, num_label(v))).collect();
        }
        let vals: Vec<f64> = ticks.iter().map(|t| t.1).collect();
        let f = TickFmt::for_values(&vals, hi - lo, 1e-9);
        ticks.iter().map(|&(s, v)| (s, f.label(v))).collect()
    }
}

/// `text` in lines of at most `width` characters, broken at spaces (a longer word stays whole):
/// the colour bar's label has the strip's width only.
fn wrap(text: &str, width: usize) -> String {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split(' ') {
        match lines.last_mut() {
            Some(l) if l.chars().count() + 1 + word.chars().count() <= width => {
                l.push(' ');
                l.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines.join("\n")
}

impl Figure for Map {
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
        let lay = Layout::new(self.size, true);
        let (ex, ey) = (edges(&self.xs), edges(&self.ys));
        let ((x0, x1), (y0, y1)) = (span(&ex), span(&ey));
        let mut chart = lay
            .chart(root)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(de)?;
        let (lo, hi) = self.zrange();
        let nx = self.xs.len();
        let cells = self.z.iter().enumerate().map(|(k, &v)| {
            let (i, j) = (k % nx, k / nx);
            let c = self.cmap.at((v - lo) / (hi - lo));
            Rectangle::new([(ex[i], ey[j]), (ex[i + 1], ey[j + 1])], c.filled())
        });
        chart.draw_series(cells).map_err(de)?;
        let desc = (self.x_desc.as_str(), self.y_desc.as_str());
        draw_axes(&mut chart, desc, false, None, text)?;
        if let Some((level, segs)) = &self.contour {
            let s = chart
                .draw_series(
                    segs.iter()
                        .map(|s| PathElement::new(vec![s[0], s[1]], BLACK.stroke_width(3))),
                )
                .map_err(de)?;
            if text {
                let name = self.z_desc.trim_end_matches(" (log scale)");
                s.label(format!("{name} = {}", num_label(*level)))
                    .legend(|(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(3))
                    });
                draw_legend(&mut chart)?;
            }
        }
        lay.title(root, &self.title, text)?;
        let ticks = self.colorbar_ticks(lo, hi);
        let label = wrap(&self.z_desc, 17);
        lay.colorbar(root, &|s| self.cmap.at(s), &ticks, &label, text)
    }
}

/// The axis range covered by cell edges `e` (0..1 when there are none), widened where empty.
fn span(e: &[f64]) -> (f64, f64) {
    let (a, b) = (
        e.first().copied().unwrap_or(0.0),
        e.last().copied().unwrap_or(1.0),
    );
    super::layout::safe_range(a, b)
}
