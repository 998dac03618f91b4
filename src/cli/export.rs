//! `beadchain export`: frames (long or wide layout) or the event log of a snapshot, as CSV,
//! NPY or NPZ (library: [`beadchain::export`], wide layouts in [`beadchain::export::wide`]).
//! The format comes from `--format`, else the `--out` extension; the output is written
//! atomically (never half-written).

use anyhow::{bail, Context, Result};
use beadchain::export::{self, ExportUnits, FrameSel};
use beadchain::snapshot::Snapshot;
use clap::ValueEnum;
use std::io::Write;
use std::path::{Path, PathBuf};

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq)]
pub enum Format {
    Csv,
    Npy,
    /// Zip of NPY arrays (wide layout only).
    Npz,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq)]
pub enum Layout {
    /// One row per bead and frame: `frame, t, bead, u, v`.
    Long,
    /// One row per frame: `t (F,)`, `u (F,N)`, `v (F,N)`.
    Wide,
}

#[derive(clap::Args, Debug)]
pub struct ExportArgs {
    /// Snapshot file.
    file: PathBuf,
    /// Output format [default: from the --out extension (.csv, .npy, .npz), else csv].
    #[arg(long, value_enum)]
    format: Option<Format>,
    /// Layout [default: long; wide for .npz]. long: one row per bead and frame
    /// (`frame,t,bead,u,v`). wide: one row per frame; .npz holds arrays t (F,), u (F,N),
    /// v (F,N), mass (N,), exponent, prefactor, precompression (N-1,) for `numpy.load`; .npy
    /// is one (F, 2N+1) array [t | u | v]: a[:,0], a[:,1:N+1], a[:,N+1:]; .csv has columns
    /// t,u0..,v0...
    #[arg(long, value_enum)]
    layout: Option<Layout>,
    /// Frames: first, last, all, or an index K.
    #[arg(long, default_value = "all")]
    frame: String,
    /// Export the event log (CSV) instead of frames.
    #[arg(long)]
    events: bool,
    /// Output path [default: standard output for CSV; required for NPY/NPZ; `-`: standard output].
    #[arg(long)]
    out: Option<PathBuf>,
    /// Units of the numbers: the snapshot's computer units, or SI for a physical scene
    /// (t in s, u in m, v in m/s; .npz mass in kg, prefactor in J/m^n).
    #[arg(long, value_enum, default_value = "computer")]
    units: UnitsOpt,
}

/// `--units` of `export`.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq)]
pub enum UnitsOpt {
    /// The simulation's computer units (the snapshot's numbers, bit for bit).
    Computer,
    /// SI (physical scenes only).
    Si,
}

/// The export's format (`--format`, else the `--out` extension, else CSV) and layout
/// (`--layout`, else wide for `.npz` and long otherwise).
fn export_kind(a: &ExportArgs) -> Result<(Format, Layout)> {
    let ext = a
        .out
        .as_deref()
        .and_then(|p| p.extension())
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    let format = a.format.unwrap_or(match ext.as_deref() {
        Some("npy") => Format::Npy,
        Some("npz") => Format::Npz,
        _ => Format::Csv,
    });
    let layout = a.layout.unwrap_or(if format == Format::Npz {
        Layout::Wide
    } else {
        Layout::Long
    });
    if a.events {
        check_events_options(a, format)?;
    }
    if format == Format::Npz && layout == Layout::Long && !a.events {
        bail!("--layout long: the npz format holds the wide layout only (arrays t, u, v and the chain's); use --layout wide, or npy/csv for the long table");
    }
    Ok((format, layout))
}

/// `--events` writes the whole event log as CSV: a binary format (`--format`, or the `--out`
/// extension), a `--layout` or a `--frame` is refused, not ignored (CSV text was written into
/// `ev.npy`, and `--frame 999` passed).
fn check_events_options(a: &ExportArgs, format: Format) -> Result<()> {
    if format != Format::Csv {
        let by = match a.format {
            Some(_) => "--format".to_string(),
            None => format!(
                "the --out extension of {}",
                a.out.as_deref().unwrap_or(Path::new("")).display()
            ),
        };
        bail!("--events: the event log is written as CSV only, not {} ({by}); write it to a .csv file or standard output", if format == Format::Npy { "npy" } else { "npz" });
    }
    if a.layout.is_some() {
        bail!("--events: --layout applies to frames, not to the event log (one row per event)");
    }
    if a.frame != "all" {
        bail!(
            "--events: --frame applies to frames; the event log is exported whole (--frame {})",
            a.frame
        );
    }
    Ok(())
}

pub fn cmd_export(a: ExportArgs) -> Result<i32> {
    let (format, layout) = export_kind(&a)?;
    let snap = Snapshot::open(&a.file)?;
    for w in snap.warnings() {
        eprintln!("beadchain: warning: {w}");
    }
    let units = match a.units {
        UnitsOpt::Computer => ExportUnits::computer(),
        UnitsOpt::Si => ExportUnits::si_of(&snap.header().scene)
            .map_err(|e| anyhow::anyhow!("{}: {e}", a.file.display()))?,
    };
    let sel: FrameSel = a
        .frame
        .parse()
        .map_err(|e| anyhow::anyhow!("--frame {}: {e}", a.frame))?;
    let exported_by = super::common::command_line();
    let write = |out: &mut dyn Write| -> Result<(), beadchain::snapshot::SnapshotError> {
        use beadchain::export::wide;
        match (a.events, format, layout) {
            (true, _, _) => export::export_events_csv(&snap, &units, out),
            (_, Format::Csv, Layout::Long) => export::export_csv(&snap, sel, &units, out),
            (_, Format::Npy, Layout::Long) => export::export_npy(&snap, sel, &units, out),
            (_, Format::Csv, Layout::Wide) => wide::export_csv_wide(&snap, sel, &units, out),
            (_, Format::Npy, Layout::Wide) => wide::export_npy_wide(&snap, sel, &units, out),
            (_, Format::Npz, _) => wide::export_npz(&snap, sel, &units, &exported_by, out),
        }
    };
    let to_stdout = a.out.as_deref().is_none_or(|p| p.as_os_str() == "-");
    if let Some(p) = a.out.as_deref().filter(|_| !to_stdout) {
        super::files::check_not_input(p, "--out", &[("snapshot", a.file.clone())])?;
    }
    if format == Format::Npz && !a.events {
        let frames = sel.range(&snap)?.len() as u64;
        let bytes = export::wide::npz_bytes_of(frames, snap.header().n_beads, snap.selection());
        if bytes > export::npz::ZIP_LIMIT {
            bail!("{}: --format npz: the archive would be {bytes} bytes, beyond the 4 GiB of a zip without ZIP64; select fewer frames (--frame) or write .npy", a.file.display());
        }
    }
    match &a.out {
        Some(p) if !to_stdout => {
            super::files::clean_stale_temps(p);
            beadchain::snapshot::write_atomically(p, write)?
        }
        _ => {
            if format != Format::Csv && !a.events && a.out.is_none() {
                bail!("--format {} needs --out PATH (binary output is not written to a terminal; `--out -` writes it to standard output)", if format == Format::Npy { "npy" } else { "npz" });
            }
            // Validate the selection first so an error never leaves partial output.
            sel.range(&snap)?;
            let stdout = std::io::stdout();
            let mut lock = std::io::BufWriter::new(stdout.lock());
            write(&mut lock)?;
            lock.flush().context("writing to standard output")?;
        }
    }
    Ok(0)
}

/// `beadchain inspect FILE`: the report, then every frame's checksum verified; a damaged frame
/// makes it exit 2 with one line naming the first damaged frame.
pub fn cmd_inspect(file: &std::path::Path) -> Result<i32> {
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
