//! Composite mass–exponent interfaces (paper Sec. 6, Figs. 24–25).
//!
//! Left medium: `n1 = 3.0`, Table 1 steel beads of mass `m1`; right medium: `n2 = n1 + Δn`
//! (contacts `k..`) and mass `m2` (beads `k + 1..`, by the density, so the Hertz prefactor of
//! eq. 3 keeps its sphere value — the convention of the `composite_mass_exponent` preset).
//! The paper scans `Δn ∈ [−0.5, 0.5]`, `m2/m1 ∈ [1/8, 8]` and shows the reflected energy with a
//! transition contour between reflecting and non-reflecting regions (for `Δn < 0`,
//! `m2/m1 < 1`), which it reads as the set where the right-hand quasi-particle's mass equals
//! `m1`.
//!
//! `E_refl` is measured as in the `(n1, n2)` grid of Fig. 7 ([`super::paper::reflection_grid`]):
//! the energy left of bead `k` ([`crate::analysis::energy_split`]) when the front (furthest bead above
//! 0.1 % of `max |v|`) has reached bead `N − 12` and at least the time the incoming wave needs
//! for `N − 12 − k` beads of the left medium has passed since it reached `k`, minus the same quantity for the uniform chain (the
//! striker's rebound). [`contour_crossings`] extracts where `E_refl` crosses a level along each
//! row of constant `Δn` (linear interpolation in `ln(m2/m1)`).

use super::paper::{time_per_bead, PaperError};
use super::periodic::run_observer;
use crate::analysis::interface::energy_split;
use crate::analysis::wave::{detect_pulses, wave_energy, WaveOptions};
use crate::analysis::window::front_bead;
use crate::engine::{Control, EngineError, Observer};
use crate::model::Chain;
use crate::scene::{self, Engine, Scene, SceneError};
use std::path::Path;

/// Density of the Table 1 steel beads (kg/m³).
const DENSITY: f64 = 7650.0;

/// A physical scene with exponent `n1` then `n2` from contact `k` and density scaled by
/// `mass_ratio` from bead `k + 1`.
pub fn composite_scene(
    n1: f64,
    n2: f64,
    mass_ratio: f64,
    beads: usize,
    k: usize,
    until: f64,
    every: f64,
) -> Result<Scene, SceneError> {
    let d2 = DENSITY * mass_ratio;
    let text = format!(
        "[scene]\nname = \"composite\"\n[units]\nsystem = \"physical\"\nradius = 4.0e-3\n\
         young = 2.26e11\npoisson = 0.3\ndensity = {{ base = {DENSITY:e}, segments = [{{ from = {}, value = {d2:e} }}] }}\n\
         n0 = 2.5\n[chain]\nbeads = {beads}\n\
         exponent = {{ base = {n1}, segments = [{{ from = {k}, value = {n2} }}] }}\n\
         [initial]\nstriker_si = 0.11\n[run]\nuntil = {until:e}\nevery = {every:e}\n",
        k + 1
    );
    scene::parse_str(&text, Path::new("."), "composite")
}

/// Observer: energy left of `k` at the stop frame and at 3/4 of the stop time after the hit,
/// the widest transmitted plateau; stops when the front has reached `stop_at` and at least
/// `wait` time units have passed since the front reached `k` (so light right-hand media, whose
/// fast waves reach the end early, do not stop while the interface still holds energy).
struct SplitWatch {
    chain: Chain,
    k: usize,
    wait: f64,
    stop_at: usize,
    t_hit: Option<f64>,
    history: Vec<(f64, f64)>,
    v_in: f64,
    last: f64,
    back: f64,
    plateau: usize,
    stop: bool,
}

impl Observer for SplitWatch {
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        let k = self.k;
        for &x in v.get(20.min(k)..k.saturating_sub(3)).unwrap_or(&[]) {
            self.v_in = self.v_in.max(x);
        }
        let sp = energy_split(&self.chain, u, v, k);
        self.last = sp.left / sp.total();
        self.back = detect_pulses(v, &WaveOptions::default())
            .iter()
            .filter(|p| p.peak_velocity < 0.0 && p.last < k)
            .map(|p| wave_energy(&self.chain, u, v, p.first, p.last))
            .sum::<f64>()
            / sp.total();
        let front = front_bead(v, 1e-3).unwrap_or(0);
        if self.t_hit.is_none() && front >= k {
            self.t_hit = Some(t);
        }
        self.history.push((t, self.last));
        // widest run of beads k..k+20 within 25 % of their (positive) max, while the front is
        // still within 25 beads of the interface (the collective quasi-particle of Sec. 3.3)
        if front > k && front <= k + 25 && k + 20 < v.len() {
            let top = v[k..k + 20].iter().cloned().fold(0.0, f64::max);
            if top > 0.05 * self.v_in {
                let (mut run, mut best) = (0, 0);
                for &x in &v[k..k + 20] {
                    run = if x >= 0.75 * top { run + 1 } else { 0 };
                    best = best.max(run);
                }
                self.plateau = self.plateau.max(best);
            }
        }
        if front >= self.stop_at && self.t_hit.is_some_and(|h| t >= h + self.wait) {
            self.stop = true;
        }
        Ok(())
    }
    fn control(&mut self, _t: f64) -> Control {
        Control::stop_if(self.stop)
    }
}

/// One grid point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompositeRow {
    /// `Δn = n2 − n1`.
    pub dn: f64,
    /// `m2/m1`.
    pub mass_ratio: f64,
    /// Energy left of bead `k` over the total at the stop frame.
    pub left_fraction: f64,
    /// `E_refl/E_in`: energy of the left-moving pulses left of `k` (eq. 13 over each pulse) over
    /// the total, minus that of the uniform chain (the striker's rebound).
    pub e_refl: f64,
    /// Energy of the left-moving pulses left of `k` over the total (before the subtraction).
    pub back_fraction: f64,
    /// `left_fraction` minus that of the uniform chain (includes slow forward-moving beads left
    /// behind at the interface, which are not reflected energy).
    pub left_excess: f64,
    /// `left_fraction` at the stop frame minus its value at 3/4 of the time from the hit of the
    /// interface to the stop (how settled the split is).
    pub settle: f64,
    /// Widest run of transmitted beads `k..k+20` moving within 25 % of their max.
    pub plateau: usize,
    /// Whether the front reached `N − 12` before the time limit.
    pub reached: bool,
    /// Wall time (s).
    pub seconds: f64,
}

/// One composite interface run (`beads` beads, interface bead `k`, `n1 = 3.0` unless given).
/// `e_refl` and `left_excess` are left unsubtracted (the caller subtracts the uniform chain's
/// values, see [`composite_grid`]).
pub fn composite_run(
    n1: f64,
    dn: f64,
    mass_ratio: f64,
    beads: usize,
    k: usize,
    engine: Engine,
) -> Result<CompositeRow, PaperError> {
    let n2 = n1 + dn;
    let tb1 = time_per_bead(n1)?;
    let tb2 = time_per_bead(n2)? * mass_ratio.sqrt();
    let every = tb1.min(tb2) / 4.0;
    // generous: the transmitted wave in a heavy medium is slower than the probe's (smaller
    // velocity); the front stop ends the run long before this in every case we ran
    let until = 2.0 * (k as f64 * tb1 + 4.0 * (beads - k) as f64 * tb2.max(tb1));
    let sc = composite_scene(n1, n2, mass_ratio, beads, k, until, every)?;
    let stop_at = beads.saturating_sub(12);
    let mut w = SplitWatch {
        chain: sc.chain.clone(),
        k,
        wait: stop_at.saturating_sub(k) as f64 * tb1,
        stop_at,
        t_hit: None,
        history: Vec::new(),
        v_in: 0.0,
        last: 0.0,
        back: 0.0,
        plateau: 0,
        stop: false,
    };
    let seconds = run_observer(&sc, engine, 1e-8, &mut w)?;
    let probe = match (w.t_hit, w.history.last()) {
        (Some(h), Some(&(te, _))) => w
            .history
            .iter()
            .find(|p| p.0 >= h + 0.75 * (te - h))
            .map_or(f64::NAN, |p| p.1),
        _ => f64::NAN,
    };
    Ok(CompositeRow {
        dn,
        mass_ratio,
        left_fraction: w.last,
        e_refl: w.back,
        back_fraction: w.back,
        left_excess: w.last,
        settle: w.last - probe,
        plateau: w.plateau,
        reached: w.stop,
        seconds,
    })
}

/// The grid `dns × ratios` with `n1 = 3.0`, `E_refl` relative to the uniform chain (which is run
/// first, also when `(0, 1)` is not in the grid).
pub fn composite_grid(
    dns: &[f64],
    ratios: &[f64],
    beads: usize,
    k: usize,
) -> Result<Vec<CompositeRow>, PaperError> {
    let base = composite_run(3.0, 0.0, 1.0, beads, k, Engine::Hybrid)?;
    let mut rows = Vec::with_capacity(dns.len() * ratios.len());
    for &dn in dns {
        for &r in ratios {
            let mut row = composite_run(3.0, dn, r, beads, k, Engine::Hybrid)?;
            row.e_refl = row.back_fraction - base.back_fraction;
            row.left_excess = row.left_fraction - base.left_fraction;
            rows.push(row);
        }
    }
    Ok(rows)
}

/// Where `e_refl` crosses `level` along each row of constant `dn`: `(dn, m2/m1)` by linear
/// interpolation of `e_refl` in `ln(m2/m1)` between neighbouring grid points (all crossings,
/// rows in the order met, ratios ascending).
pub fn contour_crossings(rows: &[CompositeRow], level: f64) -> Vec<(f64, f64)> {
    let mut dns: Vec<f64> = rows.iter().map(|r| r.dn).collect();
    dns.sort_by(f64::total_cmp);
    dns.dedup();
    let mut out = Vec::new();
    for dn in dns {
        let mut row: Vec<&CompositeRow> = rows.iter().filter(|r| r.dn == dn).collect();
        row.sort_by(|a, b| a.mass_ratio.total_cmp(&b.mass_ratio));
        for w in row.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (fa, fb) = (a.e_refl - level, b.e_refl - level);
            if fa == 0.0 {
                out.push((dn, a.mass_ratio));
            } else if fa * fb < 0.0 {
                let s = fa / (fa - fb);
                let (la, lb) = (a.mass_ratio.ln(), b.mass_ratio.ln());
                out.push((dn, (la + s * (lb - la)).exp()));
            }
        }
    }
    out
}

/// CSV of the grid (header
/// `dn,mass_ratio,e_refl,back_fraction,left_excess,left_fraction,settle,plateau,reached,seconds`).
pub fn grid_csv(rows: &[CompositeRow]) -> String {
    let mut s = String::from(
        "dn,mass_ratio,e_refl,back_fraction,left_excess,left_fraction,settle,plateau,reached,seconds\n",
    );
    for r in rows {
        s.push_str(&format!(
            "{},{:.6},{:.6e},{:.6e},{:.6e},{:.6e},{:.3e},{},{},{:.3}\n",
            r.dn,
            r.mass_ratio,
            r.e_refl,
            r.back_fraction,
            r.left_excess,
            r.left_fraction,
            r.settle,
            r.plateau,
            r.reached,
            r.seconds
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(dn: f64, r: f64, e: f64) -> CompositeRow {
        CompositeRow {
            dn,
            mass_ratio: r,
            left_fraction: e,
            e_refl: e,
            back_fraction: e,
            left_excess: e,
            settle: 0.0,
            plateau: 0,
            reached: true,
            seconds: 0.0,
        }
    }

    #[test]
    fn crossings_interpolate_in_log_ratio() {
        // row dn = −0.5: e = 0 at r = 1/4, 0.2 at r = 1 → level 0.1 halfway in ln r: r = 1/2
        // row dn = 0.5: never reaches 0.1 → no crossing (exact arithmetic, abs 1e-12)
        let rows = [
            row(-0.5, 1.0, 0.2),
            row(-0.5, 0.25, 0.0),
            row(0.5, 0.25, 0.0),
            row(0.5, 1.0, 0.05),
        ];
        let c = contour_crossings(&rows, 0.1);
        assert_eq!(c.len(), 1, "{c:?}");
        assert_eq!(c[0].0, -0.5);
        assert!((c[0].1 - 0.5).abs() < 1e-12, "{c:?}");
        let csv = grid_csv(&rows);
        assert!(csv.starts_with("dn,mass_ratio,e_refl,"));
        assert_eq!(csv.lines().count(), 5);
    }
}
