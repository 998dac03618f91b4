//! Regression tests named after the bugs they pin.

use beadchain::engine::{self, Recorder, RunConfig};
use beadchain::scene;

fn run_file(path: &str, rtol: f64, atol: f64) -> engine::RunOutcome {
    let s = scene::load(path).expect("scene loads");
    let mut cfg = RunConfig::from_scene(&s);
    cfg.rtol = rtol;
    cfg.atol = atol;
    cfg.max_steps = Some(1_000_000);
    engine::run(&s, &cfg, &mut Recorder::default()).expect("runs to the end")
}

/// Radau's Newton iteration took rounding-level increments for divergence and cut the step to
/// nothing ("step size too small") on a uniform n = 3.5 chain in the paper's units.
#[test]
fn hybrid_step_too_small_on_n3_5_physical_chain() {
    let o = run_file(
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/validation/repro/hybrid_step_too_small_n3.5.toml"
        ),
        1e-6,
        1e-8,
    );
    // relative energy error bound 1e-6 at rtol 1e-6
    assert!(
        o.relative_energy_error() < 1e-6,
        "{:e}",
        o.relative_energy_error()
    );
}

/// A step bounded by an event a few ulps ahead had coinciding stage times and failed; seen on
/// an n = 4 chain with an n = 4.5 impurity in the paper's units.
#[test]
fn sliver_step_before_event_on_n4_impurity_chain() {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = dir.path().join("imp.toml");
    std::fs::write(
        &p,
        "[units]\nsystem = \"physical\"\nradius = 4.0e-3\nyoung = 2.26e11\npoisson = 0.3\ndensity = 7650.0\nn0 = 2.5\n\
         [chain]\nbeads = 40\nexponent = { base = 4.0, impurity = { at = 20, s = 1, value = 4.5 } }\n\
         [initial]\nstriker_si = 0.11\n[run]\nuntil = 200.0\n",
    )
    .expect("write");
    let o = run_file(p.to_str().expect("utf8 path"), 1e-8, 1e-10);
    assert!(
        o.relative_energy_error() < 1e-7,
        "{:e}",
        o.relative_energy_error()
    );
}

/// The library's default engine was dense while the CLI's was hybrid.
#[test]
fn library_default_engine_is_hybrid() {
    let s = scene::preset("striker").expect("preset");
    assert_eq!(RunConfig::from_scene(&s).engine, scene::Engine::Hybrid);
}
