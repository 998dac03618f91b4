//! The front door: what a run needs, in one `use beadchain::prelude::*;` (see the crate docs
//! for a run in ten lines).
//!
//! - a [`Scene`] from a file or a preset ([`scene::load`], [`scene::preset`]);
//! - its [`RunConfig`] (the scene's `[run]` settings, [`RunOverrides`] for a caller's changes);
//! - [`engine::run`] to the end, or [`engine::start`] for an [`Engine`] that advances in pieces
//!   and says why it stopped ([`Stop`]);
//! - an [`Observer`] that watches it: [`Recorder`] in memory, [`SnapshotWriter`] to a file,
//!   several at once as [`Observers`];
//! - the run's [`RunOutcome`], and a finished file read back as a [`Snapshot`].

pub use crate::engine::{
    self, Engine, Observer, Observers, Recorder, RunConfig, RunOutcome, RunOverrides, Stop,
};
pub use crate::integrate::Method;
pub use crate::names::Named;
pub use crate::scene::{self, Scene};
pub use crate::snapshot::{Snapshot, SnapshotWriter};
