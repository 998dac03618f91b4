//! Radau IIA state as plain data: the step's solution, the previous one, `F`, the stiffnesses,
//! the collocation polynomial (dense output) and the step-control history, saved into and loaded
//! from a typed [`IntegratorState`] (checked: method and array lengths).

use super::Radau5;
use crate::integrate::{check_state, IntegratorState, Method};

impl Radau5 {
    /// The integrator's state as data ([`IntegratorState`], method `Radau5`).
    pub(super) fn save_state(&self) -> IntegratorState {
        IntegratorState {
            t: self.t,
            t_prev: self.t_old,
            h: self.h_abs,
            h_old: self.h_abs_old,
            err_old: self.err_old,
            have_sol: self.have_sol,
            vecs: vec![
                self.z.clone(),
                self.z_old.clone(),
                self.f.clone(),
                self.k.clone(),
                self.q[0].clone(),
                self.q[1].clone(),
                self.q[2].clone(),
                self.kv.clone(),
                vec![self.p0],
            ],
            stats: self.stats.clone(),
            auto: None,
            dissipated: self.diss,
            method: Method::Radau5,
            exact: None,
        }
    }

    /// Loads a state saved by [`Radau5::save_state`]; refuses another method or other lengths.
    pub(super) fn load_state(&mut self, s: &IntegratorState) -> Result<(), String> {
        let (z, q, kv) = (self.z.len(), self.q[0].len(), self.kv.len());
        let lens = [
            z,
            self.z_old.len(),
            self.f.len(),
            self.k.len(),
            q,
            q,
            q,
            kv,
            1,
        ];
        check_state(s, Method::Radau5, &lens)?;
        self.t = s.t;
        self.t_old = s.t_prev;
        self.h_abs = s.h;
        self.h_abs_old = s.h_old;
        self.err_old = s.err_old;
        self.have_sol = s.have_sol;
        let dst: [&mut Vec<f64>; 8] = {
            let [q0, q1, q2] = &mut self.q;
            [
                &mut self.z,
                &mut self.z_old,
                &mut self.f,
                &mut self.k,
                q0,
                q1,
                q2,
                &mut self.kv,
            ]
        };
        for (d, v) in dst.into_iter().zip(&s.vecs) {
            d.copy_from_slice(v);
        }
        self.p0 = s.vecs[8][0];
        self.stats = s.stats.clone();
        self.diss = s.dissipated;
        Ok(())
    }
}
