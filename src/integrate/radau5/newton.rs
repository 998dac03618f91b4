//! The Newton iteration of Radau IIA on the transformed stage system (Hairer & Wanner,
//! *Solving ODEs II*, IV.8: simplified Newton with the eigen-decomposition `T`, `TI` of the
//! Radau matrix), the stage predictor from the last collocation polynomial, and the dissipated
//! energy as one more stage component.

use super::{
    linear, Radau5, C, E, MU_COMPLEX, MU_REAL, NEGLIGIBLE_NEWTON, NEWTON_MAXITER, RADAU_A,
    ROUNDING_NEWTON, T, TI,
};
use crate::integrate::{DissipationWeight, System, Tolerances};
use num_complex::Complex64;

impl Radau5 {
    /// Newton iteration for the collocation system; returns (converged, iterations, rate).
    pub(super) fn newton(&mut self, sys: &dyn System, h: f64) -> (bool, usize, f64) {
        let mass = sys.mass();
        let cr = MU_REAL / h;
        let cc = Complex64::new(MU_COMPLEX.0, MU_COMPLEX.1) / h;
        self.newton_start();
        let mut dw_norm_old: Option<f64> = None;
        let mut rate = f64::NAN;
        for it in 0..NEWTON_MAXITER {
            self.stats.newton_iters += 1;
            if !self.transformed_residual(sys, cr, cc) {
                return (false, it + 1, rate);
            }
            let kv = Self::kv_of(sys, &self.st.kv);
            let [d0s, d1s, d2s] = &mut self.dw;
            linear::solve_real(&mut *self.real, mass, kv, cr, d0s);
            linear::solve_complex(&mut *self.cplx, mass, kv, cc, d1s, d2s, &mut self.rhs_c);
            let dw_norm = self.increment_norm();
            if let Some(old) = dw_norm_old {
                rate = dw_norm / old;
            }
            // An increment far below the Newton tolerance is converged whatever the ratio of
            // two such increments says: near rounding level that ratio is noise (≈ 1) and would
            // be read as divergence, cutting the step down to nothing (Hairer's RADAU5 avoids
            // this with its carried-over FACCON; this is the stateless equivalent).
            let mut negligible = dw_norm <= NEGLIGIBLE_NEWTON * self.newton_tol;
            let diverging = !negligible
                && rate.is_finite()
                && (rate >= 1.0
                    || rate.powi((NEWTON_MAXITER - it) as i32) / (1.0 - rate) * dw_norm
                        > self.newton_tol);
            if diverging {
                // only then: an increment at the rounding level of the state is converged too
                // (checked here, off the path of iterations that converge anyway)
                negligible = dw_norm.is_finite() && self.increment_is_rounding();
                if !negligible {
                    return (false, it + 1, rate);
                }
            }
            if !dw_norm.is_finite() {
                return (false, it + 1, rate);
            }
            self.apply_increment();
            if negligible
                || dw_norm == 0.0
                || (rate.is_finite() && rate / (1.0 - rate) * dw_norm < self.newton_tol)
            {
                return (true, it + 1, rate);
            }
            dw_norm_old = Some(dw_norm);
        }
        (false, NEWTON_MAXITER, rate)
    }

    /// The transformed stages `W = TI · Z`, and the inverses of the Newton-increment weights
    /// (those of the step start).
    fn newton_start(&mut self) {
        let n = 2 * self.m;
        let m = self.m;
        for j in 0..n {
            let z0 = self.zs[0][j];
            let z1 = self.zs[1][j];
            let z2 = self.zs[2][j];
            for i in 0..3 {
                self.w[i][j] = TI[i][0] * z0 + TI[i][1] * z1 + TI[i][2] * z2;
            }
        }
        for j in 0..m {
            self.inv_w[j] = 1.0 / self.tol.weight_u(self.st.z[j], self.st.z[j]);
        }
        for j in m..n {
            self.inv_w[j] = 1.0
                / self
                    .tol
                    .weight_v(self.vs[j - m], self.st.z[j], self.st.z[j]);
        }
    }

    /// The right-hand sides of the transformed system at the current stages, into `dw`
    /// (`TI·F(Z) − c·W`, the complex pair as `(re, im)`); `false` if a stage force is not finite.
    fn transformed_residual(&mut self, sys: &dyn System, cr: f64, cc: Complex64) -> bool {
        let n = 2 * self.m;
        let m = self.m;
        for i in 0..3 {
            for ((y, z), d) in self.ytmp.iter_mut().zip(&self.st.z).zip(&self.zs[i]) {
                *y = z + d;
            }
            Self::rhs(sys, m, &self.ytmp, &mut self.fs[i], &mut self.stats);
        }
        let [f0s, f1s, f2s] = &self.fs;
        let [w0s, w1s, w2s] = &self.w;
        let [d0s, d1s, d2s] = &mut self.dw;
        let mut finite = true;
        for j in 0..n {
            let (f0, f1, f2) = (f0s[j], f1s[j], f2s[j]);
            finite &= f0.is_finite() && f1.is_finite() && f2.is_finite();
            d0s[j] = TI[0][0] * f0 + TI[0][1] * f1 + TI[0][2] * f2 - cr * w0s[j];
            let fr = TI[1][0] * f0 + TI[1][1] * f1 + TI[1][2] * f2;
            let fi = TI[2][0] * f0 + TI[2][1] * f1 + TI[2][2] * f2;
            // (fr + i fi) − cc (W1 + i W2)
            let w = Complex64::new(w1s[j], w2s[j]);
            let r = Complex64::new(fr, fi) - cc * w;
            d1s[j] = r.re;
            d2s[j] = r.im;
        }
        finite
    }

    /// Weighted max norm of the Newton increment `dw` (infinite if any component is NaN).
    fn increment_norm(&self) -> f64 {
        let mut dw_norm: f64 = 0.0;
        for d in &self.dw {
            for (x, iw) in d.iter().zip(&self.inv_w) {
                let e = (x * iw).abs();
                dw_norm = if e.is_nan() {
                    f64::INFINITY
                } else {
                    dw_norm.max(e)
                };
            }
        }
        dw_norm
    }

    /// Whether the increment is negligible once the components at the rounding level of the
    /// state they move (`|ΔW| ≤ ROUNDING_NEWTON·ε·|z|`) are left out. A cluster integrated in
    /// its centre-of-mass frame stores a bead at rest in the lab as `−V`, whose rounding
    /// (`ε·|V|`) can exceed its error weight's `atol` part many times: such an increment is
    /// noise, not divergence (`hybrid_overdamped_contact_is_integrated_like_dense`).
    fn increment_is_rounding(&self) -> bool {
        let n = 2 * self.m;
        let bound = NEGLIGIBLE_NEWTON * self.newton_tol;
        self.dw.iter().all(|d| {
            (0..n).all(|j| {
                d[j].abs() <= ROUNDING_NEWTON * f64::EPSILON * self.st.z[j].abs()
                    || (d[j] * self.inv_w[j]).abs() <= bound
            })
        })
    }

    /// `W += dW` and the stages `Z = T · W`.
    fn apply_increment(&mut self) {
        let n = 2 * self.m;
        let [d0s, d1s, d2s] = &self.dw;
        let [w0s, w1s, w2s] = &mut self.w;
        let [z0s, z1s, z2s] = &mut self.zs;
        for j in 0..n {
            let w0 = w0s[j] + d0s[j];
            let w1 = w1s[j] + d1s[j];
            let w2 = w2s[j] + d2s[j];
            w0s[j] = w0;
            w1s[j] = w1;
            w2s[j] = w2;
            z0s[j] = T[0][0] * w0 + T[0][1] * w1 + T[0][2] * w2;
            z1s[j] = T[1][0] * w0 + T[1][1] * w1 + T[1][2] * w2;
            z2s[j] = T[2][0] * w0 + T[2][1] * w1 + T[2][2] * w2;
        }
    }

    /// The dissipated energy `E_d` as one more (error-controlled) state component, over the
    /// step of size `h` whose converged stages are in `zs`: its stage increments
    /// `D_i = h Σ_j a_ij P_j` (`P_j` the power at the stages; `D_3` is the Radau quadrature of
    /// order 5) and its error estimate `(P_0 + Σ e_i D_i / h)/(μ_r/h)` (the filter of the state's
    /// estimate, with `∂P/∂z` neglected as in the simplified Newton). Returns `(D_3, weighted
    /// error)`. Inside a step the clipped force can vanish while the power does not
    /// (`P = −F_el δ̇`), which the state's error estimate cannot see.
    pub(super) fn dissipation_error(&mut self, sys: &dyn System, h: f64, cr: f64) -> (f64, f64) {
        let m = self.m;
        for i in 0..3 {
            for ((y, z), d) in self.ytmp_d.iter_mut().zip(&self.st.z).zip(&self.zs[i]) {
                *y = z + d;
            }
            let (u, v) = self.ytmp_d.split_at(m);
            self.ps[i] = sys.accel(u, v, &mut self.acc);
        }
        let d: [f64; 3] =
            std::array::from_fn(|i| h * (0..3).map(|j| RADAU_A[i][j] * self.ps[j]).sum::<f64>());
        let err = (self.st.p0 + (E[0] * d[0] + E[1] * d[1] + E[2] * d[2]) / h) / cr;
        // relative to E_d since the reset whatever the run asks of DOP853: this estimate keeps
        // the balance within 1.2·rtol of E_0 in the dense engine too (40 damped beads, rtol
        // 1e-6 … 1e-12), and the step's increment would cost 40 % more steps there
        let tol = Tolerances {
            dissipation: DissipationWeight::SinceReset,
            ..self.tol
        };
        let w = tol.weight_e(self.diss.1, self.diss.1 + d[2]);
        (d[2], (err / w).abs())
    }

    /// Initial guess of the stages from the previous step's collocation polynomial.
    pub(super) fn predict_stages(&mut self, h: f64) {
        let n = 2 * self.m;
        if !self.st.have_sol {
            for zi in self.zs.iter_mut() {
                zi.fill(0.0);
            }
            return;
        }
        let h_prev = self.t - self.t_old;
        for i in 0..3 {
            let x = (self.t + h * C[i] - self.t_old) / h_prev;
            let (x1, x2, x3) = (x, x * x, x * x * x);
            for j in 0..n {
                let y = self.st.z_old[j]
                    + self.st.q[0][j] * x1
                    + self.st.q[1][j] * x2
                    + self.st.q[2][j] * x3;
                self.zs[i][j] = y - self.st.z[j];
            }
        }
    }
}
