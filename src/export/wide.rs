//! The wide export layout (`beadchain export --layout wide`): one row per frame, so NumPy
//! users index arrays directly instead of reshaping the long `frame, t, bead, u, v` table.
//!
//! - `.npz`: a zip archive (entries stored, not compressed) of `.npy` arrays that
//!   `numpy.load(path)` opens as a dict: `t` `(F,)`, `u` `(F, N)`, `v` `(F, N)`, and the chain
//!   `mass` `(N,)`, `exponent`, `prefactor`, `precompression` `(N−1,)` (zeros when the scene
//!   declares none), and `provenance`: a 0-d unicode array holding a JSON object (version, build
//!   commit, command lines, scene, engine settings, date; [`super::provenance`]). Entries carry a data descriptor (CRC-32 and sizes after the data, zip
//!   APPNOTE 4.3.9), so each array is streamed frame by frame; no ZIP64, so every entry and the
//!   archive stay below 4 GiB (checked before anything is written).
//! - `.npy`: one float64 array `(F, 2N+1)`: column 0 is `t`, columns `1..=N` are `u`, columns
//!   `N+1..=2N` are `v` (`a[:, 0]`, `a[:, 1:N+1]`, `a[:, N+1:]`).
//! - `.csv`: the same columns with header `t,u0,…,u{N−1},v0,…,v{N−1}`, after the provenance
//!   comment lines (`#`) every exported CSV opens with.
//!
//! Numbers are the snapshot's f64 values, bit for bit (NPY) or in shortest round-trip text (CSV).
//!
//! A snapshot with an output selection (`run --beads/--fields`: `M` beads, `q` = 1 or 2 fields)
//! exports what it stores: `u`/`v` are `(F, M)` and a field not stored is left out; the `.npz`
//! adds `beads` `(M,)` (the real bead indices, as float64); the `.npy` is `(F, 1+q·M)` in the
//! order `t | u | v`; CSV columns are labelled with the real index (`u10,u11,…`). The chain arrays
//! stay whole (`(N,)`, `(N−1,)`).

use super::{provenance, ExportUnits, FrameSel, Num};
use crate::snapshot::{Frame, Selection, Snapshot, SnapshotError};
use std::io::{self, BufWriter, Write};

/// Largest size of an entry or offset in a zip without ZIP64.
pub const ZIP_LIMIT: u64 = u32::MAX as u64;

/// The `.npy` v1.0 header of a little-endian float64 C-order array of `shape`.
pub fn npy_header_shape(shape: &[u64]) -> Vec<u8> {
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let tuple = if dims.len() == 1 {
        format!("({},)", dims[0])
    } else {
        format!("({})", dims.join(", "))
    };
    let dict = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {tuple}, }}");
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

/// Size in bytes of the whole `.npz` for `frames × beads` (entries, headers, directory; without
/// the few hundred bytes of the `provenance` entry).
pub fn npz_bytes(frames: u64, beads: u64) -> u64 {
    npz_bytes_of(frames, beads, &Selection::default())
}

/// [`npz_bytes`] of a snapshot with output selection `sel` (chain of `beads` beads).
pub fn npz_bytes_of(frames: u64, beads: u64, sel: &Selection) -> u64 {
    let m = sel.bead_count(beads);
    let n1 = beads.saturating_sub(1);
    let mut entries: Vec<(&str, Vec<u64>)> = vec![("t.npy", vec![frames])];
    if sel.fields.has_u() {
        entries.push(("u.npy", vec![frames, m]));
    }
    if sel.fields.has_v() {
        entries.push(("v.npy", vec![frames, m]));
    }
    if sel.beads.is_some() {
        entries.push(("beads.npy", vec![m]));
    }
    entries.push(("mass.npy", vec![beads]));
    for name in ["exponent.npy", "prefactor.npy", "precompression.npy"] {
        entries.push((name, vec![n1]));
    }
    entries
        .iter()
        .map(|(name, shape)| {
            let data = npy_header_shape(shape).len() as u64 + 8 * shape.iter().product::<u64>();
            entry_bytes(name, data)
        })
        .sum::<u64>()
        + 22
}

/// Bytes an entry named `name` with `data` bytes adds to the archive (local header, data
/// descriptor, central directory entry).
fn entry_bytes(name: &str, data: u64) -> u64 {
    30 + 16 + 46 + 2 * name.len() as u64 + data
}

/// Writes the selected frames as one `(F, 2N+1)` float64 `.npy` array (`(F, 1+q·M)` for an
/// output selection; see module docs).
pub fn export_npy_wide(
    snap: &Snapshot,
    sel: FrameSel,
    units: &ExportUnits,
    out: &mut dyn Write,
) -> Result<(), SnapshotError> {
    let range = sel.range(snap)?;
    let cols = stored_values(snap);
    let mut w = BufWriter::with_capacity(1 << 16, out);
    w.write_all(&npy_header_shape(&[range.len() as u64, cols + 1]))?;
    let mut f = Frame::default();
    for k in range {
        snap.read_frame_into(k, &mut f)?;
        units.frame(&mut f);
        w.write_all(&f.t.to_le_bytes())?;
        for x in f.u.iter().chain(&f.v) {
            w.write_all(&x.to_le_bytes())?;
        }
    }
    w.flush()?;
    Ok(())
}

/// Numbers per frame besides `t` (`2 N` unless the snapshot stores a selection).
fn stored_values(snap: &Snapshot) -> u64 {
    let n = snap.header().n_beads;
    snap.selection().values_per_frame(n).unwrap_or(u64::MAX)
}

/// Writes the selected frames as CSV, one row per frame: `t,u0,…,v0,…` (see module docs).
pub fn export_csv_wide(
    snap: &Snapshot,
    sel: FrameSel,
    units: &ExportUnits,
    out: &mut dyn Write,
) -> Result<(), SnapshotError> {
    let range = sel.range(snap)?;
    let s = snap.selection();
    let m = s.bead_count(snap.header().n_beads) as usize;
    let mut w = BufWriter::with_capacity(1 << 16, out);
    w.write_all(provenance::csv_comments(snap.header()).as_bytes())?;
    w.write_all(b"t")?;
    for (c, on) in [('u', s.fields.has_u()), ('v', s.fields.has_v())] {
        for j in (0..m).filter(|_| on) {
            write!(w, ",{c}{}", s.bead(j))?;
        }
    }
    writeln!(w)?;
    let mut f = Frame::default();
    for k in range {
        snap.read_frame_into(k, &mut f)?;
        units.frame(&mut f);
        write!(w, "{}", Num(f.t))?;
        for x in f.u.iter().chain(&f.v) {
            write!(w, ",{}", Num(*x))?;
        }
        writeln!(w)?;
    }
    w.flush()?;
    Ok(())
}

/// Which per-frame array an `.npz` entry streams.
#[derive(Clone, Copy)]
enum Field {
    T,
    U,
    V,
}

/// Writes the selected frames, the chain arrays and the provenance (with `exported_by`, the
/// export's command line) as an `.npz` (see module docs).
pub fn export_npz(
    snap: &Snapshot,
    sel: FrameSel,
    units: &ExportUnits,
    exported_by: &str,
    out: &mut dyn Write,
) -> Result<(), SnapshotError> {
    let range = sel.range(snap)?;
    let n = snap.header().n_beads;
    let s = snap.selection();
    let m = s.bead_count(n);
    let frames = range.len() as u64;
    let prov = provenance::npy_text(&provenance::json(snap.header(), exported_by));
    let total = npz_bytes_of(frames, n, s) + entry_bytes("provenance.npy", prov.len() as u64);
    if total > ZIP_LIMIT {
        return Err(SnapshotError::Output(io::Error::other(format!(
            "the .npz would be {total} bytes, beyond the 4 GiB of a zip without ZIP64: select fewer frames (--frame) or write .npy"
        ))));
    }
    let chain = &snap.header().scene.chain;
    let zeros = vec![0.0; chain.exponent.len()];
    let pre = chain.precompression.as_deref().unwrap_or(&zeros);
    let mass: Vec<f64> = chain.mass.iter().map(|m| m * units.mass).collect();
    let prefactor: Vec<f64> = chain.prefactor.iter().map(|a| a * units.energy).collect();
    let mut z = ZipWriter::new(BufWriter::with_capacity(1 << 16, out));
    for (name, field) in [
        ("t.npy", Field::T),
        ("u.npy", Field::U),
        ("v.npy", Field::V),
    ] {
        let shape = match field {
            Field::T => vec![frames],
            Field::U if !s.fields.has_u() => continue,
            Field::V if !s.fields.has_v() => continue,
            _ => vec![frames, m],
        };
        z.entry(name, |w| {
            w.write_all(&npy_header_shape(&shape))?;
            let mut f = Frame::default();
            for k in range.clone() {
                snap.read_frame_into(k, &mut f)?;
                units.frame(&mut f);
                match field {
                    Field::T => w.write_all(&f.t.to_le_bytes())?,
                    Field::U => write_f64s(w, &f.u)?,
                    Field::V => write_f64s(w, &f.v)?,
                }
            }
            Ok(())
        })?;
    }
    if let Some(b) = &s.beads {
        let idx: Vec<f64> = b.iter().map(|&i| i as f64).collect();
        z.entry("beads.npy", |w| {
            w.write_all(&npy_header_shape(&[m]))?;
            Ok(write_f64s(w, &idx)?)
        })?;
    }
    for (name, xs) in [
        ("mass.npy", mass.as_slice()),
        ("exponent.npy", chain.exponent.as_slice()),
        ("prefactor.npy", prefactor.as_slice()),
        ("precompression.npy", pre),
    ] {
        z.entry(name, |w| {
            w.write_all(&npy_header_shape(&[xs.len() as u64]))?;
            write_f64s(w, xs)?;
            Ok(())
        })?;
    }
    z.entry("provenance.npy", |w| Ok(w.write_all(&prov)?))?;
    let mut w = z.finish()?;
    w.flush()?;
    Ok(())
}

/// Writes named `f64` arrays (name without `.npy`, shape, values in C order) as an `.npz` with
/// the same zip writer as [`export_npz`] (stored entries, fixed timestamp).
pub fn write_npz_arrays(
    arrays: &[(&str, Vec<u64>, &[f64])],
    out: &mut dyn Write,
) -> Result<(), SnapshotError> {
    let mut z = ZipWriter::new(BufWriter::with_capacity(1 << 16, out));
    for (name, shape, xs) in arrays {
        debug_assert_eq!(shape.iter().product::<u64>(), xs.len() as u64);
        z.entry(&format!("{name}.npy"), |w| {
            w.write_all(&npy_header_shape(shape))?;
            Ok(write_f64s(w, xs)?)
        })?;
    }
    let mut w = z.finish()?;
    w.flush()?;
    Ok(())
}

fn write_f64s(w: &mut dyn Write, xs: &[f64]) -> io::Result<()> {
    for x in xs {
        w.write_all(&x.to_le_bytes())?;
    }
    Ok(())
}

/// Counts bytes and their CRC-32 on their way to the archive.
struct Counted<'a, W: Write> {
    inner: &'a mut W,
    crc: crc32fast::Hasher,
    len: u64,
}

impl<W: Write> Write for Counted<'_, W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let k = self.inner.write(buf)?;
        self.crc.update(&buf[..k]);
        self.len += k as u64;
        Ok(k)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

/// One finished entry: name, CRC-32, size, offset of its local header.
struct Entry {
    name: String,
    crc: u32,
    size: u32,
    offset: u32,
}

/// A minimal zip writer: stored entries with data descriptors, a fixed timestamp
/// (1980-01-01, so identical inputs give identical bytes), no ZIP64.
struct ZipWriter<W: Write> {
    out: W,
    pos: u64,
    entries: Vec<Entry>,
}

/// Version needed to extract (2.0: data descriptors).
const ZIP_VERSION: u16 = 20;
/// General-purpose flag bit 3: CRC and sizes follow the data.
const FLAG_DESCRIPTOR: u16 = 1 << 3;
/// MS-DOS date of 1980-01-01.
const DOS_DATE: u16 = (1 << 5) | 1;

fn u32_of(x: u64) -> Result<u32, SnapshotError> {
    u32::try_from(x).map_err(|_| {
        SnapshotError::Output(io::Error::other(
            "the .npz exceeds 4 GiB (zip without ZIP64): select fewer frames (--frame) or write .npy",
        ))
    })
}

impl<W: Write> ZipWriter<W> {
    fn new(out: W) -> Self {
        Self {
            out,
            pos: 0,
            entries: Vec::new(),
        }
    }

    fn put(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.out.write_all(bytes)?;
        self.pos += bytes.len() as u64;
        Ok(())
    }

    /// Writes one stored entry whose data `f` streams.
    fn entry(
        &mut self,
        name: &str,
        f: impl FnOnce(&mut dyn Write) -> Result<(), SnapshotError>,
    ) -> Result<(), SnapshotError> {
        let offset = u32_of(self.pos)?;
        let mut h = Vec::with_capacity(30 + name.len());
        h.extend_from_slice(&0x0403_4b50u32.to_le_bytes());
        for x in [ZIP_VERSION, FLAG_DESCRIPTOR, 0, 0, DOS_DATE] {
            h.extend_from_slice(&x.to_le_bytes());
        }
        h.extend_from_slice(&[0; 12]); // CRC and sizes: in the data descriptor
        h.extend_from_slice(&(name.len() as u16).to_le_bytes());
        h.extend_from_slice(&0u16.to_le_bytes());
        h.extend_from_slice(name.as_bytes());
        self.put(&h)?;
        let mut c = Counted {
            inner: &mut self.out,
            crc: crc32fast::Hasher::new(),
            len: 0,
        };
        f(&mut c)?;
        let (crc, len) = (c.crc.finalize(), c.len);
        self.pos += len;
        let size = u32_of(len)?;
        let mut d = Vec::with_capacity(16);
        for x in [0x0807_4b50u32, crc, size, size] {
            d.extend_from_slice(&x.to_le_bytes());
        }
        self.put(&d)?;
        self.entries.push(Entry {
            name: name.to_string(),
            crc,
            size,
            offset,
        });
        Ok(())
    }

    /// Writes the central directory and the end record; returns the output.
    fn finish(mut self) -> Result<W, SnapshotError> {
        let start = u32_of(self.pos)?;
        let mut cd = Vec::new();
        for e in &self.entries {
            cd.extend_from_slice(&0x0201_4b50u32.to_le_bytes());
            for x in [ZIP_VERSION, ZIP_VERSION, FLAG_DESCRIPTOR, 0, 0, DOS_DATE] {
                cd.extend_from_slice(&x.to_le_bytes());
            }
            for x in [e.crc, e.size, e.size] {
                cd.extend_from_slice(&x.to_le_bytes());
            }
            for x in [e.name.len() as u16, 0, 0, 0, 0] {
                cd.extend_from_slice(&x.to_le_bytes());
            }
            cd.extend_from_slice(&0u32.to_le_bytes()); // external attributes
            cd.extend_from_slice(&e.offset.to_le_bytes());
            cd.extend_from_slice(e.name.as_bytes());
        }
        let size = u32_of(cd.len() as u64)?;
        self.put(&cd)?;
        let k = self.entries.len() as u16;
        let mut end = Vec::with_capacity(22);
        end.extend_from_slice(&0x0605_4b50u32.to_le_bytes());
        for x in [0u16, 0, k, k] {
            end.extend_from_slice(&x.to_le_bytes());
        }
        end.extend_from_slice(&size.to_le_bytes());
        end.extend_from_slice(&start.to_le_bytes());
        end.extend_from_slice(&0u16.to_le_bytes());
        self.put(&end)?;
        Ok(self.out)
    }
}
