//! The three value forms of per-bead / per-contact keys, plus the builder tables that express
//! the paper's experiments without hand-written arrays.
//!
//! A value is one of
//! - a number (every entry equal),
//! - an array with exactly one number per bead (`N`) or per contact (`N−1`),
//! - `{ file = "x.csv" }`: one number per line, path relative to the scene file (blank lines and
//!   lines starting with `#` are skipped),
//! - a builder table, applied in this order:
//!   1. `base` (number | array | `{ file }`; default: `random.mean`, else `alternate[0]`, else
//!      the key's default),
//!   2. from index `start` (default 0) on, either `alternate = [x, y, ...]` (periodic chain,
//!      §4 of the paper) or `random = { mean, eps }` (uniform `mean + eps·r`, `r ∈ [−1, 1)`,
//!      eq. 19),
//!   3. `taper = { q, from }`: entry `i ≥ from` multiplied by `(1−q)^(i−from)`
//!      (`R_{i+1} = (1−q) R_i`),
//!   4. `segments = [{ from, to, value }, ...]` (inclusive index ranges; `to` defaults to the last
//!      index) and `impurity = { at, s, value }` (= segment `at ..= at+s−1`), in file order,
//!   5. `gaussian = { sigma, min }`: a `N(0, sigma²)` draw added to every entry, redrawn until the
//!      result is `> min` (default `min = 2.0`; eq. B.1).
//!
//! Random draws come from `ChaCha8Rng::seed_from_u64(seed)` with the stream set to a 64-bit
//! FNV-1a hash of the key path, so each key has its own reproducible stream and adding a random
//! key elsewhere does not change this one. Gaussians use Box–Muller (cosine branch).

use super::error::{one_line, SceneError};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::Path;
use toml::Value;

/// How many times a Gaussian draw is retried to satisfy `> min` before giving up.
const MAX_REDRAWS: usize = 10_000;

/// Whether an array is indexed by bead (`N` entries) or by contact (`N−1` entries).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Per {
    /// One entry per bead.
    Bead,
    /// One entry per contact.
    Contact,
}

impl Per {
    /// `"bead"` or `"contact"`.
    pub(crate) fn noun(self) -> &'static str {
        match self {
            Per::Bead => "bead",
            Per::Contact => "contact",
        }
    }
}

/// Parsing context: the scene file label (for messages), CSV base directory and RNG seed.
pub(crate) struct Ctx<'a> {
    /// Scene file as named in messages.
    pub file: &'a str,
    /// Directory `{ file = ... }` paths are relative to.
    pub base_dir: &'a Path,
    /// Seed of every random builder.
    pub seed: u64,
}

impl Ctx<'_> {
    /// A key error.
    pub(crate) fn err(&self, key: &str, message: impl Into<String>) -> SceneError {
        SceneError::Key {
            file: self.file.to_string(),
            key: key.to_string(),
            message: one_line(&message.into()),
        }
    }

    /// An index error.
    pub(crate) fn index_err(
        &self,
        key: &str,
        per: Per,
        index: usize,
        message: impl Into<String>,
    ) -> SceneError {
        SceneError::Index {
            file: self.file.to_string(),
            key: key.to_string(),
            what: per.noun(),
            index,
            message: one_line(&message.into()),
        }
    }

    /// Reproducible random stream of one key.
    pub(crate) fn rng(&self, key: &str) -> ChaCha8Rng {
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        rng.set_stream(fnv1a(key));
        rng
    }
}

/// 64-bit FNV-1a hash (stable across platforms and Rust versions).
fn fnv1a(s: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in s.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// TOML type name for messages.
pub(crate) fn type_name(v: &Value) -> &'static str {
    match v {
        Value::String(_) => "a string",
        Value::Integer(_) => "an integer",
        Value::Float(_) => "a number",
        Value::Boolean(_) => "a boolean",
        Value::Datetime(_) => "a date",
        Value::Array(_) => "an array",
        Value::Table(_) => "a table",
    }
}

/// A finite number (TOML integer or float).
pub(crate) fn number(ctx: &Ctx, key: &str, v: &Value) -> Result<f64, SceneError> {
    let x = match v {
        Value::Integer(i) => *i as f64,
        Value::Float(f) => *f,
        other => {
            return Err(ctx.err(key, format!("expected a number, got {}", type_name(other))));
        }
    };
    if x.is_finite() {
        Ok(x)
    } else {
        Err(ctx.err(key, format!("expected a finite number, got {x}")))
    }
}

/// A non-negative integer (index or count).
pub(crate) fn index(ctx: &Ctx, key: &str, v: &Value) -> Result<usize, SceneError> {
    match v {
        Value::Integer(i) if *i >= 0 => usize::try_from(*i)
            .map_err(|_| ctx.err(key, format!("integer {i} too large for this platform"))),
        Value::Integer(i) => Err(ctx.err(key, format!("expected a non-negative integer, got {i}"))),
        other => Err(ctx.err(
            key,
            format!("expected a non-negative integer, got {}", type_name(other)),
        )),
    }
}

/// Reject keys of `table` not in `allowed`, naming the first unknown one.
pub(crate) fn check_keys(
    ctx: &Ctx,
    path: &str,
    table: &toml::Table,
    allowed: &[&str],
) -> Result<(), SceneError> {
    for k in table.keys() {
        if !allowed.contains(&k.as_str()) {
            return Err(ctx.err(
                &format!("{path}.{}", one_line(k)),
                format!("unknown key (expected one of: {})", allowed.join(", ")),
            ));
        }
    }
    Ok(())
}

/// A fixed list of values and where it came from.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct List {
    values: Vec<f64>,
    /// The CSV path when the list was read from a file.
    csv: Option<String>,
}

/// A parsed value specification (files already read), resolved once `N` is known.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Spec {
    /// Every entry equal.
    Const(f64),
    /// Exactly one entry per bead/contact.
    List(List),
    /// A builder table.
    Build(Box<Builder>),
}

/// One overriding range `from ..= to` (inclusive; `to = None` means the last index).
#[derive(Clone, Debug, PartialEq)]
struct Segment {
    key: String,
    from: usize,
    to: Option<usize>,
    value: f64,
}

/// A builder table (see module docs for the order of application).
#[derive(Clone, Debug, PartialEq, Default)]
pub(crate) struct Builder {
    base: Option<Spec>,
    start: usize,
    alternate: Option<Vec<f64>>,
    random: Option<(f64, f64)>,
    taper: Option<(f64, usize)>,
    segments: Vec<Segment>,
    gaussian: Option<(f64, f64)>,
}

const BUILDER_KEYS: &[&str] = &[
    "base",
    "start",
    "alternate",
    "random",
    "taper",
    "segments",
    "impurity",
    "gaussian",
];

fn sub_table<'v>(ctx: &Ctx, key: &str, v: &'v Value) -> Result<&'v toml::Table, SceneError> {
    v.as_table()
        .ok_or_else(|| ctx.err(key, format!("expected a table, got {}", type_name(v))))
}

fn required<'v>(
    ctx: &Ctx,
    path: &str,
    t: &'v toml::Table,
    k: &str,
) -> Result<&'v Value, SceneError> {
    t.get(k)
        .ok_or_else(|| ctx.err(&format!("{path}.{k}"), "missing"))
}

impl Spec {
    /// Parse a value form at key path `key`.
    pub(crate) fn parse(ctx: &Ctx, key: &str, v: &Value) -> Result<Spec, SceneError> {
        match v {
            Value::Integer(_) | Value::Float(_) => Ok(Spec::Const(number(ctx, key, v)?)),
            Value::Array(items) => {
                let values = items
                    .iter()
                    .enumerate()
                    .map(|(i, x)| number(ctx, &format!("{key}[{i}]"), x))
                    .collect::<Result<Vec<_>, _>>()?;
                Ok(Spec::List(List { values, csv: None }))
            }
            Value::Table(t) if t.contains_key("file") => {
                check_keys(ctx, key, t, &["file"])?;
                let name = t.get("file").and_then(Value::as_str).ok_or_else(|| {
                    ctx.err(&format!("{key}.file"), "expected a file name string")
                })?;
                read_csv(ctx, key, name).map(Spec::List)
            }
            Value::Table(t) => Builder::parse(ctx, key, t).map(|b| Spec::Build(Box::new(b))),
            other => Err(ctx.err(
                key,
                format!(
                    "expected a number, an array, {{ file = \"...\" }} or a builder table, got {}",
                    type_name(other)
                ),
            )),
        }
    }

    /// Length fixed by this spec (explicit array/CSV, or a builder's array `base`), if any.
    pub(crate) fn explicit_len(&self) -> Option<usize> {
        match self {
            Spec::Const(_) => None,
            Spec::List(l) => Some(l.values.len()),
            Spec::Build(b) => b.base.as_ref().and_then(Spec::explicit_len),
        }
    }

    /// Expand to `len` entries. `default` is the key's default value (used by builders without
    /// `base`). Random builders draw from the key's own stream.
    pub(crate) fn resolve(
        &self,
        ctx: &Ctx,
        key: &str,
        len: usize,
        per: Per,
        default: f64,
    ) -> Result<Vec<f64>, SceneError> {
        match self {
            Spec::Const(c) => Ok(vec![*c; len]),
            Spec::List(l) => {
                if l.values.len() != len {
                    let src = l
                        .csv
                        .as_ref()
                        .map(|c| format!(" (from {c})"))
                        .unwrap_or_default();
                    return Err(ctx.err(
                        key,
                        format!(
                            "expected {len} values (one per {}), got {}{src}",
                            per.noun(),
                            l.values.len()
                        ),
                    ));
                }
                Ok(l.values.clone())
            }
            Spec::Build(b) => b.resolve(ctx, key, len, per, default),
        }
    }
}

impl Builder {
    fn parse(ctx: &Ctx, key: &str, t: &toml::Table) -> Result<Builder, SceneError> {
        check_keys(ctx, key, t, BUILDER_KEYS)?;
        let mut b = Builder::default();
        if let Some(v) = t.get("base") {
            let k = format!("{key}.base");
            let s = Spec::parse(ctx, &k, v)?;
            if matches!(s, Spec::Build(_)) {
                return Err(ctx.err(&k, "base must be a number, an array or { file = ... }"));
            }
            b.base = Some(s);
        }
        if let Some(v) = t.get("start") {
            b.start = index(ctx, &format!("{key}.start"), v)?;
        }
        if let Some(v) = t.get("alternate") {
            let k = format!("{key}.alternate");
            let arr = v
                .as_array()
                .ok_or_else(|| ctx.err(&k, format!("expected an array, got {}", type_name(v))))?;
            if arr.is_empty() {
                return Err(ctx.err(&k, "needs at least one value"));
            }
            let vals = arr
                .iter()
                .enumerate()
                .map(|(i, x)| number(ctx, &format!("{k}[{i}]"), x))
                .collect::<Result<Vec<_>, _>>()?;
            b.alternate = Some(vals);
        }
        if let Some(v) = t.get("random") {
            let k = format!("{key}.random");
            if b.alternate.is_some() {
                return Err(ctx.err(&k, "`random` and `alternate` cannot be combined"));
            }
            let rt = sub_table(ctx, &k, v)?;
            check_keys(ctx, &k, rt, &["mean", "eps"])?;
            let mean = number(ctx, &format!("{k}.mean"), required(ctx, &k, rt, "mean")?)?;
            let eps = number(ctx, &format!("{k}.eps"), required(ctx, &k, rt, "eps")?)?;
            if eps < 0.0 {
                return Err(ctx.err(&format!("{k}.eps"), format!("must be >= 0, got {eps}")));
            }
            b.random = Some((mean, eps));
        }
        if let Some(v) = t.get("taper") {
            let k = format!("{key}.taper");
            let tt = sub_table(ctx, &k, v)?;
            check_keys(ctx, &k, tt, &["q", "from"])?;
            let q = number(ctx, &format!("{k}.q"), required(ctx, &k, tt, "q")?)?;
            if !(0.0..1.0).contains(&q) {
                return Err(ctx.err(&format!("{k}.q"), format!("must be in [0, 1), got {q}")));
            }
            let from = match tt.get("from") {
                Some(f) => index(ctx, &format!("{k}.from"), f)?,
                None => 0,
            };
            b.taper = Some((q, from));
        }
        if let Some(v) = t.get("segments") {
            let k = format!("{key}.segments");
            let arr = v.as_array().ok_or_else(|| {
                ctx.err(
                    &k,
                    format!("expected an array of tables, got {}", type_name(v)),
                )
            })?;
            for (i, s) in arr.iter().enumerate() {
                let sk = format!("{k}[{i}]");
                let st = sub_table(ctx, &sk, s)?;
                check_keys(ctx, &sk, st, &["from", "to", "value"])?;
                let from = match st.get("from") {
                    Some(f) => index(ctx, &format!("{sk}.from"), f)?,
                    None => 0,
                };
                let to = st
                    .get("to")
                    .map(|x| index(ctx, &format!("{sk}.to"), x))
                    .transpose()?;
                let value = number(
                    ctx,
                    &format!("{sk}.value"),
                    required(ctx, &sk, st, "value")?,
                )?;
                b.segments.push(Segment {
                    key: sk,
                    from,
                    to,
                    value,
                });
            }
        }
        if let Some(v) = t.get("impurity") {
            let k = format!("{key}.impurity");
            let list: Vec<(String, &Value)> = match v {
                Value::Array(a) => a
                    .iter()
                    .enumerate()
                    .map(|(i, x)| (format!("{k}[{i}]"), x))
                    .collect(),
                _ => vec![(k.clone(), v)],
            };
            for (ik, iv) in list {
                let it = sub_table(ctx, &ik, iv)?;
                check_keys(ctx, &ik, it, &["at", "s", "value"])?;
                let at = index(ctx, &format!("{ik}.at"), required(ctx, &ik, it, "at")?)?;
                let s = match it.get("s") {
                    Some(x) => index(ctx, &format!("{ik}.s"), x)?,
                    None => 1,
                };
                if s == 0 {
                    return Err(ctx.err(&format!("{ik}.s"), "must be >= 1"));
                }
                let value = number(
                    ctx,
                    &format!("{ik}.value"),
                    required(ctx, &ik, it, "value")?,
                )?;
                b.segments.push(Segment {
                    key: ik,
                    from: at,
                    to: Some(at.saturating_add(s - 1)),
                    value,
                });
            }
        }
        if let Some(v) = t.get("gaussian") {
            let k = format!("{key}.gaussian");
            let gt = sub_table(ctx, &k, v)?;
            check_keys(ctx, &k, gt, &["sigma", "min"])?;
            let sigma = number(ctx, &format!("{k}.sigma"), required(ctx, &k, gt, "sigma")?)?;
            if sigma < 0.0 {
                return Err(ctx.err(&format!("{k}.sigma"), format!("must be >= 0, got {sigma}")));
            }
            let min = match gt.get("min") {
                Some(m) => number(ctx, &format!("{k}.min"), m)?,
                None => 2.0,
            };
            b.gaussian = Some((sigma, min));
        }
        Ok(b)
    }

    fn resolve(
        &self,
        ctx: &Ctx,
        key: &str,
        len: usize,
        per: Per,
        default: f64,
    ) -> Result<Vec<f64>, SceneError> {
        let base_default = match (&self.random, &self.alternate) {
            (Some((mean, _)), _) => *mean,
            (None, Some(a)) => a[0],
            (None, None) => default,
        };
        let mut v = match &self.base {
            Some(s) => s.resolve(ctx, &format!("{key}.base"), len, per, default)?,
            None => vec![base_default; len],
        };
        if (self.alternate.is_some() || self.random.is_some()) && self.start >= len {
            return Err(ctx.err(
                &format!("{key}.start"),
                format!(
                    "{} is past the last {} ({})",
                    self.start,
                    per.noun(),
                    len - 1
                ),
            ));
        }
        let mut rng = ctx.rng(key);
        if let Some(alt) = &self.alternate {
            for (j, x) in v[self.start..].iter_mut().enumerate() {
                *x = alt[j % alt.len()];
            }
        }
        if let Some((mean, eps)) = self.random {
            for x in &mut v[self.start..] {
                let r = 2.0 * rng.random::<f64>() - 1.0;
                *x = mean + eps * r;
            }
        }
        if let Some((q, from)) = self.taper {
            if from >= len {
                return Err(ctx.err(
                    &format!("{key}.taper.from"),
                    format!("{from} is past the last {} ({})", per.noun(), len - 1),
                ));
            }
            let mut f = 1.0;
            for x in &mut v[from..] {
                *x *= f;
                f *= 1.0 - q;
            }
        }
        for s in &self.segments {
            let to = s.to.unwrap_or(len - 1);
            if s.from > to || to >= len {
                return Err(ctx.err(
                    &s.key,
                    format!(
                        "range {}..={to} is not inside 0..={} ({} indices)",
                        s.from,
                        len - 1,
                        per.noun()
                    ),
                ));
            }
            v[s.from..=to].fill(s.value);
        }
        if let Some((sigma, min)) = self.gaussian {
            for (i, x) in v.iter_mut().enumerate() {
                let mut tries = 0;
                loop {
                    let y = *x + sigma * gaussian(&mut rng);
                    if y > min {
                        *x = y;
                        break;
                    }
                    tries += 1;
                    if tries >= MAX_REDRAWS {
                        return Err(ctx.index_err(
                            &format!("{key}.gaussian"),
                            per,
                            i,
                            format!(
                                "no draw above min = {min} in {MAX_REDRAWS} tries (value {x}, sigma {sigma})"
                            ),
                        ));
                    }
                }
            }
        }
        Ok(v)
    }
}

/// One standard normal draw (Box–Muller, cosine branch; `1 − U ∈ (0, 1]` avoids `ln 0`).
fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let u1 = 1.0 - rng.random::<f64>();
    let u2 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

/// Read a one-number-per-line CSV relative to the scene directory.
fn read_csv(ctx: &Ctx, key: &str, name: &str) -> Result<List, SceneError> {
    let path = ctx.base_dir.join(name);
    let shown = one_line(&path.display().to_string());
    let text = crate::files::read_text(&path).map_err(|e| SceneError::CsvIo {
        file: ctx.file.to_string(),
        key: key.to_string(),
        csv: shown.clone(),
        reason: one_line(&e.to_string()),
    })?;
    let mut values = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let s = line.trim();
        if s.is_empty() || s.starts_with('#') {
            continue;
        }
        let bad = |message: String| SceneError::Csv {
            file: ctx.file.to_string(),
            key: key.to_string(),
            csv: shown.clone(),
            line: i + 1,
            message: one_line(&message),
        };
        let s = s.strip_suffix(',').unwrap_or(s).trim();
        let x: f64 = s
            .parse()
            .map_err(|_| bad(format!("expected one number per line, got `{s}`")))?;
        if !x.is_finite() {
            return Err(bad(format!("expected a finite number, got `{s}`")));
        }
        values.push(x);
    }
    Ok(List {
        values,
        csv: Some(shown),
    })
}
