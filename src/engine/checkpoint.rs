//! Engine state for checkpoints: everything an engine needs to continue a run so that the
//! resumed run produces bit-identical frames and final state to one never interrupted.
//!
//! Engines ask their [`super::Observer`] between steps whether to checkpoint ([`Control`]);
//! saving is read-only, so a checkpoint never perturbs the run.

use crate::engine::events::EventRecord;
use crate::engine::hybrid::cluster::Pending;
use crate::engine::hybrid::free::Free;
use crate::integrate::IntegratorState;
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
            EngineState::Hybrid(h) => h.t,
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

/// One cluster of the hybrid engine.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ClusterState {
    /// First bead.
    pub lo: u64,
    /// One past the last bead.
    pub hi: u64,
    /// Frame displacement, velocity and reference time.
    pub frame: (f64, f64, f64),
    /// Current time.
    pub t_now: f64,
    /// Pending event.
    pub pending: Option<Pending>,
    /// Integrator masses.
    pub mass: Vec<f64>,
    /// Pinned ends.
    pub pinned: [bool; 2],
    /// Integrator.
    pub integ: IntegratorState,
}

/// A queue entry: key (kind, index) and priority (time, class, tie-break).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct QueueEntry {
    /// 0 frame, 1 cluster, 2 free pair, 3 wall.
    pub kind: u8,
    /// Slot / contact / side.
    pub index: u64,
    /// Time.
    pub t: f64,
    /// Class.
    pub class: u8,
    /// Tie-break.
    pub tie: u64,
}

/// Hybrid engine state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HybridState {
    /// Engine clock (time of the last processed queue entry).
    pub t: f64,
    /// Owner slot per bead (`u32::MAX` = free).
    pub owner: Vec<u32>,
    /// Free-flight states.
    pub free: Vec<Free>,
    /// Bead versions.
    pub version: Vec<u64>,
    /// Cluster slots.
    pub clusters: Vec<Option<ClusterState>>,
    /// Unused slots.
    pub spare_slots: Vec<u32>,
    /// Queue contents (order irrelevant: priorities are unique).
    pub queue: Vec<QueueEntry>,
    /// Peak overlap per contact (`N − 1`), then of the left and right wall contacts.
    pub peak: Vec<f64>,
    /// Counters of removed clusters.
    pub stats: crate::integrate::Stats,
    /// Events logged but not yet handed to the observer (at most about one block: the rest
    /// of the log is already in the output, up to the checkpoint's writer mark).
    pub events: Vec<EventRecord>,
    /// Event counts by kind.
    pub counts: [u64; 5],
    /// Largest cluster so far.
    pub largest: u64,
    /// Steps so far.
    pub steps_total: u64,
    /// Late merges so far.
    pub late_merges: u64,
    /// Implicit steps of the clusters removed so far.
    pub implicit_steps: u64,
    /// Last hard collision per contact / wall.
    pub last_hard: Vec<f64>,
    /// Wall pins.
    pub pinned: [bool; 2],
    /// Resting (sticking) hard contacts.
    pub stuck: Vec<bool>,
    /// Next frame index.
    pub next_frame: u64,
    /// Energy dissipated by cluster integrations that have ended (removed clusters, and the
    /// segments before an integrator restart).
    pub dissipated: f64,
}

impl HybridState {
    /// The consistency check on load: every per-bead and per-contact array fits a chain of `n`
    /// beads, and every cluster covers beads inside it (an inconsistent state is an error,
    /// never a panic or a silently different run).
    pub fn check(&self, n: usize) -> Result<(), String> {
        let nc = n.saturating_sub(1);
        let lens = [
            ("owner", self.owner.len(), n),
            ("free", self.free.len(), n),
            ("version", self.version.len(), n),
            ("peak", self.peak.len(), n + 1),
            ("last_hard", self.last_hard.len(), n + 1),
            ("stuck", self.stuck.len(), nc),
        ];
        for (name, got, want) in lens {
            if got != want {
                return Err(format!(
                    "hybrid state `{name}` holds {got} entries, a chain of {n} beads needs {want}"
                ));
            }
        }
        for (k, c) in self.clusters.iter().enumerate() {
            let Some(c) = c else { continue };
            if c.lo + 2 > c.hi || c.hi > n as u64 || c.mass.len() as u64 != c.hi - c.lo {
                return Err(format!(
                    "cluster slot {k}: beads {}..{} with {} masses do not fit a chain of {n} beads",
                    c.lo,
                    c.hi,
                    c.mass.len()
                ));
            }
        }
        Ok(())
    }
}
