//! The engine's event log: one record per contact event, in processing order.
//!
//! Engines hand records to their observer in blocks ([`super::Observer::events`]); the snapshot
//! format stores them through bincode (`snapshot` module docs), so any change to the fields
//! here is a snapshot format change.

use serde::{Deserialize, Serialize};

/// Kind of a contact event.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum EventKind {
    /// A gap between two beads closed (contact starts).
    Close,
    /// A contact between two beads opened (gap appears).
    Open,
    /// An instantaneous hard collision.
    HardCollision,
    /// A bead touched a wall.
    WallClose,
    /// A bead left a wall.
    WallOpen,
}

impl EventKind {
    /// The name used in exported files (`close`, `open`, `hard_collision`, `wall_close`,
    /// `wall_open`).
    pub fn name(self) -> &'static str {
        match self {
            EventKind::Close => "close",
            EventKind::Open => "open",
            EventKind::HardCollision => "hard_collision",
            EventKind::WallClose => "wall_close",
            EventKind::WallOpen => "wall_open",
        }
    }
}

/// One entry of the event log.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EventRecord {
    /// Event time.
    pub t: f64,
    /// Contact index `c` (between beads `c` and `c+1`; for wall events the bead index).
    pub contact: u64,
    /// What happened.
    pub kind: EventKind,
    /// Relative (approach) velocity at the event.
    pub rel_velocity: f64,
    /// Largest overlap the contact reached while closed (0 for a closing event).
    pub peak_overlap: f64,
}
