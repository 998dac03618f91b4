//! Shared helpers for integration tests: scenes built in code (independent of the TOML parser).
#![allow(dead_code)]

use beadchain::engine::{Recorder, RunConfig, RunOutcome};
use beadchain::integrate::Method;
use beadchain::linalg::SolverKind;
use beadchain::model::Chain;
use beadchain::scene::{Engine, RunSettings, Scene};

/// A uniform chain of `n` unit-mass beads with exponent `exp`, prefactor `a`, bead 0 striking
/// at `v0`.
pub fn striker(n: usize, exp: f64, a: f64, v0: f64, until: f64) -> Scene {
    let mut v = vec![0.0; n];
    v[0] = v0;
    Scene {
        name: format!("striker{n}"),
        description: String::new(),
        chain: Chain {
            mass: vec![1.0; n],
            exponent: vec![exp; n - 1],
            prefactor: vec![a; n - 1],
            precompression: None,
            field: None,
            left_wall: None,
            right_wall: None,
            hard: None,
        },
        u0: vec![0.0; n],
        v0: v,
        run: RunSettings {
            until,
            ..Default::default()
        },
        seed: 0,
    }
}

/// A run configuration for tests.
pub fn config(engine: Engine, method: Method, rtol: f64, atol: f64, until: f64) -> RunConfig {
    RunConfig {
        engine,
        method,
        rtol,
        atol,
        until,
        every: None,
        solver: SolverKind::Auto,
        max_steps: Some(5_000_000),
    }
}

/// Runs and returns the outcome and recorded frames.
pub fn run(scene: &Scene, cfg: &RunConfig) -> (RunOutcome, Recorder) {
    let mut rec = Recorder::default();
    let out = beadchain::engine::run(scene, cfg, &mut rec).expect("run succeeds");
    (out, rec)
}
