//! Studies of a chain that are not time integrations, and the special initial states the scene
//! layer builds with them (docs/studies.md):
//!
//! - [`solitary`]: the exact travelling (solitary) wave of the discrete sonic-vacuum chain;
//! - [`modes`]: linear modes about a state; [`modal`]: the energy per mode of a state (FPUT);
//!   [`bands`]: the band structure of a periodic chain;
//! - [`equilibrium`]: the static equilibrium under walls, fields and imposed wall forces.
//!
//! Layer 2 (`tests/layering.rs`): it imports only [`crate::model`] and [`crate::linalg`] (and
//! faer), so that scene parsing (layer 3) can build an initial state from a solitary wave, at
//! equilibrium or along a mode.

pub mod bands;
pub mod equilibrium;
pub mod modal;
pub mod modes;
pub mod solitary;

/// An error of a study: one line, naming the bead, contact or wall it is about.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct StudyError(pub String);

impl StudyError {
    pub(crate) fn new(msg: impl Into<String>) -> Self {
        Self(msg.into())
    }
}
