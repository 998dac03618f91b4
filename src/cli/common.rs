//! Pieces every run-like command shares: the engine/method/solver arguments, the run
//! configuration from a scene and the command line, loading a scene with its warnings, and the
//! run summary printed by `run` and `resume`. Imports nothing else from the CLI.

use anyhow::Result;
use beadchain::engine::{RunConfig, RunOutcome, RunOverrides};
use beadchain::integrate::Method;
use beadchain::linalg::SolverKind;
use beadchain::names::Named;
use beadchain::scene::plausible::BeadMaterial;
use beadchain::scene::{self, Scene};
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use std::io::Write;

/// clap's parser for a [`Named`] value (method, engine, solver): its names are the possible
/// values, with their help, so `--help` lists them and a wrong one gets clap's message with the
/// valid values and "did you mean".
pub fn named<T: Named + Send + Sync>() -> impl clap::builder::TypedValueParser<Value = T> {
    let values = T::ALL.iter().map(|v| {
        let p = PossibleValue::new(v.name());
        match v.help() {
            "" => p,
            h => p.help(h),
        }
    });
    PossibleValuesParser::new(values).map(|s| T::parse(&s).expect("clap checked the name"))
}

#[derive(clap::Args, Debug)]
pub struct Common {
    /// Scene file (TOML) or preset name (see `beadchain scenes`).
    pub scene: String,
    /// Integration method [default: the scene's, else auto].
    #[arg(long, value_parser = named::<Method>())]
    pub method: Option<Method>,
    /// Relative tolerance [default: the scene's, else 1e-8].
    #[arg(long)]
    pub rtol: Option<f64>,
    /// Absolute tolerance, relative to the run's characteristic length/velocity
    /// [default: the scene's, else rtol/10^4, at least 1e-15 (1e-12 at the default rtol)].
    #[arg(long)]
    pub atol: Option<f64>,
    /// End time, computer units; --until-si for seconds [default: the scene's `[run] until`].
    #[arg(long)]
    pub until: Option<f64>,
    /// End time in seconds (physical scenes: divided by the scene's time unit β).
    #[arg(long, conflicts_with = "until")]
    pub until_si: Option<f64>,
    /// Linear solver of the implicit method.
    #[arg(long, value_parser = named::<SolverKind>(), default_value = "auto")]
    pub solver: SolverKind,
    /// Abort after this many integrator steps.
    #[arg(long)]
    pub max_steps: Option<u64>,
    /// No progress bar (it is shown only when standard error is a terminal).
    #[arg(short, long)]
    pub quiet: bool,
}

/// Below this relative tolerance, rounding in f64 (≈ 1.1e-16 per operation, accumulated over a
/// step's stages) dominates the error estimate: a warning, not an error.
const RTOL_F64_FLOOR: f64 = 1e-14;

/// Loads a scene (file or preset) and prints its validation warnings on standard error (each
/// warning already names the scene: `beadchain: warning: NAME: KEY: ...`).
pub fn load_scene(spec: &str) -> Result<Scene> {
    load_scene_with_material(spec).map(|p| p.scene)
}

/// [`load_scene`], with what the resolved scene does not keep (the SI bead material of a
/// physical scene and the key of its end time, for [`warn_implausible`]).
/// Also prints the warnings of the scene's construction ([`scene::Parsed::warnings`]: the gaps
/// that `[initial] equilibrium = true` leaves).
pub fn load_scene_with_material(spec: &str) -> Result<scene::Parsed> {
    let parsed = scene::load_full(spec).map_err(not_found_hint)?;
    for w in parsed
        .warnings
        .iter()
        .chain(&scene::validate(&parsed.scene)?)
    {
        eprintln!("beadchain: warning: {w}");
    }
    Ok(parsed)
}

/// A scene that is neither a file nor a preset: the nearest preset names instead of the whole
/// list ([`beadchain::suggest::preset_hint`]); other errors unchanged.
fn not_found_hint(e: scene::SceneError) -> anyhow::Error {
    match e {
        scene::SceneError::NotFound { spec, .. } => anyhow::anyhow!(
            "{spec}: no such scene file, and no preset of that name{}",
            beadchain::suggest::preset_hint(&spec)
        ),
        other => other.into(),
    }
}

/// [`beadchain::engine::check_config`] for a run of the scene file `what` (the prefix of its
/// error, control characters escaped). An engine or method it refuses that the scene's own
/// `[run]` chose (the command line did not: `engine_given`, `method_given`) is named by that
/// key, with both ways out.
pub fn check_config(
    what: &str,
    scene: &Scene,
    cfg: &RunConfig,
    (engine_given, method_given): (bool, bool),
) -> Result<()> {
    use beadchain::engine::{unrunnable, Unrunnable};
    let what = scene::error::one_line(what);
    match unrunnable(scene, cfg) {
        Some(Unrunnable::DenseOnHard) if !engine_given => anyhow::bail!(
            "{what}: [run].engine: \"dense\" cannot run this scene: it declares hard contacts or walls, which only the hybrid engine handles (set engine = \"hybrid\" or pass --engine hybrid)"
        ),
        Some(Unrunnable::VerletOnDamped) if !method_given => anyhow::bail!(
            "{what}: [run].method: \"verlet\" does not integrate velocity-dependent (damped) contacts; set method = \"auto\", \"dop853\" or \"radau5\", or pass --method"
        ),
        _ => {}
    }
    beadchain::engine::check_config(scene, cfg).map_err(|e| anyhow::anyhow!("{what}: {e}"))
}

/// Prints the warnings of [`scene::plausible`] (a physical scene whose plain numbers look like
/// SI values: a striker faster than sound, a run shorter than one contact, ...) for a run to
/// `cfg.until`.
pub fn warn_implausible(
    scene: &Scene,
    material: Option<&BeadMaterial>,
    until_key: &str,
    cfg: &RunConfig,
    c: &Common,
) {
    let key = GivenTime::until(c, until_key, scene).key;
    for w in scene::plausible::warnings(scene, material, cfg.until, key) {
        eprintln!("beadchain: warning: {w}");
    }
}

/// Where a run's end time or output interval came from, as messages name it: the command
/// line's option (`--until`, `--until-si`, `--every`, `--every-si`) or the scene's own key
/// (`[run].until`, `[run].every_si`, …); `beta` is the scene's time unit in seconds where the
/// time was given in seconds.
pub struct GivenTime<'a> {
    pub key: &'a str,
    pub beta: Option<f64>,
}

impl<'a> GivenTime<'a> {
    /// `key`, in seconds when it ends in `_si`/`-si`.
    pub fn new(key: &'a str, scene: &Scene) -> Self {
        let si = key.ends_with("_si") || key.ends_with("-si");
        Self {
            key,
            beta: scene.units.filter(|_| si).map(|u| u.time),
        }
    }

    /// The end time: the command line's `--until`/`--until-si`, else `scene_key` (the parsed
    /// scene's).
    pub fn until(c: &Common, scene_key: &'a str, scene: &Scene) -> Self {
        let given = [(c.until, "--until"), (c.until_si, "--until-si")];
        Self::given(given, scene_key, scene)
    }

    /// The output interval: `--every`/`--every-si` where given (`cli`), else `scene_key`.
    pub fn every(cli: (Option<f64>, Option<f64>), scene_key: &'a str, scene: &Scene) -> Self {
        let given = [(cli.0, "--every"), (cli.1, "--every-si")];
        Self::given(given, scene_key, scene)
    }

    /// The first option given, else `scene_key`.
    fn given(options: [(Option<f64>, &'a str); 2], scene_key: &'a str, scene: &Scene) -> Self {
        let key = options.iter().find(|(x, _)| x.is_some());
        Self::new(key.map_or(scene_key, |&(_, k)| k), scene)
    }

    /// `x` (computer units) as given: in seconds, then in computer units, where it was given
    /// in seconds (`1.0000e-4 s = 110.4 computer units`).
    pub fn shown(&self, x: f64) -> String {
        use beadchain::snapshot::size::short;
        match self.beta {
            Some(b) => beadchain::snapshot::size::seconds_then_units(x, b),
            None => short(x),
        }
    }

    /// An optional interval as given; `none` names the default (first and last frame only).
    pub fn shown_or(&self, x: Option<f64>, none: &str) -> String {
        x.map_or(none.to_string(), |x| self.shown(x))
    }

    /// How to change it: the key, and for a scene key the option that overrides it.
    pub fn or_option(&self) -> String {
        match self.key.strip_prefix("[run].") {
            Some(k) => format!("{} (or --{})", self.key, k.replace('_', "-")),
            None => self.key.to_string(),
        }
    }
}

/// `x` seconds in the computer time of `scene` (`x / β`, paper eq. 10); a one-line error naming
/// `option` when the scene is dimensionless.
pub fn si_time(scene: &Scene, option: &str, x: f64) -> Result<f64> {
    if !(x.is_finite() && x > 0.0) {
        anyhow::bail!("{option}: must be a finite number > 0 (seconds), got {x}");
    }
    match scene.units {
        Some(u) => Ok(x / u.time),
        None => anyhow::bail!(
            "{option}: scene `{}` is dimensionless (computer units only); SI times need a \
             physical scene ([units] system = \"physical\")",
            scene.name
        ),
    }
}

/// The command line's overrides of the scene's `[run]` settings (SI times converted with the
/// scene's time unit).
pub fn overrides(scene: &Scene, c: &Common) -> Result<RunOverrides> {
    Ok(RunOverrides {
        method: c.method,
        rtol: c.rtol,
        atol: c.atol,
        until: match c.until_si {
            Some(t) => Some(si_time(scene, "--until-si", t)?),
            None => c.until,
        },
        solver: Some(c.solver),
        max_steps: c.max_steps,
        ..RunOverrides::default()
    })
}

/// The run configuration of `o` ([`RunConfig::with_overrides`]), with a warning for an rtol
/// below what f64 arithmetic delivers.
pub fn config(scene: &Scene, o: &RunOverrides) -> RunConfig {
    let cfg = RunConfig::with_overrides(scene, o);
    if cfg.rtol > 0.0 && cfg.rtol < RTOL_F64_FLOOR {
        eprintln!(
            "beadchain: warning: rtol = {:e} is below what f64 arithmetic can deliver (~{RTOL_F64_FLOOR:e} relative): the error will stall there",
            cfg.rtol
        );
    }
    cfg
}

/// The run summary, on `w` (standard output, or standard error when the snapshot itself goes
/// to a stream such as `/dev/stdout`).
pub fn print_outcome(
    w: &mut dyn Write,
    scene: &Scene,
    cfg: &RunConfig,
    out: &RunOutcome,
) -> Result<()> {
    let s = &out.stats;
    writeln!(
        w,
        "{}: {} beads, engine {}, method {}, rtol {:e}, atol {:e}",
        scene.name,
        scene.chain.len(),
        cfg.engine.name(),
        cfg.method.name(),
        cfg.rtol,
        cfg.atol
    )?;
    writeln!(
        w,
        "t = {} in {:.4} s: {} steps ({} rejected), {} active bead-steps, {} RHS evaluations, {} factorizations, {} Newton iterations ({} failures), largest cluster {}",
        out.t_end,
        out.wall_seconds,
        s.steps,
        s.rejected,
        s.bead_steps,
        s.rhs_evals,
        s.factorizations,
        s.newton_iters,
        s.newton_failures,
        out.largest_cluster
    )?;
    print_counts(w, cfg, out)?;
    if out.dissipated != 0.0 {
        if let Some(note) = beadchain::engine::balance_note(out.relative_energy_error(), cfg.rtol) {
            eprintln!("beadchain: warning: {}: {note}", scene.name);
        }
        writeln!(
            w,
            "energy {:.12e} -> {:.12e}, dissipated {:.12e} (balance error {:.3e}); momentum {:.12e} -> {:.12e}",
            out.energy_initial,
            out.energy_final,
            out.dissipated,
            signed_energy_error(out),
            out.momentum_initial,
            out.momentum_final
        )?;
        return si_line(w, scene, out);
    }
    writeln!(
        w,
        "energy {:.12e} -> {:.12e} (relative change {:.3e}); momentum {:.12e} -> {:.12e}",
        out.energy_initial,
        out.energy_final,
        signed_energy_error(out),
        out.momentum_initial,
        out.momentum_final
    )?;
    si_line(w, scene, out)
}

/// [`RunOutcome::relative_energy_error`] with the sign of `E_final + E_d − E_0`, as `inspect`
/// prints it (a gain positive, a loss negative).
fn signed_energy_error(out: &RunOutcome) -> f64 {
    let change = out.energy_final + out.dissipated - out.energy_initial;
    out.relative_energy_error().copysign(change)
}

/// The run summary's counts past the step line: `auto`'s split between its methods, the events
/// by kind, the exact two-body contacts and the slow-closings warning.
fn print_counts(w: &mut dyn Write, cfg: &RunConfig, out: &RunOutcome) -> Result<()> {
    let s = &out.stats;
    if cfg.method == Method::Auto {
        writeln!(
            w,
            "method auto: {} steps dop853, {} steps radau5",
            s.steps - out.implicit_steps,
            out.implicit_steps
        )?;
    }
    if let Some(counts) = out.events_by_kind {
        let ev: Vec<String> = counts
            .iter()
            .filter(|(_, c)| *c > 0)
            .map(|(k, c)| format!("{k} {c}"))
            .collect();
        writeln!(
            w,
            "events: {}",
            if ev.is_empty() {
                "none".into()
            } else {
                ev.join(", ")
            }
        )?;
    }
    if out.exact_pairs[0] > 0 {
        writeln!(
            w,
            "exact two-body contacts: {} ({} handed over to the integrator)",
            out.exact_pairs[0], out.exact_pairs[1]
        )?;
    }
    for note in [out.slow_closings_note(), out.shallow_closings_note()]
        .into_iter()
        .flatten()
    {
        writeln!(w, "warning: {note}")?;
    }
    Ok(())
}

/// A physical scene's end time and energies in SI (time `t β`, energy `E m0/β²`, paper eq. 10).
fn si_line(w: &mut dyn Write, scene: &Scene, out: &RunOutcome) -> Result<()> {
    let Some(u) = scene.units else {
        return Ok(());
    };
    let joule = |e: f64| e * u.mass / (u.time * u.time);
    write!(
        w,
        "in SI: t = {:.6e} s, energy {:.6e} J -> {:.6e} J",
        out.t_end * u.time,
        joule(out.energy_initial),
        joule(out.energy_final)
    )?;
    if out.dissipated != 0.0 {
        write!(w, ", dissipated {:.6e} J", joule(out.dissipated))?;
    }
    writeln!(
        w,
        " (time unit {:.6e} s, mass unit {:.6e} kg)",
        u.time, u.mass
    )?;
    Ok(())
}

/// The command line as it was run, for provenance (`created_by`, `exported_by`): every argument
/// quoted for a POSIX shell where it needs it (`run 'my scene.toml'`), so the line can be run
/// again; an argument that is not UTF-8 is written lossily (U+FFFD). (`std::env::args` panicked
/// on a non-UTF-8 `--out`, and the arguments were joined unquoted.)
pub fn command_line() -> String {
    std::env::args_os()
        .map(|a| shell_quoted(&a.to_string_lossy()))
        .collect::<Vec<_>>()
        .join(" ")
}

/// `s` as one POSIX shell word: as it is when it holds only characters no shell treats
/// specially, else in single quotes (an inner `'` written `'\''`); with a control character,
/// in bash's `$'…'` quoting (`$'n\nl.snap'`), so the recorded line stays one line and runs again.
fn shell_quoted(s: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_./:=@%+,-".contains(c);
    if !s.is_empty() && s.chars().all(plain) {
        s.to_string()
    } else if s.chars().any(char::is_control) {
        let body: String = s
            .chars()
            .map(|c| match c {
                '\'' => "\\'".to_string(),
                '\\' => "\\\\".to_string(),
                c if c.is_ascii_control() => format!("\\x{:02x}", c as u32),
                c if c.is_control() => format!("\\u{:04x}", c as u32),
                c => c.to_string(),
            })
            .collect();
        format!("$'{body}'")
    } else {
        format!("'{}'", s.replace('\'', "'\\''"))
    }
}

#[cfg(test)]
mod tests {
    use crate::cli::common::shell_quoted;

    #[test]
    fn words_are_quoted_only_where_a_shell_needs_it() {
        assert_eq!(shell_quoted("--out"), "--out");
        assert_eq!(shell_quoted("a/b_c-1.5e-3.snap"), "a/b_c-1.5e-3.snap");
        assert_eq!(shell_quoted("my scene.toml"), "'my scene.toml'");
        assert_eq!(shell_quoted("it's"), "'it'\\''s'");
        assert_eq!(shell_quoted(""), "''");
        assert_eq!(shell_quoted("a$b"), "'a$b'");
        assert_eq!(shell_quoted("n\nl's.snap"), "$'n\\x0al\\'s.snap'");
    }
}
