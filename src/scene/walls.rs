//! `[walls] left/right = { exponent, prefactor, precompression, hard, restitution, damping }`:
//! a wall is a contact of the end bead with a fixed body. Exponent and prefactor default to the
//! end contact's; in a physical scene the prefactor defaults to a Hertz sphere against a flat
//! wall of `[units] wall_young, wall_poisson` (default: the end bead's material).

use super::arrays::Len;
use super::ctx::table_of;
use super::error::SceneError;
use super::keys::{forbid, kp, opt_num, Opt, PHYSICAL_ONLY};
use super::material::Material;
use super::tables::{Tables, UnitsKeys, WallKeys};
use super::units::{self, UnitScales};
use super::values::Ctx;
use crate::model::Wall;

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

/// The left and right walls with their keys (`None` where absent).
pub(super) fn walls(
    ctx: &Ctx,
    t: &Tables,
    d: &WallDefaults,
) -> Result<[Option<(Wall, WallKeys)>; 2], SceneError> {
    let Len { nb, nc } = d.len;
    // checked whether or not a wall takes its prefactor from them
    wall_material(ctx, &t.units)?;
    let mut walls = [None, None];
    let sides = [("left", &t.walls.left), ("right", &t.walls.right)];
    for ((side, v), slot) in sides.into_iter().zip(walls.iter_mut()) {
        let k = kp("walls", side);
        let shape = "a table { exponent, prefactor, precompression }";
        let Some(wt) = table_of::<WallKeys>(ctx, &k, v.as_ref(), shape)? else {
            continue;
        };
        if !d.physical {
            let si = [
                ("prefactor_si", &wt.prefactor_si),
                ("damping_si", &wt.damping_si),
            ];
            forbid(ctx, &k, &si, PHYSICAL_ONLY)?;
        }
        let (bead, contact) = if side == "left" {
            (0, 0)
        } else {
            (nb - 1, nc - 1)
        };
        *slot = Some((wall(ctx, &t.units, &k, &wt, d, bead, contact)?, wt));
    }
    Ok(walls)
}

/// One wall next to `bead` (the end contact `contact`).
fn wall(
    ctx: &Ctx,
    u: &UnitsKeys,
    k: &str,
    wt: &WallKeys,
    d: &WallDefaults,
    bead: usize,
    contact: usize,
) -> Result<Wall, SceneError> {
    let num = |key: &str, v: &Opt| opt_num(ctx, &format!("{k}.{key}"), v);
    let exponent = num("exponent", &wt.exponent)?.unwrap_or(d.exponent[contact]);
    if wt.prefactor.is_some() && wt.prefactor_si.is_some() {
        return Err(ctx.err(
            &format!("{k}.prefactor_si"),
            "give either `prefactor` or `prefactor_si`, not both",
        ));
    }
    let prefactor = match (
        num("prefactor", &wt.prefactor)?,
        num("prefactor_si", &wt.prefactor_si)?,
        d.scales,
        d.material,
    ) {
        (Some(a), _, _, _) => a,
        (None, Some(a), Some(sc), _) => sc.prefactor(a),
        (None, None, Some(sc), Some(mat)) => {
            let (yw, sw) = wall_material(ctx, u)?;
            let (yw, sw) = (
                yw.unwrap_or(mat.young[bead]),
                sw.unwrap_or(mat.poisson[bead]),
            );
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
    let precompression = num("precompression", &wt.precompression)?.unwrap_or(from_force);
    Ok(Wall {
        exponent,
        prefactor,
        precompression,
        restitution,
    })
}

/// `[units] wall_young` (> 0) and `wall_poisson` (in (−1, 0.5]), checked as the beads' `young`
/// and `poisson` are (they were taken as given: a negative modulus made a plausible prefactor).
fn wall_material(ctx: &Ctx, u: &UnitsKeys) -> Result<(Option<f64>, Option<f64>), SceneError> {
    let young = opt_num(ctx, "[units].wall_young", &u.wall_young)?;
    if let Some(y) = young.filter(|y| !(y.is_finite() && *y > 0.0)) {
        return Err(ctx.err(
            "[units].wall_young",
            format!("must be a finite modulus > 0 (Pa), got {y}"),
        ));
    }
    let poisson = opt_num(ctx, "[units].wall_poisson", &u.wall_poisson)?;
    if let Some(p) = poisson.filter(|p| !(*p > -1.0 && *p <= 0.5)) {
        return Err(ctx.err(
            "[units].wall_poisson",
            format!("must be in (-1, 0.5], got {p}"),
        ));
    }
    Ok((young, poisson))
}
