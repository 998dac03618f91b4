//! `beadchain run`: checks the output files, writes the snapshot through the checkpointing
//! sink of [`super::ckpt`], and prints the run summary.

use super::ckpt;
use super::common::{config, load_scene_with_material, named, overrides, print_outcome, Common};
use super::files::SizeLimit;
use super::select::OutputArgs;
use anyhow::{bail, Result};
use beadchain::engine::{self, RunConfig, RunOutcome, RunOverrides};
use beadchain::progress::RunProgress;
use beadchain::scene::{self, Engine, Scene};
use beadchain::snapshot::{Header, Selection, SnapshotSink, SnapshotWriter};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Arguments of `beadchain run`.
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    #[command(flatten)]
    pub common: Common,
    /// Engine [default: the scene's, else hybrid].
    #[arg(long, value_parser = named::<Engine>())]
    pub engine: Option<Engine>,
    /// Output interval, computer units; --every-si for seconds [default: the scene's `[run]
    /// every`, else first and last frame].
    #[arg(long)]
    pub every: Option<f64>,
    /// Output interval in seconds (physical scenes: divided by the scene's time unit β).
    #[arg(long, conflicts_with = "every")]
    pub every_si: Option<f64>,
    /// Output snapshot [default: `<scene name>.snap` in the current directory].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write a resumable checkpoint `FILE.ckpt` every DT of simulated time (a checkpoint is
    /// also written on SIGINT/SIGTERM; `beadchain resume FILE.ckpt` continues the run).
    #[arg(long)]
    pub checkpoint_every: Option<f64>,
    /// Also store the wall-clock time and the date (UTC) in the snapshot (then two runs no
    /// longer give identical bytes; by default the time is only printed).
    #[arg(long)]
    pub timing: bool,
    #[command(flatten)]
    pub limit: SizeLimit,
    #[command(flatten)]
    pub output: OutputArgs,
    /// End the run at the first output frame at which no pair can ever collide again (every
    /// contact open or touching at equal velocity, velocities non-decreasing along the chain)
    /// and print the fragments; refused for a scene with a field or walls.
    #[arg(long)]
    pub stop_when_fragmented: bool,
}

/// Runs `beadchain run`; returns the exit code.
pub fn cmd_run(a: RunArgs) -> Result<i32> {
    let scene::Parsed {
        mut scene,
        material,
        until_key,
        every_key,
        ..
    } = load_scene_with_material(&a.common.scene)?;
    let o = RunOverrides {
        engine: a.engine,
        every: match a.every_si {
            Some(dt) => Some(super::common::si_time(&scene, "--every-si", dt)?),
            None => a.every,
        },
        ..overrides(&scene, &a.common)?
    };
    let cfg = config(&scene, &o);
    super::common::warn_implausible(&scene, material.as_ref(), until_key, &cfg, &a.common);
    let given = (a.engine.is_some(), a.common.method.is_some());
    super::common::check_config(&a.common.scene, &scene, &cfg, given)?;
    warn_every_past_until(&a, &scene, &cfg);
    scene.run.until = cfg.until;
    scene.run.every = cfg.every;
    if a.stop_when_fragmented {
        super::fragments::check_scene(&a.common.scene, &scene)?;
    }
    let out_path = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{}.snap", scene.name)));
    let n = scene.chain.len();
    let sel = (a.output).selection(&a.common.scene, n, scene.run.output.as_ref())?;
    check_run_files(&a, (&scene, (until_key, every_key)), &cfg, &sel, &out_path)?;
    let created_by = super::common::command_line();
    let mut header = Header::new(
        scene.clone(),
        cfg.engine,
        cfg.method,
        cfg.rtol,
        cfg.atol,
        created_by,
    );
    note_output_size(&a, &scene, &cfg, &sel);
    header.output = sel;
    if a.timing {
        // Only with --timing: a plain run's bytes do not depend on the date.
        header.created_at = Some(beadchain::provenance::utc_now());
    }
    let sink = output_sink(&a, &out_path, &header, (&scene, &cfg))?;
    let bar = RunProgress::new(a.common.quiet);
    let mut fragmented = None;
    let done = ckpt::drive(sink, &a.common.scene, |s| {
        if !a.stop_when_fragmented {
            let r = engine::run(&scene, &cfg, &mut bar.watch(s, 0.0, cfg.until, ""));
            bar.finish();
            return r;
        }
        let r = beadchain::analysis::run_until_fragmented(
            &scene,
            &cfg,
            &mut bar.watch(s, 0.0, cfg.until, ""),
        );
        bar.finish();
        let (out, f) = r?;
        if let Some(f) = &f {
            s.notes.push(super::fragments::note(f, cfg.until));
        }
        fragmented = Some(f);
        Ok(out)
    })?;
    match done {
        Ok(out) => {
            report(&out_path, (&scene, &cfg), &out, fragmented.as_ref())?;
            Ok(0)
        }
        Err(code) => Ok(code),
    }
}

/// The output of a run: stale temporaries of dead runs removed, the snapshot's temporary file
/// started with `header`, and the sink that checkpoints into `OUT.ckpt` (an earlier run's
/// checkpoint there is refused with `--checkpoint-every` before this, and kept without it:
/// [`SnapshotSink::foreign_checkpoint`]).
fn output_sink(
    a: &RunArgs,
    out_path: &Path,
    header: &Header,
    (scene, cfg): (&Scene, &RunConfig),
) -> Result<SnapshotSink> {
    super::files::clean_stale_temps(out_path);
    super::files::clean_stale_temps(&ckpt::ckpt_path(out_path));
    let writer = SnapshotWriter::create(out_path, header)?;
    let ckpt_file = ckpt::ckpt_path(out_path);
    let foreign = std::fs::symlink_metadata(&ckpt_file).is_ok();
    let mut sink = ckpt::sink(writer, ckpt_file, a.checkpoint_every, scene, cfg, a.timing)?;
    sink.foreign_checkpoint = foreign;
    Ok(sink)
}

/// The finished run's summary (and fragments, with `--stop-when-fragmented`) and the file
/// written, on standard output, or on standard error when the snapshot itself went to a stream
/// (`--out /dev/stdout` must not get the text too).
fn report(
    out_path: &Path,
    (scene, cfg): (&Scene, &RunConfig),
    out: &RunOutcome,
    fragmented: Option<&Option<beadchain::analysis::Fragmented>>,
) -> Result<()> {
    let to_stream = beadchain::files::classify_output(out_path)
        .is_ok_and(|k| k == beadchain::files::OutputKind::Stream);
    let (mut so, mut se) = (std::io::stdout().lock(), std::io::stderr().lock());
    let w: &mut dyn Write = if to_stream { &mut se } else { &mut so };
    print_outcome(w, scene, cfg, out)?;
    if let Some(f) = fragmented {
        super::fragments::print(w, scene, cfg, f.as_ref(), (&out.u, &out.v))?;
    }
    writeln!(w, "wrote {}", out_path.display())?;
    w.flush()?;
    Ok(())
}

/// `--every`/`--every-si` longer than the run gets the warning the scene's `[run].every` key
/// gets (issue 36: `--every 5` with `until` 2 was silent). Only an interval given on the
/// command line: the scene's own `every` was checked against its `until` by validation, and a
/// shorter `--until` (a quick look at a preset) is not warned about.
fn warn_every_past_until(a: &RunArgs, scene: &Scene, cfg: &RunConfig) {
    let every_key = match (a.every, a.every_si) {
        (Some(_), _) => "--every",
        (None, Some(_)) => "--every-si",
        _ => return,
    };
    let Some(every) = cfg.every.filter(|&e| e > cfg.until) else {
        return;
    };
    let until_key = match (a.common.until, a.common.until_si) {
        (Some(_), _) => "--until",
        (None, Some(_)) => "--until-si",
        _ => "until",
    };
    let si = if every_key.ends_with("-si") || until_key.ends_with("-si") {
        " (computer units)"
    } else {
        ""
    };
    eprintln!(
        "beadchain: warning: {}: {every_key}: {every} > {until_key} {}{si}: only the first and last frame",
        scene.name, cfg.until
    );
}

/// Everything `run` checks before it touches a file: the checkpoint interval, the output is no
/// input and no directory, an earlier run's checkpoint is not replaced, a stream output takes
/// no checkpoints, `--frames-max`, and the estimated output size.
fn check_run_files(
    a: &RunArgs,
    (scene, (until_key, every_key)): (&Scene, (&str, &str)),
    cfg: &RunConfig,
    sel: &Selection,
    out_path: &std::path::Path,
) -> Result<()> {
    use beadchain::files::{classify_output, OutputKind};
    let what = &a.common.scene;
    ckpt::check_checkpoint_every(what, a.checkpoint_every)?;
    let inputs = super::files::labelled_scene_inputs(what);
    super::files::check_not_input(out_path, "--out", &inputs)?;
    let kind = classify_output(out_path)?;
    if kind == OutputKind::File && out_path.is_dir() {
        // refused before the run, not by the rename at its end
        bail!(
            "{}: --out: is a directory (give a file name)",
            out_path.display()
        );
    }
    check_earlier_checkpoint(a, out_path)?;
    if kind == OutputKind::Stream && a.checkpoint_every.is_some() {
        bail!(
            "{}: --checkpoint-every: the output is a stream (device or pipe), which cannot be resumed; write to a file",
            out_path.display()
        );
    }
    use super::common::GivenTime;
    let end = GivenTime::until(&a.common, until_key, scene);
    let interval = GivenTime::every((a.every, a.every_si), every_key, scene);
    let span = (cfg.until, cfg.every);
    let cap_key = if a.output.frames_max.is_some() {
        "--frames-max"
    } else {
        "[output].frames_max"
    };
    super::select::check_frames_max(what, sel, span, cap_key, (&end, &interval))?;
    let n = scene.chain.len();
    a.limit.check(
        (what, false),
        (n, sel.values_per_frame(n as u64).unwrap_or(u64::MAX)),
        (0.0, cfg.until, cfg.every),
        0,
        (&end, &interval),
    )
}

/// Refuses `--checkpoint-every` when `OUT.ckpt` exists: it is an earlier interrupted run's
/// (a finished run removes its own), which this run's first checkpoint would replace and its
/// end remove, so that run could no longer be resumed. Without `--checkpoint-every` the run
/// goes on and leaves it as it was, with a note ([`ckpt::drive`]).
fn check_earlier_checkpoint(a: &RunArgs, out_path: &Path) -> Result<()> {
    let ckpt = ckpt::ckpt_path(out_path);
    if a.checkpoint_every.is_none() || std::fs::symlink_metadata(&ckpt).is_err() {
        return Ok(());
    }
    bail!(
        "{}: --checkpoint-every: the checkpoint of an earlier interrupted run into {} exists, and this run's checkpoints would replace it: continue that run with `beadchain resume {}`, or remove {} to start anew",
        ckpt.display(),
        out_path.display(),
        ckpt.display(),
        ckpt.display()
    )
}

/// Estimated snapshot size from which `run` says, before it starts, how large its output will be.
const NOTE_OUTPUT_BYTES: f64 = 16.0 * 1024.0 * 1024.0;

/// Prints the snapshot size estimate on stderr before a run whose output is large (not with
/// `-q`): a long run's disk use is known before it is spent.
fn note_output_size(a: &RunArgs, scene: &Scene, cfg: &RunConfig, sel: &Selection) {
    use beadchain::snapshot::size::{
        count_text, frame_count_estimate, human_bytes, output_bytes_estimate_values,
    };
    let frames = frame_count_estimate(0.0, cfg.until, cfg.every);
    let n = scene.chain.len();
    let values = sel.values_per_frame(n as u64).unwrap_or(u64::MAX) as f64;
    let bytes = output_bytes_estimate_values(n, values, frames);
    if bytes >= NOTE_OUTPUT_BYTES && !a.common.quiet {
        let of = if sel.is_full() {
            format!("of {n} beads")
        } else {
            format!("storing {}", sel.describe(n as u64))
        };
        eprintln!(
            "beadchain: note: the snapshot will be about {} ({} frames {of})",
            human_bytes(bytes),
            count_text(frames),
        );
    }
}
