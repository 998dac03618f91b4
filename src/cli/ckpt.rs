//! `run`/`resume` into a [`SnapshotSink`] (the library's snapshot-writing observer with its
//! checkpoint policy: on schedule and on SIGINT/SIGTERM), finishing or detaching the output
//! and reporting what a failed run leaves on disk. A checkpoint records
//! the writer's mark (frames and event blocks already in the file) and the engine state (with
//! the events not yet handed over), so memory never holds the whole event log.

use anyhow::{Context, Result};
use beadchain::engine::{self, EngineError, RunConfig, RunOutcome};
use beadchain::scene::Scene;
use beadchain::snapshot::ckpt::{read_checkpoint, CheckpointFile};
use beadchain::snapshot::{CheckpointPolicy, RunSummary, SnapshotSink, SnapshotWriter};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;

/// Exit code of an interrupted run (128 + SIGINT).
pub const EXIT_INTERRUPTED: i32 = 130;

/// A sink for `run`/`resume`: the output `writer`, checkpoints to `ckpt_path` every `every`
/// and when SIGINT/SIGTERM arrives (the handler raises the policy's stop flag).
pub fn sink(
    writer: SnapshotWriter,
    ckpt_path: PathBuf,
    every: Option<f64>,
    scene: &Scene,
    cfg: &RunConfig,
    timing: bool,
) -> Result<SnapshotSink> {
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(sig, Arc::clone(&stop))
            .context("installing the SIGINT/SIGTERM handler")?;
    }
    let policy = CheckpointPolicy::new(every, stop);
    Ok(SnapshotSink::new(
        writer,
        ckpt_path,
        policy,
        (scene, cfg),
        timing,
    ))
}

/// Summary stored in the snapshot.
pub fn summary(out: &RunOutcome, timing: bool) -> RunSummary {
    let mut notes = Vec::new();
    notes.extend(out.slow_closings_note());
    notes.extend(out.shallow_closings_note());
    if !timing {
        notes.push(beadchain::snapshot::WALL_NOT_RECORDED.into());
    }
    RunSummary {
        stats: out.stats.clone(),
        wall_seconds: if timing { out.wall_seconds } else { 0.0 },
        t_end: out.t_end,
        energy_initial: out.energy_initial,
        energy_final: out.energy_final,
        momentum_initial: out.momentum_initial,
        momentum_final: out.momentum_final,
        events_by_kind: out.events_named(),
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
            finish(sink, what, &out)?;
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
        Err(e @ EngineError::Observer(_)) if sink.wrote_checkpoint || sink.resumed => {
            // Writing failed (disk full, I/O error): keep the unfinished output and the last
            // good checkpoint so the run can continue once the cause is fixed.
            let ckpt = sink.ckpt_path.clone();
            let _ = sink.writer.detach();
            Err(anyhow::Error::new(e).context(write_failed(what, &ckpt)))
        }
        Err(e) if sink.resumed => {
            // The checkpoint on disk still matches the kept temporary output (cut back to its
            // mark on the next resume); the failure itself is the computation's, so resuming
            // the same checkpoint the same way meets it again.
            let ckpt = sink.ckpt_path.clone();
            let _ = sink.writer.detach();
            let again = match e {
                EngineError::Checkpoint(_) | EngineError::Config(_) | EngineError::Internal(_) => {
                    "its state cannot be continued by this run"
                }
                _ => "resuming it again fails the same way unless an earlier --until ends the run first",
            };
            Err(anyhow::Error::new(e).context(format!(
                "{what}: resumed run failed; the checkpoint {} is kept as it was, but {again}",
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

/// The context of a failed write that a checkpoint on disk can continue.
fn write_failed(what: &str, ckpt: &Path) -> String {
    format!(
        "{what}: writing failed; the last checkpoint {} is intact: fix the cause (e.g. free disk space) and continue with `beadchain resume {}`",
        ckpt.display(),
        ckpt.display()
    )
}

/// Finishes the output of a completed run: the end of the snapshot (a resumed run's header
/// first records the end time that ran, [`SnapshotWriter::set_run_until`]), the rename onto
/// the final name, then the run's own checkpoint is removed. When this fails with a checkpoint
/// on disk (a full disk at the last write, a directory put at the output path), the temporary
/// output that checkpoint continues is kept and the error says how to resume.
fn finish(sink: SnapshotSink, what: &str, out: &RunOutcome) -> Result<()> {
    let mut sink = sink;
    let ckpt = sink.ckpt_path.clone();
    let mut done = summary(out, sink.timing);
    done.notes.append(&mut sink.notes);
    let own_checkpoint = sink.wrote_checkpoint || sink.resumed;
    if own_checkpoint {
        let until = sink.config().until;
        let mut writer = sink.writer;
        let r = match sink.resumed {
            true => writer.set_run_until(until),
            false => Ok(()),
        };
        let r = match r {
            Ok(()) => writer.finish_or_keep(&[], &done),
            Err(e) => writer.detach().and(Err(e)),
        };
        r.map_err(|e| anyhow::Error::new(e).context(write_failed(what, &ckpt)))?;
    } else {
        sink.writer.finish(&[], &done)?;
    }
    if ckpt.exists() && own_checkpoint {
        std::fs::remove_file(&ckpt)
            .with_context(|| format!("removing the finished run's {}", ckpt.display()))?;
    } else if ckpt.exists() {
        // another, interrupted run's checkpoint: not this run's to remove
        eprintln!(
            "beadchain: note: {} is the checkpoint of an earlier interrupted run into the same file, left as it was (`beadchain resume` of it would replace this output)",
            ckpt.display()
        );
    }
    Ok(())
}

/// Refuses a `--checkpoint-every` that is not a finite number > 0 (0 or NaN would checkpoint
/// at every step or never).
pub fn check_checkpoint_every(what: &str, every: Option<f64>) -> Result<()> {
    match every {
        Some(dt) if !(dt > 0.0 && dt.is_finite()) => anyhow::bail!(
            "{what}: --checkpoint-every: must be a finite number > 0 (simulated time between checkpoints), got {dt}"
        ),
        _ => Ok(()),
    }
}

/// `resume`'s output checks: the frame cap (`run`'s is [`super::select::check_frames_max`])
/// and [`super::files::SizeLimit::check`]. The interval and the output selection (frame
/// cap included) are the unfinished output's own, so a refusal advises only what `resume` can
/// change: an earlier `--until`, or the size limit. The end time is `--until` where given, else
/// the original run's, in seconds too for a physical scene (the checkpoint does not record
/// whether the scene gave it in seconds).
fn check_resume_output(
    what: &str,
    ck: &CheckpointFile,
    cfg: &RunConfig,
    until_given: bool,
    limit: super::files::SizeLimit,
) -> Result<()> {
    use super::common::GivenTime;
    use beadchain::snapshot::size::{self, count_text, short};
    let sel = beadchain::snapshot::read_header(&ck.writer.temp)?.output;
    let beta = ck.scene.units.map(|u| u.time);
    let end = match until_given {
        true => GivenTime::new("--until", &ck.scene),
        false => GivenTime {
            key: "the original run's end time",
            beta,
        },
    };
    let interval = GivenTime { key: "every", beta };
    if let (Err(e), Some(every)) = (
        size::check_frames_max(sel.frames_max, cfg.until, cfg.every),
        cfg.every,
    ) {
        anyhow::bail!(
            "{what}: {}: the run would write {} frames ({} = {}, every = {}), more than the cap of {} frames its output was started with (--frames-max or [output].frames_max); pass --until {} or less (the run is unchanged and can still be resumed)",
            end.key,
            count_text(e.count),
            end.key,
            end.shown(cfg.until),
            interval.shown(every),
            e.frames_max,
            short(size::until_that_fits(every, e.frames_max)),
        );
    }
    let n = ck.scene.chain.len();
    limit.check(
        (what, true),
        (n, sel.values_per_frame(n as u64).unwrap_or(u64::MAX)),
        (ck.engine.time(), cfg.until, cfg.every),
        ck.writer.offsets.len(),
        (&end, &interval),
    )
}

/// `beadchain resume FILE.ckpt [--until T] [--checkpoint-every DT]`. Every argument is checked
/// before the unfinished output is touched, so a rejected `--until` leaves the run resumable.
/// The run continues with the output selection (`run --beads/--fields/--frames-max`) stored
/// in the unfinished output's header; the checkpoint itself holds the full engine state.
pub fn cmd_resume(
    file: &Path,
    until: Option<f64>,
    every: Option<f64>,
    limit: super::files::SizeLimit,
    quiet: bool,
) -> Result<i32> {
    let mut ck = read_checkpoint(file)?;
    super::ckpt_target::locate(file, &mut ck.writer)?;
    let what = file.display().to_string();
    check_checkpoint_every(&what, every)?;
    let mut cfg = ck.config.clone();
    if let Some(t) = until {
        let t0 = ck.engine.time();
        if !(t.is_finite() && t > 0.0 && t >= t0) {
            anyhow::bail!(
                "{what}: --until: must be a finite number at or after the checkpoint time t = {t0}, got {t} (the run is unchanged and can still be resumed)"
            );
        }
        cfg.until = t;
    }
    super::ckpt_target::check_target(&what, &ck.writer)?;
    check_resume_output(&what, &ck, &cfg, until.is_some(), limit)?;
    let writer = SnapshotWriter::reopen(&ck.writer)?;
    let out_path = ck.writer.path.clone();
    let mut sink = sink(
        writer,
        file.to_path_buf(),
        every,
        &ck.scene,
        &cfg,
        ck.timing,
    )?;
    sink.resumed = true;
    let bar = beadchain::progress::RunProgress::new(quiet);
    let t0 = ck.engine.time();
    let done = drive(sink, &what, |s| {
        let r = engine::resume(
            &ck.scene,
            &cfg,
            &ck.engine,
            &mut bar.watch(s, t0, cfg.until, ""),
        );
        bar.finish();
        r
    })?;
    match done {
        Ok(out) => {
            super::common::print_outcome(&mut std::io::stdout().lock(), &ck.scene, &cfg, &out)?;
            outln!(
                "resumed from {}; wrote {}",
                file.display(),
                out_path.display()
            );
            Ok(0)
        }
        Err(code) => Ok(code),
    }
}
