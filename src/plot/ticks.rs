//! Readable tick labels (issue 14).
//!
//! **Linear axes.** plotters picks the tick values itself (multiples of 1, 2 or 5 × 10^k, at most
//! [`N_LABELS`] of them); [`TickFmt::axis`] asks plotters' own key-point search for the same
//! values, so the labels can be formatted *together*: a value within [`ZERO_SNAP`] of the axis
//! span is 0 (summing steps of 0.1 gives `-1.1e-16`, never printed as such), and the precision is
//! the smallest that makes every label distinct and within `1e-9 · span` of its value. Fixed
//! decimals are used for magnitudes in `[1e-3, 1e6)`, else `m.mme±k` with a common mantissa
//! precision (`1.5e-7`, `2.0e-7`).
//!
//! **Logarithmic axes** are drawn as `log₁₀ y` on a linear axis ([`log_decades`]): the range
//! is widened to whole decades and plotters is asked for as many labels as there are decades (at
//! most [`N_LABELS`]), so its key points are integers and every tick is a decade (`1e-8`, `1e-6`,
//! …; `0.01` … `1000` written plainly).
//!
//! **Colour bars** ([`colorbar_ticks`]) are ticked at round values too: multiples of a step
//! `{1, 2, 5} · 10^k` inside the coloured range (3 to [`N_BAR_TICKS`] of them), placed where
//! their value lies on the bar; a log-coloured bar at decades, or at `{1, 2, 5} · 10^k` when it
//! spans less than a decade or two.

use plotters::coord::ranged1d::Ranged;
use plotters::coord::types::RangedCoordf64;

/// Most tick labels plotters is asked for on a linear axis.
pub const N_LABELS: usize = 10;

/// A tick within `ZERO_SNAP · span` of zero is zero.
pub const ZERO_SNAP: f64 = 1e-12;

/// Most ticks on a colour bar.
pub const N_BAR_TICKS: usize = 7;

/// The finest step `{1, 2, 5} · 10^k` that puts at most `max` multiples in `lo..=hi`
/// (`hi > lo`, both finite).
pub fn nice_step(lo: f64, hi: f64, max: usize) -> f64 {
    let span = hi - lo;
    let k0 = (span / max.max(1) as f64).log10().floor() as i32 - 1;
    // at most 3 decades above the first guess (one suffices; the bound only guards odd input)
    for k in k0..=k0.saturating_add(3) {
        for m in [1.0, 2.0, 5.0] {
            let step = m * 10f64.powi(k);
            let (a, b) = bounds(lo, hi, step);
            if b - a + 1.0 <= max as f64 {
                return step;
            }
        }
    }
    span
}

/// The multiples `j · step` in `lo..=hi` (relative slack `1e-9` of the span at both ends), each
/// computed as one product so that it prints round.
fn multiples(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let (a, b) = bounds(lo, hi, step);
    if !(a.is_finite() && b.is_finite()) || b < a || b - a > 1e6 {
        return vec![];
    }
    (a as i64..=b as i64).map(|j| j as f64 * step).collect()
}

/// The first and last `j` with `j · step` in `lo..=hi` (slack as in [`multiples`]).
fn bounds(lo: f64, hi: f64, step: f64) -> (f64, f64) {
    let slack = 1e-9 * (hi - lo);
    (((lo - slack) / step).ceil(), ((hi + slack) / step).floor())
}

/// Round ticks of a colour bar over the coloured range `lo..hi`: `(s, value)` with `s ∈ [0, 1]`
/// the place on the bar (0 at `lo`). With `log`, `lo..hi` is a `log₁₀` range and the values
/// are those of `z` itself (decades; within a short range `{1, 2, 5} · 10^k`, else round values
/// of `z` on the log scale). A zero-width range gives one tick at the middle.
pub fn colorbar_ticks(lo: f64, hi: f64, log: bool) -> Vec<(f64, f64)> {
    if !(lo.is_finite() && hi.is_finite()) || hi <= lo {
        let v = if log { 10f64.powf(lo) } else { lo };
        return vec![(0.5, v)];
    }
    if !(hi - lo).is_finite() {
        // a range wider than f64 (±1e308): its ends and middle, unrounded
        return vec![(0.0, lo), (0.5, lo / 2.0 + hi / 2.0), (1.0, hi)];
    }
    let place = |v: f64| {
        let x = if log { v.log10() } else { v };
        ((x - lo) / (hi - lo)).clamp(0.0, 1.0)
    };
    let values = if !log {
        multiples(lo, hi, nice_step(lo, hi, N_BAR_TICKS))
    } else {
        log_bar_values(lo, hi)
    };
    values.into_iter().map(|v| (place(v), v)).collect()
}

/// The values of a log colour bar over `log₁₀ z ∈ lo..hi`: every `d`-th decade (`d` in 1, 2,
/// 5, 10, …, at most [`N_BAR_TICKS`]); with fewer than 3 decades inside, `{1, 2, 5} · 10^k`;
/// with fewer than 2 of those, round values of `z` itself.
fn log_bar_values(lo: f64, hi: f64) -> Vec<f64> {
    let inside = |v: &f64| {
        let x = v.log10();
        x >= lo - 1e-9 && x <= hi + 1e-9
    };
    let decades = multiples(lo, hi, nice_step(lo, hi, N_BAR_TICKS).max(1.0));
    if decades.len() >= 3 {
        return decades.iter().map(|&k| 10f64.powi(k as i32)).collect();
    }
    let mut v: Vec<f64> = ((lo.floor() as i32)..=(hi.ceil() as i32))
        .flat_map(|k| [1.0, 2.0, 5.0].map(|m| m * 10f64.powi(k)))
        .filter(inside)
        .collect();
    if v.len() < 2 {
        let (a, b) = (10f64.powf(lo), 10f64.powf(hi));
        v = multiples(a, b, nice_step(a, b, N_BAR_TICKS));
        v.retain(|x| *x > 0.0 && inside(x));
    }
    v
}

/// A common format for a set of tick values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TickFmt {
    /// Scientific notation (else fixed decimals).
    sci: bool,
    /// Decimals (fixed) or mantissa decimals (scientific).
    prec: usize,
    /// Values below `ZERO_SNAP · span` in magnitude are printed `0`.
    snap: f64,
}

impl TickFmt {
    /// The format of the ticks plotters draws on an axis `lo..hi` asked for `n` labels.
    pub fn axis(lo: f64, hi: f64, n: usize) -> Self {
        let ticks = if lo.is_finite() && hi.is_finite() && hi > lo {
            RangedCoordf64::from(lo..hi).key_points(n)
        } else {
            vec![lo, hi]
        };
        Self::for_values(&ticks, (hi - lo).abs(), 1e-9)
    }

    /// The shortest common format that tells `values` apart (an axis of extent `span`), each
    /// label within `tol · span` of its value (`1e-9` for axis ticks, which are round numbers;
    /// `1e-3` for colour-bar values, which need not be).
    pub fn for_values(values: &[f64], span: f64, tol: f64) -> Self {
        let span = if span.is_finite() && span > 0.0 {
            span
        } else {
            values
                .iter()
                .fold(0.0f64, |m, v| m.max(v.abs()))
                .max(1e-300)
        };
        let snap = ZERO_SNAP * span;
        let vals: Vec<f64> = values
            .iter()
            .filter(|v| v.is_finite())
            .map(|&v| if v.abs() < snap { 0.0 } else { v })
            .collect();
        let big = vals.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let sci = big != 0.0 && !(1e-3..1e6).contains(&big);
        for prec in 0..=15 {
            let f = TickFmt { sci, prec, snap };
            let labels: Vec<String> = vals.iter().map(|&v| f.label(v)).collect();
            let exact = vals
                .iter()
                .zip(&labels)
                .all(|(v, l)| l.parse::<f64>().is_ok_and(|p| (p - v).abs() <= tol * span));
            let mut sorted = labels.clone();
            sorted.sort();
            sorted.dedup();
            if exact && sorted.len() == labels.len() {
                return f;
            }
        }
        TickFmt {
            sci,
            prec: 15,
            snap,
        }
    }

    /// The label of `x`.
    pub fn label(&self, x: f64) -> String {
        if x.abs() < self.snap || x == 0.0 {
            return "0".into();
        }
        let p = self.prec;
        let s = if self.sci {
            format!("{x:.p$e}")
        } else {
            format!("{x:.p$}")
        };
        // a value that rounds to zero (a colour bar's -1e-6 at 3 decimals) is `0`, not `-0.000`
        if s.parse::<f64>() == Ok(0.0) {
            "0".into()
        } else {
            s
        }
    }
}

/// The decade range `(floor(lo), ceil(hi))` of a `log₁₀` axis (at least one decade wide) and
/// the number of labels that makes plotters tick whole decades only.
pub fn log_decades(lo: f64, hi: f64) -> ((f64, f64), usize) {
    let (mut a, mut b) = (lo.floor(), hi.ceil());
    if !(a.is_finite() && b.is_finite()) {
        return ((0.0, 1.0), 2);
    }
    if b <= a {
        a -= 1.0;
        b += 1.0;
    }
    let count = (b - a) as usize + 1;
    ((a, b), count.clamp(2, N_LABELS))
}

/// The label of the decade `10^k` for a `log₁₀` value `k` (rounded): `0.01` … `1000` plainly,
/// `1e-8`, `1e6` otherwise.
pub fn decade_label(k: f64) -> String {
    let k = k.round() as i32;
    match k {
        -2..=-1 => format!("{}", 10f64.powi(k)),
        0..=3 => format!("{}", 10i64.pow(k as u32)),
        _ => format!("1e{k}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shortest_distinct_labels() {
        let f = TickFmt::for_values(&[-1.1e-16, 0.1, 0.2, 0.30000000000000004], 0.3, 1e-9);
        assert_eq!(f.label(-1.1e-16), "0");
        assert_eq!(f.label(0.30000000000000004), "0.3");
        let f = TickFmt::for_values(&[0.0, 2.5, 5.0, 7.5], 7.5, 1e-9);
        assert_eq!((f.label(2.5), f.label(5.0)), ("2.5".into(), "5.0".into()));
        let f = TickFmt::for_values(&[0.0, 2e-8, 4e-8, 6e-8], 6e-8, 1e-9);
        assert_eq!((f.label(0.0), f.label(4e-8)), ("0".into(), "4e-8".into()));
        let f = TickFmt::for_values(&[1.5e-7, 2e-7], 1e-7, 1e-9);
        assert_eq!(f.label(2e-7), "2.0e-7");
        let f = TickFmt::for_values(&[1000.0, 2000.0], 1e3, 1e-9);
        assert_eq!(f.label(2e3), "2000");
        // colour-bar values (not round): 0.1 % of the span
        let f = TickFmt::for_values(&[-0.109999998, 0.0, 0.054999999], 0.22, 1e-3);
        assert_eq!(f.label(-0.109999998), "-0.110");
        assert_eq!(f.label(-1e-6), "0");
    }

    #[test]
    fn colour_bar_steps() {
        assert_eq!(nice_step(0.001, 0.529, 7), 0.1);
        assert_eq!(nice_step(0.0, 0.798, 7), 0.2);
        assert_eq!(nice_step(-2.0, 2.0, 7), 1.0);
        let t = colorbar_ticks(0.001, 0.529, false);
        let v: Vec<f64> = t.iter().map(|p| p.1).collect();
        assert_eq!(v, vec![0.1, 0.2, 0.30000000000000004, 0.4, 0.5]);
        // log: decades 1e-6 … 0.1 of a bar over 1e-6 … 0.3
        let t = colorbar_ticks(-6.0, 0.3f64.log10(), true);
        assert_eq!(t.len(), 6);
        assert_eq!((t[0].0, t[0].1), (0.0, 1e-6));
        assert_eq!(colorbar_ticks(1.0, 1.0, false), vec![(0.5, 1.0)]);
        // wider than f64 (the ±1e308 of tests/input_bounds.rs): the ends, no endless search
        let t = colorbar_ticks(-1e308, 1e308, false);
        assert_eq!((t[0].1, t[2].1), (-1e308, 1e308));
        assert_eq!(nice_step(0.0, 1e-300, 7), 2e-301);
    }

    #[test]
    fn decades() {
        assert_eq!(log_decades(-7.6, -2.3), ((-8.0, -2.0), 7));
        assert_eq!(log_decades(-1.0, -1.0), ((-2.0, 0.0), 3));
        assert_eq!(log_decades(-40.2, 0.5).1, N_LABELS);
        assert_eq!(decade_label(-8.0), "1e-8");
        assert_eq!(decade_label(-2.0), "0.01");
        assert_eq!(decade_label(2.0), "100");
    }
}
