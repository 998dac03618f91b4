//! `beadchain plot`: figures of snapshots and CSV tables (library: `beadchain::plot`).

use anyhow::Result;
use beadchain::plot::{
    self, energy, font, profile, trace, BeadRange, EnergyOptions, Map, MapOptions, Scale,
    Spacetime, SpacetimeOptions, TimeRange,
};
use beadchain::snapshot::Snapshot;
use clap::{Subcommand, ValueEnum};
use std::path::{Path, PathBuf};

/// Arguments of `beadchain plot`.
#[derive(clap::Args, Debug)]
pub struct PlotArgs {
    #[command(subcommand)]
    kind: PlotKind,
}

#[derive(Subcommand, Debug)]
enum PlotKind {
    /// Space-time velocity map: bead index x time, signed velocity (paper Figs. 3, 5, 10, 13).
    Spacetime {
        /// Snapshot file.
        snapshot: PathBuf,
        /// Beads A:B (inclusive; `A:` or `:B` open) [default: all].
        #[arg(long)]
        beads: Option<BeadRange>,
        /// Time window T0:T1 (inclusive; either end optional) [default: the whole run].
        #[arg(long)]
        t: Option<TimeRange>,
        /// Colour scale: linear (v/max|v|) or log (sign*log10(|v|/max|v|), down to 1e-4).
        #[arg(long, value_enum, default_value = "linear")]
        scale: ScaleArg,
        #[command(flatten)]
        out: Out,
    },
    /// Velocity against bead index at the frames nearest the given times.
    Profile {
        /// Snapshot file.
        snapshot: PathBuf,
        /// Times, comma-separated.
        #[arg(long, value_delimiter = ',', required = true)]
        times: Vec<f64>,
        /// Beads A:B (inclusive) [default: all].
        #[arg(long)]
        beads: Option<BeadRange>,
        #[command(flatten)]
        out: Out,
    },
    /// Velocity against time of chosen beads.
    Trace {
        /// Snapshot file.
        snapshot: PathBuf,
        /// Bead indices, comma-separated.
        #[arg(long, value_delimiter = ',', required = true)]
        beads: Vec<usize>,
        /// Time window T0:T1 [default: the whole run].
        #[arg(long)]
        t: Option<TimeRange>,
        #[command(flatten)]
        out: Out,
    },
    /// Leading-wave energy (eq. 13) against its peak bead, with the fitted exponential.
    Energy {
        /// Snapshot file.
        snapshot: PathBuf,
        /// Fit from this peak bead on [default: 20; 0 for chains of at most 40 beads].
        #[arg(long)]
        from: Option<usize>,
        /// Fit up to this peak bead [default: N - 10; N - 1 for chains of at most 40 beads].
        #[arg(long)]
        to: Option<usize>,
        /// Logarithmic energy axis.
        #[arg(long)]
        log: bool,
        #[command(flatten)]
        out: Out,
    },
    /// 2-D parameter map (heatmap) of a CSV with a header row, optional level contour.
    Map {
        /// CSV file (e.g. from `beadchain sweep` or validation).
        csv: PathBuf,
        /// x column.
        #[arg(long)]
        x: String,
        /// y column.
        #[arg(long)]
        y: String,
        /// Colour column.
        #[arg(long)]
        z: String,
        /// Colour by log10(z) (rows with z <= 0 are skipped).
        #[arg(long)]
        log_z: bool,
        /// Draw the level line z = LEVEL (marching squares).
        #[arg(long)]
        contour: Option<f64>,
        #[command(flatten)]
        out: Out,
    },
}

#[derive(ValueEnum, Clone, Copy, Debug)]
enum ScaleArg {
    Linear,
    Log,
}

/// Output options shared by every plot.
#[derive(clap::Args, Debug)]
struct Out {
    /// Output: X.png, X.svg, or a base name without extension for both
    /// [default: <input stem>_<plot> (both formats) in the current directory].
    #[arg(long)]
    out: Option<PathBuf>,
    /// Image width in pixels.
    #[arg(long, default_value_t = 900)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 650)]
    height: u32,
}

impl Out {
    fn size(&self) -> Result<(u32, u32)> {
        if !(300..=8000).contains(&self.width) || !(200..=8000).contains(&self.height) {
            anyhow::bail!(
                "--width {} --height {}: the size must be 300..=8000 x 200..=8000 pixels",
                self.width,
                self.height
            );
        }
        Ok((self.width, self.height))
    }
    fn path(&self, input: &Path, kind: &str) -> PathBuf {
        self.out.clone().unwrap_or_else(|| {
            let stem = input
                .file_stem()
                .map_or("plot".into(), |s| s.to_string_lossy().into_owned());
            PathBuf::from(format!("{stem}_{kind}"))
        })
    }
}

fn open(path: &Path) -> Result<Snapshot> {
    let snap = Snapshot::open(path)?;
    for w in snap.warnings() {
        eprintln!("beadchain: warning: {w}");
    }
    snap.require_full("plot needs every bead and both fields")?;
    Ok(snap)
}

/// The output rule (`X.png`, `X.svg` or a base name), and no output file is the input.
fn check_out(path: &Path, kind: &str, input: &Path) -> Result<()> {
    for (f, _) in plot::output_paths(path)? {
        crate::cli_files::check_not_input(&f, "--out", &[(kind, input.to_path_buf())])?;
    }
    Ok(())
}

fn written<F: plot::Figure>(fig: &F, out: &Path) -> Result<i32> {
    // the output rule is checked before any work is reported
    let files = plot::write_figure(fig, out)?;
    if !font::font_available() {
        eprintln!(
            "beadchain: warning: no font file found (BEADCHAIN_FONT, {}): the plot has no text",
            font::FONT_CANDIDATES.join(", ")
        );
    }
    for f in files {
        outln!("wrote {}", f.display());
    }
    Ok(0)
}

/// Runs `beadchain plot`; returns the exit code.
pub fn cmd_plot(args: PlotArgs) -> Result<i32> {
    match args.kind {
        PlotKind::Spacetime {
            snapshot,
            beads,
            t,
            scale,
            out,
        } => {
            let path = out.path(&snapshot, "spacetime");
            check_out(&path, "snapshot", &snapshot)?;
            let snap = open(&snapshot)?;
            let opts = SpacetimeOptions {
                beads: beads.unwrap_or_default(),
                t: t.unwrap_or_default(),
                scale: match scale {
                    ScaleArg::Linear => Scale::Linear,
                    ScaleArg::Log => Scale::Log,
                },
                size: out.size()?,
            };
            let fig = Spacetime::from_snapshot(&snap, &opts)?;
            written(&fig, &path)
        }
        PlotKind::Profile {
            snapshot,
            times,
            beads,
            out,
        } => {
            let path = out.path(&snapshot, "profile");
            check_out(&path, "snapshot", &snapshot)?;
            let snap = open(&snapshot)?;
            let opts = plot::ProfileOptions {
                times,
                beads: beads.unwrap_or_default(),
                size: out.size()?,
            };
            written(&profile::profile(&snap, &opts)?, &path)
        }
        PlotKind::Trace {
            snapshot,
            beads,
            t,
            out,
        } => {
            let path = out.path(&snapshot, "trace");
            check_out(&path, "snapshot", &snapshot)?;
            let snap = open(&snapshot)?;
            let opts = plot::TraceOptions {
                beads,
                t: t.unwrap_or_default(),
                size: out.size()?,
            };
            written(&trace::trace(&snap, &opts)?, &path)
        }
        PlotKind::Energy {
            snapshot,
            from,
            to,
            log,
            out,
        } => {
            let path = out.path(&snapshot, "energy");
            check_out(&path, "snapshot", &snapshot)?;
            let snap = open(&snapshot)?;
            let opts = EnergyOptions {
                from,
                to,
                log,
                size: out.size()?,
            };
            let fig = energy::energy(&snap, &opts)?;
            match &fig.fit {
                Ok(f) => {
                    outln!(
                    "fit over peak beads {}..{}: gamma = {:.6e} +- {:.3e} ({} points, R^2 = {:.4})",
                    fig.range.0, fig.range.1, f.gamma, f.gamma_stderr, f.n, f.r2
                )
                }
                Err(e) => eprintln!(
                    "beadchain: warning: no exponential fit over peak beads {}..{}: {e}",
                    fig.range.0, fig.range.1
                ),
            }
            written(&fig, &path)
        }
        PlotKind::Map {
            csv,
            x,
            y,
            z,
            log_z,
            contour,
            out,
        } => {
            let path = out.path(&csv, "map");
            check_out(&path, "CSV file", &csv)?;
            let opts = MapOptions {
                x,
                y,
                z,
                log_z,
                contour,
                size: out.size()?,
            };
            let fig = Map::from_csv(&csv, &opts)?;
            for w in &fig.warnings {
                eprintln!("beadchain: warning: {w}");
            }
            written(&fig, &path)
        }
    }
}
