//! Analytic free flight and gap-closing prediction between free beads.
//!
//! A bead that touches nothing moves under its constant field only (paper eq. 7 with both contact
//! terms zero): `u(t) = u₀ + v₀ s + ½ g s²`, `s = t − t₀`, `g = W/m`. The gap function of a
//! contact between two free beads (or a free bead and a wall) is then a quadratic in time, and
//! its first upward crossing of the contact threshold is found with a cancellation-free root
//! formula.

/// Free-flight state of one bead, valid for `t ≥ t0`.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Free {
    /// Reference time.
    pub t0: f64,
    /// Displacement at `t0`.
    pub u0: f64,
    /// Velocity at `t0`.
    pub v0: f64,
    /// Constant acceleration `W/m` (0 without a field).
    pub g: f64,
}

impl Free {
    /// Displacement and velocity at `t`.
    #[inline]
    pub fn at(&self, t: f64) -> (f64, f64) {
        let s = t - self.t0;
        (
            self.u0 + s * (self.v0 + 0.5 * self.g * s),
            self.v0 + self.g * s,
        )
    }
}

/// First `s ≥ 0` at which `q(s) = a + b s + ½ c s²` crosses `0` upward, given `a ≤ 0`
/// (a gap that is open or exactly at the threshold). `None` when it never does.
///
/// Uses `q = −½ (b + sign(b) √disc)` and the pair of roots `q/(c/2)`, `a/q`, which loses no
/// digits to cancellation (Numerical Recipes §5.6).
pub fn first_upward_crossing(a: f64, b: f64, c: f64) -> Option<f64> {
    if a > 0.0 {
        return Some(0.0);
    }
    let half_c = 0.5 * c;
    if half_c == 0.0 {
        return if b > 0.0 { Some(-a / b) } else { None };
    }
    let disc = b * b - 4.0 * half_c * a;
    if disc < 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    let q = -0.5 * (b + b.signum() * sq);
    let mut best: Option<f64> = None;
    let mut consider = |s: f64| {
        let slope = b + c * s;
        if s.is_finite() && s >= 0.0 && (slope > 0.0 || (slope == 0.0 && c > 0.0)) {
            best = Some(best.map_or(s, |x: f64| x.min(s)));
        }
    };
    if q != 0.0 {
        consider(q / half_c);
        consider(a / q);
    } else {
        consider(0.0);
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_closing() {
        // gap −1 closing at speed 2 → s = 0.5 (abs tol 1e-15)
        let s = first_upward_crossing(-1.0, 2.0, 0.0).expect("closes");
        assert!((s - 0.5).abs() < 1e-15);
        assert_eq!(first_upward_crossing(-1.0, -2.0, 0.0), None);
    }

    #[test]
    fn quadratic_closing_under_relative_acceleration() {
        // −1 + 0 s + ½·2 s² = 0 → s = 1 (abs tol 1e-15)
        let s = first_upward_crossing(-1.0, 0.0, 2.0).expect("closes");
        assert!((s - 1.0).abs() < 1e-15);
        // receding then pulled back: −1 − s + s² → s = (1+√5)/2
        let s = first_upward_crossing(-1.0, -1.0, 2.0).expect("closes");
        assert!((s - 0.5 * (1.0 + 5f64.sqrt())).abs() < 1e-14);
        // decelerating approach that turns before touching
        assert_eq!(first_upward_crossing(-1.0, 1.0, -2.0), None);
    }

    #[test]
    fn touching_pairs() {
        // touching, at rest, pulled apart or nothing: never
        assert_eq!(first_upward_crossing(0.0, 0.0, -1.0), None);
        assert_eq!(first_upward_crossing(0.0, 0.0, 0.0), None);
        // touching, at rest, pushed together: now
        assert_eq!(first_upward_crossing(0.0, 0.0, 1.0), Some(0.0));
        // touching, separating, pushed back: at s = −2b/c = 2
        let s = first_upward_crossing(0.0, -1.0, 1.0).expect("returns");
        assert!((s - 2.0).abs() < 1e-15);
    }

    #[test]
    fn tiny_relative_speed_has_no_cancellation() {
        // gap −1e-20 with relative speed 1e-12 and a large deceleration term
        let s = first_upward_crossing(-1e-20, 1e-12, -1e-30).expect("closes");
        let expect = 1e-8;
        assert!((s - expect).abs() <= 1e-12 * expect, "{s}");
    }
}
