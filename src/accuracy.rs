//! Work–precision study: what each digit of accuracy costs on a scene.
//!
//! [`accuracy_study`] runs every combination of engines × methods × tolerances to the scene's end
//! time and compares the final state `(u, v)` with a reference solution:
//!
//! - **Reference**: the dense engine with Radau IIA at `reference_rtol` (default: the smallest
//!   `rtol` of the study, so the tightest dense Radau run *is* the reference and its error is 0).
//!   It is checked against the dense Radau run at the next looser tolerance (the second tightest;
//!   ×10 when there is none, at most `√rtol`, so always looser and below 1) and that difference
//!   is reported: errors below it are not resolved. Scenes with hard contacts or walls are
//!   refused: the dense engine cannot run them.
//! - **Error** of a run: `err_u = max_i |u_i − u_ref,i| / max_{i,t} |u_ref,i(t) − u0_i|` and
//!   `err_v = max_i |v_i − v_ref,i| / max_{i,t} |v_ref,i(t)|`, the scales the reference's motion
//!   over the run (its initial state, 256 frames and final state, [`Amplitude`]; the final
//!   state alone was the scale until a breather run for whole periods, back where it started,
//!   read errors 1e5 where they were 2e-5); `error = max(err_u, err_v)`.
//! - **Energy**: relative total-energy error between start and end `|E_end − E_0| / |E_0|`
//!   (energy = kinetic + contact potential, paper eq. 1), and the paper's appendix-A measure,
//!   the kinetic-energy error `|KE_0 − KE_end| / KE_0` (meaningful once the chain has separated,
//!   when the potential energy has returned to zero).
//! - **Cost**: wall time (median of `repeat` runs), accepted steps, rejected steps, right-hand
//!   sides, events (hybrid), active bead-steps.
//!
//! Tolerances: each run uses `rtol` and the `atol` that `beadchain run --rtol RTOL` would use
//! ([`default_atol`]: the scene's `[run] atol`, else `rtol/10⁴`, at least 1e-15), so a row is
//! what that run does; `atol_ratio` sets `atol = atol_ratio · rtol` instead (in units of the
//! characteristic scales, see [`crate::integrate`]). (Issue 36: the study's default was
//! `rtol/100`, so its "hybrid auto 1e-8" row took 707 steps where `run --rtol 1e-8` takes 920.) The fixed-step velocity Verlet method has no tolerance: its
//! accuracy knob is the step, taken from `verlet_steps` in units of the characteristic time
//! `τ = L/V` (`dt = s · τ`, passed as its `rtol`, see [`crate::integrate::verlet`]).
//!
//! Output (when `out_dir` is set): `accuracy.csv` (one row per run, columns [`CSV_HEADER`]) and a
//! log–log plot of error against wall time, one line per engine/method, `accuracy.svg` and
//! `accuracy.png` ([`plot`]).

pub mod plot;
mod report;

use crate::names::Named;
use report::write_outputs;
pub use report::{format_table, to_csv};

use crate::engine::{self, Amplitude, EngineError, Observer, RunConfig, RunOutcome};
use crate::integrate::Method;
use crate::linalg::SolverKind;
use crate::scene::{Engine, Scene};
use std::path::PathBuf;
use std::time::Instant;

/// What to run.
#[derive(Clone, Debug)]
pub struct AccuracyOptions {
    /// Engines (default: hybrid, dense).
    pub engines: Vec<Engine>,
    /// Methods (default: radau5, dop853, verlet).
    pub methods: Vec<Method>,
    /// Relative tolerances of the adaptive methods (default 1e-4, 1e-6, 1e-8, 1e-10).
    pub rtols: Vec<f64>,
    /// Steps of the Verlet runs in units of `τ = L/V` (default 0.1, 0.03, 0.01, 0.003).
    pub verlet_steps: Vec<f64>,
    /// `atol = atol_ratio · rtol` for every run; `None` (default): `run`'s default
    /// ([`default_atol`]).
    pub atol_ratio: Option<f64>,
    /// End time (default: the scene's `until`).
    pub until: Option<f64>,
    /// Timed repetitions per run; the median wall time is reported (default 1).
    pub repeat: usize,
    /// Tolerance of the dense Radau reference (default: the smallest of `rtols`).
    pub reference_rtol: Option<f64>,
    /// Linear solver of the implicit method.
    pub solver: SolverKind,
    /// Step budget per run (a run that exceeds it is reported as failed).
    pub max_steps: Option<u64>,
    /// Directory for `accuracy.csv`, `accuracy.svg`, `accuracy.png` (`None`: write nothing).
    pub out_dir: Option<PathBuf>,
    /// Progress bar fed by every run (`None`: none).
    pub progress: Option<crate::progress::RunProgress>,
}

impl Default for AccuracyOptions {
    fn default() -> Self {
        Self {
            engines: vec![Engine::Hybrid, Engine::Dense],
            methods: vec![Method::Auto, Method::Radau5, Method::Dop853, Method::Verlet],
            rtols: vec![1e-4, 1e-6, 1e-8, 1e-10],
            verlet_steps: vec![0.1, 0.03, 0.01, 0.003],
            atol_ratio: None,
            until: None,
            repeat: 1,
            reference_rtol: None,
            solver: SolverKind::Auto,
            max_steps: Some(50_000_000),
            out_dir: None,
            progress: None,
        }
    }
}

/// Why a study failed (single runs that fail are reported in their row instead).
#[derive(Debug, thiserror::Error)]
pub enum AccuracyError {
    /// Unusable options.
    #[error("accuracy study: {0}")]
    Options(String),
    /// The reference (or its check) run failed.
    #[error("accuracy study: reference run (dense radau5, rtol {rtol:e}) failed: {source}")]
    Reference {
        /// Tolerance of the failed run.
        rtol: f64,
        /// The engine error.
        source: EngineError,
    },
    /// Writing an output file failed.
    #[error("accuracy study: writing {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// Drawing the plot failed.
    #[error("accuracy study: plotting {path}: {msg}")]
    Plot {
        /// The file.
        path: PathBuf,
        /// What the plotting backend said.
        msg: String,
    },
}

/// The reference solution and its self-check.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceInfo {
    /// Tolerance of the reference (dense Radau IIA).
    pub rtol: f64,
    /// Tolerance of the check run (the second tightest dense Radau run).
    pub check_rtol: f64,
    /// Error of the check run against the reference (relative u part).
    pub check_err_u: f64,
    /// Error of the check run against the reference (relative v part).
    pub check_err_v: f64,
    /// Wall time of the reference run (one run).
    pub wall_seconds: f64,
}

/// One run of the study.
#[derive(Clone, Debug, PartialEq)]
pub struct AccuracyRow {
    /// Engine.
    pub engine: Engine,
    /// Method.
    pub method: Method,
    /// Relative tolerance (Verlet: the step in units of `τ`).
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
    /// Verlet only: the step in time units (`rtol · τ`).
    pub verlet_dt: Option<f64>,
    /// `None` on success, else the error message of the failed run.
    pub failure: Option<String>,
    /// True for the run that is the reference itself.
    pub is_reference: bool,
    /// Relative displacement error (see module docs).
    pub err_u: f64,
    /// Relative velocity error.
    pub err_v: f64,
    /// `max(err_u, err_v)`.
    pub error: f64,
    /// Relative total-energy error start → end.
    pub energy_error: f64,
    /// Relative kinetic-energy error start → end (paper appendix A); NaN when the reference's
    /// final state is not separated (contact potential energy above [`SEPARATED_PE_FRACTION`] of
    /// the total, or a field or wall acting), where the measure means nothing.
    pub ke_error: f64,
    /// Median wall time in seconds.
    pub wall_seconds: f64,
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
    /// Events (hybrid engine; 0 for dense).
    pub events: u64,
    /// Active bead-steps.
    pub bead_steps: u64,
}

/// The whole study.
#[derive(Clone, Debug, PartialEq)]
pub struct AccuracyReport {
    /// Scene name.
    pub scene: String,
    /// Number of beads.
    pub beads: usize,
    /// End time.
    pub until: f64,
    /// Characteristic time `τ = L/V` (unit of the Verlet steps).
    pub tau: f64,
    /// The reference.
    pub reference: ReferenceInfo,
    /// One row per run, in the order engines × methods × tolerances.
    pub rows: Vec<AccuracyRow>,
    /// Remarks (e.g. plot drawn without text).
    pub notes: Vec<String>,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// Column names of `accuracy.csv`.
pub const CSV_HEADER: &str = "engine,method,rtol,atol,verlet_dt,status,is_reference,err_u,err_v,error,energy_error,ke_error,wall_seconds,steps,rejected,rhs_evals,events,bead_steps";

/// An observer that keeps nothing.
struct Discard;

impl Observer for Discard {
    fn frame(&mut self, _t: f64, _u: &[f64], _v: &[f64]) -> Result<(), EngineError> {
        Ok(())
    }
}

/// Runs once, timing the whole call.
/// One run and its wall time; with `amp`, its frames sample the motion's amplitude (read from
/// the continuous output: the steps and the final state are those of a run without frames).
fn timed_run(
    scene: &Scene,
    cfg: &RunConfig,
    (bar, amp): (
        Option<&crate::progress::RunProgress>,
        Option<&mut Amplitude>,
    ),
) -> Result<(RunOutcome, f64), EngineError> {
    let mut cfg = cfg.clone();
    cfg.every = amp.as_ref().map(|_| Amplitude::every(cfg.until));
    let mut discard = Discard;
    let obs: &mut dyn Observer = match amp {
        Some(a) => a,
        None => &mut discard,
    };
    let start = Instant::now();
    let out = match bar {
        Some(b) => {
            let label = format!(
                "{} {} rtol {:e}: ",
                cfg.engine.name(),
                cfg.method.name(),
                cfg.rtol
            );
            engine::run(scene, &cfg, &mut b.watch(obs, 0.0, cfg.until, &label))?
        }
        None => engine::run(scene, &cfg, obs)?,
    };
    Ok((out, start.elapsed().as_secs_f64()))
}

/// Median of a non-empty list.
fn median(xs: &mut [f64]) -> f64 {
    xs.sort_by(f64::total_cmp);
    let k = xs.len();
    if k % 2 == 1 {
        xs[k / 2]
    } else {
        0.5 * (xs[k / 2 - 1] + xs[k / 2])
    }
}

/// Relative errors `(err_u, err_v)` of the final state `(u, v)` against the reference outcome
/// `r`, relative to the reference's motion `amp` (see module docs). Non-finite states give
/// infinity.
pub fn relative_errors(amp: &Amplitude, r: &RunOutcome, u: &[f64], v: &[f64]) -> (f64, f64) {
    let (umax, vmax) = (amp.length, amp.velocity);
    let du = u
        .iter()
        .zip(&r.u)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    let dv = v
        .iter()
        .zip(&r.v)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    let rel = |d: f64, s: f64| if s > 0.0 { d / s } else { d };
    // f64::max ignores NaN: a non-finite state is an infinite error.
    if u.iter().chain(v).all(|x| x.is_finite()) {
        (rel(du, umax), rel(dv, vmax))
    } else {
        (f64::INFINITY, f64::INFINITY)
    }
}

fn check_options(opts: &AccuracyOptions) -> Result<(), AccuracyError> {
    let bad = |s: String| Err(AccuracyError::Options(s));
    if opts.engines.is_empty() || opts.methods.is_empty() {
        return bad("no engine or no method given".into());
    }
    let adaptive = opts.methods.iter().any(|&m| m != Method::Verlet);
    if adaptive && opts.rtols.is_empty() {
        return bad("no tolerance given".into());
    }
    if opts.methods.contains(&Method::Verlet) && opts.verlet_steps.is_empty() {
        return bad("no Verlet step given".into());
    }
    let in_unit = |x: f64| x > 0.0 && x < 1.0;
    for &r in opts.rtols.iter().chain(&opts.reference_rtol) {
        if !in_unit(r) {
            return bad(format!("rtol {r} must be in (0, 1)"));
        }
    }
    for &s in &opts.verlet_steps {
        if !in_unit(s) {
            return bad(format!(
                "Verlet step {s} (in units of L/V) must be in (0, 1)"
            ));
        }
    }
    if let Some(r) = opts.atol_ratio.filter(|r| !(*r > 0.0 && *r <= 1.0)) {
        return bad(format!("atol ratio {r} must be in (0, 1]"));
    }
    if opts.repeat == 0 {
        return bad("repeat must be at least 1".into());
    }
    if let Some(t) = opts.until {
        if !(t > 0.0 && t.is_finite()) {
            return bad(format!("until = {t} must be positive and finite"));
        }
    }
    Ok(())
}

/// The `atol` of a run at `rtol`: `ratio · rtol` (at most 0.5) when a ratio is given, else what
/// `beadchain run --rtol RTOL` uses: the scene's `[run] atol`, else
/// [`crate::integrate::default_atol`] (`rtol/10⁴`, at least 1e-15).
pub fn default_atol(scene: &Scene, ratio: Option<f64>, rtol: f64) -> f64 {
    match ratio {
        Some(r) => (r * rtol).min(0.5),
        None => {
            let at_rtol = crate::engine::RunOverrides {
                rtol: Some(rtol),
                ..Default::default()
            };
            RunConfig::with_overrides(scene, &at_rtol).atol
        }
    }
}

/// Tolerances of the dense Radau reference (`--reference-rtol`, else the smallest `rtols`) and
/// of its check run (the next larger `rtols`, else ten times the reference's, at most 0.1).
fn reference_tolerances(opts: &AccuracyOptions) -> (f64, f64) {
    let mut sorted = opts.rtols.clone();
    sorted.sort_by(f64::total_cmp);
    sorted.dedup();
    let ref_rtol = opts
        .reference_rtol
        .or_else(|| sorted.first().copied())
        .unwrap_or(1e-10);
    let check_rtol = sorted
        .iter()
        .copied()
        .find(|&r| r > ref_rtol)
        .unwrap_or((10.0 * ref_rtol).min(ref_rtol.sqrt()));
    (ref_rtol, check_rtol)
}

/// Runs the study (see module docs). Runs that fail are reported in their row; the study fails
/// only on bad options, a failed reference, or an output file that cannot be written.
pub fn accuracy_study(
    scene: &Scene,
    opts: &AccuracyOptions,
) -> Result<AccuracyReport, AccuracyError> {
    check_options(opts)?;
    if scene.chain.has_hard() {
        return Err(AccuracyError::Options(
            "the reference is the dense engine (Radau IIA), which has no hard contacts or walls; this scene cannot be studied here (`check` compares hard scenes against the hybrid engine's other method family)".into(),
        ));
    }
    if let Some(dir) = &opts.out_dir {
        report::check_outputs(dir)?;
    }
    let mut base = RunConfig::from_scene(scene);
    base.until = opts.until.unwrap_or(scene.run.until);
    base.every = None;
    base.solver = opts.solver;
    base.max_steps = opts.max_steps;
    let cfg_for = |engine: Engine, method: Method, rtol: f64| RunConfig {
        engine,
        method,
        rtol,
        atol: default_atol(scene, opts.atol_ratio, rtol),
        ..base.clone()
    };

    // Reference and its check.
    let (ref_rtol, check_rtol) = reference_tolerances(opts);
    let run_ref = |rtol: f64, amp: Option<&mut Amplitude>| {
        timed_run(
            scene,
            &cfg_for(Engine::Dense, Method::Radau5, rtol),
            (opts.progress.as_ref(), amp),
        )
        .map_err(|source| AccuracyError::Reference { rtol, source })
    };
    let mut amp = Amplitude::new(&scene.u0, &scene.v0);
    let (reference, ref_wall) = run_ref(ref_rtol, Some(&mut amp))?;
    // the final state counts too (the last frame is the end time, unless rounding moved it)
    amp.frame(base.until, &reference.u, &reference.v)
        .expect("an amplitude takes every frame");
    let (check, _) = run_ref(check_rtol, None)?;
    let (check_err_u, check_err_v) = relative_errors(&amp, &reference, &check.u, &check.v);

    let chain = &scene.chain;
    let ke0 = chain.kinetic_energy(&scene.v0);
    let tau = chain.scales(&scene.u0, &scene.v0).time();
    let mut rows = Vec::new();
    for &engine in &opts.engines {
        for &method in &opts.methods {
            let knobs = if method == Method::Verlet {
                &opts.verlet_steps
            } else {
                &opts.rtols
            };
            for &rtol in knobs {
                let cfg = cfg_for(engine, method, rtol);
                let mut row = measure(scene, &cfg, opts, (&reference, &amp), ke0, tau);
                row.is_reference =
                    engine == Engine::Dense && method == Method::Radau5 && rtol == ref_rtol;
                rows.push(row);
            }
        }
    }
    let mut report = AccuracyReport {
        scene: scene.name.clone(),
        beads: chain.len(),
        until: base.until,
        tau,
        reference: ReferenceInfo {
            rtol: ref_rtol,
            check_rtol,
            check_err_u,
            check_err_v,
            wall_seconds: ref_wall,
        },
        rows,
        notes: Vec::new(),
        files: Vec::new(),
    };
    if let Some(dir) = &opts.out_dir {
        write_outputs(&mut report, dir)?;
    }
    Ok(report)
}

/// Runs one configuration `repeat` times and measures it against the reference.
fn measure(
    scene: &Scene,
    cfg: &RunConfig,
    opts: &AccuracyOptions,
    (reference, amp): (&RunOutcome, &Amplitude),
    ke0: f64,
    tau: f64,
) -> AccuracyRow {
    let mut row = AccuracyRow {
        engine: cfg.engine,
        method: cfg.method,
        rtol: cfg.rtol,
        atol: cfg.atol,
        verlet_dt: (cfg.method == Method::Verlet).then_some(cfg.rtol * tau),
        failure: None,
        is_reference: false,
        err_u: f64::NAN,
        err_v: f64::NAN,
        error: f64::NAN,
        energy_error: f64::NAN,
        ke_error: f64::NAN,
        wall_seconds: f64::NAN,
        steps: 0,
        rejected: 0,
        rhs_evals: 0,
        events: 0,
        bead_steps: 0,
    };
    let mut walls = Vec::with_capacity(opts.repeat);
    let mut last = None;
    for _ in 0..opts.repeat {
        match timed_run(scene, cfg, (opts.progress.as_ref(), None)) {
            Ok((out, wall)) => {
                walls.push(wall);
                last = Some(out);
            }
            Err(e) => {
                row.failure = Some(e.to_string());
                return row;
            }
        }
    }
    let Some(out) = last else {
        return row;
    };
    let (eu, ev) = relative_errors(amp, reference, &out.u, &out.v);
    row.err_u = eu;
    row.err_v = ev;
    row.error = eu.max(ev);
    row.energy_error = out.relative_energy_error();
    // undefined (n/a) where the chain starts without kinetic energy
    if ke0 > 0.0 && separated(&scene.chain, &reference.u, &reference.v) {
        row.ke_error = (ke0 - scene.chain.kinetic_energy(&out.v)).abs() / ke0;
    }
    row.wall_seconds = median(&mut walls);
    row.steps = out.stats.steps;
    row.rejected = out.stats.rejected;
    row.rhs_evals = out.stats.rhs_evals;
    row.events = out.events_total();
    row.bead_steps = out.stats.bead_steps;
    row
}

/// Contact potential energy below this fraction of the total energy counts as separated: the
/// kinetic-energy error then differs from the total-energy error by less than any run resolves.
pub const SEPARATED_PE_FRACTION: f64 = 1e-12;

/// Whether `(u, v)` is the appendix-A "final separated state": no field, no walls, and the contact
/// potential energy below [`SEPARATED_PE_FRACTION`] of the total (the wave has left; slow beads
/// may still touch with overlaps of rounding size).
fn separated(chain: &crate::model::Chain, u: &[f64], v: &[f64]) -> bool {
    if chain.field.is_some() || chain.left_wall.is_some() || chain.right_wall.is_some() {
        return false;
    }
    let pe = chain.potential_energy(u);
    pe <= SEPARATED_PE_FRACTION * (pe + chain.kinetic_energy(v))
}

#[cfg(test)]
#[path = "accuracy_tests.rs"]
mod tests;
