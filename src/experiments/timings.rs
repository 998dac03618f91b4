//! The gap timings of the paper's Sec. 3.1 (Figs. 4–5, interface `n1 = 3.0 → n2 = 3.5` at bead
//! `k = 50`), measured: [`Window`] records the overlaps around the interface and the hybrid
//! engine's events during a run, [`timing_run`] runs it and reads `t1 … t5` with
//! [`crate::analysis::timings`] (where the times are defined) from both sources.

use super::paper::{physical_scene, run_watched, time_per_bead, PaperError};
use crate::analysis::timings::{
    interface_timings, transitions_from_events, transitions_from_frames, InterfaceTimings,
    Transition,
};
use crate::engine::{self, EngineError, Observer, RunConfig, RunOutcome};
use crate::scene::{Engine, Scene};
use crate::snapshot::{EventKind, EventRecord};
use std::time::Instant;

/// Observer recording overlaps of contacts `c_lo..c_hi`, velocities of beads `b_lo..b_hi`, the
/// largest velocity of `probe` (incoming peak) and the last frame.
pub struct Window {
    chain: crate::model::Chain,
    /// Contact range (half-open).
    pub contacts: (usize, usize),
    /// Bead range (half-open).
    pub beads: (usize, usize),
    /// Probe bead for the incoming peak velocity.
    pub probe: usize,
    /// Frame times.
    pub t: Vec<f64>,
    /// `delta[j][f]`: overlap of contact `contacts.0 + j` at frame `f`.
    pub delta: Vec<Vec<f64>>,
    /// `vel[j][f]`: velocity of bead `beads.0 + j` at frame `f`.
    pub vel: Vec<Vec<f64>>,
    /// Largest velocity of the probe bead.
    pub v_in: f64,
    /// Last frame `(t, u, v)`.
    pub last: (f64, Vec<f64>, Vec<f64>),
    /// Events of the window's contacts (hybrid engine), in processing order.
    pub events: Vec<EventRecord>,
}

impl Window {
    /// A window over contacts `c` and beads `b` (half-open ranges) of `chain`.
    pub fn new(
        chain: crate::model::Chain,
        c: (usize, usize),
        b: (usize, usize),
        probe: usize,
    ) -> Self {
        Window {
            chain,
            contacts: c,
            beads: b,
            probe,
            t: Vec::new(),
            delta: vec![Vec::new(); c.1 - c.0],
            vel: vec![Vec::new(); b.1 - b.0],
            v_in: 0.0,
            last: (0.0, vec![], vec![]),
            events: Vec::new(),
        }
    }
}

impl Observer for Window {
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        self.t.push(t);
        for (j, c) in (self.contacts.0..self.contacts.1).enumerate() {
            self.delta[j].push(self.chain.overlap(c, u[c], u[c + 1]));
        }
        for (j, b) in (self.beads.0..self.beads.1).enumerate() {
            self.vel[j].push(v[b]);
        }
        self.v_in = self.v_in.max(v[self.probe]);
        self.last = (t, u.to_vec(), v.to_vec());
        Ok(())
    }

    fn events(&mut self, events: &[EventRecord]) -> Result<(), EngineError> {
        let (lo, hi) = self.contacts;
        self.events.extend(
            events
                .iter()
                .filter(|e| {
                    (lo as u64..hi as u64).contains(&e.contact)
                        && matches!(e.kind, EventKind::Close | EventKind::Open)
                })
                .cloned(),
        );
        Ok(())
    }
}

/// Median of a slice (`NaN` if empty).
fn median(mut x: Vec<f64>) -> f64 {
    if x.is_empty() {
        return f64::NAN;
    }
    x.sort_by(f64::total_cmp);
    x[x.len() / 2]
}

/// A timed interface run.
pub struct TimingRun {
    /// The scene that ran.
    pub scene: Scene,
    /// Times from the sampled overlaps.
    pub frames: InterfaceTimings,
    /// Times from the hybrid event log (`None` for the dense engine).
    pub events: Option<InterfaceTimings>,
    /// Openings/closings of contacts `k−3..=k+1` from the sampled overlaps.
    pub transitions: Vec<Transition>,
    /// The same from the hybrid event log (empty for the dense engine).
    pub event_transitions: Vec<Transition>,
    /// Time per bead of the left medium.
    pub tau: f64,
    /// Incoming peak velocity (bead `k−10`).
    pub v_in: f64,
    /// Median velocities of beads `k−1`, `k` between `t2` and `t3`.
    pub frozen1: (f64, f64),
    /// Median velocities of beads `k−1`, `k` between `t3_end` and `min(t4, t5)`.
    pub frozen2: (f64, f64),
    /// The window's recording.
    pub window: Window,
    /// Engine outcome (energies, events).
    pub outcome: RunOutcome,
    /// Wall-clock seconds (both the stop-time probe and the recorded run).
    pub seconds: f64,
}

/// Runs a physical scene with exponent value `exponent` (TOML), `seed`, `beads`, interface bead
/// `k`: first a watched run (stop when the leading wave reaches `beads − 12`) for the end time,
/// then the recorded run to that time with `engine`, Radau, `rtol`, `atol = rtol/100`, frames
/// `tau/50` apart (`tau`: time per bead of the left medium, `tau_slow`: of the slower medium).
#[allow(clippy::too_many_arguments)]
pub fn timing_run(
    exponent: &str,
    seed: u64,
    tau: f64,
    tau_slow: f64,
    beads: usize,
    k: usize,
    engine: Engine,
    rtol: f64,
) -> Result<TimingRun, PaperError> {
    let t0 = Instant::now();
    let probe = physical_scene(
        beads,
        exponent,
        seed,
        tau_slow * beads as f64 * 20.0,
        tau / 5.0,
    )?;
    let (w, _) = run_watched(&probe, k, beads.saturating_sub(12), rtol)?;
    let until = w.last.0.max(tau);
    let sc = physical_scene(beads, exponent, seed, until, tau / 50.0)?;
    let mut cfg = RunConfig::from_scene(&sc);
    cfg.engine = engine;
    cfg.rtol = rtol;
    cfg.atol = rtol / 100.0;
    let mut win = Window::new(
        sc.chain.clone(),
        (k - 3, k + 2),
        (k - 2, k + 2),
        k.saturating_sub(10),
    );
    let outcome = engine::run(&sc, &cfg, &mut win)?;
    let contacts: Vec<usize> = (k - 3..k + 2).collect();
    let dmax = win.delta[2].iter().cloned().fold(0.0, f64::max);
    let tr = transitions_from_frames(&win.t, &contacts, &win.delta, 1e-6 * dmax);
    let frames = interface_timings(&tr, k);
    let etr = transitions_from_events(&win.events, &contacts);
    let events = (engine == Engine::Hybrid).then(|| interface_timings(&etr, k));
    let between = |a: Option<f64>, b: Option<f64>, j: usize| {
        let (Some(a), Some(b)) = (a, b) else {
            return f64::NAN;
        };
        median(
            win.t
                .iter()
                .zip(&win.vel[j])
                .filter(|(t, _)| **t > a && **t < b)
                .map(|(_, v)| *v)
                .collect(),
        )
    };
    let end2 = match (frames.t4, frames.t5) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    };
    let frozen1 = (
        between(frames.t2, frames.t3, 1),
        between(frames.t2, frames.t3, 2),
    );
    let frozen2 = (
        between(frames.t3_end, end2, 1),
        between(frames.t3_end, end2, 2),
    );
    Ok(TimingRun {
        scene: sc,
        frames,
        events,
        transitions: tr,
        event_transitions: etr,
        tau,
        v_in: win.v_in,
        frozen1,
        frozen2,
        window: win,
        outcome,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

/// [`timing_run`] for the clean interface `n1 → n2` at bead `k` (Radau, `rtol = 1e-8`).
pub fn interface_timing_run(
    n1: f64,
    n2: f64,
    beads: usize,
    k: usize,
    engine: Engine,
) -> Result<TimingRun, PaperError> {
    let (t1, t2) = (time_per_bead(n1)?, time_per_bead(n2)?);
    let ex = format!("{{ base = {n1}, segments = [{{ from = {k}, value = {n2} }}] }}");
    timing_run(&ex, 0, t1, t1.max(t2), beads, k, engine, 1e-8)
}
