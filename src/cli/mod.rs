//! Argument parsing (clap derive) and the dispatch to the subcommands, one module per command
//! group. Layering: this module imports its children; a child never imports this module (what
//! several commands share is in [`common`], [`files`], [`select`] and [`ckpt`]).

mod accuracy;
mod analyze;
mod analyze_gas;
mod breather;
mod check;
mod ckpt;
mod ckpt_target;
mod common;
mod dispersion;
mod export;
mod files;
mod fragments;
mod modal;
mod modes;
mod plot;
mod plot_out;
mod run;
mod scene;
mod select;
mod sweep;
mod validate;

pub use files::is_broken_pipe;

use anyhow::Result;
use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// Simulator for one-dimensional granular chains with Hertz-like contacts.
#[derive(Parser, Debug)]
#[command(name = "beadchain", version = beadchain::provenance::LONG_VERSION, about)]
pub struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand, Debug)]
enum Cmd {
    /// Run a scene (a TOML file or a preset name) and write a binary snapshot.
    Run(run::RunArgs),
    /// Run the hybrid and the dense engine on a scene and compare them.
    Check(check::CheckArgs),
    /// Export frames (or the event log) of a snapshot as CSV, NPY or NPZ (long or wide layout).
    Export(export::ExportArgs),
    /// Print a snapshot's header, frame count, time span and energies.
    Inspect {
        /// Snapshot file.
        file: PathBuf,
    },
    /// List the built-in preset scenes.
    Scenes,
    /// Resolved scenes (`scene show SCENE`: every per-bead and per-contact value).
    #[command(subcommand)]
    Scene(scene::SceneCmd),
    /// Work-precision study: every engine x method x tolerance against a tight reference;
    /// writes DIR/accuracy.csv, DIR/accuracy.svg, DIR/accuracy.png and prints the table.
    Accuracy(accuracy::AccuracyArgs),
    /// Analyse a snapshot: leading wave, energies, interface split, decay fit.
    Analyze(analyze::AnalyzeArgs),
    /// Reproduce the paper's key numbers (--quick: reduced checks, seconds).
    Validate(validate::ValidateArgs),
    /// Linear modes about the static equilibrium: frequencies, mode shapes, participation
    /// ratios, density of states (--out modes.npz).
    Modes(modes::ModesArgs),
    /// Discrete breather at a frequency (e.g. in a band gap): Newton on the period map from a
    /// linear mode, continued in frequency; Floquet multipliers; --out breather.toml.
    Breather(breather::BreatherArgs),
    /// Plots (PNG/SVG): spacetime, profile, trace, energy (of a snapshot); map (of a CSV).
    Plot(plot::PlotArgs),
    /// Run a parameter sweep (grid/list over scene keys and seeds) in parallel into one CSV.
    Sweep(sweep::SweepArgs),
    /// Merge the result files of `sweep --shard K/M` runs into one CSV.
    Merge(sweep::MergeArgs),
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
        limit: files::SizeLimit,
        /// No progress bar (it is shown only when standard error is a terminal).
        #[arg(short, long)]
        quiet: bool,
    },
}

/// Runs the parsed command; returns the exit code.
pub fn dispatch(cli: Cli) -> Result<i32> {
    match cli.cmd {
        Cmd::Run(a) => run::cmd_run(a),
        Cmd::Analyze(a) => analyze::cmd_analyze(a),
        Cmd::Validate(a) => validate::cmd_validate(a),
        Cmd::Check(a) => check::cmd_check(a),
        Cmd::Export(a) => export::cmd_export(a),
        Cmd::Inspect { file } => export::cmd_inspect(&file),
        Cmd::Resume {
            file,
            until,
            checkpoint_every,
            limit,
            quiet,
        } => ckpt::cmd_resume(&file, until, checkpoint_every, limit, quiet),
        Cmd::Accuracy(a) => accuracy::cmd_accuracy(a),
        Cmd::Plot(a) => plot::cmd_plot(a),
        Cmd::Modes(a) => modes::cmd_modes(a),
        Cmd::Breather(a) => breather::cmd_breather(a),
        Cmd::Sweep(a) => sweep::cmd_sweep(a),
        Cmd::Merge(a) => sweep::cmd_merge(a),
        Cmd::Scene(c) => scene::cmd_scene(c),
        Cmd::Scenes => {
            for p in beadchain::scene::presets() {
                outln!("{:<32} {}", p.name, p.description);
            }
            Ok(0)
        }
    }
}
