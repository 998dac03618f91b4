//! `check()` (hybrid engine against the dense reference, as `beadchain check`) and the sweep
//! glue (`beadchain sweep`'s file, one point at a time so a Python executor can spread them).
//! Results are dicts of plain values or columns (DataFrame-ready).

use crate::run::{config, Options};
use crate::scene::Scene;
use crate::{without_gil, RunError, SceneError};
use beadchain::check::check as lib_check;
use beadchain::engine::Deviation;
use beadchain::sweep::exec::run_one;
use beadchain::sweep::expand::format_value;
use beadchain::sweep::SweepSpec;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::Path;

fn deviation<'py>(py: Python<'py>, d: &Deviation) -> PyResult<Bound<'py, PyDict>> {
    let o = PyDict::new(py);
    o.set_item("du", d.du.0)?;
    o.set_item("du_bead", d.du.1)?;
    o.set_item("dv", d.dv.0)?;
    o.set_item("dv_bead", d.dv.1)?;
    o.set_item("rel_u", d.rel_u)?;
    o.set_item("rel_v", d.rel_v)?;
    o.set_item("scale_u", d.scale.0)?;
    o.set_item("scale_v", d.scale.1)?;
    Ok(o)
}

/// Runs `beadchain check` on `scene`: the hybrid engine against the dense reference, judged by
/// the criteria of the CLI (default `tol = 1000·rtol`).
#[pyfunction]
#[pyo3(signature = (scene, method=None, rtol=None, atol=None, until=None, tol=None))]
pub fn check<'py>(
    py: Python<'py>,
    scene: &Scene,
    method: Option<String>,
    rtol: Option<f64>,
    atol: Option<f64>,
    until: Option<f64>,
    tol: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let o = Options {
        engine: None,
        method,
        rtol,
        atol,
        every: None,
        until,
        until_si: None,
        every_si: None,
        max_steps: None,
    };
    let (s, cfg) = config(&scene.scene, &o)?;
    let tol = tol.unwrap_or(1000.0 * cfg.rtol);
    let rep = without_gil(py, || lib_check(&s, &s, &cfg, tol))
        .map_err(|e| RunError::new_err(format!("{}: check run failed: {e}", s.name)))?;
    let d = PyDict::new(py);
    d.set_item("passed", rep.passed())?;
    d.set_item("sensitive", rep.sensitive)?;
    d.set_item("reference", rep.reference.clone())?;
    d.set_item("rtol", rep.rtol)?;
    d.set_item("tol", tol)?;
    let c = PyDict::new(py);
    let crit = &rep.criteria;
    c.set_item(
        "what",
        crit.iter().map(|x| x.what.clone()).collect::<Vec<_>>(),
    )?;
    c.set_item("value", crit.iter().map(|x| x.value).collect::<Vec<_>>())?;
    c.set_item("bound", crit.iter().map(|x| x.bound).collect::<Vec<_>>())?;
    c.set_item("holds", crit.iter().map(|x| x.holds()).collect::<Vec<_>>())?;
    d.set_item("criteria", c)?;
    d.set_item("deviation", deviation(py, &rep.deviation)?)?;
    d.set_item("sensitivity", deviation(py, &rep.sensitivity)?)?;
    Ok(d)
}

fn load_spec(path: &str) -> PyResult<SweepSpec> {
    SweepSpec::load(Path::new(path)).map_err(|e| SceneError::new_err(e.to_string()))
}

/// A sweep file's runs: `{"runs": count, "columns": parameter columns, "measure": [...]}`.
/// Every run's scene is built and checked (a bad sweep fails before anything runs).
#[pyfunction]
pub fn _sweep_spec<'py>(py: Python<'py>, path: &str) -> PyResult<Bound<'py, PyDict>> {
    let spec = load_spec(path)?;
    let runs = spec
        .check_all()
        .map_err(|e| SceneError::new_err(e.to_string()))?;
    let m = &spec.measure;
    let mut measure = Vec::new();
    if m.interface.is_some() {
        measure.push("left_fraction");
    }
    if m.decay.is_some() {
        measure.extend(["gamma", "gamma_se"]);
    }
    if m.impurity.is_some() {
        measure.push("v_ratio");
    }
    if m.fragments.is_some() {
        measure.push("fragments");
    }
    let d = PyDict::new(py);
    d.set_item("runs", runs.len())?;
    d.set_item("columns", spec.param_columns())?;
    d.set_item("measure", measure)?;
    Ok(d)
}

/// Runs point `index` of a sweep file: one row (`run` index, parameters as text, `status`,
/// `t_end`, `energy_error`, `steps`, `events` and the measured columns), as `beadchain sweep`
/// writes it. Independent of every other point: hand it to any executor.
#[pyfunction]
pub fn _sweep_run<'py>(py: Python<'py>, path: &str, index: usize) -> PyResult<Bound<'py, PyDict>> {
    let spec = load_spec(path)?;
    let runs = spec.runs();
    let Some(point) = runs.iter().find(|r| r.index == index) else {
        return Err(SceneError::new_err(format!(
            "{path}: run {index} does not exist (the sweep has {} runs)",
            runs.len()
        )));
    };
    let res = without_gil(py, || run_one(&spec, point));
    let d = PyDict::new(py);
    d.set_item("run", index)?;
    for c in spec.param_columns() {
        let v = point.params.iter().find(|(k, _)| *k == c);
        d.set_item(c, v.map(|(_, v)| format_value(v)))?;
    }
    match res {
        Err(msg) => d.set_item("status", format!("error: {msg}"))?,
        Ok((r, problem)) => {
            d.set_item(
                "status",
                problem.map_or("ok".to_string(), |p| format!("error: {p}")),
            )?;
            d.set_item("t_end", r.t_end)?;
            d.set_item("energy_error", r.energy_error)?;
            d.set_item("steps", r.steps)?;
            d.set_item("events", r.events)?;
            d.set_item("left_fraction", r.left_fraction)?;
            d.set_item("gamma", r.gamma.map(|g| g.0))?;
            d.set_item("gamma_se", r.gamma.map(|g| g.1))?;
            d.set_item("v_ratio", r.v_ratio)?;
            d.set_item("fragments", r.fragments)?;
        }
    }
    Ok(d)
}
