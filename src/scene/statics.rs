//! Static keys (issue 35, part 2): `[chain] precompression_force = F0` (every contact's `Δ`
//! from the force it carries, `Δ = (F0/(n a))^{1/(n−1)}`, and the soft walls' unless they give
//! their own `precompression`), `[walls] force = F0` (the left wall's static force; the right
//! wall's `Δ_R` follows) and `[initial] equilibrium = true` (the displacements of the chain at
//! rest under its walls and field, [`crate::studies::equilibrium`]) and
//! `[initial] mode = { index = j, amplitude = A }` (mode `j` of the chain linearised about that
//! state, [`crate::studies::modes`], scaled so that its largest bead displacement is `A`, added
//! to the displacements).

use super::error::SceneError;
use super::keys::{get, opt_num};
use super::tables::Tables;
use super::values::{check_keys, index, number, type_name, Ctx};
use super::Scene;
use crate::studies::equilibrium::{equilibrium, overlap_for_force};
use crate::studies::modes::{linearize, solve};
use toml::Value;

/// `[chain] precompression_force`, checked positive (`None` when absent). Giving it with
/// `precompression` is an error.
pub(super) fn precompression_force(ctx: &Ctx, t: &Tables) -> Result<Option<f64>, SceneError> {
    let Some(f) = opt_num(ctx, t.chain, "chain", "precompression_force")? else {
        return Ok(None);
    };
    if get(t.chain, "precompression").is_some() {
        return Err(ctx.err(
            "[chain].precompression_force",
            "give either `precompression` or `precompression_force`, not both",
        ));
    }
    if f <= 0.0 {
        return Err(ctx.err(
            "[chain].precompression_force",
            format!("must be > 0, got {f}"),
        ));
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
    match get(t.initial, "equilibrium") {
        None => Ok(false),
        Some(Value::Boolean(b)) => Ok(*b),
        Some(v) => Err(ctx.err(
            "[initial].equilibrium",
            format!("expected true or false, got {}", type_name(v)),
        )),
    }
}

/// Applies `[walls] force` and `[initial] equilibrium` to the built scene: the right wall's
/// precompression and the displacements at rest.
pub(super) fn apply(ctx: &Ctx, t: &Tables, scene: &mut Scene) -> Result<(), SceneError> {
    let eq = wants_equilibrium(ctx, t)?;
    let force = opt_num(ctx, t.walls, "walls", "force")?;
    if let Some(f) = force {
        let k = "[walls].force";
        if f < 0.0 {
            return Err(ctx.err(k, format!("must be >= 0 (a compressive force), got {f}")));
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
        if get(t.walls, "right")
            .and_then(|r| r.get("precompression"))
            .is_some()
        {
            return Err(ctx.err(
                "[walls].right.precompression",
                "is set by `[walls] force` (the right wall is placed where it carries the force); remove it",
            ));
        }
    }
    if eq {
        at_rest(ctx, t, scene, force)?;
    }
    if let Some(m) = get(t.initial, "mode") {
        add_mode(ctx, m, scene)?;
    }
    Ok(())
}

/// `[initial] equilibrium = true`: the displacements at rest (and `Δ_R` for `[walls] force`).
fn at_rest(ctx: &Ctx, t: &Tables, scene: &mut Scene, force: Option<f64>) -> Result<(), SceneError> {
    if get(t.initial, "displacement").is_some() {
        return Err(ctx.err(
            "[initial].displacement",
            "`[initial] equilibrium = true` sets the displacements; remove `displacement`",
        ));
    }
    let e = equilibrium(&scene.chain, &scene.u0, force)
        .map_err(|e| ctx.err("[initial].equilibrium", e.to_string()))?;
    if let (Some(dr), Some(w)) = (e.right_precompression, scene.chain.right_wall.as_mut()) {
        w.precompression = dr;
    }
    scene.u0 = e.u;
    Ok(())
}

/// `[initial] mode = { index, amplitude }`: adds mode `index` (0 = lowest frequency) of the
/// chain linearised about the displacements so far, its largest bead displacement `amplitude`.
fn add_mode(ctx: &Ctx, m: &Value, scene: &mut Scene) -> Result<(), SceneError> {
    let k = "[initial].mode";
    let mt = m.as_table().ok_or_else(|| {
        ctx.err(
            k,
            format!(
                "expected a table {{ index, amplitude }}, got {}",
                type_name(m)
            ),
        )
    })?;
    check_keys(ctx, k, mt, &["index", "amplitude"])?;
    let j = match mt.get("index") {
        Some(v) => index(ctx, "[initial].mode.index", v)?,
        None => return Err(ctx.err("[initial].mode.index", "missing")),
    };
    let amp = match mt.get("amplitude") {
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
    let x = &modes.shapes[j];
    let big = x.iter().fold(0.0f64, |b, v| b.max(v.abs()));
    for (u, xi) in scene.u0.iter_mut().zip(x) {
        *u += amp * xi / big;
    }
    Ok(())
}
