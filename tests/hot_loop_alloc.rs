//! Hot loops allocation-free (project standard): a run's heap allocation calls do not grow with
//! its steps, events or frames. Each test runs the same scene to `T` and to `3T` (or with 3× the
//! frames) through the library and counts the allocation calls with a counting global allocator
//! (`tests/common/counting_alloc.rs`, per thread); what a run allocates once (the chain, the
//! engine's arrays, the integrator pool up to its largest cluster) is the same for both, so the
//! counts may differ by a small slack only, stated at each assertion.

mod common;
#[path = "common/counting_alloc.rs"]
mod counting_alloc;

use beadchain::analysis;
use beadchain::engine::{self, EngineError, Observer, RunConfig, RunOutcome};
use beadchain::integrate::Method;
use beadchain::progress::{RunProgress, REDRAW, SAMPLE_CALLS};
use beadchain::scene::{parse_str, Engine, Scene};
use beadchain::snapshot::ckpt::{read_checkpoint, write_checkpoint};
use beadchain::snapshot::sink::{CheckpointPolicy, SnapshotSink};
use beadchain::snapshot::{Header, SnapshotWriter};
use common::{config, striker};
use counting_alloc::calls_of;
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

/// Drops frames: the engine's own allocations are what is counted.
#[derive(Default)]
struct Drop {
    frames: u64,
}

impl Observer for Drop {
    fn frame(&mut self, _t: f64, _u: &[f64], _v: &[f64]) -> Result<(), EngineError> {
        self.frames += 1;
        Ok(())
    }
}

/// Runs `s` with `cfg`: allocation calls, the outcome and the frames handed out.
fn counted(s: &Scene, cfg: &RunConfig) -> (u64, RunOutcome, u64) {
    let mut obs = Drop::default();
    let (out, calls) = calls_of(|| engine::run(s, cfg, &mut obs).expect("runs"));
    (calls, out, obs.frames)
}

/// A scene from its TOML text.
fn scene(text: &str) -> Scene {
    parse_str(text, Path::new("."), "s.toml").expect("scene parses")
}

/// Forty beads with viscoelastic contacts (and a damped wall) in a box, gaps between them:
/// damped merges and splits all along the run.
const VISCO_GAS: &str = r#"
[scene]
name = "visco_gas"
seed = 9
[chain]
beads = 40
precompression = -1.0
law = "viscoelastic"
damping = 0.01
[initial]
velocity = { random = { mean = 0.0, eps = 1.0 } }
[walls]
left = { exponent = 2.5, prefactor = 1.0, precompression = -1.0, damping = 0.05 }
right = { exponent = 2.5, prefactor = 1.0, precompression = -1.0 }
[run]
until = 100.0
"#;

/// Regression (defect 1 of the allocation audit): `integrate::dissipated_at` allocated two
/// scratch vectors per call, i.e. per damped merge (the removed cluster's energy at the merge
/// time) and, on every frame of a damped scene, per live cluster (hybrid) or once (dense).
/// Measured with this test before the fix (allocation calls, to t = 20 and to t = 60): hybrid
/// 7746 (211 events, 401 frames) and 20385 (574, 1201); dense 812 and 2412. After: 409 and
/// 442; 15 and 15.
#[test]
fn dissipated_at_allocates_nothing_per_merge_or_frame() {
    let s = scene(VISCO_GAS);
    let mut grew = Vec::new();
    for kind in [Engine::Hybrid, Engine::Dense] {
        let mut runs = Vec::new();
        for until in [20.0, 60.0] {
            let mut cfg = config(kind, Method::Auto, 1e-8, 1e-12, until);
            cfg.every = Some(0.05);
            let (calls, out, frames) = counted(&s, &cfg);
            runs.push((calls, out.events_total(), frames));
        }
        let ((c1, e1, f1), (c2, e2, f2)) = (runs[0], runs[1]);
        let line = format!(
            "{kind:?}: {c1} allocation calls with {e1} events and {f1} frames, {c2} with {e2} and {f2}"
        );
        println!("{line}");
        assert!(f2 >= f1 + 800, "{f1} frames to t = 20, {f2} to t = 60");
        if kind == Engine::Hybrid {
            assert!(e2 >= e1 + 300, "{e1} events to t = 20, {e2} to t = 60");
        }
        // abs tol 64 calls (allocator and queue growth, and the integrator pool's arrays
        // growing to the largest clusters: +33 measured), far below one per frame or event
        if c2 > c1 + 64 {
            grew.push(line);
        }
    }
    assert!(grew.is_empty(), "{grew:#?}");
}

/// Regression (defect 2 of the allocation audit): Radau IIA and velocity Verlet did not
/// implement `Integrator::renew`, so the hybrid engine built a new integrator for every new
/// cluster (Radau IIA: ~40 allocations, Verlet: 5) and dropped the removed ones it kept.
/// Measured with this test before the fix (allocation calls, 300-bead striker to t = 60 and to
/// t = 180): Radau IIA 5764 (143 events) and 17445 (435); Verlet 763 (144) and 2214 (434).
/// After: 235 and 236; 65 and 66.
#[test]
fn radau5_and_verlet_integrators_are_renewed_not_rebuilt() {
    let mut grew = Vec::new();
    for (method, rtol) in [(Method::Radau5, 1e-8), (Method::Verlet, 1e-3)] {
        let mut runs = Vec::new();
        for until in [60.0, 180.0] {
            let s = striker(300, 2.5, 1.0, 1.0, until);
            let cfg = config(Engine::Hybrid, method, rtol, rtol * 1e-4, until);
            let (calls, out, _) = counted(&s, &cfg);
            runs.push((calls, out.events_total()));
        }
        let ((c1, e1), (c2, e2)) = (runs[0], runs[1]);
        let line = format!("{method:?}: {c1} allocation calls with {e1} events, {c2} with {e2}");
        println!("{line}");
        assert!(e2 >= e1 + 200, "{e1} events to t = 60, {e2} to t = 180");
        // abs tol 40 calls (allocator, queue and integrator pool growth), far below one per
        // event
        if c2 > c1 + 40 {
            grew.push(line);
        }
    }
    assert!(grew.is_empty(), "{grew:#?}");
}

/// Twenty beads in a box, masses alternating 1 and 1e-3, with damped contacts: the light beads'
/// fast modes are damped out within each collision, so most clusters turn stiff and the
/// `auto` method switches them to Radau IIA.
const STIFF_DIMER_GAS: &str = r#"
[scene]
name = "stiff_dimer_gas"
seed = 3
[chain]
beads = 20
mass = [1.0, 0.001, 1.0, 0.001, 1.0, 0.001, 1.0, 0.001, 1.0, 0.001, 1.0, 0.001, 1.0, 0.001, 1.0, 0.001, 1.0, 0.001, 1.0, 0.001]
precompression = -0.2
law = "viscoelastic"
damping = 0.1
[initial]
velocity = { random = { mean = 0.0, eps = 1.0 } }
[walls]
left = { exponent = 2.5, prefactor = 1.0, precompression = -0.2 }
right = { exponent = 2.5, prefactor = 1.0, precompression = -0.2 }
[run]
until = 100.0
"#;

/// Regression (defect 3 of the allocation audit): `Auto::renew` dropped the Radau IIA it had
/// built, so every reused `auto` integrator that turned stiff built a new one (~40 allocations
/// per switch). Measured with this test before the fix (allocation calls, to t = 30 and to
/// t = 90): 1982 (174 events, 4342 implicit steps) and 3904 (416, 9366). After: 757 and 759.
#[test]
fn auto_keeps_its_radau5_when_renewed() {
    let s = scene(STIFF_DIMER_GAS);
    let mut runs = Vec::new();
    for until in [30.0, 90.0] {
        let cfg = config(Engine::Hybrid, Method::Auto, 1e-8, 1e-12, until);
        let (calls, out, _) = counted(&s, &cfg);
        runs.push((calls, out.events_total(), out.implicit_steps));
    }
    let ((c1, e1, i1), (c2, e2, i2)) = (runs[0], runs[1]);
    println!(
        "{c1} allocation calls with {e1} events and {i1} implicit steps, {c2} with {e2} and {i2}"
    );
    assert!(e2 >= e1 + 150, "{e1} events to t = 30, {e2} to t = 90");
    assert!(
        i2 >= i1 + 2000,
        "{i1} implicit steps to t = 30, {i2} to t = 90"
    );
    // abs tol 40 calls (allocator, queue and integrator pool growth), far below one per
    // switch to the implicit method
    assert!(
        c2 <= c1 + 40,
        "{c1} allocation calls with {e1} events and {i1} implicit steps, {c2} with {e2} and {i2}"
    );
}

/// Regression (defect 4 of the allocation audit): `run --stop-when-fragmented` allocated at
/// every frame: the engine's state (two `Vec`s) and, before knowing whether the chain had
/// fragmented, the fragments left of the first contact that had not. Measured with this test
/// before the fix (allocation calls, 200-bead striker to t = 40 with 401 and 1201 frames):
/// hybrid 2246 and 6548, dense 2171 and 6473. After: 92 and 92, 17 and 17.
#[test]
fn stop_when_fragmented_allocates_nothing_per_frame() {
    let mut grew = Vec::new();
    for kind in [Engine::Hybrid, Engine::Dense] {
        let mut runs = Vec::new();
        for every in [0.1, 0.1 / 3.0] {
            let s = striker(200, 2.5, 1.0, 1.0, 40.0);
            let mut cfg = config(kind, Method::Auto, 1e-8, 1e-12, 40.0);
            cfg.every = Some(every);
            let mut obs = Drop::default();
            let ((_, fragmented), calls) =
                calls_of(|| analysis::run_until_fragmented(&s, &cfg, &mut obs).expect("runs"));
            assert!(
                fragmented.is_none(),
                "the wave is still in the chain at t = 40"
            );
            runs.push((calls, obs.frames));
        }
        let ((c1, f1), (c2, f2)) = (runs[0], runs[1]);
        let line = format!("{kind:?}: {c1} allocation calls with {f1} frames, {c2} with {f2}");
        println!("{line}");
        assert!(f2 >= 2 * f1, "{f1} frames, then {f2}");
        // abs tol 16 calls (allocator and queue growth), far below one per frame
        if c2 > c1 + 16 {
            grew.push(line);
        }
    }
    assert!(grew.is_empty(), "{grew:#?}");
}

/// Regression (defect 5 of the allocation audit): a hidden progress bar (`-q`, or standard
/// error not a terminal) still formatted its message (the text and the ETA) at every redraw,
/// i.e. every [`SAMPLE_CALLS`] engine steps once [`REDRAW`] had passed. Driven here as an
/// engine drives it, one `control` call per step, with a pause longer than `REDRAW` before each
/// batch of `SAMPLE_CALLS` calls: each batch would redraw a visible bar. Measured with this test
/// before the fix (allocation calls): 6 in 2 redraw periods, 18 in 6. After: 0 and 0.
#[test]
fn hidden_progress_bar_formats_nothing() {
    let bar = RunProgress::hidden();
    let mut inner = Drop::default();
    let mut watch = bar.watch(&mut inner, 0.0, 10.0, "hybrid ");
    let mut runs = Vec::new();
    for redraws in [2, 6] {
        let ((), calls) = calls_of(|| {
            for k in 0..redraws {
                std::thread::sleep(REDRAW + Duration::from_millis(5));
                for _ in 0..SAMPLE_CALLS {
                    watch.control(k as f64);
                }
            }
        });
        runs.push(calls);
    }
    let (c1, c2) = (runs[0], runs[1]);
    println!("{c1} allocation calls in 2 redraw periods, {c2} in 6");
    // abs tol 2 calls (none expected: a hidden bar draws nothing)
    assert!(
        c2 <= c1 + 2,
        "{c1} allocation calls in 2 redraw periods, {c2} in 6"
    );
}

/// A hundred beads with gaps between them in a box of soft walls, at random velocities: many
/// clusters at once once they collide.
const GAS: &str = r#"
[scene]
name = "gas"
seed = 5
[chain]
beads = 100
precompression = -0.2
[initial]
velocity = { random = { mean = 0.0, eps = 1.0 } }
[walls]
left = { exponent = 2.5, prefactor = 1.0, precompression = -0.2 }
right = { exponent = 2.5, prefactor = 1.0, precompression = -0.2 }
[run]
until = 100.0
"#;

/// Regression (defect 6 of the allocation audit): a checkpoint cloned the engine state a second
/// time (after [`engine::Engine::save`], into the checkpoint record), and the scene and the
/// run configuration, and built the scene's named record again. The allocation calls of
/// writing a checkpoint now do not grow with the engine state: checkpoints of the gas at
/// `t = 0` (no cluster) and at `t = 3` (many), whose clones differ by many allocations, cost
/// the same but for the payload's growth. Measured with this test before the fix (allocation
/// calls of a checkpoint, of the state's clone): 80 (8) at t = 0, 157 (81) at t = 3. After: 31
/// and 35.
#[test]
fn checkpoint_does_not_clone_the_engine_state() {
    let dir = tempfile::tempdir().expect("tempdir");
    let s = scene(GAS);
    let cfg = config(Engine::Hybrid, Method::Auto, 1e-8, 1e-12, 100.0);
    let header = Header::new(
        s.clone(),
        cfg.engine,
        cfg.method,
        cfg.rtol,
        cfg.atol,
        "t".into(),
    );
    let writer = SnapshotWriter::create(&dir.path().join("gas.snap"), &header).expect("writer");
    let stop = Arc::new(AtomicBool::new(false));
    let policy = CheckpointPolicy::new(None, stop);
    let ckpt = dir.path().join("gas.snap.ckpt");
    let mut sink = SnapshotSink::new(writer, ckpt, policy, (&s, &cfg), false);
    let mut e = engine::start(&s, &cfg).expect("starts");
    let mut states = vec![e.save()];
    e.advance(3.0, &mut Drop::default()).expect("runs");
    states.push(e.save());
    // a first checkpoint: what the first write allocates once is not counted
    sink.checkpoint(&states[0]).expect("checkpoint written");
    let mut runs = Vec::new();
    for st in &states {
        let (_, clone) = calls_of(|| st.clone());
        let (r, calls) = calls_of(|| sink.checkpoint(st));
        r.expect("checkpoint written");
        runs.push((calls, clone));
        // the file holds these parts, in the bytes of their `CheckpointFile`
        let bytes = std::fs::read(&sink.ckpt_path).expect("reads");
        let ck = read_checkpoint(&sink.ckpt_path).expect("decodes");
        assert_eq!((&ck.engine, &ck.config, ck.timing), (st, &cfg, false));
        let again = dir.path().join("again.ckpt");
        write_checkpoint(&again, &ck).expect("writes");
        assert_eq!(std::fs::read(&again).expect("reads"), bytes);
    }
    let ((c1, k1), (c2, k2)) = (runs[0], runs[1]);
    println!(
        "checkpoint: {c1} allocation calls (state clone: {k1}) at t = 0, {c2} ({k2}) at t = 3"
    );
    assert!(k2 >= k1 + 50, "clones of {k1} and {k2} allocation calls");
    // abs tol 8 calls: the payload's doublings, far below the clone's difference
    assert!(
        c2 <= c1 + 8,
        "checkpoint: {c1} allocation calls (clone {k1}) at t = 0, {c2} ({k2}) at t = 3"
    );
}
