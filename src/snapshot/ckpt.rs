//! Checkpoint files (`FILE.ckpt`): what `beadchain resume` needs to continue a run into the
//! same output file with bit-identical results.
//!
//! Layout: magic `b"BEADCKPT"` (8 bytes), format version `u32` LE, payload length `u64` LE,
//! CRC32 of the payload `u32` LE, payload = bincode (fixed-width little-endian integers) of
//! [`CheckpointFile`]. Written atomically (temporary sibling, fsync, rename), so a kill at any
//! moment leaves the previous checkpoint intact.

use super::record::Value;
use super::writer::WriterMark;
use super::{decode_exact, encode, SnapshotError};
use crate::engine::{EngineState, RunConfig};
use crate::scene::Scene;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Magic bytes of a checkpoint file.
pub const CKPT_MAGIC: [u8; 8] = *b"BEADCKPT";
/// Checkpoint format version (2: the engine state holds only the unflushed events, the writer
/// mark the event blocks already written, the clusters' integrators their method-switching
/// state, the hybrid state the resting hard contacts; 3: the scene as a named record, the
/// snapshot it continues of format 4; 4: the hybrid state counts closings at tolerance-level
/// speeds; 5: the hybrid state records which soft walls are logged closed, and its queue holds
/// soft-wall crossings not yet logged; 6: an integrator state may be an exact two-body
/// contact's trajectory; 7: an integrator state is typed per method, `MethodState`; 8: it may be a cluster at
/// rest's, `MethodState::Rest`; 9: the hybrid queue's keys and priorities as the queue holds
/// them; 10: the hybrid state counts shallow integrated collisions).
pub const CKPT_VERSION: u32 = 10;

/// Everything a resumed run needs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CheckpointFile {
    /// The resolved scene (stored as its named record, [`super::header4`]).
    #[serde(with = "super::header4::scene_as_record")]
    pub scene: Scene,
    /// The run configuration.
    pub config: RunConfig,
    /// Whether wall-clock time goes into the snapshot (`--timing`).
    pub timing: bool,
    /// Output snapshot state.
    pub writer: WriterMark,
    /// Engine state.
    pub engine: EngineState,
}

/// The scene of a run's checkpoints as they store it (its named record,
/// [`super::header4::scene_as_record`]), built once per run.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneRecord(Vec<(String, Value)>);

impl SceneRecord {
    /// The record of `scene`.
    pub fn new(scene: &Scene) -> Self {
        Self(super::header4::scene_record(scene))
    }
}

/// A checkpoint by its parts, borrowed from the run that writes it: [`write_checkpoint_parts`]
/// writes the bytes of the [`CheckpointFile`] of the same parts (the same fields in the same
/// order, each encoded as its owned form is) without cloning the engine state, the scene or
/// the configuration.
#[derive(Serialize)]
pub struct CheckpointParts<'a> {
    /// The scene's record.
    pub scene: &'a SceneRecord,
    /// The run configuration.
    pub config: &'a RunConfig,
    /// Whether wall-clock time goes into the snapshot (`--timing`).
    pub timing: bool,
    /// Output snapshot state.
    pub writer: &'a WriterMark,
    /// Engine state.
    pub engine: &'a EngineState,
}

impl Serialize for SceneRecord {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(s)
    }
}

/// Writes a checkpoint atomically.
pub fn write_checkpoint(path: &Path, ck: &CheckpointFile) -> Result<(), SnapshotError> {
    write_payload(path, ck)
}

/// Writes the checkpoint of `parts` atomically: the file [`write_checkpoint`] writes for the
/// [`CheckpointFile`] of the same parts, byte for byte.
pub fn write_checkpoint_parts(path: &Path, parts: &CheckpointParts) -> Result<(), SnapshotError> {
    write_payload(path, parts)
}

/// Writes `ck` as a checkpoint file (module docs) atomically.
fn write_payload<T: Serialize>(path: &Path, ck: &T) -> Result<(), SnapshotError> {
    let payload = encode(ck).map_err(|e| SnapshotError::Encode {
        path: path.to_path_buf(),
        section: "CHECKPOINT",
        detail: e.to_string(),
    })?;
    let mut h = crc32fast::Hasher::new();
    h.update(&payload);
    let crc = h.finalize();
    super::write_atomically(path, |out| {
        let io = |e: std::io::Error| SnapshotError::Output(e);
        out.write_all(&CKPT_MAGIC).map_err(io)?;
        out.write_all(&CKPT_VERSION.to_le_bytes()).map_err(io)?;
        out.write_all(&(payload.len() as u64).to_le_bytes())
            .map_err(io)?;
        out.write_all(&crc.to_le_bytes()).map_err(io)?;
        out.write_all(&payload).map_err(io)
    })
}

/// Reads and checks a checkpoint.
pub fn read_checkpoint(path: &Path) -> Result<CheckpointFile, SnapshotError> {
    let bytes = std::fs::read(path).map_err(|e| SnapshotError::Io {
        path: path.to_path_buf(),
        action: "reading checkpoint".into(),
        source: e,
    })?;
    let corrupt = |detail: String| SnapshotError::Corrupt {
        path: path.to_path_buf(),
        section: "CHECKPOINT".into(),
        offset: 0,
        detail,
    };
    if bytes.len() < 24 || bytes[..8] != CKPT_MAGIC {
        return Err(corrupt(
            "not a beadchain checkpoint (wrong magic bytes)".into(),
        ));
    }
    let version = u32::from_le_bytes(bytes[8..12].try_into().expect("4 bytes"));
    if version != CKPT_VERSION {
        return Err(corrupt(format!(
            "checkpoint format version {version}, this build reads {CKPT_VERSION}"
        )));
    }
    let len = u64::from_le_bytes(bytes[12..20].try_into().expect("8 bytes"));
    let crc = u32::from_le_bytes(bytes[20..24].try_into().expect("4 bytes"));
    let payload = &bytes[24..];
    if payload.len() as u64 != len {
        return Err(corrupt(format!(
            "truncated: {} payload bytes, header says {len}",
            payload.len()
        )));
    }
    let mut h = crc32fast::Hasher::new();
    h.update(payload);
    if h.finalize() != crc {
        return Err(corrupt("checksum mismatch".into()));
    }
    decode_exact(payload).map_err(|e| corrupt(e.to_string()))
}
