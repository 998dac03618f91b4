//! Locating gap closings on continuous output: sampling plus Illinois (modified regula falsi).
//!
//! A cluster step gives a polynomial trajectory over `[t_prev, t]`. The gap function of a
//! boundary contact, `g(t) = Δ + u_left(t) − u_right(t) − θ`, is sampled at [`SAMPLES`] points so
//! that a gap that closes and re-opens inside one step (grazing) is not missed at the sampling
//! resolution; the first sign change is then refined by the Illinois method (Dowell & Jarratt
//! 1971), which keeps a bracket and converges superlinearly.
//!
//! **Convex gaps.** Without a field and without hard contacts, the only force on the edge bead
//! of a cluster comes from its inner contact and is compressive (paper eq. 6: zero tensile
//! strength; the damped laws are clipped at 0 too), so it pushes the edge bead towards the gap;
//! the bead across the gap is free (no force) or the edge bead of another cluster (pushed
//! towards the gap likewise). So the boundary gap `g(t)` has `g'' ≥ 0` over the step: it cannot
//! close and re-open inside one, and [`first_crossing_convex`] needs its end values only.
//!
//! [`step_max`] finds the largest value of a function over one step from the sign change of its
//! derivative (both from the continuous output), refined the same way: the peak overlaps of the
//! event log.

/// Samples per window (the endpoints plus interior points).
pub const SAMPLES: usize = 8;

/// First `t ∈ [ta, tb]` where `g` becomes positive, given as the right end of a bracket refined
/// to a few ulps. `None` if `g ≤ 0` at every sample.
pub fn first_crossing(g: impl Fn(f64) -> f64, ta: f64, tb: f64) -> Option<f64> {
    sampled_crossing(g, ta, tb, SAMPLES)
}

/// [`first_crossing`] for a gap that is convex in time over the window (`g'' ≥ 0`, module
/// docs): it has no interior maximum, so `g ≤ 0` at both ends means `g ≤ 0` throughout, and a
/// sign change is bracketed by the window itself. Two evaluations instead of up to nine, and no
/// crossing is found where only the continuous output's own error would make one.
pub fn first_crossing_convex(g: impl Fn(f64) -> f64, ta: f64, tb: f64) -> Option<f64> {
    sampled_crossing(g, ta, tb, 1)
}

/// The first sign change of `g` over `samples` equal parts of `[ta, tb]`, refined by Illinois.
fn sampled_crossing(g: impl Fn(f64) -> f64, ta: f64, tb: f64, samples: usize) -> Option<f64> {
    if tb < ta {
        return None;
    }
    let ga = g(ta);
    if ga > 0.0 {
        return Some(ta);
    }
    if tb == ta {
        return None;
    }
    let mut a = ta;
    let mut fa = ga;
    for k in 1..=samples {
        let b = if k == samples {
            tb
        } else {
            ta + (tb - ta) * (k as f64 / samples as f64)
        };
        let fb = g(b);
        if fb > 0.0 {
            return Some(illinois(&g, a, fa, b, fb));
        }
        a = b;
        fa = fb;
    }
    None
}

/// Largest value of `d` over `[ta, tb]`, given its derivative `dd`, assuming `d` was already
/// accounted for at `ta` (the previous step's end): `d(tb)`, or the interior maximum where `dd`
/// changes sign from positive (at `ta`) to negative (at `tb`), located to a few ulps. At the
/// maximum `dd = 0`, so the located time's error enters the value only to second order.
pub fn step_max(d: impl Fn(f64) -> f64, dd: impl Fn(f64) -> f64, ta: f64, tb: f64) -> f64 {
    let end = d(tb);
    if tb <= ta {
        return end;
    }
    step_max_from(end, dd(ta), dd(tb), d, dd, ta, tb)
}

/// [`step_max`] given the end-point values it reads (`end = d(tb)`, `sa = dd(ta)`,
/// `sb = dd(tb)`), for a caller that has them already: `d` and `dd` are evaluated only to refine
/// an interior maximum.
pub fn step_max_from(
    end: f64,
    sa: f64,
    sb: f64,
    d: impl Fn(f64) -> f64,
    dd: impl Fn(f64) -> f64,
    ta: f64,
    tb: f64,
) -> f64 {
    if tb > ta && sa > 0.0 && sb < 0.0 {
        let neg = |t: f64| -dd(t);
        let tm = illinois(&neg, ta, -sa, tb, -sb);
        end.max(d(tm))
    } else {
        end
    }
}

/// Refines a bracket `f(a) ≤ 0 < f(b)`; returns a time where `f > 0`, within a few ulps of the
/// root.
fn illinois(f: &impl Fn(f64) -> f64, mut a: f64, mut fa: f64, mut b: f64, mut fb: f64) -> f64 {
    let mut side = 0i8;
    for _ in 0..100 {
        let width = b - a;
        if width <= 4.0 * f64::EPSILON * a.abs().max(b.abs()) || width <= f64::MIN_POSITIVE {
            break;
        }
        let mut c = (a * fb - b * fa) / (fb - fa);
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
        }
        let fc = f(c);
        if fc > 0.0 {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        } else {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_root_of_cubic_to_ulps() {
        let root = 0.3;
        let g = |t: f64| (t - root) * (1.0 + t * t);
        let t = first_crossing(g, 0.0, 1.0).expect("crossing");
        // abs tol: a few ulps of 0.3
        assert!((t - root).abs() < 1e-15, "{t}");
        assert!(g(t) > 0.0);
    }

    #[test]
    fn finds_grazing_crossing_between_endpoints() {
        // negative at both ends, positive on (0.475, 0.525), which holds the sample 0.5
        let g = |t: f64| 1e-3 - (t - 0.5) * (t - 0.5) * 1.6;
        let t = first_crossing(g, 0.0, 1.0).expect("grazing crossing found");
        // abs tol 1e-12 on the root 0.5 − 0.025
        assert!((t - (0.5 - (1e-3f64 / 1.6).sqrt())).abs() < 1e-12);
    }

    #[test]
    fn step_max_finds_interior_maximum() {
        // d = 1 − (t − 0.37)², maximum 1 at 0.37 inside [0, 1]
        let d = |t: f64| 1.0 - (t - 0.37) * (t - 0.37);
        let dd = |t: f64| -2.0 * (t - 0.37);
        let p = step_max(d, dd, 0.0, 1.0);
        // abs tol 1e-15 (relative to the maximum 1): the located time is within ulps
        assert!((p - 1.0).abs() < 1e-15, "{p}");
        // increasing over the step: the end value
        assert_eq!(step_max(d, dd, 0.0, 0.2), d(0.2));
    }

    #[test]
    fn convex_crossing_is_bracketed_by_the_window() {
        // convex, negative at 0, positive at 1: the one root 0.6 located to ulps
        let g = |t: f64| (t - 0.6) * (t + 2.0);
        let t = first_crossing_convex(g, 0.0, 1.0).expect("crossing");
        // abs tol: a few ulps of 0.6
        assert!((t - 0.6).abs() < 1e-15 && g(t) > 0.0, "{t}");
        // negative at both ends: no crossing (a convex gap has no interior maximum)
        assert_eq!(first_crossing_convex(|t: f64| t * t - 2.0, -1.0, 1.0), None);
        // open at the start: the start
        assert_eq!(first_crossing_convex(|t: f64| t + 1.0, 0.0, 1.0), Some(0.0));
    }

    #[test]
    fn no_crossing() {
        assert_eq!(first_crossing(|t| -1.0 - t, 0.0, 1.0), None);
    }
}
