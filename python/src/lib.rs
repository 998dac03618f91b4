//! Python bindings of beadchain (`beadchain._beadchain`, built by maturin from `python/`).
//!
//! The Python package `beadchain` (`python/beadchain/__init__.py`) wraps this module; everything
//! here is glue over the library's public API: scene parsing and validation
//! ([`beadchain::scene`]), the steppable engine ([`beadchain::engine::start`], [`Engine`]) and
//! the snapshot writer/reader ([`beadchain::snapshot`]). Rules:
//!
//! - Arrays leave Rust as NumPy arrays that take over the `Vec` that collected the frames
//!   (`PyArray1::from_vec`: no copy), reshaped to `(F, N)` in Python (a view): a run's frames are
//!   copied once, from the engine's observer call into that `Vec`.
//! - The GIL is released while an engine runs; the observer re-acquires it only to check for
//!   signals (about every 50 ms of wall time and at frames) and to call Python observers, so
//!   Ctrl-C stops a run cleanly (the engine is asked to stop, `KeyboardInterrupt` is raised and
//!   no output file is left behind).
//! - Bad input raises `SceneError` (a `ValueError`) with the CLI's one-line message (without the
//!   `beadchain: error: ` prefix); engine failures raise `RunError`, unreadable snapshots
//!   `SnapshotError` (an `OSError`).
//!
//! [`Engine`]: beadchain::engine::Engine

mod accuracy;
mod analyze;
mod breather;
mod observe;
mod run;
mod scene;
mod sim;
mod snapfile;
mod statics;
mod study;
mod sweep;

use pyo3::create_exception;
use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    _beadchain,
    SceneError,
    PyValueError,
    "Bad scene or run configuration: the CLI's one-line message, naming the file and key, bead or contact."
);
create_exception!(
    _beadchain,
    RunError,
    PyRuntimeError,
    "The engine failed (e.g. the integrator's step size fell below rounding)."
);
create_exception!(
    _beadchain,
    SnapshotError,
    PyOSError,
    "A snapshot could not be read or written (one line naming the file)."
);

/// Runs `f` with the GIL released. `Python::detach` wants a `Send` closure; an engine is not
/// `Send` (it is never moved to another thread), and `detach` runs `f` on this very thread, so
/// asserting `Send` is sound as long as `f` touches Python objects only under
/// `Python::attach` (the observers do).
pub(crate) fn without_gil<T, F: FnOnce() -> T>(py: Python<'_>, f: F) -> T {
    struct AssertSend<X>(X);
    unsafe impl<X> Send for AssertSend<X> {}
    let f = AssertSend(f);
    let r = py.detach(move || {
        let f = f;
        AssertSend((f.0)())
    });
    r.0
}

#[pymodule]
fn _beadchain(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("RunError", py.get_type::<RunError>())?;
    m.add("SnapshotError", py.get_type::<SnapshotError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The git commit the beadchain crate was built from (`unknown` from an sdist; its build.rs).
    m.add("__build_commit__", beadchain::BUILD_COMMIT)?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<sim::Simulation>()?;
    m.add_class::<snapfile::SnapshotFile>()?;
    m.add_function(wrap_pyfunction!(scene::presets, m)?)?;
    m.add_function(wrap_pyfunction!(scene::_preset_toml, m)?)?;
    m.add_function(wrap_pyfunction!(scene::_nearest_presets, m)?)?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(snapfile::load, m)?)?;
    m.add_function(wrap_pyfunction!(run::energies, m)?)?;
    m.add_function(wrap_pyfunction!(study::check, m)?)?;
    m.add_function(wrap_pyfunction!(statics::modes, m)?)?;
    m.add_function(wrap_pyfunction!(statics::_modal_energies, m)?)?;
    m.add_function(wrap_pyfunction!(statics::bands, m)?)?;
    m.add_function(wrap_pyfunction!(statics::_modal_energies_file, m)?)?;
    m.add_function(wrap_pyfunction!(breather::breather, m)?)?;
    m.add_function(wrap_pyfunction!(statics::equilibrium, m)?)?;
    m.add_function(wrap_pyfunction!(analyze::_analyze, m)?)?;
    m.add_function(wrap_pyfunction!(analyze::_analyze_file, m)?)?;
    m.add_function(wrap_pyfunction!(accuracy::accuracy, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::_sweep_spec, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::_sweep_run, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::_sweep_row, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::_sweep_reuse, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::_sweep_write, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::_sweep_check_out, m)?)?;
    m.add_function(wrap_pyfunction!(run::_check_run_out, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::_sweep_table, m)?)?;
    Ok(())
}
