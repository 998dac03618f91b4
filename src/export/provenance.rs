//! Provenance of exported files, from the snapshot's HEADER: the beadchain version and build
//! commit that wrote it, its command line, scene name, engine settings and (runs with
//! `--timing`) date.
//!
//! - CSV (long and wide layouts, event log): comment lines before the column header,
//!   ```text
//!   # beadchain 0.1.0 commit 0123…abcd
//!   # created_by: beadchain run striker --out s.snap
//!   # scene: striker engine hybrid method auto rtol 1e-8 atol 1e-12
//!   # created_at: 2026-11-27T18:45:03Z
//!   ```
//!   always these 4 lines ([`CSV_COMMENT_LINES`]; `commit not recorded` for files written before
//!   commits were recorded, `created_at: not recorded (run with --timing …)` for runs without
//!   `--timing`), so readers can skip a fixed count: `pandas.read_csv(path, comment="#")`,
//!   `numpy.loadtxt(path, delimiter=",", skiprows=5)`,
//!   `numpy.genfromtxt(path, delimiter=",", names=True, skip_header=4)` (NumPy takes the first
//!   line for the names even when it is a comment). beadchain's own CSV readers skip `#`
//!   lines.
//! - `.npz`: the entry `provenance`, a 0-d NumPy unicode array (`<U{len}`, UTF-32LE) holding a
//!   JSON object with the keys `version`, `commit`, `created_at` (`null` when not recorded),
//!   `created_by`, `scene`, `engine`, `method`, `rtol`, `atol` and `exported_by` (the export's
//!   own command line): `json.loads(str(numpy.load(path)["provenance"]))`.

use super::Num;
use crate::names::Named;
use crate::snapshot::Header;

/// `s` on one line: control characters (newlines, tabs) become spaces.
fn one_line(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

/// `created_at` of a run without `--timing`.
pub const NO_DATE: &str = "not recorded (run with --timing to record the date)";

/// How many comment lines open every exported CSV.
pub const CSV_COMMENT_LINES: usize = 4;

/// The [`CSV_COMMENT_LINES`] comment lines (each ending in `\n`) that open every exported CSV
/// (see the module docs).
pub fn csv_comments(h: &Header) -> String {
    let mut s = format!(
        "# beadchain {} commit {}\n# created_by: {}\n# scene: {} engine {} method {} rtol {} atol {}\n",
        one_line(&h.crate_version),
        one_line(h.build_commit.as_deref().unwrap_or("not recorded")),
        one_line(&h.created_by),
        one_line(&h.scene.name),
        h.engine.name(),
        h.method.name(),
        Num(h.rtol),
        Num(h.atol),
    );
    let date = h.created_at.as_deref().unwrap_or(NO_DATE);
    s.push_str(&format!("# created_at: {}\n", one_line(date)));
    s
}

/// A JSON string literal of `s`.
fn json_str(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => out.push_str(&format!("\\u{:04x}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A JSON number (`null` when not finite).
fn json_num(x: f64) -> String {
    if x.is_finite() {
        Num(x).to_string()
    } else {
        "null".into()
    }
}

/// The JSON object of the `.npz` entry `provenance` (keys in the module docs).
pub fn json(h: &Header, exported_by: &str) -> String {
    let opt = |x: &Option<String>| x.as_deref().map_or("null".into(), json_str);
    let fields = [
        ("version", json_str(&h.crate_version)),
        ("commit", opt(&h.build_commit)),
        ("created_at", opt(&h.created_at)),
        ("created_by", json_str(&h.created_by)),
        ("scene", json_str(&h.scene.name)),
        ("engine", json_str(h.engine.name())),
        ("method", json_str(h.method.name())),
        ("rtol", json_num(h.rtol)),
        ("atol", json_num(h.atol)),
        ("exported_by", json_str(exported_by)),
    ];
    let body: Vec<String> = fields
        .iter()
        .map(|(k, v)| format!("{}: {v}", json_str(k)))
        .collect();
    format!("{{{}}}", body.join(", "))
}

/// A `.npy` v1.0 file of a 0-d little-endian unicode array holding `text` (`<U{chars}`, shape
/// `()`, one UTF-32LE code unit per character).
pub fn npy_text(text: &str) -> Vec<u8> {
    let chars = text.chars().count().max(1);
    let mut b = super::npy_header(&format!("<U{chars}"), &[]);
    b.reserve(4 * chars);
    for c in text.chars() {
        b.extend_from_slice(&(c as u32).to_le_bytes());
    }
    if text.is_empty() {
        b.extend_from_slice(&[0; 4]);
    }
    b
}
