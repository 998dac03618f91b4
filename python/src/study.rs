//! `check()`: the hybrid engine against the dense reference, as `beadchain check` (the sweep glue
//! is in `sweep.rs`). Results are dicts of plain values or columns (DataFrame-ready).

use crate::run::{config, Options};
use crate::scene::Scene;
use crate::{without_gil, RunError};
use beadchain::check::check as lib_check;
use beadchain::engine::Deviation;
use pyo3::prelude::*;
use pyo3::types::PyDict;

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
    if let Some(t) = tol.filter(|t| !(t.is_finite() && *t > 0.0)) {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "tol = {t}: expected a finite relative deviation > 0"
        )));
    }
    let tol = tol.unwrap_or(1000.0 * cfg.rtol);
    let rep = without_gil(py, || lib_check(&s, &s, &cfg, tol))
        .map_err(|e| RunError::new_err(format!("{}: check run failed: {e}", s.name)))?;
    let d = PyDict::new(py);
    d.set_item("passed", rep.passed())?;
    d.set_item("sensitive", rep.sensitive)?;
    d.set_item("at_rest", rep.at_rest)?;
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
