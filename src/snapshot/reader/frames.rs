//! Frames of a snapshot: reading one FRAME section (its stored values, see the output
//! selection in [`crate::snapshot::select`]) and checking a scan against an INDEX (rules in the
//! [snapshot module](crate::snapshot)).

use super::{le_u64, seek, Raw, Shape, CHUNK};
use crate::snapshot::{section_hasher, section_name, Frame, SnapshotError, TAG_FRAME};
use std::io::Read;

/// Reads and verifies the FRAME section at `offset` into `frame` (t, u, v of `shape`).
pub(super) fn read_frame_at(
    raw: &Raw,
    offset: u64,
    name: &str,
    number: u64,
    (nu, nv): Shape,
    frame_len: u64,
    frame: &mut Frame,
) -> Result<(), SnapshotError> {
    let head = frame_head(raw, offset, name, (nu, nv), frame_len)?;
    raw.check_fits(&head, name)?;
    frame.u.resize(nu, 0.0);
    frame.v.resize(nv, 0.0);
    let mut t = 0.0;
    // values before u: frame number, t (versions 1–3), and the dissipated energy (version 4)
    let lead = (frame_len / 8) as usize - nu - nv;
    let mut dissipated = None;
    let mut hasher = section_hasher(head.tag, head.len);
    let mut buf = [0u8; CHUNK];
    let mut file = raw.lock();
    seek(&mut file, head.payload_start()).map_err(|e| raw.io(&format!("seeking to {name}"), e))?;
    let mut j = 0usize; // index of the next value: 0 = frame number, 1 = t, [2 = E_d], u, v
    let mut stored = u64::MAX;
    let mut left = head.len;
    while left > 0 {
        let take = left.min(CHUNK as u64) as usize;
        let chunk = &mut buf[..take];
        file.read_exact(chunk)
            .map_err(|e| raw.io(&format!("reading {name}"), e))?;
        hasher.update(chunk);
        for b in chunk.chunks_exact(8) {
            let bytes = [b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]];
            let x = f64::from_le_bytes(bytes);
            if j == 0 {
                stored = u64::from_le_bytes(bytes);
            } else if j == 1 {
                t = x;
            } else if j < lead {
                dissipated = Some(x);
            } else if j < lead + nu {
                frame.u[j - lead] = x;
            } else {
                frame.v[j - lead - nu] = x;
            }
            j += 1;
        }
        left -= take as u64;
    }
    drop(file);
    if hasher.finalize() != head.crc {
        return Err(raw.checksum(name, offset));
    }
    if stored != number {
        return Err(raw.corrupt(
            name,
            offset,
            format!("holds frame number {stored}, expected {number} (frames moved, duplicated or dropped)"),
        ));
    }
    frame.t = t;
    frame.dissipated = dissipated;
    Ok(())
}

/// The section header at `offset`, which must be a FRAME of the frame length of `(nu, nv)`.
fn frame_head(
    raw: &Raw,
    offset: u64,
    name: &str,
    (nu, nv): Shape,
    frame_len: u64,
) -> Result<super::SectionHead, SnapshotError> {
    let head = raw
        .read_head(offset, name)?
        .ok_or_else(|| raw.truncated(format!("file ends inside {name} at byte {offset}")))?;
    if head.tag != TAG_FRAME {
        return Err(raw.corrupt(
            name,
            offset,
            format!(
                "tag {:#010x} ({}) where a frame should be",
                head.tag,
                section_name(head.tag)
            ),
        ));
    }
    if head.len != frame_len {
        return Err(raw.absurd(
            name,
            offset,
            format!(
                "{} bytes, but a frame of {nu} u and {nv} v values has {frame_len}",
                head.len
            ),
        ));
    }
    Ok(head)
}

/// A whole INDEX met during a scan must list exactly the frames scanned before it (same count,
/// same time bits); otherwise frame sections were removed, duplicated or reordered.
pub(super) fn check_scan_against_index(
    raw: &Raw,
    pos: u64,
    payload: &[u8],
    times: &[f64],
) -> Result<(), SnapshotError> {
    let len = payload.len() as u64;
    let count = if len >= 24 { le_u64(payload, 0) } else { 0 };
    if len < 24 || count.checked_mul(16).and_then(|x| x.checked_add(24)) != Some(len) {
        return Err(raw.corrupt("INDEX", pos, "malformed INDEX payload"));
    }
    let count = count as usize;
    let listed = (0..count).map(|i| le_u64(payload, 24 + 8 * (count + i)));
    if count != times.len() || listed.zip(times).any(|(a, b)| a != b.to_bits()) {
        return Err(raw.corrupt(
            "INDEX",
            pos,
            format!(
                "the INDEX lists {count} frames but the file holds {} frames before it, or at \
                 other times (sections removed, duplicated or out of order)",
                times.len()
            ),
        ));
    }
    Ok(())
}
