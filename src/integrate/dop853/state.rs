//! Checkpoint state and reuse of a [`Dop853`]: what [`Integrator::save`] stores and
//! [`Integrator::load`] restores, and [`Integrator::renew`] (the hybrid engine's reuse of a
//! removed cluster's integrator).
//!
//! [`Integrator::save`]: crate::integrate::Integrator::save
//! [`Integrator::load`]: crate::integrate::Integrator::load
//! [`Integrator::renew`]: crate::integrate::Integrator::renew

use super::{Dop853, N_DENSE, N_MAIN, N_STAGES};
use crate::integrate::{IntegratorState, Stats, Tolerances};

impl Dop853 {
    /// The stages as a checkpoint stores them: before the first step since the integrator was
    /// built (or renewed) only stages 0 and 1 are set (by `reset`); the others are written as
    /// the zeros a new integrator holds, whatever a renewed one kept.
    pub(super) fn saved_stages(&self) -> Vec<f64> {
        let mut k = self.k.clone();
        if self.stats.steps == 0 && self.stats.rejected == 0 {
            k[4 * self.m..].fill(0.0);
        }
        k
    }

    /// `Integrator::renew`: resizes the arrays in place (see there).
    pub(super) fn renew_arrays(&mut self, m: usize, tol: Tolerances) -> bool {
        let n = 2 * m;
        self.m = m;
        self.tol = tol;
        self.vs.resize(m, 0.0);
        for v in [
            &mut self.z,
            &mut self.z_old,
            &mut self.y,
            &mut self.e5,
            &mut self.e3,
        ] {
            v.resize(n, 0.0);
        }
        self.k.resize(N_STAGES * n, 0.0);
        // never shrunk: the packed stages are read by group only, and only groups that the
        // stages of this state were written into (zero-filling on every renew cost more than
        // the stage sums save on the large clusters of the interface scenes)
        let len = super::packed::packed_len(n);
        if self.kp.len() < len {
            self.kp.resize(len, 0.0);
        }
        self.f.resize(N_DENSE * n, 0.0);
        (self.t, self.t_prev, self.h) = (0.0, 0.0, 0.0);
        self.pw = [0.0; N_MAIN];
        self.diss = (0.0, 0.0);
        self.damped = false;
        self.stats = Stats::default();
        true
    }

    /// `Integrator::save`.
    pub(super) fn save_state(&self) -> IntegratorState {
        IntegratorState {
            t: self.t,
            t_prev: self.t_prev,
            h: self.h,
            h_old: None,
            err_old: None,
            have_sol: true,
            vecs: vec![
                self.z.clone(),
                self.z_old.clone(),
                self.saved_stages(),
                self.f.clone(),
                vec![self.pw[0]],
            ],
            stats: self.stats.clone(),
            auto: None,
            dissipated: self.diss,
            method: crate::integrate::Method::Dop853,
            exact: None,
        }
    }

    /// `Integrator::load`.
    pub(super) fn load_state(&mut self, s: &IntegratorState) -> Result<(), String> {
        let lens = [
            self.z.len(),
            self.z_old.len(),
            self.k.len(),
            self.f.len(),
            1,
        ];
        crate::integrate::check_state(s, crate::integrate::Method::Dop853, &lens)?;
        self.t = s.t;
        self.t_prev = s.t_prev;
        self.h = s.h;
        for (d, v) in [&mut self.z, &mut self.z_old, &mut self.k, &mut self.f]
            .into_iter()
            .zip(&s.vecs[..4])
        {
            d.copy_from_slice(v);
        }
        let n = self.z.len();
        for (s, ks) in self.k.chunks_exact(n.max(1)).enumerate() {
            super::packed::pack(&mut self.kp, s, ks);
        }
        self.stats = s.stats.clone();
        self.diss = s.dissipated;
        self.pw[0] = s.vecs[4][0];
        Ok(())
    }
}
