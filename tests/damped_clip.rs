//! The clip of a damped contact force at 0 inside a cluster's step
//! (`src/engine/hybrid/kinks.rs`, case 3), found by an adversarial review against an
//! independent SciPy integration (DOP853 at rtol 1e-12 … 3e-14, segments cut at every kink).

mod common;
use beadchain::integrate::Method;
use beadchain::scene::{self, Engine, Scene};
use common::*;
use std::path::Path;

fn scene(text: &str) -> Scene {
    scene::parse_str(text, Path::new("."), "clip").unwrap()
}

/// Largest difference of the final velocities of the default method (hybrid `auto`) at `rtol`
/// and of hybrid Radau IIA at rtol 1e-13 (whose implicit steps see the kink in their estimate).
fn deviation(s: &Scene, rtol: f64) -> f64 {
    deviation_from(s, rtol, 1e-16)
}

/// [`deviation`] with the reference at absolute tolerance `ref_atol`.
fn deviation_from(s: &Scene, rtol: f64, ref_atol: f64) -> f64 {
    let until = s.run.until;
    let a = run(
        s,
        &config(Engine::Hybrid, Method::Auto, rtol, rtol * 1e-3, until),
    )
    .0;
    let r = run(
        s,
        &config(Engine::Hybrid, Method::Radau5, 1e-13, ref_atol, until),
    )
    .0;
    a.v.iter()
        .zip(&r.v)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The defect: a linear-dashpot collision of two beads (masses 1 and 0.3, n = 2.5, c = 0.3)
/// clips its force at t = 1.3726, while the beads still overlap, and DOP853 accepted one step
/// across that kink: the final velocities were 9.4e-10 off at rtol 1e-12 (942·rtol; SciPy's
/// reference (0.6614020483925855, 1.1286598386913818) agrees with itself to 2e-15). Landed on
/// the clip: 0.45·rtol. Asserted within 10·rtol (abs; the velocities are about 1) at rtol 1e-8,
/// 1e-10 and 1e-12.
#[test]
fn a_step_across_a_damped_forces_clip_lands_on_it() {
    let s = scene(
        "[chain]\nbeads = 2\nmass = [1.0, 0.3]\nexponent = [2.5]\nprefactor = [1.0]\n\
         precompression = [-0.3]\nlaw = \"linear_dashpot\"\ndamping = [0.3]\n\
         [initial]\nvelocity = [1.0, 0.0]\n[run]\nuntil = 6.0\n",
    );
    for rtol in [1e-8, 1e-10, 1e-12] {
        let d = deviation(&s, rtol);
        assert!(d < 10.0 * rtol, "rtol {rtol:e}: {d:e}");
    }
}

/// The review's 8-bead viscoelastic box (both walls damped, gaps): 185·rtol at rtol 1e-12
/// and 168·rtol at 1e-10 before, 0.8 and 0.2·rtol now. Asserted within 20·rtol (abs; the
/// final speeds are below 1.3).
#[test]
fn a_viscoelastic_box_keeps_the_default_method_within_its_tolerance() {
    let s = scene(include_str!("common/viscoelastic_box.toml"));
    for rtol in [1e-10, 1e-12] {
        let d = deviation(&s, rtol);
        assert!(d < 20.0 * rtol, "rtol {rtol:e}: {d:e}");
    }
}

/// The clip of a damped soft wall's force (an adversarial review against SciPy, segments cut at
/// every kink): a bead leaving a viscoelastic wall (`law` of the chain, wall damping 0.4) was
/// 84·rtol off at rtol 1e-12, and two touching beads leaving a dashpot wall 216·rtol, because
/// only bead–bead clips were landed on; now 0.08 and 0.7·rtol against SciPy. Asserted within
/// 10·rtol (abs; the speeds are about 1) at rtol 1e-8, 1e-10 and 1e-12. The reference runs at
/// atol 1e-15: at 1e-16 Radau IIA fails at the dashpot wall's touch, where its force jumps
/// (known, docs/engines.md).
#[test]
fn a_step_across_a_damped_walls_clip_lands_on_it() {
    let one = "[chain]\nbeads = 2\nexponent = 2.5\nprecompression = -50.0\n\
               law = \"viscoelastic\"\ndamping = 0.0001\n\
               [initial]\nvelocity = [-1.233333, 0.0]\n\
               [walls]\nleft = { exponent = 2.5, prefactor = 1.0, precompression = -0.5, damping = 0.4 }\n\
               [run]\nuntil = 6.0\n";
    let two = "[chain]\nbeads = 2\nexponent = 2.5\nprecompression = 0.001\n\
               law = \"linear_dashpot\"\ndamping = 0.0\n\
               [initial]\nvelocity = [-0.933333, -0.933333]\n\
               [walls]\nleft = { exponent = 3.0, prefactor = 1.0, precompression = -0.5, damping = 1.0 }\n\
               [run]\nuntil = 6.0\n";
    for (name, text) in [("one bead", one), ("two beads", two)] {
        let s = scene(text);
        for rtol in [1e-8, 1e-10, 1e-12] {
            let d = deviation_from(&s, rtol, 1e-15);
            assert!(d < 10.0 * rtol, "{name}, rtol {rtol:e}: {d:e}");
        }
    }
}

/// A redone step that cannot reach its landing time (an adversarial review): 100 beads under
/// gravity between linear-dashpot walls, whose force jumps from 0 to `c·δ̇` at their touch. A
/// step landed on a later event was redone from its start, the right wall touched 2e-13 before
/// the landing time, and the redo's steps shrank to rounding in front of the jump: the default
/// method failed ("step size 1.4e-13 too small at t = 133.2", rtol 1e-10 and 1e-12; Radau IIA
/// ran). The redo now takes the accepted step's continuous output there
/// (`Hybrid::settle_at`). Asserted: both methods run at rtol 1e-10 and 1e-12, the energy books
/// balance to 100·rtol of the dissipated energy, and the final total energies of the two
/// methods at rtol 1e-12 agree to 1e-9 relative.
#[test]
fn a_redone_step_before_a_dashpot_walls_jump_does_not_fail() {
    let s = scene(include_str!("common/dashpot_column.toml"));
    let mut finals = Vec::new();
    for method in [Method::Auto, Method::Radau5] {
        for rtol in [1e-10, 1e-12] {
            let c = config(Engine::Hybrid, method, rtol, rtol * 1e-4, s.run.until);
            let mut rec = beadchain::engine::Recorder::default();
            let o = beadchain::engine::run(&s, &c, &mut rec)
                .unwrap_or_else(|e| panic!("{method:?} rtol {rtol:e}: {e}"));
            let balance = o.energy_final + o.dissipated - o.energy_initial;
            assert!(
                balance.abs() <= 100.0 * rtol * o.dissipated,
                "{method:?} rtol {rtol:e}: balance {balance:e} of {:e}",
                o.dissipated
            );
            if rtol == 1e-12 {
                finals.push(o.energy_final);
            }
        }
    }
    let (a, r) = (finals[0], finals[1]);
    assert!((a - r).abs() <= 1e-9 * r.abs(), "auto {a} radau5 {r}");
}
