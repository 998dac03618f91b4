//! The tables of a scene file, each a struct of its keys read through serde (unknown keys and
//! tables are refused, naming the file and key path: [`table_keys`], [`fields`]), `[scene].seed`,
//! and the unit system (`[units].system`), which decides the keys allowed elsewhere (the `_si`
//! keys and `[units]` material data only in physical scenes; explicit masses and prefactors only
//! in dimensionless ones). First step of [`super::parse::parse_str`].

use super::ctx::{read_keys, table_keys, table_of_owned, TakeKeys};
use super::error::SceneError;
use super::keys::{forbid, kp, opt_num, opt_str, Opt, PHYSICAL_ONLY};
use super::units::UnitScales;
use super::values::Ctx;
use toml::{Table, Value};

table_keys! {
    /// A scene file: its tables.
    Root { scene, chain, initial, run, field, walls, units, hard, output }
    /// `[scene]`.
    SceneKeys { name, description, seed }
    /// `[chain]`.
    ChainKeys {
        beads, mass, exponent, prefactor, precompression, precompression_force,
        precompression_force_si, radius, law, damping, damping_si, restitution, impact_speed,
        impact_speed_si,
    }
    /// `[units]`: `system`, then the material data of physical scenes and the scales of
    /// computer-unit ones.
    UnitsKeys {
        system, time_scale, radius, young, poisson, density, m0, n0, mu, wall_young, wall_poisson,
        viscosity_shear, viscosity_bulk, time_unit,
    }
    /// `[initial]`.
    InitialKeys {
        velocity, displacement, striker, striker_right, pulse, velocity_si, striker_si,
        striker_right_si, solitary, equilibrium, mode,
    }
    /// `[run]`.
    RunKeys { until, every, until_si, every_si, rtol, atol, method, engine }
    /// `[field]`.
    FieldKeys { force, gravity, force_si, gravity_si }
    /// `[walls]`.
    WallsKeys { left, right, force, force_si }
    /// `[walls] left`, `right`.
    WallKeys { exponent, prefactor, prefactor_si, precompression, hard, restitution, damping, damping_si }
    /// `[initial] pulse`.
    PulseKeys { beads, velocity, velocity_si }
    /// `[initial] mode`.
    ModeKeys { index, amplitude }
    /// `[initial] solitary` (one entry).
    SolitaryKeys { at, velocity, velocity_si, energy, energy_si, direction }
    /// `[hard]`.
    HardKeys { contacts, restitution, collapse_interval }
    /// `[hard] contacts = { from, to }`.
    RangeKeys { from, to }
    /// `[output]`.
    OutputKeys { beads, fields, frames_max }
}

/// The tables of a scene (absent ones empty); `[hard]` and `[output]` as written, read by their
/// own modules.
pub(super) struct Tables {
    pub scene: SceneKeys,
    pub chain: ChainKeys,
    pub units: UnitsKeys,
    pub initial: InitialKeys,
    pub run: RunKeys,
    pub field: FieldKeys,
    pub walls: WallsKeys,
    pub hard: Opt,
    pub output: Opt,
}

/// `[name]` of the scene as `T` (empty when absent); its values are moved, not copied.
fn section<T: serde::de::DeserializeOwned + TakeKeys + Default>(
    ctx: &Ctx,
    name: &str,
    v: Opt,
) -> Result<T, SceneError> {
    table_of_owned(ctx, &format!("[{name}]"), v, "a table").map(Option::unwrap_or_default)
}

/// Refuses unknown top-level tables, reads `[scene]` and its seed (the seed of every random
/// builder: messages of later tables are reported with it).
pub(super) fn scene_table(pre: &Ctx, root: Table) -> Result<(Root, SceneKeys, u64), SceneError> {
    let mut root: Root = read_keys(root).map_err(|(k, keys)| {
        pre.err(
            &format!("[{k}]"),
            format!("unknown table or key (expected one of: {keys})"),
        )
    })?;
    let scene: SceneKeys = section(pre, "scene", root.scene.take())?;
    let seed = match &scene.seed {
        Some(Value::Integer(i)) if *i >= 0 => *i as u64,
        Some(v) => {
            return Err(pre.err(
                "[scene].seed",
                format!("expected a non-negative integer, got {v}"),
            ))
        }
        None => 0,
    };
    Ok((root, scene, seed))
}

/// The tables `[chain]`, `[units]`, `[initial]`, `[run]`, `[field]`, `[walls]`, each with its
/// keys checked.
pub(super) fn read_tables(ctx: &Ctx, root: Root, scene: SceneKeys) -> Result<Tables, SceneError> {
    Ok(Tables {
        scene,
        chain: section(ctx, "chain", root.chain)?,
        units: section(ctx, "units", root.units)?,
        initial: section(ctx, "initial", root.initial)?,
        run: section(ctx, "run", root.run)?,
        field: section(ctx, "field", root.field)?,
        walls: section(ctx, "walls", root.walls)?,
        hard: root.hard,
        output: root.output,
    })
}

/// `[units].system`: true for `"physical"`. Refuses the keys the other system does not use
/// (`"computer"` follows the dimensionless rules and adds the scales of [`computer_scales`]).
pub(super) fn unit_system(ctx: &Ctx, t: &Tables) -> Result<bool, SceneError> {
    let (physical, computer) = match opt_str(ctx, "[units].system", &t.units.system)? {
        None | Some("dimensionless") => (false, false),
        Some("physical") => (true, false),
        Some("computer") => (false, true),
        Some(s) => {
            return Err(ctx.err(
                "[units].system",
                format!("expected \"dimensionless\", \"physical\" or \"computer\", got \"{s}\""),
            ))
        }
    };
    let (c, u, i) = (&t.chain, &t.units, &t.initial);
    if physical {
        let why = "not allowed in a physical scene (masses and prefactors come from [units] radius, young, poisson, density)";
        let keys = [
            ("mass", &c.mass),
            ("prefactor", &c.prefactor),
            ("radius", &c.radius),
        ];
        forbid(ctx, "[chain]", &keys, why)?;
        let why =
            "only used with [units] system = \"computer\" (a physical scene derives its time unit)";
        return forbid(ctx, "[units]", &[("time_unit", &u.time_unit)], why).map(|()| true);
    }
    let why = PHYSICAL_ONLY;
    let none = &None;
    let scale = |v| if computer { none } else { v };
    let material = [
        ("time_scale", &u.time_scale),
        ("radius", &u.radius),
        ("young", &u.young),
        ("poisson", &u.poisson),
        ("density", &u.density),
        ("m0", scale(&u.m0)),
        ("n0", scale(&u.n0)),
        ("mu", scale(&u.mu)),
        ("wall_young", &u.wall_young),
        ("wall_poisson", &u.wall_poisson),
        ("viscosity_shear", &u.viscosity_shear),
        ("viscosity_bulk", &u.viscosity_bulk),
        ("time_unit", scale(&u.time_unit)),
    ];
    forbid(ctx, "[units]", &material, why)?;
    let keys = [
        ("velocity_si", &i.velocity_si),
        ("striker_si", &i.striker_si),
        ("striker_right_si", &i.striker_right_si),
    ];
    forbid(ctx, "[initial]", &keys, why)?;
    let keys = [("until_si", &t.run.until_si), ("every_si", &t.run.every_si)];
    forbid(ctx, "[run]", &keys, why)?;
    let keys = [
        ("force_si", &t.field.force_si),
        ("gravity_si", &t.field.gravity_si),
    ];
    forbid(ctx, "[field]", &keys, why)?;
    let keys = [
        ("damping_si", &c.damping_si),
        ("impact_speed_si", &c.impact_speed_si),
        ("precompression_force_si", &c.precompression_force_si),
    ];
    forbid(ctx, "[chain]", &keys, why)?;
    forbid(ctx, "[walls]", &[("force_si", &t.walls.force_si)], why)?;
    Ok(false)
}

/// The SI scales of `[units] system = "computer"` (`None` for another system): every value
/// of the scene is in computer units already; the scales only convert outputs to SI (and the
/// checks of physical scenes use them), exactly as in the physical scene it was shown from.
/// The mass unit `m0` (kg), the time unit `β` (s), `μ` and `n0` are each required.
pub(super) fn computer_scales(ctx: &Ctx, t: &Tables) -> Result<Option<UnitScales>, SceneError> {
    if opt_str(ctx, "[units].system", &t.units.system)? != Some("computer") {
        return Ok(None);
    }
    let u = &t.units;
    let mut v = [0.0; 4];
    for (x, (k, given)) in v.iter_mut().zip([
        ("m0", &u.m0),
        ("time_unit", &u.time_unit),
        ("mu", &u.mu),
        ("n0", &u.n0),
    ]) {
        *x = match opt_num(ctx, &kp("units", k), given)? {
            Some(x) if x > 0.0 && x.is_finite() => x,
            Some(x) => return Err(ctx.err(&kp("units", k), format!("must be > 0, got {x}"))),
            None => {
                return Err(ctx.err(
                    &kp("units", k),
                    "required with system = \"computer\" (m0 in kg, time_unit in s, mu, n0)",
                ))
            }
        };
    }
    Ok(Some(UnitScales {
        mass: v[0],
        time: v[1],
        mu: v[2],
        n0: v[3],
    }))
}
