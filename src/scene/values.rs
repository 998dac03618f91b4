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

use super::builder::{self, BuilderKeys, FileKeys, Segment};
use super::ctx::fields;
pub(crate) use super::ctx::{index, number, type_name, Ctx, Per};
use super::error::{one_line, SceneError};
use rand::Rng;
use toml::Value;

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
                let f: FileKeys = fields(ctx, key, t)?;
                let name = f.file.as_ref().and_then(Value::as_str).ok_or_else(|| {
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
        let t: BuilderKeys = fields(ctx, key, t)?;
        let mut b = Builder::default();
        let sub = |name: &str| format!("{key}.{name}");
        if let Some(v) = &t.base {
            let s = Spec::parse(ctx, &sub("base"), v)?;
            if matches!(s, Spec::Build(_)) {
                let m = "base must be a number, an array or { file = ... }";
                return Err(ctx.err(&sub("base"), m));
            }
            b.base = Some(s);
        }
        if let Some(v) = &t.start {
            b.start = index(ctx, &sub("start"), v)?;
        }
        if let Some(v) = &t.alternate {
            b.alternate = Some(builder::alternate(ctx, &sub("alternate"), v)?);
        }
        if let Some(v) = &t.random {
            if b.alternate.is_some() {
                let m = "`random` and `alternate` cannot be combined";
                return Err(ctx.err(&sub("random"), m));
            }
            b.random = Some(builder::random(ctx, &sub("random"), v)?);
        }
        if let Some(v) = &t.taper {
            b.taper = Some(builder::taper(ctx, &sub("taper"), v)?);
        }
        if let Some(v) = &t.segments {
            builder::segments(ctx, &sub("segments"), v, &mut b.segments)?;
        }
        if let Some(v) = &t.impurity {
            builder::impurities(ctx, &sub("impurity"), v, &mut b.segments)?;
        }
        if let Some(v) = &t.gaussian {
            b.gaussian = Some(builder::gaussian_noise(ctx, &sub("gaussian"), v)?);
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
            builder::apply_taper(ctx, key, per, &mut v, q, from)?;
        }
        builder::apply_segments(ctx, per, &mut v, &self.segments)?;
        if let Some((sigma, min)) = self.gaussian {
            builder::apply_gaussian(ctx, key, per, &mut v, sigma, min, &mut rng)?;
        }
        Ok(v)
    }
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
