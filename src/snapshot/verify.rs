//! Verifying the sections an unfinished output already holds before a run continues it
//! (`beadchain resume`, [`super::SnapshotWriter::reopen`]): every section from the HEADER to
//! the checkpoint's mark is read and its CRC-32 compared (layout in [`super`]). Before, a byte
//! damaged in the temporary file between the interruption and the resume was carried into
//! the finished output, which `resume` renamed into place with exit 0 and which every reader
//! then refused ("checksum mismatch in section EVENT BLOCK #14").

use super::{section_hasher, section_name, SnapshotError, TAG_FRAME};
use std::io::Read;
use std::path::Path;

/// Bytes of the magic and the format version before the first section.
const PREAMBLE: u64 = 12;

/// Checks every section of `path` in `[12, len)`: a whole section header and payload, and a
/// checksum that matches. The first failure is the error (naming the section and its byte).
pub(crate) fn verify_prefix(path: &Path, len: u64) -> Result<(), SnapshotError> {
    let io = |e: std::io::Error| SnapshotError::Io {
        path: path.to_path_buf(),
        action: "verifying the unfinished output".into(),
        source: e,
    };
    let mut f = std::io::BufReader::with_capacity(1 << 16, std::fs::File::open(path).map_err(io)?);
    let mut skip = [0u8; PREAMBLE as usize];
    f.read_exact(&mut skip).map_err(io)?;
    let (mut pos, mut frames) = (PREAMBLE, 0u64);
    let mut buf = vec![0u8; 1 << 16];
    while pos < len {
        let mut head = [0u8; 16];
        f.read_exact(&mut head).map_err(io)?;
        let tag = u32::from_le_bytes(head[0..4].try_into().expect("4 bytes"));
        let n = u64::from_le_bytes(head[4..12].try_into().expect("8 bytes"));
        let crc = u32::from_le_bytes(head[12..16].try_into().expect("4 bytes"));
        let name = if tag == TAG_FRAME {
            frames += 1;
            format!("FRAME #{}", frames - 1)
        } else {
            section_name(tag).to_string()
        };
        let end = pos.checked_add(16).and_then(|p| p.checked_add(n));
        let Some(end) = end.filter(|&e| e <= len) else {
            return Err(SnapshotError::AbsurdLength {
                path: path.to_path_buf(),
                section: name,
                offset: pos,
                detail: format!("{n} bytes declared, past the checkpoint's mark at byte {len}"),
            });
        };
        let mut h = section_hasher(tag, n);
        let mut left = n;
        while left > 0 {
            let k = left.min(buf.len() as u64) as usize;
            f.read_exact(&mut buf[..k]).map_err(io)?;
            h.update(&buf[..k]);
            left -= k as u64;
        }
        if h.finalize() != crc {
            return Err(SnapshotError::ChecksumMismatch {
                path: path.to_path_buf(),
                section: name,
                offset: pos,
            });
        }
        pos = end;
    }
    Ok(())
}
