//! `[walls] left/right = { exponent, prefactor, precompression, hard, restitution, damping }`:
//! a wall is a contact of the end bead with a fixed body. Exponent and prefactor default to the
//! end contact's; in a physical scene the prefactor defaults to a Hertz sphere against a flat
//! wall of `[units] wall_young, wall_poisson` (default: the end bead's material).

use super::arrays::Len;
use super::error::SceneError;
use super::keys::{get, kp, opt_num};
use super::material::Material;
use super::tables::Tables;
use super::units::{self, UnitScales};
use super::values::{check_keys, number, type_name, Ctx};
use crate::model::Wall;
use toml::{Table, Value};

/// What a wall defaults to: the chain's length, exponents and prefactors, the scales and material of a
/// physical scene.
pub(super) struct WallDefaults<'a> {
    pub len: Len,
    pub exponent: &'a [f64],
    pub prefactor: &'a [f64],
    pub scales: Option<UnitScales>,
    pub material: Option<&'a Material>,
    pub physical: bool,
    /// `[chain] precompression_force`: the default precompression of a soft wall is the overlap
    /// at which it carries this force.
    pub precompression_force: Option<f64>,
}

/// The left and right walls (`None` where absent).
pub(super) fn walls(
    ctx: &Ctx,
    t: &Tables,
    d: &WallDefaults,
) -> Result<[Option<Wall>; 2], SceneError> {
    let Len { nb, nc } = d.len;
    let mut walls = [None, None];
    for (side, slot) in ["left", "right"].iter().zip(walls.iter_mut()) {
        let Some(v) = get(t.walls, side) else {
            continue;
        };
        let k = kp("walls", side);
        let wt = wall_table(ctx, &k, v, d.physical)?;
        let (bead, contact) = if *side == "left" {
            (0, 0)
        } else {
            (nb - 1, nc - 1)
        };
        *slot = Some(wall(ctx, t.units, &k, wt, d, bead, contact)?);
    }
    Ok(walls)
}

/// The wall's table, its keys checked.
fn wall_table<'a>(
    ctx: &Ctx,
    k: &str,
    v: &'a Value,
    physical: bool,
) -> Result<&'a Table, SceneError> {
    let wt = v.as_table().ok_or_else(|| {
        ctx.err(
            k,
            format!(
                "expected a table {{ exponent, prefactor, precompression }}, got {}",
                type_name(v)
            ),
        )
    })?;
    let allowed: &[&str] = if physical {
        &[
            "exponent",
            "prefactor",
            "prefactor_si",
            "precompression",
            "hard",
            "restitution",
            "damping",
            "damping_si",
        ]
    } else {
        &[
            "exponent",
            "prefactor",
            "precompression",
            "hard",
            "restitution",
            "damping",
        ]
    };
    check_keys(ctx, k, wt, allowed)?;
    Ok(wt)
}

/// One wall next to `bead` (the end contact `contact`).
fn wall(
    ctx: &Ctx,
    units_t: Option<&Table>,
    k: &str,
    wt: &Table,
    d: &WallDefaults,
    bead: usize,
    contact: usize,
) -> Result<Wall, SceneError> {
    let num = |key: &str| {
        wt.get(key)
            .map(|x| number(ctx, &format!("{k}.{key}"), x))
            .transpose()
    };
    let exponent = num("exponent")?.unwrap_or(d.exponent[contact]);
    if wt.contains_key("prefactor") && wt.contains_key("prefactor_si") {
        return Err(ctx.err(
            &format!("{k}.prefactor_si"),
            "give either `prefactor` or `prefactor_si`, not both",
        ));
    }
    let prefactor = match (
        num("prefactor")?,
        num("prefactor_si")?,
        d.scales,
        d.material,
    ) {
        (Some(a), _, _, _) => a,
        (None, Some(a), Some(sc), _) => sc.prefactor(a),
        (None, None, Some(sc), Some(mat)) => {
            let yw = opt_num(ctx, units_t, "units", "wall_young")?.unwrap_or(mat.young[bead]);
            let sw = opt_num(ctx, units_t, "units", "wall_poisson")?.unwrap_or(mat.poisson[bead]);
            let dd = units::hertz_d(mat.young[bead], mat.poisson[bead], yw, sw);
            sc.prefactor(units::hertz_wall_prefactor(mat.radius[bead], dd))
        }
        _ => d.prefactor[contact],
    };
    let restitution = super::hard::wall_restitution(ctx, k, wt)?;
    let from_force = match (d.precompression_force, restitution) {
        (Some(f), None) => crate::studies::equilibrium::overlap_for_force(exponent, prefactor, f),
        _ => 0.0,
    };
    let precompression = num("precompression")?.unwrap_or(from_force);
    Ok(Wall {
        exponent,
        prefactor,
        precompression,
        restitution,
    })
}
