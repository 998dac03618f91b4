//! `modes()` and `equilibrium()`: the linear modes of a scene's chain and its static
//! equilibrium (`beadchain::studies`, as `beadchain modes`; docs/studies.md); `modal_energies()`:
//! the energy per mode of a run's frames (`beadchain::analysis::modal`, as `beadchain modes
//! --snapshot`); `bands()`: the band structure of a periodic chain (`beadchain::studies::bands`,
//! as `beadchain plot dispersion`). Results are dicts of NumPy arrays and plain values.

use crate::scene::Scene;
use crate::SceneError;
use beadchain::analysis::modal::{project_frames, project_snapshot, ModalEnergies, ModalError};
use beadchain::snapshot::Snapshot;
use beadchain::studies::bands::{bands as lib_bands, cell_of, MAX_POINTS};
use beadchain::studies::equilibrium::equilibrium as lib_equilibrium;
use beadchain::studies::modal::ModalBasis;
use beadchain::studies::modes::{check_bins, density_of_states, linearize, solve, MAX_BINS};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

fn err(scene: &Scene, e: impl std::fmt::Display) -> PyErr {
    SceneError::new_err(format!("{}: {e}", scene.scene.name))
}

/// The static equilibrium of `scene`'s chain under its walls and field (`force`: the left
/// wall's imposed force, as `[walls] force`): `u`, `contact_force`, `wall_force` (left, right;
/// `None` without a wall), `gaps` (contacts without force), `iterations`,
/// `right_precompression` (with `force`).
#[pyfunction]
#[pyo3(signature = (scene, force=None))]
pub fn equilibrium<'py>(
    py: Python<'py>,
    scene: &Scene,
    force: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let s = &scene.scene;
    if let Some(f) = force.filter(|f| !f.is_finite()) {
        return Err(err(
            scene,
            format!("equilibrium: force = {f}: expected a finite force"),
        ));
    }
    let e = lib_equilibrium(&s.chain, &s.u0, force).map_err(|e| err(scene, e))?;
    let d = PyDict::new(py);
    d.set_item("u", PyArray1::from_vec(py, e.u))?;
    d.set_item("contact_force", PyArray1::from_vec(py, e.contact_force))?;
    d.set_item("wall_force", (e.wall_force[0], e.wall_force[1]))?;
    d.set_item("gaps", e.gaps)?;
    d.set_item("iterations", e.iterations)?;
    d.set_item("right_precompression", e.right_precompression)?;
    Ok(d)
}

/// The linear modes of `scene`'s chain about its static equilibrium (`about="initial"`: its
/// initial displacements), optionally only those with `window[0] <= omega <= window[1]`:
/// `omega`, `omega2`, `index`, `shapes` (N × M), `participation`, `dos_edges`, `dos_counts`
/// (`bins`, default ceil(sqrt(N))), `mass`, `overlap`, `stiffness`, `wall_stiffness`, `state`,
/// `ends` (the boundary conditions in words), `open_contacts` (zero stiffness).
#[pyfunction]
#[pyo3(signature = (scene, about="equilibrium", window=None, bins=None))]
pub fn modes<'py>(
    py: Python<'py>,
    scene: &Scene,
    about: &str,
    window: Option<(f64, f64)>,
    bins: Option<i64>,
) -> PyResult<Bound<'py, PyDict>> {
    let s = &scene.scene;
    if let Some((lo, hi)) = window {
        let ok = |x: f64| x.is_finite() && x >= 0.0;
        if !ok(lo) || !ok(hi) || lo > hi {
            return Err(err(
                scene,
                format!("modes: window = ({lo}, {hi}): expected finite frequencies 0 <= lo <= hi"),
            ));
        }
    }
    let u = state_about(scene, about)?;
    let lin = linearize(&s.chain, &u).map_err(|e| err(scene, e))?;
    let m = solve(&lin, window).map_err(|e| err(scene, e))?;
    let nb = lin.mass.len();
    let bins = match bins {
        Some(b) => usize::try_from(b)
            .ok()
            .and_then(|b| check_bins(b).ok())
            .ok_or_else(|| {
                PyValueError::new_err(format!(
                    "{}: bins = {b}: expected 1 to {MAX_BINS} bins",
                    s.name
                ))
            })?,
        None => (nb as f64).sqrt().ceil() as usize,
    };
    let (edges, counts) = density_of_states(&m.omega, bins);
    let k = m.omega.len();
    let mut shapes = Vec::with_capacity(nb * k);
    for i in 0..nb {
        shapes.extend(m.shapes.iter().map(|x| x[i]));
    }
    let d = PyDict::new(py);
    d.set_item("omega", PyArray1::from_vec(py, m.omega))?;
    d.set_item("omega2", PyArray1::from_vec(py, m.omega2))?;
    d.set_item("index", m.index)?;
    d.set_item("shapes", PyArray1::from_vec(py, shapes).reshape([nb, k])?)?;
    d.set_item("participation", PyArray1::from_vec(py, m.participation))?;
    d.set_item("dos_edges", PyArray1::from_vec(py, edges))?;
    d.set_item("dos_counts", PyArray1::from_vec(py, counts))?;
    d.set_item(
        "wall_stiffness",
        (lin.ends[0].stiffness(), lin.ends[1].stiffness()),
    )?;
    d.set_item("ends", (lin.ends[0].describe(), lin.ends[1].describe()))?;
    d.set_item("open_contacts", lin.open_contacts())?;
    d.set_item("mass", PyArray1::from_vec(py, lin.mass))?;
    d.set_item("overlap", PyArray1::from_vec(py, lin.overlap))?;
    d.set_item("stiffness", PyArray1::from_vec(py, lin.stiffness))?;
    d.set_item("state", PyArray1::from_vec(py, u))?;
    Ok(d)
}

/// The state `about` names: the static equilibrium or the initial displacements.
fn state_about(scene: &Scene, about: &str) -> PyResult<Vec<f64>> {
    let s = &scene.scene;
    match about {
        "equilibrium" => Ok(lib_equilibrium(&s.chain, &s.u0, None)
            .map_err(|e| {
                err(
                    scene,
                    format!("static equilibrium: {e} (use about=\"initial\")"),
                )
            })?
            .u),
        "initial" => Ok(s.u0.clone()),
        other => Err(pyo3::exceptions::PyValueError::new_err(format!(
            "about: expected \"equilibrium\" or \"initial\", got {other:?}"
        ))),
    }
}

/// The linear modes of `scene` about `about` (in `window`) as a projection basis, and their
/// frequencies.
fn basis_of(
    scene: &Scene,
    about: &str,
    window: Option<(f64, f64)>,
) -> PyResult<(ModalBasis, Vec<f64>)> {
    let u = state_about(scene, about)?;
    let lin = linearize(&scene.scene.chain, &u).map_err(|e| err(scene, e))?;
    let m = solve(&lin, window).map_err(|e| err(scene, e))?;
    let basis = ModalBasis::new(&lin, &m, &u).map_err(|e| err(scene, e))?;
    Ok((basis, m.omega))
}

/// The modal energies as a dict: `t` (F), `energy` (F × M), `harmonic`, `total` (F), `omega`,
/// `index` (M).
fn modal_dict<'py>(
    py: Python<'py>,
    basis: &ModalBasis,
    omega: Vec<f64>,
    e: ModalEnergies,
) -> PyResult<Bound<'py, PyDict>> {
    let (f, m) = (e.t.len(), e.modes);
    let d = PyDict::new(py);
    d.set_item("t", PyArray1::from_vec(py, e.t))?;
    d.set_item("energy", PyArray1::from_vec(py, e.energy).reshape([f, m])?)?;
    d.set_item("harmonic", PyArray1::from_vec(py, e.harmonic))?;
    d.set_item("total", PyArray1::from_vec(py, e.total))?;
    d.set_item("omega", PyArray1::from_vec(py, omega))?;
    d.set_item("index", basis.index.clone())?;
    Ok(d)
}

fn modal_err(e: ModalError) -> PyErr {
    match e {
        ModalError::Snapshot(s) => crate::SnapshotError::new_err(s.to_string()),
        ModalError::Mismatch(m) => SceneError::new_err(m),
    }
}

/// Modal energies of frames in memory (`u`, `v` flat, F·N): `what` names the run in errors.
#[pyfunction]
#[pyo3(signature = (scene, t, u, v, what, about="equilibrium", window=None))]
#[allow(clippy::too_many_arguments)]
pub fn _modal_energies<'py>(
    py: Python<'py>,
    scene: &Scene,
    t: PyReadonlyArray1<'py, f64>,
    u: PyReadonlyArray1<'py, f64>,
    v: PyReadonlyArray1<'py, f64>,
    what: &str,
    about: &str,
    window: Option<(f64, f64)>,
) -> PyResult<Bound<'py, PyDict>> {
    let (basis, omega) = basis_of(scene, about, window)?;
    let e = project_frames(
        &scene.scene.chain,
        &basis,
        t.as_slice()?,
        u.as_slice()?,
        v.as_slice()?,
        what,
    )
    .map_err(modal_err)?;
    modal_dict(py, &basis, omega, e)
}

/// Modal energies of every frame of the snapshot file `path` (as `beadchain modes --snapshot`).
#[pyfunction]
#[pyo3(signature = (scene, path, about="equilibrium", window=None))]
pub fn _modal_energies_file<'py>(
    py: Python<'py>,
    scene: &Scene,
    path: PathBuf,
    about: &str,
    window: Option<(f64, f64)>,
) -> PyResult<Bound<'py, PyDict>> {
    let (basis, omega) = basis_of(scene, about, window)?;
    let snap = Snapshot::open(&path).map_err(|e| crate::SnapshotError::new_err(e.to_string()))?;
    let e = project_snapshot(&snap, &scene.scene.chain, &basis).map_err(modal_err)?;
    modal_dict(py, &basis, omega, e)
}

/// The band structure of `scene`'s periodic chain (as `beadchain plot dispersion`): the unit
/// cell of `cell` beads from bead `start` (default: the smallest period of the masses and
/// stiffnesses) of the chain linearised about `about`, sampled at `points` wavenumbers on
/// `[0, π]`: `q` (points), `omega` (bands × points), `edges` (bands × 2: low, high), `gaps`
/// (k × 2), `mass`, `stiffness` (the cell's).
#[pyfunction]
#[pyo3(signature = (scene, cell=None, start=0, points=201, about="equilibrium"))]
pub fn bands<'py>(
    py: Python<'py>,
    scene: &Scene,
    cell: Option<i64>,
    start: i64,
    points: i64,
    about: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let count = |name: &str, x: i64, lo: usize, hi: usize| {
        usize::try_from(x)
            .ok()
            .filter(|x| (lo..=hi).contains(x))
            .ok_or_else(|| PyValueError::new_err(format!("{name}: expected {lo} to {hi}, got {x}")))
    };
    let points = count("points", points, 2, MAX_POINTS)?;
    let start = count("start", start, 0, usize::MAX)?;
    let cell = cell.map(|c| count("cell", c, 1, usize::MAX)).transpose()?;
    let u = state_about(scene, about)?;
    let lin = linearize(&scene.scene.chain, &u).map_err(|e| err(scene, e))?;
    // the library names the CLI's option
    let c = cell_of(&lin, cell, start)
        .map_err(|e| err(scene, e.to_string().replace("(--cell)", "(cell=)")))?;
    let b = lib_bands(&c, points);
    let nb = b.omega.len();
    let omega: Vec<f64> = b.omega.concat();
    let edges: Vec<f64> = b.edges.iter().flat_map(|&(lo, hi)| [lo, hi]).collect();
    let gaps = b.gaps();
    let ng = gaps.len();
    let gaps: Vec<f64> = gaps.into_iter().flat_map(|(lo, hi)| [lo, hi]).collect();
    let d = PyDict::new(py);
    d.set_item("q", PyArray1::from_vec(py, b.q))?;
    d.set_item(
        "omega",
        PyArray1::from_vec(py, omega).reshape([nb, points])?,
    )?;
    d.set_item("edges", PyArray1::from_vec(py, edges).reshape([nb, 2])?)?;
    d.set_item("gaps", PyArray1::from_vec(py, gaps).reshape([ng, 2])?)?;
    d.set_item("mass", PyArray1::from_vec(py, c.mass))?;
    d.set_item("stiffness", PyArray1::from_vec(py, c.stiffness))?;
    Ok(d)
}
