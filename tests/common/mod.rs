//! Shared helpers for integration tests: scenes built in code (independent of the TOML parser).
#![allow(dead_code)]

pub mod npy;

use beadchain::engine::{
    Control, EngineError, EngineState, Observer, Recorder, RunConfig, RunOutcome,
};
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
            damping: None,
        },
        u0: vec![0.0; n],
        v0: v,
        run: RunSettings {
            until,
            ..Default::default()
        },
        seed: 0,
        units: None,
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

/// Runs the `beadchain` binary with `args` in `dir` and returns its output.
pub fn bc(dir: &std::path::Path, args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_beadchain"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("start beadchain")
}

/// `max_i |v_i − v_ref,i| / max_i |v_ref,i|`: the final velocity error of `a` against `r`.
pub fn vel_error(a: &RunOutcome, r: &RunOutcome) -> f64 {
    let vmax = r.v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let dv =
        a.v.iter()
            .zip(&r.v)
            .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    dv / vmax
}

/// Asserts a `beadchain` run exited 0, showing its stderr and stdout otherwise.
pub fn assert_ok(o: &std::process::Output) {
    assert_eq!(
        o.status.code(),
        Some(0),
        "stderr: {}\nstdout: {}",
        String::from_utf8_lossy(&o.stderr),
        String::from_utf8_lossy(&o.stdout)
    );
}

/// Soft beads with two hard contacts (e = 0.5) falling onto a hard wall (e = 0.8): a soft
/// cluster's end bead collides with the wall and is pinned there.
pub const SOFT_ON_HARD_WALL: &str = "
[chain]
beads = 8
[field]
gravity = 1.0
[initial]
displacement = [1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5]
[hard]
contacts = [2, 5]
restitution = 0.5
[walls]
left = { hard = true, restitution = 0.8 }
[run]
until = 30.0
every = 0.5
";

/// Five beads with hard contacts (e = 0.5) falling onto a hard wall (e = 0.8) under gravity:
/// free groups, resting contacts and a pin; the stack comes to rest.
pub const FALLING_STACK: &str = "
[chain]
beads = 5
[field]
gravity = 1.0
[initial]
displacement = [1.0, 1.5, 2.0, 2.5, 3.0]
[hard]
contacts = \"all\"
restitution = 0.5
[walls]
left = { hard = true, restitution = 0.8 }
[run]
until = 30.0
every = 0.5
";

/// xorshift64* stream: a seeded test's only source of randomness.
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

/// An observer that keeps the first engine state offered after `at` (a checkpoint there).
pub struct Grab {
    pub at: f64,
    pub state: Option<EngineState>,
}

impl Observer for Grab {
    fn frame(&mut self, _t: f64, _u: &[f64], _v: &[f64]) -> Result<(), EngineError> {
        Ok(())
    }
    fn control(&mut self, t: f64) -> Control {
        if self.state.is_none() && t >= self.at {
            Control::Checkpoint
        } else {
            Control::Continue
        }
    }
    fn checkpoint(&mut self, s: &EngineState) -> Result<(), EngineError> {
        self.state = Some(s.clone());
        Ok(())
    }
}

/// A column of `n` beads (masses alternating 1 and 0.5) at rest on a left wall under gravity
/// `g = 1` (`[initial] equilibrium = true`), and one more bead of mass 1 held `gap` above it,
/// at rest: it falls onto the resting column (clusters at rest, `integrate::rest`).
pub fn column_and_falling_bead(n: usize, gap: f64, until: f64) -> Scene {
    let text = |beads: usize, eq: bool| {
        format!(
            "[chain]\nbeads = {beads}\nmass = {{ alternate = [1.0, 0.5] }}\n[field]\n\
             gravity = 1.0\n[walls]\nleft = {{}}\n[initial]\nequilibrium = {eq}\n[run]\n\
             until = {until:?}\n"
        )
    };
    let parse = |t: String| {
        beadchain::scene::parse_str(&t, std::path::Path::new("."), "column.toml")
            .unwrap_or_else(|e| panic!("{e}"))
    };
    let column = parse(text(n, true));
    let mut s = parse(text(n + 1, false));
    assert_eq!(s.chain.mass[n], 1.0, "the falling bead's mass");
    s.u0[..n].copy_from_slice(&column.u0);
    s.u0[n] = column.u0[n - 1] + gap;
    s
}
