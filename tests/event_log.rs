//! The hybrid engine's event log (issue 10 "Bounded memory", issue 11 item 7):
//! - the log is streamed: a run's peak heap does not grow with its length (counting global
//!   allocator, live bytes per thread), and the events read back from the snapshot equal the
//!   in-memory log;
//! - event contents are exact: peak overlaps from the continuous output (two-body collision:
//!   energy bound `a δ_maxⁿ = ½ μ w²`), wall openings located at the crossing (single bead on a
//!   soft wall: analytic contact duration with the Beta function), and the wall events of an
//!   end bead inside a cluster alternate;
//! - merges and splits allocate nothing (allocation calls counted the same way).

mod common;
use beadchain::engine::{self, EngineError, Observer, Recorder, RunConfig};
use beadchain::integrate::Method;
use beadchain::model::{HardContacts, Wall};
use beadchain::scene::{parse_str, Engine, Scene};
use beadchain::snapshot::{EventKind, EventRecord, Header, Snapshot, SnapshotWriter};
use common::*;
use std::path::Path;

// ---- live-bytes counting allocator (per thread: tests run in parallel) ------------------------

#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::{peak_of, CALLS};

// ---- scenes -------------------------------------------------------------------------------

fn soft_wall(precompression: f64, prefactor: f64) -> Wall {
    Wall {
        exponent: 2.5,
        prefactor,
        precompression,
        restitution: None,
    }
}

/// Four beads with elastic hard contacts in a box of two soft walls: a steady stream of hard
/// collisions and wall closings/openings that never ends (energy is conserved).
fn box_scene(until: f64) -> (Scene, RunConfig) {
    let n = 4;
    let mut s = striker(n, 2.5, 1.0, 0.0, until);
    s.chain.hard = Some(HardContacts {
        restitution: vec![Some(1.0); n - 1],
        collapse_interval: 1e-9,
    });
    s.chain.left_wall = Some(soft_wall(-0.25, 1e3));
    s.chain.right_wall = Some(soft_wall(-0.25, 1e3));
    for i in 0..n {
        s.u0[i] = 0.1 * i as f64 - 0.15; // gaps of 0.1 between beads, 0.1 to the walls
    }
    s.v0 = vec![1.0, -0.7, 0.4, -0.3];
    let mut cfg = config(Engine::Hybrid, Method::Radau5, 1e-8, 1e-10, until);
    cfg.max_steps = Some(50_000_000);
    (s, cfg)
}

/// Counts events (and drops them): the engine's own memory is what is measured.
#[derive(Default)]
struct Count {
    events: u64,
}

impl Observer for Count {
    fn frame(&mut self, _t: f64, _u: &[f64], _v: &[f64]) -> Result<(), EngineError> {
        Ok(())
    }
}

/// Streams frames and event blocks into a snapshot, as `beadchain run` does.
struct Sink {
    w: SnapshotWriter,
    events: u64,
}

impl Observer for Sink {
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        self.w
            .write_frame(t, u, v)
            .map_err(|e| EngineError::Observer(e.to_string()))
    }
    fn events(&mut self, events: &[EventRecord]) -> Result<(), EngineError> {
        self.events += events.len() as u64;
        self.w
            .write_events(events)
            .map_err(|e| EngineError::Observer(e.to_string()))
    }
}

fn total_events(o: &engine::RunOutcome) -> u64 {
    o.events_total()
}

/// Regression (issue 10): the engine kept every event in memory for the whole run, so its peak
/// heap grew with the run length. Measured with this test before the fix (engine alone, events
/// dropped by the observer): 1 317 096 B with 20 619 events, 5 249 256 B with 82 276 events;
/// after: 170 232 B for both.
#[test]
fn event_log_memory_is_bounded_by_n_not_run_length() {
    let t = 1500.0;
    let mut peaks = Vec::new();
    for until in [t, 4.0 * t] {
        let (s, cfg) = box_scene(until);
        let mut obs = Count::default();
        let (out, peak) = peak_of(|| engine::run(&s, &cfg, &mut obs).expect("runs"));
        let ev = total_events(&out);
        // enough events that the log, kept, would dominate: 4 blocks at T
        assert!(
            ev as f64 >= 4.0 * engine::EVENT_BLOCK as f64 * until / t,
            "{ev} events"
        );
        assert_eq!(obs.events, 0);
        peaks.push((peak, ev));
    }
    let ((p1, e1), (p4, e4)) = (peaks[0], peaks[1]);
    println!("engine peak heap: {p1} B with {e1} events, {p4} B with {e4} events");
    // 4× the events within a bounded footprint: the peak may differ by allocator rounding and
    // queue/cluster sizes only (abs tol 16 KiB, rel tol 5% of the T peak); keeping the log costs
    // ≥ 40 bytes per event, i.e. ≥ 40·(e4 − e1) more.
    let tol = 16_384.0 + 0.05 * p1 as f64;
    assert!(
        (p4 as f64 - p1 as f64) <= tol,
        "peak {p1} B with {e1} events, {p4} B with {e4} events"
    );
}

/// Regression (hot loops allocation-free): every merge and every split allocated the merged
/// or split beads' states (two `Vec`s) and the new cluster's mass array. Measured with this
/// test before the fix (1000-bead striker to t = 400 and t = 800): 2993 allocation calls with
/// 967 events, 5904 with 1937; after: 99 and 100.
#[test]
fn merges_and_splits_allocate_nothing() {
    let mut calls = Vec::new();
    for until in [400.0, 800.0] {
        let s = striker(1000, 2.5, 1.0, 1.0, until);
        let cfg = config(Engine::Hybrid, Method::Auto, 1e-8, 1e-12, until);
        let mut obs = Count::default();
        let before = CALLS.with(|c| c.get());
        let out = engine::run(&s, &cfg, &mut obs).expect("runs");
        calls.push((CALLS.with(|c| c.get()) - before, total_events(&out)));
    }
    let ((c1, e1), (c2, e2)) = (calls[0], calls[1]);
    println!("{c1} allocation calls with {e1} events, {c2} with {e2}");
    assert!(e2 >= e1 + 900, "{e1} events to t = 400, {e2} to t = 800");
    // abs tol 16 calls (allocator and queue growth), far below one per event
    assert!(
        c2 <= c1 + 16,
        "{c1} allocation calls with {e1} events, {c2} with {e2}"
    );
}

/// A 3-bead column under gravity bouncing on a hard ceiling (hard collisions of a cluster's
/// bead: `src/engine/hybrid/hard.rs`).
const HARD_CEILING: &str = r#"
[chain]
beads = 3
[field]
gravity = 1.0
[walls]
left = {}
right = { hard = true }
force = 4.0
[initial]
equilibrium = true
velocity = [0.0, -0.8, 0.0]
[run]
until = 50.0
"#;

/// Plastic hard contacts inside a soft chain under gravity: rigid runs whose resting contacts
/// are examined at every step (`src/engine/hybrid/release.rs`).
const RIGID_IN_SOFT: &str = r#"
[chain]
beads = 12
[initial]
striker = 1.0
[field]
gravity = 0.5
[hard]
contacts = { from = 4, to = 7 }
restitution = 0.0
[walls]
left = { exponent = 2.5, prefactor = 1.0 }
[run]
until = 20.0
"#;

/// Regression (hot loops allocation-free): a cluster with holds allocated at every step, in
/// `Hybrid::first_release` (a state, accelerations and a copy of the margins per evaluation)
/// and `tension`/`release_pin` (the margins per call), and at every hard collision of one of
/// its beads (`replace_velocity`: two `Vec`s; `accel_of`: one). Measured with this test before
/// the fix (allocation calls, steps): the ceiling 1313 / 1212 to t = 50 and 1670 / 2177 to
/// t = 150; the rigid runs 1385 / 220 to t = 20 and 4170 / 797 to t = 60. After: 65 / 65 and
/// 132 / 153 (the integrator pool growing with the largest cluster).
#[test]
fn holds_and_hard_collisions_allocate_nothing_per_step() {
    for (text, t1) in [(HARD_CEILING, 50.0), (RIGID_IN_SOFT, 20.0)] {
        let s = parse_str(text, Path::new("."), "s.toml").expect("scene parses");
        let mut runs = Vec::new();
        for until in [t1, 3.0 * t1] {
            let cfg = config(Engine::Hybrid, Method::Auto, 1e-8, 1e-12, until);
            let mut obs = Count::default();
            let before = CALLS.with(|c| c.get());
            let out = engine::run(&s, &cfg, &mut obs).expect("runs");
            runs.push((CALLS.with(|c| c.get()) - before, out.stats.steps));
        }
        let ((c1, s1), (c2, s2)) = (runs[0], runs[1]);
        println!("{c1} allocation calls with {s1} steps, {c2} with {s2}");
        assert!(s2 >= s1 + 500, "{s1} steps to t = {t1}, {s2} to 3× that");
        // abs tol 40 calls (allocator, queue and integrator pool growth), far below one per step
        assert!(
            c2 <= c1 + 40,
            "{c1} allocation calls with {s1} steps, {c2} with {s2}"
        );
    }
}

/// The streamed log, read back from the snapshot, equals the in-memory log (count and every
/// record, bit for bit), and a streaming run's peak heap (engine + writer) does not grow with
/// the run length either.
#[test]
fn streamed_events_read_back_equal_the_in_memory_log() {
    let dir = tempfile::tempdir().expect("tempdir");
    let t = 1500.0;
    let mut peaks = Vec::new();
    for until in [t, 4.0 * t] {
        let (s, cfg) = box_scene(until);
        let path = dir.path().join(format!("box{until}.snap"));
        let header = Header::new(
            s.clone(),
            cfg.engine,
            cfg.method,
            cfg.rtol,
            cfg.atol,
            "t".into(),
        );
        let (res, peak) = peak_of(|| {
            let mut sink = Sink {
                w: SnapshotWriter::create(&path, &header).expect("create"),
                events: 0,
            };
            let out = engine::run(&s, &cfg, &mut sink).expect("runs");
            let n = sink.events;
            sink.w.finish(&[], &Default::default()).expect("finish");
            (out, n)
        });
        let (out, streamed) = res;
        assert_eq!(streamed, total_events(&out));
        let mut rec = Recorder::default();
        let again = engine::run(&s, &cfg, &mut rec).expect("runs");
        assert_eq!(again.events_by_kind, out.events_by_kind);
        let snap = Snapshot::open(&path).expect("opens");
        assert!(snap.is_complete() && snap.warnings().is_empty());
        assert_eq!(snap.events().len() as u64, streamed);
        assert_eq!(snap.events().len(), rec.events.len());
        for (k, (a, b)) in snap.events().iter().zip(&rec.events).enumerate() {
            let bits = |e: &EventRecord| {
                (
                    e.t.to_bits(),
                    e.contact,
                    e.kind,
                    e.rel_velocity.to_bits(),
                    e.peak_overlap.to_bits(),
                )
            };
            assert_eq!(bits(a), bits(b), "event {k}");
        }
        peaks.push(peak);
    }
    println!("streaming peak heap (engine + writer): {peaks:?} B at T, 4T");
    // abs tol 16 KiB, rel tol 5% (as above)
    let tol = 16_384.0 + 0.05 * peaks[0] as f64;
    assert!(
        (peaks[1] as f64 - peaks[0] as f64) <= tol,
        "streaming peaks {peaks:?}"
    );
}

// ---- exact event contents -----------------------------------------------------------------

/// `∫₀¹ dx / √(1 − xⁿ) = √π Γ(1 + 1/n) / Γ(1/2 + 1/n)` (= B(1/n, 1/2)/n).
fn half_duration_integral(n: f64) -> f64 {
    std::f64::consts::PI.sqrt() * gamma(1.0 + 1.0 / n) / gamma(0.5 + 1.0 / n)
}

/// Γ(x) for x ≥ 1/2: the library's Lanczos approximation (its known values are checked below).
use beadchain::model::collision::gamma;

#[test]
fn lanczos_gamma_is_exact_at_known_values() {
    // Γ(1/2) = √π, Γ(5) = 24, Γ(3/2) = √π/2: rel tol 1e-14
    let pi = std::f64::consts::PI;
    for (x, want) in [(0.5, pi.sqrt()), (5.0, 24.0), (1.5, pi.sqrt() / 2.0)] {
        assert!((gamma(x) / want - 1.0).abs() < 1e-14, "Γ({x})");
    }
    // n = 2 (harmonic): the integral is π/2
    assert!((half_duration_integral(2.0) / (pi / 2.0) - 1.0).abs() < 1e-14);
}

fn tight(scene: &Scene, method: Method) -> Recorder {
    let cfg = config(Engine::Hybrid, method, 1e-12, 1e-14, scene.run.until);
    run(scene, &cfg).1
}

/// Regression (issue 11 item 7): pair peak overlaps were the largest overlap at step ends
/// (measured with this test before the fix: 7.9e-8 (Radau5) and 1.1e-3 (DOP853) relative low);
/// now the maximum of the continuous output. Two-body collision of unit masses
/// at relative speed 1 with `a δⁿ`: `a δ_maxⁿ = ½ μ w²`, μ = 1/2.
#[test]
fn two_body_peak_overlap_matches_energy() {
    for method in [Method::Radau5, Method::Dop853] {
        let s = striker(2, 2.5, 1.0, 1.0, 6.0);
        let rec = tight(&s, method);
        let (mu, w, a, n): (f64, f64, f64, f64) = (0.5, 1.0, 1.0, 2.5);
        let dmax: f64 = (0.5 * mu * w * w / a).powf(1.0 / n);
        let open: Vec<&EventRecord> = rec
            .events
            .iter()
            .filter(|e| e.kind == EventKind::Open)
            .collect();
        assert_eq!(open.len(), 1, "{:?}", rec.events);
        let p = open[0].peak_overlap;
        // rel tol 1e-9 (abs tol 1e-9·δ_max ≈ 5.8e-10)
        assert!(
            (p - dmax).abs() <= 1e-9 * dmax,
            "{method:?}: peak {p:e}, energy bound {dmax:e}, rel {:e}",
            (p - dmax).abs() / dmax
        );
    }
}

/// Regression (issue 11 item 7): `wall_open` was logged at the end of the step in which the
/// bead left the wall, with peak overlap 0 (measured with this test before the fix: 1.8e-5
/// (Radau5) and 1.5e-5 (DOP853) of `T_c` late, peak 0). A
/// bead at speed 1 bouncing on a soft wall `a δⁿ`: contact from `t_hit = gap/w` for
/// `T_c = 2 (δ_max/w) ∫₀¹ dx/√(1 − xⁿ)`, `a δ_maxⁿ = ½ m w²`.
#[test]
fn wall_open_is_located_and_records_the_peak() {
    let mut s = striker(2, 2.5, 1.0, 0.0, 3.0);
    let gap = 0.25;
    s.chain.left_wall = Some(soft_wall(-gap, 1.0));
    s.v0 = vec![-1.0, 0.0];
    s.u0 = vec![0.0, 1.0]; // bead 1 at rest, a gap of 1 away: not reached before `until`
    for method in [Method::Radau5, Method::Dop853] {
        let rec = tight(&s, method);
        let (m, w, a, n): (f64, f64, f64, f64) = (1.0, 1.0, 1.0, 2.5);
        let dmax: f64 = (0.5 * m * w * w / a).powf(1.0 / n);
        let tc = 2.0 * dmax / w * half_duration_integral(n);
        let t_hit = gap / w;
        let find = |k: EventKind| {
            let v: Vec<&EventRecord> = rec.events.iter().filter(|e| e.kind == k).collect();
            assert_eq!(v.len(), 1, "{k:?}: {:?}", rec.events);
            v[0].clone()
        };
        let close = find(EventKind::WallClose);
        let open = find(EventKind::WallOpen);
        // closing located exactly on the free flight (abs tol 1e-12: θ/w plus rounding)
        assert!((close.t - t_hit).abs() < 1e-12, "close at {}", close.t);
        // rel tol 1e-8 of the contact duration
        let err = (open.t - (t_hit + tc)).abs() / tc;
        assert!(
            err < 1e-8,
            "{method:?}: open at {}, analytic {}, rel {err:e}",
            open.t,
            t_hit + tc
        );
        // peak: energy bound, rel tol 1e-9
        let p = open.peak_overlap;
        assert!(
            (p - dmax).abs() <= 1e-9 * dmax,
            "{method:?}: wall peak {p:e}, energy bound {dmax:e}"
        );
        // leaving speed: elastic, rel tol 1e-8
        assert!(
            (open.rel_velocity - w).abs() < 1e-8,
            "{}",
            open.rel_velocity
        );
    }
}

/// Streams into a snapshot and stops with a checkpoint (writer mark + engine state) at poll `at`.
struct StopSink {
    w: Option<SnapshotWriter>,
    polls: u64,
    at: u64,
    saved: Option<(engine::EngineState, beadchain::snapshot::WriterMark)>,
}

impl Observer for StopSink {
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        let w = self.w.as_mut().expect("writer");
        w.write_frame(t, u, v)
            .map_err(|e| EngineError::Observer(e.to_string()))
    }
    fn events(&mut self, events: &[EventRecord]) -> Result<(), EngineError> {
        let w = self.w.as_mut().expect("writer");
        w.write_events(events)
            .map_err(|e| EngineError::Observer(e.to_string()))
    }
    fn control(&mut self, _t: f64) -> engine::Control {
        self.polls += 1;
        engine::Control::stop_if(self.polls == self.at)
    }
    fn checkpoint(&mut self, state: &engine::EngineState) -> Result<(), EngineError> {
        let w = self.w.as_mut().expect("writer");
        let mark = w.mark().map_err(|e| EngineError::Observer(e.to_string()))?;
        self.saved = Some((state.clone(), mark));
        Ok(())
    }
}

/// A run stopped with a checkpoint in the middle of an event block and resumed into the same
/// file writes the same bytes as the run never interrupted (several blocks on each side).
#[test]
fn resumed_event_stream_is_byte_identical() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (s, cfg) = box_scene(700.0);
    let header = Header::new(
        s.clone(),
        cfg.engine,
        cfg.method,
        cfg.rtol,
        cfg.atol,
        "t".into(),
    );
    let full = dir.path().join("full.snap");
    let mut sink = Sink {
        w: SnapshotWriter::create(&full, &header).expect("create"),
        events: 0,
    };
    engine::run(&s, &cfg, &mut sink).expect("runs");
    assert!(
        sink.events > 2 * engine::EVENT_BLOCK as u64,
        "{}",
        sink.events
    );
    sink.w.finish(&[], &Default::default()).expect("finish");
    let mut count = Recorder::default();
    engine::run(&s, &cfg, &mut count).expect("runs");
    let cut = dir.path().join("cut.snap");
    for frac in [0.37, 0.81] {
        // the engine polls once per queue entry, more often than it logs events: a poll
        // number below the event count lies inside the run
        let events_total = count.events.len() as f64;
        let at = (events_total * frac) as u64;
        let mut first = StopSink {
            w: Some(SnapshotWriter::create(&cut, &header).expect("create")),
            polls: 0,
            at,
            saved: None,
        };
        let err = engine::run(&s, &cfg, &mut first).expect_err("stops");
        assert!(matches!(err, EngineError::Interrupted(_)), "{err}");
        let (state, mark) = first.saved.take().expect("checkpoint");
        first.w.take().expect("writer").detach().expect("detach");
        let mut second = Sink {
            w: SnapshotWriter::reopen(&mark).expect("reopen"),
            events: 0,
        };
        engine::resume(&s, &cfg, &state, &mut second).expect("resumes");
        second.w.finish(&[], &Default::default()).expect("finish");
        assert!(
            std::fs::read(&cut).expect("cut") == std::fs::read(&full).expect("full"),
            "resumed at poll {at}: bytes differ"
        );
    }
}

/// Regression: the soft-wall contact of an end bead that also touched its neighbour was not an
/// event. Only a lone bead's wall contacts were logged (a free bead reaching the wall, a lone
/// bead leaving it), so a wall contact that opened or closed while its bead was in a cluster
/// left the log's `wall_close`/`wall_open` unpaired. Measured with this test before the fix
/// (two beads in a box of soft walls 2 units out, t = 1000): at rtol 1e-6 (auto) 176 closings
/// against 178 openings, and on each wall two closings or two openings in a row. Now every
/// crossing of `θ` by a soft wall's overlap is logged when the queue reaches it: on each wall
/// the events alternate, closing first.
#[test]
fn soft_wall_events_pair_up_when_the_end_bead_touches_its_neighbour() {
    let mut s = striker(2, 2.5, 1.0, 0.0, 1000.0);
    s.chain.left_wall = Some(soft_wall(-2.0, 1.0));
    s.chain.right_wall = Some(soft_wall(-2.0, 1.0));
    s.u0 = vec![-1.0, 1.0];
    s.v0 = vec![-1.0, 0.37];
    for (method, rtol) in [
        (Method::Auto, 1e-6),
        (Method::Auto, 1e-9),
        (Method::Radau5, 1e-7),
    ] {
        let cfg = config(Engine::Hybrid, method, rtol, rtol * 1e-4, s.run.until);
        let (out, rec) = run(&s, &cfg);
        for (side, bead) in [(0, 0u64), (1, 1)] {
            let kinds: Vec<EventKind> = rec
                .events
                .iter()
                .filter(|e| {
                    e.contact == bead
                        && matches!(e.kind, EventKind::WallClose | EventKind::WallOpen)
                })
                .map(|e| e.kind)
                .collect();
            assert!(
                kinds.len() > 40,
                "{method:?} {rtol:e} wall {side}: {kinds:?}"
            );
            for (k, kind) in kinds.iter().enumerate() {
                let want = if k % 2 == 0 {
                    EventKind::WallClose
                } else {
                    EventKind::WallOpen
                };
                assert_eq!(
                    *kind,
                    want,
                    "{method:?} {rtol:e} wall {side}, event {k} of {}: {:?}",
                    kinds.len(),
                    out.events_by_kind
                );
            }
        }
    }
}
