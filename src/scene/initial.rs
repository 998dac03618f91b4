//! The initial state (`[initial]`: displacements, velocities, a pulse of equal velocities, the
//! strikers at either end) and the external field (`[field]`: per-bead forces `W_i`, positive
//! towards increasing `u`, plus gravity `g` pulling towards decreasing `u`, `W_i −= m_i g`;
//! paper eq. 7). The `_si` keys of physical scenes are converted with the scene's [`UnitScales`].

use super::arrays::{Len, Specs};
use super::ctx::table_of;
use super::error::SceneError;
use super::keys::{exclusive, kp, opt_num, Opt, PHYSICAL_ONLY};
use super::tables::{PulseKeys, Tables};
use super::units::UnitScales;
use super::values::{index, number, Ctx, Per};

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
    let i = &t.initial;
    let pulse_keys = "a table { beads, velocity }";
    if let Some(p) = table_of(ctx, "[initial].pulse", i.pulse.as_ref(), pulse_keys)? {
        let (l, v) = pulse(ctx, p, nb, physical, scales)?;
        v0[..l].fill(v);
    }
    let si_or = |(plain, pv): (&str, &Opt), (si, sv): (&str, &Opt)| {
        if let Some(x) = opt_num(ctx, &kp("initial", plain), pv)? {
            return Ok(Some(x));
        }
        match (opt_num(ctx, &kp("initial", si), sv)?, scales) {
            (Some(x), Some(sc)) => Ok(Some(sc.velocity(x))),
            _ => Ok::<_, SceneError>(None),
        }
    };
    if let Some(v) = si_or(("striker", &i.striker), ("striker_si", &i.striker_si))? {
        v0[0] = v;
    }
    let right = (
        ("striker_right", &i.striker_right),
        ("striker_right_si", &i.striker_right_si),
    );
    if let Some(v) = si_or(right.0, right.1)? {
        v0[nb - 1] = -v;
    }
    Ok((u0, v0))
}

/// `[initial].pulse = { beads = L, velocity = v }`: the first `L` beads move with `v`.
fn pulse(
    ctx: &Ctx,
    p: PulseKeys,
    nb: usize,
    physical: bool,
    scales: Option<UnitScales>,
) -> Result<(usize, f64), SceneError> {
    if !physical && p.velocity_si.is_some() {
        return Err(ctx.err("[initial].pulse.velocity_si", PHYSICAL_ONLY));
    }
    let l = match &p.beads {
        Some(b) => index(ctx, "[initial].pulse.beads", b)?,
        None => return Err(ctx.err("[initial].pulse.beads", "missing")),
    };
    if l == 0 || l > nb {
        return Err(ctx.err(
            "[initial].pulse.beads",
            format!("must be in 1..={nb}, got {l}"),
        ));
    }
    let v = match (&p.velocity, &p.velocity_si, scales) {
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
    let f = &t.field;
    exclusive(ctx, "field", ("force", &f.force), ("force_si", &f.force_si))?;
    exclusive(
        ctx,
        "field",
        ("gravity", &f.gravity),
        ("gravity_si", &f.gravity_si),
    )?;
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
        opt_num(ctx, "[field].gravity", &f.gravity)?,
        opt_num(ctx, "[field].gravity_si", &f.gravity_si)?,
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
