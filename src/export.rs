//! Export of snapshot frames to CSV and NumPy `.npy`, the event log to CSV, and the
//! human-readable `inspect` report ([`inspect`]: energy of paper eq. 1 + kinetic).
//!
//! Numbers are written so they read back bit-identically: Rust's `{}`/`{:e}` formatting of
//! `f64` prints the shortest decimal that round-trips, and we use the exponent form outside
//! `1e-5 ≤ |x| < 1e16` so tiny displacements (1e-7 units) stay short.
//!
//! All outputs go through [`crate::snapshot::write_atomically`] in the CLI: a failed export leaves no file.
//!
//! This module writes the long layout (one row per bead and frame); [`wide`] the wide one (one
//! row per frame; `.npz` with the chain arrays). Every `.npz` goes through [`npz`] (the `zip`
//! crate; stored entries, fixed timestamps) and every `.npy` header through [`npy_header`].
//!
//! Every CSV opens with `#` comment lines and every `.npz` holds an entry `provenance`: the
//! version, build commit, command line, scene, engine settings and date of the run
//! ([`provenance`]). Read CSVs with `pandas.read_csv(path, comment="#")`.

mod inspect;
pub mod npz;
pub mod provenance;
mod units;
pub mod wide;

pub use inspect::{damaged_frames, inspect, inspect_with};
pub use npz::npy_header;
pub use units::{DimensionlessError, ExportUnits};

use crate::names::Named;
use crate::snapshot::{Frame, Snapshot, SnapshotError};
use std::fmt;
use std::io::{BufWriter, Write};
use std::ops::Range;
use std::str::FromStr;

/// Which frames to export.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameSel {
    /// Frame 0.
    First,
    /// The last whole frame.
    Last,
    /// Frame `K` (0-based).
    Index(usize),
    /// Every frame, in order.
    All,
}

/// A `--frame` value that is neither `first`, `last`, `all` nor a frame number.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("invalid frame selector '{0}': expected first, last, all or a frame number K >= 0")]
pub struct FrameSelError(pub String);

impl FromStr for FrameSel {
    type Err = FrameSelError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim() {
            "first" => Ok(FrameSel::First),
            "last" => Ok(FrameSel::Last),
            "all" => Ok(FrameSel::All),
            k => k
                .parse::<usize>()
                .map(FrameSel::Index)
                .map_err(|_| FrameSelError(s.to_string())),
        }
    }
}

impl FrameSel {
    /// The frame indices selected in `snap`; errors name the file, `K` and the frame count.
    pub fn range(self, snap: &Snapshot) -> Result<Range<usize>, SnapshotError> {
        let count = snap.frame_count();
        let no_frames = || SnapshotError::NoFrames {
            path: snap.path().to_path_buf(),
        };
        match self {
            FrameSel::All => Ok(0..count),
            FrameSel::First if count > 0 => Ok(0..1),
            FrameSel::Last if count > 0 => Ok(count - 1..count),
            FrameSel::First | FrameSel::Last => Err(no_frames()),
            FrameSel::Index(k) if k < count => Ok(k..k + 1),
            FrameSel::Index(k) => Err(SnapshotError::FrameOutOfRange {
                path: snap.path().to_path_buf(),
                index: k,
                count,
            }),
        }
    }
}

/// An `f64` printed as the shortest decimal that parses back to the same bits.
struct Num(f64);

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || !a.is_finite() || (1e-5..1e16).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

/// Writes the selected frames as CSV: the [provenance comments](provenance::csv_comments), then
/// header `frame,t,bead,u,v`, one row per bead and frame.
/// A snapshot with an output selection gives its stored beads (the real index in `bead`) and
/// only the stored fields' columns (`frame,t,bead,u` or `frame,t,bead,v`).
pub fn export_csv(
    snap: &Snapshot,
    sel: FrameSel,
    units: &ExportUnits,
    out: &mut dyn Write,
) -> Result<(), SnapshotError> {
    let s = snap.selection();
    let (hu, hv) = (s.fields.has_u(), s.fields.has_v());
    let comments = provenance::csv_comments(snap.header());
    let head = format!("{comments}frame,t,bead{}\n", long_columns(hu, hv));
    let range = sel.range(snap)?;
    write_frames(out, head.as_bytes(), snap, range, units, |w, k, f| {
        for j in 0..f.u.len().max(f.v.len()) {
            write!(w, "{k},{},{}", Num(f.t), s.bead(j))?;
            for x in [f.u.get(j), f.v.get(j)].into_iter().flatten() {
                write!(w, ",{}", Num(*x))?;
            }
            writeln!(w)?;
        }
        Ok(())
    })
}

/// Streams `head`, then `row(w, k, frame)` for each frame `k` of `range` (read in turn, in the
/// export's units), to `out` through a 64 KiB buffer.
fn write_frames(
    out: &mut dyn Write,
    head: &[u8],
    snap: &Snapshot,
    range: Range<usize>,
    units: &ExportUnits,
    mut row: impl FnMut(&mut dyn Write, usize, &Frame) -> std::io::Result<()>,
) -> Result<(), SnapshotError> {
    let mut w = BufWriter::with_capacity(1 << 16, out);
    w.write_all(head)?;
    let mut f = Frame::default();
    for k in range {
        snap.read_frame_into(k, &mut f)?;
        units.frame(&mut f);
        row(&mut w, k, &f)?;
    }
    w.flush()?;
    Ok(())
}

/// The field columns of the long layout: `,u,v`, `,u` or `,v`.
fn long_columns(u: bool, v: bool) -> &'static str {
    match (u, v) {
        (true, true) => ",u,v",
        (true, false) => ",u",
        _ => ",v",
    }
}

/// Writes the selected frames as a NumPy `.npy` (v1.0) float64 array of shape `(rows, 5)` with
/// the CSV's columns `frame, t, bead, u, v` (frame and bead as exact small integers); `(rows, 4)`
/// without the field an output selection left out.
pub fn export_npy(
    snap: &Snapshot,
    sel: FrameSel,
    units: &ExportUnits,
    out: &mut dyn Write,
) -> Result<(), SnapshotError> {
    let range = sel.range(snap)?;
    let s = snap.selection();
    let rows = range.len() as u64 * s.bead_count(snap.header().n_beads);
    let head = npy_header(npz::F8, &[rows, 3 + s.fields.count()]);
    write_frames(out, &head, snap, range, units, |w, k, f| {
        for j in 0..f.u.len().max(f.v.len()) {
            for x in [k as f64, f.t, s.bead(j) as f64] {
                w.write_all(&x.to_le_bytes())?;
            }
            for x in [f.u.get(j), f.v.get(j)].into_iter().flatten() {
                w.write_all(&x.to_le_bytes())?;
            }
        }
        Ok(())
    })
}

/// Writes the event log as CSV: the [provenance comments](provenance::csv_comments), then
/// header `t,contact,kind,rel_velocity,peak_overlap`.
pub fn export_events_csv(
    snap: &Snapshot,
    units: &ExportUnits,
    out: &mut dyn Write,
) -> Result<(), SnapshotError> {
    let mut w = BufWriter::with_capacity(1 << 16, out);
    w.write_all(provenance::csv_comments(snap.header()).as_bytes())?;
    writeln!(w, "t,contact,kind,rel_velocity,peak_overlap")?;
    for e in snap.events() {
        writeln!(
            w,
            "{},{},{},{},{}",
            Num(e.t * units.time),
            e.contact,
            e.kind.name(),
            Num(units.velocity(e.rel_velocity)),
            Num(e.peak_overlap)
        )?;
    }
    w.flush()?;
    Ok(())
}
