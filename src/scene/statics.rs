//! Static keys (issue 35, part 2): `[chain] precompression_force = F0` (every contact's `Δ`
//! from the force it carries, `Δ = (F0/(n a))^{1/(n−1)}`, and the soft walls' unless they give
//! their own `precompression`), `[walls] force = F0` (the left wall's static force; the right
//! wall's `Δ_R` follows) and `[initial] equilibrium = true` (the displacements of the chain at
//! rest under its walls and field, [`crate::studies::equilibrium`]) and
//! `[initial] mode = { index = j, amplitude = A }` (mode `j` of the chain linearised about that
//! state, [`crate::studies::modes`], scaled so that its largest bead displacement is `A`, added
//! to the displacements).
//!
//! Physical scenes may give the forces in newtons instead, `precompression_force_si` and
//! `[walls] force_si`, converted to computer units by `W β² / m0` (paper eq. 11,
//! [`UnitScales::force`]). The contacts (and walls) that the balance leaves without force, apart
//! or just touching, are returned as one warning line ([`apply`]).

use super::ctx::table_of;
use super::error::SceneError;
use super::keys::{exclusive, kp, opt_num, Opt};
use super::tables::{ModeKeys, Tables};
use super::units::UnitScales;
use super::values::{index, number, type_name, Ctx};
use super::Scene;
use crate::studies::equilibrium::{equilibrium, overlap_for_force, Equilibrium};
use crate::studies::modes::{linearize, solve};
use toml::Value;

/// How many gaps the warning names before summarising.
const GAPS_LISTED: usize = 6;

/// A force given as `key` (computer units) or `key_si` (newtons, physical scenes only; the
/// tables refuse it elsewhere): `(value in computer units, key path given, value as written)`.
/// Giving both is an error.
fn force_key(
    ctx: &Ctx,
    table: &str,
    (key, plain): (&str, &Opt),
    si: &Opt,
    scales: Option<UnitScales>,
) -> Result<Option<(f64, String, f64)>, SceneError> {
    let si_key = format!("{key}_si");
    exclusive(ctx, table, (key, plain), (&si_key, si))?;
    if let Some(f) = opt_num(ctx, &kp(table, key), plain)? {
        return Ok(Some((f, kp(table, key), f)));
    }
    let Some(f) = opt_num(ctx, &kp(table, &si_key), si)? else {
        return Ok(None);
    };
    match scales {
        Some(sc) => Ok(Some((sc.force(f), kp(table, &si_key), f))),
        None => Err(ctx.err(&kp(table, &si_key), "needs a physical scene")),
    }
}

/// `[chain] precompression_force` (or `precompression_force_si`), checked positive, in computer
/// units (`None` when absent). Giving it with `precompression` is an error.
pub(super) fn precompression_force(
    ctx: &Ctx,
    t: &Tables,
    scales: Option<UnitScales>,
) -> Result<Option<f64>, SceneError> {
    let c = &t.chain;
    let plain = ("precompression_force", &c.precompression_force);
    let Some((f, key, raw)) = force_key(ctx, "chain", plain, &c.precompression_force_si, scales)?
    else {
        return Ok(None);
    };
    let name = key.trim_start_matches("[chain].");
    if c.precompression.is_some() {
        return Err(ctx.err(
            &key,
            format!("give either `precompression` or `{name}`, not both"),
        ));
    }
    if raw <= 0.0 {
        return Err(ctx.err(&key, format!("must be > 0, got {raw}")));
    }
    Ok(Some(f))
}

/// The per-contact precompression that makes every contact carry `force`.
pub(super) fn precompression_of(force: f64, exponent: &[f64], prefactor: &[f64]) -> Vec<f64> {
    exponent
        .iter()
        .zip(prefactor)
        .map(|(n, a)| overlap_for_force(*n, *a, force))
        .collect()
}

/// `[initial] equilibrium`: `true`, `false` or absent.
fn wants_equilibrium(ctx: &Ctx, t: &Tables) -> Result<bool, SceneError> {
    match &t.initial.equilibrium {
        None => Ok(false),
        Some(Value::Boolean(b)) => Ok(*b),
        Some(v) => Err(ctx.err(
            "[initial].equilibrium",
            format!("expected true or false, got {}", type_name(v)),
        )),
    }
}

/// Applies `[walls] force` (`force_si`) and `[initial] equilibrium` to the built scene: the
/// right wall's precompression and the displacements at rest. Returns the warnings: the gaps the
/// balance leaves ([`gap_warning`]).
pub(super) fn apply(ctx: &Ctx, t: &Tables, scene: &mut Scene) -> Result<Vec<String>, SceneError> {
    let eq = wants_equilibrium(ctx, t)?;
    let w = &t.walls;
    let force = force_key(ctx, "walls", ("force", &w.force), &w.force_si, scene.units)?;
    if let Some((_, k, raw)) = &force {
        if *raw < 0.0 {
            return Err(ctx.err(k, format!("must be >= 0 (a compressive force), got {raw}")));
        }
        if scene.chain.left_wall.is_none() || scene.chain.right_wall.is_none() {
            return Err(ctx.err(k, "needs both walls ([walls] left and right)"));
        }
        if !eq {
            return Err(ctx.err(
                k,
                "needs `[initial] equilibrium = true` (the chain starts at rest under the force)",
            ));
        }
        if (w.right.as_ref().and_then(|r| r.get("precompression"))).is_some() {
            return Err(ctx.err(
                "[walls].right.precompression",
                format!("is set by `{k}` (the right wall is placed where it carries the force); remove it"),
            ));
        }
    }
    let mut warnings = Vec::new();
    if eq {
        let e = at_rest(ctx, t, scene, force.map(|f| f.0))?;
        warnings.extend(gap_warning(&scene.name, &e, scene.chain.len()));
    }
    let shape = "a table { index, amplitude }";
    if let Some(m) = table_of(ctx, "[initial].mode", t.initial.mode.as_ref(), shape)? {
        add_mode(ctx, m, scene)?;
    }
    Ok(warnings)
}

/// One line naming the contacts (and walls) that carry no force at rest, `None` when every
/// one is loaded: `NAME: [initial].equilibrium: gaps at rest (no force: ...): contacts 3
/// (beads 3-4), 7 (beads 7-8); the right wall (bead 9)`, naming the scene as the validation
/// warnings do. At most [`GAPS_LISTED`] contacts are named.
fn gap_warning(name: &str, e: &Equilibrium, beads: usize) -> Option<String> {
    let mut parts = Vec::new();
    if !e.gaps.is_empty() {
        let named: Vec<String> = e
            .gaps
            .iter()
            .take(GAPS_LISTED)
            .map(|c| format!("{c} (beads {c}-{})", c + 1))
            .collect();
        let more = e.gaps.len().saturating_sub(GAPS_LISTED);
        let tail = if more > 0 {
            format!(" and {more} more ({} of {})", e.gaps.len(), beads - 1)
        } else {
            String::new()
        };
        let noun = if e.gaps.len() == 1 {
            "contact"
        } else {
            "contacts"
        };
        parts.push(format!("{noun} {}{tail}", named.join(", ")));
    }
    for (side, f, bead) in [
        ("left", e.wall_force[0], 0),
        ("right", e.wall_force[1], beads - 1),
    ] {
        if f == Some(0.0) {
            parts.push(format!("the {side} wall (bead {bead})"));
        }
    }
    (!parts.is_empty()).then(|| {
        format!(
            "{name}: [initial].equilibrium: gaps at rest (no force: the beads are apart or just touching): {}",
            parts.join("; ")
        )
    })
}

/// `[initial] equilibrium = true`: the displacements at rest (and `Δ_R` for `[walls] force`).
fn at_rest(
    ctx: &Ctx,
    t: &Tables,
    scene: &mut Scene,
    force: Option<f64>,
) -> Result<Equilibrium, SceneError> {
    if t.initial.displacement.is_some() {
        return Err(ctx.err(
            "[initial].displacement",
            "`[initial] equilibrium = true` sets the displacements; remove `displacement`",
        ));
    }
    if t.initial.solitary.is_some() {
        // the wave's overlaps are displacements: the balance at rest would replace them and
        // keep the wave's velocities, a state that is not the wave
        return Err(ctx.err(
            "[initial].solitary",
            "`[initial] equilibrium = true` sets the displacements at rest, which would drop the wave's overlaps; a solitary wave travels on a chain without precompression: remove `equilibrium` (or `solitary`)",
        ));
    }
    let e = equilibrium(&scene.chain, &scene.u0, force)
        .map_err(|e| ctx.err("[initial].equilibrium", e.to_string()))?;
    if let (Some(dr), Some(w)) = (e.right_precompression, scene.chain.right_wall.as_mut()) {
        w.precompression = dr;
    }
    scene.u0 = e.u.clone();
    Ok(e)
}

/// `[initial] mode = { index, amplitude }`: adds mode `index` (0 = lowest frequency) of the
/// chain linearised about the displacements so far, its largest bead displacement `amplitude`.
fn add_mode(ctx: &Ctx, m: ModeKeys, scene: &mut Scene) -> Result<(), SceneError> {
    let k = "[initial].mode";
    let j = match &m.index {
        Some(v) => index(ctx, "[initial].mode.index", v)?,
        None => return Err(ctx.err("[initial].mode.index", "missing")),
    };
    let amp = match &m.amplitude {
        Some(v) => number(ctx, "[initial].mode.amplitude", v)?,
        None => return Err(ctx.err("[initial].mode.amplitude", "missing")),
    };
    let nb = scene.chain.len();
    if j >= nb {
        return Err(ctx.err(
            "[initial].mode.index",
            format!("must be in 0..{nb} (one mode per bead), got {j}"),
        ));
    }
    let lin = linearize(&scene.chain, &scene.u0).map_err(|e| ctx.err(k, e.to_string()))?;
    let modes = solve(&lin, None).map_err(|e| ctx.err(k, e.to_string()))?;
    if let Some(i) = degenerate_with(&modes.omega2, modes.omega2_max, j) {
        return Err(ctx.err(
            "[initial].mode.index",
            format!(
                "mode {j} shares its frequency (omega^2 = {:.3e}) with mode {i}, so its shape is not defined (any mix of the two is a mode){}",
                modes.omega2[j],
                match lin.open_contacts().len() {
                    0 => "; symmetric parts of the chain (e.g. two identical impurities) vibrate alike: break the symmetry, or start from a mix of both modes with `displacement`".to_string(),
                    k => format!(
                        ": the chain's contacts without stiffness ({k} of {}) split it into parts that vibrate alone; precompress it (`precompression` or `equilibrium` under a force)",
                        nb.saturating_sub(1)
                    ),
                }
            ),
        ));
    }
    let x = &modes.shapes[j];
    let big = x.iter().fold(0.0f64, |b, v| b.max(v.abs()));
    for (u, xi) in scene.u0.iter_mut().zip(x) {
        *u += amp * xi / big;
    }
    Ok(())
}

/// A neighbour of mode `j` with the same `ω²` (within `1e-12` of the largest, `top`): a
/// degenerate eigenvalue, whose eigenvector the solver picks arbitrarily in the shared space.
/// The tridiagonal `K` of a connected chain has simple eigenvalues in exact arithmetic, but
/// contacts without stiffness split it (a sonic vacuum: every mode at `ω = 0`), and symmetric
/// parts far apart (two identical impurities) give pairs equal to round-off.
fn degenerate_with(omega2: &[f64], top: f64, j: usize) -> Option<usize> {
    let tol = 1e-12 * top;
    [j.checked_sub(1), Some(j + 1)]
        .into_iter()
        .flatten()
        .find(|&i| i < omega2.len() && (omega2[i] - omega2[j]).abs() <= tol)
}
