//! Running a sweep: the runs of a shard in parallel (rayon), each measured on the fly and turned
//! into one CSV row, appended to `OUT.partial` as it finishes; the sorted `OUT` at the end.
//!
//! Each run uses the scene's own engine settings ([`RunConfig::from_scene`]) under a
//! [`Watch`] (leading-wave track, incoming/reflected peak velocities; stop at bead `N − margin`,
//! as `experiments::paper::run_watched`), optionally wrapped in [`SteadyStateStop`] (appendix A). A
//! stopped run reports the counters of the engine state handed to the observer at the stop.

use super::content::reusable_rows;
use super::csv::{self, field, ResultFile};
use super::expand::RunPoint;
use super::shard::Shard;
use super::{Decay, SweepError, SweepSpec};
use crate::analysis::{
    energy_split, fit_exponential, fragmentation, AnalysisError, ExpFit, SteadyStateStop,
};
use crate::engine::{self, EngineError, Observer, RunConfig};
use crate::experiments::paper::Watch;
use crate::scene::Engine;
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

/// How to run a sweep.
#[derive(Clone, Debug)]
pub struct SweepOptions {
    /// Final result file (`OUT.partial` holds the rows while running).
    pub out: PathBuf,
    /// Worker threads (`None`: all cores).
    pub jobs: Option<usize>,
    /// Only this slice of the runs.
    pub shard: Option<Shard>,
    /// Run at most this many new runs, then stop leaving `OUT.partial` (for tests, time limits).
    pub max_runs: Option<usize>,
    /// Add a `wall_seconds` column (then output bytes differ between runs).
    pub timing: bool,
}

/// What [`run_sweep`] did.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSummary {
    /// Runs of this shard.
    pub runs: usize,
    /// Rows taken from an existing `OUT.partial`.
    pub resumed: usize,
    /// Runs skipped because the finished `OUT` already holds their result (same content key).
    pub skipped: usize,
    /// Runs done now.
    pub ran: usize,
    /// Rows with an error status (this shard, all rows).
    pub failed: usize,
    /// Whether all runs of the shard are done (`OUT` holds them).
    pub complete: bool,
    /// Whether `OUT` or `OUT.meta` was written (false: they already held these bytes).
    pub written: bool,
}

/// `OUT.partial`.
pub fn partial_path(out: &Path) -> PathBuf {
    let mut name = out
        .file_name()
        .map(|s| s.to_os_string())
        .unwrap_or_default();
    name.push(".partial");
    out.with_file_name(name)
}

/// Measured values of one run (`None`: not asked for or not available).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Measured {
    /// End or stop time.
    pub t_end: f64,
    /// `|E_end − E_0|/|E_0|`.
    pub energy_error: f64,
    /// Accepted integrator steps.
    pub steps: Option<u64>,
    /// Hybrid-engine events.
    pub events: Option<u64>,
    /// `E_left/E_total` at the interface bead.
    pub left_fraction: Option<f64>,
    /// Decay rate and its standard error.
    pub gamma: Option<(f64, f64)>,
    /// `|v_out/v_in|`.
    pub v_ratio: Option<f64>,
    /// Fragment count.
    pub fragments: Option<usize>,
}

/// Why a sweep point could not be run at all (the `error: ...` of its row).
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    /// The run's scene was rejected.
    #[error(transparent)]
    Scene(#[from] SweepError),
    /// The engine failed.
    #[error(transparent)]
    Engine(#[from] EngineError),
    /// The run panicked (the panic message).
    #[error("panic: {0}")]
    Panic(String),
}

/// Runs one sweep point: `Ok(measured, problem)` (a measure that failed is reported as the
/// problem, with the other columns kept), `Err` when the run could not be done at all.
pub fn run_one(spec: &SweepSpec, run: &RunPoint) -> Result<(Measured, Option<String>), RunError> {
    let scene = spec.scene_for(run)?;
    let cfg = RunConfig::from_scene(&scene);
    let n = scene.chain.len();
    let m = &spec.measure;
    let stop_at = spec.stop.margin.map_or(usize::MAX, |g| n - g);
    let k = m.impurity.or(m.interface).unwrap_or(5);
    let mut watch = Watch::new(scene.chain.clone(), k, stop_at);
    let res = {
        let mut ss;
        let obs: &mut dyn Observer = if spec.stop.steady_state {
            ss = SteadyStateStop::new(&mut watch, &scene.chain);
            &mut ss
        } else {
            &mut watch
        };
        engine::run_to_stop(&scene, &cfg, obs)
    };
    let chain = &scene.chain;
    let mut out = Measured::default();
    // A stop requested by the steady-state or margin watch is a `Stop`, not an error: the
    // outcome is the state at that time.
    let (u, v) = match res {
        Ok((_stop, o)) => {
            out.t_end = o.t_end;
            out.energy_error = o.relative_energy_error();
            out.steps = Some(o.stats.steps);
            // the dense engine logs no events: no count, rather than a count of 0
            out.events = (cfg.engine != Engine::Dense).then(|| o.events_total());
            (o.u, o.v)
        }
        Err(e) => return Err(e.into()),
    };
    let mut problems = Vec::new();
    if let Some(k) = m.interface {
        let sp = energy_split(chain, &u, &v, k);
        out.left_fraction = Some(sp.left / sp.total());
    }
    if let Some(d) = m.decay {
        match decay_fit(&watch, &d) {
            Ok(f) => out.gamma = Some((f.gamma, f.gamma_stderr)),
            Err(err) => problems.push(format!("decay fit: {err}")),
        }
    }
    if m.impurity.is_some() {
        match watch.velocity().checked() {
            Ok(r) => out.v_ratio = Some(r),
            Err(err) => problems.push(format!("v_ratio: {err}")),
        }
    }
    if let Some(g) = m.fragments {
        out.fragments = Some(fragmentation(chain, &u, &v, g).fragments.len());
    }
    Ok((out, (!problems.is_empty()).then(|| problems.join("; "))))
}

/// The leading wave's decay `E/E0 = a exp(−γ x)` over the tracked positions from `d.from`
/// (`E0` at bead `d.e0_bead`), cut where the energy jumps up by more than `d.jump`.
fn decay_fit(watch: &Watch, d: &Decay) -> Result<ExpFit, AnalysisError> {
    let e0 = watch
        .track
        .iter()
        .find(|p| p.1 >= d.e0_bead)
        .map_or(1.0, |p| p.2);
    let (mut x, mut e) = (Vec::new(), Vec::<f64>::new());
    for p in watch.track.iter().filter(|p| p.1 >= d.from) {
        if e.last().is_some_and(|&prev| p.2 / e0 > d.jump * prev) {
            break;
        }
        x.push(p.1 as f64);
        e.push(p.2 / e0);
    }
    fit_exponential(&x, &e)
}

/// The CSV row of a run (without newline).
pub fn format_row<E: std::fmt::Display>(
    spec: &SweepSpec,
    run: &RunPoint,
    result: &Result<(Measured, Option<String>), E>,
    wall: Option<f64>,
) -> String {
    let mut f = run.fields(spec);
    let e = |x: f64| format!("{x:e}");
    let o = |x: Option<String>| x.unwrap_or_default();
    let m = &spec.measure;
    match result {
        Err(msg) => {
            f.push(field(&format!("error: {msg}")));
            let n = csv::FIXED.len() - 1
                + usize::from(m.interface.is_some())
                + 2 * usize::from(m.decay.is_some())
                + usize::from(m.impurity.is_some())
                + usize::from(m.fragments.is_some());
            f.extend(std::iter::repeat_n(String::new(), n));
        }
        Ok((r, problem)) => {
            f.push(match problem {
                None => "ok".into(),
                Some(p) => field(&format!("error: {p}")),
            });
            f.push(e(r.t_end));
            f.push(e(r.energy_error));
            f.push(o(r.steps.map(|s| s.to_string())));
            f.push(o(r.events.map(|s| s.to_string())));
            if m.interface.is_some() {
                f.push(o(r.left_fraction.map(e)));
            }
            if m.decay.is_some() {
                f.push(o(r.gamma.map(|g| e(g.0))));
                f.push(o(r.gamma.map(|g| e(g.1))));
            }
            if m.impurity.is_some() {
                f.push(o(r.v_ratio.map(e)));
            }
            if m.fragments.is_some() {
                f.push(o(r.fragments.map(|x| x.to_string())));
            }
        }
    }
    if let Some(w) = wall {
        f.push(format!("{w:.3}"));
    }
    f.join(",")
}

/// Runs a sweep (or one shard of it) into `opts.out`, resuming from `OUT.partial`. Every run's
/// scene is built and checked first; a bad sweep fails before anything runs. `progress(done,
/// total)` is called after each run (from worker threads).
///
/// Stages: [`plan`] (check every run, this shard's runs and the CSV header), [`rows_done`]
/// (rows resumed or reused), [`run_pending`] (the rest, in parallel, each row appended to
/// `OUT.partial`), [`finish`] (the result file once every row is there).
pub fn run_sweep(
    spec: &SweepSpec,
    opts: &SweepOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<SweepSummary, SweepError> {
    let Plan {
        keyed,
        keys,
        spec_line,
        partial_line,
        columns,
        mine,
    } = plan(spec, opts)?;
    csv::check_destinations(&opts.out)?;
    super::shard::check_other_shards((&opts.out, opts.shard), &spec_line, &mine)?;
    let (partial, done, resumed, skipped) =
        rows_done(spec, opts, keyed, &mine, &partial_line, &columns)?;
    let mut pending: Vec<&RunPoint> = mine
        .iter()
        .filter(|r| !done.contains_key(&r.index))
        .collect();
    if let Some(mx) = opts.max_runs {
        pending.truncate(mx);
    }
    let rows = run_pending(spec, opts, &pending, &partial, done, mine.len(), progress)?;
    let failed = rows.values().filter(|r| is_error_row(r)).count();
    let complete = rows.len() == mine.len();
    let written = complete && finish(opts, &partial, &partial_line, &keys, &columns, &rows)?;
    Ok(SweepSummary {
        runs: mine.len(),
        resumed,
        skipped,
        ran: pending.len(),
        failed,
        complete,
        written,
    })
}

/// Line 1 of `OUT.partial` and of `OUT.meta`: the spec line and a hash of the content keys of
/// every run of the sweep (`inputs=HASH`; every shard's alike). The spec hash covers the sweep
/// file and the base scene's text only; the keys also see the CSV files the scene reads, so
/// rows written before such a file changed are not resumed as if they were this sweep's, and
/// `merge` refuses shards run on different inputs.
pub fn partial_spec_line(spec_line: &str, all: &[(RunPoint, u64)]) -> String {
    let text: String = all
        .iter()
        .map(|(r, k)| format!("{}:{k:016x};", r.index))
        .collect();
    format!("{spec_line} inputs={:016x}", super::fnv1a(text.as_bytes()))
}

/// What a sweep (shard) runs, before anything runs: its runs with their content keys, the keys
/// by run index, the result file's spec line (and the partial file's, [`partial_spec_line`])
/// and column header.
struct Plan {
    keyed: Vec<(RunPoint, u64)>,
    keys: BTreeMap<usize, u64>,
    spec_line: String,
    partial_line: String,
    columns: String,
    mine: Vec<RunPoint>,
}

/// Checks every run of the sweep ([`SweepSpec::check_all_keyed`]) and keeps this shard's.
fn plan(spec: &SweepSpec, opts: &SweepOptions) -> Result<Plan, SweepError> {
    let all = spec.check_all_keyed()?;
    let total = all.len();
    let spec_line = csv::spec_line(spec.hash, total);
    let partial_line = partial_spec_line(&spec_line, &all);
    let keyed: Vec<(RunPoint, u64)> = all
        .into_iter()
        .filter(|(r, _)| opts.shard.is_none_or(|s| s.contains(r.index)))
        .collect();
    let keys: BTreeMap<usize, u64> = keyed.iter().map(|(r, k)| (r.index, *k)).collect();
    let columns = csv::columns(spec, opts.timing)
        .iter()
        .map(|c| field(c))
        .collect::<Vec<_>>()
        .join(",");
    let mine: Vec<RunPoint> = keyed.iter().map(|(r, _)| r.clone()).collect();
    Ok(Plan {
        keyed,
        keys,
        spec_line,
        partial_line,
        columns,
        mine,
    })
}

/// Runs `pending` on a pool of `opts.jobs` threads, appending each row to `partial` as it
/// finishes; returns every row (`done` and the new ones) by run index. `n_mine` is the shard's
/// run count, for `progress`.
fn run_pending(
    spec: &SweepSpec,
    opts: &SweepOptions,
    pending: &[&RunPoint],
    partial: &Path,
    done: BTreeMap<usize, String>,
    n_mine: usize,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<BTreeMap<usize, String>, SweepError> {
    let done_now = done.len();
    let file = open_append(partial)?;
    let sink = Mutex::new((file, done, done_now));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.jobs.unwrap_or(0))
        .build()
        .map_err(|e| SweepError::Options(format!("--jobs: {e}")))?;
    progress(done_now, n_mine);
    let result = pool.install(|| {
        use rayon::prelude::*;
        pending
            .par_iter()
            .try_for_each(|run| -> Result<(), SweepError> {
                let t0 = Instant::now();
                let res = run_caught(spec, run);
                let wall = opts.timing.then(|| t0.elapsed().as_secs_f64());
                let row = format_row(spec, run, &res, wall);
                let mut g = sink
                    .lock()
                    .map_err(|_| SweepError::Options("a worker thread failed".into()))?;
                let (file, rows, count) = &mut *g;
                append_row(file, partial, &row)?;
                rows.insert(run.index, row);
                *count += 1;
                progress(*count, n_mine);
                Ok(())
            })
    });
    result?;
    let (_, rows, _) = sink
        .into_inner()
        .map_err(|_| SweepError::Options("a worker thread failed".into()))?;
    Ok(rows)
}

/// Writes the complete result file `opts.out` (rows in run order) and removes `partial`;
/// whether the result file was written ([`csv::write_result`]).
fn finish(
    opts: &SweepOptions,
    partial: &Path,
    spec_line: &str,
    keys: &BTreeMap<usize, u64>,
    columns: &str,
    rows: &BTreeMap<usize, String>,
) -> Result<bool, SweepError> {
    let written = csv::write_result(&opts.out, spec_line, keys, columns, rows)?;
    std::fs::remove_file(partial).map_err(|e| SweepError::Io {
        file: partial.display().to_string(),
        action: "cannot remove".into(),
        reason: e.to_string(),
    })?;
    Ok(written)
}

/// The rows done before anything runs: those of `OUT.partial` ([`resume_partial`]), then those
/// the finished `OUT` holds for the other runs (by content key, [`reusable_rows`]); the partial
/// file is rewritten with them (dropping a line cut short) so rows can be appended. Returns the
/// partial file, the rows, and how many came from each.
fn rows_done(
    spec: &SweepSpec,
    opts: &SweepOptions,
    keyed: Vec<(RunPoint, u64)>,
    mine: &[RunPoint],
    spec_line: &str,
    columns: &str,
) -> Result<(PathBuf, BTreeMap<usize, String>, usize, usize), SweepError> {
    let (partial, mut done) = resume_partial(spec, opts, mine, spec_line, columns)?;
    let resumed = done.len();
    let todo: Vec<(RunPoint, u64)> = keyed
        .into_iter()
        .filter(|(r, _)| !done.contains_key(&r.index))
        .collect();
    let reused = reusable_rows(spec, &todo, &opts.out, columns);
    let skipped = reused.len();
    done.extend(reused);
    csv::write_atomic(&partial, csv::render(spec_line, columns, &done).as_bytes())?;
    Ok((partial, done, resumed, skipped))
}

/// The partial result file `OUT.partial` and the rows it already holds (checked against this
/// sweep; the caller rewrites it cleanly, dropping a line cut short, before appending rows).
fn resume_partial(
    spec: &SweepSpec,
    opts: &SweepOptions,
    mine: &[RunPoint],
    spec_line: &str,
    columns: &str,
) -> Result<(PathBuf, BTreeMap<usize, String>), SweepError> {
    let partial = partial_path(&opts.out);
    let mut done: BTreeMap<usize, String> = BTreeMap::new();
    if partial.exists() {
        let old = csv::read_result(&partial, true)?;
        check_partial(spec, &partial, &old, spec_line, columns, mine)?;
        done = old.rows;
    }
    Ok((partial, done))
}

/// Opens the partial file for appending rows.
fn open_append(partial: &Path) -> Result<std::fs::File, SweepError> {
    std::fs::OpenOptions::new()
        .append(true)
        .open(partial)
        .map_err(|e| SweepError::Io {
            file: partial.display().to_string(),
            action: "cannot open for appending".into(),
            reason: e.to_string(),
        })
}

/// [`run_one`], with a panic turned into the run's error (`panic: MESSAGE`).
fn run_caught(spec: &SweepSpec, run: &RunPoint) -> Result<(Measured, Option<String>), RunError> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| run_one(spec, run))).unwrap_or_else(
        |p| {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            Err(RunError::Panic(msg))
        },
    )
}

/// Appends one result row to the partial file and flushes it (a resumed sweep keeps it).
fn append_row(file: &mut std::fs::File, partial: &Path, row: &str) -> Result<(), SweepError> {
    file.write_all(format!("{row}\n").as_bytes())
        .and_then(|_| file.flush())
        .map_err(|e| SweepError::Io {
            file: partial.display().to_string(),
            action: "cannot append a row".into(),
            reason: e.to_string(),
        })
}

fn is_error_row(row: &str) -> bool {
    row.contains(",error: ") || row.contains(",\"error: ")
}

/// Rows of an existing partial file must belong to this sweep, shard and parameters.
fn check_partial(
    spec: &SweepSpec,
    path: &Path,
    old: &ResultFile,
    spec_line: &str,
    columns: &str,
    mine: &[RunPoint],
) -> Result<(), SweepError> {
    let bad = |line: usize, message: String| SweepError::Csv {
        file: path.display().to_string(),
        line,
        message,
    };
    let spec_of = csv::spec_part;
    let legacy = csv::inputs_part(&old.spec_line).is_none();
    if old.spec_line != spec_line && !legacy && spec_of(&old.spec_line) == spec_of(spec_line) {
        return Err(bad(
            1,
            format!("its runs' content keys differ from this sweep's: a file its scene reads changed (a CSV file), or another beadchain version wrote it (this is {}), so its rows are not this sweep's results; delete it or choose another --out", crate::provenance::VERSION),
        ));
    }
    // a partial file of a build before the inputs hash: its spec line alone, as then
    if spec_of(&old.spec_line) != spec_of(spec_line) {
        return Err(bad(
            1,
            format!(
                "written by a different sweep spec (`{}`, this sweep: `{spec_line}`): the sweep file or its scene changed; delete it or choose another --out",
                old.spec_line
            ),
        ));
    }
    if old.columns != columns {
        return Err(bad(
            2,
            "its columns differ from this sweep's (e.g. --timing changed); delete it or choose another --out".into(),
        ));
    }
    let np = spec.param_columns().len();
    for (i, row) in &old.rows {
        let Ok(pos) = mine.binary_search_by_key(i, |r| r.index) else {
            return Err(bad(0, format!("run {i} is not a run of this sweep/shard")));
        };
        let run = &mine[pos];
        let fields = csv::split_fields(row).map_err(|m| bad(0, m.to_string()))?;
        let expect = format_row(spec, run, &Err(String::new()), None);
        let expect = csv::split_fields(&expect).map_err(|m| bad(0, m.to_string()))?;
        if fields[1..=np] != expect[1..=np] {
            return Err(bad(
                0,
                format!(
                    "run {i}: its parameters differ from this sweep's ({})",
                    run.describe()
                ),
            ));
        }
    }
    Ok(())
}
