//! Studies of a chain that are not time integrations: its linear modes about a state
//! ([`modes`]), the band structure of a periodic chain ([`bands`]) and its static equilibrium
//! ([`equilibrium`]).
//!
//! Layer 2 (`tests/layering.rs`): it imports only [`crate::model`] (and faer), so that scene
//! parsing (layer 3) can build an initial state at equilibrium or along a mode.

pub mod bands;
pub mod equilibrium;
pub mod modes;

/// An error of a study: one line, naming the bead, contact or wall it is about.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct StudyError(pub String);

impl StudyError {
    pub(crate) fn new(msg: impl Into<String>) -> Self {
        Self(msg.into())
    }
}
