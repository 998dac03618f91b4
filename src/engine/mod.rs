//! Engines: drive an integrator over a scene and report frames to an observer.
//!
//! - [`dense`]: the whole chain as one ODE system (paper appendix, eq. A.3), no events; the
//!   cross-check path.
//! - [`hybrid`]: event-driven; free beads fly analytically, contact clusters are integrated on
//!   their own.
//!
//! An engine owns the loop; an [`Observer`] watches it (frames at the requested output times,
//! and the hybrid engine's event log in blocks, see [`Observer::events`]). Engines keep no
//! history: what a run produces goes to the observer, so a run's memory grows with `N`, not with
//! its length.

pub mod checkpoint;
mod config;
pub mod dense;
pub mod events;
pub mod hybrid;
mod observe;
mod start;
pub mod stepper;

pub use checkpoint::Control;
pub use config::{check_config, reaches_until, unrunnable, RunConfig, RunOverrides, Unrunnable};
pub(crate) use observe::poll_stop;
pub use observe::{Amplitude, Observer, Observers, Recorder, AMPLITUDE_FRAMES};
pub use start::{restore, start};
pub use stepper::{Engine, PauseAt, State, Stop};

use crate::integrate::{IntegrationError, Stats};
use crate::scene::Scene;
use serde::{Deserialize, Serialize};

/// Why a run failed.
#[derive(Debug, thiserror::Error)]
pub enum EngineError {
    /// The integrator failed.
    #[error("integration failed: {0}")]
    Integration(#[from] IntegrationError),
    /// The observer (e.g. the snapshot writer) failed.
    #[error("{0}")]
    Observer(String),
    /// The configuration is unusable.
    #[error("invalid run configuration: {0}")]
    Config(String),
    /// A saved engine state (checkpoint) that does not fit the run loading it.
    #[error("invalid run configuration: checkpoint: {0}")]
    Checkpoint(#[from] checkpoint::StateError),
    /// An invariant of the engine itself failed (a bug, not a property of the scene or the
    /// configuration).
    #[error("internal error (a bug in beadchain; please report it with the scene): {0}")]
    Internal(String),
    /// A frame's state is not finite (an overflow the integrator's own check did not see, e.g.
    /// an exact contact of beads of mass 1e155).
    #[error("the state became non-finite at t = {t} (bead {bead}: u = {u}, v = {v})")]
    NonFinite {
        /// Frame time.
        t: f64,
        /// The first bead with a non-finite displacement or velocity.
        bead: usize,
        /// Its displacement.
        u: f64,
        /// Its velocity.
        v: f64,
    },
    /// The observer asked to stop (after a checkpoint was written) at time `t`.
    #[error("interrupted at t = {0} (checkpoint written)")]
    Interrupted(f64),
}

/// A closing whose relative speed is below this many times the beads' absolute velocity
/// tolerance `atol·V` (the floor of every velocity error weight,
/// [`crate::integrate::Tolerances::weight_v`]) is counted in [`RunOutcome::slow_closings`].
/// Not the relative part `rtol·|v|`: a wave's front closes at speeds that scale with the
/// contact threshold `θ ∝ rtol` (`rectangular_pulse`: 2e-7, 2e-9, 3e-11 at rtol 1e-8, 1e-10,
/// 1e-12, between beads moving at ~0.3), real closings at every tolerance.
pub const SLOW_CLOSING_FACTOR: f64 = 30.0;

/// Events the hybrid engine buffers before handing them to [`Observer::events`].
pub const EVENT_BLOCK: usize = 4096;

/// What a finished run reports.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunOutcome {
    /// Integrator counters.
    pub stats: Stats,
    /// Final time.
    pub t_end: f64,
    /// Wall-clock seconds of the integration.
    pub wall_seconds: f64,
    /// Total energy at t = 0.
    pub energy_initial: f64,
    /// Total energy at the end.
    pub energy_final: f64,
    /// The scale of energy errors: the larger [`crate::model::Chain::energy_scale`] (gross
    /// energy, every part positive) of the initial and final states.
    #[serde(default)]
    pub energy_scale: f64,
    /// Momentum at t = 0.
    pub momentum_initial: f64,
    /// Momentum at the end.
    pub momentum_final: f64,
    /// Event counts by kind (hybrid engine; `None` for the dense engine, which has no events).
    pub events_by_kind: Option<events::EventCounts>,
    /// Largest number of beads integrated together.
    pub largest_cluster: u64,
    /// Hybrid engine diagnostic: merges whose overlap at the merge was far above the contact
    /// threshold (a closing detected late). Expected 0.
    pub late_merges: u64,
    /// Hybrid engine diagnostic: gap closings (and soft-wall closings) whose relative speed was
    /// below [`SLOW_CLOSING_FACTOR`] times the beads' absolute velocity tolerance `atol·V`:
    /// whether they happen at all is decided at the tolerance level (typically beads a wave
    /// left behind re-colliding with their own velocity errors under a loose `--atol`). 0 on
    /// every preset at the default tolerances.
    #[serde(default)]
    pub slow_closings: u64,
    /// Hybrid engine diagnostic: integrated collisions whose peak overlap, estimated from the
    /// two bodies' approach, is below `θ·rtol^{−1/n}` (`θ` ∝ `rtol` the contact threshold) at
    /// a speed that matters at the tolerance: the force not applied below `θ` is more than
    /// `rtol` of their energy, and a peak below `θ` is missed entirely. Exact two-body contacts
    /// do not count (they close at their onset). 0 on every preset at rtol 1e-8 and 1e-10.
    #[serde(default)]
    pub shallow_closings: u64,
    /// Accepted steps taken by an implicit method (Radau IIA); `stats.steps` minus this is the
    /// number of explicit steps.
    pub implicit_steps: u64,
    /// Hybrid engine: two-body contacts resolved in closed form (no steps), and those of them
    /// handed over to the integrator when a third body arrived during the contact.
    #[serde(default)]
    pub exact_pairs: [u64; 2],
    /// Final displacements.
    pub u: Vec<f64>,
    /// Final velocities.
    pub v: Vec<f64>,
    /// Energy dissipated by damped contacts and in hard collisions over the run (0 for a
    /// conservative scene).
    #[serde(default)]
    pub dissipated: f64,
}

/// Largest difference between two runs' final states (e.g. hybrid vs dense).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Deviation {
    /// Largest |Δu| and the bead where it occurs.
    pub du: (f64, usize),
    /// Largest |Δv| and the bead where it occurs.
    pub dv: (f64, usize),
    /// |Δu| relative to the largest displacement change of `b` (`max |u − u0|`).
    pub rel_u: f64,
    /// |Δv| relative to the largest |v| of `b` and of the initial state.
    pub rel_v: f64,
    /// The reference scales: largest displacement change and largest |v|.
    pub scale: (f64, f64),
}

impl Deviation {
    /// Compares the final states of `a` and `b` (reference) of runs of `scene`.
    pub fn between(scene: &Scene, a: &RunOutcome, b: &RunOutcome) -> Self {
        let vmax =
            b.v.iter()
                .chain(&scene.v0)
                .fold(0.0_f64, |m, x| m.max(x.abs()));
        let umax =
            b.u.iter()
                .zip(&scene.u0)
                .fold(0.0_f64, |m, (x, x0)| m.max((x - x0).abs()));
        let largest = |x: &[f64], y: &[f64]| {
            x.iter()
                .zip(y)
                .enumerate()
                .map(|(i, (p, q))| ((p - q).abs(), i))
                .fold((0.0, 0), |acc, d| if d.0 > acc.0 { d } else { acc })
        };
        let du = largest(&a.u, &b.u);
        let dv = largest(&a.v, &b.v);
        Self {
            du,
            dv,
            rel_u: if umax > 0.0 { du.0 / umax } else { du.0 },
            rel_v: if vmax > 0.0 { dv.0 / vmax } else { dv.0 },
            scale: (umax, vmax),
        }
    }

    /// The same deviation relative to scales of at least the motion `amp` over the run (the
    /// final state alone can be back near the initial one: [`Amplitude`]).
    pub fn over_motion(self, amp: &Amplitude) -> Self {
        let (length, velocity) = (self.scale.0.max(amp.length), self.scale.1.max(amp.velocity));
        let rel = |d: f64, s: f64| if s > 0.0 { d / s } else { d };
        Self {
            rel_u: rel(self.du.0, length),
            rel_v: rel(self.dv.0, velocity),
            scale: (length, velocity),
            ..self
        }
    }

    /// The same deviation relative to the scales `length`, `velocity` instead of the
    /// reference's motion (a chain at rest, whose own motion is round-off).
    pub fn against_scales(self, length: f64, velocity: f64) -> Self {
        Self {
            rel_u: self.du.0 / length,
            rel_v: self.dv.0 / velocity,
            scale: (length, velocity),
            ..self
        }
    }
}

/// A run whose energy balance error exceeds this many `rtol` is reported as unresolved
/// ([`balance_note`]): the books promise `100·rtol` ([`crate::model::Chain::loses_energy`]
/// scenes, `tests/energy_books.rs`), so 1000 means something went wrong, not noise.
pub const BALANCE_WARNING: f64 = 1000.0;

/// The warning of a run (or snapshot) that loses energy and whose relative balance error
/// `|E + E_d − E_0|/S` is above [`BALANCE_WARNING`]` · rtol`; `None` otherwise.
pub fn balance_note(balance: f64, rtol: f64) -> Option<String> {
    (balance.is_nan() || balance > BALANCE_WARNING * rtol).then(|| {
        format!(
            "energy balance error {balance:.3e} is {:.0}x rtol {rtol:e} (more than {BALANCE_WARNING}x): the dissipated energy is not resolved; rerun with a smaller --rtol or --method radau5 to check",
            balance / rtol
        )
    })
}

impl RunOutcome {
    /// Relative total-energy error `|E_end − E_0| / S` with `S` the larger of `|E_0|` and
    /// [`RunOutcome::energy_scale`]; the absolute error when both are 0 (never NaN/inf).
    ///
    /// For a dissipative scene the balance `E_end + E_dissipated` is compared with `E_0`.
    pub fn relative_energy_error(&self) -> f64 {
        let scale = self.energy_scale.max(self.energy_initial.abs());
        crate::model::relative_energy_change(
            self.energy_initial,
            self.energy_final + self.dissipated,
            scale,
        )
    }

    /// Events of kind `k` (0 for the dense engine).
    pub fn events(&self, k: events::EventKind) -> u64 {
        self.events_by_kind.map_or(0, |c| c.get(k))
    }

    /// All events (0 for the dense engine).
    pub fn events_total(&self) -> u64 {
        self.events_by_kind.map_or(0, |c| c.total())
    }

    /// The counts as the snapshot's run summary stores them: `(name, count)` for every kind,
    /// none for the dense engine.
    pub fn events_named(&self) -> Vec<(String, u64)> {
        self.events_by_kind.map_or_else(Vec::new, |c| c.named())
    }

    /// The warning of a run with closings at tolerance-level speeds
    /// ([`RunOutcome::slow_closings`]), or `None` when there were none.
    pub fn slow_closings_note(&self) -> Option<String> {
        let closings = self.events_by_kind.map_or(0, |c| c.closings());
        (self.slow_closings > 0).then(|| {
            format!(
                "{} of {} closings at relative speeds below {}x the absolute velocity tolerance \
                 atol*V: whether they happen is decided by the tolerance (e.g. beads left behind a \
                 wave re-colliding with their own velocity errors); rerun with a smaller atol to \
                 check that they persist",
                self.slow_closings, closings, SLOW_CLOSING_FACTOR
            )
        })
    }

    /// The warning of a run with shallow integrated collisions
    /// ([`RunOutcome::shallow_closings`]), or `None` when there were none.
    pub fn shallow_closings_note(&self) -> Option<String> {
        let closings = self.events_by_kind.map_or(0, |c| c.closings());
        (self.shallow_closings > 0).then(|| {
            format!(
                "{} of {} closings were collisions whose peak overlap (estimated from the two \
                 bodies' approach) is below theta*rtol^(-1/n), theta being the contact threshold \
                 (proportional to rtol): the force not applied below theta is more than rtol of \
                 their energy (a peak below theta is missed entirely); rerun with a smaller rtol, \
                 or with --engine dense, to check them",
                self.shallow_closings, closings
            )
        })
    }
}

/// Continues a run from a checkpointed state (same scene; `cfg.until` may be later) to
/// `cfg.until`. A stop requested by the observer comes back as
/// [`EngineError::Interrupted`]; drive an [`Engine`] ([`restore`]) to get it as a [`Stop`].
pub fn resume(
    scene: &Scene,
    cfg: &RunConfig,
    state: &EngineState,
    obs: &mut dyn Observer,
) -> Result<RunOutcome, EngineError> {
    finish(restore(scene, cfg, state)?, cfg, obs)
}

/// Runs a scene with the given configuration to `cfg.until` (see [`resume`] for stops).
pub fn run(
    scene: &Scene,
    cfg: &RunConfig,
    obs: &mut dyn Observer,
) -> Result<RunOutcome, EngineError> {
    finish(start(scene, cfg)?, cfg, obs)
}

/// Runs a scene until `cfg.until` or until the observer asks to stop (the analysis windows do
/// once they have seen what they need): the [`Stop`] and the outcome at that time. Neither way
/// is an error.
pub fn run_to_stop(
    scene: &Scene,
    cfg: &RunConfig,
    obs: &mut dyn Observer,
) -> Result<(Stop, RunOutcome), EngineError> {
    let mut e = start(scene, cfg)?;
    let stop = e.advance(cfg.until, obs)?;
    Ok((stop, e.outcome()))
}

fn finish(
    mut e: Box<dyn Engine + '_>,
    cfg: &RunConfig,
    obs: &mut dyn Observer,
) -> Result<RunOutcome, EngineError> {
    loop {
        match e.advance(cfg.until, obs)? {
            Stop::Reached { .. } => return Ok(e.outcome()),
            Stop::Requested { t } => return Err(EngineError::Interrupted(t)),
            Stop::Frame { .. } | Stop::Event { .. } => {}
        }
    }
}

/// The state of either engine.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum EngineState {
    /// Dense engine.
    Dense(Box<checkpoint::DenseState>),
    /// Hybrid engine.
    Hybrid(Box<hybrid::saved::HybridState>),
}

impl EngineState {
    /// Simulation time the state is at (the engine's clock).
    pub fn time(&self) -> f64 {
        match self {
            EngineState::Dense(d) => d.clock,
            EngineState::Hybrid(h) => h.data.t,
        }
    }
}
