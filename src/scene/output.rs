//! The `[output]` table of a scene (issue 14): the output selection of `beadchain run` as scene
//! keys, with the grammar and rules of [`super::selection`]:
//!
//! ```toml
//! [output]
//! beads = "0:100:10"   # or an array of bead indices, e.g. [3, 10, 20], or one index
//! fields = "v"         # "u", "v" or "u,v"
//! frames_max = 1000    # refuse a run that would write more frames
//! ```
//!
//! `run --beads/--fields/--frames-max` override the keys one by one. The table is not stored
//! in snapshots as such: the snapshot header records the selection the run used.

use super::ctx::table_of;
use super::error::SceneError;
use super::keys::Opt;
use super::selection::{parse_beads, Fields, Selection};
use super::tables::OutputKeys;
use super::values::{type_name, Ctx};
use toml::Value;

/// What a value of an `[output]` key may be, and what each item of its array may be.
#[derive(Clone, Copy)]
struct Expected {
    all: &'static str,
    item: &'static str,
}

const BEADS_EXPECTED: Expected = Expected {
    all: "a bead index, a string such as \"0:100:10\" or an array of bead indices",
    item: "a bead index (an integer >= 0)",
};
const FIELDS_EXPECTED: Expected = Expected {
    all: "a string such as \"u,v\" or an array of field names",
    item: "a field name (a string)",
};

/// The `[output]` table of a chain of `nb` beads (`None` when the scene has none).
pub(crate) fn parse_output(
    ctx: &Ctx,
    output: &Opt,
    nb: usize,
) -> Result<Option<Selection>, SceneError> {
    let Some(t) = table_of::<OutputKeys>(ctx, "[output]", output.as_ref(), "a table")? else {
        return Ok(None);
    };
    let beads = match &t.beads {
        None => None,
        Some(v) => {
            let spec = spec_text(ctx, "[output].beads", v, BEADS_EXPECTED, |x| match x {
                Value::Integer(i) if *i >= 0 => Some(i.to_string()),
                _ => None,
            })?;
            parse_beads(&spec, nb as u64).map_err(|e| ctx.err("[output].beads", e.to_string()))?
        }
    };
    let fields = match &t.fields {
        None => Fields::Both,
        Some(v) => {
            let spec = spec_text(ctx, "[output].fields", v, FIELDS_EXPECTED, |x| {
                x.as_str().map(str::to_string)
            })?;
            Fields::parse(&spec).map_err(|e| ctx.err("[output].fields", e.to_string()))?
        }
    };
    let frames_max = match &t.frames_max {
        None => None,
        Some(Value::Integer(k)) if *k >= 2 => Some(*k as u64),
        Some(v) => {
            return Err(ctx.err(
                "[output].frames_max",
                format!(
                    "must be an integer >= 2 (a run writes its first and its last frame), got {v}"
                ),
            ))
        }
    };
    Ok(Some(Selection {
        beads,
        fields,
        frames_max,
    }))
}

/// A string value as is, or an array whose items `item` turns into text, joined by commas, or
/// one such item.
fn spec_text(
    ctx: &Ctx,
    key: &str,
    v: &Value,
    expected: Expected,
    item: impl Fn(&Value) -> Option<String>,
) -> Result<String, SceneError> {
    let bad = |what: &str| ctx.err(key, format!("expected {}, got {what}", expected.all));
    match v {
        Value::String(s) => Ok(s.clone()),
        Value::Array(a) => {
            let items = a.iter().enumerate().map(|(i, x)| {
                let what = || format!("expected {}, got {x}", expected.item);
                item(x).ok_or_else(|| ctx.err(&format!("{key}[{i}]"), what()))
            });
            Ok(items.collect::<Result<Vec<_>, _>>()?.join(","))
        }
        other => item(other).ok_or_else(|| bad(type_name(other))),
    }
}
