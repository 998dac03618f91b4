//! The one `.npz` writer of the crate (wide export, `modes --out`, `modes --energies`) and the
//! one `.npy` header function.
//!
//! An `.npz` is a zip archive of `.npy` files that `numpy.load(path)` opens as a dict. The zip
//! container is written by the [`zip`] crate: entries stored (not compressed), each followed by a
//! data descriptor (CRC-32 and sizes after the data, zip APPNOTE 4.3.9), so an entry's data is
//! streamed as it is produced (the wide export writes frame by frame; memory does not grow with
//! the frame count) and the output need not be seekable (standard output, FIFOs). Every entry
//! carries the same fixed modification time (1980-01-01 00:00, the earliest a zip can hold) and
//! permissions (0o644), so identical inputs give identical bytes (tests/npz_container.rs; a
//! Windows build marks the entries as made by DOS, so its bytes differ from a Unix build's).
//!
//! No ZIP64: every entry and the whole archive stay below 4 GiB ([`ZIP_LIMIT`]); the size is
//! computed exactly beforehand ([`entry_bytes`]) and checked before anything is written.
//!
//! The `.npy` header is written here rather than by `npyz`/`ndarray-npy`: NumPy pads the
//! header to a multiple of 64 bytes (data aligned for memory mapping), `npyz` to 16, and
//! `ndarray-npy` writes whole in-memory arrays only, while the exports stream a header of known
//! shape followed by raw rows.

use crate::snapshot::SnapshotError;
use std::io::{self, BufWriter, Write};
use zip::write::{SimpleFileOptions, StreamWriter};
use zip::{CompressionMethod, DateTime, ZipWriter};

/// Largest size of an entry, an offset or the whole archive in a zip without ZIP64.
pub const ZIP_LIMIT: u64 = u32::MAX as u64;

/// `descr` of a little-endian float64 array.
pub const F8: &str = "<f8";

/// The `.npy` v1.0 header of a little-endian C-order array of element type `descr` (`<f8`,
/// `<U12`, …) and `shape` (`[]`: a 0-d array): magic, version, u16 header length, the dict
/// padded with spaces so the data starts at a multiple of 64 bytes, `\n`.
pub fn npy_header(descr: &str, shape: &[u64]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let tuple = match dims.len() {
        1 => format!("({},)", dims[0]),
        _ => format!("({})", dims.join(", ")),
    };
    let dict = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {tuple}, }}");
    let unpadded = 10 + dict.len() + 1;
    let pad = (64 - unpadded % 64) % 64;
    let header_len = dict.len() + pad + 1;
    let mut h = Vec::with_capacity(10 + header_len);
    h.extend_from_slice(b"\x93NUMPY\x01\x00");
    h.extend_from_slice(&(header_len as u16).to_le_bytes());
    h.extend_from_slice(dict.as_bytes());
    h.resize(h.len() + pad, b' ');
    h.push(b'\n');
    h
}

/// Bytes of a float64 `.npy` of `shape` (header and data).
pub fn npy_bytes(shape: &[u64]) -> u64 {
    npy_header(F8, shape).len() as u64 + 8 * shape.iter().product::<u64>()
}

/// Bytes an entry named `name` with `data` bytes adds to the archive: local header, data
/// descriptor and central directory entry (no extra fields, no comments).
pub fn entry_bytes(name: &str, data: u64) -> u64 {
    30 + 16 + 46 + 2 * name.len() as u64 + data
}

/// Bytes of the end-of-central-directory record (no archive comment).
pub const END_BYTES: u64 = 22;

/// The error of an archive of `total` bytes, beyond [`ZIP_LIMIT`]; `Ok` below it.
pub fn check_size(total: u64) -> Result<(), SnapshotError> {
    if total > ZIP_LIMIT {
        return Err(SnapshotError::Output(io::Error::other(format!(
            "the .npz would be {total} bytes, beyond the 4 GiB of a zip without ZIP64: select fewer frames (--frame) or write .npy"
        ))));
    }
    Ok(())
}

fn zip_err(e: zip::result::ZipError) -> SnapshotError {
    SnapshotError::Output(e.into())
}

/// An `.npz` being written to a (not necessarily seekable) output, entry by entry.
pub struct NpzWriter<'a> {
    zip: ZipWriter<StreamWriter<&'a mut dyn Write>>,
}

impl<'a> NpzWriter<'a> {
    /// Starts an archive on `out` (nothing is written before the first entry).
    pub fn new(out: &'a mut dyn Write) -> Self {
        Self {
            zip: ZipWriter::new_stream(out),
        }
    }

    /// Writes one stored entry `name` (with its `.npy`) whose bytes `f` streams (through a
    /// 64 KiB buffer, so small writes are cheap).
    pub fn entry(
        &mut self,
        name: &str,
        f: impl FnOnce(&mut dyn Write) -> Result<(), SnapshotError>,
    ) -> Result<(), SnapshotError> {
        let options = SimpleFileOptions::default()
            .compression_method(CompressionMethod::Stored)
            .last_modified_time(DateTime::DEFAULT)
            .unix_permissions(0o644);
        self.zip.start_file(name, options).map_err(zip_err)?;
        let mut w = BufWriter::with_capacity(1 << 16, &mut self.zip);
        f(&mut w)?;
        w.flush()?;
        Ok(())
    }

    /// Writes the float64 array `name` (without `.npy`) of `shape` (values `xs` in C order).
    pub fn array(&mut self, name: &str, shape: &[u64], xs: &[f64]) -> Result<(), SnapshotError> {
        debug_assert_eq!(shape.iter().product::<u64>(), xs.len() as u64);
        self.entry(&format!("{name}.npy"), |w| {
            w.write_all(&npy_header(F8, shape))?;
            Ok(write_f64s(w, xs)?)
        })
    }

    /// Writes the central directory and the end record, and flushes the output.
    pub fn finish(self) -> Result<(), SnapshotError> {
        let out = self.zip.finish().map_err(zip_err)?.into_inner();
        out.flush()?;
        Ok(())
    }
}

/// Writes `xs` as little-endian float64.
pub fn write_f64s(w: &mut dyn Write, xs: &[f64]) -> io::Result<()> {
    for x in xs {
        w.write_all(&x.to_le_bytes())?;
    }
    Ok(())
}

/// Writes named float64 arrays (name without `.npy`, shape, values in C order) as an `.npz`,
/// after checking its size against [`ZIP_LIMIT`] (nothing is written when it is too large).
pub fn write_npz_arrays(
    arrays: &[(&str, Vec<u64>, &[f64])],
    out: &mut dyn Write,
) -> Result<(), SnapshotError> {
    let total = arrays
        .iter()
        .map(|(name, shape, _)| entry_bytes(&format!("{name}.npy"), npy_bytes(shape)))
        .sum::<u64>()
        + END_BYTES;
    check_size(total)?;
    let mut z = NpzWriter::new(out);
    for (name, shape, xs) in arrays {
        z.array(name, shape, xs)?;
    }
    z.finish()
}
