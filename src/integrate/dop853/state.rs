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
    /// `Integrator::renew`: resizes the arrays in place (see there).
    pub(super) fn renew_arrays(&mut self, m: usize, tol: Tolerances) -> bool {
        let n = 2 * m;
        self.m = m;
        self.tol = tol;
        self.vs.resize(m, 0.0);
        for v in [
            &mut self.st.z,
            &mut self.st.z_old,
            &mut self.y,
            &mut self.e5,
            &mut self.e3,
        ] {
            v.resize(n, 0.0);
        }
        self.st.k.resize(N_STAGES * n, 0.0);
        // never shrunk: the packed stages are read by group only, and only groups that the
        // stages of this state were written into (zero-filling on every renew cost more than
        // the stage sums save on the large clusters of the interface scenes)
        let len = super::packed::packed_len(n);
        if self.kp.len() < len {
            self.kp.resize(len, 0.0);
        }
        self.st.f.resize(N_DENSE * n, 0.0);
        (self.t, self.t_prev, self.st.h) = (0.0, 0.0, 0.0);
        self.pw = [0.0; N_MAIN];
        self.diss = (0.0, 0.0);
        self.damped = false;
        self.stats = Stats::default();
        true
    }

    /// `Integrator::save`: the state as it is, but for two things the step keeps elsewhere or
    /// has not written: the power at `z` (`pw[0]`), and, before the first step since the
    /// integrator was built (or renewed), the stages after 0 and 1 (set by `reset`), written
    /// as the zeros a new integrator holds, whatever a renewed one kept.
    pub(super) fn save_state(&self) -> IntegratorState {
        let mut st = self.st.clone();
        st.p0 = self.pw[0];
        if self.stats.steps == 0 && self.stats.rejected == 0 {
            st.k[4 * self.m..].fill(0.0);
        }
        IntegratorState {
            t: self.t,
            t_prev: self.t_prev,
            stats: self.stats.clone(),
            dissipated: self.diss,
            auto: None,
            method: MethodState::Dop853(st),
        }
    }

    /// `Integrator::load`: the state as it is, the power at `z` into `pw[0]` and the stages
    /// packed again ([`super::packed`]).
    pub(super) fn load_state(&mut self, s: &IntegratorState) -> Result<(), LoadError> {
        let MethodState::Dop853(d) = &s.method else {
            return Err(LoadError::wrong_method(&s.method, Method::Dop853.name()));
        };
        let st = &self.st;
        let lens = [st.z.len(), st.z_old.len(), st.k.len(), st.f.len()];
        check_lengths(Method::Dop853, &[&d.z, &d.z_old, &d.k, &d.f], &lens)?;
        (self.t, self.t_prev) = (s.t, s.t_prev);
        self.st.clone_from(d);
        let n = self.st.z.len();
        for (s, ks) in self.st.k.chunks_exact(n.max(1)).enumerate() {
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
    /// The stages of the last step (`12 · 2m`; see [`Dop853::save_state`]).
    pub k: Vec<f64>,
    /// Dense-output coefficients of the last step.
    pub f: Vec<f64>,
    /// Dissipated power at `z` (stage 0, reused by the next step; 0 when conservative).
    pub p0: f64,
}
