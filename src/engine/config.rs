//! A run's configuration: the scene's `[run]` settings, a caller's overrides, and the checks
//! every engine and front end applies before anything runs.

use super::EngineError;
use crate::integrate::{default_atol, DissipationWeight, Method, Tolerances, DEFAULT_RTOL};
use crate::linalg::SolverKind;
use crate::model::Scales;
use crate::scene::{Engine as EngineKind, Scene};
use serde::{Deserialize, Serialize};

/// What a caller may override of a scene's `[run]` settings (`None`: the scene's, else the
/// documented default). Times are in computer units (front ends convert SI times first).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunOverrides {
    /// `--engine`.
    pub engine: Option<EngineKind>,
    /// `--method`.
    pub method: Option<Method>,
    /// `--rtol`.
    pub rtol: Option<f64>,
    /// `--atol`.
    pub atol: Option<f64>,
    /// `--until`.
    pub until: Option<f64>,
    /// `--every`.
    pub every: Option<f64>,
    /// `--solver` (default: [`SolverKind::Auto`]).
    pub solver: Option<SolverKind>,
    /// `--max-steps` (default: no limit).
    pub max_steps: Option<u64>,
}

/// Everything an engine needs besides the scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RunConfig {
    /// Which engine.
    pub engine: EngineKind,
    /// Integration method (for the hybrid engine: of the clusters).
    pub method: Method,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance (relative to the run's characteristic scales).
    pub atol: f64,
    /// End time.
    pub until: f64,
    /// Output interval (`None`: first and last frame only).
    pub every: Option<f64>,
    /// Linear solver of the implicit method.
    pub solver: SolverKind,
    /// Abort after this many accepted steps (`None`: no limit).
    pub max_steps: Option<u64>,
}

impl RunConfig {
    /// The scene's own settings, with documented defaults for what it leaves out (`atol`
    /// defaults to [`default_atol`]`(rtol)`, i.e. `rtol/10⁴`, at least `1e-15`).
    pub fn from_scene(scene: &Scene) -> Self {
        Self::with_overrides(scene, &RunOverrides::default())
    }

    /// The scene's settings with a caller's overrides (the CLI's options, Python's keywords):
    /// each given value replaces the scene's; `atol` is the given one, else the scene's, else
    /// [`default_atol`] of the rtol that runs (so `--rtol` alone moves atol with it).
    pub fn with_overrides(scene: &Scene, o: &RunOverrides) -> Self {
        let rtol = o.rtol.or(scene.run.rtol).unwrap_or(DEFAULT_RTOL);
        Self {
            engine: o.engine.or(scene.run.engine).unwrap_or_default(),
            method: o.method.or(scene.run.method).unwrap_or_default(),
            rtol,
            atol: o
                .atol
                .or(scene.run.atol)
                .unwrap_or_else(|| default_atol(rtol)),
            until: o.until.unwrap_or(scene.run.until),
            every: o.every.or(scene.run.every),
            solver: o.solver.unwrap_or_default(),
            max_steps: o.max_steps,
        }
    }

    /// The integrators' tolerances for a run with characteristic `scales`, in the lab frame
    /// (no co-moving frame velocity or displacement origin).
    pub fn tolerances(&self, scales: Scales, dissipation: DissipationWeight) -> Tolerances {
        Tolerances {
            rtol: self.rtol,
            atol: self.atol,
            scales,
            v_frame: 0.0,
            u_origin: 0.0,
            dissipation,
        }
    }

    /// Output times: `0, every, 2·every, …` (computed as `k·every`, not by summation) and
    /// `until` itself; a `k·every` that [`reaches_until`] is `until` (the last frame).
    pub fn frame_time(&self, k: u64) -> f64 {
        match self.every {
            Some(dt) => {
                let t = k as f64 * dt;
                if reaches_until(t, self.until) {
                    self.until
                } else {
                    t
                }
            }
            None => {
                if k == 0 {
                    0.0
                } else {
                    self.until
                }
            }
        }
    }
}

/// Whether the output time `t = k·every` is the end time `until`: at or past it, or within
/// `16ε·until` below it. An interval and an end time given in seconds are both divided by the
/// time unit, so `k·every` can fall a few ulps short of an `until` that is a whole number of
/// intervals (`until_si = 5e-3`, `every_si = 2.5e-4`: `20·every` one ulp below `until`); the
/// frame there was written, and then the last frame one ulp later.
pub fn reaches_until(t: f64, until: f64) -> bool {
    t >= until || until - t <= 16.0 * f64::EPSILON * until.abs()
}

/// An engine or method that cannot run a scene's contacts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unrunnable {
    /// The dense engine on hard contacts or walls (only the hybrid engine handles them).
    DenseOnHard,
    /// Velocity Verlet on damped (velocity-dependent) contacts.
    VerletOnDamped,
}

/// Whether `cfg`'s engine or method cannot run `scene` (the first rule of [`check_config`]; the
/// CLI names the key that chose it).
pub fn unrunnable(scene: &Scene, cfg: &RunConfig) -> Option<Unrunnable> {
    if cfg.engine == EngineKind::Dense && scene.chain.has_hard() {
        Some(Unrunnable::DenseOnHard)
    } else if cfg.method == Method::Verlet && scene.chain.is_dissipative() {
        Some(Unrunnable::VerletOnDamped)
    } else {
        None
    }
}

/// Checks a run configuration's tolerances and times (the engines call it; the CLI calls it
/// before it creates any output file).
pub fn check_config(scene: &Scene, cfg: &RunConfig) -> Result<(), EngineError> {
    match unrunnable(scene, cfg) {
        Some(Unrunnable::DenseOnHard) => return Err(EngineError::Config(
            "the scene declares hard contacts or walls, which only the hybrid engine handles (use --engine hybrid)"
                .into(),
        )),
        Some(Unrunnable::VerletOnDamped) => return Err(EngineError::Config(
            "method verlet does not integrate velocity-dependent (damped) contacts; use auto, dop853 or radau5"
                .into(),
        )),
        None => {}
    }
    let bad = |what: &str, x: f64| EngineError::Config(format!("{what} = {x} must be in (0, 1)"));
    if !(cfg.rtol > 0.0 && cfg.rtol < 1.0) {
        return Err(bad("rtol", cfg.rtol));
    }
    if !(cfg.atol > 0.0 && cfg.atol < 1.0) {
        return Err(bad("atol", cfg.atol));
    }
    if !(cfg.until > 0.0 && cfg.until.is_finite()) {
        return Err(EngineError::Config(format!(
            "until = {} must be positive and finite",
            cfg.until
        )));
    }
    if let Some(dt) = cfg.every {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(EngineError::Config(format!(
                "every = {dt} must be positive and finite"
            )));
        }
    }
    Ok(())
}
