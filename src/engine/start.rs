//! Starting an engine: [`start`] builds the engine a run configuration names (dense or
//! hybrid) behind the [`Engine`] trait, [`restore`] one that continues from a checkpointed
//! state. Apart from the trait (`stepper.rs`), so the engines import the trait and this file
//! imports the engines, without a cycle.

use super::stepper::Engine;
use super::EngineState;
use super::{EngineError, RunConfig};
use crate::scene::{Engine as EngineKind, Scene};

/// Starts an engine on `scene` (the configuration is checked first).
pub fn start<'a>(
    scene: &'a Scene,
    cfg: &'a RunConfig,
) -> Result<Box<dyn Engine + 'a>, EngineError> {
    super::check_config(scene, cfg)?;
    Ok(match cfg.engine {
        EngineKind::Dense => Box::new(super::dense::DenseEngine::new(scene, cfg, None)?),
        EngineKind::Hybrid => Box::new(super::hybrid::HybridEngine::new(scene, cfg, None)?),
    })
}

/// An engine continuing from a checkpointed state (same scene; `cfg.until` may be later).
pub fn restore<'a>(
    scene: &'a Scene,
    cfg: &'a RunConfig,
    state: &EngineState,
) -> Result<Box<dyn Engine + 'a>, EngineError> {
    super::check_config(scene, cfg)?;
    if state.time() > cfg.until {
        return Err(EngineError::Config(format!(
            "the checkpoint is at t = {}, after until = {}",
            state.time(),
            cfg.until
        )));
    }
    Ok(match (cfg.engine, state) {
        (EngineKind::Dense, EngineState::Dense(d)) => Box::new(super::dense::DenseEngine::new(
            scene,
            cfg,
            Some(d.as_ref()),
        )?),
        (EngineKind::Hybrid, EngineState::Hybrid(h)) => {
            Box::new(super::hybrid::HybridEngine::new(scene, cfg, Some(h))?)
        }
        _ => {
            return Err(EngineError::Config(
                "the checkpoint was written by the other engine".into(),
            ))
        }
    })
}
