//! Engine state for checkpoints: everything an engine needs to continue a run so that the
//! resumed run produces bit-identical frames and final state to one never interrupted.
//!
//! Engines ask their [`super::Observer`] between steps whether to checkpoint ([`Control`]);
//! saving is read-only, so a checkpoint never perturbs the run.

use crate::engine::events::EventRecord;
use crate::engine::hybrid::cluster::ClusterData;
use crate::engine::hybrid::free::Free;
use crate::engine::hybrid::queue::{Key, Prio};
use crate::integrate::{IntegratorState, LoadError};
use serde::{Deserialize, Serialize};

/// What the observer wants the engine to do after the current step/event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Control {
    /// Keep going.
    Continue,
    /// Save a checkpoint, then keep going.
    Checkpoint,
    /// Save a checkpoint, then stop with [`super::EngineError::Interrupted`].
    Stop,
}

impl Control {
    /// [`Control::Stop`] when `stop`, else [`Control::Continue`] (observers with a stop flag).
    pub fn stop_if(stop: bool) -> Self {
        if stop {
            Control::Stop
        } else {
            Control::Continue
        }
    }
}

/// The state of either engine.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum EngineState {
    /// Dense engine.
    Dense(Box<DenseState>),
    /// Hybrid engine.
    Hybrid(Box<HybridState>),
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

/// Dense engine state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DenseState {
    /// The whole-chain integrator.
    pub integ: IntegratorState,
    /// Index of the next output frame.
    pub next_frame: u64,
    /// Time of the last frame written.
    pub last_frame_t: f64,
    /// The engine clock (at most `integ.t`: an advance may stop inside the last step).
    pub clock: f64,
    /// Energy dissipated before the integrator's last restart (a velocity change).
    pub dissipated: f64,
}

/// One cluster of the hybrid engine: its state as the engine holds it, and its integrator's.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ClusterState {
    /// Beads, frame, clock, pending event, masses and pinned ends, as the engine holds them.
    pub data: ClusterData,
    /// Integrator.
    pub integ: IntegratorState,
}

/// Hybrid engine state: the engine's plain data ([`HybridData`], which the engine works on
/// directly), plus its clusters and event queue as data (the engine holds those as live
/// integrators and a heap, rebuilt from this on restore; rapier's islands/workspace split).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HybridState {
    /// Everything but the clusters and the queue, as the engine holds it.
    pub data: HybridData,
    /// Cluster slots.
    pub clusters: Vec<Option<ClusterState>>,
    /// Queue contents, keys and priorities as the queue holds them (its heap order is not
    /// part of the state: priorities are unique; stored in priority order).
    pub queue: Vec<(Key, Prio)>,
}

/// The hybrid engine's plain data: the engine reads and writes these fields in place, and a
/// checkpoint stores them as they are (no hand-kept copy).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HybridData {
    /// Engine clock (time of the last processed queue entry).
    pub t: f64,
    /// Owner slot per bead (`u32::MAX` = free).
    pub owner: Vec<u32>,
    /// Free-flight states.
    pub free: Vec<Free>,
    /// Bead versions.
    pub version: Vec<u64>,
    /// Unused cluster slots.
    pub spare_slots: Vec<u32>,
    /// Largest overlap per contact since it closed (`N − 1` contacts, then the left and right
    /// walls at `N − 1 + side`).
    pub peak: Vec<f64>,
    /// Counters of removed clusters.
    pub stats: crate::integrate::Stats,
    /// Events logged but not yet handed to the observer (at most about one block: the rest
    /// of the log is already in the output, up to the checkpoint's writer mark).
    pub events: Vec<EventRecord>,
    /// Event counts by kind.
    pub counts: super::events::EventCounts,
    /// Largest cluster so far (beads).
    pub largest: u64,
    /// Steps so far.
    pub steps_total: u64,
    /// Late merges so far.
    pub late_merges: u64,
    /// Closings so far at relative speeds within [`crate::engine::SLOW_CLOSING_FACTOR`] times
    /// the velocity tolerance.
    pub slow_closings: u64,
    /// Implicit steps of the clusters removed so far.
    pub implicit_steps: u64,
    /// Exact two-body contacts started, and those of them handed over to the integrator when
    /// a third body arrived (`engine::hybrid::exact`).
    pub exact_pairs: [u64; 2],
    /// Last hard collision per contact / wall.
    pub last_hard: Vec<f64>,
    /// Wall pins.
    pub pinned: [bool; 2],
    /// Per contact: a resting (sticking) hard contact joining two free beads.
    pub stuck: Vec<bool>,
    /// Next frame index.
    pub next_frame: u64,
    /// Energy dissipated by cluster integrations that have ended (removed clusters, and the
    /// segments before an integrator restart), plus the losses of hard collisions.
    pub dissipated: f64,
    /// Per soft wall (left, right): its contact is logged as closed (the last `wall_close`
    /// not yet followed by a `wall_open`; `crate::engine::hybrid` walllog module).
    pub wall_in: [bool; 2],
}

impl HybridState {
    /// The consistency check on load: every per-bead and per-contact array fits a chain of `n`
    /// beads, and every cluster covers beads inside it (an inconsistent state is an error,
    /// never a panic or a silently different run).
    pub fn check(&self, n: usize) -> Result<(), StateError> {
        let nc = n.saturating_sub(1);
        let d = &self.data;
        let lens = [
            ("owner", d.owner.len(), n),
            ("free", d.free.len(), n),
            ("version", d.version.len(), n),
            ("peak", d.peak.len(), n + 1),
            ("last_hard", d.last_hard.len(), n + 1),
            ("stuck", d.stuck.len(), nc),
        ];
        for (name, got, want) in lens {
            if got != want {
                return Err(StateError::Length { name, got, n, want });
            }
        }
        for (slot, c) in self.clusters.iter().enumerate() {
            let Some(ClusterState { data: c, .. }) = c else {
                continue;
            };
            if c.lo >= c.hi || c.hi > n || c.mass.len() != c.hi - c.lo {
                return Err(StateError::Cluster {
                    slot,
                    beads: (c.lo as u64, c.hi as u64),
                    masses: c.mass.len(),
                    n,
                });
            }
        }
        Ok(())
    }
}

/// Why a saved engine state does not fit the run that loads it (a checkpoint of another chain
/// or configuration, or a damaged one): an error, never a panic or a silently different run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StateError {
    /// A per-bead or per-contact array of the hybrid state has the wrong length.
    #[error("hybrid state `{name}` holds {got} entries, a chain of {n} beads needs {want}")]
    Length {
        /// The array.
        name: &'static str,
        /// Its length.
        got: usize,
        /// Beads of the chain.
        n: usize,
        /// The length the chain needs.
        want: usize,
    },
    /// A cluster's beads do not fit the chain.
    #[error(
        "cluster slot {slot}: beads {}..{} with {masses} masses do not fit a chain of {n} beads",
        beads.0,
        beads.1
    )]
    Cluster {
        /// The cluster's slot.
        slot: usize,
        /// Its beads `lo..hi`.
        beads: (u64, u64),
        /// Its mass entries.
        masses: usize,
        /// Beads of the chain.
        n: usize,
    },
    /// An exact pair's trajectory on a contact that does not take the exact path in this run.
    #[error("cluster slot {0}: an exact pair on an ineligible contact")]
    IneligiblePair(usize),
    /// An exact wall contact on a wall that does not take the exact path in this run.
    #[error("cluster slot {0}: an exact wall contact on an ineligible wall")]
    IneligibleWall(usize),
    /// An integrator refused its saved state.
    #[error("cluster slot {slot} (beads {}..{}): {error}", beads.0, beads.1)]
    Integrator {
        /// The cluster's slot.
        slot: usize,
        /// Its beads `lo..hi`.
        beads: (u64, u64),
        /// The integrator's refusal.
        error: LoadError,
    },
    /// The whole-chain integrator (dense engine) refused its saved state.
    #[error("{0}")]
    Dense(LoadError),
}
