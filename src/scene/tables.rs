//! The top-level tables of a scene file: which tables exist, the keys each allows, `[scene].seed`,
//! and the unit system (`[units].system`), which decides the keys allowed elsewhere (the `_si`
//! keys and `[units]` material data only in physical scenes; explicit masses and prefactors only
//! in dimensionless ones). First step of [`super::parse::parse_str`].

use super::error::{one_line, SceneError};
use super::keys::{forbid, get, kp, opt_num, opt_str, table};
use super::units::UnitScales;
use super::values::Ctx;
use toml::{Table, Value};

/// Every top-level table a scene may have.
const TABLES: &[&str] = &[
    "scene", "chain", "initial", "run", "field", "walls", "units", "hard", "output",
];

/// The tables read by the scene builder (`None` when absent; `[hard]` and `[output]` are
/// read by their own modules from the root).
pub(super) struct Tables<'a> {
    pub scene: Option<&'a Table>,
    pub chain: Option<&'a Table>,
    pub units: Option<&'a Table>,
    pub initial: Option<&'a Table>,
    pub run: Option<&'a Table>,
    pub field: Option<&'a Table>,
    pub walls: Option<&'a Table>,
}

/// Refuses unknown top-level tables, reads `[scene]` and its seed (the seed of every random
/// builder: messages of later tables are reported with it).
pub(super) fn scene_table<'a>(
    pre: &Ctx,
    root: &'a Table,
) -> Result<(Option<&'a Table>, u64), SceneError> {
    for (k, _) in root.iter() {
        if !TABLES.contains(&k.as_str()) {
            return Err(pre.err(
                &format!("[{}]", one_line(k)),
                format!(
                    "unknown table or key (expected one of: {})",
                    TABLES.join(", ")
                ),
            ));
        }
    }
    let scene_t = table(pre, root, "scene", &["name", "description", "seed"])?;
    let seed = match get(scene_t, "seed") {
        Some(Value::Integer(i)) if *i >= 0 => *i as u64,
        Some(v) => {
            return Err(pre.err(
                "[scene].seed",
                format!("expected a non-negative integer, got {v}"),
            ))
        }
        None => 0,
    };
    Ok((scene_t, seed))
}

/// The tables `[chain]`, `[units]`, `[initial]`, `[run]`, `[field]`, `[walls]`, each with its
/// keys checked.
pub(super) fn read_tables<'a>(
    ctx: &Ctx,
    root: &'a Table,
    scene: Option<&'a Table>,
) -> Result<Tables<'a>, SceneError> {
    let chain = table(
        ctx,
        root,
        "chain",
        &[
            "beads",
            "mass",
            "exponent",
            "prefactor",
            "precompression",
            "precompression_force",
            "precompression_force_si",
            "radius",
            "law",
            "damping",
            "damping_si",
            "restitution",
            "impact_speed",
            "impact_speed_si",
        ],
    )?;
    let units = table(ctx, root, "units", UNITS_KEYS)?;
    let initial = table(
        ctx,
        root,
        "initial",
        &[
            "velocity",
            "displacement",
            "striker",
            "striker_right",
            "pulse",
            "velocity_si",
            "striker_si",
            "striker_right_si",
            "solitary",
            "equilibrium",
            "mode",
        ],
    )?;
    let run = table(
        ctx,
        root,
        "run",
        &[
            "until", "every", "until_si", "every_si", "rtol", "atol", "method", "engine",
        ],
    )?;
    let field = table(
        ctx,
        root,
        "field",
        &["force", "gravity", "force_si", "gravity_si"],
    )?;
    let walls = table(ctx, root, "walls", &["left", "right", "force", "force_si"])?;
    Ok(Tables {
        scene,
        chain,
        units,
        initial,
        run,
        field,
        walls,
    })
}

/// The keys of `[units]`: `system`, then the material data of physical scenes.
const UNITS_KEYS: &[&str] = &[
    "system",
    "time_scale",
    "radius",
    "young",
    "poisson",
    "density",
    "m0",
    "n0",
    "mu",
    "wall_young",
    "wall_poisson",
    "viscosity_shear",
    "viscosity_bulk",
    "time_unit",
];

/// The keys of `[units] system = "computer"` (a resolved scene in computer units that keeps
/// its SI scales, as `scene show` writes it): the mass unit `m0` (kg), the time unit `β` (s),
/// `μ` and `n0`, each required.
const COMPUTER_KEYS: &[&str] = &["m0", "time_unit", "mu", "n0"];

/// `[units].system`: true for `"physical"`. Refuses the keys the other system does not use
/// (`"computer"` follows the dimensionless rules and adds [`COMPUTER_KEYS`]).
pub(super) fn unit_system(ctx: &Ctx, t: &Tables) -> Result<bool, SceneError> {
    let (physical, computer) = match opt_str(ctx, t.units, "units", "system")? {
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
    if physical {
        let why = "not allowed in a physical scene (masses and prefactors come from [units] radius, young, poisson, density)";
        forbid(ctx, t.chain, "chain", &["mass", "prefactor", "radius"], why)?;
        let why =
            "only used with [units] system = \"computer\" (a physical scene derives its time unit)";
        forbid(ctx, t.units, "units", &["time_unit"], why)?;
    } else {
        let why = "only allowed in a physical scene ([units] system = \"physical\")";
        let keys: Vec<&str> = UNITS_KEYS[1..]
            .iter()
            .copied()
            .filter(|k| !(computer && COMPUTER_KEYS.contains(k)))
            .collect();
        forbid(ctx, t.units, "units", &keys, why)?;
        forbid(
            ctx,
            t.initial,
            "initial",
            &["velocity_si", "striker_si", "striker_right_si"],
            why,
        )?;
        forbid(ctx, t.run, "run", &["until_si", "every_si"], why)?;
        forbid(ctx, t.field, "field", &["force_si", "gravity_si"], why)?;
        forbid(
            ctx,
            t.chain,
            "chain",
            &["damping_si", "impact_speed_si", "precompression_force_si"],
            why,
        )?;
        forbid(ctx, t.walls, "walls", &["force_si"], why)?;
    }
    Ok(physical)
}

/// The SI scales of `[units] system = "computer"` (`None` for another system): every value
/// of the scene is in computer units already; the scales only convert outputs to SI (and the
/// checks of physical scenes use them), exactly as in the physical scene it was shown from.
pub(super) fn computer_scales(ctx: &Ctx, t: &Tables) -> Result<Option<UnitScales>, SceneError> {
    if opt_str(ctx, t.units, "units", "system")? != Some("computer") {
        return Ok(None);
    }
    let mut v = [0.0; 4];
    for (x, k) in v.iter_mut().zip(COMPUTER_KEYS) {
        *x = match opt_num(ctx, t.units, "units", k)? {
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
