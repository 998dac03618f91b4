//! `breather()`: a discrete breather of a scene's chain by Newton's method on the period map,
//! continued in frequency from a linear mode, and its Floquet multipliers
//! (`beadchain::experiments::breather`, as `beadchain breather`; docs/studies.md).

use crate::scene::Scene;
use crate::SceneError;
use beadchain::experiments::breather::{continue_to, Shooter};
use beadchain::experiments::floquet::floquet;
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The breather at angular frequency `frequency` from linear mode `mode` (default: the mode
/// nearest the frequency): `frequency`, `period`, `u` (displacements at t = 0, from rest),
/// `amplitude`, `residual` (period map, max-norm), `half_residual`, `steps`, `runs`, and unless
/// `floquet=False`: `multipliers` (complex, by decreasing modulus), `max_modulus` (other than
/// the pair at 1), `stable`, `reciprocity_error`, `unit_pair_error` (|mean − 1|, |product − 1|),
/// `unit_pair_vectors` (the residuals of its time-shift and energy vectors, |M ẋ − ẋ|/|ẋ| and
/// |∇Hᵀ M − ∇Hᵀ|/|∇H|);
/// `scene_toml`: the scene with the breather as its initial state (`periods` periods).
#[pyfunction]
#[pyo3(signature = (scene, frequency, mode=None, seed_amplitude=1e-3, step=0.02, tol=1e-11, rtol=1e-12, floquet=true, periods=100.0))]
#[allow(clippy::too_many_arguments)]
pub fn breather<'py>(
    py: Python<'py>,
    scene: &Scene,
    frequency: f64,
    mode: Option<usize>,
    seed_amplitude: f64,
    step: f64,
    tol: f64,
    rtol: f64,
    floquet: bool,
    periods: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let e = |e: beadchain::experiments::breather::BreatherError| SceneError::new_err(e.to_string());
    let name = &scene.scene.name;
    for (key, x) in [
        ("frequency", frequency),
        ("seed_amplitude", seed_amplitude),
        ("step", step),
        ("tol", tol),
        ("rtol", rtol),
        ("periods", periods),
    ] {
        if !(x.is_finite() && x > 0.0) {
            return Err(SceneError::new_err(format!(
                "{name}: breather: {key} = {x}: expected a finite value > 0"
            )));
        }
    }
    let sh = Shooter::new(&scene.scene, rtol).map_err(e)?;
    let k = match mode {
        Some(k) => k,
        None => {
            let mut best = (0, f64::INFINITY);
            for k in 0..sh.len() {
                let d = (sh.mode(k).map_err(e)?.0 - frequency).abs();
                if d < best.1 {
                    best = (k, d);
                }
            }
            best.0
        }
    };
    let wk = sh.mode(k).map_err(e)?.0;
    let start = sh.from_mode(k, seed_amplitude, tol).map_err(e)?;
    let path = continue_to(&sh, start, wk, frequency, step, tol).map_err(e)?;
    let b = &path[path.len() - 1];
    let d = PyDict::new(py);
    d.set_item("frequency", b.frequency())?;
    d.set_item("period", b.period)?;
    d.set_item("mode", k)?;
    d.set_item("mode_frequency", wk)?;
    d.set_item("u", PyArray1::from_vec(py, b.u.clone()))?;
    d.set_item("amplitude", sh.amplitude(&b.u))?;
    d.set_item("residual", sh.period_residual(b).map_err(e)?)?;
    d.set_item("half_residual", b.half_residual)?;
    d.set_item("steps", path.len() - 1)?;
    if floquet {
        let f = self::floquet(&sh, b, 1e-5).map_err(e)?;
        let m: Vec<numpy::Complex64> = f
            .multipliers
            .iter()
            .map(|&(re, im)| numpy::Complex64::new(re, im))
            .collect();
        d.set_item("multipliers", PyArray1::from_vec(py, m))?;
        d.set_item("max_modulus", f.max_modulus())?;
        d.set_item("stable", f.stable(1e-6))?;
        d.set_item("reciprocity_error", f.reciprocity_error())?;
        d.set_item("unit_pair_error", f.unit_pair_error())?;
        d.set_item("unit_pair_vectors", (f.flow_residual, f.energy_residual))?;
    }
    d.set_item("runs", sh.runs.get())?;
    let s = sh.scene_of(b, periods, 20);
    d.set_item("scene_toml", beadchain::scene::show::to_toml(&s))?;
    Ok(d)
}
