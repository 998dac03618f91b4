//! Stop reasons of the steppable engine (issue 12): paused at frames ([`Stop::Frame`]) and at
//! events ([`Stop::Event`]), an engine driven stop by stop to its end gives the same bytes
//! (frames, dissipated energies, event log, final state, counters) as one `advance` to the end;
//! each `Stop::Frame` leaves the clock at its frame and each `Stop::Event` carries the record
//! the event log holds in that place.

mod common;

use beadchain::engine::events::EventKind;
use beadchain::engine::events::EventRecord;
use beadchain::engine::{self, PauseAt, Recorder, RunConfig, RunOutcome, Stop};
use beadchain::integrate::Method;
use beadchain::scene::{parse_str, Engine as Kind, Scene};
use std::path::Path;

/// A struck chain with a hard contact and a soft right wall 0.2 away: closings, openings, a hard
/// collision, wall closings and openings.
const SOFT_WALL: &str = "
[chain]
beads = 10
[initial]
striker = 1.0
[hard]
contacts = [4]
restitution = 0.5
[walls]
right = { exponent = 2.5, prefactor = 1.0, precompression = -0.2 }
[run]
until = 40.0
every = 0.25
";

const MODES: [PauseAt; 3] = [
    PauseAt {
        frames: true,
        events: false,
    },
    PauseAt {
        frames: false,
        events: true,
    },
    PauseAt {
        frames: true,
        events: true,
    },
];

fn scene(text: &str) -> Scene {
    parse_str(text, Path::new("."), "s.toml").expect("scene parses")
}

fn bits(r: &Recorder) -> Vec<u64> {
    r.t.iter()
        .chain(r.u.iter().flatten())
        .chain(r.v.iter().flatten())
        .chain(&r.dissipated)
        .map(|x| x.to_bits())
        .collect()
}

/// The parts of an outcome that must be bit-identical (not the wall clock).
fn same_outcome(a: &RunOutcome, b: &RunOutcome, what: &str) {
    let f = |o: &RunOutcome| {
        let mut x: Vec<u64> =
            o.u.iter()
                .chain(&o.v)
                .chain(&[o.t_end, o.energy_final, o.dissipated])
                .map(|x| x.to_bits())
                .collect();
        x.extend([
            o.stats.steps,
            o.implicit_steps,
            o.largest_cluster,
            o.late_merges,
        ]);
        x
    };
    assert_eq!(f(a), f(b), "{what}: outcome");
    assert_eq!(a.events_by_kind, b.events_by_kind, "{what}: event counts");
    assert_eq!(a.stats, b.stats, "{what}: counters");
}

/// Drives an engine paused at `pause` through `targets` (each advanced to until it is
/// reached); checks each stop as it comes and returns the recorder, the events the stops
/// carried and the number of frame stops.
fn drive(
    sc: &Scene,
    cfg: &RunConfig,
    pause: PauseAt,
    targets: &[f64],
) -> (RunOutcome, Recorder, Vec<EventRecord>, usize) {
    let mut e = engine::start(sc, cfg).expect("starts");
    e.pause_at(pause);
    let mut rec = Recorder::default();
    let (mut events, mut frames) = (Vec::new(), 0);
    for &until in targets {
        loop {
            match e.advance(until, &mut rec).expect("advances") {
                Stop::Reached { t } => {
                    assert_eq!(t, until);
                    break;
                }
                Stop::Frame { t } => {
                    assert!(pause.frames, "a frame stop without pausing at frames");
                    assert_eq!(rec.t.last(), Some(&t), "the frame was handed over");
                    let s = e.state();
                    assert_eq!((s.t, &s.u, &s.v), (t, &rec.u[frames], &rec.v[frames]));
                    frames += 1;
                }
                Stop::Event { t, event } => {
                    assert!(pause.events, "an event stop without pausing at events");
                    assert_eq!(e.time(), t);
                    assert!(event.t <= t, "logged at or before the clock");
                    events.push(event);
                }
                Stop::Requested { t } => panic!("nobody asked to stop (t = {t})"),
            }
        }
    }
    (e.outcome(), rec, events, frames)
}

/// Runs every pause mode over `sc` (one advance, then the targets `[until/3, until]`) and
/// compares with one plain advance to the end.
fn check_scene(name: &str, sc: &Scene, cfg: &RunConfig) {
    let (whole, reference) = common::run(sc, cfg);
    assert!(!reference.t.is_empty());
    for pause in MODES {
        for targets in [vec![cfg.until], vec![cfg.until / 3.0, cfg.until]] {
            let what = format!("{name} {pause:?} {targets:?}");
            let (out, rec, events, frames) = drive(sc, cfg, pause, &targets);
            assert_eq!(bits(&rec), bits(&reference), "{what}: frames");
            assert_eq!(rec.events, reference.events, "{what}: event log");
            same_outcome(&out, &whole, &what);
            if pause.frames {
                assert_eq!(frames, reference.t.len(), "{what}: one stop per frame");
            }
            if pause.events {
                assert_eq!(
                    events, reference.events,
                    "{what}: one stop per logged event"
                );
            } else {
                assert!(events.is_empty());
            }
        }
    }
}

#[test]
fn pausing_at_frames_and_events_gives_the_bytes_of_one_run_hybrid() {
    let striker = beadchain::scene::preset("striker").expect("preset");
    let mut cfg = RunConfig::from_scene(&striker);
    cfg.engine = Kind::Hybrid;
    check_scene("striker", &striker, &cfg);
    let (_, r) = common::run(&striker, &cfg);
    assert!(r.events.len() > 100, "{} events", r.events.len());

    let damped = beadchain::scene::preset("damped_striker").expect("preset");
    let mut cfg = RunConfig::from_scene(&damped);
    cfg.engine = Kind::Hybrid;
    cfg.until = cfg.until.min(40.0);
    check_scene("damped_striker", &damped, &cfg);

    for (name, text) in [
        (
            "hard wall",
            common::SOFT_ON_HARD_WALL.replace("until = 30.0", "until = 20.0"),
        ),
        ("soft wall", SOFT_WALL.to_string()),
    ] {
        let sc = scene(&text);
        let mut cfg = common::config(Kind::Hybrid, Method::Radau5, 1e-10, 1e-12, sc.run.until);
        cfg.every = sc.run.every;
        check_scene(name, &sc, &cfg);
        let (out, _) = common::run(&sc, &cfg);
        let count = |k: &str| out.events(k.parse::<EventKind>().expect("a kind"));
        assert!(
            count("hard_collision") > 0,
            "{name}: {:?}",
            out.events_by_kind
        );
        if name == "soft wall" {
            assert!(
                count("wall_close") > 0 && count("wall_open") > 0,
                "{:?}",
                out.events_by_kind
            );
        }
    }
}

#[test]
fn pausing_at_frames_gives_the_bytes_of_one_run_dense() {
    for method in [Method::Radau5, Method::Dop853] {
        let mut sc = common::striker(30, 2.5, 1.0, 1.0, 30.0);
        sc.v0[29] = -0.5;
        let mut cfg = common::config(Kind::Dense, method, 1e-8, 1e-12, 30.0);
        cfg.every = Some(1.5);
        check_scene(&format!("dense {method:?}"), &sc, &cfg);
    }
    let damped = beadchain::scene::preset("damped_striker").expect("preset");
    let mut cfg = RunConfig::from_scene(&damped);
    cfg.engine = Kind::Dense;
    cfg.until = cfg.until.min(40.0);
    check_scene("dense damped_striker", &damped, &cfg);
}

/// Pausing at events switched on mid-run returns only the events logged from then on, and a
/// velocity change at a frame stop starts the motion at that frame.
#[test]
fn pauses_switched_on_later_and_kicks_at_a_frame() {
    let sc = scene(SOFT_WALL);
    let mut cfg = common::config(Kind::Hybrid, Method::Radau5, 1e-10, 1e-12, sc.run.until);
    cfg.every = sc.run.every;
    let (_, reference) = common::run(&sc, &cfg);
    let mut e = engine::start(&sc, &cfg).expect("starts");
    let mut rec = Recorder::default();
    e.advance(10.0, &mut rec).expect("advances");
    let logged = |o: RunOutcome| o.events_total() as usize;
    let before = logged(e.outcome());
    assert!(before > 0 && before < reference.events.len());
    e.pause_at(PauseAt {
        frames: false,
        events: true,
    });
    let mut carried = Vec::new();
    while let Stop::Event { event, .. } = e.advance(cfg.until, &mut rec).expect("advances") {
        carried.push(event);
    }
    // exactly the events logged after the switch, in log order
    assert_eq!(carried, reference.events[before..]);

    for kind in [Kind::Dense, Kind::Hybrid] {
        let sc = common::striker(20, 2.5, 1.0, 0.0, 20.0);
        let mut cfg = common::config(kind, Method::Radau5, 1e-10, 1e-14, 20.0);
        cfg.every = Some(0.7);
        let mut e = engine::start(&sc, &cfg).expect("starts");
        e.pause_at(PauseAt {
            frames: true,
            events: false,
        });
        let mut rec = Recorder::default();
        let mut k = 0;
        let t_kick = loop {
            match e.advance(cfg.until, &mut rec).expect("advances") {
                Stop::Frame { t } if k == 3 => break t,
                Stop::Frame { .. } => k += 1,
                other => panic!("{kind:?}: {other:?}"),
            }
        };
        assert_eq!(e.time(), t_kick);
        let mut v = e.state().v;
        v[0] = 1.0;
        e.set_velocities(&v).expect("sets");
        assert_eq!(e.state().t, t_kick, "{kind:?}: the kick is at the frame");
        e.pause_at(PauseAt::default());
        assert_eq!(
            e.advance(cfg.until, &mut rec).expect("advances"),
            Stop::Reached { t: cfg.until }
        );
        // the kick's momentum (1) is all there is: abs 1e-9; the pulse has left bead 0
        let out = e.outcome();
        assert!((out.momentum_final - 1.0).abs() <= 1e-9, "{kind:?}");
        assert!(out.u[10] > 0.0, "{kind:?}: the pulse passed bead 10");
    }
}
