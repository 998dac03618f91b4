//! Masses and contact prefactors of the chain. Dimensionless scenes give them directly
//! (`[chain] mass, prefactor`, optionally scaled by `radius`: `m ∝ r³`, `a ∝ √(2 r₁r₂/(r₁+r₂))`);
//! physical scenes derive them from `[units]` material data (Hertz spheres, paper eqs. 3–4:
//! `m = (4/3)π r³ ρ`, `a = (2/5)·D⁻¹·√(r₁r₂/(r₁+r₂))` with `D` from Young's moduli and Poisson
//! ratios, see [`super::units`]) and convert them to the paper's units ([`UnitScales`]).

use super::arrays::{Len, Specs};
use super::error::SceneError;
use super::keys::{forbid, kp, opt_num, opt_str, positive, Opt};
use super::tables::{Tables, UnitsKeys};
use super::units::{self, UnitScales};
use super::values::{Ctx, Per, Spec};

/// Default per-bead mass of dimensionless scenes.
pub const DEFAULT_MASS: f64 = 1.0;
/// Default contact prefactor of dimensionless scenes.
pub const DEFAULT_PREFACTOR: f64 = 1.0;

/// The `[units]` material data of a physical scene, resolved (walls derive their prefactor from
/// it).
pub(super) struct Material {
    pub radius: Vec<f64>,
    pub young: Vec<f64>,
    pub poisson: Vec<f64>,
    pub density: Vec<f64>,
    /// Per bead, the viscoelastic constant `A` (s) from `[units] viscosity_shear` and
    /// `viscosity_bulk` ([`units::brilliantov_a`]); `None` when the scene gives no viscosity.
    pub viscous_a: Option<Vec<f64>>,
}

/// Masses and prefactors in scene units, with the unit scales and material of a physical scene.
pub(super) struct Inertia {
    pub mass: Vec<f64>,
    pub prefactor: Vec<f64>,
    pub scales: Option<UnitScales>,
    pub material: Option<Material>,
}

/// Masses and prefactors of a dimensionless scene (`physical` false) or a physical one.
pub(super) fn inertia(
    ctx: &Ctx,
    t: &Tables,
    s: &Specs,
    len: Len,
    physical: bool,
) -> Result<Inertia, SceneError> {
    if physical {
        return physical_inertia(ctx, t, s, len);
    }
    let mut mass = len.resolve(ctx, &s.mass, "[chain].mass", Per::Bead, DEFAULT_MASS)?;
    let mut prefactor = len.resolve(
        ctx,
        &s.prefactor,
        "[chain].prefactor",
        Per::Contact,
        DEFAULT_PREFACTOR,
    )?;
    if s.radius.is_some() {
        let r = len.resolve(ctx, &s.radius, "[chain].radius", Per::Bead, 1.0)?;
        positive(ctx, "[chain].radius", Per::Bead, &r)?;
        for (m, ri) in mass.iter_mut().zip(&r) {
            *m *= ri.powi(3);
        }
        for (c, a) in prefactor.iter_mut().enumerate() {
            *a *= (2.0 * r[c] * r[c + 1] / (r[c] + r[c + 1])).sqrt();
        }
    }
    Ok(Inertia {
        mass,
        prefactor,
        scales: None,
        material: None,
    })
}

/// Physical scene: SI masses and Hertz prefactors from the material data, in paper units.
fn physical_inertia(ctx: &Ctx, t: &Tables, s: &Specs, len: Len) -> Result<Inertia, SceneError> {
    let need = |s: &Option<Spec>, k: &str| -> Result<(), SceneError> {
        if s.is_none() {
            return Err(ctx.err(&kp("units", k), "required in a physical scene"));
        }
        Ok(())
    };
    need(&s.units_radius, "radius")?;
    need(&s.young, "young")?;
    need(&s.poisson, "poisson")?;
    need(&s.density, "density")?;
    let radius = len.resolve(ctx, &s.units_radius, "[units].radius", Per::Bead, 0.0)?;
    let young = len.resolve(ctx, &s.young, "[units].young", Per::Bead, 0.0)?;
    let poisson = len.resolve(ctx, &s.poisson, "[units].poisson", Per::Bead, 0.0)?;
    let density = len.resolve(ctx, &s.density, "[units].density", Per::Bead, 0.0)?;
    positive(ctx, "[units].radius", Per::Bead, &radius)?;
    positive(ctx, "[units].young", Per::Bead, &young)?;
    positive(ctx, "[units].density", Per::Bead, &density)?;
    if let Some(i) = poisson.iter().position(|p| !(*p > -1.0 && *p <= 0.5)) {
        return Err(ctx.index_err(
            "[units].poisson",
            Per::Bead,
            i,
            format!("must be in (-1, 0.5], got {}", poisson[i]),
        ));
    }
    let mass_si: Vec<f64> = radius
        .iter()
        .zip(&density)
        .map(|(r, d)| units::sphere_mass(*r, *d))
        .collect();
    let pref_si: Vec<f64> = (0..len.nc)
        .map(|c| {
            let d = units::hertz_d(young[c], poisson[c], young[c + 1], poisson[c + 1]);
            units::hertz_prefactor(radius[c], radius[c + 1], d)
        })
        .collect();
    let viscous_a = viscous_constants(ctx, s, len, &young, &poisson)?;
    let sc = time_scale(ctx, &t.units, mass_si[0], pref_si[0])?;
    Ok(Inertia {
        mass: mass_si.iter().map(|m| sc.mass(*m)).collect(),
        prefactor: pref_si.iter().map(|a| sc.prefactor(*a)).collect(),
        scales: Some(sc),
        material: Some(Material {
            radius,
            young,
            poisson,
            density,
            viscous_a,
        }),
    })
}

/// Per-bead `A` (s) of Brilliantov et al. from `[units] viscosity_shear`, `viscosity_bulk`
/// (Pa·s; both or neither), Young's moduli and Poisson ratios (which must then be > 0).
fn viscous_constants(
    ctx: &Ctx,
    s: &Specs,
    len: Len,
    young: &[f64],
    poisson: &[f64],
) -> Result<Option<Vec<f64>>, SceneError> {
    match (&s.viscosity_shear, &s.viscosity_bulk) {
        (None, None) => return Ok(None),
        (Some(_), None) => {
            return Err(ctx.err(
                "[units].viscosity_bulk",
                "missing: the viscoelastic constant needs both viscosity_shear and viscosity_bulk",
            ))
        }
        (None, Some(_)) => {
            return Err(ctx.err(
                "[units].viscosity_shear",
                "missing: the viscoelastic constant needs both viscosity_shear and viscosity_bulk",
            ))
        }
        (Some(_), Some(_)) => {}
    }
    let mut eta = Vec::with_capacity(2);
    for (spec, key) in [
        (&s.viscosity_shear, "[units].viscosity_shear"),
        (&s.viscosity_bulk, "[units].viscosity_bulk"),
    ] {
        let x = len.resolve(ctx, spec, key, Per::Bead, 0.0)?;
        if let Some(i) = x.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
            let msg = format!("must be a finite number >= 0 (Pa·s), got {}", x[i]);
            return Err(ctx.index_err(key, Per::Bead, i, msg));
        }
        eta.push(x);
    }
    if let Some(i) = poisson.iter().position(|p| *p <= 0.0) {
        return Err(ctx.index_err(
            "[units].poisson",
            Per::Bead,
            i,
            format!(
                "must be > 0 with viscosities (the viscoelastic constant grows as (1 − 2ν)/ν²), got {}",
                poisson[i]
            ),
        ));
    }
    Ok(Some(
        (0..young.len())
            .map(|i| units::brilliantov_a(young[i], poisson[i], eta[0][i], eta[1][i]))
            .collect(),
    ))
}

/// `[units].time_scale`: `"paper"` (eqs. 10–11, with `m0`, `n0`, `mu` defaulting to the first
/// bead's mass, [`units::DEFAULT_N0`] and the first prefactor's order of magnitude) or `"si"`.
fn time_scale(ctx: &Ctx, u: &UnitsKeys, mass0: f64, pref0: f64) -> Result<UnitScales, SceneError> {
    match opt_str(ctx, "[units].time_scale", &u.time_scale)? {
        None | Some("paper") => {
            let pos = |k: &str, v: &Opt| -> Result<Option<f64>, SceneError> {
                match opt_num(ctx, &kp("units", k), v)? {
                    Some(x) if x <= 0.0 => {
                        Err(ctx.err(&kp("units", k), format!("must be > 0, got {x}")))
                    }
                    x => Ok(x),
                }
            };
            let m0 = pos("m0", &u.m0)?.unwrap_or(mass0);
            let n0 = pos("n0", &u.n0)?.unwrap_or(units::DEFAULT_N0);
            let mu = pos("mu", &u.mu)?.unwrap_or_else(|| UnitScales::order_of_magnitude(pref0));
            if n0 <= 0.0 || n0.is_nan() {
                return Err(ctx.err(
                    "[units].n0",
                    format!("typical exponent must be > 0, got {n0}"),
                ));
            }
            Ok(UnitScales::paper(m0, mu, n0))
        }
        Some("si") => {
            let keys = [("m0", &u.m0), ("n0", &u.n0), ("mu", &u.mu)];
            forbid(
                ctx,
                "[units]",
                &keys,
                "only used with time_scale = \"paper\"",
            )?;
            Ok(UnitScales::si())
        }
        Some(s) => Err(ctx.err(
            "[units].time_scale",
            format!("expected \"paper\" or \"si\", got \"{s}\""),
        )),
    }
}
