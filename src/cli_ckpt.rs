//! The snapshot observer of `run`/`resume`: streams frames and event blocks, writes checkpoints
//! on schedule and on SIGINT/SIGTERM, and finishes or detaches the output. A checkpoint records
//! the writer's mark (frames and event blocks already in the file) and the engine state (with
//! the events not yet handed over), so memory never holds the whole event log.

use anyhow::{Context, Result};
use beadchain::engine::{self, Control, EngineError, EngineState, Observer, RunConfig, RunOutcome};
use beadchain::scene::Scene;
use beadchain::snapshot::ckpt::{read_checkpoint, write_checkpoint, CheckpointFile};
use beadchain::snapshot::{EventRecord, RunSummary, SnapshotWriter};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Exit code of an interrupted run (128 + SIGINT).
pub const EXIT_INTERRUPTED: i32 = 130;

/// Streams frames into a snapshot writer and checkpoints the engine.
pub struct SnapshotSink {
    /// The output.
    pub writer: SnapshotWriter,
    ckpt_path: PathBuf,
    every: Option<f64>,
    next: f64,
    stop: Arc<AtomicBool>,
    scene: Scene,
    cfg: RunConfig,
    timing: bool,
    wrote_checkpoint: bool,
}

impl SnapshotSink {
    /// A sink writing checkpoints to `ckpt_path` every `every` (and on SIGINT/SIGTERM).
    pub fn new(
        writer: SnapshotWriter,
        ckpt_path: PathBuf,
        every: Option<f64>,
        scene: &Scene,
        cfg: &RunConfig,
        timing: bool,
    ) -> Result<Self> {
        let stop = Arc::new(AtomicBool::new(false));
        for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
            signal_hook::flag::register(sig, Arc::clone(&stop))
                .context("installing the SIGINT/SIGTERM handler")?;
        }
        Ok(Self {
            writer,
            ckpt_path,
            every,
            next: f64::NEG_INFINITY,
            stop,
            scene: scene.clone(),
            cfg: cfg.clone(),
            timing,
            wrote_checkpoint: false,
        })
    }
}

impl Observer for SnapshotSink {
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        self.writer
            .write_frame(t, u, v)
            .map_err(|e| EngineError::Observer(e.to_string()))
    }

    fn events(&mut self, events: &[EventRecord]) -> Result<(), EngineError> {
        self.writer
            .write_events(events)
            .map_err(|e| EngineError::Observer(e.to_string()))
    }

    fn control(&mut self, t: f64) -> Control {
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

    fn checkpoint(&mut self, state: &EngineState) -> Result<(), EngineError> {
        let err = |e: beadchain::snapshot::SnapshotError| EngineError::Observer(e.to_string());
        let mark = self.writer.mark().map_err(err)?;
        let ck = CheckpointFile {
            scene: self.scene.clone(),
            config: self.cfg.clone(),
            timing: self.timing,
            writer: mark,
            engine: state.clone(),
        };
        write_checkpoint(&self.ckpt_path, &ck).map_err(err)?;
        self.wrote_checkpoint = true;
        Ok(())
    }
}

/// Summary stored in the snapshot.
pub fn summary(out: &RunOutcome, timing: bool) -> RunSummary {
    let mut notes = Vec::new();
    if !timing {
        notes.push(
            "wall time not recorded (identical inputs give identical bytes; see --timing)".into(),
        );
    }
    RunSummary {
        stats: out.stats.clone(),
        wall_seconds: if timing { out.wall_seconds } else { 0.0 },
        t_end: out.t_end,
        energy_initial: out.energy_initial,
        energy_final: out.energy_final,
        momentum_initial: out.momentum_initial,
        momentum_final: out.momentum_final,
        events_by_kind: out.events_by_kind.clone(),
        largest_cluster: out.largest_cluster,
        notes,
    }
}

/// The checkpoint path of an output file: `FILE.ckpt`.
pub fn ckpt_path(out: &Path) -> PathBuf {
    let mut s = out.as_os_str().to_owned();
    s.push(".ckpt");
    PathBuf::from(s)
}

/// Runs (or resumes) into `sink`; finishes the snapshot, or on an interrupt keeps it for
/// `beadchain resume`. Returns the exit code, or the finished run's outcome.
pub fn drive(
    sink: SnapshotSink,
    what: &str,
    run: impl FnOnce(&mut SnapshotSink) -> Result<RunOutcome, EngineError>,
) -> Result<Result<RunOutcome, i32>> {
    let mut sink = sink;
    match run(&mut sink) {
        Ok(out) => {
            let timing = sink.timing;
            let ckpt = sink.ckpt_path.clone();
            sink.writer.finish(&[], &summary(&out, timing))?;
            if ckpt.exists() {
                std::fs::remove_file(&ckpt)
                    .with_context(|| format!("removing the finished run's {}", ckpt.display()))?;
            }
            Ok(Ok(out))
        }
        Err(EngineError::Interrupted(t)) => {
            let ckpt = sink.ckpt_path.clone();
            sink.writer.detach()?;
            eprintln!(
                "beadchain: interrupted at t = {t}: checkpoint written to {}; continue with `beadchain resume {}`",
                ckpt.display(),
                ckpt.display()
            );
            Ok(Err(EXIT_INTERRUPTED))
        }
        Err(e @ EngineError::Observer(_)) if sink.wrote_checkpoint => {
            // Writing failed (disk full, I/O error): keep the unfinished output and the last
            // good checkpoint so the run can continue once the cause is fixed.
            let ckpt = sink.ckpt_path.clone();
            let _ = sink.writer.detach();
            Err(anyhow::Error::new(e).context(format!(
                "{what}: writing failed; the last checkpoint {} is intact: fix the cause (e.g. free disk space) and continue with `beadchain resume {}`",
                ckpt.display(),
                ckpt.display()
            )))
        }
        Err(e) => {
            let ckpt = sink.ckpt_path.clone();
            if sink.wrote_checkpoint {
                let _ = std::fs::remove_file(&ckpt);
            }
            drop(sink); // removes the unfinished output
            Err(anyhow::Error::new(e).context(format!("{what}: run failed (no output written)")))
        }
    }
}

/// `beadchain resume FILE.ckpt [--until T] [--checkpoint-every DT]`.
pub fn cmd_resume(file: &Path, until: Option<f64>, every: Option<f64>) -> Result<i32> {
    let ck = read_checkpoint(file)?;
    let mut cfg = ck.config.clone();
    if let Some(t) = until {
        cfg.until = t;
    }
    let writer = SnapshotWriter::reopen(&ck.writer)?;
    let out_path = ck.writer.path.clone();
    let sink = SnapshotSink::new(
        writer,
        file.to_path_buf(),
        every,
        &ck.scene,
        &cfg,
        ck.timing,
    )?;
    let what = file.display().to_string();
    match drive(sink, &what, |s| {
        engine::resume(&ck.scene, &cfg, &ck.engine, s)
    })? {
        Ok(out) => {
            crate::cli::print_outcome(&ck.scene, &cfg, &out);
            println!(
                "resumed from {}; wrote {}",
                file.display(),
                out_path.display()
            );
            Ok(0)
        }
        Err(code) => Ok(code),
    }
}
