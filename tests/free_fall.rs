//! A uniform field costs no accuracy (issue "Energy books…", item 4): a free chain in a field
//! is integrated relative to its free fall ([`beadchain::model::Chain::free_fall`]), so its
//! relative motion is the one without the field, and columns falling onto walls (no free fall
//! there) stay as accurate as the tolerance asks.

mod common;

use beadchain::engine::{self, Recorder};
use beadchain::integrate::Method;
use beadchain::scene::{parse_str, Engine, Scene};
use std::path::Path;

const METHODS: [Method; 3] = [Method::Dop853, Method::Radau5, Method::Auto];
const ENGINES: [Engine; 2] = [Engine::Hybrid, Engine::Dense];

fn scene(text: &str) -> Scene {
    parse_str(text, Path::new("."), "test").expect("valid scene")
}

/// 20 free Hertz beads, bead 0 striking at v = 1, in gravity `g` (W_i = −m_i g).
fn falling(g: f64) -> Scene {
    scene(&format!(
        "[chain]\nbeads = 20\n[field]\ngravity = {g}\n[initial]\nstriker = 1.0\n[run]\n\
         until = 40.0\nevery = 4.0\n"
    ))
}

fn frames(sc: &Scene, engine: Engine, method: Method) -> Recorder {
    let mut c = common::config(engine, method, 1e-8, 1e-12, sc.run.until);
    c.every = sc.run.every;
    common::run(sc, &c).1
}

/// Before: the error weights followed the common velocity `g t`, and the relative motion of a
/// chain falling at g = 100 was off by 2.5e-4 (dense DOP853), 1.5e-6 (dense Radau IIA) and
/// 1.6e-7 (hybrid) in velocity against the same chain without a field, whose own error is
/// 4e-9. Now the integrated numbers are those of the chain without a field: the lab frames
/// differ from it by the rounding of `½ g t²` and `g t` alone.
#[test]
fn uniform_field_leaves_the_relative_motion_unchanged() {
    let (still, fall) = (falling(0.0), falling(100.0));
    for engine in ENGINES {
        for method in METHODS {
            let (a, b) = (
                frames(&still, engine, method),
                frames(&fall, engine, method),
            );
            assert_eq!(a.t, b.t);
            for k in 0..a.t.len() {
                let t = a.t[k];
                for i in 0..20 {
                    let du = b.u[k][i] + 50.0 * t * t - a.u[k][i];
                    let dv = b.v[k][i] + 100.0 * t - a.v[k][i];
                    // abs 1e-10 / 1e-11: a few ulps of ½gt² = 8e4 and gt = 4e3 at t = 40
                    assert!(
                        du.abs() <= 1e-10 && dv.abs() <= 1e-11,
                        "{engine:?} {method:?} t = {t}, bead {i}: du {du:e}, dv {dv:e}"
                    );
                }
            }
        }
    }
}

/// A field that is not uniform keeps its differences: the free fall takes its mean
/// acceleration, the rest acts on the beads as before. At rtol 1e-10 against dense Radau IIA at
/// 1e-13 (velocities up to 40), the final velocities were off by 5.2e-9 (hybrid) and 4.0e-6
/// (dense, DOP853 stepping across the contacts' kinks) before, 2.1e-10 and 2.6e-7 now: bounds
/// abs 2e-9 and 1e-6.
#[test]
fn non_uniform_field_falls_with_its_mean() {
    let sc = scene(
        "[chain]\nbeads = 12\n[field]\nforce = { base = -1.0, segments = [{ from = 6, value = -1.5 }] }\n\
         [initial]\nstriker = 1.0\n[run]\nuntil = 30.0\n",
    );
    let (g, reduced) = sc.chain.free_fall();
    assert!((g + 1.25).abs() <= 1e-15, "mean acceleration {g}");
    let w = reduced.expect("falls").field.expect("a non-uniform rest");
    assert!((w[0] - 0.25).abs() <= 1e-15 && (w[11] + 0.25).abs() <= 1e-15);
    let (r, _) = common::run(
        &sc,
        &common::config(Engine::Dense, Method::Radau5, 1e-13, 1e-17, 30.0),
    );
    for (engine, bound) in [(Engine::Hybrid, 2e-9), (Engine::Dense, 1e-6)] {
        let (o, _) = common::run(
            &sc,
            &common::config(engine, Method::Auto, 1e-10, 1e-14, 30.0),
        );
        for i in 0..12 {
            let dv = (o.v[i] - r.v[i]).abs();
            assert!(dv <= bound, "{engine:?} bead {i}: dv {dv:e}");
        }
    }
}

/// Ten damped beads falling 20 length units onto a soft wall at g = 100 (no free fall: the
/// wall holds the chain's end): the final state at rtol 1e-8 against dense Radau IIA at 1e-13,
/// within 1e-9 of the largest speed (300) in velocity and 1e-8 in position (abs).
#[test]
fn column_falling_onto_a_wall_is_as_accurate_as_the_tolerance() {
    let sc = scene(
        "[chain]\nbeads = 10\nlaw = \"viscoelastic\"\ndamping = 0.05\n[field]\ngravity = 100.0\n\
         [walls]\nleft = { exponent = 2.5, precompression = -20.0 }\n[initial]\nvelocity = 0.0\n\
         [run]\nuntil = 3.0\n",
    );
    assert_eq!(sc.chain.free_fall().0, 0.0, "walls: lab frame");
    let (r, _) = common::run(
        &sc,
        &common::config(Engine::Dense, Method::Radau5, 1e-13, 1e-17, 3.0),
    );
    for engine in ENGINES {
        for method in METHODS {
            let (o, _) = common::run(&sc, &common::config(engine, method, 1e-8, 1e-12, 3.0));
            for i in 0..10 {
                let (du, dv) = ((o.u[i] - r.u[i]).abs(), (o.v[i] - r.v[i]).abs());
                assert!(
                    du <= 1e-8 && dv <= 3e-7,
                    "{engine:?} {method:?} bead {i}: du {du:e}, dv {dv:e}"
                );
            }
        }
    }
}

/// A falling chain resumed from a checkpoint ends where the uninterrupted run ends, bit for bit
/// (the free fall is derived from the chain, not saved).
#[test]
fn falling_chain_resumes_bit_for_bit() {
    let sc = falling(100.0);
    for engine in ENGINES {
        let cfg = common::config(engine, Method::Auto, 1e-8, 1e-12, 40.0);
        let mut g = common::Grab {
            at: 13.0,
            state: None,
        };
        let whole = engine::run(&sc, &cfg, &mut g).expect("runs");
        let st = g.state.expect("a state after t = 13");
        let mut e = engine::restore(&sc, &cfg, &st).expect("restores");
        e.advance(cfg.until, &mut Recorder::default())
            .expect("runs");
        let out = e.outcome();
        let bits = |x: &[f64]| x.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&out.u), bits(&whole.u), "{engine:?}");
        assert_eq!(bits(&out.v), bits(&whole.v), "{engine:?}");
    }
}
