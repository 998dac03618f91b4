//! `Simulation`: the steppable engine ([`beadchain::engine::Engine`]) from Python: `advance(t)`
//! returns why it stopped, `state` is every bead at the engine clock, `set_velocities(v)` changes
//! the state between advances, and Python observers are called at frames (never per step).
//! Advancing in pieces gives the same frames as one `run()` (the library guarantees it).

use crate::observe::Collector;
use crate::run::{config, engine_err, frames_dict, stats, Options};
use crate::scene::Scene;
use crate::{without_gil, RunError, SceneError};
use beadchain::engine::{self, Engine, EngineError, PauseAt, RunConfig, Stop};
use beadchain::model::relative_energy_change;
use beadchain::names::Named;
use beadchain::scene::Scene as LibScene;
use beadchain::snapshot::size::short;
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::{Mutex, MutexGuard, PoisonError};

/// A running engine with the scene and configuration it borrows.
///
/// `engine` borrows `*scene` and `*cfg`: both are boxed (their addresses never change while the
/// boxes live) and never mutated, and `engine` is declared first, so it is dropped before them.
struct Running {
    /// Behind a mutex so that a `Simulation` may be used, and dropped, on any thread (an
    /// engine is `Send`, not `Sync`); `&mut` paths reach it without locking.
    engine: Mutex<Box<dyn Engine + 'static>>,
    obs: Collector,
    cfg: Box<RunConfig>,
    scene: Box<LibScene>,
}

impl Running {
    fn start(scene: LibScene, cfg: RunConfig, obs: Collector) -> Result<Self, engine::EngineError> {
        let scene = Box::new(scene);
        let cfg = Box::new(cfg);
        // SAFETY: see the struct docs (stable heap addresses, drop order, no mutation).
        let (s, c): (&'static LibScene, &'static RunConfig) = unsafe {
            (
                &*(scene.as_ref() as *const LibScene),
                &*(cfg.as_ref() as *const RunConfig),
            )
        };
        let engine = Mutex::new(engine::start(s, c)?);
        Ok(Self {
            engine,
            obs,
            cfg,
            scene,
        })
    }

    /// The engine, for reading (a panic inside an earlier call does not make it unreadable).
    fn engine(&self) -> MutexGuard<'_, Box<dyn Engine + 'static>> {
        self.engine.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The engine, for changing.
    fn engine_mut(&mut self) -> &mut Box<dyn Engine + 'static> {
        self.engine
            .get_mut()
            .unwrap_or_else(PoisonError::into_inner)
    }
}

/// The state `stats()` measures the energy error from: the last one `set_velocities` gave
/// (before any, the scene's initial state, as the engine's outcome reports it). The engine keeps
/// t = 0 as its reference; this layer records the set state so that the injected energy is not
/// reported as an integration error.
struct Reference {
    t: f64,
    energy: f64,
    /// [`beadchain::model::Chain::energy_scale`] of the set state.
    scale: f64,
    momentum: f64,
    /// The engine's dissipated energy (since t = 0) when the state was set.
    dissipated: f64,
}

/// A time as Python writes it (`nan`, `inf`, `-inf`; else as the CLI's messages do).
fn py_time(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        short(x)
    }
}

/// A simulation advanced step by step (see the Python `Simulation`).
#[pyclass(module = "beadchain._beadchain")]
pub struct Simulation {
    run: Running,
    /// Why and when the engine failed: later advances raise until a valid state is set.
    failed: Option<(f64, String)>,
    /// The last state `set_velocities` gave (None: the run's initial state).
    reference: Option<Reference>,
    /// Energy added by `set_velocities` calls (new minus old total energy, summed).
    injected: f64,
}

impl Simulation {
    /// Refuses an advance target that is not a time from the engine clock to the run's end
    /// (`ValueError` naming it and the valid range; the simulation is left as it was).
    fn check_target(&self, until: f64) -> PyResult<()> {
        let (now, end) = (self.run.engine().time(), self.run.cfg.until);
        let why = if until.is_nan() {
            "is not a number".to_string()
        } else if until.is_infinite() {
            "is not finite".to_string()
        } else if until > end {
            format!("is beyond the run's end time {}", short(end))
        } else if until < now {
            format!(
                "is before the engine clock t = {} (a simulation does not go back)",
                short(now)
            )
        } else {
            return Ok(());
        };
        Err(SceneError::new_err(format!(
            "{}: advance: until = {} {why}; expected a time from t = {} (the engine clock) to {} (the run's end time)",
            self.run.scene.name,
            py_time(until),
            short(now),
            short(end)
        )))
    }
}

#[pymethods]
impl Simulation {
    #[new]
    #[pyo3(signature = (scene, engine=None, method=None, rtol=None, atol=None, every=None, until=None, record=true, observers=Vec::new(), until_si=None, every_si=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        scene: &Scene,
        engine: Option<String>,
        method: Option<String>,
        rtol: Option<f64>,
        atol: Option<f64>,
        every: Option<f64>,
        until: Option<f64>,
        record: bool,
        observers: Vec<Py<PyAny>>,
        until_si: Option<f64>,
        every_si: Option<f64>,
    ) -> PyResult<Self> {
        let o = Options {
            engine,
            method,
            rtol,
            atol,
            every,
            until,
            until_si,
            every_si,
            max_steps: None,
        };
        let (s, cfg) = config(&scene.scene, &o)?;
        let name = s.name.clone();
        let obs = Collector::new(record, None, observers);
        let run =
            Running::start(s, cfg, obs).map_err(|e| SceneError::new_err(format!("{name}: {e}")))?;
        Ok(Self {
            run,
            failed: None,
            reference: None,
            injected: 0.0,
        })
    }

    /// Adds a Python observer `f(t, u, v)`, called at every later frame.
    fn add_observer(&mut self, f: Py<PyAny>) {
        self.run.obs.callbacks.push(f);
    }

    /// Where later advances pause: after every frame (`frames`), after every logged event
    /// (`events`, hybrid engine). Pausing changes no number of the run.
    #[pyo3(signature = (frames=false, events=false))]
    fn pause_at(&mut self, frames: bool, events: bool) {
        self.run.engine_mut().pause_at(PauseAt { frames, events });
    }

    /// Advances to `until` (default: the run's end time); returns `(reason, t, event)`:
    /// `("reached", t, None)`, `("frame", t, None)` or `("event", t, {t, contact, kind,
    /// rel_velocity, peak_overlap})` when paused there ([`Simulation::pause_at`]), or
    /// `("requested", t, None)` (an observer raised or Ctrl-C: the exception is raised instead).
    /// A target that is not a time from the engine clock to the run's end raises `SceneError`
    /// (a `ValueError`) and changes nothing; only an engine failure leaves the simulation
    /// failed.
    #[pyo3(signature = (until=None))]
    fn advance<'py>(
        &mut self,
        py: Python<'py>,
        until: Option<f64>,
    ) -> PyResult<(&'static str, f64, Option<Bound<'py, PyDict>>)> {
        if let Some((t, why)) = &self.failed {
            return Err(RunError::new_err(format!(
                "{}: advance: the simulation failed at t = {} ({why}) and stays failed; set a valid state with set_velocities(v) to go on, or start a new Simulation",
                self.run.scene.name,
                short(*t)
            )));
        }
        let target = until.unwrap_or(self.run.cfg.until);
        self.check_target(target)?;
        let Running { engine, obs, .. } = &mut self.run;
        let engine = engine.get_mut().unwrap_or_else(PoisonError::into_inner);
        let r = without_gil(py, || engine.advance(target, obs));
        let stop = r.map_err(|e| {
            // a refused configuration leaves the state as it was: only an engine that failed
            // while it ran stays failed
            if !matches!(e, EngineError::Config(_) | EngineError::Checkpoint(_)) {
                self.failed = Some((self.run.engine().time(), e.to_string()));
            }
            engine_err(&self.run.scene, &mut self.run.obs, e)
        })?;
        if let Some(err) = self.run.obs.error.take() {
            return Err(err);
        }
        Ok(match stop {
            Stop::Reached { t } => ("reached", t, None),
            Stop::Requested { t } => ("requested", t, None),
            Stop::Frame { t } => ("frame", t, None),
            Stop::Event { t, event } => {
                let d = PyDict::new(py);
                d.set_item("t", event.t)?;
                d.set_item("contact", event.contact)?;
                d.set_item("kind", event.kind.name())?;
                d.set_item("rel_velocity", event.rel_velocity)?;
                d.set_item("peak_overlap", event.peak_overlap)?;
                ("event", t, Some(d))
            }
        })
    }

    /// The engine clock.
    #[getter]
    fn time(&self) -> f64 {
        self.run.engine().time()
    }

    /// The run's end time.
    #[getter]
    fn until(&self) -> f64 {
        self.run.cfg.until
    }

    /// `(t, u, v)`: every bead at the engine clock.
    #[getter]
    fn state<'py>(
        &self,
        py: Python<'py>,
    ) -> (f64, Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>) {
        let s = self.run.engine().state();
        (
            s.t,
            PyArray1::from_vec(py, s.u),
            PyArray1::from_vec(py, s.v),
        )
    }

    /// Gives every bead the velocity `v` at the engine clock (displacements unchanged).
    fn set_velocities(&mut self, v: PyReadonlyArray1<'_, f64>) -> PyResult<()> {
        let v = v.as_slice()?;
        let n = self.run.scene.chain.len();
        if v.len() != n {
            return Err(SceneError::new_err(format!(
                "{}: set_velocities: expected {n} velocities (one per bead), got {}",
                self.run.scene.name,
                v.len()
            )));
        }
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(SceneError::new_err(format!(
                "{}: set_velocities: bead {i}: velocity must be finite, got {}",
                self.run.scene.name, v[i]
            )));
        }
        let name = self.run.scene.name.clone();
        let energy_before = {
            let s = self.run.engine().state();
            self.run.scene.chain.energy(&s.u, &s.v)
        };
        self.run
            .engine_mut()
            .set_velocities(v)
            .map_err(|e| SceneError::new_err(format!("{name}: {e}")))?;
        if self.failed.is_some() {
            let s = self.run.engine().state();
            if let Some(i) = s.u.iter().position(|x| !x.is_finite()) {
                return Err(RunError::new_err(format!(
                    "{name}: set_velocities: the failed simulation's displacement of bead {i} is {} at t = {}: it cannot go on; start a new Simulation",
                    s.u[i], s.t
                )));
            }
            self.failed = None;
        }
        let o = self.run.engine().outcome();
        let chain = &self.run.scene.chain;
        if energy_before.is_finite() {
            self.injected += o.energy_final - energy_before;
        }
        self.reference = Some(Reference {
            t: o.t_end,
            energy: o.energy_final,
            scale: chain.energy_scale(&o.u, &o.v),
            momentum: o.momentum_final,
            dissipated: o.dissipated,
        });
        Ok(())
    }

    /// Counters and energies at the engine clock (as `run().stats`), with the reference the
    /// energy error is measured from: `t_reference`, `energy_reference`, `momentum_reference`
    /// (the last state `set_velocities` gave, else t = 0) and `energy_injected` (the energy
    /// `set_velocities` calls added). `relative_energy_error` is
    /// `|E + E_d − E_ref − E_d,ref| / S` from that reference (`S`: the larger of `|E_ref|` and the
    /// gross energies of the reference and current states); `energy_initial` and
    /// `momentum_initial` stay those of t = 0.
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let o = self.run.engine().outcome();
        let d = stats(py, &o)?;
        match &self.reference {
            None => {
                d.set_item("t_reference", 0.0)?;
                d.set_item("energy_reference", o.energy_initial)?;
                d.set_item("momentum_reference", o.momentum_initial)?;
            }
            Some(r) => {
                let now = self.run.scene.chain.energy_scale(&o.u, &o.v);
                let scale = r.scale.max(now).max(r.energy.abs());
                let err = relative_energy_change(
                    r.energy,
                    o.energy_final + (o.dissipated - r.dissipated),
                    scale,
                );
                d.set_item("relative_energy_error", err)?;
                d.set_item("t_reference", r.t)?;
                d.set_item("energy_reference", r.energy)?;
                d.set_item("momentum_reference", r.momentum)?;
            }
        }
        d.set_item("energy_injected", self.injected)?;
        Ok(d)
    }

    /// `(engine, method, rtol, atol, every)` the simulation runs with.
    #[getter]
    fn _settings(&self) -> (&'static str, &'static str, f64, f64, Option<f64>) {
        let c = &self.run.cfg;
        (c.engine.name(), c.method.name(), c.rtol, c.atol, c.every)
    }

    /// Takes the frames recorded so far (a dict as `run()` returns; later frames start anew).
    fn _take_frames<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let n = self.run.scene.chain.len();
        frames_dict(py, &mut self.run.obs, n)
    }

    /// The scene as it runs (with `[run]` until/every of this simulation).
    #[getter]
    fn scene(&self) -> PyResult<Scene> {
        Scene::new(self.run.scene.as_ref().clone())
    }
}
