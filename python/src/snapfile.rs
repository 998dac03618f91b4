//! `load()`: a snapshot file opened from its index (header, frame times, event log, summary;
//! no frame read), and its frames read on demand (`SnapshotFile.read`), each checked against
//! its checksum and the index as the CLI reads it. A 2 GB file opens in the time of its index
//! and event log; the frames cost their read when they are first used.

use crate::observe::EventColumns;
use crate::scene::Scene;
use crate::{without_gil, SnapshotError};
use beadchain::names::Named;
use beadchain::snapshot::{Frame, Snapshot};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

fn snap_err(e: beadchain::snapshot::SnapshotError) -> PyErr {
    SnapshotError::new_err(e.to_string())
}

/// An open snapshot file.
#[pyclass(module = "beadchain._beadchain")]
pub struct SnapshotFile {
    snap: Snapshot,
}

type Flat<'py> = Option<Bound<'py, PyArray1<f64>>>;

#[pymethods]
impl SnapshotFile {
    /// Number of frames.
    fn __len__(&self) -> usize {
        self.snap.frame_count()
    }

    /// Reads frames `indices` (in that order): `(t, u, v, dissipated)`, `u` and `v` flat
    /// (`len·M` for `M` stored beads), None for a field the file does not store; `dissipated`
    /// (energy dissipated up to each frame) is None for files before format 4.
    fn read<'py>(
        &self,
        py: Python<'py>,
        indices: Vec<usize>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, Flat<'py>, Flat<'py>, Flat<'py>)> {
        let sel = &self.snap.header().output;
        let m = sel
            .beads
            .as_ref()
            .map_or(self.snap.header().n_beads as usize, |b| b.len());
        let (has_u, has_v) = (sel.fields.has_u(), sel.fields.has_v());
        let f = indices.len();
        let mut t = Vec::with_capacity(f);
        let mut u = Vec::with_capacity(if has_u { f * m } else { 0 });
        let mut v = Vec::with_capacity(if has_v { f * m } else { 0 });
        let mut dis = Some(Vec::with_capacity(f));
        let snap = &self.snap;
        without_gil(py, || -> Result<(), beadchain::snapshot::SnapshotError> {
            let mut fr = Frame::default();
            for &k in &indices {
                snap.read_frame_into(k, &mut fr)?;
                t.push(fr.t);
                u.extend_from_slice(&fr.u);
                v.extend_from_slice(&fr.v);
                match (dis.as_mut(), fr.dissipated) {
                    (Some(d), Some(x)) => d.push(x),
                    _ => dis = None,
                }
            }
            Ok(())
        })
        .map_err(snap_err)?;
        Ok((
            PyArray1::from_vec(py, t),
            has_u.then(|| PyArray1::from_vec(py, u)),
            has_v.then(|| PyArray1::from_vec(py, v)),
            dis.map(|d| PyArray1::from_vec(py, d)),
        ))
    }
}

/// Opens a snapshot file: everything but the frames (see the module docs), and the open file.
#[pyfunction]
pub fn load(py: Python<'_>, path: PathBuf) -> PyResult<Bound<'_, PyDict>> {
    let snap = without_gil(py, || Snapshot::open(&path)).map_err(snap_err)?;
    let h = snap.header();
    let sel = &h.output;
    let mut ev = EventColumns::default();
    for e in snap.events() {
        ev.push(e);
    }
    let d = PyDict::new(py);
    d.set_item(
        "n",
        sel.beads.as_ref().map_or(h.n_beads as usize, |b| b.len()),
    )?;
    d.set_item("times", PyArray1::from_slice(py, snap.frame_times()))?;
    d.set_item("beads", sel.beads.clone())?;
    d.set_item("events", ev.into_dict(py)?)?;
    d.set_item("engine", h.engine.name())?;
    d.set_item("method", h.method.name())?;
    d.set_item("rtol", h.rtol)?;
    d.set_item("atol", h.atol)?;
    d.set_item("created_by", h.created_by.clone())?;
    d.set_item("crate_version", h.crate_version.clone())?;
    d.set_item("build_commit", h.build_commit.clone())?;
    d.set_item("created_at", h.created_at.clone())?;
    d.set_item("format_version", h.format_version)?;
    d.set_item("complete", snap.is_complete())?;
    d.set_item("warnings", snap.warnings().to_vec())?;
    d.set_item("stats", summary(py, &snap)?)?;
    d.set_item("dissipative", h.scene.chain.loses_energy())?;
    d.set_item("scene", Scene::unchecked(h.scene.clone()))?;
    d.set_item("file", SnapshotFile { snap })?;
    Ok(d)
}

fn summary<'py>(py: Python<'py>, snap: &Snapshot) -> PyResult<Option<Bound<'py, PyDict>>> {
    let Some(s) = snap.summary() else {
        return Ok(None);
    };
    let o = PyDict::new(py);
    o.set_item("steps", s.stats.steps)?;
    o.set_item("rejected", s.stats.rejected)?;
    o.set_item("rhs_evals", s.stats.rhs_evals)?;
    o.set_item("bead_steps", s.stats.bead_steps)?;
    o.set_item("t_end", s.t_end)?;
    // a run without --timing stores 0 s and a note: not recorded, None (as `inspect` says)
    let untimed = s
        .notes
        .iter()
        .any(|n| n == beadchain::snapshot::WALL_NOT_RECORDED);
    o.set_item("wall_seconds", (!untimed).then_some(s.wall_seconds))?;
    o.set_item("energy_initial", s.energy_initial)?;
    o.set_item("energy_final", s.energy_final)?;
    o.set_item("momentum_initial", s.momentum_initial)?;
    o.set_item("momentum_final", s.momentum_final)?;
    let ev = PyDict::new(py);
    for (k, n) in &s.events_by_kind {
        ev.set_item(k, n)?;
    }
    o.set_item("events_by_kind", ev)?;
    o.set_item("largest_cluster", s.largest_cluster)?;
    o.set_item("notes", s.notes.clone())?;
    Ok(Some(o))
}
