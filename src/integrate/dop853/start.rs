//! Hairer's starting step of [`Dop853`] (HNW I, II.4, p. 169; SciPy `select_initial_step`),
//! made dimensionless with the run's time scale (module docs of [`super`]).

use super::{rhs, Dop853, System, ERROR_EXPONENT};

impl Dop853 {
    /// Time scale for the dimensionless initial-step heuristic.
    pub(super) fn time_scale(&self) -> f64 {
        let t = self.tol.scales.time();
        if t.is_finite() && t > 0.0 {
            t
        } else {
            1.0
        }
    }

    /// Hairer's starting step (SciPy `select_initial_step`, order 7), in max norms and units of
    /// the time scale. Needs `k[0] = f(z)`; uses stage 1 and `y` as scratch.
    pub(super) fn initial_step(&mut self, sys: &dyn System) -> f64 {
        let n = 2 * self.m;
        let ts = self.time_scale();
        let (mut d0, mut d1) = (0.0_f64, 0.0_f64);
        for i in 0..n {
            let sc = self.weight(i, self.st.z[i], self.st.z[i]);
            d0 = d0.max((self.st.z[i] / sc).abs());
            d1 = d1.max((self.st.k[i] / sc).abs());
        }
        d1 *= ts;
        let h0 = if d0 < 1e-5 || d1 < 1e-5 || !(d0 / d1).is_finite() {
            1e-6
        } else {
            0.01 * d0 / d1
        };
        for i in 0..n {
            self.y[i] = self.st.z[i] + h0 * ts * self.st.k[i];
        }
        rhs(sys, &mut self.stats, &self.y, &mut self.st.k[n..2 * n]);
        let mut d2 = 0.0_f64;
        for i in 0..n {
            let sc = self.weight(i, self.st.z[i], self.st.z[i]);
            d2 = d2.max(((self.st.k[n + i] - self.st.k[i]) / sc).abs());
        }
        d2 *= ts / h0;
        let h1 = if d1 <= 1e-15 && d2 <= 1e-15 {
            (h0 * 1e-3).max(1e-6)
        } else {
            (0.01 / d1.max(d2)).powf(-ERROR_EXPONENT)
        };
        let h = ts * (100.0 * h0).min(h1);
        if h.is_finite() && h > 0.0 {
            h
        } else {
            1e-6 * ts
        }
    }
}
