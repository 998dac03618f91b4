//! The parsing context of scene keys (file label, CSV directory, seed of the random builders)
//! and the typed accessors every scene table uses: numbers, indices, and the tables themselves,
//! read through serde into structs of their keys ([`table_keys`], [`fields`]: unknown keys are
//! refused). Every failure is a [`SceneError`] naming the file and key path.
//!
//! Random draws come from `ChaCha8Rng::seed_from_u64(seed)` with the stream set to a 64-bit
//! FNV-1a hash of the key path ([`Ctx::rng`]).

use super::error::{one_line, SceneError};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::de::DeserializeOwned;
use std::path::Path;
use toml::{Table, Value};

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
        rng.set_stream(fnv1a(key.as_bytes()));
        rng
    }
}

/// 64-bit FNV-1a hash (stable across platforms and Rust versions): random streams of scene
/// keys, the sweep file's identity.
pub(crate) fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The TOML type of a value, with its article, for messages (scene and sweep files).
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

/// Declares the structs of scene tables: each field is a key of the table, its value kept as
/// TOML for the reader of its forms (numbers, arrays, builders, CSVs). serde refuses any other
/// key ([`fields`]), so a struct is the list of its table's keys; [`TakeKeys`] moves the values
/// of those keys out of the table by the same names (`stringify!`), so a key must be a plain
/// identifier (no `r#`) and the structs take no serde renaming attributes.
macro_rules! table_keys {
    ($($(#[$m:meta])* $name:ident { $($key:ident),* $(,)? })*) => {$(
        $(#[$m])*
        #[derive(Default, serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        pub(crate) struct $name { $(pub $key: Option<toml::Value>,)* }

        impl $crate::scene::ctx::TakeKeys for $name {
            fn take(mut t: toml::Table) -> Self {
                Self { $($key: t.remove(stringify!($key)),)* }
            }
        }
    )*};
}
pub(crate) use table_keys;

/// A [`table_keys`] struct built by moving its keys' values out of a table.
pub(crate) trait TakeKeys {
    /// The struct of `t`'s values (a key `t` lacks is `None`; `t`'s other keys are dropped).
    fn take(t: Table) -> Self;
}

/// Reads table `t` into `T` (a [`table_keys`] struct). serde checks the keys, on a copy of the
/// table with every value replaced by `false` (every field of `T` takes any value); the values
/// are then moved into `T` ([`TakeKeys`]): a scene's arrays of millions of beads are neither
/// copied nor rebuilt, and a date stays a date. An unknown key is `Err((key, keys))`: the key
/// and the keys `T` has, comma-separated.
pub(crate) fn read_keys<T: DeserializeOwned + TakeKeys>(t: Table) -> Result<T, (String, String)> {
    let keys_only = Value::Table(
        t.keys()
            .map(|k| (k.clone(), Value::Boolean(false)))
            .collect(),
    );
    serde_path_to_error::deserialize::<_, T>(keys_only).map_err(|e| {
        let key = e
            .path()
            .iter()
            .next_back()
            .map_or(String::new(), |s| s.to_string());
        // serde's "unknown field `KEY`, expected one of `a`, `b`": the list follows the last
        // ", expected " (a quoted key may hold the words itself; the keys never do)
        let m = e.inner().message();
        let keys = m.rsplit_once(", expected ").map_or("", |(_, k)| k);
        let keys = keys.trim_start_matches("one of ").replace('`', "");
        (one_line(&key), keys.replace(" or ", ", "))
    })?;
    Ok(T::take(t))
}

/// The keys of table `t` at key path `path` as `T` (a [`table_keys`] struct); an unknown key
/// is refused, naming it and the keys the table has.
pub(crate) fn fields<T: DeserializeOwned + TakeKeys>(
    ctx: &Ctx,
    path: &str,
    t: &Table,
) -> Result<T, SceneError> {
    fields_owned(ctx, path, t.clone())
}

/// [`fields`] of a table the caller gives up (its values are moved, not copied).
fn fields_owned<T: DeserializeOwned + TakeKeys>(
    ctx: &Ctx,
    path: &str,
    t: Table,
) -> Result<T, SceneError> {
    read_keys(t).map_err(|(k, keys)| {
        ctx.err(
            &format!("{path}.{k}"),
            format!("unknown key (expected one of: {keys})"),
        )
    })
}

/// [`fields`] of the table `v` (`None` when absent); another value is refused as not
/// `expected` (`"a table"`, `"a table { beads, velocity }"`).
pub(crate) fn table_of<T: DeserializeOwned + TakeKeys>(
    ctx: &Ctx,
    key: &str,
    v: Option<&Value>,
    expected: &str,
) -> Result<Option<T>, SceneError> {
    // a table is copied as `fields` copies it; another value only to be named in the error
    table_of_owned(ctx, key, v.cloned(), expected)
}

/// [`table_of`] of a value the caller gives up (a whole scene table: its values are moved).
pub(crate) fn table_of_owned<T: DeserializeOwned + TakeKeys>(
    ctx: &Ctx,
    key: &str,
    v: Option<Value>,
    expected: &str,
) -> Result<Option<T>, SceneError> {
    match v {
        None => Ok(None),
        Some(Value::Table(t)) => fields_owned(ctx, key, t).map(Some),
        Some(v) => Err(ctx.err(key, format!("expected {expected}, got {}", type_name(&v)))),
    }
}
