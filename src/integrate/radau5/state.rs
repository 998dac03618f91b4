//! Radau IIA state as plain data: the step's solution, the previous one, `F`, the stiffnesses,
//! the collocation polynomial (dense output) and the step-control history, which the integrator
//! holds as a typed [`Radau5State`] and a checkpoint stores as it is (loading checks the method
//! and the array lengths).

use super::Radau5;
use crate::integrate::{check_lengths, IntegratorState, LoadError, Method, MethodState};
use crate::names::Named;
use serde::{Deserialize, Serialize};

/// The state of a [`Radau5`] ([`MethodState::Radau5`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Radau5State {
    /// Step-size proposal.
    pub h: f64,
    /// Previous accepted step size (step-size controller memory).
    pub h_old: Option<f64>,
    /// Previous error norm (step-size controller memory).
    pub err_old: Option<f64>,
    /// Whether the continuous output of the last step is valid.
    pub have_sol: bool,
    /// State at `t` (u then v, `2m`).
    pub z: Vec<f64>,
    /// State at `t_prev`.
    pub z_old: Vec<f64>,
    /// `F(z)` at `t`.
    pub f: Vec<f64>,
    /// Stiffnesses at `t` (`m + 1`: contacts, then left/right wall).
    pub k: Vec<f64>,
    /// Collocation polynomial of the last step (dense output).
    pub q: [Vec<f64>; 3],
    /// Damping Jacobian `∂F/∂δ̇` at `t` (same layout; zero when conservative).
    pub kv: Vec<f64>,
    /// Dissipated power at `z`.
    pub p0: f64,
}

impl Radau5 {
    /// The integrator's state as data ([`MethodState::Radau5`]).
    pub(super) fn save_state(&self) -> IntegratorState {
        IntegratorState {
            t: self.t,
            t_prev: self.t_old,
            stats: self.stats.clone(),
            dissipated: self.diss,
            auto: None,
            method: MethodState::Radau5(self.st.clone()),
        }
    }

    /// Loads a state saved by [`Radau5::save_state`]; refuses another method or other lengths.
    pub(super) fn load_state(&mut self, s: &IntegratorState) -> Result<(), LoadError> {
        let MethodState::Radau5(r) = &s.method else {
            return Err(LoadError::wrong_method(&s.method, Method::Radau5.name()));
        };
        let st = &self.st;
        let (z, q, kv) = (st.z.len(), st.q[0].len(), st.kv.len());
        let lens = [z, st.z_old.len(), st.f.len(), st.k.len(), q, q, q, kv];
        let got = [&r.z, &r.z_old, &r.f, &r.k, &r.q[0], &r.q[1], &r.q[2], &r.kv];
        check_lengths(Method::Radau5, &got, &lens)?;
        (self.t, self.t_old) = (s.t, s.t_prev);
        self.st.clone_from(r);
        self.stats = s.stats.clone();
        self.diss = s.dissipated;
        Ok(())
    }
}
