//! A cluster at rest: an [`Integrator`] whose state does not change.
//!
//! A cluster whose beads are all at rest and whose forces balance to round-off (the
//! static equilibrium of the paper's eq. 7 with `u̇ = 0`, e.g. `[initial] equilibrium = true`)
//! would, integrated, move only by what the integrator adds: its truncation error at the
//! tolerance and the round-off of many steps (measured on a gravity column over 10⁴ time
//! units: 7·10⁻¹² of its wave speed with Radau IIA's long steps, 10⁻⁹ with DOP853). The exact
//! motion from a state whose net forces are `r` is an oscillation of velocity amplitude about
//! `r/√(K m)`, the round-off of the balance itself. The engine that decides a cluster is at
//! rest (`engine::hybrid`, its `rest` module) gives it this integrator: one step reaches any
//! bound, every continuous output is the state it started from, and it evaluates nothing.
//! Anything that changes the cluster (a bead closing on it, new velocities) makes a new
//! cluster with an integrating method.

use super::{IntegrationError, Integrator, IntegratorState, LoadError, MethodState, Stats, System};
use serde::{Deserialize, Serialize};

/// The name of the resting cluster's integrator in messages.
pub const REST_NAME: &str = "at rest";

/// The saved state of a cluster at rest: its displacements then velocities (`2m`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RestState {
    /// `u` then `v` (all zero) of the cluster's beads, in its frame.
    pub z: Vec<f64>,
}

/// The integrator of a cluster at rest (module docs).
#[derive(Clone, Debug)]
pub struct Rest {
    /// The resting state as data, saved as it is.
    st: RestState,
    t: f64,
    t_prev: f64,
    stats: Stats,
}

impl Rest {
    /// A resting cluster of `m` beads (its state is set by [`Integrator::reset`]).
    pub fn new(m: usize) -> Self {
        Self {
            st: RestState {
                z: vec![0.0; 2 * m],
            },
            t: 0.0,
            t_prev: 0.0,
            stats: Stats::default(),
        }
    }
}

impl Integrator for Rest {
    fn reset(&mut self, _sys: &dyn System, t: f64, u: &[f64], v: &[f64]) {
        let m = u.len();
        self.st.z[..m].copy_from_slice(u);
        self.st.z[m..].copy_from_slice(v);
        self.t = t;
        self.t_prev = t;
    }

    fn set_step_size(&mut self, _h: f64) {}

    /// Any step: the state does not change.
    fn step_size(&self) -> f64 {
        f64::INFINITY
    }

    fn step(&mut self, _sys: &dyn System, t_bound: f64) -> Result<f64, IntegrationError> {
        self.t_prev = self.t;
        self.t = t_bound.max(self.t);
        Ok(self.t)
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

    fn dense(&self, _t: f64, z: &mut [f64]) {
        z[..self.st.z.len()].copy_from_slice(&self.st.z);
    }

    fn dense_at(&self, _t: f64, j: usize) -> f64 {
        self.st.z[j]
    }

    fn end_states(&self) -> Option<(&[f64], &[f64])> {
        Some((&self.st.z, &self.st.z))
    }

    fn stats(&self) -> &Stats {
        &self.stats
    }

    fn at_rest(&self) -> bool {
        true
    }

    fn save(&self) -> IntegratorState {
        IntegratorState {
            t: self.t,
            t_prev: self.t_prev,
            stats: self.stats.clone(),
            dissipated: (0.0, 0.0),
            auto: None,
            method: MethodState::Rest(self.st.clone()),
        }
    }

    fn load(&mut self, s: &IntegratorState) -> Result<(), LoadError> {
        let MethodState::Rest(r) = &s.method else {
            return Err(LoadError::wrong_method(&s.method, REST_NAME));
        };
        if r.z.len() != self.st.z.len() {
            return Err(LoadError::Lengths {
                method: REST_NAME,
                got: vec![r.z.len()],
                expected: vec![self.st.z.len()],
            });
        }
        self.st.z.copy_from_slice(&r.z);
        (self.t, self.t_prev) = (s.t, s.t_prev);
        self.stats = s.stats.clone();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::test_util::uniform_chain;
    use crate::integrate::{ChainRange, Tolerances};

    #[test]
    fn a_resting_cluster_keeps_its_state_and_round_trips() {
        let chain = uniform_chain(3);
        let sys = ChainRange::whole(&chain);
        let mut r = Rest::new(3);
        r.reset(&sys, 2.0, &[0.1, -0.2, 0.3], &[0.0; 3]);
        assert_eq!(r.step(&sys, 50.0).unwrap(), 50.0);
        assert_eq!((r.t_prev(), r.t()), (2.0, 50.0));
        assert_eq!(r.state(), &[0.1, -0.2, 0.3, 0.0, 0.0, 0.0]);
        assert_eq!(r.dense_at(17.0, 1), -0.2);
        let mut z = [9.0; 6];
        r.dense(3.0, &mut z);
        assert_eq!(z, [0.1, -0.2, 0.3, 0.0, 0.0, 0.0]);
        let saved = r.save();
        let mut back = Rest::new(3);
        back.load(&saved).unwrap();
        assert_eq!(
            (back.state(), back.t(), back.t_prev()),
            (r.state(), 50.0, 2.0)
        );
        // another method's state, or another size, is refused and changes nothing
        let mut two = Rest::new(2);
        assert!(matches!(two.load(&saved), Err(LoadError::Lengths { .. })));
        let tol = Tolerances {
            rtol: 1e-8,
            atol: 1e-12,
            scales: chain.scales(&[0.0; 3], &[1.0, 0.0, 0.0]),
            v_frame: 0.0,
            u_origin: 0.0,
            dissipation: Default::default(),
        };
        let dop = crate::integrate::dop853::Dop853::new(3, tol).save();
        let err = back.load(&dop).unwrap_err().to_string();
        assert_eq!(
            err,
            "the state of a dop853 integrator cannot continue as at rest"
        );
        assert_eq!(back.state(), r.state());
    }
}
