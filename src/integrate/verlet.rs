//! Fixed-step velocity Verlet: the symplectic, second-order baseline that discrete-element (DEM)
//! codes use, for the equation of motion `ü = f(u)` (paper eq. 7; first-order form appendix eqs.
//! A.2–A.3 for the state `z = (u, v)` it exposes).
//!
//! One step of size `h` (kick–drift–kick, one force evaluation per step):
//! `v½ = v + ½h·a(u)`, `u' = u + h·v½`, `v' = v½ + ½h·a(u')`.
//!
//! ## The accuracy knob: `rtol` is the step
//! There is no error control. The step is `dt = rtol · L/V`, with `L/V` the characteristic
//! time [`crate::model::Scales::time`] of the run (so it is unit-free like every tolerance of
//! [`crate::integrate`]): `--method verlet --rtol 1e-2` integrates with `dt = 0.01·L/V`. `atol` is
//! not used. The global error is `O(dt²)`; the energy error stays bounded (`O(dt²)`, no drift)
//! because the method is symplectic.
//!
//! ## Steps and output
//! Steps are `t_k = t_reset + k·dt` (computed as products, not sums); a step that would pass
//! `t_bound` is shortened to land on it exactly (the grid then restarts from there).
//! [`Integrator::set_step_size`] only lowers the *next* step (to land on a requested time, as the
//! hybrid engine does at events); the fixed step resumes after it. The continuous output is the
//! cubic Hermite interpolant on each step: for `u` from `(u, v)` at both ends, for `v` from
//! `(v, a)` at both ends (third order, exact at the step ends).

use super::{
    check_lengths, IntegrationError, Integrator, IntegratorState, LoadError, Method, MethodState,
    Stats, System, Tolerances,
};
use crate::names::Named;
use serde::{Deserialize, Serialize};

/// Fixed-step velocity Verlet for an `m`-bead [`System`]; all scratch is allocated by
/// [`Verlet::new`], a step allocates nothing.
#[derive(Clone, Debug)]
pub struct Verlet {
    m: usize,
    t: f64,
    t_prev: f64,
    /// The method's state as data (step, grid, states and accelerations), saved as it is.
    st: VerletState,
    stats: Stats,
}

impl Verlet {
    /// An integrator for `m` beads whose step is `tol.rtol · tol.scales.time()` (see module
    /// docs). Call [`Integrator::reset`] before stepping.
    pub fn new(m: usize, tol: Tolerances) -> Self {
        Self {
            m,
            t: 0.0,
            t_prev: 0.0,
            st: VerletState {
                dt: tol.rtol * tol.scales.time(),
                h_once: None,
                t_grid: 0.0,
                k: 0,
                z: vec![0.0; 2 * m],
                z_old: vec![0.0; 2 * m],
                acc: vec![0.0; m],
                acc_old: vec![0.0; m],
            },
            stats: Stats::default(),
        }
    }

    /// The fixed step `dt`.
    /// Cubic Hermite interpolation of component `j` at `t ∈ [t_prev, t]`.
    #[inline]
    fn hermite(&self, t: f64, j: usize) -> f64 {
        let m = self.m;
        let h = self.t - self.t_prev;
        if t == self.t || h <= 0.0 {
            return self.st.z[j];
        }
        if t == self.t_prev {
            return self.st.z_old[j];
        }
        let s = (t - self.t_prev) / h;
        let (y0, y1, d0, d1) = if j < m {
            (
                self.st.z_old[j],
                self.st.z[j],
                self.st.z_old[m + j],
                self.st.z[m + j],
            )
        } else {
            let i = j - m;
            (
                self.st.z_old[j],
                self.st.z[j],
                self.st.acc_old[i],
                self.st.acc[i],
            )
        };
        let r = 1.0 - s;
        let h00 = (1.0 + 2.0 * s) * r * r;
        let h10 = s * r * r;
        let h01 = s * s * (3.0 - 2.0 * s);
        let h11 = -s * s * r;
        h00 * y0 + h01 * y1 + h * (h10 * d0 + h11 * d1)
    }
}

impl Integrator for Verlet {
    fn reset(&mut self, sys: &dyn System, t: f64, u: &[f64], v: &[f64]) {
        let m = self.m;
        super::assert_sizes(m, sys, u, v);
        self.st.z[..m].copy_from_slice(u);
        self.st.z[m..].copy_from_slice(v);
        self.st.z_old.copy_from_slice(&self.st.z);
        sys.accel(u, v, &mut self.st.acc);
        self.stats.rhs_evals += 1;
        self.st.acc_old.copy_from_slice(&self.st.acc);
        self.t = t;
        self.t_prev = t;
        self.st.t_grid = t;
        self.st.k = 0;
        self.st.h_once = None;
    }

    /// Fixed-step method: `h` only bounds the next step (see module docs).
    fn set_step_size(&mut self, h: f64) {
        if h > 0.0 && h.is_finite() {
            self.st.h_once = Some(h);
        }
    }

    fn step(&mut self, sys: &dyn System, t_bound: f64) -> Result<f64, IntegrationError> {
        debug_assert_eq!(sys.len(), self.m);
        let t = self.t;
        if !t.is_finite() || !self.st.z.iter().all(|x| x.is_finite()) {
            return Err(IntegrationError::NonFinite { t });
        }
        if t_bound.is_nan() || t_bound <= t {
            return Ok(t);
        }
        // Next grid point; a last step that would pass (or nearly reach) t_bound lands on it.
        let mut t_new = self.st.t_grid + (self.st.k + 1) as f64 * self.st.dt;
        let mut on_grid = true;
        if let Some(h) = self.st.h_once.take() {
            if t + h < t_new {
                t_new = t + h;
                on_grid = false;
            }
        }
        if t_new >= t_bound - 1e-9 * self.st.dt {
            t_new = t_bound;
            on_grid = false;
        }
        let h = t_new - t;
        if h.is_nan() || h <= 0.0 || self.st.dt.is_nan() || self.st.dt <= 0.0 {
            return Err(IntegrationError::StepTooSmall { t, h });
        }
        let m = self.m;
        self.st.z_old.copy_from_slice(&self.st.z);
        std::mem::swap(&mut self.st.acc, &mut self.st.acc_old);
        let (u, v) = self.st.z.split_at_mut(m);
        for i in 0..m {
            v[i] += 0.5 * h * self.st.acc_old[i];
            u[i] += h * v[i];
        }
        // Conservative systems only (dissipative ones are refused: the half-step velocity
        // would make the damping force first-order).
        sys.accel(u, v, &mut self.st.acc);
        for i in 0..m {
            v[i] += 0.5 * h * self.st.acc[i];
        }
        self.stats.rhs_evals += 1;
        self.stats.steps += 1;
        self.stats.bead_steps += m as u64;
        self.t_prev = t;
        self.t = t_new;
        if on_grid {
            self.st.k += 1;
        } else {
            self.st.t_grid = t_new;
            self.st.k = 0;
        }
        if !self.st.z.iter().all(|x| x.is_finite()) {
            return Err(IntegrationError::NonFinite { t: t_new });
        }
        Ok(t_new)
    }

    fn t(&self) -> f64 {
        self.t
    }

    fn t_prev(&self) -> f64 {
        self.t_prev
    }

    fn state(&self) -> &[f64] {
        &self.st.z
    }

    /// Cubic Hermite output of the last step (exact copies of the step's end states).
    fn dense(&self, t: f64, z: &mut [f64]) {
        debug_assert_eq!(z.len(), 2 * self.m);
        for (j, zj) in z.iter_mut().enumerate() {
            *zj = self.hermite(t, j);
        }
    }

    fn dense_at(&self, t: f64, j: usize) -> f64 {
        self.hermite(t, j)
    }

    fn stats(&self) -> &Stats {
        &self.stats
    }

    fn step_size(&self) -> f64 {
        self.st.dt
    }

    /// The integrator [`Verlet::new`]`(m, tol)` builds, in the allocations of this one (arrays
    /// resized in place and zeroed as `new` makes them).
    fn renew(&mut self, m: usize, tol: Tolerances) -> bool {
        self.m = m;
        (self.t, self.t_prev) = (0.0, 0.0);
        let st = &mut self.st;
        st.dt = tol.rtol * tol.scales.time();
        (st.h_once, st.t_grid, st.k) = (None, 0.0, 0);
        for (v, len) in [
            (&mut st.z, 2 * m),
            (&mut st.z_old, 2 * m),
            (&mut st.acc, m),
            (&mut st.acc_old, m),
        ] {
            v.clear();
            v.resize(len, 0.0);
        }
        self.stats = Stats::default();
        true
    }

    fn save(&self) -> IntegratorState {
        IntegratorState {
            t: self.t,
            t_prev: self.t_prev,
            stats: self.stats.clone(),
            dissipated: (0.0, 0.0),
            auto: None,
            method: MethodState::Verlet(self.st.clone()),
        }
    }

    fn load(&mut self, s: &IntegratorState) -> Result<(), LoadError> {
        let MethodState::Verlet(w) = &s.method else {
            return Err(LoadError::wrong_method(&s.method, Method::Verlet.name()));
        };
        let st = &self.st;
        let lens = [st.z.len(), st.z_old.len(), st.acc.len(), st.acc_old.len()];
        check_lengths(Method::Verlet, &[&w.z, &w.z_old, &w.acc, &w.acc_old], &lens)?;
        (self.t, self.t_prev) = (s.t, s.t_prev);
        self.st.clone_from(w);
        self.stats = s.stats.clone();
        Ok(())
    }
}

/// The state of a [`Verlet`] ([`MethodState::Verlet`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct VerletState {
    /// Fixed step.
    pub dt: f64,
    /// One-shot upper bound on the next step.
    pub h_once: Option<f64>,
    /// Start of the current grid `t_grid + k·dt`.
    pub t_grid: f64,
    /// Steps taken on the current grid.
    pub k: u64,
    /// State at `t` (u then v, `2m`).
    pub z: Vec<f64>,
    /// State at `t_prev`.
    pub z_old: Vec<f64>,
    /// Accelerations at `t`.
    pub acc: Vec<f64>,
    /// Accelerations at `t_prev`.
    pub acc_old: Vec<f64>,
}

#[cfg(test)]
#[path = "verlet_tests.rs"]
mod tests;
