//! The hybrid engine as an [`Engine`]: advancing to a time, the state of every bead at the
//! clock (free beads analytically, cluster beads from their continuous output), a velocity
//! change that restarts the event structure from the current state, and the run's outcome.

use super::{Hybrid, FREE};
use crate::engine::checkpoint::{EngineState, HybridState};
use crate::engine::stepper::{check_target, outcome_at, Engine, State, Stop};
use crate::engine::{EngineError, Observer, RunConfig, RunOutcome};
use crate::scene::Scene;
use std::time::Instant;

/// The hybrid engine as an [`Engine`].
pub struct HybridEngine<'a> {
    h: Hybrid<'a>,
    scene: &'a Scene,
    start: Instant,
}

impl<'a> HybridEngine<'a> {
    /// A hybrid engine at `t = 0`, or at a checkpointed state.
    pub fn new(
        scene: &'a Scene,
        cfg: &'a RunConfig,
        from: Option<&HybridState>,
    ) -> Result<Self, EngineError> {
        let mut h = Hybrid::new(scene, cfg);
        match from {
            None => h.init(0.0, &scene.u0, &scene.v0),
            Some(s) => h
                .restore(s)
                .map_err(|m| EngineError::Config(format!("checkpoint: {m}")))?,
        }
        Ok(Self {
            h,
            scene,
            start: Instant::now(),
        })
    }
}

impl Engine for HybridEngine<'_> {
    fn advance(&mut self, until: f64, obs: &mut dyn Observer) -> Result<Stop, EngineError> {
        check_target(until, self.h.cfg.until)?;
        if self.h.finished || until < self.h.st.t {
            return Ok(Stop::Reached { t: self.h.st.t });
        }
        self.h.advance_to(until, obs)
    }

    fn time(&self) -> f64 {
        self.h.st.t
    }

    fn state(&self) -> State {
        let t = self.h.st.t;
        let (u, v) = (0..self.h.n).map(|i| self.h.pos(i, t)).unzip();
        State { t, u, v }
    }

    /// Ends every cluster at the clock (their dissipation and counters are kept) and starts the
    /// event structure again from the current displacements and the new velocities. Resting
    /// hard contacts and wall pins are detected again from there.
    fn set_velocities(&mut self, v: &[f64]) -> Result<(), EngineError> {
        let h = &mut self.h;
        if v.len() != h.n || !v.iter().all(|x| x.is_finite()) {
            return Err(EngineError::Config(format!(
                "set_velocities: expected {} finite velocities, got {} values",
                h.n,
                v.len()
            )));
        }
        let t = h.st.t;
        let u: Vec<f64> = (0..h.n).map(|i| h.pos(i, t).0).collect();
        for slot in 0..h.clusters.len() {
            if let Some(cl) = h.clusters[slot].as_mut() {
                cl.t_now = t;
                h.remove_cluster(slot as u32);
            }
        }
        h.queue.clear();
        for i in 0..h.n {
            h.st.owner[i] = FREE;
            h.st.version[i] += 1;
        }
        h.st.stuck.iter_mut().for_each(|s| *s = false);
        h.st.pinned = [false; 2];
        // the tolerances' scales and the contact threshold follow the new state
        h.tol.scales = h.chain.scales(&u, v);
        h.theta = super::contact_threshold(h.chain, h.cfg.rtol, h.cfg.atol) * h.tol.scales.length;
        h.init(t, &u, v);
        Ok(())
    }

    fn outcome(&self) -> RunOutcome {
        let h = &self.h;
        let mut stats = h.st.stats.clone();
        let mut implicit_steps = h.st.implicit_steps;
        for c in h.clusters.iter().flatten() {
            stats.add(c.integ.stats());
            implicit_steps += c.integ.implicit_steps();
        }
        let names = ["close", "open", "hard_collision", "wall_close", "wall_open"];
        RunOutcome {
            stats,
            events_by_kind: names
                .iter()
                .zip(h.st.counts)
                .map(|(n, c)| (n.to_string(), c))
                .collect(),
            largest_cluster: h.st.largest,
            late_merges: h.st.late_merges,
            implicit_steps,
            dissipated: h.dissipated_at(h.st.t),
            ..outcome_at(self.scene, self.state(), self.start)
        }
    }

    fn save(&self) -> EngineState {
        EngineState::Hybrid(Box::new(self.h.save()))
    }
}
