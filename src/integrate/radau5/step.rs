//! The two halves of a Radau IIA step after Newton converged (Hairer & Wanner, *Solving ODEs
//! II*, IV.8): the embedded error estimate `err = (μ_r/h I − J)⁻¹ (f + Σ E_i Z_i / h)`, with
//! Hairer's second estimate after a rejection and the dissipated energy's own error, and the
//! advance of an accepted step (collocation polynomial `Q = Zᵀ P` for dense output, the new
//! state, `F` and the contact stiffnesses at the new point).

use super::{linear, Radau5, E, MU_REAL, P};
use crate::integrate::System;

impl Radau5 {
    /// The scaled error norm of the step of size `h` just solved (`ytmp` = the new state), and
    /// the energy dissipated over it (0 for a conservative system).
    pub(super) fn error_estimate(
        &mut self,
        sys: &dyn System,
        h: f64,
        rejected: bool,
    ) -> (f64, f64) {
        let n = 2 * self.m;
        let m = self.m;
        // y_new = y + Z_3; error estimate (I·μ_r/h − J)⁻¹ (f + ZE)
        for j in 0..n {
            self.ytmp[j] = self.st.z[j] + self.zs[2][j];
            let ze = (E[0] * self.zs[0][j] + E[1] * self.zs[1][j] + E[2] * self.zs[2][j]) / h;
            self.err[j] = self.st.f[j] + ze;
        }
        let mass = sys.mass();
        let cr = MU_REAL / h;
        linear::solve_real(
            &mut *self.real,
            mass,
            Self::kv_of(sys, &self.st.kv),
            cr,
            &mut self.err,
        );
        let mut err_norm = self.weights_norm(&self.err, &self.st.z, &self.ytmp);
        if rejected && err_norm > 1.0 {
            // Hairer's second error estimate after a rejection: err = (..)⁻¹(F(y+err) + ZE).
            let mut tmp = std::mem::take(&mut self.dw[0]);
            for j in 0..n {
                tmp[j] = self.st.z[j] + self.err[j];
            }
            let mut fe = std::mem::take(&mut self.dw[1]);
            Self::rhs(sys, m, &tmp, &mut fe, &mut self.stats);
            for j in 0..n {
                let ze = (E[0] * self.zs[0][j] + E[1] * self.zs[1][j] + E[2] * self.zs[2][j]) / h;
                self.err[j] = fe[j] + ze;
            }
            let kv = Self::kv_of(sys, &self.st.kv);
            linear::solve_real(&mut *self.real, mass, kv, cr, &mut self.err);
            err_norm = self.weights_norm(&self.err, &self.st.z, &self.ytmp);
            self.dw[0] = tmp;
            self.dw[1] = fe;
        }
        // after the state's (second) estimate, which replaces err_norm
        let mut d_step = 0.0;
        if sys.dissipative() {
            let (d, e) = self.dissipation_error(sys, h, cr);
            d_step = d;
            err_norm = err_norm.max(e);
        }
        (err_norm, d_step)
    }

    /// Accepts the step from `t` to `t_new`: dense output, new state, `F` and stiffnesses there.
    pub(super) fn advance(&mut self, sys: &dyn System, t: f64, t_new: f64) {
        let n = 2 * self.m;
        let m = self.m;
        // dense output Q = Z^T P, then advance
        for j in 0..n {
            let (z0, z1, z2) = (self.zs[0][j], self.zs[1][j], self.zs[2][j]);
            for c in 0..3 {
                self.st.q[c][j] = z0 * P[0][c] + z1 * P[1][c] + z2 * P[2][c];
            }
        }
        self.st.z_old.copy_from_slice(&self.st.z);
        self.st.z.copy_from_slice(&self.ytmp);
        self.t_old = t;
        self.t = t_new;
        self.st.have_sol = true;
        // F and stiffness at the new point (one evaluation gives both)
        self.st.f[..m].copy_from_slice(&self.st.z[m..]);
        let (u, v) = self.st.z.split_at(m);
        self.st.p0 = sys.accel_stiffness(u, v, &mut self.acc, &mut self.ktmp, &mut self.kvtmp);
        self.st.f[m..].copy_from_slice(&self.acc);
        std::mem::swap(&mut self.st.k, &mut self.ktmp);
        std::mem::swap(&mut self.st.kv, &mut self.kvtmp);
        self.stats.rhs_evals += 1;
        self.stats.jac_evals += 1;
        self.stats.steps += 1;
        self.stats.bead_steps += m as u64;
    }
}
