//! Output selection of a snapshot: what its frames store ([`Selection`], defined with the scene
//! settings in [`crate::scene::selection`], whose docs give the grammar and the frame layout),
//! and the checks readers make on it.

pub use crate::scene::selection::{parse_beads, Fields, Selection, SelectionError};

use super::{Snapshot, SnapshotError};

impl Snapshot {
    /// What the frames of this snapshot store.
    pub fn selection(&self) -> &Selection {
        &self.header().output
    }

    /// Errors unless the frames store every bead and both fields; `need` says who needs them
    /// (`"analyze needs every bead and both fields (energies)"`).
    pub fn require_full(&self, need: &str) -> Result<(), SnapshotError> {
        let s = self.selection();
        if s.is_full() {
            return Ok(());
        }
        Err(SnapshotError::Partial {
            path: self.path().to_path_buf(),
            detail: format!(
                "frames store {} only (run --beads/--fields); {need}",
                s.describe(self.header().n_beads)
            ),
        })
    }
}
