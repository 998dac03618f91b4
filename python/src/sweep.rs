//! The sweep glue: `beadchain sweep`'s file one point at a time (so a Python executor can spread
//! the points), its rows as the CLI writes them, typed result columns, and the finished result
//! file (`OUT`, `OUT.meta` with content keys) with the CLI's resume by content.

use crate::{without_gil, SceneError};
use beadchain::sweep::content::reusable_rows;
use beadchain::sweep::csv::{self, field, split_fields};
use beadchain::sweep::exec::{format_row, partial_spec_line, run_one};
use beadchain::sweep::expand::format_value;
use beadchain::sweep::{RunPoint, SweepSpec};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::collections::BTreeMap;
use std::path::Path;
use toml::Value;

fn load_spec(path: &str) -> PyResult<SweepSpec> {
    SweepSpec::load(Path::new(path)).map_err(|e| SceneError::new_err(e.to_string()))
}

fn keyed(spec: &SweepSpec) -> PyResult<Vec<(RunPoint, u64)>> {
    spec.check_all_keyed()
        .map_err(|e| SceneError::new_err(e.to_string()))
}

fn point(spec: &SweepSpec, path: &str, index: usize) -> PyResult<RunPoint> {
    let runs = spec.runs();
    let n = runs.len();
    runs.into_iter().find(|r| r.index == index).ok_or_else(|| {
        SceneError::new_err(format!(
            "{path}: run {index} does not exist (the sweep has {n} runs)"
        ))
    })
}

/// A swept value as Python takes it: a number as `int` or `float` (as the sweep file gives it),
/// a boolean or string as itself, anything else (an inline table, an array) as its CSV text.
fn value<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Float(x) => x.into_pyobject(py)?.into_any(),
        Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        Value::Boolean(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        other => format_value(other).into_pyobject(py)?.into_any(),
    })
}

/// A sweep file's runs: `{"runs": count, "columns": parameter columns, "measure": [...]}`.
/// Every run's scene is built and checked (a bad sweep fails before anything runs).
#[pyfunction]
pub fn _sweep_spec<'py>(py: Python<'py>, path: &str) -> PyResult<Bound<'py, PyDict>> {
    let spec = load_spec(path)?;
    let runs = spec
        .check_all()
        .map_err(|e| SceneError::new_err(e.to_string()))?;
    let np = spec.param_columns().len();
    let d = PyDict::new(py);
    d.set_item("runs", runs.len())?;
    d.set_item("columns", spec.param_columns())?;
    d.set_item(
        "measure",
        csv::columns(&spec, false)[1 + np + csv::FIXED.len()..].to_vec(),
    )?;
    Ok(d)
}

/// Runs point `index` of a sweep file: one row (`run` index, the swept values as numbers,
/// `status`, `t_end`, `energy_error`, `steps`, `events` and the measured columns), the values
/// `beadchain sweep` writes. Independent of every other point: hand it to any executor.
#[pyfunction]
pub fn _sweep_run<'py>(py: Python<'py>, path: &str, index: usize) -> PyResult<Bound<'py, PyDict>> {
    let spec = load_spec(path)?;
    let point = point(&spec, path, index)?;
    let res = without_gil(py, || run_one(&spec, &point));
    let d = PyDict::new(py);
    d.set_item("run", index)?;
    for c in spec.param_columns() {
        match point.params.iter().find(|(k, _)| *k == c) {
            Some((_, v)) => d.set_item(c, value(py, v)?)?,
            None => d.set_item(c, py.None())?,
        }
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

/// Runs point `index` of a sweep file: its CSV row (no newline), the bytes `beadchain sweep`
/// writes for it.
#[pyfunction]
pub fn _sweep_row(py: Python<'_>, path: &str, index: usize) -> PyResult<String> {
    let spec = load_spec(path)?;
    let point = point(&spec, path, index)?;
    Ok(without_gil(py, || {
        let res = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            run_one(&spec, &point).map_err(|e| e.to_string())
        }))
        .unwrap_or_else(|_| Err("panic".into()));
        format_row(&spec, &point, &res, None)
    }))
}

fn header(spec: &SweepSpec) -> String {
    csv::columns(spec, false)
        .iter()
        .map(|c| field(c))
        .collect::<Vec<_>>()
        .join(",")
}

/// The rows of the finished result `out` that this sweep's runs take as they are (resume by
/// content, as `beadchain sweep`): `{run index: CSV row}`.
#[pyfunction]
pub fn _sweep_reuse(path: &str, out: &str) -> PyResult<BTreeMap<usize, String>> {
    let spec = load_spec(path)?;
    let all = keyed(&spec)?;
    Ok(reusable_rows(&spec, &all, Path::new(out), &header(&spec)))
}

/// Refuses an `out` whose file or `out.meta` is one of the sweep's inputs (the sweep file, its
/// base scene file and the CSV files that names), as `beadchain sweep --out` does, before any
/// run.
#[pyfunction]
pub fn _sweep_check_out(path: &str, out: &str) -> PyResult<()> {
    let spec = load_spec(path)?;
    let file = Path::new(path);
    let dir = file.parent().unwrap_or(Path::new("."));
    let mut inputs = vec![("sweep file", file.to_path_buf())];
    inputs.extend(beadchain::files::labelled_scene_inputs(
        &dir.join(&spec.scene_spec),
    ));
    let out = Path::new(out);
    let meta = csv::meta_path(out);
    beadchain::files::check_not_input(&[out, &meta], "out", &inputs)
        .map_err(|e| SceneError::new_err(e.to_string()))
}

/// Writes the finished result of every run's CSV row (`rows`, in run order) to `out` and
/// `out.meta` (spec line and content keys), the bytes `beadchain sweep --out OUT` writes; files
/// that already hold them are left alone. Returns whether anything was written.
#[pyfunction]
pub fn _sweep_write(path: &str, out: &str, rows: Vec<String>) -> PyResult<bool> {
    let spec = load_spec(path)?;
    let all = keyed(&spec)?;
    if rows.len() != all.len() {
        return Err(SceneError::new_err(format!(
            "{path}: {} rows for a sweep of {} runs",
            rows.len(),
            all.len()
        )));
    }
    let keys: BTreeMap<usize, u64> = all.iter().map(|(r, k)| (r.index, *k)).collect();
    let rows: BTreeMap<usize, String> = rows.into_iter().enumerate().collect();
    let line = partial_spec_line(&csv::spec_line(spec.hash, all.len()), &all);
    csv::write_result(Path::new(out), &line, &keys, &header(&spec), &rows)
        .map_err(|e| pyo3::exceptions::PyOSError::new_err(e.to_string()))
}

/// Result columns of `rows` (CSV rows of runs 0.., in order): `run`; the swept values as the
/// sweep file gives them (`int`, `float`, ...; None where a point has no value); `status`;
/// integer counts (`steps`, `events`, `fragments`) and floats (the rest) read back exactly
/// (None where empty).
#[pyfunction]
pub fn _sweep_table<'py>(
    py: Python<'py>,
    path: &str,
    rows: Vec<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let spec = load_spec(path)?;
    let runs = spec.runs();
    let params = spec.param_columns();
    let cols = csv::columns(&spec, false);
    let lists: Vec<Bound<'py, PyList>> = cols.iter().map(|_| PyList::empty(py)).collect();
    for (i, row) in rows.iter().enumerate() {
        let bad = |m: String| SceneError::new_err(format!("{path}: run {i}: {m}"));
        let f = split_fields(row).map_err(|e| bad(e.to_string()))?;
        let run = runs.get(i).ok_or_else(|| bad("no such run".into()))?;
        if f.len() != cols.len() {
            return Err(bad(format!("{} fields, expected {}", f.len(), cols.len())));
        }
        lists[0].append(i)?;
        for (j, c) in params.iter().enumerate() {
            match run.params.iter().find(|(k, _)| k == c) {
                Some((_, v)) => lists[1 + j].append(value(py, v)?)?,
                None => lists[1 + j].append(py.None())?,
            }
        }
        for j in 1 + params.len()..cols.len() {
            let x = f[j].as_str();
            let item: Bound<'py, PyAny> = match cols[j].as_str() {
                _ if x.is_empty() => py.None().into_bound(py),
                "status" => x.into_pyobject(py)?.into_any(),
                "steps" | "events" | "fragments" => {
                    let n: u64 = x.parse().map_err(|_| bad(format!("{}: `{x}`", cols[j])))?;
                    n.into_pyobject(py)?.into_any()
                }
                _ => {
                    let v: f64 = x.parse().map_err(|_| bad(format!("{}: `{x}`", cols[j])))?;
                    v.into_pyobject(py)?.into_any()
                }
            };
            lists[j].append(item)?;
        }
    }
    let d = PyDict::new(py);
    for (c, l) in cols.iter().zip(lists) {
        d.set_item(c, l)?;
    }
    Ok(d)
}
