//! The hybrid engine as an [`Engine`]: the loop that processes the event queue up to a time,
//! the state of every bead at the clock (free beads analytically, cluster beads from their
//! continuous output), a velocity change that restarts the event structure from the current
//! state, and the run's outcome.
//!
//! **Pauses** ([`PauseAt`]). The loop (the one driver, [`crate::engine::stepper::drive`]) is:
//! return the next event not yet returned (when paused at events), ask the observer
//! ([`crate::engine::Observer::control`]), then this engine's work: hand over a full event
//! block, pop and process one queue entry. A [`Stop::Frame`] returns at the end of the
//! iteration that emitted the frame, a [`Stop::Event`] at the start of the next one, so the
//! next advance continues with exactly the calls an uninterrupted loop makes: pausing changes
//! no byte. Returned events are read from the log's buffer, which is handed over only at a
//! full block or a frame, i.e. after every event it holds was returned.

use super::cluster::ClusterId;
use super::saved::HybridState;
use super::{cluster, prio, Hybrid, Key, FREE};
use crate::engine::stepper::{
    check_budget, check_velocities, drive, outcome_at, Drive, Engine, PauseAt, State, Stop,
};
use crate::engine::EngineState;
use crate::engine::{EngineError, Observer, RunConfig, RunOutcome};
use crate::scene::Scene;
use std::cmp::Reverse;
use std::time::Instant;

impl Hybrid<'_> {
    /// Counts an accepted cluster step against the run's step budget (`max_steps`).
    pub(super) fn count_step(&mut self) -> Result<(), EngineError> {
        self.st.steps_total += 1;
        check_budget(self.st.steps_total, self.ctx.cfg.max_steps)
    }

    /// Events logged so far (all kinds).
    fn logged(&self) -> u64 {
        self.st.counts.total()
    }

    /// When paused at events: the next logged event not yet returned, as a stop.
    fn next_event_stop(&mut self) -> Option<Stop> {
        let logged = self.logged();
        if !self.pause.events || self.reported >= logged {
            return None;
        }
        let behind = (logged - self.reported) as usize;
        let event = self.st.events[self.st.events.len() - behind].clone();
        self.reported += 1;
        Some(Stop::Event {
            t: self.st.t,
            event,
        })
    }

    /// Processes one queue entry (entries at `until` included), after handing over a full
    /// event block; [`Stop::Reached`] when the next entry is past `until` (the clock moves
    /// there), a stop when the entry emitted a frame that pauses or ends the run.
    fn process_next(
        &mut self,
        until: f64,
        obs: &mut dyn Observer,
    ) -> Result<Option<Stop>, EngineError> {
        if self.st.events.len() >= crate::engine::EVENT_BLOCK {
            self.flush_events(obs)?;
        }
        let Some((_, Reverse((t, _, _, _)))) = self.queue.peek() else {
            return Err(EngineError::Internal(
                "event queue ran empty before the end time".into(),
            ));
        };
        if t.0 > until {
            self.st.t = self.st.t.max(until);
            return Ok(Some(Stop::Reached { t: until }));
        }
        let Some((key, Reverse((t, _, _, _)))) = self.queue.pop() else {
            unreachable!("peeked above");
        };
        let t = t.0;
        self.st.t = t;
        match key {
            Key::Frame => return self.emit_frame(t, obs),
            Key::Cluster(slot) => self.process_cluster_entry(slot)?,
            Key::FreeFree(c) => self.process_free_close(c as usize, t)?,
            Key::WallLog(side) => self.process_wall_log(side, t),
            Key::Wall(side) => {
                if self.hard_wall(side).is_some() {
                    self.process_hard_wall(side, t)?
                } else {
                    self.process_wall_close(side, t)
                }
            }
        }
        Ok(None)
    }

    /// A cluster's queue entry: its pending event (a closing, split, hard-wall contact or
    /// opening it landed on), else its next step.
    fn process_cluster_entry(&mut self, slot: ClusterId) -> Result<(), EngineError> {
        let pending = self
            .clusters
            .get_mut(slot)
            .and_then(|c| c.data.pending.take());
        match pending {
            Some(cluster::Pending::Close { contact, t, ver }) => {
                self.process_close(slot, contact, t, ver)
            }
            Some(cluster::Pending::Split) => {
                self.process_split(slot);
                Ok(())
            }
            Some(cluster::Pending::HardWall { side, t }) => self.process_hard_wall(side, t),
            Some(cluster::Pending::Open { t }) => self.open_at(slot, t),
            Some(cluster::Pending::Release { t, hold }) => self.release_at(slot, t, hold),
            None => self.step_cluster(slot),
        }
    }

    /// Hands the frame at `t` (and the events before it, and `E_d` when the scene loses energy)
    /// to the observer and schedules the next one. Returns the stop to return: the run's end
    /// ([`Stop::Reached`]) after the last frame, or [`Stop::Frame`] when paused at frames.
    fn emit_frame(&mut self, t: f64, obs: &mut dyn Observer) -> Result<Option<Stop>, EngineError> {
        for i in 0..self.ctx.n {
            let (u, v) = self.pos(i, t);
            self.ws.bu[i] = u;
            self.ws.bv[i] = v;
        }
        let (u, v) = (&self.ws.bu, &self.ws.bv);
        if let Some(bead) = (0..self.ctx.n).find(|&i| !u[i].is_finite() || !v[i].is_finite()) {
            let (u, v) = (u[bead], v[bead]);
            return Err(EngineError::NonFinite { t, bead, u, v });
        }
        self.flush_events(obs)?;
        if self.ctx.chain.loses_energy() {
            obs.dissipated(t, self.dissipated_at(t))?;
        }
        obs.frame(t, &self.ws.bu, &self.ws.bv)?;
        if t >= self.ctx.cfg.until {
            self.finished = true;
        } else {
            self.st.next_frame += 1;
            let tf = self.ctx.cfg.frame_time(self.st.next_frame);
            self.queue.push(Key::Frame, prio(tf, 0, 0, Key::Frame));
        }
        Ok(if self.pause.frames {
            Some(Stop::Frame { t })
        } else {
            self.finished.then_some(Stop::Reached { t })
        })
    }
}

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
            Some(s) => h.restore(s)?,
        }
        Ok(Self {
            h,
            scene,
            start: Instant::now(),
        })
    }
}

impl Drive for HybridEngine<'_> {
    fn end(&self) -> f64 {
        self.h.ctx.cfg.until
    }

    fn begin(&mut self, until: f64, _obs: &mut dyn Observer) -> Result<Option<Stop>, EngineError> {
        let h = &self.h;
        Ok((h.finished || until < h.st.t).then_some(Stop::Reached { t: h.st.t }))
    }

    fn pending_event(&mut self) -> Option<Stop> {
        self.h.next_event_stop()
    }

    fn poll_time(&self) -> f64 {
        self.h.st.t
    }

    fn work(&mut self, until: f64, obs: &mut dyn Observer) -> Result<Option<Stop>, EngineError> {
        self.h.process_next(until, obs)
    }
}

impl Engine for HybridEngine<'_> {
    fn advance(&mut self, until: f64, obs: &mut dyn Observer) -> Result<Stop, EngineError> {
        drive(self, until, obs)
    }

    fn pause_at(&mut self, pause: PauseAt) {
        let h = &mut self.h;
        if pause.events && !h.pause.events {
            // only events logged from now on come back
            h.reported = h.logged();
        }
        h.pause = pause;
    }

    fn time(&self) -> f64 {
        self.h.st.t
    }

    fn state(&self) -> State {
        let n = self.h.ctx.n;
        let mut s = State {
            t: 0.0,
            u: Vec::with_capacity(n),
            v: Vec::with_capacity(n),
        };
        self.state_into(&mut s);
        s
    }

    fn state_into(&self, s: &mut State) {
        let t = self.h.st.t;
        s.t = t;
        s.u.clear();
        s.v.clear();
        for i in 0..self.h.ctx.n {
            let (u, v) = self.h.pos(i, t);
            s.u.push(u);
            s.v.push(v);
        }
    }

    /// Ends every cluster at the clock (their dissipation and counters are kept) and starts the
    /// event structure again from the current displacements and the new velocities. Resting
    /// hard contacts and wall pins are detected again from there.
    fn set_velocities(&mut self, v: &[f64]) -> Result<(), EngineError> {
        let h = &mut self.h;
        check_velocities(h.ctx.chain, v)?;
        let t = h.st.t;
        let u: Vec<f64> = (0..h.ctx.n).map(|i| h.pos(i, t).0).collect();
        let closed = h.settle_for_kick(t);
        let ids: Vec<ClusterId> = h.clusters.ids().collect();
        for slot in ids {
            if let Some(cl) = h.clusters.get_mut(slot) {
                cl.data.t_now = t;
                h.remove_cluster(slot, t);
            }
        }
        h.queue.clear();
        for i in 0..h.ctx.n {
            h.st.owner[i] = FREE;
            h.st.version[i] += 1;
        }
        h.st.stuck.iter_mut().for_each(|s| *s = false);
        h.st.pinned = [false; 2];
        // the tolerances' scales and the contact threshold follow the new state
        h.ctx.tol.scales = h.ctx.chain.scales(&u, v);
        h.ctx.theta = super::threshold(
            h.ctx.chain,
            h.ctx.cfg.rtol,
            h.ctx.cfg.atol,
            &h.ctx.tol.scales,
        );
        h.init(t, &u, v);
        h.log_reclassified(t, &closed, &u, v);
        Ok(())
    }

    fn outcome(&self) -> RunOutcome {
        let h = &self.h;
        let mut stats = h.st.stats.clone();
        let mut implicit_steps = h.st.implicit_steps;
        for c in h.clusters.iter() {
            stats.add(c.integ.stats());
            implicit_steps += c.integ.implicit_steps();
        }
        RunOutcome {
            stats,
            events_by_kind: Some(h.st.counts),
            largest_cluster: h.st.largest,
            late_merges: h.st.late_merges,
            slow_closings: h.st.slow_closings,
            shallow_closings: h.st.shallow_closings,
            implicit_steps,
            exact_pairs: h.st.exact_pairs,
            dissipated: h.dissipated_at(h.st.t),
            ..outcome_at(self.scene, self.state(), self.start)
        }
    }

    fn save(&self) -> EngineState {
        EngineState::Hybrid(Box::new(self.h.save()))
    }
}
