//! Argument parsing (clap derive) and the subcommands.

use crate::cli_ckpt;
use anyhow::{bail, Context, Result};
use beadchain::engine::{self, RunConfig, RunOutcome};
use beadchain::export;
use beadchain::integrate::Method;
use beadchain::linalg::SolverKind;
use beadchain::progress::RunProgress;
use beadchain::scene::{self, Engine, Scene};
use beadchain::snapshot::{Header, Selection, Snapshot, SnapshotWriter};
use clap::{Parser, Subcommand, ValueEnum};
use std::io::Write;
use std::path::PathBuf;

/// Simulator for one-dimensional granular chains with Hertz-like contacts.
#[derive(Parser, Debug)]
#[command(name = "beadchain", version, about)]
pub struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand, Debug)]
enum Cmd {
    /// Run a scene (a TOML file or a preset name) and write a binary snapshot.
    Run(RunArgs),
    /// Run the hybrid and the dense engine on a scene and compare them.
    Check(CheckArgs),
    /// Export frames (or the event log) of a snapshot as CSV, NPY or NPZ (long or wide layout).
    Export(crate::cli_export::ExportArgs),
    /// Print a snapshot's header, frame count, time span and energies.
    Inspect {
        /// Snapshot file.
        file: PathBuf,
    },
    /// List the built-in preset scenes.
    Scenes,
    /// Resolved scenes (`scene show SCENE`: every per-bead and per-contact value).
    #[command(subcommand)]
    Scene(crate::cli_scene::SceneCmd),
    /// Work-precision study: every engine x method x tolerance against a tight reference;
    /// writes DIR/accuracy.csv, DIR/accuracy.svg, DIR/accuracy.png and prints the table.
    Accuracy(AccuracyArgs),
    /// Analyse a snapshot: leading wave, energies, interface split, decay fit.
    Analyze(crate::cli_analysis::AnalyzeArgs),
    /// Reproduce the paper's key numbers (--quick: reduced checks, seconds).
    Validate(crate::cli_analysis::ValidateArgs),
    /// Plots (PNG/SVG): spacetime, profile, trace, energy (of a snapshot); map (of a CSV).
    Plot(crate::cli_plot::PlotArgs),
    /// Run a parameter sweep (grid/list over scene keys and seeds) in parallel into one CSV.
    Sweep(crate::cli_sweep::SweepArgs),
    /// Merge the result files of `sweep --shard K/M` runs into one CSV.
    Merge(crate::cli_sweep::MergeArgs),
    /// Continue an interrupted run from its checkpoint into the same output file.
    Resume {
        /// Checkpoint file (`OUTPUT.ckpt`).
        file: PathBuf,
        /// New end time (default: the original run's).
        #[arg(long)]
        until: Option<f64>,
        /// Keep writing checkpoints every DT of simulated time.
        #[arg(long)]
        checkpoint_every: Option<f64>,
        #[command(flatten)]
        limit: crate::cli_files::SizeLimit,
        /// No progress bar (it is shown only when standard error is a terminal).
        #[arg(short, long)]
        quiet: bool,
    },
}

#[derive(clap::Args, Debug)]
struct AccuracyArgs {
    /// Scene file (TOML) or preset name.
    scene: String,
    /// Engines, comma-separated (hybrid, dense).
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "hybrid,dense"
    )]
    engines: Vec<EngineArg>,
    /// Methods, comma-separated (auto, radau5, dop853, verlet).
    #[arg(
        long,
        value_enum,
        value_delimiter = ',',
        default_value = "auto,radau5,dop853,verlet"
    )]
    methods: Vec<MethodArg>,
    /// Relative tolerances of the adaptive methods (atol = atol-ratio * rtol).
    #[arg(long, value_delimiter = ',', default_value = "1e-4,1e-6,1e-8,1e-10")]
    rtols: Vec<f64>,
    /// Verlet steps in units of the characteristic time L/V (dt = s * L/V).
    #[arg(long, value_delimiter = ',', default_value = "0.1,0.03,0.01,0.003")]
    verlet_steps: Vec<f64>,
    /// atol = atol-ratio * rtol.
    #[arg(long, default_value_t = 0.01)]
    atol_ratio: f64,
    /// Tolerance of the dense radau5 reference [default: the smallest --rtols].
    #[arg(long)]
    reference_rtol: Option<f64>,
    /// End time [default: the scene's `[run] until`].
    #[arg(long)]
    until: Option<f64>,
    /// Timed repetitions per run (median wall time).
    #[arg(long, default_value_t = 1)]
    repeat: usize,
    /// Output directory.
    #[arg(long, default_value = "accuracy")]
    out: PathBuf,
    /// No progress bar (it is shown only when standard error is a terminal).
    #[arg(short, long)]
    quiet: bool,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
enum EngineArg {
    Dense,
    Hybrid,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
enum MethodArg {
    Radau5,
    Dop853,
    /// Fixed-step velocity Verlet; its step is rtol·L/V.
    Verlet,
    /// DOP853 while non-stiff, Radau IIA while stiff, per cluster.
    Auto,
}

impl From<MethodArg> for Method {
    fn from(m: MethodArg) -> Self {
        match m {
            MethodArg::Radau5 => Method::Radau5,
            MethodArg::Dop853 => Method::Dop853,
            MethodArg::Verlet => Method::Verlet,
            MethodArg::Auto => Method::Auto,
        }
    }
}

#[derive(ValueEnum, Clone, Copy, Debug)]
enum SolverArg {
    Auto,
    Direct,
    Faer,
}

#[derive(clap::Args, Debug)]
struct Common {
    /// Scene file (TOML) or preset name (see `beadchain scenes`).
    scene: String,
    /// Integration method [default: the scene's, else auto].
    #[arg(long, value_enum)]
    method: Option<MethodArg>,
    /// Relative tolerance [default: the scene's, else 1e-8].
    #[arg(long)]
    rtol: Option<f64>,
    /// Absolute tolerance, relative to the run's characteristic length/velocity
    /// [default: the scene's, else rtol/10^4, at least 1e-14 (1e-12 at the default rtol)].
    #[arg(long)]
    atol: Option<f64>,
    /// End time [default: the scene's `[run] until`].
    #[arg(long)]
    until: Option<f64>,
    /// Linear solver of the implicit method.
    #[arg(long, value_enum, default_value = "auto")]
    solver: SolverArg,
    /// Abort after this many integrator steps.
    #[arg(long)]
    max_steps: Option<u64>,
    /// No progress bar (it is shown only when standard error is a terminal).
    #[arg(short, long)]
    quiet: bool,
}

#[derive(clap::Args, Debug)]
struct RunArgs {
    #[command(flatten)]
    common: Common,
    /// Engine [default: the scene's, else hybrid].
    #[arg(long, value_enum)]
    engine: Option<EngineArg>,
    /// Output interval [default: the scene's `[run] every`, else first and last frame].
    #[arg(long)]
    every: Option<f64>,
    /// Output snapshot [default: `<scene name>.snap` in the current directory].
    #[arg(long)]
    out: Option<PathBuf>,
    /// Write a resumable checkpoint `FILE.ckpt` every DT of simulated time (a checkpoint is
    /// also written on SIGINT/SIGTERM; `beadchain resume FILE.ckpt` continues the run).
    #[arg(long)]
    checkpoint_every: Option<f64>,
    /// Also store the wall-clock time in the snapshot (then two runs no longer give identical
    /// bytes; by default it is only printed).
    #[arg(long)]
    timing: bool,
    #[command(flatten)]
    limit: crate::cli_files::SizeLimit,
    #[command(flatten)]
    output: crate::cli_select::OutputArgs,
}

#[derive(clap::Args, Debug)]
struct CheckArgs {
    #[command(flatten)]
    common: Common,
    /// Allowed trajectory deviation, relative to the largest |v| (for u: to the largest |u|
    /// change), when the scene is not more sensitive than that [default: 1000·rtol].
    #[arg(long)]
    tol: Option<f64>,
}

/// Runs the parsed command; returns the exit code.
pub fn dispatch(cli: Cli) -> Result<i32> {
    match cli.cmd {
        Cmd::Run(a) => cmd_run(a),
        Cmd::Analyze(a) => crate::cli_analysis::cmd_analyze(a),
        Cmd::Validate(a) => crate::cli_analysis::cmd_validate(a),
        Cmd::Check(a) => cmd_check(a),
        Cmd::Export(a) => crate::cli_export::cmd_export(a),
        Cmd::Inspect { file } => cmd_inspect(&file),
        Cmd::Resume {
            file,
            until,
            checkpoint_every,
            limit,
            quiet,
        } => cli_ckpt::cmd_resume(&file, until, checkpoint_every, limit, quiet),
        Cmd::Accuracy(a) => cmd_accuracy(a),
        Cmd::Plot(a) => crate::cli_plot::cmd_plot(a),
        Cmd::Sweep(a) => crate::cli_sweep::cmd_sweep(a),
        Cmd::Merge(a) => crate::cli_sweep::cmd_merge(a),
        Cmd::Scene(c) => crate::cli_scene::cmd_scene(c),
        Cmd::Scenes => {
            for p in scene::presets() {
                outln!("{:<32} {}", p.name, p.description);
            }
            Ok(0)
        }
    }
}

/// `beadchain inspect FILE`: the report, then every frame's checksum verified; a damaged frame
/// makes it exit 2 with one line naming the first damaged frame.
fn cmd_inspect(file: &std::path::Path) -> Result<i32> {
    let snap = Snapshot::open(file)?;
    let chain = snap.header().scene.chain.clone();
    let damaged = export::damaged_frames(&snap);
    out!("{}", export::inspect_with(&snap, &chain, &damaged));
    if let Some((k, e)) = damaged.first() {
        bail!(
            "{}: {} of {} frames damaged (first: frame {k}: {e})",
            file.display(),
            damaged.len(),
            snap.frame_count()
        );
    }
    Ok(0)
}

/// Below this relative tolerance, rounding in f64 (≈ 1.1e-16 per operation, accumulated over a
/// step's stages) dominates the error estimate: a warning, not an error.
const RTOL_F64_FLOOR: f64 = 1e-14;

pub(crate) fn load_scene(spec: &str) -> Result<Scene> {
    let scene = scene::load(spec)?;
    for w in scene::validate(&scene)? {
        eprintln!("beadchain: warning: {}: {w}", scene.name);
    }
    Ok(scene)
}

fn config(scene: &Scene, c: &Common) -> RunConfig {
    let mut cfg = RunConfig::from_scene(scene);
    if let Some(m) = c.method {
        cfg.method = m.into();
    }
    if let Some(r) = c.rtol {
        cfg.rtol = r;
        if scene.run.atol.is_none() {
            cfg.atol = beadchain::integrate::default_atol(r);
        }
    }
    if let Some(a) = c.atol {
        cfg.atol = a;
    }
    if cfg.rtol > 0.0 && cfg.rtol < RTOL_F64_FLOOR {
        eprintln!(
            "beadchain: warning: rtol = {:e} is below what f64 arithmetic can deliver (~{RTOL_F64_FLOOR:e} relative): the error will stall there",
            cfg.rtol
        );
    }
    if let Some(t) = c.until {
        cfg.until = t;
    }
    cfg.solver = match c.solver {
        SolverArg::Auto => SolverKind::Auto,
        SolverArg::Direct => SolverKind::Direct,
        SolverArg::Faer => SolverKind::Faer,
    };
    cfg.max_steps = c.max_steps;
    cfg
}

fn cmd_run(a: RunArgs) -> Result<i32> {
    let mut scene = load_scene(&a.common.scene)?;
    let mut cfg = config(&scene, &a.common);
    if let Some(e) = a.engine {
        cfg.engine = match e {
            EngineArg::Dense => Engine::Dense,
            EngineArg::Hybrid => Engine::Hybrid,
        };
    }
    if a.every.is_some() {
        cfg.every = a.every;
    }
    scene.run.until = cfg.until;
    scene.run.every = cfg.every;
    engine::check_config(&scene, &cfg).with_context(|| scene.name.clone())?;
    let out_path = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("{}.snap", scene.name)));
    let n = scene.chain.len();
    let sel = (a.output).selection(&a.common.scene, n, scene.run.output.as_ref())?;
    check_run_files(&a, &scene, &cfg, &sel, &out_path)?;
    let created_by = std::env::args().collect::<Vec<_>>().join(" ");
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
    let writer = SnapshotWriter::create(&out_path, &header)?;
    let ckpt = cli_ckpt::ckpt_path(&out_path);
    let sink =
        cli_ckpt::SnapshotSink::new(writer, ckpt, a.checkpoint_every, &scene, &cfg, a.timing)?;
    let bar = RunProgress::new(a.common.quiet);
    let done = cli_ckpt::drive(sink, &a.common.scene, |s| {
        let r = engine::run(&scene, &cfg, &mut bar.watch(s, 0.0, cfg.until, ""));
        bar.finish();
        r
    })?;
    match done {
        Ok(out) => {
            // A snapshot written to a stream (`--out /dev/stdout`) must not get the text too.
            let to_stream = beadchain::files::classify_output(&out_path)
                .is_ok_and(|k| k == beadchain::files::OutputKind::Stream);
            let (mut so, mut se) = (std::io::stdout().lock(), std::io::stderr().lock());
            let w: &mut dyn Write = if to_stream { &mut se } else { &mut so };
            print_outcome(w, &scene, &cfg, &out)?;
            writeln!(w, "wrote {}", out_path.display())?;
            w.flush()?;
            Ok(0)
        }
        Err(code) => Ok(code),
    }
}

/// Everything `run` checks before it touches a file: the checkpoint interval, the output is no
/// input, a stream output takes no checkpoints, `--frames-max`, and the estimated output size.
fn check_run_files(
    a: &RunArgs,
    scene: &Scene,
    cfg: &RunConfig,
    sel: &Selection,
    out_path: &std::path::Path,
) -> Result<()> {
    use beadchain::files::{classify_output, OutputKind};
    let what = &a.common.scene;
    cli_ckpt::check_checkpoint_every(what, a.checkpoint_every)?;
    let inputs = crate::cli_files::labelled_scene_inputs(what);
    crate::cli_files::check_not_input(out_path, "--out", &inputs)?;
    let kind = classify_output(out_path)?;
    if kind == OutputKind::Stream && a.checkpoint_every.is_some() {
        bail!(
            "{}: --checkpoint-every: the output is a stream (device or pipe), which cannot be resumed; write to a file",
            out_path.display()
        );
    }
    let until_key = if a.common.until.is_some() {
        "--until"
    } else {
        "[run].until"
    };
    let span = (cfg.until, cfg.every);
    let cap_key = if a.output.frames_max.is_some() {
        "--frames-max"
    } else {
        "[output].frames_max"
    };
    crate::cli_select::check_frames_max(what, sel, span, (cap_key, cap_key), until_key)?;
    let n = scene.chain.len();
    a.limit.check(
        what,
        (n, sel.values_per_frame(n as u64).unwrap_or(u64::MAX)),
        (0.0, cfg.until, cfg.every),
        0,
        until_key,
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

/// The run summary, on `w` (standard output, or standard error when the snapshot itself goes
/// to a stream such as `/dev/stdout`).
pub fn print_outcome(
    w: &mut dyn Write,
    scene: &Scene,
    cfg: &RunConfig,
    out: &RunOutcome,
) -> Result<()> {
    let s = &out.stats;
    writeln!(
        w,
        "{}: {} beads, engine {}, method {}, rtol {:e}, atol {:e}",
        scene.name,
        scene.chain.len(),
        cfg.engine.name(),
        cfg.method.name(),
        cfg.rtol,
        cfg.atol
    )?;
    writeln!(
        w,
        "t = {} in {:.3} s: {} steps ({} rejected), {} active bead-steps, {} RHS evaluations, {} factorizations, {} Newton iterations ({} failures), largest cluster {}",
        out.t_end,
        out.wall_seconds,
        s.steps,
        s.rejected,
        s.bead_steps,
        s.rhs_evals,
        s.factorizations,
        s.newton_iters,
        s.newton_failures,
        out.largest_cluster
    )?;
    if cfg.method == Method::Auto {
        writeln!(
            w,
            "method auto: {} steps dop853, {} steps radau5",
            s.steps - out.implicit_steps,
            out.implicit_steps
        )?;
    }
    if !out.events_by_kind.is_empty() {
        let ev: Vec<String> = out
            .events_by_kind
            .iter()
            .filter(|(_, c)| *c > 0)
            .map(|(k, c)| format!("{k} {c}"))
            .collect();
        writeln!(
            w,
            "events: {}",
            if ev.is_empty() {
                "none".into()
            } else {
                ev.join(", ")
            }
        )?;
    }
    if out.dissipated != 0.0 {
        writeln!(
            w,
            "energy {:.12e} -> {:.12e}, dissipated {:.12e} (balance error {:.3e}); momentum {:.12e} -> {:.12e}",
            out.energy_initial,
            out.energy_final,
            out.dissipated,
            out.relative_energy_error(),
            out.momentum_initial,
            out.momentum_final
        )?;
        return Ok(());
    }
    writeln!(
        w,
        "energy {:.12e} -> {:.12e} (relative change {:.3e}); momentum {:.12e} -> {:.12e}",
        out.energy_initial,
        out.energy_final,
        out.relative_energy_error(),
        out.momentum_initial,
        out.momentum_final
    )?;
    Ok(())
}

fn cmd_check(a: CheckArgs) -> Result<i32> {
    let scene = load_scene(&a.common.scene)?;
    let base = config(&scene, &a.common);
    engine::check_config(&scene, &base).with_context(|| scene.name.clone())?;
    let tol = a.tol.unwrap_or(1000.0 * base.rtol);
    crate::cli_check::cmd_check(&scene, &base, tol, a.common.quiet)
}

fn cmd_accuracy(a: AccuracyArgs) -> Result<i32> {
    use beadchain::accuracy::{accuracy_study, format_table, AccuracyOptions};
    let scene = load_scene(&a.scene)?;
    let opts = AccuracyOptions {
        engines: a
            .engines
            .iter()
            .map(|e| match e {
                EngineArg::Dense => Engine::Dense,
                EngineArg::Hybrid => Engine::Hybrid,
            })
            .collect(),
        methods: a.methods.iter().map(|&m| m.into()).collect(),
        rtols: a.rtols,
        verlet_steps: a.verlet_steps,
        atol_ratio: a.atol_ratio,
        until: a.until,
        repeat: a.repeat,
        reference_rtol: a.reference_rtol,
        out_dir: Some(a.out),
        progress: Some(RunProgress::new(a.quiet)),
        ..AccuracyOptions::default()
    };
    let report = accuracy_study(&scene, &opts)?;
    if let Some(bar) = &opts.progress {
        bar.finish();
    }
    out!("{}", format_table(&report));
    for f in &report.files {
        outln!("wrote {}", f.display());
    }
    Ok(0)
}
