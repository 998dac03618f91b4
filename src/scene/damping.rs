//! Scene keys of dissipative contacts: `[chain] law`, `damping` / `damping_si`, or
//! `restitution` with `impact_speed` / `impact_speed_si`, and `damping` / `damping_si` of a
//! wall (see [`crate::model::law`] for the laws).
//!
//! - `law = "power"` (default) is the paper's conservative law; no damping key is allowed.
//! - `law = "viscoelastic"`: `damping` is Kuwabara–Kono's `A` (a time; `damping_si` in s).
//! - `law = "linear_dashpot"`: `damping` is `c` (force per velocity; `damping_si` in N·s/m).
//! - Instead of `damping`, `restitution = e` and `impact_speed = v` give every contact the
//!   coefficient for which a head-on collision of its two beads at relative speed `v` rebounds
//!   with `e` ([`crate::model::law::restitution`]: the collision is solved numerically, to the
//!   law's own clipped force, so `e` is exact for this model at `v`).
//! - Physical scenes may instead give the material's viscosities, `[units] viscosity_shear`
//!   (η₁) and `viscosity_bulk` (η₂) in Pa·s per bead, with `law = "viscoelastic"`: each bead's
//!   `A = (1/3)(3η₂ − η₁)²/(3η₂ + 2η₁) · (1 − ν²)(1 − 2ν)/(Y ν²)` (Brilliantov et al., Phys.
//!   Rev. E 53, 5382 (1996); [`super::units::brilliantov_a`]), a contact takes the mean of its
//!   two beads' `A` (exact for one material).
//! - A soft wall takes the coefficient of the contact next to it unless its table gives
//!   `damping` (`damping_si`).
//!
//! A law whose coefficients are all 0 is the power law: the scene declares no damping and runs
//! the conservative kernel (bit-identical results).

use super::error::SceneError;
use super::keys::{exclusive, forbid, opt_num, opt_spec, opt_str, Opt, PHYSICAL_ONLY};
use super::tables::{ChainKeys, WallKeys};
use super::units::UnitScales;
use super::values::{Ctx, Per};
use crate::model::restitution;
use crate::model::{Damping, DampingLaw, Wall};

/// The resolved chain arrays the damping keys depend on.
pub(crate) struct ChainArrays<'a> {
    pub mass: &'a [f64],
    pub exponent: &'a [f64],
    pub prefactor: &'a [f64],
    /// Per-bead viscoelastic constant `A` (s) from the material viscosities of a physical
    /// scene ([`super::units::brilliantov_a`]), if given.
    pub material_a: Option<&'a [f64]>,
}

/// Parses the damping keys of `[chain]` and the wall tables; `None` for a conservative scene.
pub(crate) fn parse(
    ctx: &Ctx,
    c: &ChainKeys,
    walls: &[Option<(Wall, WallKeys)>; 2],
    arrays: ChainArrays,
    scales: Option<UnitScales>,
) -> Result<Option<Damping>, SceneError> {
    let law = match opt_str(ctx, "[chain].law", &c.law)? {
        None | Some("power") => None,
        Some("viscoelastic") => Some(DampingLaw::Viscoelastic),
        Some("linear_dashpot") => Some(DampingLaw::LinearDashpot),
        Some(s) => {
            return Err(ctx.err(
                "[chain].law",
                format!("expected \"power\", \"viscoelastic\" or \"linear_dashpot\", got \"{s}\""),
            ))
        }
    };
    let Some(law) = law else {
        refuse_damping_keys(ctx, c, walls)?;
        if arrays.material_a.is_some() {
            return Err(ctx.err("[units].viscosity_shear", VISCOSITY_LAW));
        }
        return Ok(None);
    };
    let contact = match (arrays.material_a, scales) {
        (Some(a), Some(sc)) => material_coefficients(ctx, c, law, a, sc)?,
        _ => contact_coefficients(ctx, c, law, &arrays, scales)?,
    };
    let mut wall = [0.0; 2];
    for (s, side) in ["left", "right"].iter().enumerate() {
        let key = format!("[walls].{side}");
        let [plain, si] = wall_damping(&walls[s]);
        let value = match (
            opt_num(ctx, &format!("{key}.damping"), plain.1)?,
            opt_num(ctx, &format!("{key}.damping_si"), si.1)?,
        ) {
            (Some(_), Some(_)) => {
                return Err(ctx.err(
                    &format!("{key}.damping_si"),
                    "give either `damping` or `damping_si`, not both",
                ))
            }
            (Some(g), None) => g,
            (None, Some(g)) => to_computer(ctx, &format!("{key}.damping_si"), law, g, scales)?,
            (None, None) => {
                let c = if s == 0 { 0 } else { contact.len() - 1 };
                contact[c]
            }
        };
        check_coefficient(ctx, &format!("{key}.damping"), value)?;
        let hard = walls[s].as_ref().is_some_and(|w| w.0.restitution.is_some());
        if hard && (plain.1.is_some() || si.1.is_some()) {
            return Err(ctx.err(
                &format!("{key}.damping"),
                "a hard wall has a restitution, not a damping",
            ));
        }
        wall[s] = value;
    }
    if contact.iter().chain(&wall).all(|g| *g == 0.0) {
        return Ok(None);
    }
    Ok(Some(Damping {
        law,
        contact,
        left_wall: wall[0],
        right_wall: wall[1],
    }))
}

/// Why material viscosities need the viscoelastic law.
const VISCOSITY_LAW: &str = "the material viscosities give the constant A of [chain] law = \"viscoelastic\" (Brilliantov et al. 1996); set that law, or give `damping` for another law";

/// Per-contact `A` (computer time) from the beads' material constants `a` (s): the mean of the
/// two beads' `A` (exact for a contact of one material, the setting of Brilliantov et al.; an
/// interpolation between two materials). Excludes `damping` and `restitution`.
fn material_coefficients(
    ctx: &Ctx,
    c: &ChainKeys,
    law: DampingLaw,
    a: &[f64],
    sc: UnitScales,
) -> Result<Vec<f64>, SceneError> {
    if law != DampingLaw::Viscoelastic {
        return Err(ctx.err("[units].viscosity_shear", VISCOSITY_LAW));
    }
    let why = "give either the material viscosities ([units] viscosity_shear, viscosity_bulk) or the contacts' damping, not both";
    forbid(ctx, "[chain]", &damping_keys(c), why)?;
    Ok(a.windows(2).map(|w| sc.time(0.5 * (w[0] + w[1]))).collect())
}

/// A conservative scene (law `power`) refuses the damping keys of `[chain]` and the walls.
fn refuse_damping_keys(
    ctx: &Ctx,
    c: &ChainKeys,
    walls: &[Option<(Wall, WallKeys)>; 2],
) -> Result<(), SceneError> {
    let why = "needs a dissipative law ([chain] law = \"viscoelastic\" or \"linear_dashpot\")";
    forbid(ctx, "[chain]", &damping_keys(c), why)?;
    for (side, wall) in ["left", "right"].into_iter().zip(walls) {
        forbid(ctx, &format!("[walls].{side}"), &wall_damping(wall), why)?;
    }
    Ok(())
}

/// The damping keys of `[chain]`.
fn damping_keys(c: &ChainKeys) -> [(&str, &Opt); 5] {
    [
        ("damping", &c.damping),
        ("damping_si", &c.damping_si),
        ("restitution", &c.restitution),
        ("impact_speed", &c.impact_speed),
        ("impact_speed_si", &c.impact_speed_si),
    ]
}

/// The damping keys of a wall (absent without the wall).
fn wall_damping(wall: &Option<(Wall, WallKeys)>) -> [(&str, &Opt); 2] {
    match wall {
        Some((_, k)) => [("damping", &k.damping), ("damping_si", &k.damping_si)],
        None => [("damping", &None), ("damping_si", &None)],
    }
}

/// Per-contact coefficients from `damping`, `damping_si`, or `restitution` + `impact_speed`.
fn contact_coefficients(
    ctx: &Ctx,
    c: &ChainKeys,
    law: DampingLaw,
    arrays: &ChainArrays,
    scales: Option<UnitScales>,
) -> Result<Vec<f64>, SceneError> {
    let nc = arrays.exponent.len();
    let [damping, damping_si, restitution, impact_speed, impact_speed_si] = damping_keys(c);
    exclusive(ctx, "chain", damping, damping_si)?;
    exclusive(ctx, "chain", damping, restitution)?;
    exclusive(ctx, "chain", damping_si, restitution)?;
    exclusive(ctx, "chain", impact_speed, impact_speed_si)?;
    if scales.is_none() {
        forbid(
            ctx,
            "[chain]",
            &[damping_si, impact_speed_si],
            PHYSICAL_ONLY,
        )?;
    }
    if let Some(e) = opt_num(ctx, "[chain].restitution", restitution.1)? {
        return from_restitution(ctx, c, law, arrays, scales, e);
    }
    let why = "only used with [chain].restitution";
    forbid(ctx, "[chain]", &[impact_speed, impact_speed_si], why)?;
    let (spec, key, si) = match (
        opt_spec(ctx, "[chain].damping", &c.damping)?,
        opt_spec(ctx, "[chain].damping_si", &c.damping_si)?,
    ) {
        (Some(s), _) => (s, "[chain].damping", false),
        (None, Some(s)) => (s, "[chain].damping_si", true),
        (None, None) => {
            return Err(ctx.err(
                "[chain].damping",
                format!(
                    "missing: law \"{}\" needs `damping` (or `restitution` with `impact_speed`)",
                    law.name()
                ),
            ))
        }
    };
    let mut g = spec.resolve(ctx, key, nc, Per::Contact, 0.0)?;
    for (c, x) in g.iter_mut().enumerate() {
        if si {
            *x = to_computer(ctx, key, law, *x, scales)?;
        }
        if !(x.is_finite() && *x >= 0.0) {
            return Err(ctx.index_err(
                key,
                Per::Contact,
                c,
                format!("must be a finite number >= 0, got {x}"),
            ));
        }
    }
    Ok(g)
}

/// Coefficients that give restitution `e` at impact speed `v` for every contact.
fn from_restitution(
    ctx: &Ctx,
    c: &ChainKeys,
    law: DampingLaw,
    arrays: &ChainArrays,
    scales: Option<UnitScales>,
    e: f64,
) -> Result<Vec<f64>, SceneError> {
    if !(e > 0.0 && e <= 1.0) {
        return Err(ctx.err("[chain].restitution", format!("must be in (0, 1], got {e}")));
    }
    let v = match (
        opt_num(ctx, "[chain].impact_speed", &c.impact_speed)?,
        opt_num(ctx, "[chain].impact_speed_si", &c.impact_speed_si)?,
        scales,
    ) {
        (Some(v), _, _) => v,
        (None, Some(v), Some(sc)) => sc.velocity(v),
        _ => {
            return Err(ctx.err(
                "[chain].impact_speed",
                "missing: `restitution` is measured at an impact speed (the relative speed of the two beads)",
            ))
        }
    };
    if !(v > 0.0 && v.is_finite()) {
        return Err(ctx.err("[chain].impact_speed", format!("must be > 0, got {v}")));
    }
    let mut out = Vec::with_capacity(arrays.exponent.len());
    let mut memo: Vec<(f64, f64)> = Vec::new(); // (n, dimensionless coefficient)
    for c in 0..arrays.exponent.len() {
        let n = arrays.exponent[c];
        if n < 2.0 {
            return Err(ctx.index_err(
                "[chain].restitution",
                Per::Contact,
                c,
                format!("needs exponent >= 2 (the damping force of exponent {n} is unbounded at first touch); give `damping` instead"),
            ));
        }
        let x = match memo.iter().find(|(m, _)| *m == n) {
            Some((_, x)) => *x,
            None => {
                let x = restitution::dimensionless_coefficient(law, n, e);
                if x.is_nan() {
                    return Err(ctx.index_err(
                        "[chain].restitution",
                        Per::Contact,
                        c,
                        format!(
                            "{e} is below what law \"{}\" reaches with exponent {n}",
                            law.name()
                        ),
                    ));
                }
                memo.push((n, x));
                x
            }
        };
        let mu = arrays.mass[c] * arrays.mass[c + 1] / (arrays.mass[c] + arrays.mass[c + 1]);
        out.push(restitution::coefficient(
            law,
            n,
            arrays.prefactor[c],
            mu,
            v,
            x,
        ));
    }
    Ok(out)
}

/// Computer units of an SI damping coefficient: `A` in s → `A/β`; `c` in kg/s → `c β/m0`.
fn to_computer(
    ctx: &Ctx,
    key: &str,
    law: DampingLaw,
    g: f64,
    scales: Option<UnitScales>,
) -> Result<f64, SceneError> {
    let Some(sc) = scales else {
        return Err(ctx.err(key, PHYSICAL_ONLY));
    };
    Ok(match law {
        DampingLaw::Viscoelastic => sc.time(g),
        DampingLaw::LinearDashpot => g * sc.time / sc.mass,
    })
}

fn check_coefficient(ctx: &Ctx, key: &str, g: f64) -> Result<(), SceneError> {
    if g.is_finite() && g >= 0.0 {
        Ok(())
    } else {
        Err(ctx.err(key, format!("must be a finite number >= 0, got {g}")))
    }
}

/// Largest damping ratio `ζ` a contact may have ([`check_scale`]).
pub const MAX_DAMPING_RATIO: f64 = 1e100;

/// Refuses damping too strong to integrate: a contact's ratio of its damping rate to the run's
/// time scale `T = L/V` ([`crate::model::Chain::scales`]), `ζ = A/T` (viscoelastic) or
/// `ζ = c·T/μ` (linear dashpot, `μ` the reduced mass; a wall's bead mass), above
/// [`MAX_DAMPING_RATIO`]. Such a contact relaxes `ζ` times faster than it oscillates: it sticks
/// at first touch, and its force overflows the integration (3 beads, `A = 1e308`: both engines
/// wrote a snapshot with the energy going 0.5 → 8e58).
pub(crate) fn check_scale(ctx: &Ctx, scene: &crate::scene::Scene) -> Result<(), SceneError> {
    let c = &scene.chain;
    let Some(d) = &c.damping else {
        return Ok(());
    };
    let t = c.scales(&scene.u0, &scene.v0).time();
    let ratio = |g: f64, mu: f64| match d.law {
        DampingLaw::Viscoelastic => g / t,
        DampingLaw::LinearDashpot => g * t / mu,
    };
    let too_strong = |z: f64| z.is_nan() || z > MAX_DAMPING_RATIO;
    let advice = "a contact this overdamped sticks at first touch: give a smaller `damping`, \
                  or a [hard] contact with restitution = 0";
    let n = c.mass.len();
    for (k, &g) in d.contact.iter().enumerate() {
        let mu = c.mass[k] * c.mass[k + 1] / (c.mass[k] + c.mass[k + 1]);
        let z = ratio(g, mu);
        if too_strong(z) {
            let msg = format!("damping {g:e} relaxes the contact {z:.1e} times faster than the run's time scale T = {t:.3e} (ratio at most {MAX_DAMPING_RATIO:e}): {advice}");
            return Err(ctx.index_err("[chain].damping", Per::Contact, k, msg));
        }
    }
    for (side, wall, g, m) in [
        ("left", &c.left_wall, d.left_wall, c.mass[0]),
        ("right", &c.right_wall, d.right_wall, c.mass[n - 1]),
    ] {
        let z = ratio(g, m);
        if wall.is_some() && too_strong(z) {
            let msg = format!("damping {g:e} relaxes the wall contact {z:.1e} times faster than the run's time scale T = {t:.3e} (ratio at most {MAX_DAMPING_RATIO:e}): {advice}");
            return Err(ctx.err(&format!("[walls].{side}.damping"), msg));
        }
    }
    Ok(())
}
