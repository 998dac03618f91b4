//! Result files: the spec line and column header, row fields, reading a (possibly interrupted)
//! result file, atomic writes, and merging shard files.
//!
//! Layout of a finished result `OUT` (and of merged shards): line 1 the column names, then one
//! row per run (RFC 4180 quoting: a field with `,` or `"` is quoted, `"` doubled; no field holds
//! a newline), so `pandas.read_csv(OUT)` needs no options. The spec line
//! `# beadchain sweep spec=HASH runs=N` (what `merge` and resuming check) is in the sidecar
//! `OUT.meta`, followed by the provenance line `# beadchain VERSION commit COMMIT` (the build
//! that wrote it; informative only, never checked) and the content key of every row (`# run I content=KEY`: what a rerun
//! matches to skip the runs whose results are already there). The unfinished `OUT.partial`
//! keeps the spec line as its line 1.

use super::{SweepError, SweepSpec};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// The first line of a result file (without newline).
pub fn spec_line(hash: u64, runs: usize) -> String {
    format!("# beadchain sweep spec={hash:016x} runs={runs}")
}

/// The fixed result columns after the parameters.
pub const FIXED: &[&str] = &["status", "t_end", "energy_error", "steps", "events"];

/// All column names of a sweep's result file.
pub fn columns(spec: &SweepSpec, timing: bool) -> Vec<String> {
    let mut c = vec!["run".to_string()];
    c.extend(spec.param_columns());
    c.extend(FIXED.iter().map(|s| s.to_string()));
    let m = &spec.measure;
    if m.interface.is_some() {
        c.push("left_fraction".into());
    }
    if m.decay.is_some() {
        c.push("gamma".into());
        c.push("gamma_se".into());
    }
    if m.impurity.is_some() {
        c.push("v_ratio".into());
    }
    if m.fragments.is_some() {
        c.push("fragments".into());
    }
    if timing {
        c.push("wall_seconds".into());
    }
    c
}

/// A CSV field, quoted when it holds `,` or `"`; control characters become spaces.
pub fn field(s: &str) -> String {
    let s: String = s
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    if s.contains(',') || s.contains('"') {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s
    }
}

/// Why a CSV line cannot be split into fields.
#[derive(Debug, thiserror::Error)]
pub enum FieldsError {
    /// An odd number of quotes.
    #[error("unterminated quoted field")]
    Unterminated,
    /// The CSV reader's error.
    #[error(transparent)]
    Csv(::csv::Error),
}

/// Splits one CSV line into fields (inverse of [`field`]), by the `csv` crate's RFC 4180
/// reader, as [`crate::plot::csvtable`] reads tables. A quote left open is an error (the reader
/// itself would take the rest of the line into the field).
pub fn split_fields(line: &str) -> Result<Vec<String>, FieldsError> {
    if line.bytes().filter(|&b| b == b'"').count() % 2 == 1 {
        return Err(FieldsError::Unterminated);
    }
    let mut reader = ::csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(line.as_bytes());
    let mut record = ::csv::StringRecord::new();
    match reader.read_record(&mut record) {
        Ok(true) => Ok(record.iter().map(String::from).collect()),
        Ok(false) => Ok(vec![String::new()]),
        Err(e) => Err(FieldsError::Csv(e)),
    }
}

/// The sidecar of a result file holding its spec line: `OUT.meta`.
pub fn meta_path(out: &Path) -> PathBuf {
    let mut s = out.as_os_str().to_owned();
    s.push(".meta");
    PathBuf::from(s)
}

/// A spec line without its ` inputs=HASH` (the sweep file and scene part alone).
pub fn spec_part(line: &str) -> &str {
    line.split(" inputs=").next().unwrap_or("")
}

/// The ` inputs=HASH` of a spec line (none in results of builds before 2026-11-29).
pub fn inputs_part(line: &str) -> Option<&str> {
    line.split(" inputs=").nth(1)
}

/// The sidecar `OUT.meta`: the spec line, the [provenance line](provenance_line), then one line
/// `# run I content=KEY` per row (KEY: the run's content key,
/// [`super::SweepSpec::content_key`], 16 hex digits), in run order.
pub fn meta_text(spec_line: &str, keys: &BTreeMap<usize, u64>) -> String {
    let mut s = String::with_capacity(spec_line.len() + 100 + 40 * keys.len());
    s.push_str(spec_line);
    s.push('\n');
    s.push_str(&provenance_line());
    s.push('\n');
    for (i, k) in keys {
        s.push_str(&format!("{CONTENT_TAG}{i} content={k:016x}\n"));
    }
    s
}

/// Line 2 of `OUT.meta`: `# beadchain VERSION commit COMMIT` of the build that wrote it
/// (`# beadchain VERSION` with `BEADCHAIN_NO_BUILD_COMMIT=1`). Only informative: merging and
/// resuming read the spec line and the content keys, so a sweep resumed or merged by another
/// build is not refused.
pub fn provenance_line() -> String {
    let v = crate::provenance::VERSION;
    match crate::provenance::recorded_commit() {
        Some(c) => format!("# beadchain {v} commit {c}"),
        None => format!("# beadchain {v}"),
    }
}

/// Start of a content-key line of `OUT.meta`.
const CONTENT_TAG: &str = "# run ";

/// The content keys of a finished result's rows, from its sidecar `OUT.meta` (empty when it has
/// none: a result of an older beadchain, or no sidecar). Lines that are not content lines are
/// skipped.
pub fn read_keys(out: &Path) -> BTreeMap<usize, u64> {
    let Ok(text) = std::fs::read_to_string(meta_path(out)) else {
        return BTreeMap::new();
    };
    text.lines()
        .filter_map(|l| {
            let (i, k) = l.strip_prefix(CONTENT_TAG)?.split_once(" content=")?;
            Some((i.parse().ok()?, u64::from_str_radix(k.trim(), 16).ok()?))
        })
        .collect()
}

/// Writes a finished result: the spec line and content keys to `OUT.meta`, then the table to
/// `OUT` (each atomically; `OUT` appears last). A file that already holds those bytes is left
/// alone (its modification time too). Both paths are checked before anything is written (a
/// symbolic link or a directory is refused), and when `OUT` cannot be written after all, the
/// sidecar is put back as it was, so it never describes a table `OUT` does not hold. Returns
/// whether anything was written.
pub fn write_result(
    out: &Path,
    spec_line: &str,
    keys: &BTreeMap<usize, u64>,
    columns: &str,
    rows: &BTreeMap<usize, String>,
) -> Result<bool, SweepError> {
    write_result_via(out, spec_line, keys, columns, rows, write_atomic)
}

/// [`write_result`] with the atomic writer `write` (a failing one in the tests).
fn write_result_via(
    out: &Path,
    spec_line: &str,
    keys: &BTreeMap<usize, u64>,
    columns: &str,
    rows: &BTreeMap<usize, String>,
    write: impl Fn(&Path, &[u8]) -> Result<(), SweepError>,
) -> Result<bool, SweepError> {
    let mut table = render(spec_line, columns, rows);
    table.drain(..=spec_line.len());
    let meta = meta_path(out);
    check_destinations(out)?;
    let old_meta = std::fs::read(&meta).ok();
    let new_meta = meta_text(spec_line, keys);
    let meta_changes = old_meta.as_deref() != Some(new_meta.as_bytes());
    if meta_changes {
        write(&meta, new_meta.as_bytes())?;
    }
    let out_changes = std::fs::read(out).ok().as_deref() != Some(table.as_bytes());
    if out_changes {
        if let Err(e) = write(out, table.as_bytes()) {
            if meta_changes {
                // best effort: the error above is the one to report
                let _ = match &old_meta {
                    Some(bytes) => write(&meta, bytes),
                    None => {
                        std::fs::remove_file(&meta).map_err(|e| io_err(&meta, "cannot remove", e))
                    }
                };
            }
            return Err(e);
        }
    }
    Ok(meta_changes || out_changes)
}

/// `OUT` and `OUT.meta` can be replaced by [`write_atomic`] ([`check_destination`]): checked
/// before a sweep runs or a merge reads its shards, and again before the result is written.
pub fn check_destinations(out: &Path) -> Result<(), SweepError> {
    check_destination(&meta_path(out))?;
    check_destination(out)
}

/// A result path that [`write_atomic`] can replace: not a symbolic link (its target would be
/// bypassed) and not a directory.
fn check_destination(path: &Path) -> Result<(), SweepError> {
    if let Err(crate::files::OutputError::Symlink { target, .. }) =
        crate::files::classify_output(path)
    {
        return Err(SweepError::Io {
            file: path.display().to_string(),
            action: format!("is a symbolic link (to {})", target.display()),
            reason: "refusing to replace it: remove the link, or give the target path itself (or another OUT)".into(),
        });
    }
    if path.is_dir() {
        return Err(SweepError::Io {
            file: path.display().to_string(),
            action: "cannot write".into(),
            reason: "is a directory".into(),
        });
    }
    Ok(())
}

/// A result file read back: its spec line, column header and its rows by run index.
#[derive(Clone, Debug, Default)]
pub struct ResultFile {
    /// The spec line (`# beadchain sweep ...`: line 1 of a partial file, or of `OUT.meta`).
    pub spec_line: String,
    /// Line 2 (column names).
    pub columns: String,
    /// Rows (without newline) by run index.
    pub rows: BTreeMap<usize, String>,
}

impl ResultFile {
    /// The total number of runs of the sweep, from the spec line.
    pub fn total_runs(&self) -> Option<usize> {
        self.spec_line
            .split(' ')
            .find_map(|w| w.strip_prefix("runs="))
            .and_then(|s| s.parse().ok())
    }
}

fn io_err(path: &Path, action: &str, e: std::io::Error) -> SweepError {
    SweepError::Io {
        file: path.display().to_string(),
        action: action.to_string(),
        reason: e.to_string(),
    }
}

/// Reads a result file. With `partial`, a last line without newline (a write cut short) is
/// dropped; otherwise it is an error. Each row must have as many fields as there are columns and
/// a run index not seen before.
pub fn read_result(path: &Path, partial: bool) -> Result<ResultFile, SweepError> {
    let text = std::fs::read_to_string(path).map_err(|e| io_err(path, "cannot read", e))?;
    let file = path.display().to_string();
    let bad = |line: usize, message: String| SweepError::Csv {
        file: file.clone(),
        line,
        message,
    };
    let mut lines: Vec<&str> = text.split_inclusive('\n').collect();
    if let Some(last) = lines.last() {
        if !last.ends_with('\n') {
            if partial {
                lines.pop();
            } else {
                return Err(bad(
                    lines.len(),
                    "last line is cut short (no newline)".into(),
                ));
            }
        }
    }
    let mut lines = lines
        .into_iter()
        .map(|l| l.trim_end_matches(['\n', '\r']))
        .peekable();
    let tag = "# beadchain sweep spec=";
    // line number of the column header: 2 with the spec line inside, 1 with a sidecar
    let (spec_line, head) = match lines.peek() {
        Some(l) if l.starts_with(tag) => (lines.next().unwrap_or("").to_string(), 2),
        _ => (read_meta(path, tag)?, 1),
    };
    let columns = lines
        .next()
        .ok_or_else(|| bad(head, "missing the column header".into()))?
        .to_string();
    let ncol = split_fields(&columns)
        .map_err(|m| bad(head, m.to_string()))?
        .len();
    let mut rows = BTreeMap::new();
    for (i, l) in lines.enumerate() {
        let ln = i + head + 1;
        let f = split_fields(l).map_err(|m| bad(ln, m.to_string()))?;
        if f.len() != ncol {
            return Err(bad(
                ln,
                format!("{} fields, the header has {ncol}", f.len()),
            ));
        }
        let idx: usize = f[0]
            .parse()
            .map_err(|_| bad(ln, format!("run index `{}` is not a number", f[0])))?;
        if rows.insert(idx, l.to_string()).is_some() {
            return Err(bad(ln, format!("run {idx} appears twice")));
        }
    }
    Ok(ResultFile {
        spec_line,
        columns,
        rows,
    })
}

/// The spec line of a finished result, from its sidecar `PATH.meta`.
fn read_meta(path: &Path, tag: &str) -> Result<String, SweepError> {
    let meta = meta_path(path);
    let text = std::fs::read_to_string(&meta).map_err(|e| SweepError::Csv {
        file: meta.display().to_string(),
        line: 0,
        message: format!(
            "cannot read the sweep's spec sidecar of {} ({e}); a sweep result is `OUT` with `OUT.meta` beside it",
            path.display()
        ),
    })?;
    let line = text.lines().next().unwrap_or("").trim_end().to_string();
    if !line.starts_with(tag) {
        return Err(SweepError::Csv {
            file: meta.display().to_string(),
            line: 1,
            message: format!("not a beadchain sweep spec line (expected `{tag}...`)"),
        });
    }
    Ok(line)
}

/// The whole file with the spec line as line 1 (the partial file), the header line and the
/// rows in run order.
pub fn render(spec_line: &str, columns: &str, rows: &BTreeMap<usize, String>) -> String {
    let mut s = String::with_capacity(64 * (rows.len() + 2));
    s.push_str(spec_line);
    s.push('\n');
    s.push_str(columns);
    s.push('\n');
    for r in rows.values() {
        s.push_str(r);
        s.push('\n');
    }
    s
}

/// Writes `content` to `path` atomically ([`crate::snapshot::write_atomically`]: a temporary
/// sibling, fsynced and renamed; never a half-written file under `path`).
pub fn write_atomic(path: &Path, content: &[u8]) -> Result<(), SweepError> {
    crate::snapshot::write_atomically(path, |w| {
        w.write_all(content)
            .map_err(crate::snapshot::SnapshotError::Output)
    })
    .map_err(|e| SweepError::Io {
        file: path.display().to_string(),
        action: "cannot write".into(),
        reason: match e {
            crate::snapshot::SnapshotError::Io { action, source, .. } => {
                format!("{action}: {source}")
            }
            other => other.to_string(),
        },
    })
}

/// What [`merge`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct MergeSummary {
    /// Rows written.
    pub rows: usize,
    /// Run indices of the sweep found in no shard.
    pub missing: Vec<usize>,
}

/// Joins shard result files into `out` (rows sorted by run, written atomically). The shards must
/// carry the same spec line and columns and no run twice; runs of the sweep found in no shard are
/// an error unless `allow_missing`.
pub fn merge(
    out: &Path,
    shards: &[PathBuf],
    allow_missing: bool,
) -> Result<MergeSummary, SweepError> {
    let first = shards
        .first()
        .ok_or_else(|| SweepError::Options("merge: no shard files given".into()))?;
    check_destinations(out)?;
    let head = read_result(first, false)?;
    let mut rows: BTreeMap<usize, String> = BTreeMap::new();
    let mut from: BTreeMap<usize, &Path> = BTreeMap::new();
    let mut inputs_of: Option<(String, &PathBuf)> = None;
    for s in shards {
        let r = read_result(s, false)?;
        let mismatch = |what: &str| SweepError::Csv {
            file: s.display().to_string(),
            line: if what == "spec line" { 1 } else { 2 },
            message: format!(
                "its {what} differs from {}'s: the shards come from different sweeps",
                first.display()
            ),
        };
        if spec_part(&r.spec_line) != spec_part(&head.spec_line) {
            return Err(mismatch("spec line"));
        }
        // the first shard with an inputs hash is the one the others' are compared with (an
        // older beadchain's shards have none)
        if let Some(a) = inputs_part(&r.spec_line).map(str::to_string) {
            match &inputs_of {
                None => inputs_of = Some((a, s)),
                Some((b, by)) if *b != a => {
                    return Err(SweepError::Csv {
                        file: s.display().to_string(),
                        line: 1,
                        message: format!(
                            "its runs' content keys differ from {}'s: a file the scene reads (a \
                             CSV file) changed between the shards, or another beadchain version \
                             ran one; run that shard again",
                            by.display()
                        ),
                    });
                }
                Some(_) => {}
            }
        }
        if r.columns != head.columns {
            return Err(mismatch("column header"));
        }
        for (i, row) in r.rows {
            if let Some(prev) = from.get(&i) {
                return Err(SweepError::Csv {
                    file: s.display().to_string(),
                    line: 0,
                    message: format!("run {i} is also in {}", prev.display()),
                });
            }
            from.insert(i, s);
            rows.insert(i, row);
        }
    }
    let total = head.total_runs().ok_or_else(|| SweepError::Csv {
        file: first.display().to_string(),
        line: 1,
        message: "no `runs=N` in the spec line".into(),
    })?;
    if let Some((&i, _)) = rows.range(total..).next() {
        return Err(SweepError::Csv {
            file: from[&i].display().to_string(),
            line: 0,
            message: format!("run {i} is beyond the sweep's {total} runs"),
        });
    }
    let missing: Vec<usize> = (0..total).filter(|i| !rows.contains_key(i)).collect();
    if !missing.is_empty() && !allow_missing {
        let shown: Vec<String> = missing.iter().take(20).map(|i| i.to_string()).collect();
        return Err(SweepError::Csv {
            file: out.display().to_string(),
            line: 0,
            message: format!(
                "{} of {total} runs are in no shard: {}{} (use --allow-missing to merge anyway)",
                missing.len(),
                shown.join(", "),
                if missing.len() > 20 { ", ..." } else { "" }
            ),
        });
    }
    let keys: BTreeMap<usize, u64> = shards
        .iter()
        .flat_map(|s| read_keys(s))
        .filter(|(i, _)| rows.contains_key(i))
        .collect();
    let line = match &inputs_of {
        Some((a, _)) => format!("{} inputs={a}", spec_part(&head.spec_line)),
        None => head.spec_line.clone(),
    };
    write_result(out, &line, &keys, &head.columns, &rows)?;
    Ok(MergeSummary {
        rows: rows.len(),
        missing,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A writer that fails for `OUT` (not for its sidecar), as a full disk or a lost directory
    /// would after the sidecar was written.
    fn failing_for(out: &Path) -> impl Fn(&Path, &[u8]) -> Result<(), SweepError> + '_ {
        move |path: &Path, bytes: &[u8]| {
            if path == out {
                Err(SweepError::Io {
                    file: path.display().to_string(),
                    action: "cannot write".into(),
                    reason: "injected failure".into(),
                })
            } else {
                write_atomic(path, bytes)
            }
        }
    }

    fn result_rows() -> (BTreeMap<usize, u64>, BTreeMap<usize, String>) {
        let keys = BTreeMap::from([(0, 0xabc), (1, 0xdef)]);
        let rows = BTreeMap::from([(0, "0,1.5".to_string()), (1, "1,2.5".to_string())]);
        (keys, rows)
    }

    #[test]
    fn sidecar_is_put_back_when_the_result_cannot_be_written() {
        let dir = tempfile::tempdir().expect("temp dir");
        let out = dir.path().join("r.csv");
        let (keys, rows) = result_rows();
        // an earlier result: its sidecar and table
        assert!(write_result(&out, "# sweep old", &keys, "run,x", &rows).expect("first write"));
        let (meta_before, out_before) = (
            std::fs::read(meta_path(&out)).expect("sidecar"),
            std::fs::read(&out).expect("table"),
        );
        // a new result: other keys and rows
        let keys2 = BTreeMap::from([(0, 0x123), (1, 0x456)]);
        let rows2 = BTreeMap::from([(0, "0,9.5".to_string()), (1, "1,8.5".to_string())]);
        let e = write_result_via(
            &out,
            "# sweep new",
            &keys2,
            "run,x",
            &rows2,
            failing_for(&out),
        )
        .expect_err("OUT cannot be written");
        assert!(e.to_string().contains("injected failure"), "{e}");
        assert_eq!(
            std::fs::read(meta_path(&out)).expect("sidecar"),
            meta_before
        );
        assert_eq!(std::fs::read(&out).expect("table"), out_before);
    }

    #[test]
    fn new_sidecar_is_removed_when_the_result_cannot_be_written() {
        let dir = tempfile::tempdir().expect("temp dir");
        let out = dir.path().join("r.csv");
        let (keys, rows) = result_rows();
        let e = write_result_via(
            &out,
            "# sweep new",
            &keys,
            "run,x",
            &rows,
            failing_for(&out),
        )
        .expect_err("OUT cannot be written");
        assert!(e.to_string().contains("injected failure"), "{e}");
        assert!(
            !meta_path(&out).exists(),
            "a sidecar without its table was left behind"
        );
        assert!(!out.exists());
    }
}
