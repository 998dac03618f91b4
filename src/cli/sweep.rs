//! `beadchain sweep` and `beadchain merge` (the file format is documented in `beadchain::sweep`).

use anyhow::Result;
use beadchain::sweep::{self, Shard, SweepOptions, SweepSpec};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::path::PathBuf;

/// Arguments of `beadchain sweep`.
#[derive(clap::Args, Debug)]
pub struct SweepArgs {
    /// Sweep file (TOML).
    pub file: PathBuf,
    /// Result CSV [default: `<sweep file stem>.csv` in the current directory]. Rows collect in
    /// `OUT.partial` while running; rerunning the same command resumes from it.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Worker threads [default: all cores].
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Run only the runs with index % M == K-1 (K in 1..=M), e.g. `--shard 3/8`.
    #[arg(long)]
    pub shard: Option<String>,
    /// Run at most N runs now, then stop (the partial file keeps them; rerun to continue).
    #[arg(long)]
    pub max_runs: Option<usize>,
    /// Add a wall_seconds column (the output then differs from run to run).
    #[arg(long)]
    pub timing: bool,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
    /// Per-run limit of the estimated frame data (`run.until / run.every` frames x beads).
    #[command(flatten)]
    pub limit: super::files::SizeLimit,
}

/// Arguments of `beadchain merge`.
#[derive(clap::Args, Debug)]
pub struct MergeArgs {
    /// Merged result CSV (written atomically).
    pub out: PathBuf,
    /// Shard result files (from `beadchain sweep --shard K/M`).
    #[arg(required = true)]
    pub shards: Vec<PathBuf>,
    /// Write the merge even if some runs are in no shard (they are listed).
    #[arg(long)]
    pub allow_missing: bool,
}

/// Runs `beadchain sweep`.
pub fn cmd_sweep(a: SweepArgs) -> Result<i32> {
    let mut spec = SweepSpec::load(&a.file)?;
    spec.max_output_bytes = a.limit.bytes();
    let shard: Option<Shard> = a.shard.as_deref().map(str::parse).transpose()?;
    if a.jobs == Some(0) {
        anyhow::bail!("--jobs 0: need at least one worker thread");
    }
    let out = a.out.clone().unwrap_or_else(|| {
        let stem = a
            .file
            .file_stem()
            .map_or("sweep".into(), |s| s.to_string_lossy());
        PathBuf::from(format!("{stem}.csv"))
    });
    let dir = a.file.parent().unwrap_or(std::path::Path::new("."));
    let scene_file = dir.join(&spec.scene_spec);
    let mut inputs = vec![("sweep file", a.file.clone())];
    inputs.extend(super::files::labelled_scene_inputs(
        &scene_file.to_string_lossy(),
    ));
    let meta = beadchain::sweep::csv::meta_path(&out);
    beadchain::files::check_not_input(&[&out, &meta], "--out", &inputs)?;
    // before any run: a refused output (a symbolic link) would otherwise fail only at the end
    beadchain::files::classify_output(&out)?;
    let opts = SweepOptions {
        out: out.clone(),
        jobs: a.jobs,
        shard,
        max_runs: a.max_runs,
        timing: a.timing,
    };
    let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::stderr());
    if a.quiet || !std::io::stderr().is_terminal() {
        bar.set_draw_target(ProgressDrawTarget::hidden());
    }
    if let Ok(style) =
        ProgressStyle::with_template("{bar:40} {pos}/{len} runs, {elapsed} (eta {eta})")
    {
        bar.set_style(style);
    }
    let progress = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let s = sweep::run_sweep(&spec, &opts, &progress)?;
    bar.finish_and_clear();
    let what = shard.map_or(String::new(), |s| format!(" (shard {}/{})", s.k, s.m));
    outln!(
        "{}: {} runs{what}: {} resumed, {} skipped (result already in {}), {} run now, {} with errors",
        a.file.display(),
        s.runs,
        s.resumed,
        s.skipped,
        out.display(),
        s.ran,
        s.failed
    );
    if s.complete && s.written {
        outln!("wrote {}", out.display());
    } else if s.complete {
        outln!("{} is up to date (unchanged)", out.display());
    } else {
        outln!(
            "stopped with {} of {} runs done; rows are in {} (rerun the same command to continue)",
            s.resumed + s.ran,
            s.runs,
            sweep::exec::partial_path(&out).display()
        );
    }
    Ok(0)
}

/// Runs `beadchain merge`.
pub fn cmd_merge(a: MergeArgs) -> Result<i32> {
    let mut inputs: Vec<_> = a.shards.iter().map(|s| ("shard file", s.clone())).collect();
    let metas = a.shards.iter().map(|s| beadchain::sweep::csv::meta_path(s));
    inputs.extend(metas.map(|m| ("shard's meta file", m)));
    let meta = beadchain::sweep::csv::meta_path(&a.out);
    beadchain::files::check_not_input(&[&a.out, &meta], "OUT", &inputs)?;
    let m = sweep::merge(&a.out, &a.shards, a.allow_missing)?;
    if !m.missing.is_empty() {
        eprintln!(
            "beadchain: warning: {} runs are in no shard: {:?}",
            m.missing.len(),
            m.missing
        );
    }
    outln!("wrote {} ({} rows)", a.out.display(), m.rows);
    Ok(0)
}
