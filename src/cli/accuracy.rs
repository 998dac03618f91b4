//! `beadchain accuracy`: the work-precision study of [`beadchain::accuracy`], its table on
//! standard output and the files it wrote.

use super::common::{load_scene, named};
use anyhow::Result;
use beadchain::integrate::Method;
use beadchain::progress::RunProgress;
use beadchain::scene::Engine;
use std::path::PathBuf;

/// Arguments of `beadchain accuracy`.
#[derive(clap::Args, Debug)]
pub struct AccuracyArgs {
    /// Scene file (TOML) or preset name.
    pub scene: String,
    /// Engines, comma-separated (hybrid, dense).
    #[arg(
        long,
        value_parser = named::<Engine>(),
        value_delimiter = ',',
        default_value = "hybrid,dense"
    )]
    pub engines: Vec<Engine>,
    /// Methods, comma-separated (auto, radau5, dop853, verlet).
    #[arg(
        long,
        value_parser = named::<Method>(),
        value_delimiter = ',',
        default_value = "auto,radau5,dop853,verlet"
    )]
    pub methods: Vec<Method>,
    /// Relative tolerances of the adaptive methods (atol: as `run --rtol RTOL`, see
    /// --atol-ratio).
    #[arg(long, value_delimiter = ',', default_value = "1e-4,1e-6,1e-8,1e-10")]
    pub rtols: Vec<f64>,
    /// Verlet steps in units of the characteristic time L/V (dt = s * L/V).
    #[arg(long, value_delimiter = ',', default_value = "0.1,0.03,0.01,0.003")]
    pub verlet_steps: Vec<f64>,
    /// atol = atol-ratio * rtol [default: what `run --rtol RTOL` uses: the scene's `[run]
    /// atol`, else rtol/10^4, at least 1e-15].
    #[arg(long)]
    pub atol_ratio: Option<f64>,
    /// Tolerance of the dense radau5 reference [default: the smallest --rtols].
    #[arg(long)]
    pub reference_rtol: Option<f64>,
    /// End time [default: the scene's `[run] until`].
    #[arg(long)]
    pub until: Option<f64>,
    /// Timed repetitions per run (median wall time).
    #[arg(long, default_value_t = 1)]
    pub repeat: usize,
    /// Output directory.
    #[arg(long, default_value = "accuracy")]
    pub out: PathBuf,
    /// No progress bar (it is shown only when standard error is a terminal).
    #[arg(short, long)]
    pub quiet: bool,
}

/// Runs `beadchain accuracy`; returns the exit code.
pub fn cmd_accuracy(a: AccuracyArgs) -> Result<i32> {
    use beadchain::accuracy::{accuracy_study, format_table, AccuracyOptions};
    let scene = load_scene(&a.scene)?;
    let inputs = super::files::labelled_scene_inputs(&a.scene);
    for f in ["accuracy.csv", "accuracy.svg", "accuracy.png"] {
        super::files::check_not_input(&a.out.join(f), "--out", &inputs)?;
    }
    let opts = AccuracyOptions {
        engines: a.engines.clone(),
        methods: a.methods.clone(),
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
