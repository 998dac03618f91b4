//! Progress of long runs on standard error (`run`, `resume`, `check`, `accuracy`).
//!
//! [`RunProgress`] is an [indicatif] bar showing the simulated time reached, the engine's
//! events per second (hybrid: queue events, i.e. steps, closings, openings and frames; dense:
//! steps) and an ETA ([`eta_text`]: from the average rate since the start, and only once
//! [`ETA_AFTER`] has passed and [`ETA_MIN_FRACTION`] of the span is done; indicatif's own
//! estimate followed the recent rate and swung by orders of magnitude in the first seconds). It is drawn only when standard error is a terminal and the user did not
//! ask for `-q/--quiet`; otherwise it is hidden and prints nothing.
//!
//! It is driven by [`Watch`], an [`Observer`] wrapped around the run's own observer: every
//! call is forwarded unchanged (frames, event blocks, checkpoints, and the answer of
//! [`Observer::control`]), so a run's results are identical with and without the bar. The
//! engines ask `control` once per step/event; `Watch` reads the clock only every
//! [`SAMPLE_CALLS`] calls and redraws at most every [`REDRAW`] of wall time, so the hot loop
//! pays one counter increment per step (a hidden bar: nothing else, not even its message).

use crate::engine::{Control, EngineError, EngineState, Observer};
use crate::snapshot::EventRecord;
use indicatif::{HumanDuration, ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// `control` calls between two clock reads.
pub const SAMPLE_CALLS: u64 = 256;
/// Shortest wall time between two redraws (at most 10 per second).
pub const REDRAW: Duration = Duration::from_millis(100);
/// Bar resolution: the simulated-time span is shown in this many steps.
const TICKS: u64 = 1000;
/// Wall time before the first ETA.
pub const ETA_AFTER: Duration = Duration::from_secs(3);
/// Fraction of the simulated span done before the first ETA.
pub const ETA_MIN_FRACTION: f64 = 0.01;

/// The ETA shown after `elapsed` wall time with `fraction` of the simulated span done:
/// `elapsed·(1 − f)/f` (the average rate so far), as `eta 42s`, `eta 3m05s` or `eta 2h07m`;
/// `eta --` before [`ETA_AFTER`] or [`ETA_MIN_FRACTION`], when one step's cost and the
/// simulated time it covers still say little about the rest.
pub fn eta_text(elapsed: Duration, fraction: f64) -> String {
    if elapsed < ETA_AFTER || fraction.is_nan() || fraction < ETA_MIN_FRACTION {
        return "eta --".into();
    }
    let left = elapsed.as_secs_f64() * (1.0 - fraction.min(1.0)) / fraction;
    let s = left.round() as u64;
    match s {
        0..=59 => format!("eta {s}s"),
        60..=3599 => format!("eta {}m{:02}s", s / 60, s % 60),
        _ => format!("eta {}h{:02}m", s / 3600, s / 60 % 60),
    }
}

/// A progress bar on standard error (hidden when not a terminal or when quiet).
#[derive(Clone, Debug)]
pub struct RunProgress {
    bar: ProgressBar,
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
        if let Ok(style) = ProgressStyle::with_template("{bar:20} {msg}") {
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
            hidden: self.bar.is_hidden(),
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
    /// The bar is hidden: nothing to redraw, so no message is formatted (hot loops
    /// allocation-free).
    hidden: bool,
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
        let elapsed = now.duration_since(self.start);
        let rate = self.calls as f64 / elapsed.as_secs_f64().max(1e-9);
        let f = self.fraction(t);
        self.bar.set_position((f * TICKS as f64).round() as u64);
        self.bar.set_message(format!(
            "{}t = {t:.4e} of {:.4e}, {rate:.2e} events/s [{:#}, {}]",
            self.label,
            self.until,
            HumanDuration(elapsed),
            eta_text(elapsed, f)
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
        if !self.hidden && self.calls.is_multiple_of(SAMPLE_CALLS) {
            self.redraw(t);
        }
        self.inner.control(t)
    }

    fn checkpoint(&mut self, state: &EngineState) -> Result<(), EngineError> {
        self.inner.checkpoint(state)
    }
}
