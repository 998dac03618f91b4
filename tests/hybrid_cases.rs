//! Hard cases for the hybrid engine (issue: event-driven hybrid engine, "Done means"). Each case
//! checks agreement with the dense engine where affordable, plus its own stability assertions:
//! no NaN, energy drift bound, event count bound, a step budget (`max_steps` makes the run fail
//! instead of hanging) and no late merges.

mod common;
use beadchain::engine::events::EventKind;
use beadchain::engine::RunOutcome;
use beadchain::integrate::Method;
use beadchain::model::Wall;
use beadchain::scene::{Engine, Scene};
use common::*;

const BUDGET: u64 = 5_000_000;

fn hybrid(scene: &Scene, rtol: f64) -> RunOutcome {
    let mut cfg = config(
        Engine::Hybrid,
        Method::Radau5,
        rtol,
        rtol * 1e-2,
        scene.run.until,
    );
    cfg.max_steps = Some(BUDGET);
    run(scene, &cfg).0
}

fn dense(scene: &Scene, rtol: f64) -> RunOutcome {
    run(
        scene,
        &config(
            Engine::Dense,
            Method::Radau5,
            rtol,
            rtol * 1e-2,
            scene.run.until,
        ),
    )
    .0
}

/// (max |Δu| / max |u − u0|, max |Δv| / max |v|) of `a` against the reference `b`.
fn deviation(scene: &Scene, a: &RunOutcome, b: &RunOutcome) -> (f64, f64) {
    let d = beadchain::engine::Deviation::between(scene, a, b);
    (d.rel_u, d.rel_v)
}

fn stable(o: &RunOutcome, energy_bound: f64, max_events: u64) {
    assert!(
        o.u.iter().chain(&o.v).all(|x| x.is_finite()),
        "NaN/inf in final state"
    );
    let err = o.relative_energy_error();
    assert!(
        err < energy_bound,
        "energy drift {err:e} ≥ {energy_bound:e}"
    );
    let events: u64 = o.events_total();
    assert!(events <= max_events, "{events} events > {max_events}");
    assert_eq!(o.late_merges, 0, "closings detected late");
}

fn agree(scene: &Scene, rtol: f64, tol: f64) -> (RunOutcome, RunOutcome) {
    let h = hybrid(scene, rtol);
    let d = dense(scene, rtol);
    let (du, dv) = deviation(scene, &h, &d);
    assert!(
        du < tol && dv < tol,
        "hybrid vs dense: du {du:e} dv {dv:e} (tol {tol:e})"
    );
    (h, d)
}

#[test]
fn light_bead_inside_chain() {
    let mut s = striker(30, 2.5, 1.0, 1.0, 60.0);
    s.chain.mass[15] = 1e-3;
    let (h, _) = agree(&s, 1e-9, 1e-6);
    stable(&h, 1e-7, 10_000);
}

#[test]
fn exponent_near_two() {
    let s = striker(30, 2.01, 1.0, 1.0, 80.0);
    let (h, _) = agree(&s, 1e-9, 1e-6);
    stable(&h, 1e-7, 10_000);
}

#[test]
fn large_exponent() {
    let s = striker(30, 10.0, 1.0, 1.0, 60.0);
    let (h, _) = agree(&s, 1e-9, 1e-6);
    stable(&h, 1e-7, 10_000);
}

/// Striker speeds from 1e-9 to 1e3: the hybrid runs obey the similarity law (v → λv scales
/// lengths by λ^{2/n} and time by λ^{(2−n)/n}).
#[test]
fn striker_speeds_over_twelve_decades() {
    let n = 2.5;
    let t1 = 40.0;
    let base = hybrid(&striker(25, n, 1.0, 1.0, t1), 1e-9);
    for lambda in [1e-9, 1e-4, 1e3] {
        let tl = t1 * f64::powf(lambda, (2.0 - n) / n);
        let o = hybrid(&striker(25, n, 1.0, lambda, tl), 1e-9);
        stable(&o, 1e-7, 10_000);
        let lu = f64::powf(lambda, 2.0 / n);
        let umax = base.u.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for i in 0..25 {
            // rel 1e-7 of the largest displacement / velocity
            assert!(
                (o.u[i] / lu - base.u[i]).abs() < 1e-7 * umax,
                "λ={lambda} bead {i} u"
            );
            assert!(
                (o.v[i] / lambda - base.v[i]).abs() < 1e-7,
                "λ={lambda} bead {i} v"
            );
        }
    }
}

/// Two strikers meeting head-on at the middle bead: simultaneous symmetric events; the result
/// stays mirror-symmetric.
#[test]
fn two_strikers_meet_mirror_symmetric() {
    let n = 41;
    let mut s = striker(n, 2.5, 1.0, 1.0, 70.0);
    s.v0[n - 1] = -1.0;
    let h = hybrid(&s, 1e-10);
    stable(&h, 1e-7, 10_000);
    let vmax = h.v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let asym = (0..n).fold(0.0_f64, |m, i| m.max((h.v[i] + h.v[n - 1 - i]).abs()));
    eprintln!("mirror asymmetry max |v_i + v_(N-1-i)| = {asym:e} (max |v| {vmax:e})");
    for i in 0..n {
        let j = n - 1 - i;
        // mirror: u_i = −u_j, v_i = −v_j to abs 1e-9·max|v| (rounding-level asymmetry only)
        assert!(
            (h.v[i] + h.v[j]).abs() <= 1e-9 * vmax,
            "bead {i}: {} vs {}",
            h.v[i],
            h.v[j]
        );
        assert!(
            (h.u[i] + h.u[j]).abs() <= 1e-9 * 60.0,
            "bead {i}: {} vs {}",
            h.u[i],
            h.u[j]
        );
    }
    let (du, dv) = deviation(&s, &h, &dense(&s, 1e-10));
    assert!(du < 1e-6 && dv < 1e-6, "du {du:e} dv {dv:e}");
}

/// Newton's cradle with soft contacts: five touching beads at rest, a sixth arriving across a
/// gap. Momentum and energy are conserved and the hybrid agrees with the dense engine.
#[test]
fn newtons_cradle_soft() {
    let mut s = striker(6, 4.0, 1.0, 0.0, 40.0);
    s.u0[0] = -2.0; // gap of 2 before the first contact
    s.v0[0] = 1.0;
    let (h, d) = agree(&s, 1e-10, 1e-6);
    stable(&h, 1e-8, 1_000);
    assert!((h.momentum_final - 1.0).abs() < 1e-12);
    // the last bead leaves with most of the momentum (soft contacts: not exactly all)
    assert!(d.v[5] > 0.5, "v_last = {}", d.v[5]);
}

/// A precompressed chain: everything one cluster, so hybrid = dense (one cluster, no events).
#[test]
fn precompressed_chain_is_one_cluster() {
    let mut s = striker(20, 2.5, 1.0, 0.0, 30.0);
    s.chain.precompression = Some(vec![0.05; 19]);
    // walls hold the precompression (same law and overlap: static equilibrium)
    let wall = Wall {
        exponent: 2.5,
        prefactor: 1.0,
        precompression: 0.05,
        restitution: None,
    };
    s.chain.left_wall = Some(wall.clone());
    s.chain.right_wall = Some(wall);
    s.v0[0] = 0.01; // small enough that no contact ever opens
    let (h, _) = agree(&s, 1e-9, 1e-7);
    stable(&h, 1e-7, 0);
    assert_eq!(h.largest_cluster, 20);
}

/// Gravity pressing a chain onto a wall: persistent contacts must not chatter (no event storm),
/// and the static overlaps are kept.
#[test]
fn gravity_presses_chain_onto_wall() {
    // The preset: six beads resting on a left wall under gravity (static overlaps), the top
    // bead pushed down.
    let s = beadchain::scene::preset("gravity_on_wall").expect("preset");
    let (h, _) = agree(&s, 1e-9, 1e-6);
    stable(&h, 1e-8, 200);
    assert!(h.stats.steps < 200_000, "{} steps", h.stats.steps);
    // A chain falling onto a wall from rest with gaps: it must come to rest-like bouncing
    // without an event storm.
    let n = 8;
    let mut s = striker(n, 2.5, 1.0, 0.0, 40.0);
    s.chain.field = Some(vec![-1.0; n]);
    s.chain.left_wall = Some(Wall {
        exponent: 2.5,
        prefactor: 1.0,
        precompression: 0.0,
        restitution: None,
    });
    for i in 0..n {
        s.u0[i] = 0.1 * (i as f64 + 1.0); // gaps of 0.1 above the wall and between beads
    }
    let (h, _) = agree(&s, 1e-9, 1e-5);
    assert!(h.u.iter().chain(&h.v).all(|x| x.is_finite()));
    // falling energy is large against the initial energy: bound the drift against the
    // gravitational energy released, m g Σ u0 = 3.6
    assert!((h.energy_final - h.energy_initial).abs() < 1e-7 * 3.6);
    let events: u64 = h.events_total();
    assert!(events < 2_000, "{events} events");
}

/// Time reversal: run to T, negate velocities, run back T: the initial state returns.
#[test]
fn time_reversal_recovers_initial_state() {
    let s = striker(20, 2.5, 1.0, 1.0, 12.0);
    let fwd = hybrid(&s, 1e-11);
    let mut back = s.clone();
    back.u0 = fwd.u.clone();
    back.v0 = fwd.v.iter().map(|v| -v).collect();
    let b = hybrid(&back, 1e-11);
    for i in 0..20 {
        // abs 1e-7 on displacement (order 10) and velocity (order 1)
        assert!((b.u[i] - s.u0[i]).abs() < 1e-7, "bead {i}: u {}", b.u[i]);
        assert!((-b.v[i] - s.v0[i]).abs() < 1e-7, "bead {i}: v {}", -b.v[i]);
    }
}

/// A 10⁵-bead chain with many fragmentation gaps: random velocities everywhere (seeded), so the
/// chain breaks into many clusters and free beads. Finishes within the step budget with no NaN,
/// energy conserved.
#[test]
fn hundred_thousand_beads_fragmenting() {
    use rand::{Rng, SeedableRng};
    let n = 100_000;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut s = striker(n, 2.5, 10.0, 0.0, 1.5);
    for i in 0..n {
        s.v0[i] = rng.random::<f64>() * 2.0 - 1.0;
        s.u0[i] = 0.5 * i as f64; // gaps of 0.5 between neighbours
    }
    let h = hybrid(&s, 1e-8);
    stable(&h, 1e-6, 2_000_000);
    let closes = h.events(EventKind::Close);
    let opens = h.events(EventKind::Open);
    assert!(
        closes > 10_000 && opens > 1_000,
        "only {closes} closings, {opens} openings"
    );
}
