//! `beadchain validate --quick`: the paper's key numbers, reduced (library: [`beadchain::experiments::quick`]).

use anyhow::{Context, Result};
use std::path::PathBuf;

/// Arguments of `beadchain validate`.
#[derive(clap::Args, Debug)]
pub struct ValidateArgs {
    /// Run the reduced checks (a few seconds); the full report is
    /// `cargo bench --bench paper_validation -- all` (validation/REPORT.md).
    #[arg(long)]
    pub quick: bool,
    /// Directory for `quick.md` (the table; deterministic).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs `beadchain validate --quick`; exit code 1 when a check is outside its range.
pub fn cmd_validate(args: ValidateArgs) -> Result<i32> {
    use beadchain::experiments::quick::{checks_markdown, quick_checks};
    if !args.quick {
        anyhow::bail!(
            "only --quick is implemented here; the full report: cargo bench --bench paper_validation -- all (see validation/REPORT.md)"
        );
    }
    if let Some(dir) = args.out.as_ref().filter(|d| d.exists() && !d.is_dir()) {
        // before the checks run (a minute), not after
        anyhow::bail!(
            "{}: --out: is a file; give a directory (validate writes quick.md into it)",
            dir.display()
        );
    }
    let t0 = std::time::Instant::now();
    let checks = quick_checks(false)?;
    let table = checks_markdown(&checks);
    out!("{table}");
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir).with_context(|| format!("{}", dir.display()))?;
        let path = dir.join("quick.md");
        // atomically, and never through a symbolic link (the rule of every output)
        super::files::clean_stale_temps(&path);
        beadchain::snapshot::write_atomically(&path, |w| {
            w.write_all(table.as_bytes())
                .map_err(beadchain::snapshot::SnapshotError::Output)
        })?;
        outln!("wrote {}", path.display());
    }
    let failed = checks.iter().filter(|c| !c.pass()).count();
    outln!(
        "{} checks, {failed} outside their range, {:.1} s",
        checks.len(),
        t0.elapsed().as_secs_f64()
    );
    Ok(i32::from(failed > 0))
}
