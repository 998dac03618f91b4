//! Dispersion relation of a periodic chain: the bands `ω(q)` of its unit cell for `q` from 0
//! to π (Bloch problem of [`crate::studies::bands`]), one line per band, and the band edges
//! around each gap as dashed lines.

use super::lines::{LineChart, Series, Style};
use crate::studies::bands::Bands;

/// The chart of `bands` (title `title`, image size `size`).
pub fn dispersion(bands: &Bands, title: &str, size: (u32, u32)) -> LineChart {
    let nb = bands.omega.len();
    let mut series: Vec<Series> = bands
        .omega
        .iter()
        .enumerate()
        .map(|(b, w)| Series {
            name: band_name(b, nb),
            points: bands.q.iter().copied().zip(w.iter().copied()).collect(),
            style: Style::Line,
        })
        .collect();
    let q_end = *bands.q.last().unwrap_or(&std::f64::consts::PI);
    for (k, (lo, hi)) in bands.gaps().into_iter().enumerate() {
        for (edge, w) in [("below", lo), ("above", hi)] {
            series.push(Series {
                name: format!("gap {} edge {edge}: {w:.4e}", k + 1),
                points: vec![(0.0, w), (q_end, w)],
                style: Style::Fit,
            });
        }
    }
    LineChart {
        title: title.to_string(),
        x_desc: "wavenumber q per unit cell (rad)".to_string(),
        y_desc: "angular frequency omega (computer units)".to_string(),
        series,
        log_y: false,
        x_span: None,
        size,
    }
}

/// "acoustic", "optical", "optical 2", … ("band k" beyond).
fn band_name(b: usize, nb: usize) -> String {
    match (b, nb) {
        (0, _) => "acoustic band".to_string(),
        (1, 2) => "optical band".to_string(),
        (b, _) => format!("optical band {b}"),
    }
}
