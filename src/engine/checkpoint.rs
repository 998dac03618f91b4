//! Engine state for checkpoints: everything an engine needs to continue a run so that the
//! resumed run produces bit-identical frames and final state to one never interrupted.
//!
//! Engines ask their [`super::Observer`] between steps whether to checkpoint ([`Control`]);
//! saving is read-only, so a checkpoint never perturbs the run.

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
