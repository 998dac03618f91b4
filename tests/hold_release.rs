//! A hold inside a cluster lets go where it stops holding, not at the end of the step that
//! crossed that point (`src/engine/hybrid/release.rs`).
//!
//! Before: a bead pinned against a hard wall was released at the end of the step in which the
//! net force on it turned away from the wall (a column pressed against a hard ceiling: released
//! at t = 4.104 / 4.017 / 3.974 / 3.953 at rtol 1e-6 / 1e-8 / 1e-10 / 1e-12, where the force
//! turns at 3.951278; the bead's velocity at t = 8 had the wrong sign at rtol 1e-8), and a
//! resting contact made by a plastic collision while already tensile held until its step's end
//! (the two beads moved as one for 0.018 time units after the logged opening; u₀(6) off by
//! 0.03 at rtol 1e-8 and 0.02 at 1e-12).
//!
//! The reference values (release at t = 3.951278; u₀(6) = −10.3543, v₀(6) = −3.33372) are from
//! an independent SciPy DOP853 integration at rtol 1e-12 with its own force law, its own
//! event location of the hard collisions and the pinning rule of docs/engines.md.

mod common;
use beadchain::engine::events::EventKind;
use beadchain::engine::{Recorder, RunConfig};
use beadchain::integrate::Method;
use beadchain::scene::{parse_str, Engine, Scene};
use common::config;
use std::path::Path;

/// A 3-bead column under gravity pressed against a hard right wall by a field, its middle bead
/// kicked: bead 2 is pinned, then pulled off the wall by its neighbour's rebound.
const CEILING: &str = r#"
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
until = 8.0
every = 0.25
"#;

/// A plastic hard contact 0 closed while the field pulls its beads apart: tensile at once.
const TENSILE: &str = r#"
[chain]
beads = 3
precompression = [0.0, -1.0]
[field]
force = [-0.5, 0.5, 0.0]
[hard]
contacts = [0]
restitution = 0.0
[initial]
velocity = [0.0, 0.0, -2.0]
[run]
until = 6.0
every = 0.05
"#;

fn scene(text: &str) -> Scene {
    parse_str(text, Path::new("."), "s.toml").expect("scene parses")
}

fn run(s: &Scene, method: Method, rtol: f64) -> Recorder {
    let mut c: RunConfig = config(Engine::Hybrid, method, rtol, rtol * 1e-4, s.run.until);
    c.every = s.run.every;
    let mut rec = Recorder::default();
    beadchain::engine::run(s, &c, &mut rec).expect("runs");
    rec
}

#[test]
fn pinned_bead_leaves_its_hard_wall_where_its_net_force_turns() {
    let s = scene(CEILING);
    for method in [Method::Auto, Method::Radau5] {
        for rtol in [1e-6, 1e-8, 1e-10] {
            let rec = run(&s, method, rtol);
            let t_open = rec
                .events
                .iter()
                .find(|e| e.kind == EventKind::WallOpen)
                .map(|e| e.t)
                .expect("bead 2 leaves the wall");
            // abs tol 2e-6 (the reference's 7 digits and the rtol), rel 0
            assert!(
                (t_open - 3.951278).abs() < 2e-6,
                "{method:?} rtol {rtol}: released at {t_open}, the force turns at 3.951278"
            );
            let (u, v) = (rec.u.last().unwrap()[2], rec.v.last().unwrap()[2]);
            // abs tol 1e-5 on u₂(8) = −3.359643, v₂(8) = −0.016092 (before: v₂ = +0.0148)
            assert!(
                (u + 3.359643).abs() < 1e-5 && (v + 0.016092).abs() < 1e-5,
                "{method:?} rtol {rtol}: u2(8) = {u}, v2(8) = {v}"
            );
        }
    }
}

#[test]
fn resting_contact_tensile_at_its_collision_lets_go_at_once() {
    let s = scene(TENSILE);
    for rtol in [1e-8, 1e-12] {
        let rec = run(&s, Method::Auto, rtol);
        let hit = rec
            .events
            .iter()
            .find(|e| e.kind == EventKind::HardCollision)
            .expect("the plastic collision")
            .t;
        // the first frame after the collision: the beads already separate (before: moving as
        // one, v₀ = v₁ exactly)
        let k = rec.t.iter().position(|&t| t > hit).expect("a frame after");
        let dv = rec.v[k][1] - rec.v[k][0];
        assert!(dv > 1e-3, "rtol {rtol}: v1 - v0 = {dv} at t = {}", rec.t[k]);
        let (u0, v0) = (rec.u.last().unwrap()[0], rec.v.last().unwrap()[0]);
        // abs tol 1e-4 (the reference's digits), rel 0
        assert!(
            (u0 + 10.3543).abs() < 1e-4 && (v0 + 3.33372).abs() < 1e-4,
            "rtol {rtol}: u0(6) = {u0}, v0(6) = {v0}"
        );
    }
}
