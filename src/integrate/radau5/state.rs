//! Radau IIA state as plain data: the step's solution, the previous one, `F`, the stiffnesses,
//! the collocation polynomial (dense output) and the step-control history, saved into and loaded
//! from a typed [`Radau5State`] (checked: method and array lengths).

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
            method: MethodState::Radau5(Radau5State {
                h: self.h_abs,
                h_old: self.h_abs_old,
                err_old: self.err_old,
                have_sol: self.have_sol,
                z: self.z.clone(),
                z_old: self.z_old.clone(),
                f: self.f.clone(),
                k: self.k.clone(),
                q: self.q.clone(),
                kv: self.kv.clone(),
                p0: self.p0,
            }),
        }
    }

    /// Loads a state saved by [`Radau5::save_state`]; refuses another method or other lengths.
    pub(super) fn load_state(&mut self, s: &IntegratorState) -> Result<(), LoadError> {
        let MethodState::Radau5(r) = &s.method else {
            return Err(LoadError::wrong_method(&s.method, Method::Radau5.name()));
        };
        let (z, q, kv) = (self.z.len(), self.q[0].len(), self.kv.len());
        let lens = [z, self.z_old.len(), self.f.len(), self.k.len(), q, q, q, kv];
        let got = [&r.z, &r.z_old, &r.f, &r.k, &r.q[0], &r.q[1], &r.q[2], &r.kv];
        check_lengths(Method::Radau5, &got, &lens)?;
        self.t = s.t;
        self.t_old = s.t_prev;
        self.h_abs = r.h;
        self.h_abs_old = r.h_old;
        self.err_old = r.err_old;
        self.have_sol = r.have_sol;
        self.z.copy_from_slice(&r.z);
        self.z_old.copy_from_slice(&r.z_old);
        self.f.copy_from_slice(&r.f);
        self.k.copy_from_slice(&r.k);
        for (d, v) in self.q.iter_mut().zip(&r.q) {
            d.copy_from_slice(v);
        }
        self.kv.copy_from_slice(&r.kv);
        self.p0 = r.p0;
        self.stats = s.stats.clone();
        self.diss = s.dissipated;
        Ok(())
    }
}
