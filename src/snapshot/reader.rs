//! Snapshot reader: opens a file from its INDEX (or by scanning when the file is unfinished or
//! damaged) and reads single frames by seeking. Rules in the [parent module](super).

use super::{
    decode_exact, section_name, EventRecord, Frame, Header, RunSummary, SnapshotError,
    FORMAT_VERSION, MAGIC, PREAMBLE_LEN, SECTION_HEADER_LEN, TAG_END, TAG_EVENTS, TAG_EVENT_BLOCK,
    TAG_EVENT_INDEX, TAG_FRAME, TAG_HEADER, TAG_INDEX, TAG_STATS,
};
use events::check_scan_against_event_index;
use frames::{check_scan_against_index, read_frame_at};
use std::fs::File;

mod events;
mod frames;
mod raw;
mod tail;

use raw::{le_u64, read_up_to, seek, Raw};
use std::path::Path;
use std::sync::Mutex;
use tail::from_tail;

/// Bytes read per chunk when streaming a frame payload.
const CHUNK: usize = 1 << 16;

/// Section lengths at or above this (256 TiB) are corruption, never a truncated file.
const MAX_PLAUSIBLE_LEN: u64 = 1 << 48;

/// An open snapshot file. Frames are read on demand; everything else is loaded at open.
#[derive(Debug)]
pub struct Snapshot {
    raw: Raw,
    header: Header,
    frame_len: u64,
    /// Values of `u` and of `v` per frame (the output selection).
    shape: Shape,
    offsets: Vec<u64>,
    times: Vec<f64>,
    events: Vec<EventRecord>,
    summary: Option<RunSummary>,
    complete: bool,
    warnings: Vec<String>,
}

/// Numbers of stored `u` and `v` values per frame.
type Shape = (usize, usize);

/// A parsed section header.
#[derive(Clone, Copy, Debug)]
struct SectionHead {
    offset: u64,
    tag: u32,
    len: u64,
    crc: u32,
}

impl SectionHead {
    fn payload_start(&self) -> u64 {
        self.offset + SECTION_HEADER_LEN
    }
    /// End of the payload (saturating: a forged length must not overflow).
    fn end(&self) -> u64 {
        self.payload_start().saturating_add(self.len)
    }
}

/// Frame offsets/times, event log and summary: what open loads besides the header.
#[derive(Default)]
struct Contents {
    offsets: Vec<u64>,
    times: Vec<f64>,
    events: Vec<EventRecord>,
    summary: Option<RunSummary>,
    /// Offsets of the EVENT BLOCK sections met during a scan.
    event_blocks: Vec<u64>,
}

impl Snapshot {
    /// Opens `path`: checks magic and version, reads the HEADER, then the INDEX, EVENTS and
    /// STATS of a finished file, or scans the sections of an unfinished or damaged one (keeping
    /// every whole frame and explaining in [`Self::warnings`] where it stopped). Frames
    /// themselves are not loaded.
    pub fn open(path: &Path) -> Result<Snapshot, SnapshotError> {
        let (file, len, version) = open_preamble(path)?;
        let raw = Raw {
            path: path.to_path_buf(),
            file: Mutex::new(file),
            len,
        };
        let (head, header, frame_len) = read_header(&raw, version)?;
        let m = header.output.bead_count(header.n_beads) as usize;
        let f = header.output.fields;
        let shape = (m * usize::from(f.has_u()), m * usize::from(f.has_v()));
        let first = head.end();
        let mut warnings = Vec::new();
        let (contents, complete) = match from_tail(&raw, first, frame_len, version) {
            Ok(Ok(c)) => (c, true),
            Ok(Err(why)) => {
                warnings.push(format!(
                    "{}: {why}; scanned the sections from the start",
                    path.display()
                ));
                let sc = scan(&raw, first, shape, frame_len, &mut warnings)?;
                (sc, false)
            }
            Err(fatal) => return Err(fatal),
        };
        Ok(Snapshot {
            raw,
            header,
            frame_len,
            shape,
            offsets: contents.offsets,
            times: contents.times,
            events: contents.events,
            summary: contents.summary,
            complete,
            warnings,
        })
    }

    /// Path the snapshot was opened from.
    pub fn path(&self) -> &Path {
        &self.raw.path
    }

    /// The run header.
    pub fn header(&self) -> &Header {
        &self.header
    }

    /// Number of whole frames available.
    pub fn frame_count(&self) -> usize {
        self.offsets.len()
    }

    /// Time of frame `k` (from the INDEX, or from the verified frame during a scan), without
    /// reading the frame.
    pub fn frame_time(&self, k: usize) -> Result<f64, SnapshotError> {
        self.times
            .get(k)
            .copied()
            .ok_or_else(|| self.out_of_range(k))
    }

    /// All frame times, in file order.
    pub fn frame_times(&self) -> &[f64] {
        &self.times
    }

    /// The event log (empty when the file has none).
    pub fn events(&self) -> &[EventRecord] {
        &self.events
    }

    /// Run statistics, if the file has a (whole) STATS section.
    pub fn summary(&self) -> Option<&RunSummary> {
        self.summary.as_ref()
    }

    /// True when the file ends with valid INDEX and END sections (a cleanly finished run).
    pub fn is_complete(&self) -> bool {
        self.complete
    }

    /// Everything the reader noticed but could work around (missing END, where a truncated
    /// file stops, damaged INDEX), one line each, naming the file.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Reads frame `k` (seeks; verifies the section header, length, checksum and time).
    pub fn frame(&self, k: usize) -> Result<Frame, SnapshotError> {
        let mut f = Frame::default();
        self.read_frame_into(k, &mut f)?;
        Ok(f)
    }

    /// Reads frame `k` into `frame`, reusing its vectors (no allocation once they have grown).
    pub fn read_frame_into(&self, k: usize, frame: &mut Frame) -> Result<(), SnapshotError> {
        let offset = *self.offsets.get(k).ok_or_else(|| self.out_of_range(k))?;
        let name = format!("FRAME #{k}");
        read_frame_at(
            &self.raw,
            offset,
            &name,
            k as u64,
            self.shape,
            self.frame_len,
            frame,
        )?;
        if frame.t.to_bits() != self.times[k].to_bits() {
            return Err(self.raw.corrupt(
                &name,
                offset,
                format!(
                    "frame time {:e} differs from the INDEX time {:e}",
                    frame.t, self.times[k]
                ),
            ));
        }
        Ok(())
    }

    /// Reads every frame once and verifies every checksum (reads the whole file).
    pub fn verify(&self) -> Result<(), SnapshotError> {
        let mut f = Frame::default();
        for k in 0..self.frame_count() {
            self.read_frame_into(k, &mut f)?;
        }
        Ok(())
    }

    fn out_of_range(&self, k: usize) -> SnapshotError {
        SnapshotError::FrameOutOfRange {
            path: self.raw.path.clone(),
            index: k,
            count: self.offsets.len(),
        }
    }
}

/// Reads and decodes a bincode section the INDEX points to (must end before `limit`).
fn indexed_section<T: serde::de::DeserializeOwned>(
    raw: &Raw,
    at: u64,
    tag: u32,
    name: &str,
    limit: u64,
) -> Result<T, SnapshotError> {
    let h = raw
        .read_head(at, name)?
        .ok_or_else(|| raw.truncated(format!("file ends inside {name} at byte {at}")))?;
    if h.tag != tag {
        return Err(raw.corrupt(
            name,
            at,
            format!(
                "the INDEX points to a section tagged {:#010x} ({})",
                h.tag,
                section_name(h.tag)
            ),
        ));
    }
    if h.len > limit.saturating_sub(h.payload_start()) {
        return Err(raw.absurd(
            name,
            at,
            format!(
                "{} bytes declared, the section must end before byte {limit}",
                h.len
            ),
        ));
    }
    let p = raw.read_payload(&h, name)?;
    decode_exact(&p).map_err(|d| raw.corrupt(name, at, d))
}

/// Sequential scan from the first section after the HEADER, verifying every checksum.
fn scan(
    raw: &Raw,
    first: u64,
    shape: Shape,
    frame_len: u64,
    warnings: &mut Vec<String>,
) -> Result<Contents, SnapshotError> {
    let mut c = Contents::default();
    let mut warn = |w: String| warnings.push(format!("{}: {w}", raw.path.display()));
    let mut pos = first;
    let mut frame = Frame::default();
    loop {
        let k = c.offsets.len();
        if pos == raw.len {
            warn(format!(
                "file ends at byte {pos} without an END section; kept {k} whole frames"
            ));
            break;
        }
        let Some(h) = raw.read_head(pos, "section")? else {
            warn(format!(
                "truncated: file ends at byte {} inside a section header at byte {pos}; \
                 kept {k} whole frames",
                raw.len
            ));
            break;
        };
        let name = match h.tag {
            TAG_FRAME => format!("FRAME #{k}"),
            t => section_name(t).to_string(),
        };
        if let Some(w) = section_fits(raw, &h, pos, &name, (shape, frame_len), k)? {
            warn(w);
            break;
        }
        match h.tag {
            TAG_FRAME => {
                read_frame_at(raw, pos, &name, k as u64, shape, frame_len, &mut frame)?;
                push_frame(raw, pos, &name, frame.t, &mut c)?;
            }
            TAG_EVENTS => {
                let p = raw.read_payload(&h, "EVENTS")?;
                c.events = decode_exact(&p).map_err(|d| raw.corrupt("EVENTS", pos, d))?;
            }
            TAG_EVENT_BLOCK => {
                let name = format!("EVENT BLOCK #{}", c.event_blocks.len());
                let p = raw.read_payload(&h, &name)?;
                events::read_block(raw, pos, &name, &p, &mut c.events)?;
                c.event_blocks.push(pos);
            }
            TAG_STATS => {
                let p = raw.read_payload(&h, "STATS")?;
                c.summary = Some(decode_exact(&p).map_err(|d| raw.corrupt("STATS", pos, d))?);
            }
            TAG_HEADER => {
                return Err(raw.corrupt("HEADER", pos, "a second HEADER section"));
            }
            _ => {
                if scan_other(raw, &h, &name, &c, &mut warn)? {
                    break;
                }
            }
        }
        pos = h.end();
    }
    Ok(c)
}

/// Checks the declared length of section `name` (header `h` at `pos`; `k` whole frames so
/// far): a frame must have the frame length of `shape`; a section running past the end of the
/// file is an error where the length is absurd (or it is a HEADER), else a truncation, whose
/// warning is returned (the scan keeps the `k` frames before it).
fn section_fits(
    raw: &Raw,
    h: &SectionHead,
    pos: u64,
    name: &str,
    (shape, frame_len): (Shape, u64),
    k: usize,
) -> Result<Option<String>, SnapshotError> {
    if h.tag == TAG_FRAME && h.len != frame_len {
        return Err(raw.absurd(
            name,
            pos,
            format!(
                "{} bytes, but a frame of {} u and {} v values has {frame_len}",
                h.len, shape.0, shape.1
            ),
        ));
    }
    let remain = raw.len - h.payload_start();
    if h.len <= remain {
        return Ok(None);
    }
    if h.len >= MAX_PLAUSIBLE_LEN || h.tag == TAG_HEADER {
        return Err(raw.absurd(
            name,
            pos,
            format!("{} bytes declared but only {remain} remain", h.len),
        ));
    }
    Ok(Some(format!(
        "truncated: file ends at byte {} inside {name} (starts at byte {pos}, \
         needs {} payload bytes, {remain} remain); kept {k} whole frames",
        raw.len, h.len
    )))
}

/// Records frame `name` at `pos` with time `t`: frames are written in strictly increasing time,
/// so a repeated or earlier time means sections were duplicated or reordered (numbering on
/// would put frames at the wrong index).
fn push_frame(
    raw: &Raw,
    pos: u64,
    name: &str,
    t: f64,
    c: &mut Contents,
) -> Result<(), SnapshotError> {
    if let Some(&prev) = c.times.last() {
        if t.partial_cmp(&prev) != Some(std::cmp::Ordering::Greater) {
            return Err(raw.corrupt(
                name,
                pos,
                format!(
                    "frame time {t:e} is not after the previous frame's {prev:e} \
                     (sections duplicated or out of order)"
                ),
            ));
        }
    }
    c.offsets.push(pos);
    c.times.push(t);
    Ok(())
}

/// An INDEX, EVENT INDEX, END or unknown section met by [`scan`]; `Ok(true)` ends the scan.
/// Its checksum also covers the tag, so a frame whose tag was damaged fails here: the scan
/// stops rather than renumber later frames.
fn scan_other(
    raw: &Raw,
    h: &SectionHead,
    name: &str,
    c: &Contents,
    warn: &mut impl FnMut(String),
) -> Result<bool, SnapshotError> {
    let (pos, k) = (h.offset, c.offsets.len());
    let Ok(p) = raw.read_payload(h, name) else {
        warn(format!(
            "damaged section (checksum) at byte {pos}; kept {k} whole frames, \
             ignored everything after it"
        ));
        return Ok(true);
    };
    match h.tag {
        TAG_INDEX => check_scan_against_index(raw, pos, &p, &c.times)?,
        TAG_EVENT_INDEX => check_scan_against_event_index(raw, pos, &p, c)?,
        TAG_END => {
            if h.end() != raw.len {
                warn(format!(
                    "{} bytes after the END section ignored",
                    raw.len - h.end()
                ));
            }
            return Ok(true);
        }
        t => warn(format!(
            "skipped a section with unknown tag {t:#010x} at byte {pos}"
        )),
    }
    Ok(false)
}

/// Opens `path` and checks its preamble (magic, format version); returns the file, its length
/// and the version.
fn open_preamble(path: &Path) -> Result<(File, u64, u32), SnapshotError> {
    let io = |action: &str, e| SnapshotError::Io {
        path: path.to_path_buf(),
        action: action.to_string(),
        source: e,
    };
    let mut file = File::open(path).map_err(|e| io("opening snapshot", e))?;
    let len = file
        .metadata()
        .map_err(|e| io("reading file size", e))?
        .len();
    let mut pre = [0u8; PREAMBLE_LEN as usize];
    let got = read_up_to(&mut file, &mut pre).map_err(|e| io("reading preamble", e))?;
    if got < 8 || pre[..8] != MAGIC {
        return Err(SnapshotError::NotSnapshot {
            path: path.to_path_buf(),
        });
    }
    if got < pre.len() {
        return Err(SnapshotError::Truncated {
            path: path.to_path_buf(),
            detail: format!("file ends at byte {got} inside the format version"),
        });
    }
    let version = u32::from_le_bytes([pre[8], pre[9], pre[10], pre[11]]);
    if version == 0 || version > FORMAT_VERSION {
        return Err(SnapshotError::UnsupportedVersion {
            path: path.to_path_buf(),
            found: version,
        });
    }
    Ok((file, len, version))
}

/// Reads and decodes the HEADER section (the first one); returns its section head, the header
/// and the frame payload length it implies.
fn read_header(raw: &Raw, version: u32) -> Result<(SectionHead, Header, u64), SnapshotError> {
    let len = raw.len;
    let head = raw.read_head(PREAMBLE_LEN, "HEADER")?.ok_or_else(|| {
        raw.truncated(format!(
            "file ends at byte {len} inside the HEADER section header"
        ))
    })?;
    if head.tag != TAG_HEADER {
        return Err(raw.corrupt(
            "HEADER",
            head.offset,
            format!(
                "first section has tag {:#010x} ({}), expected HEADER",
                head.tag,
                section_name(head.tag)
            ),
        ));
    }
    let payload = raw.read_payload(&head, "HEADER")?;
    let header = super::header::decode_header(version, &payload)
        .map_err(|d| raw.corrupt("HEADER", head.offset, d))?;
    let frame_len = (header.output.frame_payload_len(header.n_beads, version))
        .filter(|&l| l < MAX_PLAUSIBLE_LEN)
        .ok_or_else(|| {
            raw.corrupt(
                "HEADER",
                head.offset,
                format!("bead count {} is absurd", header.n_beads),
            )
        })?;
    Ok((head, header, frame_len))
}
