//! The parts of a builder table (module docs of [`super::values`]): parsing each key
//! (`alternate`, `random`, `taper`, `segments`, `impurity`, `gaussian`) and applying the taper,
//! the segments and the Gaussian noise (eq. B.1; Box–Muller, cosine branch) to resolved values.

use super::ctx::{index, number, table_keys, table_of, type_name, Ctx, Per, TakeKeys};
use super::error::SceneError;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use serde::de::DeserializeOwned;
use toml::Value;

/// How many times a Gaussian draw is retried to satisfy `> min` before giving up.
const MAX_REDRAWS: usize = 10_000;

/// One overriding range `from ..= to` (inclusive; `to = None` means the last index).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Segment {
    pub key: String,
    pub from: usize,
    pub to: Option<usize>,
    pub value: f64,
}

table_keys! {
    /// A builder table.
    BuilderKeys { base, start, alternate, random, taper, segments, impurity, gaussian }
    /// `{ file = "x.csv" }`.
    FileKeys { file }
    /// `random = { mean, eps }`.
    RandomKeys { mean, eps }
    /// `taper = { q, from }`.
    TaperKeys { q, from }
    /// One of `segments = [{ from, to, value }, ...]`.
    SegmentKeys { from, to, value }
    /// `impurity = { at, s, value }`.
    ImpurityKeys { at, s, value }
    /// `gaussian = { sigma, min }`.
    GaussianKeys { sigma, min }
}

/// A sub-table of a builder key, as `T`.
fn sub_table<T: DeserializeOwned + TakeKeys + Default>(
    ctx: &Ctx,
    key: &str,
    v: &Value,
) -> Result<T, SceneError> {
    table_of(ctx, key, Some(v), "a table").map(Option::unwrap_or_default)
}

/// A required key of a sub-table.
fn required<'v>(ctx: &Ctx, key: &str, v: &'v Option<Value>) -> Result<&'v Value, SceneError> {
    v.as_ref().ok_or_else(|| ctx.err(key, "missing"))
}

/// `alternate = [x, y, ...]`: at least one number.
pub(crate) fn alternate(ctx: &Ctx, k: &str, v: &Value) -> Result<Vec<f64>, SceneError> {
    let arr = v
        .as_array()
        .ok_or_else(|| ctx.err(k, format!("expected an array, got {}", type_name(v))))?;
    if arr.is_empty() {
        return Err(ctx.err(k, "needs at least one value"));
    }
    arr.iter()
        .enumerate()
        .map(|(i, x)| number(ctx, &format!("{k}[{i}]"), x))
        .collect()
}

/// `random = { mean, eps }` with `eps >= 0`.
pub(crate) fn random(ctx: &Ctx, k: &str, v: &Value) -> Result<(f64, f64), SceneError> {
    let r: RandomKeys = sub_table(ctx, k, v)?;
    let (mk, ek) = (format!("{k}.mean"), format!("{k}.eps"));
    let mean = number(ctx, &mk, required(ctx, &mk, &r.mean)?)?;
    let eps = number(ctx, &ek, required(ctx, &ek, &r.eps)?)?;
    if eps < 0.0 {
        return Err(ctx.err(&format!("{k}.eps"), format!("must be >= 0, got {eps}")));
    }
    Ok((mean, eps))
}

/// `taper = { q, from }` with `q` in `[0, 1)`.
pub(crate) fn taper(ctx: &Ctx, k: &str, v: &Value) -> Result<(f64, usize), SceneError> {
    let t: TaperKeys = sub_table(ctx, k, v)?;
    let qk = format!("{k}.q");
    let q = number(ctx, &qk, required(ctx, &qk, &t.q)?)?;
    if !(0.0..1.0).contains(&q) {
        return Err(ctx.err(&format!("{k}.q"), format!("must be in [0, 1), got {q}")));
    }
    let from = match &t.from {
        Some(f) => index(ctx, &format!("{k}.from"), f)?,
        None => 0,
    };
    Ok((q, from))
}

/// `segments = [{ from, to, value }, ...]`, appended to `out`.
pub(crate) fn segments(
    ctx: &Ctx,
    k: &str,
    v: &Value,
    out: &mut Vec<Segment>,
) -> Result<(), SceneError> {
    let arr = v.as_array().ok_or_else(|| {
        ctx.err(
            k,
            format!("expected an array of tables, got {}", type_name(v)),
        )
    })?;
    for (i, s) in arr.iter().enumerate() {
        let sk = format!("{k}[{i}]");
        let st: SegmentKeys = sub_table(ctx, &sk, s)?;
        let from = match &st.from {
            Some(f) => index(ctx, &format!("{sk}.from"), f)?,
            None => 0,
        };
        let to = (st.to.as_ref())
            .map(|x| index(ctx, &format!("{sk}.to"), x))
            .transpose()?;
        let vk = format!("{sk}.value");
        let value = number(ctx, &vk, required(ctx, &vk, &st.value)?)?;
        out.push(Segment {
            key: sk,
            from,
            to,
            value,
        });
    }
    Ok(())
}

/// `impurity = { at, s, value }` (or an array of them): segments `at ..= at+s−1`, appended.
pub(crate) fn impurities(
    ctx: &Ctx,
    k: &str,
    v: &Value,
    out: &mut Vec<Segment>,
) -> Result<(), SceneError> {
    let list: Vec<(String, &Value)> = match v {
        Value::Array(a) => a
            .iter()
            .enumerate()
            .map(|(i, x)| (format!("{k}[{i}]"), x))
            .collect(),
        _ => vec![(k.to_string(), v)],
    };
    for (ik, iv) in list {
        let it: ImpurityKeys = sub_table(ctx, &ik, iv)?;
        let ak = format!("{ik}.at");
        let at = index(ctx, &ak, required(ctx, &ak, &it.at)?)?;
        let s = match &it.s {
            Some(x) => index(ctx, &format!("{ik}.s"), x)?,
            None => 1,
        };
        if s == 0 {
            return Err(ctx.err(&format!("{ik}.s"), "must be >= 1"));
        }
        let vk = format!("{ik}.value");
        let value = number(ctx, &vk, required(ctx, &vk, &it.value)?)?;
        out.push(Segment {
            key: ik,
            from: at,
            to: Some(at.saturating_add(s - 1)),
            value,
        });
    }
    Ok(())
}

/// `gaussian = { sigma, min }` with `sigma >= 0` (`min` default 2.0).
pub(crate) fn gaussian_noise(ctx: &Ctx, k: &str, v: &Value) -> Result<(f64, f64), SceneError> {
    let g: GaussianKeys = sub_table(ctx, k, v)?;
    let sk = format!("{k}.sigma");
    let sigma = number(ctx, &sk, required(ctx, &sk, &g.sigma)?)?;
    if sigma < 0.0 {
        return Err(ctx.err(&format!("{k}.sigma"), format!("must be >= 0, got {sigma}")));
    }
    let min = match &g.min {
        Some(m) => number(ctx, &format!("{k}.min"), m)?,
        None => 2.0,
    };
    Ok((sigma, min))
}

/// Entry `i >= from` multiplied by `(1−q)^(i−from)`.
pub(crate) fn apply_taper(
    ctx: &Ctx,
    key: &str,
    per: Per,
    v: &mut [f64],
    q: f64,
    from: usize,
) -> Result<(), SceneError> {
    let len = v.len();
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
    Ok(())
}

/// Each segment's range set to its value, in file order.
pub(crate) fn apply_segments(
    ctx: &Ctx,
    per: Per,
    v: &mut [f64],
    segments: &[Segment],
) -> Result<(), SceneError> {
    let len = v.len();
    for s in segments {
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
    Ok(())
}

/// A `N(0, sigma²)` draw added to every entry, redrawn until the result is `> min`.
pub(crate) fn apply_gaussian(
    ctx: &Ctx,
    key: &str,
    per: Per,
    v: &mut [f64],
    sigma: f64,
    min: f64,
    rng: &mut ChaCha8Rng,
) -> Result<(), SceneError> {
    for (i, x) in v.iter_mut().enumerate() {
        let mut tries = 0;
        loop {
            let y = *x + sigma * gaussian(rng);
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
    Ok(())
}

/// One standard normal draw (Box–Muller, cosine branch; `1 − U ∈ (0, 1]` avoids `ln 0`).
fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let u1 = 1.0 - rng.random::<f64>();
    let u2 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}
