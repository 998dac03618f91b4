//! The snapshot-writing observer of a run that can be resumed: frames, the dissipated energy
//! and event blocks go to a [`SnapshotWriter`]; a [`CheckpointPolicy`] decides when the engine
//! state is saved, and [`SnapshotSink::checkpoint`] writes it with the writer's mark
//! ([`super::ckpt`]). The policy is separate from the writing (argmin's habit: checkpointing is
//! a policy, not an observer's side job), so a run without checkpoints uses the writer alone.

use super::ckpt::{write_checkpoint_parts, CheckpointParts, SceneRecord};
use super::writer::observer_err;
use super::{EventRecord, SnapshotWriter};
use crate::engine::{Control, EngineError, EngineState, Observer, RunConfig};
use crate::scene::Scene;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// When to save the engine state: every `every` of simulated time (the first poll only sets
/// the schedule), and at once, then stop, when the `stop` flag is raised (a signal handler's).
#[derive(Clone, Debug)]
pub struct CheckpointPolicy {
    every: Option<f64>,
    next: f64,
    stop: Arc<AtomicBool>,
}

impl CheckpointPolicy {
    /// Checkpoints every `every` (none: only when `stop` is raised).
    pub fn new(every: Option<f64>, stop: Arc<AtomicBool>) -> Self {
        Self {
            every,
            next: f64::NEG_INFINITY,
            stop,
        }
    }

    /// The decision at engine clock `t`: stop (flag raised), checkpoint (a multiple of `every`
    /// passed since the last poll), or continue.
    pub fn control(&mut self, t: f64) -> Control {
        if self.stop.load(Ordering::Relaxed) {
            return Control::Stop;
        }
        match self.every {
            Some(dt) if t >= self.next => {
                let first = self.next == f64::NEG_INFINITY;
                self.next = ((t / dt).floor() + 1.0) * dt;
                if first {
                    Control::Continue
                } else {
                    Control::Checkpoint
                }
            }
            _ => Control::Continue,
        }
    }
}

/// Streams a run into a snapshot writer and writes its checkpoints to `ckpt_path` when the
/// policy asks (module docs).
pub struct SnapshotSink {
    /// The output.
    pub writer: SnapshotWriter,
    /// Where checkpoints go (`OUT.ckpt`).
    pub ckpt_path: PathBuf,
    policy: CheckpointPolicy,
    /// The scene's record, built once for every checkpoint of the run.
    scene: SceneRecord,
    cfg: RunConfig,
    /// Whether wall-clock time goes into the snapshot (`--timing`).
    pub timing: bool,
    /// A checkpoint was written by this sink.
    pub wrote_checkpoint: bool,
    /// A resumed run: its checkpoint and temporary output predate this process and are kept
    /// when the run fails (the previous state stays resumable).
    pub resumed: bool,
    /// Notes the driver adds to the snapshot's run summary (e.g. why the run ended early).
    pub notes: Vec<String>,
    /// `ckpt_path` holds another, interrupted run's checkpoint (a run without scheduled
    /// checkpoints into its output): a stop (SIGINT/SIGTERM) then fails the run instead of
    /// replacing that checkpoint, which would lose the other run.
    pub foreign_checkpoint: bool,
}

impl SnapshotSink {
    /// A sink writing checkpoints of the run of `scene` with `cfg` to `ckpt_path` as `policy`
    /// decides.
    pub fn new(
        writer: SnapshotWriter,
        ckpt_path: PathBuf,
        policy: CheckpointPolicy,
        (scene, cfg): (&Scene, &RunConfig),
        timing: bool,
    ) -> Self {
        Self {
            writer,
            ckpt_path,
            policy,
            scene: SceneRecord::new(scene),
            cfg: cfg.clone(),
            timing,
            wrote_checkpoint: false,
            resumed: false,
            notes: Vec::new(),
            foreign_checkpoint: false,
        }
    }
}

impl SnapshotSink {
    /// The run configuration its checkpoints record (a resumed run's: with its `--until`).
    pub fn config(&self) -> &RunConfig {
        &self.cfg
    }
}

impl Observer for SnapshotSink {
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        self.writer.frame(t, u, v)
    }

    fn dissipated(&mut self, t: f64, energy: f64) -> Result<(), EngineError> {
        self.writer.dissipated(t, energy)
    }

    fn events(&mut self, events: &[EventRecord]) -> Result<(), EngineError> {
        self.writer.events(events)
    }

    fn control(&mut self, t: f64) -> Control {
        self.policy.control(t)
    }

    fn checkpoint(&mut self, state: &EngineState) -> Result<(), EngineError> {
        if self.foreign_checkpoint {
            return Err(EngineError::Observer(format!(
                "{}: is the checkpoint of an earlier interrupted run into the same file, kept as it was: this run stopped without writing its own",
                self.ckpt_path.display()
            )));
        }
        let mark = self.writer.mark().map_err(observer_err)?;
        // the parts as they are: the engine state is the caller's (no second copy)
        let ck = CheckpointParts {
            scene: &self.scene,
            config: &self.cfg,
            timing: self.timing,
            writer: &mark,
            engine: state,
        };
        write_checkpoint_parts(&self.ckpt_path, &ck).map_err(observer_err)?;
        self.wrote_checkpoint = true;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The schedule: the first poll only sets it (no checkpoint at the start), then one
    /// checkpoint per multiple of `every` passed (several passed at once give one), and a
    /// raised stop flag stops at the next poll whatever the schedule.
    #[test]
    fn checkpoint_policy_schedule_and_stop_flag() {
        let stop = Arc::new(AtomicBool::new(false));
        let mut p = CheckpointPolicy::new(Some(2.0), Arc::clone(&stop));
        let got: Vec<Control> = [0.5, 1.9, 2.0, 2.1, 7.3, 7.9, 8.0]
            .iter()
            .map(|&t| p.control(t))
            .collect();
        use Control::{Checkpoint as C, Continue as G};
        assert_eq!(got, [G, G, C, G, C, G, C]);
        stop.store(true, Ordering::Relaxed);
        assert_eq!(p.control(8.1), Control::Stop);
        let mut never = CheckpointPolicy::new(None, Arc::new(AtomicBool::new(false)));
        assert!((0..10).all(|k| never.control(k as f64) == Control::Continue));
    }
}
