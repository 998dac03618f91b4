//! Clusters at rest (`integrate::rest`, `engine::hybrid`'s rest test): a cluster whose beads
//! are all at rest and whose forces balance to round-off is not integrated by the hybrid engine,
//! so an equilibrium stays at rest exactly (issue 35: "stays at rest to round-off"); a state
//! off the balance by far less than any tolerance is integrated; a bead landing on a resting
//! column wakes it, and the run agrees with the dense engine, which integrates everything.

mod common;

use beadchain::integrate::Method;
use beadchain::scene::{parse_str, Engine, Scene};
use common::*;
use std::path::Path;

fn scene(text: &str) -> Scene {
    parse_str(text, Path::new("."), "rest.toml").unwrap_or_else(|e| panic!("{e}"))
}

/// Equilibrium scenes: gravity columns on a soft and on a hard wall (its bottom bead pinned at
/// the start: before, a first collision at zero speed pinned it and left the other beads at
/// round-off speeds, integrated for the whole run), a long random column, a chain squeezed by a
/// wall force between two soft walls.
fn equilibria() -> Vec<(&'static str, Scene)> {
    let column = |beads: usize| {
        format!(
            "[scene]\nseed = 3\n[chain]\nbeads = {beads}\nmass = {{ random = {{ mean = 1.0, eps = 0.5 }} }}\n\
             [field]\ngravity = 1.0\n[walls]\nleft = {{}}\n[initial]\nequilibrium = true\n[run]\nuntil = 1.0\n"
        )
    };
    let squeezed = "[chain]\nbeads = 12\nexponent = 2.7\nprecompression = 0.01\n[walls]\n\
                    force = 0.37\nleft = { precompression = 0.02 }\nright = { exponent = 3.0 }\n\
                    [initial]\nequilibrium = true\n[run]\nuntil = 1.0\n";
    let hard = "[chain]\nbeads = 9\nexponent = { alternate = [2.5, 3.0] }\nprefactor = 1.3\n\
                [field]\ngravity = 0.7\n[walls]\nleft = { hard = true, restitution = 0.8 }\n\
                [initial]\nequilibrium = true\n[run]\nuntil = 1.0\n";
    vec![
        ("column 12", scene(&column(12))),
        ("column on a hard wall", scene(hard)),
        ("column 1000", scene(&column(1000))),
        ("squeezed 12", scene(squeezed)),
    ]
}

#[test]
fn equilibria_stay_exactly_at_rest_in_the_hybrid_engine() {
    for (name, s) in equilibria() {
        for method in [Method::Auto, Method::Dop853, Method::Radau5] {
            let mut cfg = config(Engine::Hybrid, method, 1e-10, 1e-12, 1.0e4);
            cfg.every = Some(37.0);
            let (out, rec) = run(&s, &cfg);
            assert_eq!(rec.t.len(), 272, "{name} {method:?}: frames");
            // exact: every frame is the initial state, bit for bit (abs tol 0)
            for (u, v) in rec.u.iter().zip(&rec.v) {
                assert!(
                    u == &s.u0 && v.iter().all(|v| *v == 0.0),
                    "{name} {method:?}"
                );
            }
            assert_eq!(out.stats.steps, 0, "{name} {method:?}: nothing integrated");
        }
    }
}

#[test]
fn a_state_off_the_balance_by_1e_12_is_integrated() {
    for (name, mut s) in equilibria() {
        let dmax = s.u0.iter().fold(0.0f64, |m, u| m.max(u.abs()));
        s.u0[5] += 1e-12 * dmax;
        let cfg = config(Engine::Hybrid, Method::Auto, 1e-10, 1e-14, 50.0);
        let (out, rec) = run(&s, &cfg);
        assert!(out.stats.steps > 0, "{name}: integrated");
        let v = rec
            .v
            .last()
            .unwrap()
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(v > 0.0, "{name}: the displaced bead moves ({v:e})");
    }
}

#[test]
fn a_bead_landing_on_a_resting_column_wakes_it() {
    let s = column_and_falling_bead(10, 0.5, 30.0);
    let mut cfg = config(Engine::Hybrid, Method::Auto, 1e-10, 1e-12, 30.0);
    cfg.every = Some(0.25);
    let (hybrid, rec) = run(&s, &cfg);
    // before the landing (free fall of 0.5 at g = 1 takes 1), the column is exactly at rest
    for (k, v) in rec.v.iter().take(4).enumerate() {
        assert!(v[..10].iter().all(|v| *v == 0.0), "frame {k}: {v:?}");
    }
    assert!(
        rec.v[8][..10].iter().any(|v| *v != 0.0),
        "the column moves after the landing"
    );
    assert!(hybrid.stats.steps > 0);
    cfg.engine = Engine::Dense;
    let (dense, _) = run(&s, &cfg);
    let e = vel_error(&hybrid, &dense);
    // both at rtol 1e-10 over 30 time units of bouncing (measured 2.3e-11): rel tol 1e-9
    assert!(e <= 1e-9, "hybrid against dense: {e:e} (rel tol 1e-9)");
}
