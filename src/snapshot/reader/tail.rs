//! The fast path of opening a finished file: END → INDEX → EVENTS, STATS.

use super::events::event_log;
use super::raw::{le_u64, Raw};
use super::{indexed_section, Contents};
use crate::snapshot::{
    SnapshotError, END_SECTION_LEN, SECTION_HEADER_LEN, TAG_END, TAG_EVENTS, TAG_INDEX, TAG_STATS,
};

/// Why the fast path gave up (the file is then scanned from the start; the reason becomes a
/// warning).
#[derive(Debug, thiserror::Error)]
pub(super) enum NoTail {
    /// No (valid) END section at the end of the file.
    #[error("file has no END section (unfinished or truncated run)")]
    NoEnd,
    /// END fails its checksum.
    #[error("END section is damaged (checksum)")]
    EndDamaged,
    /// END points outside the file.
    #[error("END points to an INDEX at impossible byte {0}")]
    EndPointer(u64),
    /// The INDEX section header cannot be read.
    #[error("cannot read the INDEX section")]
    IndexUnreadable,
    /// The INDEX section header is inconsistent.
    #[error("INDEX section at byte {0} is malformed")]
    IndexMalformed(u64),
    /// INDEX fails its checksum.
    #[error("INDEX section is damaged (checksum)")]
    IndexDamaged,
    /// The INDEX frame count disagrees with its length.
    #[error("INDEX frame count {0} disagrees with its length")]
    IndexCount(u64),
    /// A frame offset overlaps its neighbour or the INDEX.
    #[error("INDEX offset of frame {frame} ({offset}) is impossible")]
    FrameOffset {
        /// Frame index.
        frame: usize,
        /// Its offset.
        offset: u64,
    },
}

/// Fast path for a finished file: END → INDEX → EVENTS, STATS.
///
/// `Ok(Err(reason))`: END or INDEX missing or damaged, fall back to scanning. `Err`: a fatal
/// problem in EVENTS or STATS (a scan could not do better).
pub(super) fn from_tail(
    raw: &Raw,
    first: u64,
    frame_len: u64,
    version: u32,
) -> Result<Result<Contents, NoTail>, SnapshotError> {
    let (index_at, end_at) = match index_position(raw, first)? {
        Ok(at) => at,
        Err(reason) => return Ok(Err(reason)),
    };
    let Some(ih) = raw.read_head(index_at, "INDEX")? else {
        return Ok(Err(NoTail::IndexUnreadable));
    };
    if ih.tag != TAG_INDEX || ih.end() != end_at || ih.len < 24 || (ih.len - 24) % 16 != 0 {
        return Ok(Err(NoTail::IndexMalformed(index_at)));
    }
    let Ok(ip) = raw.read_payload(&ih, "INDEX") else {
        return Ok(Err(NoTail::IndexDamaged));
    };
    let count = le_u64(&ip, 0);
    if count != (ih.len - 24) / 16 {
        return Ok(Err(NoTail::IndexCount(count)));
    }
    let count = count as usize;
    let (events_at, stats_at) = (le_u64(&ip, 8), le_u64(&ip, 16));
    let mut offsets = Vec::with_capacity(count);
    let mut prev_end = first;
    for i in 0..count {
        let o = le_u64(&ip, 24 + 8 * i);
        let end = o.checked_add(SECTION_HEADER_LEN + frame_len);
        if o < prev_end || end.is_none_or(|e| e > index_at) {
            return Ok(Err(NoTail::FrameOffset {
                frame: i,
                offset: o,
            }));
        }
        prev_end = o + SECTION_HEADER_LEN + frame_len;
        offsets.push(o);
    }
    let times = (0..count)
        .map(|i| f64::from_bits(le_u64(&ip, 24 + 8 * (count + i))))
        .collect();
    let events = match events_at {
        0 => Vec::new(),
        o if version == 1 => indexed_section(raw, o, TAG_EVENTS, "EVENTS", index_at)?,
        o => event_log(raw, o, first, index_at)?,
    };
    let summary = match stats_at {
        0 => None,
        o => Some(indexed_section(raw, o, TAG_STATS, "STATS", index_at)?),
    };
    Ok(Ok(Contents {
        offsets,
        times,
        events,
        summary,
        event_blocks: Vec::new(),
    }))
}

/// Where the END section at the file's end says the INDEX starts, and where END starts:
/// `Ok(Err(reason))` when END is missing, damaged or points outside the file.
fn index_position(raw: &Raw, first: u64) -> Result<Result<(u64, u64), NoTail>, SnapshotError> {
    let no_end = || Ok(Err(NoTail::NoEnd));
    if raw.len < first + END_SECTION_LEN {
        return no_end();
    }
    let end_at = raw.len - END_SECTION_LEN;
    let Some(end) = raw.read_head(end_at, "END")? else {
        return no_end();
    };
    if end.tag != TAG_END || end.len != 8 {
        return no_end();
    }
    let Ok(ep) = raw.read_payload(&end, "END") else {
        return Ok(Err(NoTail::EndDamaged));
    };
    let index_at = le_u64(&ep, 0);
    if index_at < first || index_at > end_at.saturating_sub(SECTION_HEADER_LEN) {
        return Ok(Err(NoTail::EndPointer(index_at)));
    }
    Ok(Ok((index_at, end_at)))
}
