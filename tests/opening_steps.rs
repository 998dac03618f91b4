//! Explicit cluster steps that run into a contact opening (issue "fast by default").
//!
//! Defect: a DOP853 cluster step that crossed an opening (`δ = 0`, where `n a δ₊^{n−1}` has a
//! kink) was rejected by its error estimate, and the error-based retry usually crossed it again:
//! on `periodic_decay_2.5_2.555` at rtol 1e-5, 2528 of 10 330 steps were rejected (24 %), on
//! `disorder_2.5_0.04` at rtol 1e-6, 170 294 of 488 150 (35 %), most of them such steps. Now a
//! rejected step that crossed an opening is retried to end just before it
//! (`engine::hybrid::opening::retry_fraction`): 1586 of 9932 (16 %) and 156 668 of 474 291
//! (33 %). The counts are deterministic (same inputs, same steps).

mod common;

use beadchain::engine::{self, Recorder, RunOutcome};
use beadchain::integrate::Method;
use beadchain::scene::{preset, Engine, Scene};

fn run(s: &Scene, engine: Engine, rtol: f64, atol: f64, until: f64) -> RunOutcome {
    let cfg = common::config(engine, Method::Auto, rtol, atol, until);
    engine::run(s, &cfg, &mut Recorder::default()).expect("runs to the end")
}

#[test]
fn explicit_steps_across_openings_are_not_rejected() {
    let s = preset("periodic_decay_2.5_2.555").expect("preset");
    let o = run(&s, Engine::Hybrid, 1e-5, 1e-7, s.run.until);
    let (acc, rej) = (o.stats.steps, o.stats.rejected);
    assert!(
        o.stats.newton_iters == 0,
        "the chain is non-stiff: auto stays explicit"
    );
    assert!(rej * 5 <= acc, "{rej} of {acc} steps rejected (> 20 %)");
    // the chain's energy is conserved to the tolerance's order (relative, measured 1.9e-6)
    let e = o.relative_energy_error();
    assert!(e < 2e-5, "relative energy error {e:e}");
}

/// The retried steps keep the accuracy: the hybrid run of a chain whose contacts open
/// all the time agrees with the dense engine (which has no events and no such step control) to
/// the tolerance, before the sensitivity of the chaotic scene takes over (t = 1000 of 4700).
#[test]
fn capped_steps_agree_with_the_dense_engine() {
    let s = preset("periodic_decay_2.5_2.555").expect("preset");
    let hybrid = run(&s, Engine::Hybrid, 1e-9, 1e-13, 1000.0);
    let dense = run(&s, Engine::Dense, 1e-11, 1e-15, 1000.0);
    let e = common::vel_error(&hybrid, &dense);
    // relative to the largest velocity (vel_error; measured 3.0e-8), rtol 1e-9: bound 100·rtol
    assert!(e < 1e-7, "hybrid vs dense velocity error {e:e}");
}
