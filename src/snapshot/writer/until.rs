//! The end time in an unfinished snapshot's HEADER: `resume --until T` runs the scene to `T`,
//! so the finished file's header must say `run.until = T` (it held the end time of the run
//! that started the file). The HEADER is the first section of the temporary file; the record
//! stores `run.until` as a fixed-width real, so the section keeps its length and is rewritten
//! in place (one write of its 16-byte section header and payload, CRC recomputed) before the
//! file is finished and renamed onto the final name: the final file still appears atomically.

use super::super::header4::header_record;
use super::super::{encode, read_header, section_hasher, SnapshotError, TAG_HEADER};
use super::{finished_err, section_header, SnapshotWriter};
use std::io::{Read, Seek, SeekFrom, Write};

/// Offset of the HEADER section: after the preamble (8 magic bytes, `u32` format version).
const HEADER_AT: u64 = 12;

impl SnapshotWriter {
    /// Makes the HEADER's `run.until` `until` (nothing is written when it is already). Refused,
    /// with the file unchanged, when the stored header does not re-encode to its own bytes or
    /// the new one would change the section's length (neither happens with format 4).
    pub fn set_run_until(&mut self, until: f64) -> Result<(), SnapshotError> {
        let out = self.out.as_mut().ok_or_else(finished_err)?;
        if let Err(e) = out.flush() {
            return Err(self.io_err(e));
        }
        let mut h = read_header(&self.tmp)?;
        if self.stream || h.scene.run.until.to_bits() == until.to_bits() {
            return Ok(());
        }
        let old = encode(&header_record(&h)).map_err(|e| self.encode_err("HEADER", e))?;
        h.scene.run.until = until;
        let new = encode(&header_record(&h)).map_err(|e| self.encode_err("HEADER", e))?;
        let stored = self.stored_header(old.len())?;
        if stored != old || new.len() != old.len() {
            return Err(SnapshotError::Encode {
                path: self.path.clone(),
                section: "HEADER",
                detail: format!(
                    "cannot record the end time {until} in place (the stored header does not re-encode to the same length)"
                ),
            });
        }
        let len = new.len() as u64;
        let mut crc = section_hasher(TAG_HEADER, len);
        crc.update(&new);
        let mut bytes = section_header(TAG_HEADER, len, crc.finalize()).to_vec();
        bytes.extend_from_slice(&new);
        let pos = self.pos;
        let out = self.out.as_mut().ok_or_else(finished_err)?;
        let r = (out.seek(SeekFrom::Start(HEADER_AT)))
            .and_then(|_| out.write_all(&bytes))
            .and_then(|_| out.flush())
            .and_then(|_| out.seek(SeekFrom::Start(pos)));
        r.map(|_| ()).map_err(|e| self.io_err(e))
    }

    /// The stored HEADER payload if it is `len` bytes long (empty otherwise, which the caller
    /// then refuses).
    fn stored_header(&self, len: usize) -> Result<Vec<u8>, SnapshotError> {
        let mut f = std::fs::File::open(&self.tmp).map_err(|e| self.io_err(e))?;
        let mut head = [0u8; 16];
        f.seek(SeekFrom::Start(HEADER_AT))
            .and_then(|_| f.read_exact(&mut head))
            .map_err(|e| self.io_err(e))?;
        let stored_len = u64::from_le_bytes(head[4..12].try_into().expect("8 bytes"));
        if head[..4] != TAG_HEADER.to_le_bytes() || stored_len != len as u64 {
            return Ok(Vec::new());
        }
        let mut payload = vec![0u8; len];
        f.read_exact(&mut payload).map_err(|e| self.io_err(e))?;
        Ok(payload)
    }
}
