//! Binary snapshot files: header, frames, event log and run statistics of one run.
//!
//! A snapshot stores the resolved scene (the chain of paper eqs. 1 and 6–7 with its initial
//! state), the engine settings, a sequence of *frames* — the state `z = (u, v)` of appendix
//! eq. A.3 for every bead at the output times — the event log and the run statistics.
//! [`SnapshotWriter`] streams frames to disk as a run produces them; [`Snapshot`] opens a file
//! and reads any frame by seeking, without loading the others.
//!
//! # Byte layout (format version 4; versions 1 to 3 differences below)
//!
//! All integers are fixed-width little-endian (never `usize` on disk); all floats are IEEE-754
//! binary64 little-endian.
//!
//! ```text
//! offset  size  field
//! 0       8     magic  b"BEADCHN\0"
//! 8       4     format version, u32 (= 4)
//! 12      ...   sections, back to back
//! ```
//!
//! Every section is a 16-byte section header followed by its payload:
//!
//! ```text
//! 0       4     tag, u32: four ASCII bytes read as u32 LE ("HEAD", "FRAM", ...)
//! 4       8     payload length L, u64
//! 12      4     CRC-32 (ISO-HDLC, as zlib/crc32fast) of  tag bytes ‖ length bytes ‖ payload
//! 16      L     payload
//! ```
//!
//! The checksum covers the tag and the length as well as the payload, so a damaged length that
//! still points inside the file is caught as a checksum mismatch of that section.
//!
//! | tag    | section | payload |
//! |--------|---------|---------|
//! | `HEAD` | HEADER  | bincode of the named record of [`Header`]: `Vec<(String, `[`record::Value`]`)>`, keys in [`header4`] (see *bincode* below). Exactly once, first. |
//! | `FRAM` | FRAME   | frame number `k` u64 (0, 1, 2, … in file order), then `t` f64, then the energy `E_d` f64 dissipated by damped contacts and hard collisions from `t = 0` (0 for a conservative chain), then `u[i]` f64 for every stored bead `i`, then `v[i]` f64 for every stored bead (raw LE, no bincode); a field not stored is left out. `L = 24 + 8 M F` exactly for `M` stored beads and `F` stored fields ([`Header::output`], see [`select`]); every bead and both fields (`L = 24 + 16 N`, `N = Header::n_beads`) unless the run selected fewer. Zero or more, in time order. The number lets a reader reject frames that were moved, duplicated or dropped even where no INDEX survives. |
//! | `EVTB` | EVENT BLOCK | `first` u64 (the log index of the block's first event: the number of events in the blocks before it), then bincode of `Vec<`[`EventRecord`]`>` (not empty): the next events of the log, in processing order. Zero or more, between the frames. The number lets a reader reject blocks that were moved, duplicated or dropped. |
//! | `EVIX` | EVENT INDEX | `count` u64, then `count` × u64 byte offsets of the EVENT BLOCK sections in file order. `L = 8 + 8 count`. |
//! | `STAT` | STATS   | bincode of [`RunSummary`]. |
//! | `INDX` | INDEX   | `count` u64, `events_offset` u64 (of the EVENT INDEX), `stats_offset` u64, then `count` × u64 byte offsets of the FRAME sections (offset of their tag), then `count` × f64 frame times. `L = 24 + 16 count`. An offset of 0 means "section absent". |
//! | `END\0`| END     | `index_offset` u64: byte offset of the INDEX section. Always the last 24 bytes of a finished file. |
//!
//! The writer emits `HEADER (FRAME | EVENT BLOCK)* EVENT INDEX STATS INDEX END`. The event log
//! is the concatenation of the EVENT BLOCKs in file order. The engine hands its events over in
//! blocks of at most [`crate::engine::EVENT_BLOCK`] and before every frame, and the writer
//! appends each block at once, so neither holds the whole log: a run's memory does not grow
//! with its number of events, and an unfinished file holds the events up to its last block.
//!
//! *Version 3* (still read): the HEADER is bincode of the internal `Header` (with the `Scene`
//! and `Chain` structs of that version, frozen in `header.rs`; the SI scales of a physical scene
//! only in its description, to seven significant digits), and a FRAME has no `E_d`
//! (`L = 16 + 8 M F`). Golden file `data/golden/v3_selection.snap`.
//!
//! *Version 2* (still read): the HEADER has no `output` field (bincode of the version-3
//! header without its last field), and the `Chain` inside it has no `damping` field
//! (dissipative contact laws came with version 3); its frames hold every bead and both fields.
//! Decoded in `header.rs` (frozen layouts); golden file `data/golden/v2.snap`.
//!
//! *Version 1* (still read): as version 2, and no EVENT BLOCK or EVENT INDEX sections; the whole log is one
//! `EVNT` (EVENTS) section, bincode of `Vec<`[`EventRecord`]`>` (possibly empty), written after
//! the last frame, and `events_offset` of the INDEX points to it.
//!
//! *bincode*: `bincode` 2.0.1 through serde with
//! `config::standard().with_fixed_int_encoding().with_little_endian()`: integers fixed width LE,
//! `String`/`Vec` prefixed by a u64 length, `Option` by a u8 (0/1), enums by a u32 variant index,
//! struct fields in declaration order with no names. The payload must be consumed exactly.
//! The HEADER's record names its keys, so a field added to `Scene` or `Chain` needs a key
//! ([`header4`] destructures every struct, so it does not compile until it has one) and a
//! reader of an older build refuses the unknown key. [`EventRecord`] and [`RunSummary`]
//! (including `Stats`) are still stored by field order: any change to their field lists is a
//! format change: bump [`FORMAT_VERSION`] and keep a decoder for the old layout, proven by the
//! golden files in `data/golden/`.
//!
//! # Reading rules
//!
//! - Wrong magic (or a file shorter than the magic) → [`SnapshotError::NotSnapshot`]; a version
//!   of 0 or above [`FORMAT_VERSION`] → [`SnapshotError::UnsupportedVersion`].
//! - A finished file is opened from its tail: END (last 24 bytes) → INDEX → EVENT INDEX and its
//!   EVENT BLOCKs (version 1: EVENTS) and STATS.
//!   Frames are not read at open; [`Snapshot::frame`] seeks to one frame and verifies its
//!   section header, length, checksum and (against the INDEX) its time.
//! - If END or INDEX is missing or damaged (a run that never finished, a truncated copy), the
//!   reader scans the sections from the start, verifying every checksum, keeps every whole frame
//!   and records in [`Snapshot::warnings`] where and why it stopped.
//! - Lengths are validated before anything is allocated: a section must fit in the rest of the
//!   file, a FRAME must be exactly its selection's length (`24 + 16 N` bytes for every bead),
//!   an INDEX exactly `24 + 16 count`, and
//!   bincode decoding runs under a byte limit proportional to the payload size. A corrupted
//!   length is an error ([`SnapshotError::AbsurdLength`]), never a huge allocation. A HEADER
//!   whose output selection is not a strictly increasing bead list below `N` is corrupt.
//! - A finished version-2 file reads its event log through the EVENT INDEX: every block it lists
//!   must be an EVENT BLOCK section, in file order, before the EVENT INDEX; during a scan the
//!   blocks are read as met, and a whole EVENT INDEX must list exactly the blocks scanned before
//!   it, or the file is an error ([`SnapshotError::Corrupt`]).
//! - Checksum mismatches in HEADER, FRAME, EVENTS, EVENT BLOCK or STATS (and in an EVENT INDEX
//!   the INDEX points to) are errors naming the section
//!   ([`SnapshotError::ChecksumMismatch`]); INDEX and END only hold derived data, so damage there
//!   is a warning and the file is rescanned. During a scan, an INDEX, END or unknown-tag section
//!   that fails its checksum ends the scan with a warning (it may be a frame whose tag was
//!   damaged, and skipping it would renumber the frames after it); an unknown tag with a valid
//!   checksum is skipped with a warning, so optional sections can be added later without a
//!   version bump.
//! - During a scan, frame times must increase strictly, and a whole INDEX met on the way must
//!   list exactly the frames scanned before it (count and time bits); otherwise sections were
//!   duplicated, removed or reordered and the file is an error ([`SnapshotError::Corrupt`]),
//!   since numbering on would put numbers at the wrong frame index. (A frame section removed
//!   whole from a file without INDEX remains undetectable: frames carry no index of their own.)
//! - The guarantee, tested by flipping every byte of small files: the reader returns an error
//!   or the original numbers at their original frame numbers, never a wrong number.
//!
//! # Writing rules
//!
//! The writer streams into a temporary sibling `.<name>.tmp-<pid>-<k>` and only renames it onto
//! the target after `fsync`, so a failed or killed run never leaves a half-written file under the
//! requested name; dropping an unfinished writer deletes the temporary file. Stale temporaries of
//! dead processes are removed first, a character device or FIFO is written in place, a symbolic
//! link is refused (rules in [`crate::files`]).

mod atomic;
pub mod ckpt;
mod header;
pub mod header4;
mod reader;
pub mod record;
pub mod select;
pub mod sink;
pub mod size;
mod verify;
mod writer;

pub use atomic::write_atomically;
pub use header::read_header;
pub use reader::Snapshot;
pub use select::{Fields, Selection};
pub use sink::{CheckpointPolicy, SnapshotSink};
pub use writer::{SnapshotWriter, WriterMark};
// The event log's records are the engine's; the format stores them as they are.
pub use crate::engine::events::{EventKind, EventRecord};

use crate::integrate::{Method, Stats};
use crate::scene::{Engine, Scene};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// The 8 magic bytes every snapshot starts with.
pub const MAGIC: [u8; 8] = *b"BEADCHN\0";
/// Format version written by this build (and the newest it reads; versions 1 and 2 are still
/// read).
pub const FORMAT_VERSION: u32 = 4;
/// Bytes before the first section: magic + version.
pub const PREAMBLE_LEN: u64 = 12;
/// Bytes of a section header: tag + length + CRC.
pub const SECTION_HEADER_LEN: u64 = 16;
/// Total bytes of the END section (header + 8-byte payload), always the file's tail.
pub const END_SECTION_LEN: u64 = SECTION_HEADER_LEN + 8;

/// Section tag of the HEADER section (`"HEAD"`).
pub const TAG_HEADER: u32 = u32::from_le_bytes(*b"HEAD");
/// Section tag of a FRAME section (`"FRAM"`).
pub const TAG_FRAME: u32 = u32::from_le_bytes(*b"FRAM");
/// Section tag of the EVENTS section of format version 1 (`"EVNT"`).
pub const TAG_EVENTS: u32 = u32::from_le_bytes(*b"EVNT");
/// Section tag of an EVENT BLOCK section (`"EVTB"`, format version 2).
pub const TAG_EVENT_BLOCK: u32 = u32::from_le_bytes(*b"EVTB");
/// Section tag of the EVENT INDEX section (`"EVIX"`, format version 2).
pub const TAG_EVENT_INDEX: u32 = u32::from_le_bytes(*b"EVIX");
/// Section tag of the STATS section (`"STAT"`).
pub const TAG_STATS: u32 = u32::from_le_bytes(*b"STAT");
/// Section tag of the INDEX section (`"INDX"`).
pub const TAG_INDEX: u32 = u32::from_le_bytes(*b"INDX");
/// Section tag of the END section (`"END\0"`).
pub const TAG_END: u32 = u32::from_le_bytes(*b"END\0");

/// Human-readable name of a section tag (as used in error messages).
pub fn section_name(tag: u32) -> &'static str {
    match tag {
        TAG_HEADER => "HEADER",
        TAG_FRAME => "FRAME",
        TAG_EVENTS => "EVENTS",
        TAG_EVENT_BLOCK => "EVENT BLOCK",
        TAG_EVENT_INDEX => "EVENT INDEX",
        TAG_STATS => "STATS",
        TAG_INDEX => "INDEX",
        TAG_END => "END",
        _ => "unknown",
    }
}

/// Run metadata stored once at the start of a snapshot.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Header {
    /// Format version of the file (the writer always stores [`FORMAT_VERSION`]).
    pub format_version: u32,
    /// Version of the beadchain crate that wrote the file.
    pub crate_version: String,
    /// The scene as resolved (every array expanded).
    pub scene: Scene,
    /// Engine that produced the frames.
    pub engine: Engine,
    /// Integration method.
    pub method: Method,
    /// Relative tolerance used.
    pub rtol: f64,
    /// Absolute tolerance used (relative to the run's scales).
    pub atol: f64,
    /// Seed of the scene's random generators.
    pub seed: u64,
    /// Number of beads `N` of every frame.
    pub n_beads: u64,
    /// The command line that produced the file.
    pub created_by: String,
    /// What the frames store: beads, fields, frame cap (format version 3; older files hold
    /// every bead and both fields). See [`select`].
    pub output: Selection,
    /// Git commit the writing beadchain was built from ([`crate::provenance::BUILD_COMMIT`]);
    /// `None` in files written before it was recorded, or with `BEADCHAIN_NO_BUILD_COMMIT=1`.
    pub build_commit: Option<String>,
    /// When the run started, UTC, `YYYY-MM-DDTHH:MM:SSZ`; only runs that record timing
    /// (`run --timing`) store it, so two plain runs give identical bytes.
    pub created_at: Option<String>,
}

impl Header {
    /// A header for `scene`, filling format/crate version, build commit
    /// ([`crate::provenance::recorded_commit`]), seed and bead count from it (no `created_at`).
    pub fn new(
        scene: Scene,
        engine: Engine,
        method: Method,
        rtol: f64,
        atol: f64,
        created_by: String,
    ) -> Self {
        Header {
            format_version: FORMAT_VERSION,
            crate_version: env!("CARGO_PKG_VERSION").to_string(),
            build_commit: crate::provenance::recorded_commit(),
            created_at: None,
            seed: scene.seed,
            n_beads: scene.chain.len() as u64,
            scene,
            engine,
            method,
            rtol,
            atol,
            created_by,
            output: Selection::default(),
        }
    }
}

/// One output state: time and displacement/velocity of every bead.
///
/// Read from a snapshot with an [output selection](select), `u` and `v` hold the stored beads
/// only (in the order of [`Selection::beads`]), and a field that is not stored is empty.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Frame {
    /// Time (computer units).
    pub t: f64,
    /// Displacements `u_i`, length `N` (or the stored beads; empty when not stored).
    pub u: Vec<f64>,
    /// Velocities `v_i`, length `N` (or the stored beads; empty when not stored).
    pub v: Vec<f64>,
    /// Energy dissipated by damped contacts and hard collisions from `t = 0` to `t` (format version 4; 0 for a
    /// conservative chain; `None` in older files, which did not store it).
    pub dissipated: Option<f64>,
}

/// The note of a [`RunSummary`] whose wall time was not stored (`run` without `--timing`; its
/// `wall_seconds` is then 0).
pub const WALL_NOT_RECORDED: &str =
    "wall time not recorded (identical inputs give identical bytes; see --timing)";

/// Statistics of a finished run.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RunSummary {
    /// Integrator counters (summed over clusters).
    pub stats: Stats,
    /// Wall-clock time of the run in seconds (0 when not recorded: [`WALL_NOT_RECORDED`]).
    pub wall_seconds: f64,
    /// Time the run stopped at.
    pub t_end: f64,
    /// Total energy at the start.
    pub energy_initial: f64,
    /// Total energy at the end.
    pub energy_final: f64,
    /// Total momentum at the start.
    pub momentum_initial: f64,
    /// Total momentum at the end.
    pub momentum_final: f64,
    /// Number of events per kind name.
    pub events_by_kind: Vec<(String, u64)>,
    /// Largest contact cluster seen (beads).
    pub largest_cluster: u64,
    /// Free-text notes (warnings of the run).
    pub notes: Vec<String>,
}

/// Errors reading or writing snapshots and exports. Every message is one line naming the file.
#[derive(Debug, thiserror::Error)]
pub enum SnapshotError {
    /// An operating-system I/O error.
    #[error("{}: {action}: {source}", path.display())]
    Io {
        /// File concerned.
        path: PathBuf,
        /// What was being done.
        action: String,
        /// Underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The file does not start with [`MAGIC`].
    #[error("{}: not a beadchain snapshot (wrong magic bytes)", path.display())]
    NotSnapshot {
        /// File concerned.
        path: PathBuf,
    },
    /// The format version is newer than this build (or invalid).
    #[error("{}: {}", path.display(), version_message(*found))]
    UnsupportedVersion {
        /// File concerned.
        path: PathBuf,
        /// Version found in the file.
        found: u32,
    },
    /// The file ends before a required part.
    #[error("{}: truncated: {detail}", path.display())]
    Truncated {
        /// File concerned.
        path: PathBuf,
        /// What was missing, and where.
        detail: String,
    },
    /// A section's checksum does not match its contents.
    #[error("{}: checksum mismatch in section {section} at byte {offset}", path.display())]
    ChecksumMismatch {
        /// File concerned.
        path: PathBuf,
        /// Section name (`FRAME #k` for frames).
        section: String,
        /// Byte offset of the section header.
        offset: u64,
    },
    /// A length field that cannot be right (beyond the end of the file, or not the size the
    /// section must have).
    #[error("{}: absurd length in section {section} at byte {offset}: {detail}", path.display())]
    AbsurdLength {
        /// File concerned.
        path: PathBuf,
        /// Section name.
        section: String,
        /// Byte offset of the section header.
        offset: u64,
        /// The length and the limit it broke.
        detail: String,
    },
    /// A structurally invalid section (wrong tag where one is required, undecodable payload).
    #[error("{}: corrupt section {section} at byte {offset}: {detail}", path.display())]
    Corrupt {
        /// File concerned.
        path: PathBuf,
        /// Section name.
        section: String,
        /// Byte offset of the section header.
        offset: u64,
        /// What is wrong.
        detail: String,
    },
    /// A frame index beyond the frames stored.
    #[error("{}: frame {index} out of range (the snapshot has {count} frames)", path.display())]
    FrameOutOfRange {
        /// File concerned.
        path: PathBuf,
        /// Requested frame.
        index: usize,
        /// Frames available.
        count: usize,
    },
    /// The snapshot holds no frames but one was requested.
    #[error("{}: the snapshot has no frames", path.display())]
    NoFrames {
        /// File concerned.
        path: PathBuf,
    },
    /// A frame handed to the writer has the wrong number of beads.
    #[error(
        "{}: frame {frame} has {u_len} displacements and {v_len} velocities, expected {expected} each",
        path.display()
    )]
    FrameShape {
        /// Output file.
        path: PathBuf,
        /// Index the frame would have had.
        frame: u64,
        /// Beads in the header.
        expected: u64,
        /// Length of `u`.
        u_len: usize,
        /// Length of `v`.
        v_len: usize,
    },
    /// Serialising a section failed.
    #[error("{}: encoding section {section}: {detail}", path.display())]
    Encode {
        /// Output file.
        path: PathBuf,
        /// Section name.
        section: &'static str,
        /// Encoder message.
        detail: String,
    },
    /// Writing to an output stream failed (no path known yet; [`write_atomically`]
    /// turns this into [`SnapshotError::Io`] naming its file).
    #[error("writing output: {0}")]
    Output(#[from] std::io::Error),
    /// The frames lack beads or fields a reader needs (an output selection, see [`select`]).
    #[error("{}: {detail}", path.display())]
    Partial {
        /// File concerned.
        path: PathBuf,
        /// What is stored and who needs what.
        detail: String,
    },
    /// The output path is refused (a symbolic link; see [`crate::files::classify_output`]).
    #[error(transparent)]
    Refused(#[from] crate::files::OutputError),
}

fn version_message(found: u32) -> String {
    if found > FORMAT_VERSION {
        format!(
            "snapshot format version {found} is newer than this beadchain {} supports \
             (versions 1 to {FORMAT_VERSION}); upgrade beadchain",
            env!("CARGO_PKG_VERSION")
        )
    } else {
        format!("unsupported snapshot format version {found} (valid versions are 1 to {FORMAT_VERSION})")
    }
}

/// Why a bincode payload could not be decoded (the detail of a corrupt section).
#[derive(Debug, thiserror::Error)]
pub enum DecodeError {
    /// The decoder failed.
    #[error(transparent)]
    Bincode(#[from] bincode::error::DecodeError),
    /// Bytes left after the value.
    #[error("{0} trailing bytes after the encoded value")]
    Trailing(usize),
}

/// The bincode configuration of every bincode-encoded section.
pub(crate) fn bincode_config() -> bincode::config::Configuration<
    bincode::config::LittleEndian,
    bincode::config::Fixint,
    bincode::config::NoLimit,
> {
    bincode::config::standard()
        .with_fixed_int_encoding()
        .with_little_endian()
}

/// Encodes a value with the snapshot bincode configuration.
pub(crate) fn encode<T: Serialize>(value: &T) -> Result<Vec<u8>, bincode::error::EncodeError> {
    bincode::serde::encode_to_vec(value, bincode_config())
}

/// Decodes a whole payload (every byte must be consumed) under an allocation limit of about
/// 16× the payload size, so a forged length prefix inside the payload cannot allocate much more
/// memory than the file holds.
pub(crate) fn decode_exact<T: serde::de::DeserializeOwned>(bytes: &[u8]) -> Result<T, DecodeError> {
    fn dec<T: serde::de::DeserializeOwned, const L: usize>(
        b: &[u8],
    ) -> Result<(T, usize), bincode::error::DecodeError> {
        bincode::serde::decode_from_slice(b, bincode_config().with_limit::<L>())
    }
    let n = bytes.len();
    let r = if n <= 1 << 16 {
        dec::<T, { 1 << 20 }>(bytes)
    } else if n <= 1 << 20 {
        dec::<T, { 1 << 24 }>(bytes)
    } else if n <= 1 << 24 {
        dec::<T, { 1 << 28 }>(bytes)
    } else {
        decode_large::<T>(bytes)
    };
    let (value, used) = r?;
    if used != n {
        return Err(DecodeError::Trailing(n - used));
    }
    Ok(value)
}

#[cfg(target_pointer_width = "64")]
fn decode_large<T: serde::de::DeserializeOwned>(
    b: &[u8],
) -> Result<(T, usize), bincode::error::DecodeError> {
    let c = bincode_config();
    if b.len() <= 1 << 28 {
        bincode::serde::decode_from_slice(b, c.with_limit::<{ 1 << 32 }>())
    } else if b.len() <= 1 << 32 {
        bincode::serde::decode_from_slice(b, c.with_limit::<{ 1 << 36 }>())
    } else {
        bincode::serde::decode_from_slice(b, c.with_limit::<{ 1 << 40 }>())
    }
}

#[cfg(not(target_pointer_width = "64"))]
fn decode_large<T: serde::de::DeserializeOwned>(
    b: &[u8],
) -> Result<(T, usize), bincode::error::DecodeError> {
    bincode::serde::decode_from_slice(b, bincode_config().with_limit::<{ usize::MAX }>())
}

/// CRC of a section: over tag and length bytes, then the payload (fed by the caller).
pub(crate) fn section_hasher(tag: u32, len: u64) -> crc32fast::Hasher {
    let mut h = crc32fast::Hasher::new();
    h.update(&tag.to_le_bytes());
    h.update(&len.to_le_bytes());
    h
}

/// A fresh temporary sibling path `.<name>.tmp-<pid>-<k>` for atomic writes to `path`.
pub(crate) fn temp_sibling(path: &Path) -> Result<PathBuf, SnapshotError> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let name = path.file_name().ok_or_else(|| SnapshotError::Io {
        path: path.to_path_buf(),
        action: "choosing the output file".into(),
        source: std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name"),
    })?;
    let k = COUNTER.fetch_add(1, Ordering::Relaxed);
    let tmp = format!(".{}.tmp-{}-{k}", name.to_string_lossy(), std::process::id());
    Ok(path.with_file_name(tmp))
}

/// Makes a rename durable by syncing the parent directory (best effort; Unix only).
pub(crate) fn sync_parent_dir(path: &Path) {
    #[cfg(unix)]
    {
        let parent = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        if let Ok(d) = std::fs::File::open(parent) {
            let _ = d.sync_all();
        }
    }
    #[cfg(not(unix))]
    let _ = path;
}

/// Removes the stale temporaries of `path` ([`crate::files::remove_stale_temps`]) but the one
/// that `<path>.ckpt` continues; removes nothing when that checkpoint exists but cannot be read.
pub fn remove_stale_temps(path: &Path) -> Vec<PathBuf> {
    match checkpoint_temp(path) {
        Some(keep) => crate::files::remove_stale_temps(path, keep.as_deref()),
        None => Vec::new(),
    }
}

/// File name of the temporary that `<path>.ckpt` continues: `Some(None)` without a checkpoint,
/// `None` when the checkpoint exists but cannot be read.
fn checkpoint_temp(path: &Path) -> Option<Option<String>> {
    let mut ck = path.as_os_str().to_owned();
    ck.push(".ckpt");
    let ck = PathBuf::from(ck);
    if !ck.exists() {
        return Some(None);
    }
    let file = ckpt::read_checkpoint(&ck).ok()?;
    let name = file.writer.temp.file_name()?.to_str()?.to_string();
    Some(Some(name))
}
