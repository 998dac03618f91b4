//! Progress of long runs on standard error (`run`, `resume`, `check`, `accuracy`).
//!
//! [`RunProgress`] is an [indicatif] bar showing the simulated time reached, the engine's
//! events per second (hybrid: queue events, i.e. steps, closings, openings and frames; dense:
//! steps) and an ETA. It is drawn only when standard error is a terminal and the user did not
//! ask for `-q/--quiet`; otherwise it is hidden and prints nothing.
//!
//! It is driven by [`Watch`], an [`Observer`] wrapped around the run's own observer: every
//! call is forwarded unchanged (frames, event blocks, checkpoints, and the answer of
//! [`Observer::control`]), so a run's results are identical with and without the bar. The
//! engines ask `control` once per step/event; `Watch` reads the clock only every
//! [`SAMPLE_CALLS`] calls and redraws at most every [`REDRAW`] of wall time, so the hot loop
//! pays one counter increment per step.

use crate::engine::{Control, EngineError, EngineState, Observer};
use crate::snapshot::EventRecord;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// `control` calls between two clock reads.
pub const SAMPLE_CALLS: u64 = 256;
/// Shortest wall time between two redraws (at most 10 per second).
pub const REDRAW: Duration = Duration::from_millis(100);
/// Bar resolution: the simulated-time span is shown in this many steps.
const TICKS: u64 = 1000;

/// A progress bar on standard error (hidden when not a terminal or when quiet).
#[derive(Clone, Debug)]
pub struct RunProgress {
    bar: ProgressBar,
}

impl PartialEq for RunProgress {
    /// Bars carry no result: any two compare equal (so options holding one stay comparable).
    fn eq(&self, _other: &Self) -> bool {
        true
    }
}

impl RunProgress {
    /// A bar on standard error, drawn only if standard error is a terminal and `!quiet`.
    pub fn new(quiet: bool) -> Self {
        let target = if quiet || !std::io::stderr().is_terminal() {
            ProgressDrawTarget::hidden()
        } else {
            ProgressDrawTarget::stderr_with_hz(10)
        };
        let bar = ProgressBar::with_draw_target(Some(TICKS), target);
        if let Ok(style) = ProgressStyle::with_template("{bar:20} {msg} [{elapsed}, eta {eta}]") {
            bar.set_style(style);
        }
        Self { bar }
    }

    /// A bar that never draws.
    pub fn hidden() -> Self {
        Self::new(true)
    }

    /// Is the bar drawn?
    pub fn is_hidden(&self) -> bool {
        self.bar.is_hidden()
    }

    /// Wraps `inner` for one run from simulated time `t0` to `until`; `label` prefixes the
    /// message (e.g. "hybrid").
    pub fn watch<'a>(
        &'a self,
        inner: &'a mut dyn Observer,
        t0: f64,
        until: f64,
        label: &str,
    ) -> Watch<'a> {
        self.bar.reset();
        self.bar.set_position(0);
        let now = Instant::now();
        Watch {
            inner,
            bar: &self.bar,
            label: label.to_string(),
            t0,
            until,
            calls: 0,
            start: now,
            last: now,
        }
    }

    /// Removes the bar from the terminal (before the results are printed).
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// The observer wrapper that feeds a [`RunProgress`] (see the module docs).
pub struct Watch<'a> {
    inner: &'a mut dyn Observer,
    bar: &'a ProgressBar,
    label: String,
    t0: f64,
    until: f64,
    calls: u64,
    start: Instant,
    last: Instant,
}

impl Watch<'_> {
    /// Number of `control` calls (engine steps/events) seen so far.
    pub fn calls(&self) -> u64 {
        self.calls
    }

    /// Fraction of the simulated span `[t0, until]` reached at `t`, in `[0, 1]`.
    pub fn fraction(&self, t: f64) -> f64 {
        let span = self.until - self.t0;
        if span > 0.0 && t.is_finite() {
            ((t - self.t0) / span).clamp(0.0, 1.0)
        } else {
            0.0
        }
    }

    fn redraw(&mut self, t: f64) {
        let now = Instant::now();
        if now.duration_since(self.last) < REDRAW {
            return;
        }
        self.last = now;
        let secs = now.duration_since(self.start).as_secs_f64().max(1e-9);
        let rate = self.calls as f64 / secs;
        self.bar
            .set_position((self.fraction(t) * TICKS as f64).round() as u64);
        self.bar.set_message(format!(
            "{}t = {t:.4e} of {:.4e}, {rate:.2e} events/s",
            self.label, self.until
        ));
    }
}

impl Observer for Watch<'_> {
    fn dissipated(&mut self, t: f64, energy: f64) -> Result<(), EngineError> {
        self.inner.dissipated(t, energy)
    }
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        self.inner.frame(t, u, v)
    }

    fn events(&mut self, events: &[EventRecord]) -> Result<(), EngineError> {
        self.inner.events(events)
    }

    fn control(&mut self, t: f64) -> Control {
        self.calls += 1;
        if self.calls % SAMPLE_CALLS == 0 {
            self.redraw(t);
        }
        self.inner.control(t)
    }

    fn checkpoint(&mut self, state: &EngineState) -> Result<(), EngineError> {
        self.inner.checkpoint(state)
    }
}
