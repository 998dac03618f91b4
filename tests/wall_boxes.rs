//! Random boxes of soft walls (hybrid engine): the wall events of the log agree with the motion.
//!
//! Chains of 2–5 beads (random masses, exponents ≥ 2.05, prefactors, velocities) between two
//! soft walls with their own random laws, from 0.08 into the end bead to 1.5 length units away,
//! half of them in a uniform field of either sign, under `auto` and Radau IIA at rtol 1e-6 and
//! 1e-8. On each wall the log's `wall_close` and `wall_open` alternate, starting from the wall's
//! initial state, at non-decreasing times; and the log's last word on a wall matches the final
//! state wherever that is clear of the threshold: an end bead pressing into its wall by more
//! than 1e-3 has it closed, one more than 1e-3 away has it open. Seeded (a fixed xorshift
//! stream), so every run checks the same 64 boxes.

mod common;
use beadchain::engine::{self, Recorder, RunConfig};
use beadchain::integrate::Method;
use beadchain::model::Wall;
use beadchain::scene::{Engine, Scene};
use beadchain::snapshot::EventKind;
use common::*;

/// A soft wall `gap` ∈ [−0.08, 1.5) beyond an end bead at distance `end` from the centre (a
/// negative gap: the wall starts pressed into the bead).
fn random_wall(r: &mut Rng, end: f64) -> Wall {
    Wall {
        exponent: r.range(2.05, 4.0),
        prefactor: r.range(0.3, 3.0),
        precompression: -(end + r.range(-0.08, 1.5)),
        restitution: None,
    }
}

/// A box of 2–5 beads touching nothing (spaced 0.3 apart, centred), random velocities.
fn random_box(r: &mut Rng) -> Scene {
    let n = 2 + (r.unit() * 4.0) as usize;
    let mut s = striker(n, 2.5, 1.0, 0.0, 150.0);
    for i in 0..n {
        s.chain.mass[i] = r.range(0.2, 5.0);
        s.u0[i] = 0.3 * (i as f64 - (n as f64 - 1.0) / 2.0);
        s.v0[i] = r.range(-1.0, 1.0);
    }
    for c in 0..n - 1 {
        s.chain.exponent[c] = r.range(2.05, 4.0);
        s.chain.prefactor[c] = r.range(0.3, 3.0);
    }
    let end = 0.3 * (n as f64 - 1.0) / 2.0;
    s.chain.left_wall = Some(random_wall(r, end));
    s.chain.right_wall = Some(random_wall(r, end));
    if r.unit() < 0.5 {
        let g = r.range(-0.3, 0.3);
        s.chain.field = Some(s.chain.mass.iter().map(|m| m * g).collect());
    }
    s
}

#[test]
fn wall_events_of_random_boxes_alternate_and_match_the_final_state() {
    let mut r = Rng(0x9E37_79B9_7F4A_7C15);
    let mut checked = 0;
    for case in 0..64 {
        let s = random_box(&mut r);
        let (method, rtol) = [
            (Method::Auto, 1e-6),
            (Method::Auto, 1e-8),
            (Method::Radau5, 1e-6),
            (Method::Radau5, 1e-8),
        ][case % 4];
        let mut cfg: RunConfig = config(Engine::Hybrid, method, rtol, rtol * 1e-4, s.run.until);
        cfg.max_steps = Some(20_000_000);
        let mut rec = Recorder::default();
        let out = engine::run(&s, &cfg, &mut rec)
            .unwrap_or_else(|e| panic!("case {case} ({method:?}, {rtol:e}): {e}"));
        let n = s.chain.len();
        for (side, bead) in [(0usize, 0u64), (1, n as u64 - 1)] {
            let wall = if side == 0 {
                s.chain.left_wall.as_ref()
            } else {
                s.chain.right_wall.as_ref()
            };
            let pre = wall.expect("soft wall").precompression;
            let events: Vec<(f64, EventKind)> = rec
                .events
                .iter()
                .filter(|e| {
                    matches!(e.kind, EventKind::WallClose | EventKind::WallOpen)
                        && e.contact == bead
                })
                .map(|e| (e.t, e.kind))
                .collect();
            let what = format!("case {case} ({method:?}, {rtol:e}) wall {side}: {events:?}");
            let start_closed = pre + 0.3 * (n as f64 - 1.0) / 2.0 > 0.0;
            for (k, (_, kind)) in events.iter().enumerate() {
                let want = if (k % 2 == 0) != start_closed {
                    EventKind::WallClose
                } else {
                    EventKind::WallOpen
                };
                assert_eq!(*kind, want, "{what}");
            }
            assert!(events.windows(2).all(|w| w[0].0 <= w[1].0), "{what}");
            let overlap = if side == 0 {
                pre - out.u[0]
            } else {
                pre + out.u[n - 1]
            };
            let closed = (events.len() % 2 == 1) != start_closed;
            if overlap > 1e-3 {
                assert!(closed, "{what}: final overlap {overlap:e}");
            } else if overlap < -1e-3 {
                assert!(!closed, "{what}: final overlap {overlap:e}");
            }
            checked += events.len();
        }
    }
    assert!(checked > 200, "only {checked} wall events checked");
}
