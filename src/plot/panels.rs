//! Side-by-side space–time maps (issue 14: the paper's multi-panel figures, e.g. Figs. 10, 11, 13, 14):
//! `beadchain plot spacetime A.snap B.snap …` draws one panel per snapshot in a row, with one
//! **shared colour scale**: every panel is normalised by the largest `|v|` over all panels (in
//! the axis units), and a single colour bar right of the last panel states it. Each panel keeps
//! its own bead and time axes (the same `--beads`/`--t` selection applies to every snapshot).
//! All panels have plot areas of equal size: the last panel is wider by the colour-bar strip.
//! An optional figure title (`--title`) is drawn in a strip above the panels.

use super::layout::{Layout, COLORBAR_STRIP};
use super::spacetime::{Spacetime, SpacetimeOptions};
use super::{de, font::FAMILY, DrawError, Figure, PlotError};
use crate::snapshot::Snapshot;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Height of the figure-title strip above the panels.
pub const TITLE_STRIP: u32 = 34;

/// Narrowest panel, in pixels.
pub const MIN_PANEL: u32 = 200;

/// A row of space–time maps sharing one colour scale.
#[derive(Clone, Debug, PartialEq)]
pub struct Panels {
    /// The panels, left to right (each sized to its column).
    pub panels: Vec<Spacetime>,
    /// Figure title above the panels.
    pub title: Option<String>,
    /// Image size.
    pub size: (u32, u32),
}

/// Column widths of `n` panels in `w` pixels: equal plot areas, the last column wider by the
/// colour-bar strip (the few pixels of the rounding stay blank at the right).
pub fn widths(w: u32, n: usize) -> Vec<u32> {
    let n = n.max(1) as u32;
    let extra = COLORBAR_STRIP - Layout::new((w, 1), false).right;
    let base = w.saturating_sub(extra) / n;
    let mut v = vec![base; n as usize];
    v[n as usize - 1] = base + extra;
    v
}

impl Panels {
    /// One panel per snapshot with the options `opts` (its `size` is the whole figure's).
    pub fn from_snapshots(
        snaps: &[Snapshot],
        opts: &SpacetimeOptions,
        title: Option<String>,
    ) -> Result<Self, PlotError> {
        let (w, h) = opts.size;
        let n = snaps.len();
        if n == 0 || w / (n as u32) < MIN_PANEL {
            return Err(PlotError::Input(format!(
                "--width {w}: too narrow for {n} panels (at least {MIN_PANEL} px each)"
            )));
        }
        let ph = h - if title.is_some() { TITLE_STRIP } else { 0 };
        let ws = widths(w, n);
        let mut panels = Vec::with_capacity(n);
        for (k, snap) in snaps.iter().enumerate() {
            let o = SpacetimeOptions {
                size: (ws[k], ph),
                colorbar: k + 1 == n,
                ..opts.clone()
            };
            let mut p = Spacetime::from_snapshot(snap, &o)?;
            let file = snap
                .path()
                .file_name()
                .map_or(String::new(), |f| f.to_string_lossy().into_owned());
            p.title = format!("{file}: {}", snap.header().scene.name);
            panels.push(p);
        }
        let vmax = panels.iter().fold(0.0f64, |m, p| m.max(p.vmax));
        for p in &mut panels {
            p.vmax = vmax;
        }
        if let Some(last) = panels.last_mut() {
            last.bar_desc = format!("{}\nall panels", last.bar_desc);
        }
        Ok(Panels {
            panels,
            title,
            size: opts.size,
        })
    }
}

impl Figure for Panels {
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
        let body = match &self.title {
            Some(t) => {
                let (top, body) = root.split_vertically(TITLE_STRIP);
                if text {
                    let style = TextStyle::from((FAMILY, 20).into_font())
                        .pos(Pos::new(HPos::Center, VPos::Center))
                        .color(&BLACK);
                    let c = (self.size.0 as i32 / 2, TITLE_STRIP as i32 / 2 + 2);
                    top.draw(&Text::new(t.clone(), c, style)).map_err(de)?;
                }
                body
            }
            None => root.clone(),
        };
        let mut rest = body;
        for p in &self.panels {
            let (area, right) = rest.split_horizontally(p.size.0);
            p.draw(&area, text)?;
            rest = right;
        }
        Ok(())
    }
}
