//! Checkpoint state and reuse of a [`Dop853`]: what [`Integrator::save`] stores and
//! [`Integrator::load`] restores, and [`Integrator::renew`] (the hybrid engine's reuse of a
//! removed cluster's integrator).
//!
//! [`Integrator::save`]: crate::integrate::Integrator::save
//! [`Integrator::load`]: crate::integrate::Integrator::load
//! [`Integrator::renew`]: crate::integrate::Integrator::renew

use super::{Dop853, N_DENSE, N_MAIN, N_STAGES};
use crate::integrate::{
    check_lengths, IntegratorState, LoadError, Method, MethodState, Stats, Tolerances,
};
use crate::names::Named;
use serde::{Deserialize, Serialize};

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
            stats: self.stats.clone(),
            dissipated: self.diss,
            auto: None,
            method: MethodState::Dop853(Dop853State {
                h: self.h,
                z: self.z.clone(),
                z_old: self.z_old.clone(),
                k: self.saved_stages(),
                f: self.f.clone(),
                p0: self.pw[0],
            }),
        }
    }

    /// `Integrator::load`.
    pub(super) fn load_state(&mut self, s: &IntegratorState) -> Result<(), LoadError> {
        let MethodState::Dop853(d) = &s.method else {
            return Err(LoadError::wrong_method(&s.method, Method::Dop853.name()));
        };
        let lens = [self.z.len(), self.z_old.len(), self.k.len(), self.f.len()];
        check_lengths(Method::Dop853, &[&d.z, &d.z_old, &d.k, &d.f], &lens)?;
        self.t = s.t;
        self.t_prev = s.t_prev;
        self.h = d.h;
        self.z.copy_from_slice(&d.z);
        self.z_old.copy_from_slice(&d.z_old);
        self.k.copy_from_slice(&d.k);
        self.f.copy_from_slice(&d.f);
        let n = self.z.len();
        for (s, ks) in self.k.chunks_exact(n.max(1)).enumerate() {
            super::packed::pack(&mut self.kp, s, ks);
        }
        self.stats = s.stats.clone();
        self.diss = s.dissipated;
        self.pw[0] = d.p0;
        Ok(())
    }
}

/// The state of a [`Dop853`] ([`MethodState::Dop853`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Dop853State {
    /// Step-size proposal.
    pub h: f64,
    /// State at `t` (u then v, `2m`).
    pub z: Vec<f64>,
    /// State at `t_prev`.
    pub z_old: Vec<f64>,
    /// The stages of the last step (`12 · 2m`; see [`Dop853::saved_stages`]).
    pub k: Vec<f64>,
    /// Dense-output coefficients of the last step.
    pub f: Vec<f64>,
    /// Dissipated power at `z` (stage 0, reused by the next step; 0 when conservative).
    pub p0: f64,
}
