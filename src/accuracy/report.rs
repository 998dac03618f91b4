//! Output of the work-precision study: the CSV ([`super::CSV_HEADER`]), the table printed by
//! `beadchain accuracy`, and the files written into the output directory (CSV, SVG and PNG
//! plots of [`super::plot`]).

use super::{plot, AccuracyError, AccuracyReport, CSV_HEADER};
use crate::names::Named;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The CSV text (header [`CSV_HEADER`], one line per row; numbers in shortest round-trip form).
pub fn to_csv(report: &AccuracyReport) -> String {
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for r in &report.rows {
        let dt = r.verlet_dt.map(|x| x.to_string()).unwrap_or_default();
        let status = match &r.failure {
            None => "ok".to_string(),
            // Keep the CSV one field: no commas, quotes or newlines in the message.
            Some(m) => format!("failed: {}", m.replace([',', '"', '\n'], " ")),
        };
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            r.engine.name(),
            r.method.name(),
            r.rtol,
            r.atol,
            dt,
            status,
            r.is_reference,
            r.err_u,
            r.err_v,
            r.error,
            r.energy_error,
            r.ke_error,
            r.wall_seconds,
            r.steps,
            r.rejected,
            r.rhs_evals,
            r.events,
            r.bead_steps
        );
    }
    s
}

/// The table printed by `beadchain accuracy`.
pub fn format_table(report: &AccuracyReport) -> String {
    let mut s = String::new();
    let rf = &report.reference;
    let _ = writeln!(
        s,
        "{}: {} beads, until {}, tau = L/V = {:.4}; reference dense radau5 rtol {:e} ({:.3} s); \
         check vs rtol {:e}: err_u {:.2e}, err_v {:.2e}",
        report.scene,
        report.beads,
        report.until,
        report.tau,
        rf.rtol,
        rf.wall_seconds,
        rf.check_rtol,
        rf.check_err_u,
        rf.check_err_v
    );
    let _ = writeln!(
        s,
        "{:<7} {:<7} {:>9} {:>9} {:>9} {:>9} {:>9} {:>10} {:>9} {:>8} {:>12}",
        "engine",
        "method",
        "rtol/dt",
        "err_u",
        "err_v",
        "energy",
        "KE",
        "wall [s]",
        "steps",
        "events",
        "bead-steps"
    );
    for r in &report.rows {
        let knob = match r.verlet_dt {
            Some(_) => format!("{}τ", r.rtol),
            None => format!("{:e}", r.rtol),
        };
        if let Some(f) = &r.failure {
            let _ = writeln!(
                s,
                "{:<7} {:<7} {:>9} FAILED: {f}",
                r.engine.name(),
                r.method.name(),
                knob
            );
            continue;
        }
        let _ = writeln!(
            s,
            "{:<7} {:<7} {:>9} {:>9.2e} {:>9.2e} {:>9.2e} {} {:>10.4} {:>9} {:>8} {:>12}{}",
            r.engine.name(),
            r.method.name(),
            knob,
            r.err_u,
            r.err_v,
            r.energy_error,
            cell(r.ke_error, 9),
            r.wall_seconds,
            r.steps,
            r.events,
            r.bead_steps,
            if r.is_reference { "  (reference)" } else { "" }
        );
    }
    for n in &report.notes {
        let _ = writeln!(s, "note: {n}");
    }
    s
}

/// `x` for a table or CSV cell: empty / "n/a" when NaN.
fn cell(x: f64, width: usize) -> String {
    if x.is_nan() {
        format!("{:>width$}", "n/a")
    } else {
        format!("{:>width$.2e}", x)
    }
}

/// Writes `bytes` to `path` atomically ([`crate::snapshot::write_atomically`]: a temporary
/// sibling, fsynced and renamed).
fn write_file(path: &Path, bytes: &[u8]) -> Result<(), AccuracyError> {
    crate::snapshot::write_atomically(path, |w| {
        w.write_all(bytes)
            .map_err(crate::snapshot::SnapshotError::Output)
    })
    .map_err(|e| AccuracyError::Io {
        path: path.to_path_buf(),
        source: match e {
            crate::snapshot::SnapshotError::Io { source, .. } => source,
            other => std::io::Error::other(other.to_string()),
        },
    })
}

/// The files of the study in `dir`: CSV, SVG and PNG.
pub(super) fn output_paths(dir: &Path) -> [PathBuf; 3] {
    ["accuracy.csv", "accuracy.svg", "accuracy.png"].map(|f| dir.join(f))
}

/// Each output file can be replaced (not a directory, not a symbolic link): checked before the
/// study runs and again before anything is written.
pub(super) fn check_outputs(dir: &Path) -> Result<(), AccuracyError> {
    let refused = |p: &Path, why: String| AccuracyError::Io {
        path: p.to_path_buf(),
        source: std::io::Error::other(why),
    };
    // the directory itself: absent (made), or a directory (a file or a dangling link is not)
    if std::fs::symlink_metadata(dir).is_ok() && !dir.is_dir() {
        return Err(refused(
            dir,
            "the output directory is not a directory".into(),
        ));
    }
    for p in output_paths(dir) {
        if let Err(crate::files::OutputError::Symlink { target, .. }) =
            crate::files::classify_output(&p)
        {
            return Err(refused(
                &p,
                format!(
                    "is a symbolic link (to {}); refusing to replace it",
                    target.display()
                ),
            ));
        }
        if p.is_dir() {
            return Err(refused(&p, "is a directory".into()));
        }
    }
    Ok(())
}

/// Writes the CSV and the plots into `dir` (created if needed): all rendered first, then each
/// written atomically; when one cannot be written, the ones written before it are put back as
/// they were (removed where they did not exist), so a failed study leaves no output of its own.
pub(super) fn write_outputs(report: &mut AccuracyReport, dir: &Path) -> Result<(), AccuracyError> {
    std::fs::create_dir_all(dir).map_err(|source| AccuracyError::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    check_outputs(dir)?;
    let paths = output_paths(dir);
    let (svg, png, with_text) = plot::render_plots(report).map_err(|msg| AccuracyError::Plot {
        path: paths[1].clone(),
        msg,
    })?;
    let contents = [to_csv(report).into_bytes(), svg.into_bytes(), png];
    let before: Vec<Option<Vec<u8>>> = paths.iter().map(|p| std::fs::read(p).ok()).collect();
    for (k, (p, bytes)) in paths.iter().zip(&contents).enumerate() {
        if let Err(e) = write_file(p, bytes) {
            for (q, old) in paths.iter().zip(&before).take(k) {
                // best effort: the error above is the one to report
                let _ = match old {
                    Some(b) => write_file(q, b),
                    None => std::fs::remove_file(q).map_err(|source| AccuracyError::Io {
                        path: q.clone(),
                        source,
                    }),
                };
            }
            return Err(e);
        }
    }
    if !with_text {
        report.notes.push(format!(
            "no font file found (BEADCHAIN_FONT, {}): the plots are drawn without text",
            plot::FONT_CANDIDATES.join(", ")
        ));
    }
    report.files.extend(paths);
    Ok(())
}
