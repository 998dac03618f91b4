//! Radau IIA state as plain data: the step's solution, the previous one, `F`, the stiffnesses,
//! the collocation polynomial (dense output) and the step-control history, which the integrator
//! holds as a typed [`Radau5State`] and a checkpoint stores as it is (loading checks the method
//! and the array lengths).

use super::Radau5;
use crate::integrate::{
    check_lengths, IntegratorState, LoadError, Method, MethodState, Stats, Tolerances,
};
use crate::linalg::{new_solver, resolve};
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

/// `v` as a new array of `len` zeros, in its own allocation where it is large enough.
fn zeroed<T: Clone>(v: &mut Vec<T>, len: usize, zero: T) {
    v.clear();
    v.resize(len, zero);
}

impl Radau5 {
    /// `Integrator::renew`: the integrator [`Radau5::new`]`(m, tol, solver)` builds, in the
    /// allocations of this one (every array zeroed as `new` makes it, so that the states saved
    /// and the numbers computed are the new integrator's; the linear solvers keep theirs
    /// through [`crate::linalg::TridiagSolver::pattern`], or are built again where the solver
    /// `Auto` resolves to another kind at the new size).
    pub(super) fn renew_arrays(&mut self, m: usize, tol: Tolerances) {
        let n = 2 * m;
        if resolve(self.solver, m) == resolve(self.solver, self.m) {
            self.real.pattern(m);
            self.cplx.pattern(m);
        } else {
            self.real = new_solver(self.solver, m);
            self.cplx = new_solver(self.solver, m);
        }
        self.m = m;
        self.tol = tol;
        self.newton_tol = super::newton_tol(tol.rtol);
        (self.t, self.t_old) = (0.0, 0.0);
        let st = &mut self.st;
        (st.h, st.h_old, st.err_old, st.have_sol, st.p0) = (0.0, None, None, false, 0.0);
        let [q0, q1, q2] = &mut st.q;
        let [z0, z1, z2] = &mut self.zs;
        let [w0, w1, w2] = &mut self.w;
        let [f0, f1, f2] = &mut self.fs;
        let [d0, d1, d2] = &mut self.dw;
        for v in [
            &mut st.z,
            &mut st.z_old,
            &mut st.f,
            q0,
            q1,
            q2,
            z0,
            z1,
            z2,
            w0,
            w1,
            w2,
        ] {
            zeroed(v, n, 0.0);
        }
        for v in [f0, f1, f2, d0, d1, d2, &mut self.ytmp, &mut self.ytmp_d] {
            zeroed(v, n, 0.0);
        }
        zeroed(&mut self.err, n, 0.0);
        zeroed(&mut self.inv_w, n, 0.0);
        for v in [&mut self.vs, &mut self.acc, &mut self.d_r] {
            zeroed(v, m, 0.0);
        }
        for v in [&mut st.k, &mut st.kv, &mut self.ktmp, &mut self.kvtmp] {
            zeroed(v, m + 1, 0.0);
        }
        zeroed(&mut self.e_r, m.saturating_sub(1), 0.0);
        let c0 = num_complex::Complex64::new(0.0, 0.0);
        zeroed(&mut self.d_c, m, c0);
        zeroed(&mut self.rhs_c, m, c0);
        zeroed(&mut self.e_c, m.saturating_sub(1), c0);
        self.diss = (0.0, 0.0);
        self.ps = [0.0; 3];
        self.stats = Stats::default();
    }

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
