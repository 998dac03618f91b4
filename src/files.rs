//! File-system rules shared by every command that reads or writes files.
//!
//! **Outputs** ([`classify_output`]). An output path is one of:
//! - a regular file or a name that does not exist yet: written through a temporary sibling
//!   `.<name>.tmp-<pid>-<k>` that is fsynced and renamed onto the name (atomic; a failed run
//!   leaves nothing under the name);
//! - a character device or a FIFO (`/dev/null`, `/dev/stdout` when it is a terminal or a pipe, a
//!   named pipe): a *stream*, opened and written in place; nothing is renamed over it;
//! - a symbolic link to a regular file or to nothing: **refused** (renaming over the link would
//!   replace the link by a file, writing through it would move the output somewhere the user did
//!   not name; the message names the link's target, so the user can pass that path);
//! - a directory: refused by the rename (as before).
//!
//! **Stale temporaries** ([`remove_stale_temps`]). A run killed without a chance to clean up
//! (SIGKILL, power loss) leaves its hidden `.<name>.tmp-<pid>-<k>`. Before a new output of the
//! same name is written, siblings of that exact pattern whose `<pid>` is no longer a running
//! process are removed. A process is taken as alive when `/proc/<pid>` exists (Linux); where
//! `/proc` is not mounted nothing is removed. The caller names a temporary to keep: the snapshot
//! layer keeps the one `<name>.ckpt` continues (a checkpoint a `beadchain resume` can still
//! continue), and keeps everything when that checkpoint exists but cannot be read
//! (`crate::snapshot::remove_stale_temps`).
//!
//! **Inputs** ([`read_text_limited`]). Text inputs (scene files, CSV files, sweep files) are
//! read through a byte limit ([`MAX_TEXT_BYTES`]), so `beadchain run /dev/zero` fails at once
//! instead of reading forever, and a leading UTF-8 byte-order mark is dropped (files saved by
//! spreadsheet programs start with one).

use std::io::Read;
use std::path::{Path, PathBuf};

/// Largest text input read (scene, CSV, sweep file): 256 MiB, about ten times a CSV of the
/// largest chain a scene may declare (10⁷ beads, ~25 bytes a line).
pub const MAX_TEXT_BYTES: u64 = 256 << 20;

/// How an output path is written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OutputKind {
    /// A regular file (or a new name): temporary sibling + rename.
    File,
    /// A character device or FIFO: opened and written in place.
    Stream,
}

/// Why an output path is refused.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The path is a symbolic link to a regular file, or to nothing.
    #[error("{}: is a symbolic link (to {}); refusing to replace it: give the target path itself", path.display(), target.display())]
    Symlink {
        /// The path given.
        path: PathBuf,
        /// What the link points to.
        target: PathBuf,
    },
}

/// Classifies an output path (see the module docs).
pub fn classify_output(path: &Path) -> Result<OutputKind, OutputError> {
    let Ok(meta) = std::fs::symlink_metadata(path) else {
        return Ok(OutputKind::File);
    };
    if meta.file_type().is_symlink() {
        return match std::fs::metadata(path) {
            Ok(m) if is_stream(&m) => Ok(OutputKind::Stream),
            _ => Err(OutputError::Symlink {
                path: path.to_path_buf(),
                target: std::fs::read_link(path).unwrap_or_default(),
            }),
        };
    }
    Ok(if is_stream(&meta) {
        OutputKind::Stream
    } else {
        OutputKind::File
    })
}

#[cfg(unix)]
fn is_stream(m: &std::fs::Metadata) -> bool {
    use std::os::unix::fs::FileTypeExt;
    let t = m.file_type();
    t.is_char_device() || t.is_fifo()
}

#[cfg(not(unix))]
fn is_stream(_m: &std::fs::Metadata) -> bool {
    false
}

/// Whether `a` and `b` name the same existing file (same device and inode on Unix, same
/// canonical path elsewhere). `false` when either does not exist.
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}

/// `(pid, k)` of a temporary name `.<name>.tmp-<pid>-<k>` of `name`, `None` otherwise.
pub fn parse_temp_name(temp: &str, name: &str) -> Option<(u32, u64)> {
    let rest = temp.strip_prefix('.')?.strip_prefix(name)?;
    let rest = rest.strip_prefix(".tmp-")?;
    let (pid, k) = rest.split_once('-')?;
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    if !digits(pid) || !digits(k) {
        return None;
    }
    Some((pid.parse().ok()?, k.parse().ok()?))
}

/// Whether process `pid` is running (`/proc/<pid>` exists); `None` where `/proc` is absent.
pub fn process_alive(pid: u32) -> Option<bool> {
    if !Path::new("/proc/self").exists() {
        return None;
    }
    Some(Path::new(&format!("/proc/{pid}")).exists())
}

/// Removes the stale temporaries of `path` (see the module docs) except the one named `keep`;
/// returns the removed paths. Best effort: errors (unreadable directory, a file that vanished)
/// are skipped.
pub fn remove_stale_temps(path: &Path, keep: Option<&str>) -> Vec<PathBuf> {
    let mut removed = Vec::new();
    let Some(name) = path.file_name().and_then(|n| n.to_str()) else {
        return removed;
    };
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let Ok(entries) = std::fs::read_dir(dir) else {
        return removed;
    };
    for e in entries.flatten() {
        let file_name = e.file_name();
        let Some(s) = file_name.to_str() else {
            continue;
        };
        let Some((pid, _)) = parse_temp_name(s, name) else {
            continue;
        };
        if pid == std::process::id() || keep == Some(s) {
            continue;
        }
        let is_file = e.file_type().is_ok_and(|t| t.is_file());
        if is_file && process_alive(pid) == Some(false) && std::fs::remove_file(e.path()).is_ok() {
            removed.push(e.path());
        }
    }
    removed
}

/// Reads a text file of at most `limit` bytes (UTF-8; a leading byte-order mark is dropped).
/// Larger inputs (`/dev/zero`, a wrong file) fail with [`std::io::ErrorKind::InvalidData`]
/// after reading `limit + 1` bytes.
pub fn read_text_limited(path: &Path, limit: u64) -> std::io::Result<String> {
    let file = std::fs::File::open(path)?;
    let mut bytes = Vec::new();
    file.take(limit + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "larger than the limit of {} MiB for a text input",
                limit >> 20
            ),
        ));
    }
    let mut text = String::from_utf8(bytes).map_err(|e| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "not UTF-8 text (invalid byte at offset {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })?;
    if text.starts_with('\u{feff}') {
        text.drain(..3);
    }
    Ok(text)
}

/// [`read_text_limited`] with [`MAX_TEXT_BYTES`].
pub fn read_text(path: &Path) -> std::io::Result<String> {
    read_text_limited(path, MAX_TEXT_BYTES)
}

/// The files a scene file reads: the file itself and the CSV files its `{ file = "..." }`
/// values name, resolved against its directory (nothing when `path` is not a file).
pub fn scene_inputs(path: &Path) -> Vec<PathBuf> {
    if !path.is_file() {
        return Vec::new();
    }
    let mut out = vec![path.to_path_buf()];
    let dir = path.parent().unwrap_or(Path::new("."));
    if let Ok(text) = read_text(path) {
        if let Ok(root) = text.parse::<toml::Table>() {
            collect_csv(&toml::Value::Table(root), dir, &mut out);
        }
    }
    out
}

fn collect_csv(v: &toml::Value, dir: &Path, out: &mut Vec<PathBuf>) {
    match v {
        toml::Value::Table(t) => {
            if let Some(toml::Value::String(f)) = t.get("file") {
                out.push(dir.join(f));
            }
            for x in t.values() {
                collect_csv(x, dir, out);
            }
        }
        toml::Value::Array(a) => a.iter().for_each(|x| collect_csv(x, dir, out)),
        _ => {}
    }
}

/// An output that is one of the command's inputs.
#[derive(Debug, thiserror::Error)]
#[error("{}: {flag}: is the {kind} {} read by this command; refusing to overwrite an input (choose another output name)", out.display(), input.display())]
pub struct InputOverwrite {
    /// The output path.
    pub out: PathBuf,
    /// The option or argument that names it.
    pub flag: String,
    /// What the input is ("scene file", ...).
    pub kind: String,
    /// The input it is.
    pub input: PathBuf,
}

/// Refuses each of `outs` (the files a command writes) that is one of `inputs` (same device
/// and inode); `flag` names the option.
pub fn check_not_input(
    outs: &[&Path],
    flag: &str,
    inputs: &[(&str, PathBuf)],
) -> Result<(), InputOverwrite> {
    for out in outs {
        if let Some((kind, input)) = inputs.iter().find(|(_, i)| same_file(out, i)) {
            return Err(InputOverwrite {
                out: out.to_path_buf(),
                flag: flag.to_string(),
                kind: kind.to_string(),
                input: input.clone(),
            });
        }
    }
    Ok(())
}

/// [`scene_inputs`] labelled for [`check_not_input`].
pub fn labelled_scene_inputs(path: &Path) -> Vec<(&'static str, PathBuf)> {
    scene_inputs(path)
        .into_iter()
        .enumerate()
        .map(|(i, p)| (if i == 0 { "scene file" } else { "CSV file" }, p))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn temp_names() {
        assert_eq!(parse_temp_name(".o.snap.tmp-12-0", "o.snap"), Some((12, 0)));
        assert_eq!(parse_temp_name(".o.snap.tmp-12-", "o.snap"), None);
        assert_eq!(parse_temp_name(".o.snap.ckpt.tmp-12-0", "o.snap"), None);
        assert_eq!(parse_temp_name("o.snap.tmp-12-0", "o.snap"), None);
        assert_eq!(parse_temp_name(".o.snap.tmp-x-0", "o.snap"), None);
    }
}
