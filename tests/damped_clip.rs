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
    let until = s.run.until;
    let a = run(
        s,
        &config(Engine::Hybrid, Method::Auto, rtol, rtol * 1e-3, until),
    )
    .0;
    let r = run(
        s,
        &config(Engine::Hybrid, Method::Radau5, 1e-13, 1e-16, until),
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
