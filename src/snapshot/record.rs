//! Named records: the self-describing encoding of the HEADER (format version 4) and of the scene
//! inside checkpoints.
//!
//! Formats 1–3 stored the internal `Scene` struct through bincode, so any field added to `Chain`
//! silently changed the file format. A record instead stores a list of `(key, value)` entries
//! with the key names on disk (`chain.mass`, `run.until`, …; the full list is in
//! `docs/snapshots.md` and [`super::header4`]). Writing goes through an exhaustive destructuring
//! of every struct, so a new field does not compile until it has a key; reading looks keys up by
//! name, requires the mandatory ones, and refuses a key it does not know (a newer file could
//! carry physics this build would silently ignore).
//!
//! Encoding: bincode (module `snapshot`) of `Vec<(String, Value)>`; [`Value`]'s variant indices
//! are part of the format: append only.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// One value of a record.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Value {
    /// UTF-8 text (variant 0).
    Text(String),
    /// A float (variant 1).
    Real(f64),
    /// An unsigned integer (variant 2).
    Int(u64),
    /// Floats (variant 3).
    Reals(Vec<f64>),
    /// Unsigned integers (variant 4).
    Ints(Vec<u64>),
    /// Optional floats, one per contact (variant 5).
    OptReals(Vec<Option<f64>>),
}

impl Value {
    fn kind(&self) -> &'static str {
        match self {
            Value::Text(_) => "text",
            Value::Real(_) => "real",
            Value::Int(_) => "integer",
            Value::Reals(_) => "real array",
            Value::Ints(_) => "integer array",
            Value::OptReals(_) => "optional-real array",
        }
    }
}

/// Why a record cannot be read: one line naming the key.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RecordError {
    /// A key stored twice.
    #[error("key `{0}` appears twice")]
    Duplicate(String),
    /// A key holding a value of another kind.
    #[error("key `{key}` holds a {got}, expected a {want}")]
    WrongKind {
        /// The key.
        key: String,
        /// Kind stored.
        got: &'static str,
        /// Kind expected.
        want: &'static str,
    },
    /// A mandatory key is absent.
    #[error("key `{0}` is missing")]
    Missing(String),
    /// An array of the wrong length.
    #[error("key `{key}` holds {got} values, expected {want}")]
    Length {
        /// The key.
        key: String,
        /// Values stored.
        got: usize,
        /// Values expected.
        want: usize,
    },
    /// Keys left over (written by a newer beadchain, or damaged).
    #[error("unknown key `{key}` (written by a newer beadchain?){}", more_text(*more))]
    Unknown {
        /// The first unknown key.
        key: String,
        /// How many more unknown keys.
        more: usize,
    },
    /// An array that must not be empty is.
    #[error("key `{0}` holds no beads")]
    NoBeads(String),
    /// `n_beads` disagrees with the chain.
    #[error("`n_beads` = {n_beads} but `chain.mass` holds {mass} beads")]
    BeadCount {
        /// The `n_beads` entry.
        n_beads: u64,
        /// Beads in `chain.mass`.
        mass: usize,
    },
    /// A name that is none of the choices.
    #[error("key `{key}` = `{got}`, expected one of {choices}")]
    Choice {
        /// The key.
        key: String,
        /// The name stored.
        got: String,
        /// The valid names, comma-separated.
        choices: String,
    },
}

fn more_text(more: usize) -> String {
    if more > 0 {
        format!(" and {more} more")
    } else {
        String::new()
    }
}

/// Builds a record in key order of writing.
#[derive(Default)]
pub struct RecordWriter {
    entries: Vec<(String, Value)>,
}

impl RecordWriter {
    /// Appends `key = value`.
    pub fn put(&mut self, key: &str, value: Value) {
        debug_assert!(self.entries.iter().all(|(k, _)| k != key), "{key} twice");
        self.entries.push((key.to_string(), value));
    }
    /// Text entry.
    pub fn text(&mut self, key: &str, s: &str) {
        self.put(key, Value::Text(s.to_string()));
    }
    /// Float entry.
    pub fn real(&mut self, key: &str, x: f64) {
        self.put(key, Value::Real(x));
    }
    /// Float entry, left out when `None`.
    pub fn opt_real(&mut self, key: &str, x: Option<f64>) {
        if let Some(x) = x {
            self.real(key, x);
        }
    }
    /// Integer entry.
    pub fn int(&mut self, key: &str, x: u64) {
        self.put(key, Value::Int(x));
    }
    /// Float array entry.
    pub fn reals(&mut self, key: &str, x: &[f64]) {
        self.put(key, Value::Reals(x.to_vec()));
    }
    /// Float array entry, left out when `None`.
    pub fn opt_reals(&mut self, key: &str, x: Option<&[f64]>) {
        if let Some(x) = x {
            self.reals(key, x);
        }
    }
    /// The entries.
    pub fn finish(self) -> Vec<(String, Value)> {
        self.entries
    }
}

/// Reads a record: typed lookups by key, each key taken at most once.
pub struct RecordReader {
    map: BTreeMap<String, Value>,
}

impl RecordReader {
    /// Errors on a key that appears twice.
    pub fn new(entries: Vec<(String, Value)>) -> Result<Self, RecordError> {
        let mut map = BTreeMap::new();
        for (k, v) in entries {
            if map.insert(k.clone(), v).is_some() {
                return Err(RecordError::Duplicate(k));
            }
        }
        Ok(Self { map })
    }

    fn take(&mut self, key: &str) -> Option<Value> {
        self.map.remove(key)
    }

    fn wrong(key: &str, want: &'static str, got: &Value) -> RecordError {
        RecordError::WrongKind {
            key: key.to_string(),
            got: got.kind(),
            want,
        }
    }

    fn missing(key: &str) -> RecordError {
        RecordError::Missing(key.to_string())
    }

    fn length(key: &str, got: usize, want: usize) -> RecordError {
        RecordError::Length {
            key: key.to_string(),
            got,
            want,
        }
    }

    /// True when `key` is present (not taken).
    pub fn has(&self, key: &str) -> bool {
        self.map.contains_key(key)
    }

    /// Optional text.
    pub fn opt_text(&mut self, key: &str) -> Result<Option<String>, RecordError> {
        match self.take(key) {
            None => Ok(None),
            Some(Value::Text(s)) => Ok(Some(s)),
            Some(v) => Err(Self::wrong(key, "text", &v)),
        }
    }
    /// Mandatory text.
    pub fn text(&mut self, key: &str) -> Result<String, RecordError> {
        self.opt_text(key)?.ok_or_else(|| Self::missing(key))
    }
    /// Optional float.
    pub fn opt_real(&mut self, key: &str) -> Result<Option<f64>, RecordError> {
        match self.take(key) {
            None => Ok(None),
            Some(Value::Real(x)) => Ok(Some(x)),
            Some(v) => Err(Self::wrong(key, "real", &v)),
        }
    }
    /// Mandatory float.
    pub fn real(&mut self, key: &str) -> Result<f64, RecordError> {
        self.opt_real(key)?.ok_or_else(|| Self::missing(key))
    }
    /// Optional integer.
    pub fn opt_int(&mut self, key: &str) -> Result<Option<u64>, RecordError> {
        match self.take(key) {
            None => Ok(None),
            Some(Value::Int(x)) => Ok(Some(x)),
            Some(v) => Err(Self::wrong(key, "integer", &v)),
        }
    }
    /// Mandatory integer.
    pub fn int(&mut self, key: &str) -> Result<u64, RecordError> {
        self.opt_int(key)?.ok_or_else(|| Self::missing(key))
    }
    /// Optional float array of length `len`.
    pub fn opt_reals(&mut self, key: &str, len: usize) -> Result<Option<Vec<f64>>, RecordError> {
        match self.take(key) {
            None => Ok(None),
            Some(Value::Reals(x)) if x.len() == len => Ok(Some(x)),
            Some(Value::Reals(x)) => Err(Self::length(key, x.len(), len)),
            Some(v) => Err(Self::wrong(key, "real array", &v)),
        }
    }
    /// Mandatory float array of length `len`.
    pub fn reals(&mut self, key: &str, len: usize) -> Result<Vec<f64>, RecordError> {
        self.opt_reals(key, len)?.ok_or_else(|| Self::missing(key))
    }
    /// Mandatory float array of any length.
    pub fn reals_any(&mut self, key: &str) -> Result<Vec<f64>, RecordError> {
        match self.take(key) {
            None => Err(Self::missing(key)),
            Some(Value::Reals(x)) => Ok(x),
            Some(v) => Err(Self::wrong(key, "real array", &v)),
        }
    }
    /// Optional integer array (any length).
    pub fn opt_ints(&mut self, key: &str) -> Result<Option<Vec<u64>>, RecordError> {
        match self.take(key) {
            None => Ok(None),
            Some(Value::Ints(x)) => Ok(Some(x)),
            Some(v) => Err(Self::wrong(key, "integer array", &v)),
        }
    }
    /// Optional array of optional floats of length `len`.
    pub fn opt_opt_reals(
        &mut self,
        key: &str,
        len: usize,
    ) -> Result<Option<Vec<Option<f64>>>, RecordError> {
        match self.take(key) {
            None => Ok(None),
            Some(Value::OptReals(x)) if x.len() == len => Ok(Some(x)),
            Some(Value::OptReals(x)) => Err(Self::length(key, x.len(), len)),
            Some(v) => Err(Self::wrong(key, "optional-real array", &v)),
        }
    }

    /// Errors when keys are left over (written by a newer beadchain, or damaged).
    pub fn finish(self) -> Result<(), RecordError> {
        match self.map.keys().next() {
            None => Ok(()),
            Some(k) => Err(RecordError::Unknown {
                key: k.clone(),
                more: self.map.len() - 1,
            }),
        }
    }
}

/// One of `names` by its name, or an error naming the key and the choices.
pub fn pick<T: Copy>(
    key: &str,
    got: &str,
    all: &[T],
    name: impl Fn(T) -> &'static str,
) -> Result<T, RecordError> {
    all.iter()
        .copied()
        .find(|&x| name(x) == got)
        .ok_or_else(|| {
            let names: Vec<_> = all.iter().map(|&x| name(x)).collect();
            RecordError::Choice {
                key: key.to_string(),
                got: got.to_string(),
                choices: names.join(", "),
            }
        })
}
