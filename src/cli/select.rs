//! Output selection of `run` (issue 14): `--beads LIST`, `--fields u,v`, `--frames-max K`.
//!
//! The bead/field grammar and the snapshot side are in [`beadchain::snapshot::select`]. Every
//! value is checked before anything is written (one-line error naming the option, exit 2).
//!
//! `--frames-max K` rule: a run that would write more than `K` frames is **refused** before it
//! starts — never thinned silently. A run writes the frames `0, every, 2·every, …` below
//! `until` and `until` itself ([`frame_count`]); the error gives the count and the smallest
//! `--every` that fits (`until/(K−1)`, rounded up to a value that fits). The cap is stored in
//! the snapshot header, so `resume --until T` is refused the same way.

use super::common::GivenTime;
use super::files::short;
use anyhow::{bail, Result};
use beadchain::snapshot::select::parse_beads;
use beadchain::snapshot::size::{self, count_text, TooManyFrames};
use beadchain::snapshot::{Fields, Selection};

/// The output-selection options of `run`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct OutputArgs {
    /// Store only these beads in the frames: comma-separated 0-based indices I and half-open
    /// ranges A:B (beads A..B-1) or A:B:STEP, e.g. `0:100`, `0:1000:10`, `3,10,20`, `500:`
    /// [default: every bead]. Checkpoints still hold the full state.
    #[arg(long, value_name = "LIST")]
    pub beads: Option<String>,
    /// Store only these fields: u (displacements), v (velocities) or u,v [default: u,v].
    #[arg(long, value_name = "FIELDS")]
    pub fields: Option<String>,
    /// Refuse to start a run that would write more than K frames (K >= 2); the error names the
    /// --every that fits. No silent thinning.
    #[arg(long, value_name = "K")]
    pub frames_max: Option<u64>,
}

impl OutputArgs {
    /// The selection for a chain of `n` beads: each option given overrides the scene's
    /// `[output]` key (`scene`); `what` (the scene argument) prefixes errors.
    pub fn selection(&self, what: &str, n: usize, scene: Option<&Selection>) -> Result<Selection> {
        let base = scene.cloned().unwrap_or_default();
        let beads = match &self.beads {
            Some(spec) => {
                parse_beads(spec, n as u64).map_err(|e| anyhow::anyhow!("{what}: --beads: {e}"))?
            }
            None => base.beads,
        };
        let fields = match &self.fields {
            Some(spec) => {
                Fields::parse(spec).map_err(|e| anyhow::anyhow!("{what}: --fields: {e}"))?
            }
            None => base.fields,
        };
        if let Some(k) = self.frames_max.filter(|&k| k < 2) {
            bail!(
                "{what}: --frames-max: must be at least 2 (a run writes its first and its last frame), got {k}"
            );
        }
        Ok(Selection {
            beads,
            fields,
            frames_max: self.frames_max.or(base.frames_max),
        })
    }
}

/// Refuses a run to `until` with interval `every` that would write more frames than the
/// selection's `frames_max` (`run`'s rule; `resume` has its own advice, `cli::ckpt`).
/// `cap_key` names where the cap came from (`--frames-max` or `[output].frames_max`), `end` and
/// `interval` where `until` and `every` came from.
pub fn check_frames_max(
    what: &str,
    sel: &Selection,
    (until, every): (f64, Option<f64>),
    cap_key: &str,
    (end, interval): (&GivenTime, &GivenTime),
) -> Result<()> {
    let Err(TooManyFrames {
        count,
        frames_max: k,
        every_that_fits: dt,
    }) = size::check_frames_max(sel.frames_max, until, every)
    else {
        return Ok(());
    };
    bail!(
        "{what}: {cap_key}: the run would write {} frames ({} = {}, every = {}), more than {cap_key} {k}; use --every {} or larger, or raise {cap_key}",
        count_text(count),
        end.key,
        end.shown(until),
        interval.shown_or(every, "none"),
        short(dt),
    )
}
