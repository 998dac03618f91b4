//! `[run]` (end time, frame interval, tolerances, method, engine; `_si` times in physical
//! scenes), with the `[hard]` and `[output]` tables read alongside, and the scene's name and
//! description (`[scene]`; a physical scene's description records its unit scales).

use super::error::SceneError;
use super::keys::{exclusive, kp, opt_num, opt_str, Opt};
use super::tables::Tables;
use super::units::UnitScales;
use super::values::Ctx;
use super::{Engine, RunSettings};
use crate::integrate::Method;
use crate::model::HardContacts;
use crate::names::Named;
use std::path::Path;

/// The run settings, and the hard contacts of `[hard]` (read between `[run].engine` and
/// `[run].rtol`, the order in which their errors are reported).
pub(super) fn run_settings(
    ctx: &Ctx,
    t: &Tables,
    scales: Option<UnitScales>,
    nb: usize,
) -> Result<(RunSettings, Option<HardContacts>), SceneError> {
    let r = &t.run;
    let until = (("until", &r.until), ("until_si", &r.until_si));
    let every = (("every", &r.every), ("every_si", &r.every_si));
    exclusive(ctx, "run", until.0, until.1)?;
    exclusive(ctx, "run", every.0, every.1)?;
    let time = |((plain, pv), (si, sv)): ((&str, &Opt), (&str, &Opt))| {
        let given = (
            opt_num(ctx, &kp("run", plain), pv)?,
            opt_num(ctx, &kp("run", si), sv)?,
        );
        Ok::<_, SceneError>(match (given, scales) {
            ((Some(t), _), _) => Some(t),
            ((None, Some(t)), Some(sc)) => Some(sc.time(t)),
            _ => None,
        })
    };
    let until =
        time(until)?.ok_or_else(|| ctx.err("[run].until", "missing (end time of the run)"))?;
    let every = time(every)?;
    let method = named::<Method>(ctx, "method", &r.method)?;
    let engine = named::<Engine>(ctx, "engine", &r.engine)?;
    let hard = super::hard::parse_hard(ctx, &t.hard, nb - 1)?;
    let run = RunSettings {
        until,
        every,
        rtol: opt_num(ctx, "[run].rtol", &r.rtol)?,
        atol: opt_num(ctx, "[run].atol", &r.atol)?,
        method,
        engine,
        output: super::output::parse_output(ctx, &t.output, nb)?,
    };
    Ok((run, hard))
}

/// `[run].KEY` naming a value of `T` (the method, the engine); `None` when absent.
fn named<T: Named>(ctx: &Ctx, key: &str, v: &Opt) -> Result<Option<T>, SceneError> {
    let key = kp("run", key);
    opt_str(ctx, &key, v)?
        .map(|s| T::parse(s).map_err(|e| ctx.err(&key, e.to_string())))
        .transpose()
}

/// `[scene].name` (default: the file stem of `origin`) and `[scene].description`.
pub(super) fn name_and_description(
    ctx: &Ctx,
    t: &Tables,
    origin: &str,
    scales: Option<UnitScales>,
) -> Result<(String, String), SceneError> {
    let stem = Path::new(origin)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| origin.to_string());
    let name = opt_str(ctx, "[scene].name", &t.scene.name)?.map_or(stem, str::to_string);
    let mut description = opt_str(ctx, "[scene].description", &t.scene.description)?
        .unwrap_or("")
        .to_string();
    if let Some(sc) = scales {
        if !description.is_empty() {
            description.push(' ');
        }
        description.push_str(&units_note(&sc));
    }
    Ok((name, description))
}

/// The note a physical scene's description ends with (its unit scales; older snapshots are
/// read back through it).
pub(crate) fn units_note(sc: &UnitScales) -> String {
    format!(
        "[physical units: time unit {:.6e} s, mass unit {:.6e} kg, mu {:e}, n0 {}; lengths in m]",
        sc.time, sc.mass, sc.mu, sc.n0
    )
}
