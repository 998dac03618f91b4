//! Exact wall contacts (issue "The cost of an event"): a lone bead against a soft power-law
//! wall is the two-body contact with a body of infinite mass, resolved in closed form by the
//! hybrid engine whatever the tolerance; a neighbour arriving during the contact hands the bead
//! over to the integrator from the exact state.

mod common;

use beadchain::engine::events::EventKind;
use beadchain::engine::{self, Recorder, RunOutcome};
use beadchain::integrate::Method;
use beadchain::model::collision::collision;
use beadchain::model::Wall;
use beadchain::scene::{Engine, Scene};
use common::{config, run, Grab};

/// A soft wall of exponent `n`, prefactor 0.4 and precompression `pre`.
fn wall(n: f64, pre: f64) -> Option<Wall> {
    Some(Wall {
        exponent: n,
        prefactor: 0.4,
        precompression: pre,
        restitution: None,
    })
}

/// Two beads (masses `m`, 1), the bead at `side` (0 left, 1 right) moving at `w` into the soft
/// wall there (overlap `pre` at t = 0: touching or a gap), the other at rest 100 length units away (out of reach).
fn bead_into_wall(side: usize, n: f64, m: f64, w: f64, pre: f64, until: f64) -> Scene {
    let mut s = common::striker(2, 2.5, 1.0, 0.0, until);
    s.chain.precompression = Some(vec![-100.0]);
    let i = side;
    s.chain.mass[i] = m;
    s.v0[i] = if side == 0 { -w } else { w };
    if side == 0 {
        s.chain.left_wall = wall(n, pre);
    } else {
        s.chain.right_wall = wall(n, pre);
    }
    s
}

fn close(a: f64, b: f64, rel: f64, abs: f64) -> bool {
    (a - b).abs() <= abs + rel * b.abs()
}

/// The bead's velocity is reversed to 1e-14 relative, the peak overlap and the contact time are
/// exact to 1e-13, for wall exponents from 2.01 to 10, both walls, touching or closing a gap
/// from free flight, and every tolerance: one contact, no steps.
#[test]
fn bead_against_a_soft_wall_is_exact_whatever_the_rtol() {
    for n in [2.01, 2.5, 3.0, 4.7, 10.0] {
        for (side, m) in [(0, 1.0), (1, 3.7), (0, 0.3)] {
            let (w, until) = (0.8, 20.0);
            let (d_max, t_c) = collision(m, w, n, 0.4);
            for (rtol, pre) in [(1e-3, 0.0), (1e-6, -0.2), (1e-10, 0.0), (1e-10, -0.2)] {
                let sc = bead_into_wall(side, n, m, w, pre, until);
                let cfg = config(Engine::Hybrid, Method::Auto, rtol, rtol * 1e-4, until);
                let (out, rec) = run(&sc, &cfg);
                let what = format!("n = {n}, side {side}, m = {m}, rtol {rtol}, gap {pre}");
                assert_eq!(out.exact_pairs, [1, 0], "{what}");
                assert_eq!(out.stats.steps, 0, "{what}: no integration steps");
                let s = if side == 0 { -1.0 } else { 1.0 };
                assert!(
                    close(out.v[side], -s * w, 1e-14, 1e-16),
                    "{what}: {}",
                    out.v[side]
                );
                let open = rec.events.iter().find(|e| e.kind == EventKind::WallOpen);
                let peak = open.expect("the wall contact opens").peak_overlap;
                assert!(
                    close(peak, d_max, 1e-13, 0.0),
                    "{what}: peak {peak} vs {d_max}"
                );
                // After the contact the overlap falls as δ(T) = −w (T − t_e), and the contact
                // started at t_s = −Δ/w: t_c = T + δ(T)/w + Δ/w.
                let d_end = pre + s * out.u[side];
                let tc = until + d_end / w + pre / w;
                assert!(close(tc, t_c, 1e-13, 0.0), "{what}: t_c {tc} vs {t_c}");
            }
        }
    }
}

/// Frames inside the wall contact are the exact profile: they agree with a tight dense
/// Radau IIA run to 1e-12 (relative to the impact speed and the peak overlap).
#[test]
fn frames_inside_a_wall_contact_match_a_tight_radau_run() {
    for (n, side, m) in [(2.5, 1, 1.0), (3.5, 0, 2.0), (2.01, 1, 0.5)] {
        let w = 1.0;
        let (d_max, t_c) = collision(m, w, n, 0.4);
        let until = 1.5 * t_c;
        let mut sc = bead_into_wall(side, n, m, w, 0.0, until);
        sc.run.every = Some(t_c / 25.0);
        let mut cfg = config(Engine::Hybrid, Method::Auto, 1e-6, 1e-10, until);
        cfg.every = sc.run.every;
        let (out, exact) = run(&sc, &cfg);
        assert_eq!(out.exact_pairs, [1, 0], "n = {n}");
        let mut tight = config(Engine::Dense, Method::Radau5, 1e-13, 1e-16, until);
        tight.every = sc.run.every;
        let (_, reference) = run(&sc, &tight);
        assert_eq!(exact.t, reference.t);
        for (k, t) in exact.t.iter().enumerate() {
            let du = (exact.u[k][side] - reference.u[k][side]).abs();
            let dv = (exact.v[k][side] - reference.v[k][side]).abs();
            assert!(du <= 1e-12 * d_max, "n = {n}, t = {t}: du = {du:e}");
            assert!(dv <= 1e-12 * w, "n = {n}, t = {t}: dv = {dv:e}");
        }
    }
}

/// A neighbour that reaches the bead before its wall contact ends: the bead is handed over to
/// the integrator at the neighbour's closing, from the exact state, and the run agrees with the
/// dense engine (which integrates everything) to the tolerance.
#[test]
fn neighbour_arriving_during_a_wall_contact_is_handed_over() {
    for (n, gap, v0) in [(2.5, -0.3, 0.6), (3.0, -0.05, 0.5), (2.01, -0.5, 1.0)] {
        let until = 30.0;
        let mut sc = bead_into_wall(1, n, 1.3, 1.0, 0.0, until);
        sc.chain.precompression = Some(vec![gap]);
        sc.v0[0] = v0;
        let rtol = 1e-10;
        let cfg = config(Engine::Hybrid, Method::Auto, rtol, 1e-14, until);
        let (out, _) = run(&sc, &cfg);
        let what = format!("n = {n}, gap {gap}, v0 {v0}");
        assert!(out.exact_pairs[1] >= 1, "{what}: {:?}", out.exact_pairs);
        let dense = config(Engine::Dense, Method::Radau5, 1e-12, 1e-16, until);
        let (reference, _) = run(&sc, &dense);
        let err = common::vel_error(&out, &reference);
        assert!(err <= 100.0 * rtol, "{what}: final velocity error {err:e}");
        let de = (out.energy_final - out.energy_initial).abs() / out.energy_initial;
        assert!(de <= 100.0 * rtol, "{what}: energy error {de:e}");
    }
}

/// Where the closed form does not hold the wall contact is integrated: a field on the bead (the
/// wall does not fall with it), a damped scene, a lone bead between two walls.
#[test]
fn wall_contacts_outside_the_closed_form_are_integrated() {
    let until = 10.0;
    let mut field = bead_into_wall(1, 2.5, 1.0, 1.0, 0.0, until);
    field.chain.field = Some(vec![0.0, 0.2]);
    let mut box1 = bead_into_wall(1, 2.5, 1.0, 1.0, 0.0, until);
    box1.chain = common::striker(1, 2.5, 1.0, 0.0, until).chain;
    box1.chain.left_wall = wall(2.5, -3.0);
    box1.chain.right_wall = wall(2.5, 0.0);
    (box1.u0, box1.v0) = (vec![0.0], vec![1.0]);
    for (what, sc) in [("field", field), ("two walls", box1)] {
        let cfg = config(Engine::Hybrid, Method::Auto, 1e-8, 1e-12, until);
        let (out, _) = run(&sc, &cfg);
        assert_eq!(out.exact_pairs, [0, 0], "{what}");
        assert!(out.stats.steps > 0, "{what}");
    }
}

/// A checkpoint taken inside an exact wall contact continues bit for bit.
#[test]
fn checkpoint_inside_an_exact_wall_contact_resumes_bit_for_bit() {
    let until = 10.0;
    let mut sc = bead_into_wall(0, 3.0, 1.7, 1.0, 0.0, until);
    sc.run.every = Some(0.25);
    let mut cfg = config(Engine::Hybrid, Method::Auto, 1e-8, 1e-12, until);
    cfg.every = sc.run.every;
    let mut grab = Grab {
        at: 0.5,
        state: None,
    };
    engine::run(&sc, &cfg, &mut grab).unwrap();
    let state = grab.state.expect("a checkpoint inside the contact");
    let mut e = engine::restore(&sc, &cfg, &state).unwrap();
    let mut rest = Recorder::default();
    e.advance(until, &mut rest).unwrap();
    let whole: RunOutcome = engine::run(&sc, &cfg, &mut Recorder::default()).unwrap();
    assert_eq!(whole.exact_pairs, [1, 0]);
    let out = e.outcome();
    let bits = |x: &[f64]| x.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&out.u), bits(&whole.u));
    assert_eq!(bits(&out.v), bits(&whole.v));
}
