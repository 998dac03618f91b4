//! Parameter sweeps: many runs of one base scene with scene keys overridden, run in parallel,
//! one CSV row per run (`beadchain sweep SWEEP.toml`, `beadchain merge`).
//!
//! Submodules: [`expand`] (grid/list expansion, scene overrides), [`exec`] (parallel execution and
//! the measurements), [`csv`] (result rows, resuming, merging shards), [`content`] (content
//! keys: skipping runs whose results a finished `OUT` already holds).
//!
//! ## The sweep file
//!
//! ```toml
//! scene = "interface_3.0_2.5"      # REQUIRED: preset name, or a scene file relative to this file
//!
//! [set]                            # fixed overrides for every run (not result columns)
//! "chain.beads" = 60
//! "run.until" = 20000.0
//!
//! [grid]                           # cartesian product; keys in alphabetical order, the last fastest
//! "chain.exponent.base" = [2.5, 3.0, 3.5]
//! "chain.exponent.segments.0.value" = [2.5, 3.0, 3.5]
//!
//! [[point]]                        # explicit list (combined with the grid: every point x the grid)
//! "initial.striker_si" = 0.11
//!
//! [seeds]                          # fastest-varying dimension; the target key is explicit
//! key = "scene.seed"
//! values = [1, 2, 3]
//!
//! [measure]                        # optional result columns (see below)
//! interface = 30                   # left_fraction = E_left/E_total at interface bead 30
//! impurity = 50                    # v_ratio = |v_out/v_in| in front of bead 50
//! decay = true                     # gamma, gamma_se; or { from = 25, e0_bead = 15, jump = 1.3 }
//! fragments = true                 # fragments at the end; or { gap_tol = 0.0 }
//!
//! [stop]                           # optional early stops (default: the scene's [run] until)
//! margin = 10                      # when the leading pulse's peak reaches bead N - margin
//! steady_state = true              # at the appendix-A steady state
//! ```
//!
//! The file is read through typed structs (`parse`: serde with `deny_unknown_fields`; [`Measure`],
//! [`Decay`], [`Stop`] are the tables as written): an unknown key, a missing one or a value of the
//! wrong form fails with one line naming the sweep file and the key (`[stop].margin`).
//!
//! **Keys** are the keys of a scene file written with dots and always quoted: `"chain.exponent"`
//! is `exponent` in `[chain]`; deeper parts walk into inline tables (`"chain.exponent.random.eps"`)
//! and numeric parts index arrays (`"chain.exponent.segments.0.value"`). Missing tables on the way
//! are created; a key must have at least two parts (a whole table is never replaced). Each run's
//! TOML is the base scene with `[set]`, the grid values, the point's and the seed written in
//! (in that order; a point's keys in sorted order), then
//! read by the normal scene parser and validator, so every value gets the scene's checks and
//! messages. Every run's scene is built before any run starts: an unknown key, a wrong type, an
//! empty list or a bad preset fails the whole sweep with one line naming the sweep file, the run
//! and the key; nothing is run. A run that fails (integration error, no wave to fit) gives a row
//! with `status` = the error text instead.
//!
//! **Columns**: `run` (0-based index), one column per grid/point/seed key (the value as given;
//! numbers in `{:e}` form), `status` (`ok` or the error), `t_end` (the stop or end time),
//! `energy_error` (the balance error `|E_end + E_d − E_0| / max(|E_0|, S)`,
//! [`crate::engine::RunOutcome::relative_energy_error`]: `E_d` dissipated, `S` the energy
//! scale), `steps` (accepted integrator steps), `events` (hybrid engine events: contact
//! closings/openings, collisions; empty for the dense engine), then the `[measure]` columns:
//! - `left_fraction` (`interface = K`): energy of beads `0..K` over the total at the final frame,
//!   [`crate::analysis::energy_split`]. It contains the striker's rebound; the paper's reflected
//!   energy (Fig. 7) is `left_fraction − left_fraction(n2 = n1)` (the uniform run of the grid).
//! - `gamma`, `gamma_se` (`decay`): fit `E/E0 = a e^{−γ x}` of the leading-wave energy (eq. 13)
//!   against its peak bead `x ≥ from`, `E0` at the first frame with peak `≥ e0_bead`, up to the first
//!   jump by more than `jump` between frames (as [`crate::experiments::paper::decay_gamma`], Sec. 5.2,
//!   Fig. 20).
//! - `v_ratio` (`impurity = K`): `|v_out/v_in|` of beads `min(K/2, 20)..K−3` over all frames
//!   (Sec. 5.1, Fig. 18; [`crate::experiments::paper::Watch`]); empty, with the row's status
//!   an error, when that window is empty (`K ≤ 6`) or the frames do not resolve the peaks
//!   ([`crate::analysis::VelocityRatio::checked`]: a pulse that passes a bead in fewer than 3
//!   frames).
//! - `fragments`: number of fragments of the final state ([`crate::analysis::fragmentation`]).
//! - `wall_seconds` only with `--timing` (otherwise identical inputs give identical bytes).
//!
//! The frame-based measures and stops need frames: the scene (or `[set]`) must give `run.every`.
//!
//! **Files.** The first line is `# beadchain sweep spec=HASH runs=N`: HASH is a 64-bit FNV-1a hash
//! of the sweep file and base scene (as parsed TOML, so comments and spacing do not count) and N
//! the number of runs of the whole sweep. Rows are appended to `OUT.partial` (flushed per row) as
//! runs finish; a restart skips the rows already there (refusing a partial file of another spec);
//! at the end the rows are written sorted by run into `OUT` (temporary file + rename) and the
//! partial file is removed. `OUT.meta` also keeps each row's content key ([`content`]): a rerun
//! skips the runs whose result `OUT` already holds (same resolved scene, run settings, measures
//! and version), so only new or changed points run. `--shard K/M` runs the runs with `run % M == K − 1`; `merge` joins
//! shard files into the same bytes as an unsharded run.

pub mod content;
pub mod csv;
pub mod exec;
pub mod expand;
mod parse;
pub mod shard;

pub use csv::merge;
pub use exec::{run_sweep, SweepOptions, SweepSummary};
pub use expand::{RunPoint, MAX_RUNS};
pub use shard::Shard;

use crate::scene::SceneError;
use serde::Deserialize;
use std::path::PathBuf;
use toml::{Table, Value};

/// Why a sweep could not be read, resumed, run or merged. Every message is one line naming the
/// file (and key, run or line).
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// A file could not be read or written.
    #[error("{file}: {action}: {reason}")]
    Io {
        /// The file.
        file: String,
        /// What was being done.
        action: String,
        /// OS error text.
        reason: String,
    },
    /// A key of the sweep file is unknown, missing, of the wrong type or has a bad value.
    #[error("{file}: {key}: {message}")]
    Key {
        /// Sweep file.
        file: String,
        /// Key path in the sweep file (e.g. `[grid]."chain.exponent"`).
        key: String,
        /// What is wrong.
        message: String,
    },
    /// The scene of one run was rejected by the scene parser/validator.
    #[error("{file}: run {run} ({params}): {source}")]
    Scene {
        /// Sweep file.
        file: String,
        /// Run index.
        run: usize,
        /// The run's parameters, `key=value` comma-separated.
        params: String,
        /// The scene error.
        source: Box<SceneError>,
    },
    /// A result file is malformed or does not belong to this sweep.
    #[error("{file}{}: {message}", line_suffix(*.line))]
    Csv {
        /// The CSV file.
        file: String,
        /// 1-based line (0: the file as a whole).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// Bad options (shard, jobs).
    #[error("{0}")]
    Options(String),
}

/// `:LINE`, or nothing for line 0 (the file as a whole).
fn line_suffix(line: usize) -> String {
    if line == 0 {
        String::new()
    } else {
        format!(":{line}")
    }
}

/// What `[measure]` asks for beyond the fixed columns (read from the sweep file as written; the
/// value forms are checked in `parse`).
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Measure {
    /// Interface bead `K` for `left_fraction`.
    #[serde(default, deserialize_with = "parse::non_neg")]
    pub interface: Option<usize>,
    /// Impurity bead `K` for `v_ratio`.
    #[serde(default, deserialize_with = "parse::non_neg")]
    pub impurity: Option<usize>,
    /// Leading-wave decay fit settings for `gamma`, `gamma_se`.
    #[serde(default, deserialize_with = "parse::toggle")]
    pub decay: Option<Decay>,
    /// Gap tolerance of the fragment count, when asked for.
    #[serde(default, deserialize_with = "parse::fragments")]
    pub fragments: Option<f64>,
}

/// Settings of the leading-wave decay fit (defaults as in `experiments::paper::decay_gamma`).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Decay {
    /// Fit the points whose peak bead is at least this (default 25).
    #[serde(deserialize_with = "parse::non_neg")]
    pub from: usize,
    /// Normalise by the energy at the first frame whose peak bead is at least this (default 15).
    #[serde(deserialize_with = "parse::non_neg")]
    pub e0_bead: usize,
    /// Stop the fit at the first frame-to-frame energy rise by more than this factor (default 1.3).
    #[serde(deserialize_with = "parse::jump")]
    pub jump: f64,
}

impl Default for Decay {
    fn default() -> Self {
        Decay {
            from: 25,
            e0_bead: 15,
            jump: 1.3,
        }
    }
}

/// Early stop conditions (`[stop]`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stop {
    /// Stop when the leading pulse's peak reaches bead `N − margin`.
    #[serde(default, deserialize_with = "parse::non_neg")]
    pub margin: Option<usize>,
    /// Stop at the appendix-A steady state.
    #[serde(default, deserialize_with = "parse::flag")]
    pub steady_state: bool,
}

/// A parsed sweep file.
#[derive(Clone, Debug)]
pub struct SweepSpec {
    /// The sweep file as named by the user (used in messages).
    pub file: String,
    /// The base scene as written in the file (`scene = ...`).
    pub scene_spec: String,
    /// The base scene's TOML.
    pub base: Table,
    /// Directory that resolves the base scene's `{ file = ... }` references.
    pub base_dir: PathBuf,
    /// Fixed overrides.
    pub set: Vec<(String, Value)>,
    /// Grid dimensions (alphabetical key order; the last varies fastest).
    pub grid: Vec<(String, Vec<Value>)>,
    /// Explicit points (each a list of overrides).
    pub points: Vec<Vec<(String, Value)>>,
    /// Seed key and values (fastest-varying dimension).
    pub seeds: Option<(String, Vec<Value>)>,
    /// Result columns.
    pub measure: Measure,
    /// Early stops.
    pub stop: Stop,
    /// FNV-1a hash of the sweep file and base scene (as parsed TOML).
    pub hash: u64,
    /// Limit of one run's estimated frame data (as the snapshot `run` would write; checked for
    /// every run before any runs): [`crate::snapshot::size::DEFAULT_MAX_OUTPUT_BYTES`] unless
    /// the caller (`--max-output-bytes`, `--force`) changes it.
    pub max_output_bytes: u64,
}

pub(crate) use crate::scene::{fnv1a, type_name};
