//! Streaming snapshot writer (layout in the [parent module](super)).
//!
//! Frames and event blocks go straight to a buffered temporary file; only each frame's byte
//! offset and time (16 bytes per frame) and each event block's offset (8 bytes per block of up
//! to [`crate::engine::EVENT_BLOCK`] events) stay in memory for the INDEX and EVENT INDEX
//! sections. Writing a frame allocates nothing: the values are converted to little-endian bytes
//! through a fixed scratch buffer, once to compute the CRC and once to write, so the section
//! header can precede the payload without seeking. An event block is encoded into a reused
//! buffer (no allocation once it has grown to a block's size).
//!
//! The engine hands over every bead's `u` and `v`; the writer stores the beads and fields of
//! the header's [output selection](super::select) only, read from the header again when a run
//! resumes (so a resumed run continues with the same selection).

use super::select::{Fields, Selection};
use super::{
    encode, section_hasher, sync_parent_dir, temp_sibling, EventRecord, Header, RunSummary,
    SnapshotError, FORMAT_VERSION, MAGIC, TAG_END, TAG_EVENT_BLOCK, TAG_EVENT_INDEX, TAG_FRAME,
    TAG_HEADER, TAG_INDEX, TAG_STATS,
};
use crate::files::OutputKind;
use std::fs::{File, OpenOptions};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

mod until;

/// Floats converted per scratch chunk (8 KiB of f64 → 64 KiB of bytes).
const CHUNK_VALUES: usize = 8192;

/// Writes a snapshot file frame by frame; see [`SnapshotWriter::create`].
///
/// The file appears under its final name only when [`SnapshotWriter::finish`] succeeds.
/// Dropping an unfinished writer (an error, a panic unwinding, an early return) deletes the
/// temporary file.
pub struct SnapshotWriter {
    path: PathBuf,
    tmp: PathBuf,
    out: Option<BufWriter<File>>,
    pos: u64,
    n_beads: u64,
    frame_len: u64,
    /// Stored beads (`None`: every bead) and fields.
    beads: Option<Vec<usize>>,
    fields: Fields,
    offsets: Vec<u64>,
    times: Vec<f64>,
    event_blocks: Vec<u64>,
    events_written: u64,
    scratch: Box<[u8]>,
    ev_scratch: Vec<u8>,
    /// Writing in place to a character device or FIFO (no temporary, no rename, no mark).
    stream: bool,
    /// Energy dissipated up to the next frame ([`SnapshotWriter::set_dissipated`]).
    dissipated: f64,
}

impl SnapshotWriter {
    /// Starts a snapshot for `path`: creates the temporary sibling `.<name>.tmp-<pid>-<k>` and
    /// writes the preamble and the HEADER section (with `format_version` set to
    /// [`FORMAT_VERSION`]).
    ///
    /// A character device or FIFO is written in place instead (see [`crate::files`]); a
    /// symbolic link to a file is refused; stale temporaries of dead runs are removed first.
    pub fn create(path: &Path, header: &Header) -> Result<Self, SnapshotError> {
        // Checked before the temporary file exists (an early return would leave it behind).
        let frame_len = frame_len(path, header)?;
        let stream = crate::files::classify_output(path)? == OutputKind::Stream;
        let (tmp, file) = if stream {
            let f = OpenOptions::new()
                .write(true)
                .open(path)
                .map_err(|e| SnapshotError::Io {
                    path: path.to_path_buf(),
                    action: "opening the output stream".into(),
                    source: e,
                })?;
            (PathBuf::new(), f)
        } else {
            super::remove_stale_temps(path);
            let tmp = temp_sibling(path)?;
            let f = OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&tmp)
                .map_err(|e| SnapshotError::Io {
                    path: path.to_path_buf(),
                    action: format!("creating temporary file {}", tmp.display()),
                    source: e,
                })?;
            let _ = f.try_lock(); // held while written: a `resume` of it is refused (`reopen`)
            (tmp, f)
        };
        let mut w = SnapshotWriter {
            path: path.to_path_buf(),
            tmp,
            out: Some(BufWriter::with_capacity(1 << 16, file)),
            pos: 0,
            n_beads: header.n_beads,
            frame_len,
            beads: bead_list(&header.output),
            fields: header.output.fields,
            offsets: Vec::new(),
            times: Vec::new(),
            event_blocks: Vec::new(),
            events_written: 0,
            scratch: vec![0u8; CHUNK_VALUES * 8].into_boxed_slice(),
            ev_scratch: Vec::new(),
            dissipated: 0.0,
            stream,
        };
        let mut h = header.clone();
        h.format_version = FORMAT_VERSION;
        let payload =
            encode(&super::header4::header_record(&h)).map_err(|e| w.encode_err("HEADER", e))?;
        let mut pre = [0u8; 12];
        pre[..8].copy_from_slice(&MAGIC);
        pre[8..].copy_from_slice(&FORMAT_VERSION.to_le_bytes());
        w.write_raw(&pre)?;
        w.write_section(TAG_HEADER, &payload)?;
        Ok(w)
    }

    /// Final path of the snapshot.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Temporary file being written (renamed onto [`Self::path`] by `finish`).
    pub fn temp_path(&self) -> &Path {
        &self.tmp
    }

    /// Appends one frame (time `t`, displacements `u`, velocities `v` of every bead, each
    /// `n_beads` long; the frame stores the selected beads and fields).
    pub fn write_frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), SnapshotError> {
        let n = self.n_beads;
        if u.len() as u64 != n || v.len() as u64 != n {
            return Err(SnapshotError::FrameShape {
                path: self.path.clone(),
                frame: self.offsets.len() as u64,
                expected: n,
                u_len: u.len(),
                v_len: v.len(),
            });
        }
        let number = (self.offsets.len() as u64).to_le_bytes();
        let mut h = section_hasher(TAG_FRAME, self.frame_len);
        h.update(&number);
        let sel = (self.beads.as_deref(), self.fields);
        let lead = [t, self.dissipated];
        for_each_chunk(lead, u, v, sel, &mut self.scratch, |b| {
            h.update(b);
            Ok(())
        })
        .map_err(|e| self.io_err(e))?;
        let offset = self.pos;
        let head = section_header(TAG_FRAME, self.frame_len, h.finalize());
        self.write_raw(&head)?;
        self.write_raw(&number)?;
        self.pos -= 8; // counted again below with the rest of the payload
        let out = self.out.as_mut().ok_or_else(finished_err)?;
        let sel = (self.beads.as_deref(), self.fields);
        for_each_chunk(lead, u, v, sel, &mut self.scratch, |b| out.write_all(b)).map_err(|e| {
            SnapshotError::Io {
                path: self.path.clone(),
                action: format!("writing frame {}", self.offsets.len()),
                source: e,
            }
        })?;
        self.pos += self.frame_len;
        self.offsets.push(offset);
        self.times.push(t);
        Ok(())
    }

    /// The energy dissipated from `t = 0` to the next frame (stored in it; 0 until set, as
    /// for a conservative chain).
    pub fn set_dissipated(&mut self, energy: f64) {
        self.dissipated = energy;
    }

    /// Event blocks written so far.
    pub fn event_blocks_written(&self) -> u64 {
        self.event_blocks.len() as u64
    }

    /// Appends one EVENT BLOCK section holding `events` (nothing when empty). The payload is
    /// encoded into a reused buffer: no allocation once it has grown to a block's size.
    pub fn write_events(&mut self, events: &[EventRecord]) -> Result<(), SnapshotError> {
        if events.is_empty() {
            return Ok(());
        }
        let mut buf = std::mem::take(&mut self.ev_scratch);
        buf.clear();
        buf.extend_from_slice(&self.events_written.to_le_bytes());
        let r = bincode::serde::encode_into_std_write(events, &mut buf, super::bincode_config());
        if let Err(e) = r {
            return Err(self.encode_err("EVENT BLOCK", e));
        }
        let offset = self.pos;
        let w = self.write_section(TAG_EVENT_BLOCK, &buf);
        self.ev_scratch = buf;
        w?;
        self.event_blocks.push(offset);
        self.events_written += events.len() as u64;
        Ok(())
    }

    /// Writes `events` as a last EVENT BLOCK (if any), then EVENT INDEX, STATS, INDEX and END,
    /// flushes, fsyncs and renames the temporary file onto the final path (then syncs the
    /// directory, best effort). On failure the writer is dropped: the temporary file is removed.
    pub fn finish(
        mut self,
        events: &[EventRecord],
        summary: &RunSummary,
    ) -> Result<(), SnapshotError> {
        self.complete(events, summary)
    }

    /// [`Self::finish`], but a failure (a full disk, a directory put at the final path) keeps
    /// the temporary file, closed: a checkpoint on disk continues it (its mark cuts off what
    /// this call appended), so the run can be resumed once the cause is fixed.
    pub fn finish_or_keep(
        mut self,
        events: &[EventRecord],
        summary: &RunSummary,
    ) -> Result<(), SnapshotError> {
        let r = self.complete(events, summary);
        if r.is_err() {
            drop(self.out.take());
            self.tmp = PathBuf::new(); // nothing for Drop to remove
        }
        r
    }

    /// The work of [`Self::finish`]; the temporary file is renamed only when all succeeded.
    fn complete(
        &mut self,
        events: &[EventRecord],
        summary: &RunSummary,
    ) -> Result<(), SnapshotError> {
        self.write_events(events)?;
        let st = encode(summary).map_err(|e| self.encode_err("STATS", e))?;
        let mut evix = Vec::with_capacity(8 + 8 * self.event_blocks.len());
        evix.extend_from_slice(&(self.event_blocks.len() as u64).to_le_bytes());
        for o in &self.event_blocks {
            evix.extend_from_slice(&o.to_le_bytes());
        }
        let events_offset = self.pos;
        self.write_section(TAG_EVENT_INDEX, &evix)?;
        let stats_offset = self.pos;
        self.write_section(TAG_STATS, &st)?;

        let count = self.offsets.len();
        let mut index = Vec::with_capacity(24 + 16 * count);
        index.extend_from_slice(&(count as u64).to_le_bytes());
        index.extend_from_slice(&events_offset.to_le_bytes());
        index.extend_from_slice(&stats_offset.to_le_bytes());
        for o in &self.offsets {
            index.extend_from_slice(&o.to_le_bytes());
        }
        for t in &self.times {
            index.extend_from_slice(&t.to_le_bytes());
        }
        let index_offset = self.pos;
        self.write_section(TAG_INDEX, &index)?;
        self.write_section(TAG_END, &index_offset.to_le_bytes())?;

        let out = self.out.take().ok_or_else(finished_err)?;
        let file = out.into_inner().map_err(|e| SnapshotError::Io {
            path: self.path.clone(),
            action: "flushing snapshot".into(),
            source: e.into_error(),
        })?;
        if self.stream {
            return Ok(()); // written in place: nothing to sync or rename
        }
        file.sync_all().map_err(|e| SnapshotError::Io {
            path: self.path.clone(),
            action: "syncing snapshot to disk".into(),
            source: e,
        })?;
        drop(file);
        std::fs::rename(&self.tmp, &self.path).map_err(|e| SnapshotError::Io {
            path: self.path.clone(),
            action: format!("renaming {} onto it", self.tmp.display()),
            source: e,
        })?;
        // Renamed: nothing left for Drop to clean up.
        self.tmp = PathBuf::new();
        sync_parent_dir(&self.path);
        Ok(())
    }

    fn write_raw(&mut self, b: &[u8]) -> Result<(), SnapshotError> {
        let out = self.out.as_mut().ok_or_else(finished_err)?;
        if let Err(e) = out.write_all(b) {
            return Err(self.io_err(e));
        }
        self.pos += b.len() as u64;
        Ok(())
    }

    fn write_section(&mut self, tag: u32, payload: &[u8]) -> Result<(), SnapshotError> {
        let len = payload.len() as u64;
        let mut h = section_hasher(tag, len);
        h.update(payload);
        self.write_raw(&section_header(tag, len, h.finalize()))?;
        self.write_raw(payload)
    }

    fn io_err(&self, e: std::io::Error) -> SnapshotError {
        SnapshotError::Io {
            path: self.path.clone(),
            action: format!("writing snapshot (temporary file {})", self.tmp.display()),
            source: e,
        }
    }

    fn encode_err(&self, section: &'static str, e: bincode::error::EncodeError) -> SnapshotError {
        SnapshotError::Encode {
            path: self.path.clone(),
            section,
            detail: e.to_string(),
        }
    }
}

/// The snapshot-writing observer: frames, the dissipated energy and event blocks go to the
/// file as the engine hands them over (checkpoints are a separate policy:
/// [`super::sink::SnapshotSink`] wraps a writer and adds one).
impl crate::engine::Observer for SnapshotWriter {
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), crate::engine::EngineError> {
        self.write_frame(t, u, v).map_err(observer_err)
    }

    fn dissipated(&mut self, _t: f64, energy: f64) -> Result<(), crate::engine::EngineError> {
        self.set_dissipated(energy);
        Ok(())
    }

    fn events(&mut self, events: &[EventRecord]) -> Result<(), crate::engine::EngineError> {
        self.write_events(events).map_err(observer_err)
    }
}

/// A snapshot error as an observer's.
pub(super) fn observer_err(e: SnapshotError) -> crate::engine::EngineError {
    crate::engine::EngineError::Observer(e.to_string())
}

impl Drop for SnapshotWriter {
    fn drop(&mut self) {
        if !self.tmp.as_os_str().is_empty() {
            // Close the handle first (required on Windows), then remove the partial file.
            drop(self.out.take());
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

fn finished_err() -> SnapshotError {
    SnapshotError::Output(std::io::Error::other("snapshot writer already finished"))
}

/// The 16-byte section header.
pub(crate) fn section_header(tag: u32, len: u64, crc: u32) -> [u8; 16] {
    let mut b = [0u8; 16];
    b[..4].copy_from_slice(&tag.to_le_bytes());
    b[4..12].copy_from_slice(&len.to_le_bytes());
    b[12..].copy_from_slice(&crc.to_le_bytes());
    b
}

/// The FRAME payload length of `header` (its output selection), or an encoding error.
fn frame_len(path: &Path, header: &Header) -> Result<u64, SnapshotError> {
    let bad = |detail: String| SnapshotError::Encode {
        path: path.to_path_buf(),
        section: "HEADER",
        detail,
    };
    header
        .output
        .check(header.n_beads)
        .map_err(|e| bad(e.to_string()))?;
    (header
        .output
        .frame_payload_len(header.n_beads, FORMAT_VERSION))
    .ok_or_else(|| bad(format!("bead count {} is too large", header.n_beads)))
}

/// The stored bead indices as `usize` (`None`: every bead).
fn bead_list(sel: &Selection) -> Option<Vec<usize>> {
    sel.beads
        .as_ref()
        .map(|b| b.iter().map(|&i| i as usize).collect())
}

/// The stored values of `xs`: none when `on` is false, else every value or those at `beads`.
fn stored<'a>(
    xs: &'a [f64],
    beads: Option<&'a [usize]>,
    on: bool,
) -> impl Iterator<Item = f64> + 'a {
    let (all, pick): (&[f64], &[usize]) = match (on, beads) {
        (false, _) => (&[], &[]),
        (true, None) => (xs, &[]),
        (true, Some(b)) => (&[], b),
    };
    all.iter().copied().chain(pick.iter().map(move |&i| xs[i]))
}

/// Feeds the little-endian bytes of `lead` (`t`, dissipated energy), the stored `u`, the stored `v` (selection `sel`) to
/// `f` in chunks of at most `scratch.len()` bytes (a multiple of 8). Allocates nothing.
fn for_each_chunk(
    lead: [f64; 2],
    u: &[f64],
    v: &[f64],
    (beads, fields): (Option<&[usize]>, Fields),
    scratch: &mut [u8],
    mut f: impl FnMut(&[u8]) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let cap = scratch.len() / 8;
    let mut fill = 0;
    for x in lead
        .into_iter()
        .chain(stored(u, beads, fields.has_u()))
        .chain(stored(v, beads, fields.has_v()))
    {
        scratch[8 * fill..8 * fill + 8].copy_from_slice(&x.to_le_bytes());
        fill += 1;
        if fill == cap {
            f(&scratch[..8 * fill])?;
            fill = 0;
        }
    }
    if fill > 0 {
        f(&scratch[..8 * fill])?;
    }
    Ok(())
}

/// Where an unfinished snapshot stands: enough to reopen its temporary file and continue
/// writing frames after a crash (see [`SnapshotWriter::mark`], [`SnapshotWriter::reopen`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WriterMark {
    /// Final path.
    pub path: PathBuf,
    /// Temporary file holding the sections written so far.
    pub temp: PathBuf,
    /// Bytes of the temporary file that are part of the snapshot.
    pub len: u64,
    /// Beads per frame.
    pub n_beads: u64,
    /// Offsets of the frames written.
    pub offsets: Vec<u64>,
    /// Times of the frames written.
    pub times: Vec<f64>,
    /// Offsets of the event blocks written.
    pub event_blocks: Vec<u64>,
    /// Events written (in those blocks).
    pub events_written: u64,
}

impl SnapshotWriter {
    /// Flushes and fsyncs everything written so far and returns the mark to continue from.
    ///
    /// Paths in the mark are absolute, so `resume` works from any working directory.
    pub fn mark(&mut self) -> Result<WriterMark, SnapshotError> {
        if self.stream {
            return Err(SnapshotError::Io {
                path: self.path.clone(),
                action: "writing a checkpoint".into(),
                source: std::io::Error::other(
                    "the output is a stream (device or pipe), which cannot be resumed",
                ),
            });
        }
        let out = self.out.as_mut().ok_or_else(finished_err)?;
        out.flush().map_err(|e| SnapshotError::Io {
            path: self.path.clone(),
            action: "flushing snapshot".into(),
            source: e,
        })?;
        out.get_ref().sync_data().map_err(|e| SnapshotError::Io {
            path: self.path.clone(),
            action: "syncing snapshot to disk".into(),
            source: e,
        })?;
        let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
        Ok(WriterMark {
            path: abs(&self.path),
            temp: abs(&self.tmp),
            len: self.pos,
            n_beads: self.n_beads,
            offsets: self.offsets.clone(),
            times: self.times.clone(),
            event_blocks: self.event_blocks.clone(),
            events_written: self.events_written,
        })
    }

    /// Reopens the temporary file of an interrupted run, cut back to `mark.len` (frames and event
    /// blocks written after the mark are dropped), to continue writing. Refused while another
    /// writer holds the file's lock (taken by `create` and here, where the file system has
    /// them), so two processes never write one temporary file. The output selection is
    /// read from the file's own HEADER, so the run continues with it.
    pub fn reopen(mark: &WriterMark) -> Result<Self, SnapshotError> {
        let io = |action: &str, e: std::io::Error| SnapshotError::Io {
            path: mark.path.clone(),
            action: format!("{action} {}", mark.temp.display()),
            source: e,
        };
        let file = OpenOptions::new()
            .write(true)
            .open(&mark.temp)
            .map_err(|e| io("reopening the temporary file", e))?;
        if let Err(std::fs::TryLockError::WouldBlock) = file.try_lock() {
            let busy = "another beadchain process is writing it (a run or resume still going)";
            return Err(io("resuming:", std::io::Error::other(busy)));
        }
        let on_disk = file
            .metadata()
            .map_err(|e| io("reading the size of", e))?
            .len();
        if on_disk < mark.len {
            return Err(io(
                "resuming:",
                std::io::Error::other(format!(
                    "the temporary file has {on_disk} bytes, the checkpoint expects {}",
                    mark.len
                )),
            ));
        }
        super::verify::verify_prefix(&mark.temp, mark.len)?;
        file.set_len(mark.len).map_err(|e| io("cutting back", e))?;
        let mut out = BufWriter::with_capacity(1 << 16, file);
        use std::io::Seek;
        out.seek(std::io::SeekFrom::Start(mark.len))
            .map_err(|e| io("seeking in", e))?;
        let header = super::read_header(&mark.temp)?;
        if header.n_beads != mark.n_beads {
            return Err(io(
                "resuming:",
                std::io::Error::other(format!(
                    "the temporary file's header has {} beads, the checkpoint {}",
                    header.n_beads, mark.n_beads
                )),
            ));
        }
        let frame_len = frame_len(&mark.path, &header)?;
        Ok(SnapshotWriter {
            path: mark.path.clone(),
            tmp: mark.temp.clone(),
            out: Some(out),
            pos: mark.len,
            n_beads: mark.n_beads,
            frame_len,
            beads: bead_list(&header.output),
            fields: header.output.fields,
            offsets: mark.offsets.clone(),
            times: mark.times.clone(),
            event_blocks: mark.event_blocks.clone(),
            events_written: mark.events_written,
            scratch: vec![0u8; CHUNK_VALUES * 8].into_boxed_slice(),
            ev_scratch: Vec::new(),
            dissipated: 0.0,
            stream: false,
        })
    }

    /// Closes the writer but keeps its temporary file (an interrupted run that will resume).
    pub fn detach(mut self) -> Result<(), SnapshotError> {
        if let Some(out) = self.out.take() {
            out.into_inner().map_err(|e| SnapshotError::Io {
                path: self.path.clone(),
                action: "flushing snapshot".into(),
                source: e.into_error(),
            })?;
        }
        self.tmp = PathBuf::new();
        Ok(())
    }
}
