//! `run()`, `load()` and `energies()`: a whole run of a scene into NumPy arrays (and optionally
//! the CLI's snapshot file), a snapshot file back into the same arrays, and per-frame energies.

use crate::observe::{Collector, Progress};
use crate::scene::Scene;
use crate::{without_gil, RunError, SceneError, SnapshotError};
use beadchain::engine::{self, EngineError, RunConfig, RunOutcome, RunOverrides, Stop};
use beadchain::integrate::Method;
use beadchain::names::Named;
use beadchain::scene::{Engine as EngineKind, Scene as LibScene};
use beadchain::snapshot::size::DEFAULT_MAX_OUTPUT_BYTES;
use beadchain::snapshot::{Header, RunSummary, Selection, SnapshotWriter};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// Run options as Python gives them (None: the scene's setting, else the documented default).
pub(crate) struct Options {
    pub engine: Option<String>,
    pub method: Option<String>,
    pub rtol: Option<f64>,
    pub atol: Option<f64>,
    pub every: Option<f64>,
    pub until: Option<f64>,
    /// `until` in seconds (physical scenes; the CLI's `--until-si`).
    pub until_si: Option<f64>,
    /// `every` in seconds (physical scenes; the CLI's `--every-si`).
    pub every_si: Option<f64>,
    pub max_steps: Option<u64>,
}

/// `x` seconds as computer time of `scene` (`x / β`, as the CLI's `--until-si`/`--every-si`);
/// `key` names the keyword in the error of a dimensionless scene or of a duplicate keyword.
fn si_time(
    scene: &LibScene,
    key: &str,
    plain: Option<f64>,
    x: Option<f64>,
) -> PyResult<Option<f64>> {
    let Some(x) = x else {
        return Ok(plain);
    };
    let plain_key = key.trim_end_matches("_si");
    if plain.is_some() {
        return Err(SceneError::new_err(format!(
            "{}: {key}: give {plain_key} (computer units) or {key} (seconds), not both",
            scene.name
        )));
    }
    if !(x.is_finite() && x > 0.0) {
        return Err(SceneError::new_err(format!(
            "{}: {key}: must be a finite number > 0 (seconds), got {x}",
            scene.name
        )));
    }
    match scene.units {
        Some(u) => Ok(Some(x / u.time)),
        None => Err(SceneError::new_err(format!(
            "{}: {key}: the scene is dimensionless (computer units only); SI times need a physical scene ([units] system = \"physical\"), else give {plain_key}",
            scene.name
        ))),
    }
}

/// An engine name as the CLI's `--engine` takes it.
pub(crate) fn parse_engine(e: &str) -> PyResult<EngineKind> {
    EngineKind::parse(e).map_err(|err| SceneError::new_err(format!("engine: {err}")))
}

/// A method name as the CLI's `--method` takes it.
pub(crate) fn parse_method(m: &str) -> PyResult<Method> {
    Method::parse(m).map_err(|err| SceneError::new_err(format!("method: {err}")))
}

/// The run configuration, as the CLI builds it from the scene and its options (`--rtol` sets
/// `atol = rtol/10⁴` unless the scene or `--atol` gives one), and the scene with `[run]`
/// `until`/`every` updated to what runs (the snapshot header records them), both checked.
pub(crate) fn config(scene: &LibScene, o: &Options) -> PyResult<(LibScene, RunConfig)> {
    let overrides = RunOverrides {
        engine: o.engine.as_deref().map(parse_engine).transpose()?,
        method: o.method.as_deref().map(parse_method).transpose()?,
        rtol: o.rtol,
        atol: o.atol,
        until: si_time(scene, "until_si", o.until, o.until_si)?,
        every: si_time(scene, "every_si", o.every, o.every_si)?,
        solver: None,
        max_steps: o.max_steps,
    };
    let cfg = RunConfig::with_overrides(scene, &overrides);
    let mut s = scene.clone();
    s.run.until = cfg.until;
    s.run.every = cfg.every;
    unrunnable(&s, &cfg, o)?;
    // the options first (their messages name them: `until = -1 must be …`), then the scene: one
    // read from a snapshot or a pickle of an older version was not validated again
    // (`Scene::unchecked`); it is here, before any output is written
    engine::check_config(&s, &cfg).map_err(|e| config_err(&s, e))?;
    beadchain::scene::validate(&s).map_err(crate::scene::scene_err)?;
    Ok((s, cfg))
}

/// An engine or method that cannot run the scene ([`engine::unrunnable`]), refused as the CLI
/// refuses it (`beadchain::cli::common::check_config`) but naming Python's keywords
/// (`engine="hybrid"`, not `--engine hybrid`): the keyword that chose it, or the scene's `[run]`
/// key when no keyword did, with the way out.
fn unrunnable(s: &LibScene, cfg: &RunConfig, o: &Options) -> PyResult<()> {
    use beadchain::engine::Unrunnable;
    let name = &s.name;
    let msg = match engine::unrunnable(s, cfg) {
        None => return Ok(()),
        Some(Unrunnable::DenseOnHard) => {
            let why = "cannot run this scene: it declares hard contacts or walls, which only the hybrid engine handles";
            match o.engine {
                Some(_) => format!("{name}: engine=\"dense\" {why}; pass engine=\"hybrid\""),
                None => format!(
                    "{name}: [run].engine: \"dense\" {why} (set engine = \"hybrid\" in the scene, or pass engine=\"hybrid\")"
                ),
            }
        }
        Some(Unrunnable::VerletOnDamped) => {
            let why = "does not integrate velocity-dependent (damped) contacts";
            match o.method {
                Some(_) => format!(
                    "{name}: method=\"verlet\" {why}; pass method=\"auto\", \"dop853\" or \"radau5\""
                ),
                None => format!(
                    "{name}: [run].method: \"verlet\" {why} (set method = \"auto\", \"dop853\" or \"radau5\" in the scene, or pass method=)"
                ),
            }
        }
    };
    Err(SceneError::new_err(msg))
}

fn config_err(scene: &LibScene, e: EngineError) -> PyErr {
    SceneError::new_err(format!("{}: {e}", scene.name))
}

/// An engine failure as a Python exception (the Python error first, if the observer has one).
pub(crate) fn engine_err(scene: &LibScene, obs: &mut Collector, e: EngineError) -> PyErr {
    if let Some(err) = obs.error.take() {
        return err;
    }
    match e {
        EngineError::Config(_) | EngineError::Checkpoint(_) => config_err(scene, e),
        _ => RunError::new_err(format!("{}: run failed: {e}", scene.name)),
    }
}

/// The counters and energies of an outcome.
pub(crate) fn stats<'py>(py: Python<'py>, o: &RunOutcome) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let s = &o.stats;
    d.set_item("steps", s.steps)?;
    d.set_item("implicit_steps", o.implicit_steps)?;
    d.set_item("rejected", s.rejected)?;
    d.set_item("rhs_evals", s.rhs_evals)?;
    d.set_item("jac_evals", s.jac_evals)?;
    d.set_item("factorizations", s.factorizations)?;
    d.set_item("newton_iters", s.newton_iters)?;
    d.set_item("newton_failures", s.newton_failures)?;
    d.set_item("bead_steps", s.bead_steps)?;
    d.set_item("t_end", o.t_end)?;
    d.set_item("wall_seconds", o.wall_seconds)?;
    d.set_item("energy_initial", o.energy_initial)?;
    d.set_item("energy_final", o.energy_final)?;
    d.set_item("energy_scale", o.energy_scale)?;
    d.set_item("dissipated", o.dissipated)?;
    d.set_item("relative_energy_error", o.relative_energy_error())?;
    d.set_item("momentum_initial", o.momentum_initial)?;
    d.set_item("momentum_final", o.momentum_final)?;
    let ev = PyDict::new(py);
    for (k, n) in o.events_by_kind.iter().flat_map(|c| c.iter()) {
        ev.set_item(k.to_string(), n)?;
    }
    d.set_item("events_by_kind", ev)?;
    d.set_item("largest_cluster", o.largest_cluster)?;
    d.set_item("late_merges", o.late_merges)?;
    d.set_item("slow_closings", o.slow_closings)?;
    d.set_item("shallow_closings", o.shallow_closings)?;
    Ok(d)
}

/// What `run` stores in the snapshot's STATS section (as `beadchain run` without `--timing`).
fn summary(out: &RunOutcome) -> RunSummary {
    RunSummary {
        stats: out.stats.clone(),
        wall_seconds: 0.0,
        t_end: out.t_end,
        energy_initial: out.energy_initial,
        energy_final: out.energy_final,
        momentum_initial: out.momentum_initial,
        momentum_final: out.momentum_final,
        events_by_kind: out.events_named(),
        largest_cluster: out.largest_cluster,
        notes: out
            .slow_closings_note()
            .into_iter()
            .chain(out.shallow_closings_note())
            .chain(std::iter::once(
                beadchain::snapshot::WALL_NOT_RECORDED.into(),
            ))
            .collect(),
    }
}

/// Moves the collected frames into a dict of arrays (`u`, `v` flat, `F·M` for the `M` stored
/// beads, None for a field not stored; `beads`: the stored bead indices, None for every bead;
/// no copy).
pub(crate) fn frames_dict<'py>(
    py: Python<'py>,
    c: &mut Collector,
    n: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let sel = &c.selection;
    d.set_item("n", sel.bead_count(n as u64))?;
    d.set_item("beads", sel.beads.clone())?;
    let (has_u, has_v) = (sel.fields.has_u(), sel.fields.has_v());
    d.set_item("t", PyArray1::from_vec(py, std::mem::take(&mut c.t)))?;
    let u = std::mem::take(&mut c.u);
    let v = std::mem::take(&mut c.v);
    d.set_item("u", has_u.then(|| PyArray1::from_vec(py, u)))?;
    d.set_item("v", has_v.then(|| PyArray1::from_vec(py, v)))?;
    let dis = std::mem::take(&mut c.dissipated);
    d.set_item(
        "dissipated",
        (!dis.is_empty()).then(|| PyArray1::from_vec(py, dis)),
    )?;
    d.set_item("events", std::mem::take(&mut c.events).into_dict(py)?)?;
    Ok(d)
}

/// The output rules of `beadchain run`, shared with it ([`size::check_frames_max`],
/// [`size::check_output_size`]): a run that would write more frames than `[output].frames_max`,
/// or whose estimated output (kept frames or snapshot file, the same bytes) is above `limit`, is
/// refused before it starts, with the keywords that fit it. The end time and the interval are
/// named as given (`until_si=` in seconds, then computer units; [`given_time`]).
fn check_output(
    s: &LibScene,
    (cfg, o): (&RunConfig, &Options),
    sel: &Selection,
    limit: u64,
) -> PyResult<()> {
    use beadchain::snapshot::size::{self, count_text, human_bytes};
    let (until, every) = (cfg.until, cfg.every);
    let until_text = given_time(s, ("until", o.until_si.is_some()), until);
    let every_text = every.map_or("every = none (first and last frame)".into(), |x| {
        given_time(s, ("every", o.every_si.is_some()), x)
    });
    if let Err(e) = size::check_frames_max(sel.frames_max, until, every) {
        let fits = e.every_that_fits;
        let fits_si = s.units.map_or(String::new(), |u| {
            format!(" (every_si={:.4e})", fits * u.time)
        });
        return Err(SceneError::new_err(format!(
            "{}: output.frames_max: the run would write {} frames ({until_text}, {every_text}), more than frames_max {}; use every={}{fits_si} or larger, or raise output frames_max",
            s.name,
            count_text(e.count),
            e.frames_max,
            size::short(fits),
        )));
    }
    let n = s.chain.len();
    let values = sel.values_per_frame(n as u64).unwrap_or(u64::MAX);
    if let Err(e) = size::check_output_size((n, values), (0.0, until, every), 0, limit) {
        let of = if sel.is_full() {
            format!("{n} beads")
        } else {
            format!("{values} stored values of {n} beads")
        };
        // the keywords as given: a larger every_si= where the interval came in seconds
        let ek = if o.every_si.is_some() {
            "every_si"
        } else {
            "every"
        };
        let uk = if o.until_si.is_some() {
            "until_si"
        } else {
            "until"
        };
        return Err(SceneError::new_err(format!(
            "{}: {ek}: the output would be about {} ({} frames of {of}: {until_text}, {every_text}), above the limit of {}: use a larger {ek}=, a smaller {uk}=, fewer beads or fields (output={{\"beads\": ..., \"fields\": ...}}), or pass max_output_bytes=",
            s.name,
            human_bytes(e.bytes),
            count_text(e.frames),
            human_bytes(limit as f64),
        )));
    }
    Ok(())
}

/// A run time `x` (computer units) named as given: `until_si = 1.0000e-4 s = 110.4 computer
/// units` where the keyword in seconds was passed (`key.1`), else `until = 110.4`, with the
/// seconds beside it in a physical scene (`until = 110.4 (1.0000e-4 s)`: the scene's own
/// `until_si` or `until`).
fn given_time(s: &LibScene, (key, si): (&str, bool), x: f64) -> String {
    use beadchain::snapshot::size::{seconds_then_units, short};
    match (s.units, si) {
        (Some(u), true) => format!("{key}_si = {}", seconds_then_units(x, u.time)),
        (Some(u), false) => format!("{key} = {} ({:.4e} s)", short(x), x * u.time),
        (None, _) => format!("{key} = {}", short(x)),
    }
}

/// Refuses an `out` that is the scene file `scene_file` or a CSV file it reads, as
/// `beadchain run --out` does.
#[pyfunction]
pub fn _check_run_out(out: PathBuf, scene_file: PathBuf) -> PyResult<()> {
    let inputs = beadchain::files::labelled_scene_inputs(&scene_file);
    beadchain::files::check_not_input(&[&out], "out", &inputs)
        .map_err(|e| SceneError::new_err(e.to_string()))
}

/// Runs `scene` to its end time; frames in memory (unless `record` is false) and, with `out`,
/// the CLI's snapshot file (written under a temporary name, renamed when the run finishes).
#[pyfunction]
#[pyo3(signature = (scene, engine=None, method=None, rtol=None, atol=None, every=None, until=None, out=None, record=true, max_steps=None, observers=Vec::new(), until_si=None, every_si=None, max_output_bytes=None, progress=None))]
#[allow(clippy::too_many_arguments)]
pub fn run<'py>(
    py: Python<'py>,
    scene: &Scene,
    engine: Option<String>,
    method: Option<String>,
    rtol: Option<f64>,
    atol: Option<f64>,
    every: Option<f64>,
    until: Option<f64>,
    out: Option<PathBuf>,
    record: bool,
    max_steps: Option<u64>,
    observers: Vec<Py<PyAny>>,
    until_si: Option<f64>,
    every_si: Option<f64>,
    max_output_bytes: Option<u64>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let o = Options {
        engine,
        method,
        rtol,
        atol,
        every,
        until,
        until_si,
        every_si,
        max_steps,
    };
    let (s, cfg) = config(&scene.scene, &o)?;
    let sel = s.run.output.clone().unwrap_or_default();
    let limit = match (record, &out) {
        (false, None) => u64::MAX, // nothing kept: only frames_max applies
        _ => max_output_bytes.unwrap_or(DEFAULT_MAX_OUTPUT_BYTES),
    };
    check_output(&s, (&cfg, &o), &sel, limit)?;
    let created_by = format!("python: beadchain.run({})", s.name);
    let writer = match &out {
        Some(path) => {
            let mut header = Header::new(
                s.clone(),
                cfg.engine,
                cfg.method,
                cfg.rtol,
                cfg.atol,
                created_by.clone(),
            );
            header.output = sel.clone();
            Some(
                SnapshotWriter::create(path, &header)
                    .map_err(|e| SnapshotError::new_err(e.to_string()))?,
            )
        }
        None => None,
    };
    let mut obs = Collector::new(record, writer, observers);
    obs.selection = sel;
    obs.progress = progress.map(|f| Progress::new(f, cfg.until));
    let r = without_gil(py, || -> Result<(Stop, RunOutcome), EngineError> {
        let mut e = engine::start(&s, &cfg)?;
        let stop = e.advance(cfg.until, &mut obs)?;
        Ok((stop, e.outcome()))
    });
    let (stop, outcome) = r.map_err(|e| engine_err(&s, &mut obs, e))?;
    if let Some(err) = obs.error.take() {
        return Err(err); // the unfinished output is removed when the writer drops
    }
    if let (Stop::Reached { .. }, Some(w)) = (stop, obs.writer.take()) {
        w.finish(&[], &summary(&outcome))
            .map_err(|e| SnapshotError::new_err(e.to_string()))?;
    }
    let d = frames_dict(py, &mut obs, s.chain.len())?;
    d.set_item("stats", stats(py, &outcome)?)?;
    // The settings the engine ran with (as a snapshot header stores them).
    d.set_item("engine", cfg.engine.name())?;
    d.set_item("method", cfg.method.name())?;
    d.set_item("rtol", cfg.rtol)?;
    d.set_item("atol", cfg.atol)?;
    // Provenance, as a snapshot header stores it (no date: runs from Python record no timing).
    d.set_item("crate_version", beadchain::provenance::VERSION)?;
    d.set_item("build_commit", beadchain::provenance::recorded_commit())?;
    d.set_item("created_by", created_by)?;
    d.set_item("scene", Scene::new(s)?)?;
    Ok(d)
}

/// A 1-D float array owned by Python.
type Array<'py> = Bound<'py, PyArray1<f64>>;

/// Kinetic and potential energy of every frame (`u`, `v` flat, `F·N`; computer units; the
/// potential holds contacts, walls and the field, as `beadchain inspect` reports it).
#[pyfunction]
pub fn energies<'py>(
    py: Python<'py>,
    scene: &Scene,
    u: PyReadonlyArray1<'py, f64>,
    v: PyReadonlyArray1<'py, f64>,
) -> PyResult<(Array<'py>, Array<'py>)> {
    let chain = &scene.scene.chain;
    let n = chain.len();
    let (u, v) = (u.as_slice()?, v.as_slice()?);
    if u.len() != v.len() || u.len() % n != 0 {
        return Err(SceneError::new_err(format!(
            "{}: energies: u and v must hold whole frames of {n} beads (got {} and {} values)",
            scene.scene.name,
            u.len(),
            v.len()
        )));
    }
    let (ke, pe): (Vec<f64>, Vec<f64>) = u
        .chunks_exact(n)
        .zip(v.chunks_exact(n))
        .map(|(u, v)| (chain.kinetic_energy(v), chain.potential_energy(u)))
        .unzip();
    Ok((PyArray1::from_vec(py, ke), PyArray1::from_vec(py, pe)))
}
