//! The wide export layout (`beadchain export --layout wide`): one row per frame, so NumPy
//! users index arrays directly instead of reshaping the long `frame, t, bead, u, v` table.
//!
//! - `.npz`: a zip archive (entries stored, not compressed; written by [`super::npz`]) of `.npy`
//!   arrays that `numpy.load(path)` opens as a dict: `t` `(F,)`, `u` `(F, N)`, `v` `(F, N)`, and the chain
//!   `mass` `(N,)`, `exponent`, `prefactor`, `precompression` `(N−1,)` (zeros when the scene
//!   declares none), and `provenance`: a 0-d unicode array holding a JSON object (version, build
//!   commit, command lines, scene, engine settings, date; [`super::provenance`]). Each array is
//!   streamed frame by frame (entries carry a data descriptor); no ZIP64, so the archive stays
//!   below 4 GiB (checked before anything is written), and identical inputs give identical bytes.
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

use super::npz::{self, npy_bytes, npy_header, write_f64s, NpzWriter, F8};
use super::{provenance, write_frames, ExportUnits, FrameSel, Num};
use crate::snapshot::{Selection, Snapshot, SnapshotError};
use std::io::Write;

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
        .map(|(name, shape)| npz::entry_bytes(name, npy_bytes(shape)))
        .sum::<u64>()
        + npz::END_BYTES
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
    let head = npy_header(F8, &[range.len() as u64, stored_values(snap) + 1]);
    write_frames(out, &head, snap, range, units, |w, _, f| {
        w.write_all(&f.t.to_le_bytes())?;
        write_f64s(w, &f.u)?;
        write_f64s(w, &f.v)
    })
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
    let s = snap.selection();
    let m = s.bead_count(snap.header().n_beads) as usize;
    let mut head = provenance::csv_comments(snap.header()) + "t";
    for (c, on) in [('u', s.fields.has_u()), ('v', s.fields.has_v())] {
        for j in (0..m).filter(|_| on) {
            head += &format!(",{c}{}", s.bead(j));
        }
    }
    head.push('\n');
    let range = sel.range(snap)?;
    write_frames(out, head.as_bytes(), snap, range, units, |w, _, f| {
        write!(w, "{}", Num(f.t))?;
        for x in f.u.iter().chain(&f.v) {
            write!(w, ",{}", Num(*x))?;
        }
        writeln!(w)
    })
}

/// Which per-frame array an `.npz` entry streams.
#[derive(Clone, Copy)]
enum Field {
    T,
    U,
    V,
}

/// Writes the selected frames, the chain arrays and the provenance (with `exported_by`, the
/// export's command line) as an `.npz` (see module docs); its size is checked first.
pub fn export_npz(
    snap: &Snapshot,
    sel: FrameSel,
    units: &ExportUnits,
    exported_by: &str,
    out: &mut dyn Write,
) -> Result<(), SnapshotError> {
    let range = sel.range(snap)?;
    let (n, s) = (snap.header().n_beads, snap.selection());
    let prov = provenance::npy_text(&provenance::json(snap.header(), exported_by));
    let total = npz_bytes_of(range.len() as u64, n, s)
        + npz::entry_bytes("provenance.npy", prov.len() as u64);
    npz::check_size(total)?;
    let mut z = NpzWriter::new(out);
    for field in [Field::T, Field::U, Field::V] {
        frame_entry(&mut z, snap, range.clone(), units, field)?;
    }
    if let Some(b) = &s.beads {
        let idx: Vec<f64> = b.iter().map(|&i| i as f64).collect();
        z.array("beads", &[idx.len() as u64], &idx)?;
    }
    let chain = &snap.header().scene.chain;
    let zeros = vec![0.0; chain.exponent.len()];
    let pre = chain.precompression.as_deref().unwrap_or(&zeros);
    let mass: Vec<f64> = chain.mass.iter().map(|m| m * units.mass).collect();
    let prefactor: Vec<f64> = chain.prefactor.iter().map(|a| a * units.energy).collect();
    for (name, xs) in [
        ("mass", mass.as_slice()),
        ("exponent", chain.exponent.as_slice()),
        ("prefactor", prefactor.as_slice()),
        ("precompression", pre),
    ] {
        z.array(name, &[xs.len() as u64], xs)?;
    }
    z.entry("provenance.npy", |w| Ok(w.write_all(&prov)?))?;
    z.finish()
}

/// Streams the per-frame array `field` of the frames `range` as the entry `t`, `u` or `v`,
/// one frame at a time; a field the snapshot does not store is skipped.
fn frame_entry(
    z: &mut NpzWriter<'_>,
    snap: &Snapshot,
    range: std::ops::Range<usize>,
    units: &ExportUnits,
    field: Field,
) -> Result<(), SnapshotError> {
    let s = snap.selection();
    let frames = range.len() as u64;
    let m = s.bead_count(snap.header().n_beads);
    let (name, shape) = match field {
        Field::T => ("t.npy", vec![frames]),
        Field::U if !s.fields.has_u() => return Ok(()),
        Field::V if !s.fields.has_v() => return Ok(()),
        Field::U => ("u.npy", vec![frames, m]),
        Field::V => ("v.npy", vec![frames, m]),
    };
    let head = npy_header(F8, &shape);
    z.entry(name, |out| {
        write_frames(out, &head, snap, range, units, |w, _, f| match field {
            Field::T => w.write_all(&f.t.to_le_bytes()),
            Field::U => write_f64s(w, &f.u),
            Field::V => write_f64s(w, &f.v),
        })
    })
}
