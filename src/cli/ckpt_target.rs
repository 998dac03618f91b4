//! Where `beadchain resume` writes, checked before anything is touched:
//!
//! - **The checkpoint's own directory.** `run` puts `OUT.ckpt` beside `OUT` and its temporary
//!   `.OUT.tmp-PID-K`, and the checkpoint records both as absolute paths. A checkpoint that lies
//!   in another directory was copied or moved there: when the temporary output it continues
//!   lies beside it too (the run's directory copied or moved whole), the run continues there,
//!   into `OUT` beside the checkpoint, with a note; without it, `resume` is refused (before, it
//!   went on in the recorded directory, which a copy's user did not expect). Paths recorded
//!   relative (older builds) are resolved beside the checkpoint, as before.
//! - **The output path** gets `run`'s checks: not a symbolic link, a directory, a device or a
//!   pipe (renaming the finished file over one would replace it).
//! - **The run still going.** The temporary's name holds the PID of the run that created it;
//!   while that process is alive (`/proc/PID`), `resume` is refused (both would write the same
//!   temporary file).

use anyhow::{bail, Result};
use beadchain::files::{classify_output, parse_temp_name, process_alive, OutputError, OutputKind};
use beadchain::snapshot::WriterMark;
use std::path::{Path, PathBuf};

/// The directory of `file` (`.` for a bare name).
fn dir_of(file: &Path) -> &Path {
    match file.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// Whether two directories are the same (canonical paths; `false` when either is missing).
fn same_dir(a: &Path, b: &Path) -> bool {
    matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y)
}

/// Resolves the checkpoint `file`'s output and temporary paths (module docs): relative ones
/// beside it; absolute ones of another directory onto the checkpoint's when the temporary
/// output lies beside it, else refused.
pub fn locate(file: &Path, mark: &mut WriterMark) -> Result<()> {
    let dir = dir_of(file);
    let (Some(name), Some(temp)) = (mark.path.file_name(), mark.temp.file_name()) else {
        bail!(
            "{}: the checkpoint names no output file ({})",
            file.display(),
            mark.path.display()
        );
    };
    let (name, temp) = (name.to_owned(), temp.to_owned());
    if mark.path.is_relative() || mark.temp.is_relative() {
        mark.path = dir.join(&name);
        mark.temp = dir.join(&temp);
        return Ok(());
    }
    let recorded = dir_of(&mark.path).to_path_buf();
    if same_dir(dir, &recorded) {
        return Ok(());
    }
    let beside: PathBuf = dir.join(&temp);
    if !beside.is_file() {
        bail!(
            "{}: the checkpoint was written for {} in another directory, and the temporary output it continues ({}) is not beside it: resume the checkpoint in {}, or copy {} beside it",
            file.display(),
            mark.path.display(),
            temp.to_string_lossy(),
            recorded.display(),
            temp.to_string_lossy()
        );
    }
    let out = dir.join(&name);
    eprintln!(
        "beadchain: note: {} was written for {}; continuing into {} beside it, with the temporary output {} found there",
        file.display(),
        mark.path.display(),
        out.display(),
        beside.display()
    );
    mark.path = out;
    mark.temp = beside;
    Ok(())
}

/// Refuses to resume into an output path `run` would refuse (a symbolic link, a directory, a
/// device or pipe), or while the run that created the temporary output is still going.
pub fn check_target(what: &str, mark: &WriterMark) -> Result<()> {
    let out = &mark.path;
    let keep = "(the run is unchanged)";
    match classify_output(out) {
        Err(OutputError::Symlink { target, .. }) => bail!(
            "{what}: its output {} is a symbolic link (to {}); refusing to replace it: remove the link, then resume {keep}",
            out.display(),
            target.display()
        ),
        Ok(OutputKind::Stream) => bail!(
            "{what}: its output {} is a device or pipe; refusing to rename the finished file over it: remove it, then resume {keep}",
            out.display()
        ),
        Ok(OutputKind::File) if out.is_dir() => bail!(
            "{what}: its output {} is a directory; remove or rename it, then resume {keep}",
            out.display()
        ),
        Ok(OutputKind::File) => {}
    }
    check_not_running(what, mark)
}

/// Refuses while the process named in the temporary file's name (`.OUT.tmp-PID-K`) runs.
fn check_not_running(what: &str, mark: &WriterMark) -> Result<()> {
    let names = mark
        .temp
        .file_name()
        .and_then(|t| t.to_str())
        .zip((mark.path.file_name()).and_then(|n| n.to_str()));
    let Some((pid, _)) = names.and_then(|(t, n)| parse_temp_name(t, n)) else {
        return Ok(());
    };
    if pid != std::process::id() && process_alive(pid) == Some(true) {
        bail!(
            "{what}: the run writing {} is still going (process {pid}): wait for it to end, or stop it (`kill -INT {pid}` writes a checkpoint), then resume",
            mark.temp.display()
        );
    }
    Ok(())
}
