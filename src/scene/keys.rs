//! Small typed accessors for the keys of scene tables (the fields of their
//! [`super::ctx::table_keys`] structs): every failure is a [`SceneError`] naming the key path.

use super::error::SceneError;
use super::values::{number, type_name, Ctx, Per, Spec};
use toml::Value;

/// A key of a table: its TOML value, `None` when absent.
pub(crate) type Opt = Option<Value>;

/// Why a key of physical scenes (an `_si` key, `[units]` material data) is refused in another.
pub(crate) const PHYSICAL_ONLY: &str =
    "only allowed in a physical scene ([units] system = \"physical\")";

/// Key path of `key` inside `[table]`.
pub(crate) fn kp(table: &str, key: &str) -> String {
    format!("[{table}].{key}")
}

/// The value form at `key` ([`Spec`]), `None` when absent.
pub(crate) fn opt_spec(ctx: &Ctx, key: &str, v: &Opt) -> Result<Option<Spec>, SceneError> {
    v.as_ref().map(|v| Spec::parse(ctx, key, v)).transpose()
}

/// The number at `key`, `None` when absent.
pub(crate) fn opt_num(ctx: &Ctx, key: &str, v: &Opt) -> Result<Option<f64>, SceneError> {
    v.as_ref().map(|v| number(ctx, key, v)).transpose()
}

/// The string at `key`, `None` when absent.
pub(crate) fn opt_str<'a>(ctx: &Ctx, key: &str, v: &'a Opt) -> Result<Option<&'a str>, SceneError> {
    v.as_ref()
        .map(|v| {
            v.as_str()
                .ok_or_else(|| ctx.err(key, format!("expected a string, got {}", type_name(v))))
        })
        .transpose()
}

/// Reject the keys of the table at `path` (`[chain]`) given that it does not allow (`why`).
pub(crate) fn forbid(
    ctx: &Ctx,
    path: &str,
    keys: &[(&str, &Opt)],
    why: &str,
) -> Result<(), SceneError> {
    match keys.iter().find(|(_, v)| v.is_some()) {
        Some((k, _)) => Err(ctx.err(&format!("{path}.{k}"), why.to_string())),
        None => Ok(()),
    }
}

/// At most one of two alternative keys of `[table]`.
pub(crate) fn exclusive(
    ctx: &Ctx,
    table: &str,
    (a, va): (&str, &Opt),
    (b, vb): (&str, &Opt),
) -> Result<(), SceneError> {
    if va.is_some() && vb.is_some() {
        return Err(ctx.err(
            &kp(table, b),
            format!("give either `{a}` or `{b}`, not both"),
        ));
    }
    Ok(())
}

/// Check every entry of a resolved array is `> 0` (radii, densities, moduli).
pub(crate) fn positive(ctx: &Ctx, key: &str, per: Per, v: &[f64]) -> Result<(), SceneError> {
    match v.iter().position(|x| *x <= 0.0 || x.is_nan()) {
        Some(i) => Err(ctx.index_err(key, per, i, format!("must be > 0, got {}", v[i]))),
        None => Ok(()),
    }
}
