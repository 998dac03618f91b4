//! `beadchain modes SCENE --snapshot RUN.snap [--energies E.csv|E.npz]`: the energy of each
//! linear mode in every frame of a run (modal energy analysis, FPUT-style; library:
//! [`beadchain::studies::modal`], whose docs give `q_j = x_jᵀ M (u − u*)`,
//! `E_j = ½ (q̇_j² + ω_j² q_j²)` and Parseval's identity).

use anyhow::{bail, Result};
use beadchain::analysis::modal::{project_snapshot, ModalEnergies};
use beadchain::scene::Scene;
use beadchain::snapshot::Snapshot;
use beadchain::studies::modal::ModalBasis;
use std::io::Write;
use std::path::Path;

/// Format of the `--energies` file, from its extension.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EnergiesFormat {
    /// One row per frame: `t,E_<index>…,harmonic,energy`.
    Csv,
    /// Arrays `t` (F), `index` (M), `omega` (M), `energy` (F × M), `harmonic` (F), `total` (F).
    Npz,
}

/// The format of `--energies PATH` (`.csv` or `.npz`), checked before any work.
pub fn energies_format(p: &Path) -> Result<EnergiesFormat> {
    match p.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("csv") => Ok(EnergiesFormat::Csv),
        Some(e) if e.eq_ignore_ascii_case("npz") => Ok(EnergiesFormat::Npz),
        _ => bail!(
            "{}: --energies: expected a .csv or .npz file name",
            p.display()
        ),
    }
}

/// Reads every frame of `path` (every bead, both fields; the scene's bead count) and projects
/// it on `basis` (the reader's warnings on standard error).
pub fn project_run(scene: &Scene, basis: &ModalBasis, path: &Path) -> Result<ModalEnergies> {
    let snap = Snapshot::open(path)?;
    for w in snap.warnings() {
        eprintln!("beadchain: warning: {w}");
    }
    Ok(project_snapshot(&snap, &scene.chain, basis)?)
}

/// The summary lines: frames, harmonic and full energy at the first and last frame, and the
/// modes that carry the most energy there.
pub fn summary(path: &Path, basis: &ModalBasis, e: &ModalEnergies) -> Result<()> {
    let frames = e.t.len();
    outln!(
        "modal energies of {}: {frames} frames from t = {} to {}, {} modes",
        path.display(),
        e.t.first().copied().unwrap_or(0.0),
        e.t.last().copied().unwrap_or(0.0),
        basis.modes()
    );
    let m = basis.modes();
    for (label, k) in [("first", 0), ("last", frames.saturating_sub(1))] {
        if frames == 0 || m == 0 {
            break;
        }
        let row = e.row(k);
        let sum: f64 = row.iter().sum();
        let mut order: Vec<usize> = (0..m).collect();
        order.sort_by(|&a, &b| row[b].total_cmp(&row[a]));
        let top: Vec<String> = order
            .iter()
            .take(3)
            .map(|&j| {
                let frac = if sum > 0.0 { row[j] / sum } else { 0.0 };
                format!("{} ({frac:.6})", basis.index[j])
            })
            .collect();
        outln!(
            "{label} frame (t = {}): sum of E_j {sum:.9e}, harmonic {:.9e}, energy above the state {:.9e}; most energetic modes (fraction): {}",
            e.t[k],
            e.harmonic[k],
            e.total[k],
            top.join(", ")
        );
    }
    Ok(())
}

/// Writes the energies as CSV or `.npz` (atomically: a temporary file renamed at the end).
pub fn write(
    p: &Path,
    format: EnergiesFormat,
    basis: &ModalBasis,
    omega: &[f64],
    e: &ModalEnergies,
) -> Result<()> {
    super::files::clean_stale_temps(p);
    let m = basis.modes();
    match format {
        EnergiesFormat::Csv => beadchain::snapshot::write_atomically(p, |w| {
            write_csv(w, basis, e).map_err(|err| beadchain::snapshot::SnapshotError::Io {
                path: p.to_path_buf(),
                action: "write".to_string(),
                source: err,
            })
        })?,
        EnergiesFormat::Npz => {
            let (f, mu) = (e.t.len() as u64, m as u64);
            let index: Vec<f64> = basis.index.iter().map(|&i| i as f64).collect();
            let arrays: Vec<(&str, Vec<u64>, &[f64])> = vec![
                ("t", vec![f], &e.t),
                ("index", vec![mu], &index),
                ("omega", vec![mu], omega),
                ("energy", vec![f, mu], &e.energy),
                ("harmonic", vec![f], &e.harmonic),
                ("total", vec![f], &e.total),
            ];
            beadchain::snapshot::write_atomically(p, |w| {
                beadchain::export::npz::write_npz_arrays(&arrays, w)
            })?
        }
    }
    Ok(())
}

/// `t,E_<index>…,harmonic,energy`, one row per frame, shortest round-trip decimals.
fn write_csv(w: &mut dyn Write, basis: &ModalBasis, e: &ModalEnergies) -> std::io::Result<()> {
    let mut w = std::io::BufWriter::with_capacity(1 << 16, w);
    w.write_all(b"t")?;
    for j in &basis.index {
        write!(w, ",E_{j}")?;
    }
    writeln!(w, ",harmonic,energy")?;
    for k in 0..e.t.len() {
        write!(w, "{:e}", e.t[k])?;
        for x in e.row(k) {
            write!(w, ",{x:e}")?;
        }
        writeln!(w, ",{:e},{:e}", e.harmonic[k], e.total[k])?;
    }
    w.flush()
}
