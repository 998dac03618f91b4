//! Leading-wave energy against its position with the fitted exponential (paper Sec. 5.2,
//! Fig. 21): per frame, the leading wave of [`crate::analysis::track_leading`] (beads above 0.1 %
//! of its peak `|v|`, energy eq. 13) gives a point `(x, E_wave/E₀)` with `x` its energy-weighted
//! position in beads and `E₀` the total energy of the first frame;
//! [`crate::analysis::decay_fit`] fits `E = a e^{−γ x}` over the points with `from ≤ x ≤ to`,
//! drawn dashed with `γ ± s.e.` in the legend. The fit is the one `beadchain analyze` reports
//! (same points, same `γ`; only `a` differs, by the energy each divides by).
//!
//! **Interfaces** (`--interface K`, paper Sec. 5: the decay differs on either side of an
//! interface at bead `K`): the points are split into positions `< K` and `≥ K` and each side is
//! fitted on its own (`from ≤ x < K` and `K ≤ x ≤ to`); no fit ever spans the interface, whose
//! energy jump (reflection) would otherwise read as decay. Both fits are drawn and printed.

use super::lines::{LineChart, Series, Style};
use super::select::require_frames;
use super::units::{AxisUnits, Units};
use super::{DrawError, PlotError};
use crate::analysis::{
    decay_fit, track_leading, ExpFit, FitError, FitRange, TrackPoint, WaveOptions,
};
use crate::snapshot::{Frame, Snapshot};

/// What to draw.
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyOptions {
    /// Fit from this leading-wave position on [default: 20, or 0 for chains of at most 40 beads].
    pub from: Option<usize>,
    /// ... up to this position [default: N − 10, or N − 1 for chains of at most 40 beads].
    pub to: Option<usize>,
    /// Logarithmic energy axis.
    pub log: bool,
    /// Interface bead `K`: fit beads `< K` and `≥ K` separately.
    pub interface: Option<usize>,
    /// Axis units (`E/E₀` is dimensionless; SI is checked like the other plots).
    pub units: Units,
    /// Image size in pixels.
    pub size: (u32, u32),
}

impl Default for EnergyOptions {
    fn default() -> Self {
        Self {
            from: None,
            to: None,
            log: false,
            interface: None,
            units: Units::Computer,
            size: (900, 650),
        }
    }
}

/// One exponential fit over a range of leading-wave positions.
#[derive(Clone, Debug, PartialEq)]
pub struct SideFit {
    /// The positions fitted.
    pub range: FitRange,
    /// The fit, or why there is none.
    pub fit: Result<ExpFit, FitError>,
}

/// The energy figure and its fits (one, or one per side of the interface).
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyPlot {
    /// The chart (points, fit lines).
    pub chart: LineChart,
    /// The fits, left to right.
    pub fits: Vec<SideFit>,
}

/// The fit ranges of positions: `from ≤ x ≤ to`, or split at the interface.
fn fit_ranges(n: usize, opts: &EnergyOptions) -> Result<Vec<FitRange>, PlotError> {
    let small = n <= 40;
    let mut from = opts.from.unwrap_or(if small { 0 } else { 20 });
    let mut to = opts
        .to
        .unwrap_or(if small { n.saturating_sub(1) } else { n - 10 });
    if let Some(k) = opts.interface {
        if k == 0 || k >= n {
            return Err(PlotError::Input(format!(
                "--interface: bead {k} is out of range (it must split the chain of {n} beads: 1..={})",
                n.saturating_sub(1)
            )));
        }
        // defaults reach the interface from both sides
        if opts.from.is_none() {
            from = from.min(k - 1);
        }
        if opts.to.is_none() {
            to = to.max(k);
        }
    }
    for (flag, b) in [("--from", from), ("--to", to)] {
        if b >= n {
            return Err(PlotError::Input(format!(
                "{flag}: bead {b} is out of range (the chain has {n} beads, 0..={})",
                n - 1
            )));
        }
    }
    if from > to {
        return Err(PlotError::Input(format!(
            "fit range --from {from} --to {to} is empty"
        )));
    }
    let (from, to) = (from as f64, to as f64);
    match opts.interface {
        None => Ok(vec![FitRange::inclusive(from, to)]),
        Some(k) if from >= k as f64 || to < k as f64 => Err(PlotError::Input(format!(
            "--interface {k}: the fit range --from {from} --to {to} must contain beads on both \
             sides (from < {k} <= to)"
        ))),
        Some(k) => Ok(vec![
            FitRange::below(from, k as f64),
            FitRange::inclusive(k as f64, to),
        ]),
    }
}

/// The fit of the track points in `range` ([`decay_fit`], energies over `e0`) and its dashed
/// curve.
fn side_fit(track: &[TrackPoint], range: FitRange, e0: f64) -> (SideFit, Option<Series>) {
    let fit = decay_fit(track, &range, e0);
    let curve = fit.as_ref().ok().map(|fit| {
        let xs = track
            .iter()
            .map(|p| p.position)
            .filter(|&x| range.contains(x));
        let (x0, x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
        Series {
            name: format!(
                "fit x {range}: γ = {:.4e} ± {:.2e} ({} points)",
                fit.gamma, fit.gamma_stderr, fit.n
            ),
            points: (0..=100)
                .map(|j| {
                    let x = x0 + (x1 - x0) * j as f64 / 100.0;
                    (x, fit.a * (-fit.gamma * x).exp())
                })
                .collect(),
            style: Style::Fit,
        }
    });
    (SideFit { range, fit }, curve)
}

/// Builds the energy chart of `snap` (frames streamed one at a time).
pub fn energy(snap: &Snapshot, opts: &EnergyOptions) -> Result<EnergyPlot, PlotError> {
    require_frames(snap)?;
    let chain = &snap.header().scene.chain;
    AxisUnits::of(&snap.header().scene, opts.units, snap.path())?;
    let ranges = fit_ranges(chain.len(), opts)?;
    let wave = WaveOptions::default();
    let mut f = Frame::default();
    let mut e0 = f64::NAN;
    let mut track = Vec::new();
    for k in 0..snap.frame_count() {
        snap.read_frame_into(k, &mut f)?;
        if k == 0 {
            e0 = chain.energy(&f.u, &f.v);
        }
        track.extend(track_leading(
            chain,
            std::iter::once((f.t, &f.u[..], &f.v[..])),
            &wave,
        ));
    }
    if !(e0 > 0.0 && e0.is_finite()) {
        return Err(PlotError::Input(format!(
            "{}: the first frame's energy is {e0}: nothing to normalise by",
            snap.path().display()
        )));
    }
    if track.is_empty() {
        return Err(PlotError::Input(format!(
            "{}: no leading wave in any frame",
            snap.path().display()
        )));
    }
    let mut fits = Vec::with_capacity(ranges.len());
    let mut curves = Vec::new();
    for r in ranges {
        let (f, c) = side_fit(&track, r, e0);
        fits.push(f);
        curves.extend(c);
    }
    let mut series = vec![Series {
        name: "leading wave (one point per frame)".into(),
        points: track.iter().map(|p| (p.position, p.energy / e0)).collect(),
        style: Style::Markers,
    }];
    series.append(&mut curves);
    Ok(EnergyPlot {
        chart: LineChart {
            title: format!(
                "{}: leading-wave energy, E = a exp(-γ x)",
                snap.header().scene.name
            ),
            x_desc: "position x of the leading wave (energy-weighted, beads)".into(),
            y_desc: "energy ratio E_wave / E_0 (dimensionless)".into(),
            series,
            log_y: opts.log,
            x_span: None,
            size: opts.size,
        },
        fits,
    })
}

impl super::Figure for EnergyPlot {
    fn size(&self) -> (u32, u32) {
        self.chart.size
    }

    fn draw<DB: plotters::prelude::DrawingBackend>(
        &self,
        root: &plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
        text: bool,
    ) -> Result<(), DrawError>
    where
        DB::ErrorType: 'static,
    {
        self.chart.draw(root, text)
    }
}
