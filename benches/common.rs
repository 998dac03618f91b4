//! Shared helpers of the whole-run benchmarks (plain harness: each prints a table).
#![allow(dead_code)]

use beadchain::engine::{self, EngineError, Observer, RunConfig, RunOutcome};
use beadchain::integrate::Method;
use beadchain::linalg::SolverKind;
use beadchain::scene::{Engine, Scene};

#[path = "../tests/common/mod.rs"]
mod shared;

/// Uniform striker chain: m = a = v0 = 1.
pub fn striker(n: usize, exp: f64, until: f64) -> Scene {
    shared::striker(n, exp, 1.0, 1.0, until)
}

struct Null;
impl Observer for Null {
    fn frame(&mut self, _t: f64, _u: &[f64], _v: &[f64]) -> Result<(), EngineError> {
        Ok(())
    }
}

/// One run (no frames kept).
pub fn run(scene: &Scene, engine: Engine, method: Method, rtol: f64, until: f64) -> RunOutcome {
    let cfg = RunConfig {
        engine,
        method,
        rtol,
        atol: rtol * 1e-2,
        until,
        every: None,
        solver: SolverKind::Auto,
        max_steps: None,
    };
    engine::run(scene, &cfg, &mut Null).expect("benchmark run succeeds")
}

/// Time for the solitary wave (n = 2.5, m = a = v0 = 1) to cross `n` beads: 1.21 beads per
/// time unit (measured; `t_end` of the scaling tables in docs/benchmarks.md), plus 5 %.
pub fn exit_time(n: usize) -> f64 {
    n as f64 / 1.21 * 1.05
}
