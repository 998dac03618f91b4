//! Small typed accessors for TOML tables: every failure is a [`SceneError`] naming the key path.

use super::error::SceneError;
use super::values::{check_keys, number, type_name, Ctx, Per, Spec};
use toml::{Table, Value};

/// A top-level table, with its keys checked.
pub(crate) fn table<'a>(
    ctx: &Ctx,
    root: &'a Table,
    name: &str,
    allowed: &[&str],
) -> Result<Option<&'a Table>, SceneError> {
    match root.get(name) {
        None => Ok(None),
        Some(Value::Table(t)) => {
            check_keys(ctx, &format!("[{name}]"), t, allowed)?;
            Ok(Some(t))
        }
        Some(v) => Err(ctx.err(
            &format!("[{name}]"),
            format!("expected a table, got {}", type_name(v)),
        )),
    }
}

/// Key path of `key` inside `[table]`.
pub(crate) fn kp(table: &str, key: &str) -> String {
    format!("[{table}].{key}")
}

pub(crate) fn get<'a>(t: Option<&'a Table>, key: &str) -> Option<&'a Value> {
    t.and_then(|t| t.get(key))
}

pub(crate) fn opt_spec(
    ctx: &Ctx,
    t: Option<&Table>,
    table: &str,
    key: &str,
) -> Result<Option<Spec>, SceneError> {
    get(t, key)
        .map(|v| Spec::parse(ctx, &kp(table, key), v))
        .transpose()
}

pub(crate) fn opt_num(
    ctx: &Ctx,
    t: Option<&Table>,
    table: &str,
    key: &str,
) -> Result<Option<f64>, SceneError> {
    get(t, key)
        .map(|v| number(ctx, &kp(table, key), v))
        .transpose()
}

pub(crate) fn opt_str<'a>(
    ctx: &Ctx,
    t: Option<&'a Table>,
    table: &str,
    key: &str,
) -> Result<Option<&'a str>, SceneError> {
    get(t, key)
        .map(|v| {
            v.as_str().ok_or_else(|| {
                ctx.err(
                    &kp(table, key),
                    format!("expected a string, got {}", type_name(v)),
                )
            })
        })
        .transpose()
}

/// Reject a key that only makes sense in the other unit system.
pub(crate) fn forbid(
    ctx: &Ctx,
    t: Option<&Table>,
    table: &str,
    keys: &[&str],
    why: &str,
) -> Result<(), SceneError> {
    for k in keys {
        if get(t, k).is_some() {
            return Err(ctx.err(&kp(table, k), why.to_string()));
        }
    }
    Ok(())
}

/// At most one of two alternative keys.
pub(crate) fn exclusive(
    ctx: &Ctx,
    t: Option<&Table>,
    table: &str,
    a: &str,
    b: &str,
) -> Result<(), SceneError> {
    if get(t, a).is_some() && get(t, b).is_some() {
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
