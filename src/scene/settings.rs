//! `[run]` (end time, frame interval, tolerances, method, engine; `_si` times in physical
//! scenes), with the `[hard]` and `[output]` tables read alongside, and the scene's name and
//! description (`[scene]`; a physical scene's description records its unit scales).

use super::error::SceneError;
use super::keys::{exclusive, opt_num, opt_str};
use super::tables::Tables;
use super::units::UnitScales;
use super::values::Ctx;
use super::{Engine, RunSettings};
use crate::integrate::Method;
use crate::model::HardContacts;
use crate::names::Named;
use std::path::Path;
use toml::Table;

/// The run settings, and the hard contacts of `[hard]` (read between `[run].engine` and
/// `[run].rtol`, the order in which their errors are reported).
pub(super) fn run_settings(
    ctx: &Ctx,
    root: &Table,
    t: &Tables,
    scales: Option<UnitScales>,
    nb: usize,
) -> Result<(RunSettings, Option<HardContacts>), SceneError> {
    exclusive(ctx, t.run, "run", "until", "until_si")?;
    exclusive(ctx, t.run, "run", "every", "every_si")?;
    let time = |plain: &str, si: &str| -> Result<Option<f64>, SceneError> {
        match (
            opt_num(ctx, t.run, "run", plain)?,
            opt_num(ctx, t.run, "run", si)?,
            scales,
        ) {
            (Some(t), _, _) => Ok(Some(t)),
            (None, Some(t), Some(sc)) => Ok(Some(sc.time(t))),
            _ => Ok(None),
        }
    };
    let until = time("until", "until_si")?
        .ok_or_else(|| ctx.err("[run].until", "missing (end time of the run)"))?;
    let every = time("every", "every_si")?;
    let method = named::<Method>(ctx, t.run, "method")?;
    let engine = named::<Engine>(ctx, t.run, "engine")?;
    let hard = super::hard::parse_hard(ctx, root, nb - 1)?;
    let run = RunSettings {
        until,
        every,
        rtol: opt_num(ctx, t.run, "run", "rtol")?,
        atol: opt_num(ctx, t.run, "run", "atol")?,
        method,
        engine,
        output: super::output::parse_output(ctx, root, nb)?,
    };
    Ok((run, hard))
}

/// `[run].KEY` naming a value of `T` (the method, the engine); `None` when absent.
fn named<T: Named>(ctx: &Ctx, run_t: Option<&Table>, key: &str) -> Result<Option<T>, SceneError> {
    opt_str(ctx, run_t, "run", key)?
        .map(|s| T::parse(s).map_err(|e| ctx.err(&format!("[run].{key}"), e.to_string())))
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
    let name = opt_str(ctx, t.scene, "scene", "name")?.map_or(stem, str::to_string);
    let mut description = opt_str(ctx, t.scene, "scene", "description")?
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
