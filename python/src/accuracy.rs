//! `accuracy()`: the work–precision study of `beadchain accuracy` (every engine × method ×
//! tolerance against a tight dense Radau reference), rows as columns (DataFrame-ready).

use crate::run::{parse_engine, parse_method};
use crate::scene::Scene;
use crate::{without_gil, RunError, SceneError};
use beadchain::accuracy::{accuracy_study, AccuracyError, AccuracyOptions, AccuracyRow};
use beadchain::names::Named;
use pyo3::prelude::*;
use pyo3::types::PyDict;

fn column<'py, T: pyo3::IntoPyObject<'py> + Clone>(
    d: &Bound<'py, PyDict>,
    rows: &[AccuracyRow],
    name: &str,
    f: impl Fn(&AccuracyRow) -> T,
) -> PyResult<()> {
    d.set_item(name, rows.iter().map(f).collect::<Vec<T>>())
}

/// Runs `beadchain accuracy` on `scene`; None leaves an option at the CLI's default (engines
/// hybrid and dense; methods radau5, dop853, verlet; rtols 1e-4, 1e-6, 1e-8, 1e-10; Verlet
/// steps 0.1, 0.03, 0.01, 0.003 τ; atol = 0.01·rtol; the scene's until; 1 repetition).
#[pyfunction]
#[pyo3(signature = (scene, engines=None, methods=None, rtols=None, verlet_steps=None, atol_ratio=None, until=None, repeat=None, reference_rtol=None, max_steps=None))]
#[allow(clippy::too_many_arguments)]
pub fn accuracy<'py>(
    py: Python<'py>,
    scene: &Scene,
    engines: Option<Vec<String>>,
    methods: Option<Vec<String>>,
    rtols: Option<Vec<f64>>,
    verlet_steps: Option<Vec<f64>>,
    atol_ratio: Option<f64>,
    until: Option<f64>,
    repeat: Option<usize>,
    reference_rtol: Option<f64>,
    max_steps: Option<u64>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut o = AccuracyOptions::default();
    if let Some(e) = engines {
        o.engines = e.iter().map(|x| parse_engine(x)).collect::<PyResult<_>>()?;
    }
    if let Some(m) = methods {
        o.methods = m.iter().map(|x| parse_method(x)).collect::<PyResult<_>>()?;
    }
    o.rtols = rtols.unwrap_or(o.rtols);
    o.verlet_steps = verlet_steps.unwrap_or(o.verlet_steps);
    o.atol_ratio = atol_ratio.or(o.atol_ratio);
    o.until = until;
    o.repeat = repeat.unwrap_or(o.repeat);
    o.reference_rtol = reference_rtol;
    o.max_steps = max_steps;
    let s = &scene.scene;
    let rep = without_gil(py, || accuracy_study(s, &o)).map_err(|e| match e {
        AccuracyError::Options(_) => SceneError::new_err(format!("{}: {e}", s.name)),
        _ => RunError::new_err(format!("{}: {e}", s.name)),
    })?;
    let rows = PyDict::new(py);
    let r = &rep.rows;
    column(&rows, r, "engine", |x| x.engine.name())?;
    column(&rows, r, "method", |x| x.method.name())?;
    column(&rows, r, "rtol", |x| x.rtol)?;
    column(&rows, r, "atol", |x| x.atol)?;
    column(&rows, r, "verlet_dt", |x| x.verlet_dt)?;
    column(&rows, r, "failure", |x| x.failure.clone())?;
    column(&rows, r, "is_reference", |x| x.is_reference)?;
    column(&rows, r, "err_u", |x| x.err_u)?;
    column(&rows, r, "err_v", |x| x.err_v)?;
    column(&rows, r, "error", |x| x.error)?;
    column(&rows, r, "energy_error", |x| x.energy_error)?;
    column(&rows, r, "ke_error", |x| x.ke_error)?;
    column(&rows, r, "wall_seconds", |x| x.wall_seconds)?;
    column(&rows, r, "steps", |x| x.steps)?;
    column(&rows, r, "rejected", |x| x.rejected)?;
    column(&rows, r, "rhs_evals", |x| x.rhs_evals)?;
    column(&rows, r, "events", |x| x.events)?;
    column(&rows, r, "bead_steps", |x| x.bead_steps)?;
    let reference = PyDict::new(py);
    let f = &rep.reference;
    reference.set_item("rtol", f.rtol)?;
    reference.set_item("check_rtol", f.check_rtol)?;
    reference.set_item("check_err_u", f.check_err_u)?;
    reference.set_item("check_err_v", f.check_err_v)?;
    reference.set_item("wall_seconds", f.wall_seconds)?;
    let d = PyDict::new(py);
    d.set_item("rows", rows)?;
    d.set_item("reference", reference)?;
    d.set_item("until", rep.until)?;
    d.set_item("tau", rep.tau)?;
    d.set_item("notes", rep.notes.clone())?;
    Ok(d)
}
