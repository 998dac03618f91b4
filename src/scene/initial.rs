//! The initial state (`[initial]`: displacements, velocities, a pulse of equal velocities, the
//! strikers at either end) and the external field (`[field]`: per-bead forces `W_i`, positive
//! towards increasing `u`, plus gravity `g` pulling towards decreasing `u`, `W_i −= m_i g`;
//! paper eq. 7). The `_si` keys of physical scenes are converted with the scene's [`UnitScales`].

use super::arrays::{Len, Specs};
use super::error::SceneError;
use super::keys::{exclusive, get, opt_num};
use super::tables::Tables;
use super::units::UnitScales;
use super::values::{check_keys, index, number, type_name, Ctx, Per};
use toml::Value;

/// Initial displacements `u0` and velocities `v0`.
pub(super) fn initial_state(
    ctx: &Ctx,
    t: &Tables,
    s: &Specs,
    len: Len,
    physical: bool,
    scales: Option<UnitScales>,
) -> Result<(Vec<f64>, Vec<f64>), SceneError> {
    let nb = len.nb;
    let u0 = len.resolve(
        ctx,
        &s.displacement,
        "[initial].displacement",
        Per::Bead,
        0.0,
    )?;
    let mut v0 = match (&s.velocity, &s.velocity_si, scales) {
        (_, Some(s), Some(sc)) => s
            .resolve(ctx, "[initial].velocity_si", nb, Per::Bead, 0.0)?
            .into_iter()
            .map(|v| sc.velocity(v))
            .collect(),
        _ => len.resolve(ctx, &s.velocity, "[initial].velocity", Per::Bead, 0.0)?,
    };
    if let Some(pv) = get(t.initial, "pulse") {
        let (l, v) = pulse(ctx, pv, nb, physical, scales)?;
        v0[..l].fill(v);
    }
    let si_or = |plain: &str, si: &str| -> Result<Option<f64>, SceneError> {
        if let Some(x) = opt_num(ctx, t.initial, "initial", plain)? {
            return Ok(Some(x));
        }
        match (opt_num(ctx, t.initial, "initial", si)?, scales) {
            (Some(x), Some(sc)) => Ok(Some(sc.velocity(x))),
            _ => Ok(None),
        }
    };
    if let Some(v) = si_or("striker", "striker_si")? {
        v0[0] = v;
    }
    if let Some(v) = si_or("striker_right", "striker_right_si")? {
        v0[nb - 1] = -v;
    }
    Ok((u0, v0))
}

/// `[initial].pulse = { beads = L, velocity = v }`: the first `L` beads move with `v`.
fn pulse(
    ctx: &Ctx,
    pv: &Value,
    nb: usize,
    physical: bool,
    scales: Option<UnitScales>,
) -> Result<(usize, f64), SceneError> {
    let k = "[initial].pulse";
    let pt = pv.as_table().ok_or_else(|| {
        ctx.err(
            k,
            format!(
                "expected a table {{ beads, velocity }}, got {}",
                type_name(pv)
            ),
        )
    })?;
    let allowed: &[&str] = if physical {
        &["beads", "velocity", "velocity_si"]
    } else {
        &["beads", "velocity"]
    };
    check_keys(ctx, k, pt, allowed)?;
    let l = match pt.get("beads") {
        Some(b) => index(ctx, "[initial].pulse.beads", b)?,
        None => return Err(ctx.err("[initial].pulse.beads", "missing")),
    };
    if l == 0 || l > nb {
        return Err(ctx.err(
            "[initial].pulse.beads",
            format!("must be in 1..={nb}, got {l}"),
        ));
    }
    let v = match (pt.get("velocity"), pt.get("velocity_si"), scales) {
        (Some(_), Some(_), _) => {
            return Err(ctx.err(
                "[initial].pulse.velocity_si",
                "give either `velocity` or `velocity_si`, not both",
            ))
        }
        (Some(v), None, _) => number(ctx, "[initial].pulse.velocity", v)?,
        (None, Some(v), Some(sc)) => sc.velocity(number(ctx, "[initial].pulse.velocity_si", v)?),
        _ => return Err(ctx.err("[initial].pulse.velocity", "missing")),
    };
    Ok((l, v))
}

/// The external force per bead (`None` when zero everywhere).
pub(super) fn field(
    ctx: &Ctx,
    t: &Tables,
    s: &Specs,
    len: Len,
    scales: Option<UnitScales>,
    mass: &[f64],
) -> Result<Option<Vec<f64>>, SceneError> {
    exclusive(ctx, t.field, "field", "force", "force_si")?;
    exclusive(ctx, t.field, "field", "gravity", "gravity_si")?;
    let mut w = vec![0.0; len.nb];
    if s.force.is_some() {
        w = len.resolve(ctx, &s.force, "[field].force", Per::Bead, 0.0)?;
    } else if let (Some(s), Some(sc)) = (&s.force_si, scales) {
        w = s
            .resolve(ctx, "[field].force_si", len.nb, Per::Bead, 0.0)?
            .into_iter()
            .map(|f| sc.force(f))
            .collect();
    }
    let g = match (
        opt_num(ctx, t.field, "field", "gravity")?,
        opt_num(ctx, t.field, "field", "gravity_si")?,
        scales,
    ) {
        (Some(g), _, _) => g,
        (None, Some(g), Some(sc)) => sc.acceleration(g),
        _ => 0.0,
    };
    if g != 0.0 {
        for (wi, m) in w.iter_mut().zip(mass) {
            *wi -= m * g;
        }
    }
    Ok(w.iter().any(|x| *x != 0.0).then_some(w))
}
