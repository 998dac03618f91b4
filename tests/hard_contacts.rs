//! Hard contacts (instantaneous collisions with restitution) in the hybrid engine.

mod common;
use beadchain::engine::events::EventKind;
use beadchain::engine::RunOutcome;
use beadchain::integrate::Method;
use beadchain::model::{HardContacts, Wall};
use beadchain::scene::{Engine, Scene};
use common::*;

fn all_hard(s: &mut Scene, e: f64, tc: f64) {
    let nc = s.chain.len() - 1;
    s.chain.hard = Some(HardContacts {
        restitution: vec![Some(e); nc],
        collapse_interval: tc,
    });
}

fn hybrid(s: &Scene) -> RunOutcome {
    let mut cfg = config(Engine::Hybrid, Method::Radau5, 1e-10, 1e-12, s.run.until);
    cfg.max_steps = Some(1_000_000);
    run(s, &cfg).0
}

fn hard_wall(e: f64) -> Wall {
    Wall {
        exponent: 2.5,
        prefactor: 1.0,
        precompression: 0.0,
        restitution: Some(e),
    }
}

/// Newton's cradle, hard and elastic: five touching beads at rest, a sixth arriving. The
/// sequential rule passes the whole velocity to the last bead; nothing is integrated.
#[test]
fn newtons_cradle_hard_elastic() {
    let mut s = striker(6, 2.5, 1.0, 0.0, 10.0);
    s.u0[0] = -1.0;
    s.v0[0] = 1.0;
    all_hard(&mut s, 1.0, 1e-9);
    let o = hybrid(&s);
    // exact: abs 1e-15
    for i in 0..5 {
        assert!(o.v[i].abs() < 1e-15, "bead {i}: v = {}", o.v[i]);
    }
    assert!((o.v[5] - 1.0).abs() < 1e-15);
    assert_eq!(
        o.stats.steps, 0,
        "a chain of hard contacts integrates no ODE"
    );
    assert_eq!(o.events(EventKind::HardCollision), 5, "five collisions");
    assert!(o.relative_energy_error() < 1e-15);
}

/// A pure hard chain with random masses and velocities and restitution 1: momentum and energy
/// conserved to rounding, no ODE steps.
#[test]
fn pure_hard_gas_conserves_energy() {
    use rand::{Rng, SeedableRng};
    let n = 200;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let mut s = striker(n, 2.5, 1.0, 0.0, 20.0);
    for i in 0..n {
        s.chain.mass[i] = 0.5 + rng.random::<f64>();
        s.v0[i] = rng.random::<f64>() * 2.0 - 1.0;
        s.u0[i] = 0.3 * rng.random::<f64>() + i as f64 * 0.31;
    }
    all_hard(&mut s, 1.0, 1e-12);
    let o = hybrid(&s);
    assert_eq!(o.stats.steps, 0);
    assert!(
        o.events(EventKind::HardCollision) > 500,
        "{:?}",
        o.events_by_kind
    );
    // relative 1e-12 energy, abs 1e-12 momentum
    assert!(
        o.relative_energy_error() < 1e-12,
        "{:e}",
        o.relative_energy_error()
    );
    assert!((o.momentum_final - o.momentum_initial).abs() < 1e-12);
}

/// Inelastic collapse: beads with restitution 0.5 falling onto a hard floor under gravity
/// would collide infinitely often in finite time. Resting contacts keep the run finite: it
/// ends with a bounded number of events, no NaN, and energy only lost.
#[test]
fn inelastic_collapse_is_handled() {
    let n = 5;
    let mut s = striker(n, 2.5, 1.0, 0.0, 30.0);
    for i in 0..n {
        s.u0[i] = 1.0 + 0.5 * i as f64;
    }
    s.chain.field = Some(vec![-1.0; n]);
    s.chain.left_wall = Some(hard_wall(0.5));
    all_hard(&mut s, 0.5, 1e-4);
    let o = hybrid(&s);
    assert!(o.u.iter().chain(&o.v).all(|x| x.is_finite()));
    // between beads and on the floor (a hard wall's bounce is logged as `wall_close`)
    let events = o.events(EventKind::HardCollision) + o.events(EventKind::WallClose);
    // the stack comes to rest (resting contacts): measured 77 collisions at t_c = 1e-4 (was
    // 3.1e6 of TC chatter before resting contacts)
    assert!(events > 50 && events < 1_000, "{events} collisions");
    assert!(o.energy_final < o.energy_initial + 1e-6, "energy gained");
    // the stack has settled near the floor: every bead within 1e-2 of its resting height
    for (i, u) in o.u.iter().enumerate() {
        assert!(*u > -1e-6 && *u < 1e-2, "bead {i} at {u}");
    }
}

/// Hard walls with soft bead contacts (a scene mixing both): a solitary wave reflects off a
/// hard right wall; energy is conserved and the hybrid run takes ODE steps only for the soft
/// part.
#[test]
fn soft_chain_between_hard_walls() {
    let mut s = striker(30, 2.5, 1.0, 1.0, 80.0);
    s.chain.right_wall = Some(hard_wall(1.0));
    s.chain.left_wall = Some(hard_wall(1.0));
    let o = hybrid(&s);
    assert!(
        o.relative_energy_error() < 1e-8,
        "{:e}",
        o.relative_energy_error()
    );
    // a hard wall's bounce is a wall event (`wall_close`), not a collision between beads
    assert!(
        o.events(EventKind::WallClose) >= 1,
        "the wave reached the wall"
    );
    assert!(o.stats.steps > 0);
    // momentum reversed by the wall: total momentum now negative
    assert!(o.momentum_final < 0.0);
    assert_eq!(o.late_merges, 0);
}

/// The dense engine refuses hard contacts with a clear error.
#[test]
fn dense_engine_rejects_hard_contacts() {
    let mut s = striker(4, 2.5, 1.0, 1.0, 5.0);
    all_hard(&mut s, 1.0, 1e-9);
    let cfg = config(Engine::Dense, Method::Radau5, 1e-8, 1e-10, 5.0);
    let mut rec = beadchain::engine::Recorder::default();
    let err = beadchain::engine::run(&s, &cfg, &mut rec).unwrap_err();
    assert!(err.to_string().contains("hybrid"), "{err}");
}

/// The `[hard]` scene keys and the preset: parse, then the hybrid engine gives the textbook
/// cradle result.
#[test]
fn hard_preset_and_scene_keys() {
    let s = beadchain::scene::preset("newtons_cradle_hard").expect("preset");
    let h = s.chain.hard.as_ref().expect("hard contacts declared");
    assert!(h.restitution.iter().all(|e| *e == Some(1.0)));
    let o = hybrid(&s);
    assert!((o.v[5] - 1.0).abs() < 1e-15 && o.v[0].abs() < 1e-15);
    let text = r#"
[chain]
beads = 4
[hard]
contacts = [1]
restitution = 0.5
[walls]
left = { hard = true, restitution = 0.9 }
[run]
until = 1.0
"#;
    let s = beadchain::scene::parse_str(text, std::path::Path::new("."), "h.toml").expect("parses");
    let h = s.chain.hard.as_ref().expect("hard");
    assert_eq!(h.restitution, vec![None, Some(0.5), None]);
    assert_eq!(
        s.chain.left_wall.as_ref().and_then(|w| w.restitution),
        Some(0.9)
    );
    for (bad, key) in [
        ("[hard]\ncontacts = [7]", "[hard].contacts[0]"),
        (
            "[hard]\ncontacts = \"all\"\nrestitution = 1.5",
            "[hard].restitution",
        ),
        (
            "[walls]\nleft = { restitution = 0.5 }",
            "[walls].left.restitution",
        ),
    ] {
        let text = format!("[chain]\nbeads = 4\n[run]\nuntil = 1.0\n{bad}\n");
        let err = beadchain::scene::parse_str(&text, std::path::Path::new("."), "h.toml")
            .expect_err("rejected")
            .to_string();
        assert!(err.contains("h.toml") && err.contains(key), "{err}");
    }
}
