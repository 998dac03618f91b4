//! `beadchain plot`: figures of snapshots and CSV tables (library: `beadchain::plot`).

use super::plot_out::{size_of, written, Out};
use anyhow::Result;
use beadchain::plot::{
    self, animate, energy, font, profile, trace, AnimateOptions, Animation, BeadRange, Cmap,
    EnergyOptions, Field, Labels, Map, MapOptions, Panels, Scale, Spacetime, SpacetimeOptions,
    TimeRange, Units,
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
    /// Space-time velocity map: bead index x time, signed velocity (paper Figs. 4, 6, 10, 13);
    /// several snapshots give side-by-side panels with one shared colour scale.
    Spacetime {
        /// Snapshot file(s): one panel each.
        #[arg(required = true)]
        snapshots: Vec<PathBuf>,
        /// Beads: one range A:B, half-open as in `run --beads` (beads A to B-1; `A:` to the
        /// end, `:B` from 0) [default: all].
        #[arg(long, value_name = "A:B")]
        beads: Option<BeadRange>,
        /// Time window T0:T1 (inclusive; either end optional) [default: the whole run].
        #[arg(long)]
        t: Option<TimeRange>,
        /// Colour scale: linear (v/max|v|) or log (sign*log10(|v|/max|v|), down to 1e-4).
        #[arg(long, value_enum, default_value = "linear")]
        scale: ScaleArg,
        /// Colour map: coolwarm, bwr, viridis or gray.
        #[arg(long, default_value = "coolwarm")]
        cmap: String,
        #[command(flatten)]
        units: UnitsArg,
        #[command(flatten)]
        out: Out,
    },
    /// Velocity against bead index at the frames nearest the given times.
    Profile {
        /// Snapshot file.
        snapshot: PathBuf,
        /// Times, comma-separated (in the axis units).
        #[arg(long, value_delimiter = ',', required = true)]
        times: Vec<f64>,
        /// Beads: one range A:B, half-open as in `run --beads` (beads A to B-1) [default: all].
        #[arg(long, value_name = "A:B")]
        beads: Option<BeadRange>,
        #[command(flatten)]
        units: UnitsArg,
        #[command(flatten)]
        out: Out,
    },
    /// Velocity against time of chosen beads.
    Trace {
        /// Snapshot file.
        snapshot: PathBuf,
        /// Beads, as `run --beads`: indices I, half-open ranges A:B (beads A to B-1) and
        /// A:B:STEP, comma-separated, e.g. `48,49,50` or `48:52`.
        #[arg(long, value_name = "LIST", required = true)]
        beads: String,
        /// Time window T0:T1 (in the axis units) [default: the whole run].
        #[arg(long)]
        t: Option<TimeRange>,
        #[command(flatten)]
        units: UnitsArg,
        #[command(flatten)]
        out: Out,
    },
    /// Leading-wave energy (eq. 13) against its position, with the fitted exponential (the
    /// decay rate `analyze` reports).
    Energy {
        /// Snapshot file.
        snapshot: PathBuf,
        /// Fit from this leading-wave position on (its energy-weighted centre, in beads, as
        /// `analyze`) [default: 20; 0 for chains of at most 40 beads].
        #[arg(long)]
        from: Option<usize>,
        /// Fit up to this position [default: N - 10; N - 1 for chains of at most 40 beads].
        #[arg(long)]
        to: Option<usize>,
        /// Logarithmic energy axis (ticks at decades).
        #[arg(long)]
        log: bool,
        /// Interface bead K: fit beads < K and >= K separately (never across the interface).
        #[arg(long)]
        interface: Option<usize>,
        #[command(flatten)]
        units: UnitsArg,
        #[command(flatten)]
        out: Out,
    },
    /// Animated GIF of velocity (or displacement, kinetic energy) against bead index, one frame
    /// per snapshot frame, fixed y limits over the whole run.
    Animate(AnimateArgs),
    /// Band structure omega(q) of a periodic chain's unit cell (Bloch problem), with its gaps.
    Dispersion(super::dispersion::DispersionArgs),
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
        /// Colour map: viridis, gray, coolwarm or bwr.
        #[arg(long, default_value = "viridis")]
        cmap: String,
        /// Colour-bar label [default: the z column's readable name].
        #[arg(long)]
        zlabel: Option<String>,
        #[command(flatten)]
        out: Out,
    },
}

/// Arguments of `plot animate`.
#[derive(clap::Args, Debug)]
struct AnimateArgs {
    /// Snapshot file.
    snapshot: PathBuf,
    /// Field: v (velocity), u (displacement) or energy (kinetic, m v^2/2).
    #[arg(long, value_enum, default_value = "v")]
    field: FieldArg,
    /// Beads: one range A:B, half-open as in `run --beads` (beads A to B-1) [default: all].
    #[arg(long, value_name = "A:B")]
    beads: Option<BeadRange>,
    /// Time window T0:T1 (in the axis units) [default: the whole run].
    #[arg(long)]
    t: Option<TimeRange>,
    /// Take every K-th frame of the window.
    #[arg(long, value_name = "K", default_value_t = 1,
          value_parser = clap::value_parser!(u32).range(1..))]
    every: u32,
    /// At most N frames, spread evenly over the run (first and last kept).
    #[arg(long, value_name = "N", default_value_t = animate::DEFAULT_FRAMES_MAX as u32,
          value_parser = clap::value_parser!(u32).range(1..))]
    frames_max: u32,
    /// Frames per second (1..=50).
    #[arg(long, default_value_t = animate::DEFAULT_FPS)]
    fps: u32,
    #[command(flatten)]
    units: UnitsArg,
    /// Output: X.gif (a name without extension gets .gif; .mp4 is not supported)
    /// [default: <input stem>_animate.gif in the current directory].
    #[arg(long)]
    out: Option<PathBuf>,
    /// Image width in pixels.
    #[arg(long, default_value_t = 900)]
    width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 650)]
    height: u32,
    /// Title (each frame appends its time).
    #[arg(long)]
    title: Option<String>,
    /// x axis label (replaces the default).
    #[arg(long)]
    xlabel: Option<String>,
    /// y axis label (replaces the default, units included).
    #[arg(long)]
    ylabel: Option<String>,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
enum FieldArg {
    /// Velocity.
    V,
    /// Displacement.
    U,
    /// Kinetic energy m v^2 / 2.
    Energy,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
enum ScaleArg {
    Linear,
    Log,
}

#[derive(ValueEnum, Clone, Copy, Debug, Default)]
enum UnitsValue {
    /// The simulation's computer units.
    #[default]
    Computer,
    /// SI (s, m/s); physical scenes only.
    Si,
}

/// `--units` of the snapshot plots.
#[derive(clap::Args, Debug)]
struct UnitsArg {
    /// Axis units: computer (default) or si (physical scenes: s, m/s).
    #[arg(long, value_enum, default_value = "computer")]
    units: UnitsValue,
}

impl UnitsArg {
    fn get(&self) -> Units {
        match self.units {
            UnitsValue::Computer => Units::Computer,
            UnitsValue::Si => Units::Si,
        }
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
        super::files::check_not_input(&f, "--out", &[(kind, input.to_path_buf())])?;
    }
    Ok(())
}

/// Runs `beadchain plot`; returns the exit code.
pub fn cmd_plot(args: PlotArgs) -> Result<i32> {
    match args.kind {
        PlotKind::Spacetime {
            snapshots,
            beads,
            t,
            scale,
            cmap,
            units,
            out,
        } => {
            let opts = spacetime_options(beads, t, scale, &cmap, &units, &out)?;
            spacetime(&snapshots, &opts, &out)
        }
        PlotKind::Profile {
            snapshot,
            times,
            beads,
            units,
            out,
        } => {
            let opts = profile_options(times, beads, &units, &out)?;
            chart(&snapshot, "profile", &out, |s| profile::profile(s, &opts))
        }
        PlotKind::Trace {
            snapshot,
            beads,
            t,
            units,
            out,
        } => {
            let mut opts = trace_options(t, &units, &out)?;
            chart(&snapshot, "trace", &out, |s| {
                opts.beads = plot::bead_list(&beads, s.header().n_beads as usize)?;
                trace::trace(s, &opts)
            })
        }
        PlotKind::Energy {
            snapshot,
            from,
            to,
            log,
            interface,
            units,
            out,
        } => {
            let opts = EnergyOptions {
                from,
                to,
                log,
                interface,
                units: units.get(),
                size: out.size()?,
            };
            energy_plot(&snapshot, &opts, &out)
        }
        PlotKind::Animate(a) => animate_plot(a),
        PlotKind::Dispersion(a) => super::dispersion::cmd_dispersion(a),
        PlotKind::Map {
            csv,
            x,
            y,
            z,
            log_z,
            contour,
            cmap,
            zlabel,
            out,
        } => {
            let opts = map_options([x, y, z], log_z, contour, &cmap, &out)?;
            map(&csv, &opts, zlabel, &out)
        }
    }
}

/// Options of `plot map` (`[x, y, z]`: the column names).
fn map_options(
    [x, y, z]: [String; 3],
    log_z: bool,
    contour: Option<f64>,
    cmap: &str,
    out: &Out,
) -> Result<MapOptions> {
    Ok(MapOptions {
        x,
        y,
        z,
        log_z,
        contour,
        cmap: Cmap::parse(cmap)?,
        size: out.size()?,
    })
}

/// Options of `plot spacetime`.
fn spacetime_options(
    beads: Option<BeadRange>,
    t: Option<TimeRange>,
    scale: ScaleArg,
    cmap: &str,
    units: &UnitsArg,
    out: &Out,
) -> Result<SpacetimeOptions> {
    Ok(SpacetimeOptions {
        beads: beads.unwrap_or_default(),
        t: t.unwrap_or_default(),
        scale: match scale {
            ScaleArg::Linear => Scale::Linear,
            ScaleArg::Log => Scale::Log,
        },
        units: units.get(),
        cmap: Cmap::parse(cmap)?,
        colorbar: true,
        size: out.size()?,
    })
}

/// Options of `plot profile`.
fn profile_options(
    times: Vec<f64>,
    beads: Option<BeadRange>,
    units: &UnitsArg,
    out: &Out,
) -> Result<plot::ProfileOptions> {
    Ok(plot::ProfileOptions {
        times,
        beads: beads.unwrap_or_default(),
        units: units.get(),
        size: out.size()?,
    })
}

/// Options of `plot trace` (the beads are resolved against the snapshot).
fn trace_options(t: Option<TimeRange>, units: &UnitsArg, out: &Out) -> Result<plot::TraceOptions> {
    Ok(plot::TraceOptions {
        beads: Vec::new(),
        t: t.unwrap_or_default(),
        units: units.get(),
        size: out.size()?,
    })
}

/// `plot profile` / `plot trace`: the line chart `build` makes of the snapshot, texts replaced.
fn chart<F>(snapshot: &Path, kind: &str, out: &Out, build: F) -> Result<i32>
where
    F: FnOnce(&Snapshot) -> Result<plot::lines::LineChart, plot::PlotError>,
{
    let path = out.path(snapshot, kind);
    check_out(&path, "snapshot", snapshot)?;
    let snap = open(snapshot)?;
    let mut fig = build(&snap)?;
    out.labels()
        .apply(&mut fig.title, &mut fig.x_desc, &mut fig.y_desc);
    written(&fig, &path)
}

/// `plot map`: the CSV's heatmap, its skipped rows warned about.
fn map(csv: &Path, opts: &MapOptions, zlabel: Option<String>, out: &Out) -> Result<i32> {
    let path = out.path(csv, "map");
    check_out(&path, "CSV file", csv)?;
    let mut fig = Map::from_csv(csv, opts)?;
    for w in &fig.warnings {
        eprintln!("beadchain: warning: {w}");
    }
    out.labels()
        .apply(&mut fig.title, &mut fig.x_desc, &mut fig.y_desc);
    if let Some(z) = zlabel {
        fig.z_desc = z;
    }
    written(&fig, &path)
}

/// `plot spacetime`: one map, or side-by-side panels for several snapshots.
fn spacetime(snapshots: &[PathBuf], opts: &SpacetimeOptions, out: &Out) -> Result<i32> {
    let first = &snapshots[0];
    let path = out.path(first, "spacetime");
    for s in snapshots {
        check_out(&path, "snapshot", s)?;
    }
    let snaps = snapshots
        .iter()
        .map(|s| open(s))
        .collect::<Result<Vec<_>>>()?;
    let labels = out.labels();
    if snaps.len() == 1 {
        let mut fig = Spacetime::from_snapshot(&snaps[0], opts)?;
        labels.apply(&mut fig.title, &mut fig.x_desc, &mut fig.y_desc);
        return written(&fig, &path);
    }
    let mut fig = Panels::from_snapshots(&snaps, opts, labels.title.clone())?;
    for p in &mut fig.panels {
        let mut title = p.title.clone();
        labels.apply(&mut title, &mut p.x_desc, &mut p.y_desc);
    }
    written(&fig, &path)
}

/// `plot energy`: the chart, and each fit printed (or why there is none).
fn energy_plot(snapshot: &Path, opts: &EnergyOptions, out: &Out) -> Result<i32> {
    let path = out.path(snapshot, "energy");
    check_out(&path, "snapshot", snapshot)?;
    let snap = open(snapshot)?;
    let mut fig = energy::energy(&snap, opts)?;
    for s in &fig.fits {
        match &s.fit {
            Ok(f) => outln!(
                "decay fit over positions {}: gamma = {:.6e} +- {:.3e} ({} points, R^2 = {:.4})",
                s.range,
                f.gamma,
                f.gamma_stderr,
                f.n,
                f.r2
            ),
            Err(e) => eprintln!(
                "beadchain: warning: no exponential fit over positions {}: {e}",
                s.range
            ),
        }
    }
    let c = &mut fig.chart;
    out.labels()
        .apply(&mut c.title, &mut c.x_desc, &mut c.y_desc);
    written(&fig, &path)
}

/// `plot animate`: the GIF of the chosen frames, written atomically.
fn animate_plot(a: AnimateArgs) -> Result<i32> {
    let opts = AnimateOptions {
        field: match a.field {
            FieldArg::V => Field::Velocity,
            FieldArg::U => Field::Displacement,
            FieldArg::Energy => Field::Energy,
        },
        beads: a.beads.clone().unwrap_or_default(),
        t: a.t.unwrap_or_default(),
        every: a.every as usize,
        frames_max: a.frames_max as usize,
        fps: a.fps,
        units: a.units.get(),
        size: size_of(a.width, a.height)?,
    };
    let out = a.out.clone().unwrap_or_else(|| {
        let stem = a
            .snapshot
            .file_stem()
            .map_or("plot".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}_animate.gif"))
    });
    let path = animate::gif_path(&out)?;
    super::files::check_not_input(&path, "--out", &[("snapshot", a.snapshot.clone())])?;
    let snap = open(&a.snapshot)?;
    let mut anim = Animation::from_snapshot(&snap, &opts)?;
    let labels = Labels {
        title: a.title,
        xlabel: a.xlabel,
        ylabel: a.ylabel,
    };
    labels.apply(&mut anim.title, &mut anim.x_desc, &mut anim.y_desc);
    let bytes = anim.encode_gif()?;
    super::files::clean_stale_temps(&path);
    beadchain::snapshot::write_atomically(&path, |w| {
        w.write_all(&bytes)
            .map_err(beadchain::snapshot::SnapshotError::Output)
    })?;
    if !font::font_available() {
        eprintln!(
            "beadchain: warning: no font file found (BEADCHAIN_FONT, {}): the plot has no text",
            font::FONT_CANDIDATES.join(", ")
        );
    }
    outln!("wrote {} ({} frames)", path.display(), anim.frames.len());
    Ok(0)
}
