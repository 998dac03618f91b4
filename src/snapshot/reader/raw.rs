//! The open snapshot file: section headers and payloads read by seeking, and the error
//! constructors that name the file (truncated, corrupt, absurd length, checksum).

use super::SectionHead;
use crate::snapshot::{section_hasher, SnapshotError, SECTION_HEADER_LEN};
use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::PathBuf;
use std::sync::Mutex;

/// The open file and the error constructors that name it.
#[derive(Debug)]
pub(super) struct Raw {
    pub(super) path: PathBuf,
    pub(super) file: Mutex<File>,
    pub(super) len: u64,
}

impl Raw {
    /// Reads the 16-byte section header at `at`; `Ok(None)` if the file ends inside it.
    pub(super) fn read_head(
        &self,
        at: u64,
        name: &str,
    ) -> Result<Option<SectionHead>, SnapshotError> {
        if self.len.saturating_sub(at) < SECTION_HEADER_LEN {
            return Ok(None);
        }
        let mut b = [0u8; SECTION_HEADER_LEN as usize];
        let mut file = self.lock();
        seek(&mut file, at).map_err(|e| self.io(&format!("seeking to {name}"), e))?;
        file.read_exact(&mut b)
            .map_err(|e| self.io(&format!("reading {name}"), e))?;
        Ok(Some(SectionHead {
            offset: at,
            tag: u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            len: le_u64(&b, 4),
            crc: u32::from_le_bytes([b[12], b[13], b[14], b[15]]),
        }))
    }

    /// Errors unless the payload of `h` lies inside the file.
    pub(super) fn check_fits(&self, h: &SectionHead, name: &str) -> Result<(), SnapshotError> {
        let remain = self.len.saturating_sub(h.payload_start());
        if h.len > remain {
            return Err(self.absurd(
                name,
                h.offset,
                format!("{} bytes declared but only {remain} remain", h.len),
            ));
        }
        Ok(())
    }

    /// Reads a whole payload (after checking it fits in the file) and verifies its checksum.
    pub(super) fn read_payload(
        &self,
        h: &SectionHead,
        name: &str,
    ) -> Result<Vec<u8>, SnapshotError> {
        self.check_fits(h, name)?;
        let mut p = vec![0u8; h.len as usize];
        let mut file = self.lock();
        seek(&mut file, h.payload_start())
            .map_err(|e| self.io(&format!("seeking to {name}"), e))?;
        file.read_exact(&mut p)
            .map_err(|e| self.io(&format!("reading {name}"), e))?;
        drop(file);
        let mut hasher = section_hasher(h.tag, h.len);
        hasher.update(&p);
        if hasher.finalize() != h.crc {
            return Err(self.checksum(name, h.offset));
        }
        Ok(p)
    }

    pub(super) fn lock(&self) -> std::sync::MutexGuard<'_, File> {
        self.file.lock().unwrap_or_else(|p| p.into_inner())
    }

    pub(super) fn io(&self, action: &str, e: std::io::Error) -> SnapshotError {
        SnapshotError::Io {
            path: self.path.clone(),
            action: action.to_string(),
            source: e,
        }
    }

    pub(super) fn truncated(&self, detail: String) -> SnapshotError {
        SnapshotError::Truncated {
            path: self.path.clone(),
            detail,
        }
    }

    pub(super) fn corrupt(
        &self,
        section: &str,
        offset: u64,
        detail: impl std::fmt::Display,
    ) -> SnapshotError {
        SnapshotError::Corrupt {
            path: self.path.clone(),
            section: section.to_string(),
            offset,
            detail: detail.to_string(),
        }
    }

    pub(super) fn absurd(&self, section: &str, offset: u64, detail: String) -> SnapshotError {
        SnapshotError::AbsurdLength {
            path: self.path.clone(),
            section: section.to_string(),
            offset,
            detail,
        }
    }

    pub(super) fn checksum(&self, section: &str, offset: u64) -> SnapshotError {
        SnapshotError::ChecksumMismatch {
            path: self.path.clone(),
            section: section.to_string(),
            offset,
        }
    }
}

/// Little-endian u64 at `at` (caller guarantees the bounds).
pub(super) fn le_u64(b: &[u8], at: usize) -> u64 {
    let mut w = [0u8; 8];
    w.copy_from_slice(&b[at..at + 8]);
    u64::from_le_bytes(w)
}

pub(super) fn seek(f: &mut File, at: u64) -> std::io::Result<()> {
    f.seek(SeekFrom::Start(at)).map(|_| ())
}

/// Reads until `buf` is full or EOF; returns the bytes read.
pub(super) fn read_up_to(f: &mut File, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut got = 0;
    while got < buf.len() {
        match f.read(&mut buf[got..]) {
            Ok(0) => break,
            Ok(n) => got += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(got)
}
