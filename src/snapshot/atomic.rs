//! Atomic output files: everything the crate writes besides the snapshot stream itself (exports,
//! checkpoints, plots) goes through [`write_atomically`], so a failed write leaves no file and
//! never a half-written one. It lives here, below `export` and `plot`, because checkpoints
//! ([`super::ckpt`]) use it too.

use super::{sync_parent_dir, temp_sibling, SnapshotError};
use std::fs::OpenOptions;
use std::io::{self, BufWriter, Write};
use std::path::Path;

/// Writes `path` atomically: `f` writes into a buffered temporary sibling, which is flushed,
/// fsynced and renamed onto `path` only if `f` succeeds; otherwise it is removed. Output
/// errors ([`SnapshotError::Output`]) are reported as I/O errors naming `path`.
///
/// A character device or FIFO (`/dev/stdout`, `/dev/null`, a named pipe) is written in place;
/// a symbolic link to a file is refused; stale temporaries of dead runs are removed first (rules
/// in [`crate::files`]).
pub fn write_atomically(
    path: &Path,
    f: impl FnOnce(&mut dyn Write) -> Result<(), SnapshotError>,
) -> Result<(), SnapshotError> {
    let named = |action: &str, e: io::Error| SnapshotError::Io {
        path: path.to_path_buf(),
        action: action.to_string(),
        source: e,
    };
    if crate::files::classify_output(path)? == crate::files::OutputKind::Stream {
        let file = OpenOptions::new()
            .write(true)
            .open(path)
            .map_err(|e| named("opening the output stream", e))?;
        let mut w = BufWriter::with_capacity(1 << 16, file);
        f(&mut w).map_err(|e| match e {
            SnapshotError::Output(io) => named("writing", io),
            other => other,
        })?;
        return w.flush().map_err(|e| named("writing", e));
    }
    super::remove_stale_temps(path);
    let tmp = temp_sibling(path)?;
    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)
        .map_err(|e| named(&format!("creating temporary file {}", tmp.display()), e))?;
    let result = (|| {
        let mut w = BufWriter::with_capacity(1 << 16, file);
        f(&mut w).map_err(|e| match e {
            SnapshotError::Output(io) => named("writing", io),
            other => other,
        })?;
        let file = w
            .into_inner()
            .map_err(|e| named("flushing", e.into_error()))?;
        file.sync_all().map_err(|e| named("syncing to disk", e))?;
        drop(file);
        std::fs::rename(&tmp, path)
            .map_err(|e| named(&format!("renaming {} onto it", tmp.display()), e))
    })();
    match result {
        Ok(()) => {
            sync_parent_dir(path);
            Ok(())
        }
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}
