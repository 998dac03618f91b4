//! The hybrid engine's state as data, what a checkpoint stores ([`HybridState`]): its plain data
//! ([`HybridData`], which the engine works on directly), each cluster's data with its
//! integrator's typed state ([`ClusterState`]) and the queue's keys and priorities. Saving and
//! restoring are in `state.rs`.

use super::cluster::{ClusterData, ClusterId};
use super::free::Free;
use super::queue::{Key, Prio};
use crate::engine::checkpoint::StateError;
use crate::engine::events::EventRecord;
use crate::integrate::IntegratorState;
use serde::{Deserialize, Serialize};

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
    /// Owner slot per bead ([`ClusterId::FREE`]: free, stored as `u32::MAX`).
    pub owner: Vec<ClusterId>,
    /// Free-flight states.
    pub free: Vec<Free>,
    /// Bead versions.
    pub version: Vec<u64>,
    /// Unused cluster slots.
    pub spare_slots: Vec<ClusterId>,
    /// Largest overlap per contact since it closed (`N − 1` contacts, then the left and right
    /// walls at `N − 1 + side`).
    pub peak: Vec<f64>,
    /// Counters of removed clusters.
    pub stats: crate::integrate::Stats,
    /// Events logged but not yet handed to the observer (at most about one block: the rest
    /// of the log is already in the output, up to the checkpoint's writer mark).
    pub events: Vec<EventRecord>,
    /// Event counts by kind.
    pub counts: crate::engine::events::EventCounts,
    /// Largest cluster so far (beads).
    pub largest: u64,
    /// Steps so far.
    pub steps_total: u64,
    /// Late merges so far.
    pub late_merges: u64,
    /// Closings so far at relative speeds within [`crate::engine::SLOW_CLOSING_FACTOR`] times
    /// the velocity tolerance.
    pub slow_closings: u64,
    /// Integrated closings whose two-body peak overlap is shallow ([`super::eventlog`]).
    pub shallow_closings: u64,
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
