//! The steppable engine ([`beadchain::engine::Engine`]): advancing in pieces gives the bytes of
//! one run, the state between advances is the frame at that time, an observer's stop is a
//! [`Stop`] (not an error) after which the run can go on, and velocities can be changed
//! between advances.

mod common;

use beadchain::engine::{self, Control, EngineError, Observer, Recorder, RunConfig, Stop};
use beadchain::integrate::Method;
use beadchain::scene::{Engine as Kind, Scene};

const CASES: [(Kind, Method); 5] = [
    (Kind::Dense, Method::Radau5),
    (Kind::Dense, Method::Dop853),
    (Kind::Hybrid, Method::Radau5),
    (Kind::Hybrid, Method::Dop853),
    (Kind::Hybrid, Method::Auto),
];

fn setup(kind: Kind, method: Method) -> (Scene, RunConfig) {
    let mut sc = common::striker(30, 2.5, 1.0, 1.0, 30.0);
    sc.v0[29] = -0.5;
    let mut cfg = common::config(kind, method, 1e-8, 1e-12, 30.0);
    cfg.every = Some(1.5);
    (sc, cfg)
}

fn bits(r: &Recorder) -> Vec<u64> {
    r.t.iter()
        .chain(r.u.iter().flatten())
        .chain(r.v.iter().flatten())
        .map(|x| x.to_bits())
        .collect()
}

#[test]
fn advancing_in_pieces_gives_the_bytes_of_one_run() {
    for (kind, method) in CASES {
        let (sc, cfg) = setup(kind, method);
        let (whole, rec) = common::run(&sc, &cfg);
        let mut e = engine::start(&sc, &cfg).expect("starts");
        let mut pieces = Recorder::default();
        for t in [0.0, 4.0, 4.0, 10.3, 22.5, 30.0] {
            assert_eq!(
                e.advance(t, &mut pieces).expect("advances"),
                Stop::Reached { t }
            );
            assert_eq!(e.time(), t, "{kind:?}/{method:?}");
        }
        assert_eq!(bits(&pieces), bits(&rec), "{kind:?}/{method:?}: frames");
        let out = e.outcome();
        assert_eq!(out.u, whole.u, "{kind:?}/{method:?}");
        assert_eq!(out.v, whole.v, "{kind:?}/{method:?}");
        assert_eq!(out.stats.steps, whole.stats.steps);
    }
}

#[test]
fn the_state_between_advances_is_the_frame_at_that_time() {
    for (kind, method) in CASES {
        let (sc, cfg) = setup(kind, method);
        let mut e = engine::start(&sc, &cfg).expect("starts");
        let mut rec = Recorder::default();
        e.advance(12.0, &mut rec).expect("advances");
        let s = e.state();
        let k = rec.t.iter().position(|t| *t == 12.0).expect("frame at 12");
        assert_eq!(s.t, 12.0);
        assert_eq!(s.u, rec.u[k], "{kind:?}/{method:?}");
        assert_eq!(s.v, rec.v[k], "{kind:?}/{method:?}");
        assert_eq!(rec.t.last(), Some(&12.0), "no frame after the target");
    }
}

/// Asks to stop at its `at`-th poll, once.
struct StopOnce {
    polls: u64,
    at: u64,
    rec: Recorder,
}

impl Observer for StopOnce {
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        self.rec.frame(t, u, v)
    }
    fn control(&mut self, _t: f64) -> Control {
        self.polls += 1;
        Control::stop_if(self.polls == self.at)
    }
}

#[test]
fn an_observer_stop_is_a_stop_and_the_run_can_go_on() {
    for (kind, method) in CASES {
        let (sc, cfg) = setup(kind, method);
        let (whole, rec) = common::run(&sc, &cfg);
        let mut e = engine::start(&sc, &cfg).expect("starts");
        let mut obs = StopOnce {
            polls: 0,
            at: 40,
            rec: Recorder::default(),
        };
        match e.advance(cfg.until, &mut obs) {
            Ok(Stop::Requested { t }) => assert!(t < cfg.until, "{kind:?}/{method:?}"),
            other => panic!("{kind:?}/{method:?}: expected a requested stop, got {other:?}"),
        }
        assert_eq!(
            e.advance(cfg.until, &mut obs).expect("goes on"),
            Stop::Reached { t: cfg.until }
        );
        assert_eq!(bits(&obs.rec), bits(&rec), "{kind:?}/{method:?}");
        assert_eq!(e.outcome().v, whole.v);
    }
}

#[test]
fn velocities_set_between_advances_start_the_motion_there() {
    // A chain at rest, kicked at t = 5, moves like a chain struck at t = 0, 5 time units later
    // (the time shift changes rounding, so to the tolerance, not bit for bit).
    for (kind, method) in CASES {
        let rest = common::striker(20, 2.5, 1.0, 0.0, 25.0);
        let struck = common::striker(20, 2.5, 1.0, 1.0, 20.0);
        let c = |until| common::config(kind, method, 1e-10, 1e-14, until);
        let (c25, c20) = (c(25.0), c(20.0));
        let (want, _) = common::run(&struck, &c20);
        let mut e = engine::start(&rest, &c25).expect("starts");
        let mut rec = Recorder::default();
        e.advance(5.0, &mut rec).expect("advances");
        let mut v = e.state().v;
        assert!(v.iter().all(|x| *x == 0.0));
        v[0] = 1.0;
        e.set_velocities(&v).expect("sets");
        e.advance(25.0, &mut rec).expect("advances");
        let got = e.outcome();
        let dv = got
            .v
            .iter()
            .zip(&want.v)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        let du = got
            .u
            .iter()
            .zip(&want.u)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        let umax = want.u.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        // rel 1e-9 of the largest |v| (= 1) and |u| (rtol 1e-10)
        assert!(
            dv <= 1e-9 && du <= 1e-9 * umax,
            "{kind:?}/{method:?}: dv {dv:e}, du {du:e} (|u| <= {umax})"
        );
        assert!(e.set_velocities(&[1.0]).is_err(), "wrong length is refused");
    }
}

#[test]
fn advancing_past_the_end_time_is_refused() {
    let (sc, cfg) = setup(Kind::Hybrid, Method::Auto);
    let mut e = engine::start(&sc, &cfg).expect("starts");
    let err = e
        .advance(31.0, &mut Recorder::default())
        .expect_err("refused");
    assert!(
        err.to_string().contains("beyond the run's end time 30"),
        "{err}"
    );
}
