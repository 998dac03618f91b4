//! Overdamped contacts in the hybrid engine (issue 32 item 13): three beads struck at 1 with a
//! viscoelastic damping time `A = 1e25` stick (all beads at 1/3). The dense engine finished this
//! run; the hybrid one stopped with "step size too small" because
//! - the contact closed only at the overlap threshold `θ` (1e-8 deep, where the damping force is
//!   1e20), not at its onset (`hybrid_overdamped_contact_is_integrated_like_dense`), and
//! - Radau IIA's Newton iteration in a cluster's centre-of-mass frame read the rounding of a
//!   bead at rest in the lab (stored as `−V`) as divergence and halved its first step down to
//!   4e-323 (`radau_newton_accepts_rounding_level_increments_in_a_moving_frame`).

mod common;

use beadchain::engine::RunConfig;
use beadchain::integrate::Method;
use beadchain::model::{Damping, DampingLaw};
use beadchain::scene::{Engine, Scene};

/// Three beads (n = 2.5, a = 1), bead 0 striking at 1, viscoelastic damping time `g`.
fn sticky(g: f64) -> Scene {
    let mut sc = common::striker(3, 2.5, 1.0, 1.0, 10.0);
    sc.chain.damping = Some(Damping {
        law: DampingLaw::Viscoelastic,
        contact: vec![g; 2],
        left_wall: 0.0,
        right_wall: 0.0,
    });
    sc
}

fn cfg(engine: Engine, method: Method) -> RunConfig {
    common::config(engine, method, 1e-8, 1e-12, 10.0)
}

/// Velocity tolerance (abs; rel 0) at rtol 1e-8: 1e-9 for the implicit and automatic methods,
/// 3·rtol for DOP853, whose sticking transient leaves relative velocities of ~5e-9 (the dense
/// engine's DOP853 too: 4.9e-9).
fn vtol(method: Method) -> f64 {
    if method == Method::Dop853 {
        3e-8
    } else {
        1e-9
    }
}

/// Runs `sc` and checks that the beads end stuck together: every velocity 1/3 (abs
/// [`vtol`], rel 0), momentum 1 (abs 1e-12) and the energy books balanced (abs 100·rtol·E0).
fn check_stuck(sc: &Scene, engine: Engine, method: Method) -> Vec<f64> {
    let mut rec = beadchain::engine::Recorder::default();
    let out = beadchain::engine::run(sc, &cfg(engine, method), &mut rec)
        .unwrap_or_else(|e| panic!("{engine:?} {method:?}: {e}"));
    for (i, v) in out.v.iter().enumerate() {
        assert!(
            (v - 1.0 / 3.0).abs() <= vtol(method),
            "{engine:?} {method:?}: bead {i} at {v}"
        );
    }
    let p: f64 = out.v.iter().sum();
    assert!(
        (p - 1.0).abs() <= 1e-12,
        "{engine:?} {method:?}: momentum {p}"
    );
    let balance = out.energy_final + out.dissipated - out.energy_initial;
    assert!(
        balance.abs() <= 100.0 * 1e-8 * out.energy_initial,
        "{engine:?} {method:?}: balance {balance:e}"
    );
    out.v
}

#[test]
fn hybrid_overdamped_contact_is_integrated_like_dense() {
    let sc = sticky(1e25);
    let dense = check_stuck(&sc, Engine::Dense, Method::Auto);
    for method in [Method::Auto, Method::Radau5, Method::Dop853] {
        let hybrid = check_stuck(&sc, Engine::Hybrid, method);
        for (i, (h, d)) in hybrid.iter().zip(&dense).enumerate() {
            assert!(
                (h - d).abs() <= vtol(method),
                "{method:?} bead {i}: {h} vs {d}"
            );
        }
    }
}

#[test]
fn radau_newton_accepts_rounding_level_increments_in_a_moving_frame() {
    // The touching pair's first Radau IIA step at t = 0 (cluster frame V = 1/2, bead 1 stored
    // as −1/2): before, every Newton iteration was refused down to a step of 4e-323.
    check_stuck(&sticky(1e22), Engine::Hybrid, Method::Radau5);
}
