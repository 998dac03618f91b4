//! The hybrid engine agrees with the dense one.

mod common;
use beadchain::integrate::Method;
use beadchain::scene::Engine;
use common::*;

fn max_dev(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn striker_chain_hybrid_matches_dense() {
    let scene = striker(40, 2.5, 0.4, 1.0, 60.0);
    let d = config(Engine::Dense, Method::Radau5, 1e-10, 1e-12, 60.0);
    let h = config(Engine::Hybrid, Method::Radau5, 1e-10, 1e-12, 60.0);
    let (od, _) = run(&scene, &d);
    let (oh, _) = run(&scene, &h);
    let du = max_dev(&od.u, &oh.u);
    let dv = max_dev(&od.v, &oh.v);
    eprintln!(
        "du {du:e} dv {dv:e}; energy err dense {:e} hybrid {:e}; steps d {} h {}; bead-steps d {} h {}; events {:?}; largest {}",
        od.relative_energy_error(),
        oh.relative_energy_error(),
        od.stats.steps,
        oh.stats.steps,
        od.stats.bead_steps,
        oh.stats.bead_steps,
        oh.events_by_kind,
        oh.largest_cluster
    );
    // abs 1e-6 on displacements/velocities of order 1 (rtol 1e-10 runs, long-time divergence)
    assert!(du < 1e-6 && dv < 1e-6, "du {du:e} dv {dv:e}");
    assert!(oh.relative_energy_error() < 1e-8);
}
