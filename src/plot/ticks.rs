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

use plotters::coord::ranged1d::Ranged;
use plotters::coord::types::RangedCoordf64;

/// Most tick labels plotters is asked for on a linear axis.
pub const N_LABELS: usize = 10;

/// A tick within `ZERO_SNAP · span` of zero is zero.
pub const ZERO_SNAP: f64 = 1e-12;

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
    fn decades() {
        assert_eq!(log_decades(-7.6, -2.3), ((-8.0, -2.0), 7));
        assert_eq!(log_decades(-1.0, -1.0), ((-2.0, 0.0), 3));
        assert_eq!(log_decades(-40.2, 0.5).1, N_LABELS);
        assert_eq!(decade_label(-8.0), "1e-8");
        assert_eq!(decade_label(-2.0), "0.01");
        assert_eq!(decade_label(2.0), "100");
    }
}
