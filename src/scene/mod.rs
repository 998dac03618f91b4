//! Scenes: a chain, its initial state and run settings, as read from a TOML file.
//!
//! (Parsing lives in submodules; this file holds the plain data types.)

use crate::integrate::Method;
use crate::model::Chain;
use serde::{Deserialize, Serialize};

/// Which engine runs a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Engine {
    /// Whole-chain integration, no events (the cross-check path).
    #[default]
    Dense,
    /// Event-driven: analytic free flight, implicit cluster integration.
    Hybrid,
}

impl Engine {
    /// The name used on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            Engine::Dense => "dense",
            Engine::Hybrid => "hybrid",
        }
    }
}

/// Run settings of a scene (`[run]` table). `None` means "use the documented default".
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, Default)]
pub struct RunSettings {
    /// End time (computer units), > 0.
    pub until: f64,
    /// Output interval; `None` writes only the first and last frame.
    pub every: Option<f64>,
    /// Relative tolerance.
    pub rtol: Option<f64>,
    /// Absolute tolerance (relative to the run's characteristic scales).
    pub atol: Option<f64>,
    /// Integration method.
    pub method: Option<Method>,
    /// Engine.
    pub engine: Option<Engine>,
}

/// A fully resolved scene: every per-bead and per-contact array expanded.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scene {
    /// Short name (file stem or preset name).
    pub name: String,
    /// Free-text description.
    pub description: String,
    /// The chain physics.
    pub chain: Chain,
    /// Initial displacements, length `N`.
    pub u0: Vec<f64>,
    /// Initial velocities, length `N`.
    pub v0: Vec<f64>,
    /// Run settings.
    pub run: RunSettings,
    /// Seed of every random generator the scene used (stored so runs can be reproduced).
    pub seed: u64,
}
