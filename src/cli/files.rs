//! File rules of the command line (issue 11, items 10 and 13): an output never overwrites an
//! input, and a run whose estimated output is above the limit is refused before it starts.
//!
//! - **Output = input.** `--out` (or the default `<scene name>.snap`) is compared with every
//!   input — the scene file and every `{ file = "..." }` CSV it references, the sweep file, the
//!   snapshot or CSV being read — by device and inode ([`beadchain::files::same_file`]: hard
//!   links and `./x` vs `x` are caught). Symbolic links and streams follow the library's rules
//!   ([`beadchain::files::classify_output`]).
//! - **Output size.** Before `run`/`resume` writes anything, the snapshot size is estimated
//!   ([`beadchain::snapshot::size`]: frames × (16 N + 48) bytes plus the header). Above
//!   `--max-output-bytes` (default [`DEFAULT_MAX_OUTPUT_BYTES`] = 10 GiB) the run is refused with
//!   the size, the frame count and the keys to change; `--force` lifts the limit.
//! - **Stale temporaries.** Before an output is written, the hidden `.<name>.tmp-<pid>-<k>` a
//!   killed run left beside it is removed ([`beadchain::files::remove_stale_temps`]) and each
//!   removal is said on standard error ([`clean_stale_temps`]; it used to be silent).

use super::common::GivenTime;
use anyhow::{bail, Result};
pub use beadchain::snapshot::size::short;
use beadchain::snapshot::size::{
    check_output_size, count_text, human_bytes, OutputTooLarge, DEFAULT_MAX_OUTPUT_BYTES,
};
use std::path::{Path, PathBuf};

/// `--max-output-bytes` / `--force` of `run`, `resume` and `sweep`.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct SizeLimit {
    /// Refuse a run whose estimated output (frames x beads) is above N bytes [default: 10 GiB].
    #[arg(long, value_name = "N")]
    pub max_output_bytes: Option<u64>,
    /// Run even if the estimated output is above the limit.
    #[arg(long)]
    pub force: bool,
}

impl SizeLimit {
    /// The limit in bytes (`u64::MAX` with `--force`).
    pub fn bytes(&self) -> u64 {
        if self.force {
            u64::MAX
        } else {
            self.max_output_bytes.unwrap_or(DEFAULT_MAX_OUTPUT_BYTES)
        }
    }

    /// Refuses a run of `n_beads` (frames of `values` stored numbers: `2 N`, or fewer with an
    /// output selection) from `t0` to `until` with interval `every` writing `frames_before`
    /// frames already, if its snapshot would exceed the limit. `what` names the file (scene or
    /// checkpoint), `end` and `interval` the options or keys that set the end time and the
    /// interval; `resume`'s refusal advises only what it can change (its interval and output
    /// selection are the unfinished output's): an earlier `--until`, or the limit.
    pub fn check(
        &self,
        (what, resume): (&str, bool),
        sizes: (usize, u64),
        span: (f64, f64, Option<f64>),
        frames_before: usize,
        (end, interval): (&GivenTime, &GivenTime),
    ) -> Result<()> {
        let Some(over) = self.over(sizes, span, frames_before, (end, interval)) else {
            return Ok(());
        };
        if resume {
            bail!(
                "{what}: the output would be {over}: pass an earlier --until, or --max-output-bytes N or --force (the run is unchanged and can still be resumed)"
            );
        }
        bail!(
            "{what}: {}: the output would be {over}: raise {}, lower {}, or pass --max-output-bytes N or --force",
            interval.key,
            interval.or_option(),
            end.key,
        )
    }

    /// `about B (F frames of N beads: END = T, every = DT), above the limit of L` when the
    /// output would exceed the limit.
    fn over(
        &self,
        (n_beads, values): (usize, u64),
        span: (f64, f64, Option<f64>),
        frames_before: usize,
        (end, interval): (&GivenTime, &GivenTime),
    ) -> Option<String> {
        let limit = self.bytes();
        let of = if values == 2 * n_beads as u64 {
            format!("{n_beads} beads")
        } else {
            format!("{values} stored values of {n_beads} beads")
        };
        let OutputTooLarge { bytes, frames } =
            check_output_size((n_beads, values), span, frames_before, limit).err()?;
        Some(format!(
            "about {} ({} frames of {of}: {} = {}, every = {}), above the limit of {}",
            human_bytes(bytes),
            count_text(frames),
            end.key,
            end.shown(span.1),
            interval.shown_or(span.2, "none (first and last frame)"),
            human_bytes(limit as f64),
        ))
    }
}

/// Refuses `out` when it is one of `inputs` (same device and inode); `flag` names the option.
pub fn check_not_input(out: &Path, flag: &str, inputs: &[(&str, PathBuf)]) -> Result<()> {
    Ok(beadchain::files::check_not_input(&[out], flag, inputs)?)
}

/// Checks, before a long computation, that the output `out` (written at its end) can be made:
/// not an input ([`check_not_input`]), not a symbolic link or a directory, and in a directory
/// that exists. What only the write can tell (permissions, a full disk) is still reported then.
pub fn check_output_before_work(out: &Path, flag: &str, inputs: &[(&str, PathBuf)]) -> Result<()> {
    check_not_input(out, flag, inputs)?;
    if let Err(beadchain::files::OutputError::Symlink { target, .. }) =
        beadchain::files::classify_output(out)
    {
        bail!(
            "{}: {flag}: is a symbolic link (to {}); refusing to replace it: give the target path itself",
            out.display(),
            target.display()
        );
    }
    if out.is_dir() {
        bail!(
            "{}: {flag}: is a directory (give a file name)",
            out.display()
        );
    }
    let dir = match out.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        bail!(
            "{}: {flag}: directory {} does not exist",
            out.display(),
            dir.display()
        );
    }
    Ok(())
}

/// Scene inputs labelled for [`check_not_input`].
pub fn labelled_scene_inputs(spec: &str) -> Vec<(&'static str, PathBuf)> {
    beadchain::files::labelled_scene_inputs(Path::new(spec))
}

/// True when an error (or any cause) is a closed pipe on output (`beadchain ... | head`).
pub fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// Removes the stale temporaries of the output `path` (a killed run's hidden
/// `.<name>.tmp-<pid>-<k>`, not one its checkpoint continues) and says so for each, on standard
/// error. Call before the output is written (the writer's own cleanup then finds nothing).
pub fn clean_stale_temps(path: &Path) {
    use beadchain::files::{classify_output, parse_temp_name, OutputKind};
    if !matches!(classify_output(path), Ok(OutputKind::File)) {
        return;
    }
    for tmp in beadchain::snapshot::remove_stale_temps(path) {
        let pid = tmp
            .file_name()
            .and_then(|n| n.to_str())
            .zip(path.file_name().and_then(|n| n.to_str()))
            .and_then(|(t, n)| parse_temp_name(t, n))
            .map_or(String::new(), |(pid, _)| format!("process {pid}, "));
        eprintln!(
            "beadchain: note: removed {}, the partial output of an interrupted run ({pid}no longer running)",
            tmp.display()
        );
    }
}
