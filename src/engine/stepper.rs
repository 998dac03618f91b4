//! The steppable engine: one [`Engine`] trait for the dense and the hybrid engine, after
//! diffsol's `OdeSolverMethod` (a step returns *why* it stopped) and argmin's executor (the
//! engine owns the loop, observers watch it, stopping is a reason, not an error).
//!
//! ```no_run
//! # use beadchain::engine::{self, PauseAt, Recorder, RunConfig, Stop};
//! # let scene = beadchain::scene::preset("striker").unwrap();
//! let cfg = RunConfig::from_scene(&scene);
//! let mut e = engine::start(&scene, &cfg).unwrap();
//! let mut frames = Recorder::default();
//! e.advance(40.0, &mut frames).unwrap();          // frames up to t = 40 reach the observer
//! let mid = e.state();                             // every bead at t = 40
//! let mut v = mid.v.clone();
//! v[99] = -0.5;                                    // kick the last bead
//! e.set_velocities(&v).unwrap();
//! e.pause_at(PauseAt { frames: true, events: true });
//! loop {
//!     match e.advance(cfg.until, &mut frames).unwrap() {
//!         Stop::Frame { t } => assert_eq!(e.state().t, t), // the frame just handed over
//!         Stop::Event { event, .. } => println!("{} at {}", event.kind, event.t),
//!         Stop::Reached { .. } | Stop::Requested { .. } => break,
//!     }
//! }
//! let outcome = e.outcome();                       // counters, energies, final state
//! ```
//!
//! **Resuming.** Every [`Stop`] is a point the engine can continue from: calling
//! [`Engine::advance`] again goes on exactly where it returned. Advancing in pieces, or pausing
//! at every frame and every event ([`Engine::pause_at`]), gives the same bytes (frames, event
//! log, final state, counters) as one advance to the end: steps are bounded by the run's end
//! time `cfg.until`, never by the intermediate targets, and a pause returns between two
//! iterations of the engine's loop, where the next call picks up (`tests/engine_stops.rs`), until
//! a state is changed ([`Engine::set_velocities`]).

use super::events::EventRecord;
use super::EngineState;
use super::{EngineError, Observer, RunOutcome};
use crate::scene::Scene;
use serde::{Deserialize, Serialize};

/// Why [`Engine::advance`] returned. Only [`Stop::Reached`] means the target was reached;
/// after any other stop, advancing again to the same target goes on from there.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Stop {
    /// The engine reached the requested time `t`.
    Reached {
        /// The time reached.
        t: f64,
    },
    /// The observer asked to stop ([`super::Control::Stop`]) at `t`, after a checkpoint.
    Requested {
        /// The engine clock when it stopped.
        t: f64,
    },
    /// A frame at `t` was just handed to the observer ([`PauseAt::frames`]); the clock is `t`,
    /// so [`Engine::state`] is that frame. With frames paused on, the last frame (at
    /// `cfg.until`) also returns this, and the next advance returns [`Stop::Reached`].
    Frame {
        /// The frame's time.
        t: f64,
    },
    /// The hybrid engine just logged `event` ([`PauseAt::events`]): the record equals the one
    /// the event log holds (and hands to [`Observer::events`]) in that place. Events logged
    /// while processing one queue entry (a hard collision and the merge it causes, a split
    /// opening several contacts) come back one per call, the clock unchanged. The dense engine
    /// detects no events and never returns this.
    Event {
        /// The engine clock (where [`Engine::state`] is): the time of the queue entry that
        /// logged the event. `event.t` is when it happened, which for an opening (logged at
        /// the located crossing of the threshold) can be earlier.
        t: f64,
        /// The event log's record.
        event: EventRecord,
    },
}

/// Where [`Engine::advance`] pauses before its target, besides an observer's stop (default:
/// nowhere, so one advance runs to its target).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct PauseAt {
    /// Return [`Stop::Frame`] right after each frame.
    pub frames: bool,
    /// Return [`Stop::Event`] right after each logged event (hybrid engine).
    pub events: bool,
}

/// Every bead's displacement and velocity at time `t`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct State {
    /// Time.
    pub t: f64,
    /// Displacements, one per bead.
    pub u: Vec<f64>,
    /// Velocities, one per bead.
    pub v: Vec<f64>,
}

/// A running simulation of one scene.
pub trait Engine: Send {
    /// Advances to `until` (at most the run's end time `cfg.until`), handing frames, events and
    /// checkpoints to `obs`. Frames after `until` are not emitted before the next advance.
    fn advance(&mut self, until: f64, obs: &mut dyn Observer) -> Result<Stop, EngineError>;
    /// Where later advances pause ([`Stop::Frame`], [`Stop::Event`]); pausing changes no byte
    /// of the run. Events logged before this call are never returned.
    fn pause_at(&mut self, pause: PauseAt);
    /// The engine clock: the time [`Engine::state`] describes.
    fn time(&self) -> f64;
    /// Every bead at [`Engine::time`] (free beads from their analytic flight, cluster beads
    /// from the continuous output).
    fn state(&self) -> State;
    /// [`Engine::state`] into `s`, in its allocations (a caller reading the state at every
    /// frame allocates nothing once `s` has held one). Default: a new state.
    fn state_into(&self, s: &mut State) {
        *s = self.state();
    }
    /// Gives every bead the velocity `v` at [`Engine::time`] (displacements unchanged); the
    /// integration restarts there.
    fn set_velocities(&mut self, v: &[f64]) -> Result<(), EngineError>;
    /// Counters, energies and the state at [`Engine::time`].
    fn outcome(&self) -> RunOutcome;
    /// The state to continue from exactly (checkpoints).
    fn save(&self) -> EngineState;
}

/// The part of a [`RunOutcome`] every engine fills the same way: time, wall clock, energies,
/// momenta and the state `s` (engine-specific counters are left at their defaults).
pub(crate) fn outcome_at(scene: &Scene, s: State, start: std::time::Instant) -> RunOutcome {
    let chain = &scene.chain;
    RunOutcome {
        t_end: s.t,
        wall_seconds: start.elapsed().as_secs_f64(),
        energy_initial: chain.energy(&scene.u0, &scene.v0),
        energy_final: chain.energy(&s.u, &s.v),
        energy_scale: chain
            .energy_scale(&scene.u0, &scene.v0)
            .max(chain.energy_scale(&s.u, &s.v)),
        momentum_initial: chain.momentum(&scene.v0),
        momentum_final: chain.momentum(&s.v),
        u: s.u,
        v: s.v,
        ..RunOutcome::default()
    }
}

/// Checks an advance target against the clock and the run's end time.
pub(crate) fn check_target(until: f64, end: f64) -> Result<(), EngineError> {
    if until.is_nan() || until > end {
        return Err(EngineError::Config(format!(
            "advance to t = {until} is beyond the run's end time {end} (set it in the run configuration)"
        )));
    }
    Ok(())
}

/// Checks the velocities given to [`Engine::set_velocities`]: one finite value per bead.
pub(crate) fn check_velocities(chain: &crate::model::Chain, v: &[f64]) -> Result<(), EngineError> {
    let n = chain.len();
    if v.len() != n {
        return Err(EngineError::Config(format!(
            "set_velocities: expected {n} velocities (one per bead), got {}",
            v.len()
        )));
    }
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(EngineError::Config(format!(
            "set_velocities: bead {i}: velocity must be finite, got {}",
            v[i]
        )));
    }
    // as a scene's initial state: an energy the floating-point range cannot hold is refused
    let ke: f64 = chain.mass.iter().zip(v).map(|(m, x)| 0.5 * m * x * x).sum();
    if !ke.is_finite() {
        return Err(EngineError::Config(format!(
            "set_velocities: the kinetic energy overflows f64 ({ke:e}): rescale the velocities"
        )));
    }
    Ok(())
}

/// The run's step budget (`max_steps`): an error once `steps` accepted steps reach it.
pub(crate) fn check_budget(steps: u64, max_steps: Option<u64>) -> Result<(), EngineError> {
    match max_steps {
        Some(max) if steps >= max => Err(crate::integrate::IntegrationError::Budget(max).into()),
        _ => Ok(()),
    }
}

/// What the one driver loop ([`drive`]) asks of an engine: an engine does its own work (a
/// whole-chain step, or one entry of the hybrid event queue) and says when it must stop; the
/// driver owns the order in which events, the observer's control and work come, so pausing,
/// checkpoints and stops behave the same in every engine (argmin's executor).
pub(crate) trait Drive: Engine {
    /// The run's end time (`cfg.until`): no advance goes past it.
    fn end(&self) -> f64;
    /// What an advance does before its loop (the dense engine: the frame at `t = 0` and the
    /// frames already due); `Some(stop)` ends the advance there.
    fn begin(&mut self, until: f64, obs: &mut dyn Observer) -> Result<Option<Stop>, EngineError>;
    /// When paused at events: a logged event not yet returned.
    fn pending_event(&mut self) -> Option<Stop> {
        None
    }
    /// The time the observer's [`Observer::control`] is asked at (the integrator's time).
    fn poll_time(&self) -> f64;
    /// One unit of work toward `until`; `Some(stop)` ends the advance (a paused frame, the
    /// target reached).
    fn work(&mut self, until: f64, obs: &mut dyn Observer) -> Result<Option<Stop>, EngineError>;
}

/// The run loop, written once for every engine: check the target, begin, then repeat: return a
/// pending event, ask the observer (checkpoint, stop), work.
pub(crate) fn drive<E: Drive>(
    e: &mut E,
    until: f64,
    obs: &mut dyn Observer,
) -> Result<Stop, EngineError> {
    check_target(until, e.end())?;
    if let Some(stop) = e.begin(until, obs)? {
        return Ok(stop);
    }
    loop {
        if let Some(stop) = e.pending_event() {
            return Ok(stop);
        }
        if super::poll_stop(obs, e.poll_time(), || e.save())? {
            return Ok(Stop::Requested { t: e.time() });
        }
        if let Some(stop) = e.work(until, obs)? {
            return Ok(stop);
        }
    }
}
