//! Event log of a version-2 snapshot: the EVENT INDEX and the EVENT BLOCKs it lists (layout and
//! reading rules in the [snapshot module](crate::snapshot)).

use super::{le_u64, Contents, Raw};
use crate::snapshot::{
    decode_exact, section_name, EventRecord, SnapshotError, SECTION_HEADER_LEN, TAG_EVENT_BLOCK,
    TAG_EVENT_INDEX,
};

/// The event log of a finished version-2 file: the EVENT INDEX at `at` (ending before `limit`)
/// and the EVENT BLOCKs it lists (in file order, after `first`, before the EVENT INDEX).
pub(super) fn event_log(
    raw: &Raw,
    at: u64,
    first: u64,
    limit: u64,
) -> Result<Vec<EventRecord>, SnapshotError> {
    const NAME: &str = "EVENT INDEX";
    let h = raw
        .read_head(at, NAME)?
        .ok_or_else(|| raw.truncated(format!("file ends inside {NAME} at byte {at}")))?;
    if h.tag != TAG_EVENT_INDEX {
        return Err(raw.corrupt(
            NAME,
            at,
            format!(
                "the INDEX points to a section tagged {:#010x} ({})",
                h.tag,
                section_name(h.tag)
            ),
        ));
    }
    if h.len > limit.saturating_sub(h.payload_start()) || h.len < 8 || h.len % 8 != 0 {
        return Err(raw.absurd(
            NAME,
            at,
            format!(
                "{} bytes: must be 8 + 8·count and end before byte {limit}",
                h.len
            ),
        ));
    }
    let p = raw.read_payload(&h, NAME)?;
    let count = le_u64(&p, 0);
    if count != (h.len - 8) / 8 {
        return Err(raw.corrupt(
            NAME,
            at,
            format!("block count {count} disagrees with its length"),
        ));
    }
    let mut events = Vec::new();
    let mut prev_end = first;
    for i in 0..count as usize {
        let o = le_u64(&p, 8 + 8 * i);
        let name = format!("EVENT BLOCK #{i}");
        let bad = |d: String| Err(raw.corrupt(NAME, at, d));
        if o < prev_end || o > at.saturating_sub(SECTION_HEADER_LEN) {
            return bad(format!("offset of block {i} ({o}) is impossible"));
        }
        let b = raw
            .read_head(o, &name)?
            .ok_or_else(|| raw.truncated(format!("file ends inside {name} at byte {o}")))?;
        if b.tag != TAG_EVENT_BLOCK {
            return bad(format!("block {i} at byte {o} is not an EVENT BLOCK"));
        }
        if b.len > at.saturating_sub(b.payload_start()) {
            return Err(raw.absurd(
                &name,
                o,
                format!(
                    "{} bytes declared, the block must end before byte {at}",
                    b.len
                ),
            ));
        }
        let bp = raw.read_payload(&b, &name)?;
        read_block(raw, o, &name, &bp, &mut events)?;
        prev_end = b.end();
    }
    Ok(events)
}

/// A whole EVENT INDEX met during a scan must list exactly the EVENT BLOCKs scanned before it.
pub(super) fn check_scan_against_event_index(
    raw: &Raw,
    pos: u64,
    payload: &[u8],
    c: &Contents,
) -> Result<(), SnapshotError> {
    let n = payload.len();
    let ok = n >= 8
        && n.is_multiple_of(8)
        && le_u64(payload, 0) == c.event_blocks.len() as u64
        && (n - 8) / 8 == c.event_blocks.len()
        && c.event_blocks
            .iter()
            .enumerate()
            .all(|(i, &o)| le_u64(payload, 8 + 8 * i) == o);
    if !ok {
        return Err(raw.corrupt(
            "EVENT INDEX",
            pos,
            format!(
                "the EVENT INDEX does not list the {} event blocks before it (sections removed, \
                 duplicated or out of order)",
                c.event_blocks.len()
            ),
        ));
    }
    Ok(())
}

/// Decodes the payload of the EVENT BLOCK at `at` onto `events`, checking that it continues the
/// log where `events` ends (its stored first index).
pub(super) fn read_block(
    raw: &Raw,
    at: u64,
    name: &str,
    payload: &[u8],
    events: &mut Vec<EventRecord>,
) -> Result<(), SnapshotError> {
    if payload.len() < 8 {
        return Err(raw.corrupt(name, at, "payload shorter than its first index"));
    }
    let first = le_u64(payload, 0);
    if first != events.len() as u64 {
        return Err(raw.corrupt(
            name,
            at,
            format!(
                "holds events from #{first}, expected #{} (blocks moved, duplicated or dropped)",
                events.len()
            ),
        ));
    }
    let mut block: Vec<EventRecord> =
        decode_exact(&payload[8..]).map_err(|d| raw.corrupt(name, at, d))?;
    events.append(&mut block);
    Ok(())
}
