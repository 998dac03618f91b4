//! Output options and figure writing shared by the `plot` subcommands (`--out`, size, labels).

use anyhow::Result;
use beadchain::plot::{self, font, Labels};
use std::path::{Path, PathBuf};

/// Output options shared by every plot.
#[derive(clap::Args, Debug)]
pub(super) struct Out {
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
    /// Figure title (several spacetime snapshots: the title above all panels).
    #[arg(long)]
    title: Option<String>,
    /// x axis label (replaces the default, units included).
    #[arg(long)]
    xlabel: Option<String>,
    /// y axis label (replaces the default, units included).
    #[arg(long)]
    ylabel: Option<String>,
}

/// The checked `--width`/`--height` of a plot.
pub(super) fn size_of(width: u32, height: u32) -> Result<(u32, u32)> {
    if !(300..=8000).contains(&width) || !(200..=8000).contains(&height) {
        anyhow::bail!(
            "--width {width} --height {height}: the size must be 300..=8000 x 200..=8000 pixels"
        );
    }
    Ok((width, height))
}

impl Out {
    pub(super) fn size(&self) -> Result<(u32, u32)> {
        size_of(self.width, self.height)
    }
    pub(super) fn labels(&self) -> Labels {
        Labels {
            title: self.title.clone(),
            xlabel: self.xlabel.clone(),
            ylabel: self.ylabel.clone(),
        }
    }
    pub(super) fn path(&self, input: &Path, kind: &str) -> PathBuf {
        self.out.clone().unwrap_or_else(|| {
            let stem = input
                .file_stem()
                .map_or("plot".into(), |s| s.to_string_lossy().into_owned());
            PathBuf::from(format!("{stem}_{kind}"))
        })
    }
}

pub(super) fn written<F: plot::Figure>(fig: &F, out: &Path) -> Result<i32> {
    // the output rule is checked before any work is reported
    for (f, _) in plot::output_paths(out)? {
        super::files::clean_stale_temps(&f);
    }
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
