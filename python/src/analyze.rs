//! `analyze()`: `beadchain analyze`'s summary ([`beadchain::analysis::summary`]) of a run's
//! frames (NumPy arrays) or of a snapshot file, as a dict of scalars and DataFrame-ready
//! columns. A value that cannot be computed is None with its reason under `<key>_error`
//! (None when the value is there); no NaN stands for a missing value.

use crate::scene::Scene;
use crate::without_gil;
use beadchain::analysis::summary::{FrameView, InterfaceSplit};
use beadchain::analysis::{summarize, Summary, SummaryError, SummaryOptions};
use beadchain::snapshot::{Frame, Snapshot};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// The options of a chain of `n` beads; an interface bead below 0 is refused as the library
/// refuses every bead outside `1..N` (`ValueError("interface must be in 1..N")`).
fn options(
    (interface, n): (Option<i64>, usize),
    fit_from: Option<f64>,
    fit_to: Option<f64>,
) -> PyResult<SummaryOptions> {
    let interface = match interface.map(usize::try_from) {
        None => None,
        Some(Ok(k)) => Some(k),
        Some(Err(_)) => {
            return Err(PyValueError::new_err(
                SummaryError::Interface { k: 0, n }.to_string(),
            ))
        }
    };
    Ok(SummaryOptions {
        interface,
        fit_from,
        fit_to,
    })
}

/// The library's reasons name the CLI's options; Python's keywords are `fit_from`/`fit_to`.
fn py_reason(e: &impl std::fmt::Display) -> String {
    e.to_string()
        .replace("--fit-from/--fit-to", "fit_from/fit_to")
}

fn summary_err(e: SummaryError, what: &str) -> PyErr {
    match e {
        SummaryError::Interface { .. } => PyValueError::new_err(e.to_string()),
        other => PyValueError::new_err(format!("{what}: {other}")),
    }
}

/// `(value, reason)` items `key` and `key_error` of a result.
fn set_result<'py, T: IntoPyObject<'py> + Copy, E: std::fmt::Display>(
    d: &Bound<'py, PyDict>,
    key: &str,
    r: &Result<T, E>,
) -> PyResult<()> {
    d.set_item(key, r.as_ref().ok().copied())?;
    d.set_item(
        format!("{key}_error"),
        r.as_ref().err().map(|e| py_reason(e)),
    )
}

fn opt_result(x: Option<f64>, why: &str) -> Result<f64, String> {
    x.ok_or_else(|| why.to_string())
}

fn interface_dict<'py>(py: Python<'py>, i: &InterfaceSplit) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("k", i.k)?;
    d.set_item("t", i.t)?;
    d.set_item("energy_left", i.left)?;
    d.set_item("energy_right", i.right)?;
    d.set_item("energy_total", i.left + i.right)?;
    let total0 = "the total energy is 0";
    set_result(
        &d,
        "reflected_fraction",
        &opt_result(i.left_fraction(), total0),
    )?;
    set_result(
        &d,
        "transmitted_fraction",
        &opt_result(i.right_fraction(), total0),
    )?;
    d.set_item("reflected_wave_energy", i.reflected_energy)?;
    d.set_item("reflected_first", i.reflected.map(|p| p.first))?;
    d.set_item("reflected_last", i.reflected.map(|p| p.last))?;
    d.set_item("v_in", i.v_in)?;
    d.set_item("v_out", i.v_out)?;
    let ratio = i.velocity_ratio();
    set_result(&d, "velocity_ratio", &ratio)?;
    d.set_item(
        "velocity_ratio_sampling_error",
        ratio.ok().map(|_| i.velocity.sampling_error()),
    )?;
    Ok(d)
}

fn track_dict<'py>(py: Python<'py>, s: &Summary) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let f = |g: fn(&beadchain::analysis::TrackPoint) -> f64| {
        PyArray1::from_vec(py, s.track.iter().map(g).collect())
    };
    let i = |g: fn(&beadchain::analysis::TrackPoint) -> usize| {
        PyArray1::from_vec(py, s.track.iter().map(|p| g(p) as i64).collect())
    };
    d.set_item("t", f(|p| p.t))?;
    d.set_item("position", f(|p| p.position))?;
    d.set_item("energy", f(|p| p.energy))?;
    d.set_item("peak_velocity", f(|p| p.pulse.peak_velocity))?;
    d.set_item("peak_bead", i(|p| p.pulse.peak_bead))?;
    d.set_item("first", i(|p| p.pulse.first))?;
    d.set_item("last", i(|p| p.pulse.last))?;
    d.set_item("width", i(|p| p.pulse.width()))?;
    Ok(d)
}

/// The summary as a dict (see `beadchain.analyze`).
fn to_dict<'py>(py: Python<'py>, s: &Summary) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("n", s.n)?;
    d.set_item("frames", s.frames)?;
    d.set_item("t_first", s.t_first)?;
    d.set_item("t_last", s.t_last)?;
    d.set_item("e0", s.e0)?;
    d.set_item("e_end", s.e_end)?;
    d.set_item("e_ref", s.e_ref)?;
    let scale0 = "the energy scale is 0 (the chain is at rest)";
    set_result(
        &d,
        "relative_change",
        &opt_result(s.relative_change(), scale0),
    )?;
    d.set_item("fit_from", s.fit_range.0)?;
    d.set_item("fit_to", s.fit_range.1)?;
    set_result(
        &d,
        "speed",
        &s.speed.as_ref().map(|v| v.value).map_err(Clone::clone),
    )?;
    d.set_item("speed_points", s.speed.as_ref().ok().map(|v| v.points))?;
    let decay = match &s.decay {
        Ok(f) => {
            let x = PyDict::new(py);
            x.set_item("a", f.a)?;
            x.set_item("gamma", f.gamma)?;
            x.set_item("gamma_stderr", f.gamma_stderr)?;
            x.set_item("r2", f.r2)?;
            x.set_item("points", f.n)?;
            Some(x)
        }
        Err(_) => None,
    };
    d.set_item("decay", decay)?;
    d.set_item("decay_error", s.decay.as_ref().err().map(py_reason))?;
    set_result(&d, "e_in", &s.e_in)?;
    let fr = &s.fragmentation;
    d.set_item("gaps", fr.gaps)?;
    d.set_item("fragments", fr.fragments.len())?;
    let ft = PyDict::new(py);
    let col = |g: fn(&beadchain::analysis::Fragment) -> f64| {
        PyArray1::from_vec(py, fr.fragments.iter().map(g).collect())
    };
    let icol = |g: fn(&beadchain::analysis::Fragment) -> usize| {
        PyArray1::from_vec(py, fr.fragments.iter().map(|f| g(f) as i64).collect())
    };
    ft.set_item("first", icol(|f| f.first))?;
    ft.set_item("last", icol(|f| f.last))?;
    ft.set_item("mass", col(|f| f.mass))?;
    ft.set_item("velocity", col(|f| f.velocity))?;
    d.set_item("fragment_table", ft)?;
    d.set_item("steady", s.steady)?;
    d.set_item(
        "interface",
        s.interface
            .as_ref()
            .map(|i| interface_dict(py, i))
            .transpose()?,
    )?;
    d.set_item("track", track_dict(py, s)?)?;
    Ok(d)
}

/// Summary of in-memory frames: `t` (F,), `u` and `v` flat (`F·N`) in computer units.
#[pyfunction]
#[pyo3(signature = (scene, t, u, v, interface=None, fit_from=None, fit_to=None))]
#[allow(clippy::too_many_arguments)]
pub fn _analyze<'py>(
    py: Python<'py>,
    scene: &Scene,
    t: PyReadonlyArray1<'py, f64>,
    u: PyReadonlyArray1<'py, f64>,
    v: PyReadonlyArray1<'py, f64>,
    interface: Option<i64>,
    fit_from: Option<f64>,
    fit_to: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let chain = &scene.scene.chain;
    let n = chain.len();
    let (t, u, v) = (t.as_slice()?, u.as_slice()?, v.as_slice()?);
    if n == 0 || u.len() != t.len() * n || v.len() != t.len() * n {
        return Err(PyValueError::new_err(format!(
            "{}: analyze: u and v must hold {} frames of {n} beads (got {} and {} values)",
            scene.scene.name,
            t.len(),
            u.len(),
            v.len()
        )));
    }
    let opts = options((interface, n), fit_from, fit_to)?;
    let s = without_gil(py, || {
        let views: Vec<FrameView<'_>> = t
            .iter()
            .zip(u.chunks_exact(n).zip(v.chunks_exact(n)))
            .map(|(&t, (u, v))| (t, u, v))
            .collect();
        summarize(chain, &views, &opts)
    })
    .map_err(|e| summary_err(e, &scene.scene.name))?;
    to_dict(py, &s)
}

/// Summary of a snapshot file, as `beadchain analyze` reads it (every bead and both fields
/// stored, or the CLI's error); the reader's warnings are returned under `warnings`.
#[pyfunction]
#[pyo3(signature = (path, interface=None, fit_from=None, fit_to=None))]
pub fn _analyze_file(
    py: Python<'_>,
    path: PathBuf,
    interface: Option<i64>,
    fit_from: Option<f64>,
    fit_to: Option<f64>,
) -> PyResult<Bound<'_, PyDict>> {
    let snap_err =
        |e: beadchain::snapshot::SnapshotError| crate::SnapshotError::new_err(e.to_string());
    let (snap, s) = without_gil(py, || -> PyResult<(Snapshot, Summary)> {
        let snap = Snapshot::open(&path).map_err(snap_err)?;
        snap.require_full("analyze needs every bead and both fields (energies, leading wave)")
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let n = snap.header().scene.chain.len();
        let opts = options((interface, n), fit_from, fit_to)?;
        let mut frames: Vec<Frame> = Vec::with_capacity(snap.frame_count());
        for k in 0..snap.frame_count() {
            frames.push(snap.frame(k).map_err(snap_err)?);
        }
        let views: Vec<FrameView<'_>> = frames
            .iter()
            .map(|f| (f.t, f.u.as_slice(), f.v.as_slice()))
            .collect();
        let s = summarize(&snap.header().scene.chain, &views, &opts)
            .map_err(|e| summary_err(e, &path.display().to_string()))?;
        Ok((snap, s))
    })?;
    let d = to_dict(py, &s)?;
    d.set_item("warnings", snap.warnings().to_vec())?;
    Ok(d)
}
