//! `[hard]`: hard contacts (instantaneous collisions with restitution), and hard walls.
//!
//! ```toml
//! [hard]
//! contacts = "all"          # "all" | [k, ...] contact indices | { from = a, to = b } (inclusive)
//! restitution = 1.0         # e in [0, 1]: a number, or one value per listed contact; default 1
//! collapse_interval = 1e-6  # collapse interval t_c; default 1e-6 * L/V of the initial state
//!
//! [walls]
//! left = { hard = true, restitution = 0.9 }   # a hard wall (no force law)
//! ```
//!
//! **Default collapse interval.** `t_c = 10⁻⁶ · L/V` with the characteristic length `L` and
//! velocity `V` of the initial state ([`crate::model::Chain::scales`], the scales that make the
//! tolerances unit-free), so it scales with the scene and does not depend on `[run].until`.
//! Between free beads `t_c` only decides when an inelastic collision becomes a resting contact
//! (a bouncing ball sticks after about `log(v₀ / (g t_c)) / log(1/e)` bounces); for a hard
//! contact with a bead in a soft cluster it is the TC-model interval of the chatter.
//!
//! **Start state.** A hard contact may not start overlapping (`Δ + u_c − u_{c+1} > 0`) and a
//! bead may not start inside a hard wall: there is no force law that could push them apart, so
//! the run would start from an impossible state (energy rose ×36 in such a run).

use super::ctx::{fields, table_of};
use super::error::SceneError;
use super::keys::{forbid, kp, opt_num, Opt};
use super::tables::{HardKeys, RangeKeys, WallKeys};
use super::values::{number, type_name, Ctx};
use super::Scene;
use crate::model::HardContacts;
use toml::Value;

/// Parses `[hard]` for a chain of `nc` contacts. Without `collapse_interval` the interval is
/// NaN here, and [`default_collapse_interval`] sets it once the initial state is known.
pub(crate) fn parse_hard(
    ctx: &Ctx,
    hard: &Opt,
    nc: usize,
) -> Result<Option<HardContacts>, SceneError> {
    let Some(t) = table_of::<HardKeys>(ctx, "[hard]", hard.as_ref(), "a table")? else {
        return Ok(None);
    };
    let list = contact_list(ctx, &t, nc)?;
    let values = restitutions(ctx, &t, &list)?;
    let mut restitution = vec![None; nc];
    for (c, e) in list.iter().zip(values) {
        restitution[*c] = Some(e);
    }
    let given = opt_num(ctx, "[hard].collapse_interval", &t.collapse_interval)?;
    let collapse_interval = given.unwrap_or(f64::NAN);
    if given.is_some() && !(collapse_interval > 0.0 && collapse_interval.is_finite()) {
        return Err(ctx.err(
            &kp("hard", "collapse_interval"),
            format!("must be positive and finite, got {collapse_interval}"),
        ));
    }
    Ok(Some(HardContacts {
        restitution,
        collapse_interval,
    }))
}

/// `[hard].contacts`: `"all"`, a list of contact indices (each once) or `{ from, to }`.
fn contact_list(ctx: &Ctx, t: &HardKeys, nc: usize) -> Result<Vec<usize>, SceneError> {
    let key = kp("hard", "contacts");
    let list: Vec<usize> = match &t.contacts {
        None => {
            return Err(ctx.err(
                &key,
                "missing (\"all\", a list of contact indices, or { from, to })",
            ))
        }
        Some(Value::String(s)) if s == "all" => (0..nc).collect(),
        Some(Value::Array(a)) => {
            let mut out: Vec<usize> = Vec::with_capacity(a.len());
            let mut seen = vec![false; nc];
            for (i, v) in a.iter().enumerate() {
                let c = index(ctx, &format!("{key}[{i}]"), v, nc)?;
                if std::mem::replace(&mut seen[c], true) {
                    let j = out.iter().position(|&o| o == c).unwrap_or(0);
                    return Err(ctx.err(
                        &format!("{key}[{i}]"),
                        format!("contact {c} is listed twice (also at [{j}])"),
                    ));
                }
                out.push(c);
            }
            out
        }
        Some(Value::Table(r)) => {
            let r: RangeKeys = fields(ctx, &key, r)?;
            let from = (r.from.as_ref())
                .map(|v| index(ctx, &format!("{key}.from"), v, nc))
                .transpose()?
                .unwrap_or(0);
            let to = (r.to.as_ref())
                .map(|v| index(ctx, &format!("{key}.to"), v, nc))
                .transpose()?
                .unwrap_or(nc - 1);
            if to < from {
                return Err(ctx.err(&key, format!("empty range {from}..={to}")));
            }
            (from..=to).collect()
        }
        Some(v) => {
            return Err(ctx.err(
                &key,
                format!(
                    "expected \"all\", an array or {{ from, to }}, got {}",
                    type_name(v)
                ),
            ))
        }
    };
    Ok(list)
}

/// `[hard].restitution`: one value for every hard contact or one per contact, each in [0, 1].
fn restitutions(ctx: &Ctx, t: &HardKeys, list: &[usize]) -> Result<Vec<f64>, SceneError> {
    let rkey = kp("hard", "restitution");
    let values: Vec<f64> = match &t.restitution {
        None => vec![1.0; list.len()],
        Some(Value::Array(a)) => {
            if a.len() != list.len() {
                return Err(ctx.err(
                    &rkey,
                    format!(
                        "expected {} values (one per hard contact), got {}",
                        list.len(),
                        a.len()
                    ),
                ));
            }
            a.iter()
                .enumerate()
                .map(|(i, v)| number(ctx, &format!("{rkey}[{i}]"), v))
                .collect::<Result<_, _>>()?
        }
        Some(v) => vec![number(ctx, &rkey, v)?; list.len()],
    };
    for (i, e) in values.iter().enumerate() {
        if !(0.0..=1.0).contains(e) {
            return Err(ctx.err(
                &rkey,
                format!("restitution {e} of contact {} outside [0, 1]", list[i]),
            ));
        }
    }
    Ok(values)
}

/// Sets the default collapse interval (module docs) where `[hard]` did not give one.
pub(crate) fn default_collapse_interval(scene: &mut Scene) {
    let scales = scene.chain.scales(&scene.u0, &scene.v0);
    if let Some(h) = scene.chain.hard.as_mut() {
        if h.collapse_interval.is_nan() {
            h.collapse_interval = scales.collapse_interval();
        }
    }
}

/// Rejects a start state with a hard contact overlapping or a bead inside a hard wall.
pub(crate) fn check_start(ctx: &Ctx, scene: &Scene) -> Result<(), SceneError> {
    let (c, u) = (&scene.chain, &scene.u0);
    let n = c.len();
    for k in (0..n - 1).filter(|&k| c.hard_restitution(k).is_some()) {
        let d = c.overlap(k, u[k], u[k + 1]);
        if d > 0.0 {
            return Err(ctx.err(
                &kp("hard", "contacts"),
                format!(
                    "contact {k} (beads {k}–{}) starts overlapping by {d}",
                    k + 1
                ),
            ));
        }
    }
    for (side, wall, i, d) in [
        (
            "left",
            &c.left_wall,
            0,
            c.left_wall.as_ref().map(|w| w.precompression - u[0]),
        ),
        (
            "right",
            &c.right_wall,
            n - 1,
            c.right_wall.as_ref().map(|w| w.precompression + u[n - 1]),
        ),
    ] {
        match (wall.as_ref().and_then(|w| w.restitution), d) {
            (Some(_), Some(d)) if d > 0.0 => {
                return Err(ctx.err(
                    &format!("[walls].{side}"),
                    format!("bead {i} starts inside the hard wall by {d}"),
                ))
            }
            _ => {}
        }
    }
    Ok(())
}

/// A wall's `hard`/`restitution` keys: `Some(e)` for a hard wall.
pub(crate) fn wall_restitution(
    ctx: &Ctx,
    key: &str,
    wt: &WallKeys,
) -> Result<Option<f64>, SceneError> {
    let hard = match &wt.hard {
        None => false,
        Some(Value::Boolean(b)) => *b,
        Some(v) => {
            return Err(ctx.err(
                &format!("{key}.hard"),
                format!("expected true or false, got {}", type_name(v)),
            ))
        }
    };
    let e = opt_num(ctx, &format!("{key}.restitution"), &wt.restitution)?;
    match (hard, e) {
        (false, Some(_)) => Err(ctx.err(
            &format!("{key}.restitution"),
            "only a hard wall has a restitution (add hard = true)",
        )),
        (false, None) => Ok(None),
        (true, e) => {
            // A hard wall has no force law: a contact-law key would be silently ignored.
            let laws = [
                ("exponent", &wt.exponent),
                ("prefactor", &wt.prefactor),
                ("prefactor_si", &wt.prefactor_si),
            ];
            let why = "a hard wall has no force law (remove the key, or set hard = false)";
            forbid(ctx, key, &laws, why)?;
            let e = e.unwrap_or(1.0);
            if !(0.0..=1.0).contains(&e) {
                return Err(ctx.err(
                    &format!("{key}.restitution"),
                    format!("restitution {e} outside [0, 1]"),
                ));
            }
            Ok(Some(e))
        }
    }
}

fn index(ctx: &Ctx, key: &str, v: &Value, nc: usize) -> Result<usize, SceneError> {
    match v {
        Value::Integer(i) if *i >= 0 && (*i as usize) < nc => Ok(*i as usize),
        Value::Integer(i) => Err(ctx.err(
            key,
            format!("contact index {i} outside 0..{}", nc.saturating_sub(1)),
        )),
        other => Err(ctx.err(
            key,
            format!("expected a contact index, got {}", type_name(other)),
        )),
    }
}
