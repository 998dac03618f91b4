//! The observer of Python runs: collects frames into flat vectors (handed to NumPy without a
//! copy), the event log as columns and the dissipated energy; optionally streams the same
//! snapshot file the CLI writes; calls Python observers at frames; and polls for signals so
//! Ctrl-C stops the engine (Control::Stop) instead of waiting for the run's end.
//!
//! Frames kept in memory hold only the run's output selection (`[output]` beads and fields, as
//! the snapshot file). Their buffers grow with `try_reserve`: an allocation that fails becomes a
//! Python `MemoryError` instead of aborting the interpreter. A frame with a non-finite value
//! stops the run with an error (no NaN frame is ever kept or written).

use beadchain::engine::{Control, EngineError, EngineState, Observer};
use beadchain::names::Named;
use beadchain::snapshot::{EventRecord, Selection, SnapshotWriter};
use numpy::PyArray1;
use pyo3::exceptions::PyMemoryError;
use pyo3::prelude::*;
use std::time::{Duration, Instant};

/// Wall time between two signal checks while the engine runs.
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Least wall time between two progress calls made between frames (a run with few frames).
const PROGRESS_EVERY: Duration = Duration::from_millis(200);

/// A Python progress callable `f(t, until)`: called at every frame and, between frames, at most
/// every [`PROGRESS_EVERY`] of wall time (checked with the signal poll, never per step).
pub(crate) struct Progress {
    pub f: Py<PyAny>,
    pub until: f64,
    last: Instant,
}

impl Progress {
    pub fn new(f: Py<PyAny>, until: f64) -> Self {
        Self {
            f,
            until,
            last: Instant::now(),
        }
    }
}

/// The event log as columns (a `pandas.DataFrame` takes them as they are).
#[derive(Default)]
pub(crate) struct EventColumns {
    pub t: Vec<f64>,
    /// Contact indices as int64, as `events_to_xarray` has them (a uint64 `contact - 1` wraps).
    pub contact: Vec<i64>,
    pub kind: Vec<&'static str>,
    pub rel_velocity: Vec<f64>,
    pub peak_overlap: Vec<f64>,
}

impl EventColumns {
    pub fn push(&mut self, e: &EventRecord) {
        self.t.push(e.t);
        self.contact
            .push(i64::try_from(e.contact).unwrap_or(i64::MAX));
        self.kind.push(e.kind.name());
        self.rel_velocity.push(e.rel_velocity);
        self.peak_overlap.push(e.peak_overlap);
    }

    /// Moves the columns into a dict of arrays (`kind` as a list of names).
    pub fn into_dict(self, py: Python<'_>) -> PyResult<Bound<'_, pyo3::types::PyDict>> {
        let d = pyo3::types::PyDict::new(py);
        d.set_item("t", PyArray1::from_vec(py, self.t))?;
        d.set_item("contact", PyArray1::from_vec(py, self.contact))?;
        d.set_item("kind", self.kind)?;
        d.set_item("rel_velocity", PyArray1::from_vec(py, self.rel_velocity))?;
        d.set_item("peak_overlap", PyArray1::from_vec(py, self.peak_overlap))?;
        Ok(d)
    }
}

/// Frames, events, dissipated energy; output file; Python observers; signal polling.
pub(crate) struct Collector {
    /// Keep frames in memory.
    pub record: bool,
    /// Which beads and fields the kept frames hold (every bead and both fields by default).
    pub selection: Selection,
    pub t: Vec<f64>,
    /// Displacements, frame after frame (`F·N`).
    pub u: Vec<f64>,
    /// Velocities, frame after frame (`F·N`).
    pub v: Vec<f64>,
    pub dissipated: Vec<f64>,
    pub events: EventColumns,
    pub writer: Option<SnapshotWriter>,
    /// Python callables `f(t, u, v)` called at every frame.
    pub callbacks: Vec<Py<PyAny>>,
    /// The first Python exception (a signal handler's KeyboardInterrupt, an observer's error):
    /// the engine is asked to stop and the caller raises it.
    pub error: Option<PyErr>,
    /// The progress callable of `run(progress=...)`.
    pub progress: Option<Progress>,
    last_poll: Instant,
    polls: u32,
}

impl Collector {
    pub fn new(record: bool, writer: Option<SnapshotWriter>, callbacks: Vec<Py<PyAny>>) -> Self {
        Self {
            record,
            selection: Selection::default(),
            t: Vec::new(),
            u: Vec::new(),
            v: Vec::new(),
            dissipated: Vec::new(),
            events: EventColumns::default(),
            writer,
            callbacks,
            error: None,
            progress: None,
            last_poll: Instant::now(),
            polls: 0,
        }
    }

    /// Runs Python's signal handlers (KeyboardInterrupt on Ctrl-C); keeps the first error.
    fn check_signals(&mut self) {
        if self.error.is_none() {
            if let Err(e) = Python::attach(|py| py.check_signals()) {
                self.error = Some(e);
            }
        }
        self.last_poll = Instant::now();
    }

    /// Calls the progress callable with `t` (keeps its error as an observer's).
    fn call_progress(&mut self, t: f64) {
        let Some(p) = self.progress.as_mut() else {
            return;
        };
        if self.error.is_some() {
            return;
        }
        p.last = Instant::now();
        if let Err(e) = Python::attach(|py| p.f.call1(py, (t, p.until)).map(drop)) {
            self.error = Some(e);
        }
    }

    fn call_observers(&mut self, t: f64, u: &[f64], v: &[f64]) {
        if self.callbacks.is_empty() || self.error.is_some() {
            return;
        }
        let r = Python::attach(|py| -> PyResult<()> {
            let (pu, pv) = (PyArray1::from_slice(py, u), PyArray1::from_slice(py, v));
            for cb in &self.callbacks {
                cb.call1(py, (t, pu.clone(), pv.clone()))?;
            }
            Ok(())
        });
        if let Err(e) = r {
            self.error = Some(e);
        }
    }
}

/// Appends the values of `x` at `beads` (every bead: `None`) to `out`, growing it with
/// `try_reserve`.
fn push_selected(
    out: &mut Vec<f64>,
    x: &[f64],
    beads: Option<&[u64]>,
) -> Result<(), std::collections::TryReserveError> {
    match beads {
        None => {
            out.try_reserve(x.len())?;
            out.extend_from_slice(x);
        }
        Some(b) => {
            out.try_reserve(b.len())?;
            out.extend(b.iter().map(|&i| x[i as usize]));
        }
    }
    Ok(())
}

/// The first bead whose displacement or velocity is not finite.
fn non_finite(t: f64, u: &[f64], v: &[f64]) -> Option<String> {
    let i = (0..u.len()).find(|&i| !u[i].is_finite() || !v[i].is_finite())?;
    Some(format!(
        "the state became non-finite at t = {t} (bead {i}: u = {}, v = {}); no frame was kept",
        u[i], v[i]
    ))
}

impl Collector {
    /// Keeps a frame in memory (the selected beads and fields); a failed allocation leaves a
    /// `MemoryError` for the caller and stops the engine.
    fn keep(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        let beads = self.selection.beads.as_deref();
        let fields = self.selection.fields;
        let r = (|| {
            self.t.try_reserve(1)?;
            if fields.has_u() {
                push_selected(&mut self.u, u, beads)?;
            }
            if fields.has_v() {
                push_selected(&mut self.v, v, beads)?;
            }
            self.t.push(t);
            Ok::<(), std::collections::TryReserveError>(())
        })();
        r.map_err(|e| {
            let kept = self.t.len();
            let msg = format!(
                "run: out of memory keeping frame {kept} at t = {t} ({e}): keep fewer frames (a larger every=), fewer beads or fields (output={{\"beads\": ..., \"fields\": ...}}), or write them to a file only (out=..., record=False)"
            );
            self.error = Some(PyMemoryError::new_err(msg.clone()));
            EngineError::Observer(msg)
        })
    }
}

impl Observer for Collector {
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        if let Some(msg) = non_finite(t, u, v) {
            return Err(EngineError::Observer(msg));
        }
        if self.record {
            self.keep(t, u, v)?;
        }
        if let Some(w) = self.writer.as_mut() {
            w.frame(t, u, v)?;
        }
        self.call_observers(t, u, v);
        self.call_progress(t);
        self.check_signals();
        Ok(())
    }

    fn dissipated(&mut self, t: f64, energy: f64) -> Result<(), EngineError> {
        if let Some(w) = self.writer.as_mut() {
            w.dissipated(t, energy)?;
        }
        if self.record {
            self.dissipated.try_reserve(1).map_err(|e| {
                self.error = Some(PyMemoryError::new_err(format!(
                    "run: out of memory keeping the dissipated energy ({e})"
                )));
                EngineError::Observer("out of memory".into())
            })?;
            self.dissipated.push(energy);
        }
        Ok(())
    }

    fn events(&mut self, events: &[EventRecord]) -> Result<(), EngineError> {
        if self.record {
            for e in events {
                self.events.push(e);
            }
        }
        if let Some(w) = self.writer.as_mut() {
            w.events(events)?;
        }
        Ok(())
    }

    fn control(&mut self, t: f64) -> Control {
        self.polls = self.polls.wrapping_add(1);
        if self.polls.is_multiple_of(64) && self.last_poll.elapsed() >= SIGNAL_POLL {
            self.check_signals();
            if self
                .progress
                .as_ref()
                .is_some_and(|p| p.last.elapsed() >= PROGRESS_EVERY)
            {
                self.call_progress(t);
            }
        }
        if self.error.is_some() {
            Control::Stop
        } else {
            Control::Continue
        }
    }

    fn checkpoint(&mut self, _state: &EngineState) -> Result<(), EngineError> {
        Ok(())
    }
}
