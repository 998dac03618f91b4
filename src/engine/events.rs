//! The engine's event log: one record per contact event, in processing order.
//!
//! Engines hand records to their observer in blocks ([`super::Observer::events`]); the snapshot
//! format stores them through bincode (`snapshot` module docs), so any change to the fields
//! here is a snapshot format change.

use crate::names::Named;
use serde::{Deserialize, Serialize};

/// Kind of a contact event.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum EventKind {
    /// A gap between two beads closed (contact starts).
    Close,
    /// A contact between two beads opened (gap appears).
    Open,
    /// An instantaneous hard collision between two beads.
    HardCollision,
    /// A bead touched a wall (a soft wall's contact starts, or the bead bounced off a hard wall).
    WallClose,
    /// A bead left a wall.
    WallOpen,
}

impl Named for EventKind {
    const WHAT: &'static str = "event kind";
    /// In the order of [`EventKind::index`].
    const ALL: &'static [Self] = &[
        EventKind::Close,
        EventKind::Open,
        EventKind::HardCollision,
        EventKind::WallClose,
        EventKind::WallOpen,
    ];
    /// The name used in exported files (`close`, `open`, `hard_collision`, `wall_close`,
    /// `wall_open`).
    fn name(self) -> &'static str {
        match self {
            EventKind::Close => "close",
            EventKind::Open => "open",
            EventKind::HardCollision => "hard_collision",
            EventKind::WallClose => "wall_close",
            EventKind::WallOpen => "wall_open",
        }
    }
}
crate::display_and_from_str!(EventKind);

impl EventKind {
    /// Number of kinds.
    pub const COUNT: usize = 5;

    /// Position in [`Named::ALL`] (and in [`EventCounts`]).
    pub fn index(self) -> usize {
        match self {
            EventKind::Close => 0,
            EventKind::Open => 1,
            EventKind::HardCollision => 2,
            EventKind::WallClose => 3,
            EventKind::WallOpen => 4,
        }
    }

    /// A gap or wall contact starting (`close`, `wall_close`).
    pub fn is_closing(self) -> bool {
        matches!(self, EventKind::Close | EventKind::WallClose)
    }
}

/// Number of events of each kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct EventCounts(pub [u64; EventKind::COUNT]);

impl EventCounts {
    /// Events of kind `k`.
    pub fn get(&self, k: EventKind) -> u64 {
        self.0[k.index()]
    }

    /// Counts one event of kind `k`.
    pub fn add(&mut self, k: EventKind) {
        self.0[k.index()] += 1;
    }

    /// Every kind with its count, in [`Named::ALL`] order.
    pub fn iter(&self) -> impl Iterator<Item = (EventKind, u64)> + '_ {
        EventKind::ALL.iter().map(|&k| (k, self.get(k)))
    }

    /// All events.
    pub fn total(&self) -> u64 {
        self.0.iter().sum()
    }

    /// Gap and wall closings.
    pub fn closings(&self) -> u64 {
        self.iter()
            .filter(|(k, _)| k.is_closing())
            .map(|(_, c)| c)
            .sum()
    }

    /// As the snapshot's run summary stores them: `(name, count)` for every kind.
    pub fn named(&self) -> Vec<(String, u64)> {
        self.iter()
            .map(|(k, c)| (k.name().to_string(), c))
            .collect()
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
