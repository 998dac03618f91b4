//! The dense engine: the whole chain integrated as one ODE system `ż = F(z)` (paper appendix,
//! eq. A.3) with Radau IIA or DOP853, no events. Frames come from the integrator's continuous
//! output at the requested times.
//!
//! **Pauses.** It has no event log (contacts are part of the ODE right-hand side, and hard
//! contacts are refused), so it never returns [`Stop::Event`]; paused at frames
//! ([`crate::engine::PauseAt::frames`]) it returns [`Stop::Frame`] after each frame with the
//! clock at the frame (the integrator may be a step ahead; [`Engine::state`] comes from its
//! continuous output), and the next advance continues with the clock it had before the pause.
//!
//! **Free fall.** A chain in a field without walls is integrated relative to its free fall
//! ([`crate::model::Chain::free_fall`]): the integrator holds `w = u − ½ g t²`, `ẇ = v − g t`
//! of the chain less the field's common part, so its error weights follow the beads' motion
//! relative to the falling chain, not the common velocity `g t`; frames and states are given in
//! the lab frame.

use super::checkpoint::{DenseState, StateError};
use super::stepper::{
    check_budget, check_velocities, drive, outcome_at, Drive, Engine, PauseAt, State, Stop,
};
use super::EngineState;
use super::{EngineError, Observer, RunConfig, RunOutcome};
use crate::integrate::{
    dissipated_at, new_integrator, ChainRange, DissipationWeight, Integrator, System,
};
use crate::model::Chain;
use crate::scene::Scene;
use std::time::Instant;

/// The dense engine as an [`Engine`].
pub struct DenseEngine<'a> {
    scene: &'a Scene,
    cfg: &'a RunConfig,
    integ: Box<dyn Integrator>,
    /// Index of the next frame to emit.
    next: u64,
    last_frame_t: f64,
    /// Engine clock (≤ `integ.t()`).
    clock: f64,
    /// Whether frame 0 still has to be emitted.
    fresh: bool,
    /// Energy dissipated before the integrator's last restart.
    diss_base: f64,
    /// Counters and implicit steps of integrators replaced by [`Engine::set_velocities`].
    stats_base: (crate::integrate::Stats, u64),
    start: Instant,
    buf: Vec<f64>,
    /// Scratch of [`dissipated_at`] (`3N`); a cell, as [`Engine::outcome`] reads the dissipated
    /// energy through `&self` too.
    diss_scratch: std::cell::RefCell<Vec<f64>>,
    pause: PauseAt,
    /// The clock before a [`Stop::Frame`] moved it to the frame (restored by the next advance).
    paused_clock: Option<f64>,
    /// The free fall the chain is integrated relative to (module docs): `g` and the chain less
    /// the field's common part (`None`: the scene's chain, in the lab frame).
    fall: (f64, Option<Chain>),
}

/// Moves a state `z = (u, v)` at `t` between the free-falling frame and the lab frame
/// (module docs): `sign = 1` to the lab, `u = w + ½ g t²`, `v = ẇ + g t`; `sign = −1` back.
/// Nothing to do without a free fall (`g = 0`).
fn shift_fall(g: f64, t: f64, z: &mut [f64], sign: f64) {
    if g != 0.0 {
        let n = z.len() / 2;
        z[..n]
            .iter_mut()
            .for_each(|x| *x += sign * (0.5 * g * t * t));
        z[n..].iter_mut().for_each(|x| *x += sign * (g * t));
    }
}

/// The chain the integrator sees: the scene's, or the one relative to its free fall.
fn frame_chain<'c>(scene: &'c Scene, fall: &'c Option<Chain>) -> &'c Chain {
    fall.as_ref().unwrap_or(&scene.chain)
}

impl<'a> DenseEngine<'a> {
    /// A dense engine at `t = 0`, or at a checkpointed state.
    pub fn new(
        scene: &'a Scene,
        cfg: &'a RunConfig,
        from: Option<&DenseState>,
    ) -> Result<Self, EngineError> {
        let chain = &scene.chain;
        let n = chain.len();
        // never restarted: E_d's weight is relative to each step's own increment
        let tol = cfg.tolerances(chain.scales(&scene.u0, &scene.v0), DissipationWeight::Step);
        let mut e = Self {
            scene,
            cfg,
            integ: new_integrator(cfg.method, cfg.solver, n, tol),
            next: 1,
            last_frame_t: 0.0,
            clock: 0.0,
            fresh: true,
            diss_base: 0.0,
            stats_base: Default::default(),
            start: Instant::now(),
            buf: vec![0.0; 2 * n],
            diss_scratch: std::cell::RefCell::new(vec![0.0; 3 * n]),
            pause: PauseAt::default(),
            paused_clock: None,
            fall: chain.free_fall(),
        };
        match from {
            None => {
                // at t = 0 the free-falling frame is the lab frame
                let sys = ChainRange::whole(frame_chain(scene, &e.fall.1));
                e.integ.reset(&sys, 0.0, &scene.u0, &scene.v0);
            }
            Some(d) => {
                e.integ.load(&d.integ).map_err(StateError::Dense)?;
                e.next = d.next_frame;
                e.last_frame_t = d.last_frame_t;
                e.clock = d.clock;
                e.diss_base = d.dissipated;
                e.fresh = false;
            }
        }
        Ok(e)
    }

    fn sys(&self) -> ChainRange<'_> {
        ChainRange::whole(frame_chain(self.scene, &self.fall.1))
    }

    /// Dissipated energy at `t` (within the last step).
    fn dissipated(&self, t: f64) -> f64 {
        let scratch = &mut *self.diss_scratch.borrow_mut();
        self.diss_base + dissipated_at(&*self.integ, &self.sys(), t, scratch)
    }

    /// Emits the frames due up to `min(integ.t(), until)`; `Some(Stop::Frame)` right after
    /// one when paused at frames.
    fn frames(&mut self, until: f64, obs: &mut dyn Observer) -> Result<Option<Stop>, EngineError> {
        let n = self.scene.chain.len();
        loop {
            let tf = self.cfg.frame_time(self.next);
            if tf > self.integ.t() || tf > until || self.last_frame_t >= self.cfg.until {
                return Ok(None);
            }
            self.integ.dense(tf, &mut self.buf);
            shift_fall(self.fall.0, tf, &mut self.buf, 1.0);
            if self.scene.chain.loses_energy() {
                obs.dissipated(tf, self.dissipated(tf))?;
            }
            obs.frame(tf, &self.buf[..n], &self.buf[n..])?;
            self.last_frame_t = tf;
            self.next += 1;
            if let Some(stop) = self.pause_at_frame(tf) {
                return Ok(Some(stop));
            }
        }
    }

    /// When paused at frames: the clock moves to the frame at `tf` (kept aside for the next
    /// advance) and the stop to return.
    fn pause_at_frame(&mut self, tf: f64) -> Option<Stop> {
        if !self.pause.frames {
            return None;
        }
        self.paused_clock = Some(self.clock);
        self.clock = tf;
        Some(Stop::Frame { t: tf })
    }

    /// [`Stop::Reached`] once the integrator has passed `until` (the clock moves there).
    fn reached(&mut self, until: f64) -> Option<Stop> {
        if self.integ.t() < until {
            return None;
        }
        self.clock = self.clock.max(until.min(self.integ.t()));
        Some(Stop::Reached { t: self.clock })
    }
}

impl Drive for DenseEngine<'_> {
    fn end(&self) -> f64 {
        self.cfg.until
    }

    fn begin(&mut self, until: f64, obs: &mut dyn Observer) -> Result<Option<Stop>, EngineError> {
        if let Some(clock) = self.paused_clock.take() {
            self.clock = clock;
        }
        let scene = self.scene;
        if self.fresh {
            if scene.chain.loses_energy() {
                obs.dissipated(0.0, 0.0)?;
            }
            obs.frame(0.0, &scene.u0, &scene.v0)?;
            self.fresh = false;
            if let Some(stop) = self.pause_at_frame(0.0) {
                return Ok(Some(stop));
            }
        }
        if let Some(stop) = self.frames(until, obs)? {
            return Ok(Some(stop));
        }
        Ok(self.reached(until))
    }

    fn poll_time(&self) -> f64 {
        self.integ.t()
    }

    /// One whole-chain step, then the frames it covers.
    fn work(&mut self, until: f64, obs: &mut dyn Observer) -> Result<Option<Stop>, EngineError> {
        let sys = ChainRange::whole(frame_chain(self.scene, &self.fall.1));
        self.integ.step(&sys as &dyn System, self.cfg.until)?;
        self.clock = self.integ.t().min(until);
        check_budget(self.integ.stats().steps, self.cfg.max_steps)?;
        if let Some(stop) = self.frames(until, obs)? {
            return Ok(Some(stop));
        }
        Ok(self.reached(until))
    }
}

impl Engine for DenseEngine<'_> {
    fn advance(&mut self, until: f64, obs: &mut dyn Observer) -> Result<Stop, EngineError> {
        drive(self, until, obs)
    }

    /// Frames only: the dense engine has no event log (module docs).
    fn pause_at(&mut self, pause: PauseAt) {
        self.pause = pause;
    }

    fn time(&self) -> f64 {
        self.clock
    }

    fn state(&self) -> State {
        let n = self.scene.chain.len();
        let mut s = State {
            t: 0.0,
            u: Vec::with_capacity(2 * n),
            v: Vec::with_capacity(n),
        };
        self.state_into(&mut s);
        s
    }

    /// The whole state `z = (u, v)` is evaluated into `s.u` (`2N`), then its velocities moved
    /// to `s.v`.
    fn state_into(&self, s: &mut State) {
        let n = self.scene.chain.len();
        let z = &mut s.u;
        z.clear();
        z.resize(2 * n, 0.0);
        if self.clock == self.integ.t() {
            z.copy_from_slice(self.integ.state());
        } else {
            self.integ.dense(self.clock, z);
        }
        shift_fall(self.fall.0, self.clock, z, 1.0);
        s.v.clear();
        s.v.extend_from_slice(&z[n..]);
        z.truncate(n);
        s.t = self.clock;
    }

    fn set_velocities(&mut self, v: &[f64]) -> Result<(), EngineError> {
        let n = self.scene.chain.len();
        check_velocities(&self.scene.chain, v)?;
        // paused at a frame: the new velocities start there
        self.paused_clock = None;
        let s = self.state();
        self.diss_base = self.dissipated(self.clock);
        self.stats_base.0.add(self.integ.stats());
        self.stats_base.1 += self.integ.implicit_steps();
        // the tolerances' scales follow the new state (a kicked chain at rest had none)
        let scales = self.scene.chain.scales(&s.u, v);
        let tol = self.cfg.tolerances(scales, DissipationWeight::Step);
        self.integ = new_integrator(self.cfg.method, self.cfg.solver, n, tol);
        // back to the free-falling frame (module docs)
        let mut z = [&s.u[..], v].concat();
        shift_fall(self.fall.0, self.clock, &mut z, -1.0);
        let sys = ChainRange::whole(frame_chain(self.scene, &self.fall.1));
        self.integ.reset(&sys, self.clock, &z[..n], &z[n..]);
        Ok(())
    }

    fn outcome(&self) -> RunOutcome {
        let mut stats = self.stats_base.0.clone();
        stats.add(self.integ.stats());
        RunOutcome {
            stats,
            largest_cluster: self.scene.chain.len() as u64,
            implicit_steps: self.stats_base.1 + self.integ.implicit_steps(),
            dissipated: self.dissipated(self.clock),
            ..outcome_at(self.scene, self.state(), self.start)
        }
    }

    fn save(&self) -> EngineState {
        EngineState::Dense(Box::new(DenseState {
            integ: self.integ.save(),
            next_frame: self.next,
            last_frame_t: self.last_frame_t,
            clock: self.clock,
            dissipated: self.diss_base,
        }))
    }
}
