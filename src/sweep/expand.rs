//! Expansion of a sweep into runs (points × grid product × seeds, in that nesting order, the
//! seeds fastest) and the scene of each run: the base scene's TOML with the dotted-key overrides
//! written in, then the normal scene parser and validator.

use super::{SweepError, SweepSpec};
use crate::scene::{self, Scene};
use std::path::Path;
use toml::{Table, Value};

/// One run of a sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct RunPoint {
    /// 0-based run index (the order of expansion).
    pub index: usize,
    /// The swept keys and their values, in column order (absent point keys are left out).
    pub params: Vec<(String, Value)>,
}

impl RunPoint {
    /// The row's first fields: the run index and the swept values in column order (CSV fields,
    /// empty where the run has no value for a column).
    pub fn fields(&self, spec: &SweepSpec) -> Vec<String> {
        let mut f = vec![self.index.to_string()];
        for c in spec.param_columns() {
            let v = self.params.iter().find(|(k, _)| *k == c);
            f.push(v.map_or(String::new(), |(_, v)| super::csv::field(&format_value(v))));
        }
        f
    }

    /// `key=value, ...` for messages.
    pub fn describe(&self) -> String {
        self.params
            .iter()
            .map(|(k, v)| format!("{k}={}", format_value(v)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// A parameter value as written in the CSV: floats with `{:?}` (shortest exact round trip),
/// integers, booleans and strings as they are, anything else as inline TOML.
pub fn format_value(v: &Value) -> String {
    match v {
        // Shortest round-trip text without an exponent where Rust writes none: `2.5`, `0.1`,
        // `1e-8` (pandas and spreadsheets read it as written).
        Value::Float(x) => format!("{x:?}"),
        Value::Integer(i) => i.to_string(),
        Value::Boolean(b) => b.to_string(),
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

impl SweepSpec {
    /// The parameter column names: grid keys, then point keys not in the grid (alphabetical),
    /// then the seed key.
    pub fn param_columns(&self) -> Vec<String> {
        let mut cols: Vec<String> = self.grid.iter().map(|(k, _)| k.clone()).collect();
        let mut extra: Vec<String> = Vec::new();
        for p in &self.points {
            for (k, _) in p {
                if !cols.contains(k) && !extra.contains(k) {
                    extra.push(k.clone());
                }
            }
        }
        extra.sort();
        cols.extend(extra);
        if let Some((k, _)) = &self.seeds {
            cols.push(k.clone());
        }
        cols
    }

    /// Every run of the sweep, in index order.
    pub fn runs(&self) -> Vec<RunPoint> {
        let cols = self.param_columns();
        let empty = vec![Vec::new()];
        let points = if self.points.is_empty() {
            &empty
        } else {
            &self.points
        };
        let seeds: Vec<Option<&Value>> = match &self.seeds {
            Some((_, v)) => v.iter().map(Some).collect(),
            None => vec![None],
        };
        let grid_total: usize = self.grid.iter().map(|(_, v)| v.len()).product();
        let mut out = Vec::new();
        for p in points {
            for g in 0..grid_total {
                // Mixed-radix digits of g, the last grid key fastest.
                let mut rest = g;
                let mut gvals = vec![None; self.grid.len()];
                for (d, (_, vals)) in self.grid.iter().enumerate().rev() {
                    gvals[d] = Some(&vals[rest % vals.len()]);
                    rest /= vals.len();
                }
                for s in &seeds {
                    let mut params = Vec::new();
                    for c in &cols {
                        let v = if let Some(d) = self.grid.iter().position(|(k, _)| k == c) {
                            gvals[d]
                        } else if let Some((_, v)) = p.iter().find(|(k, _)| k == c) {
                            Some(v)
                        } else if self.seeds.as_ref().is_some_and(|(k, _)| k == c) {
                            *s
                        } else {
                            None
                        };
                        if let Some(v) = v {
                            params.push((c.clone(), v.clone()));
                        }
                    }
                    out.push(RunPoint {
                        index: out.len(),
                        params,
                    });
                }
            }
        }
        out
    }

    /// The base scene's TOML with `[set]` and the run's parameters written in.
    pub fn run_table(&self, run: &RunPoint) -> Result<Table, SweepError> {
        write_overrides(&self.base, self.set.iter().chain(&run.params)).map_err(|(k, m)| {
            let in_set = self.set.iter().any(|(s, _)| s == k);
            SweepError::Key {
                file: self.file.clone(),
                key: if in_set {
                    format!("[set].\"{k}\"")
                } else {
                    format!("\"{k}\"")
                },
                message: if in_set {
                    m.to_string()
                } else {
                    format!("run {} ({}): {m}", run.index, run.describe())
                },
            }
        })
    }

    /// The resolved, validated scene of one run.
    pub fn scene_for(&self, run: &RunPoint) -> Result<Scene, SweepError> {
        let t = self.run_table(run)?;
        let origin = format!("scene {}", self.scene_spec);
        parse_table(&t, &self.base_dir, &origin, &self.scene_spec).map_err(|e| match e {
            TableError::Toml(m) => SweepError::Key {
                file: self.file.clone(),
                key: format!("run {}", run.index),
                message: m,
            },
            TableError::Scene(source) => SweepError::Scene {
                file: self.file.clone(),
                run: run.index,
                params: run.describe(),
                source: Box::new(source),
            },
        })
    }

    /// Builds every run's scene once (nothing is run) and checks the measures fit the chains:
    /// the first problem fails the whole sweep.
    pub fn check_all(&self) -> Result<Vec<RunPoint>, SweepError> {
        Ok(self
            .check_all_keyed()?
            .into_iter()
            .map(|(r, _)| r)
            .collect())
    }

    /// [`SweepSpec::check_all`], with each run's content key ([`SweepSpec::content_key`]).
    pub fn check_all_keyed(&self) -> Result<Vec<(RunPoint, u64)>, SweepError> {
        let runs = self.runs();
        let mut out = Vec::with_capacity(runs.len());
        for r in runs {
            let s = self.scene_for(&r)?;
            self.check_scene(&r, &s)?;
            let key = self.content_key(&s);
            out.push((r, key));
        }
        Ok(out)
    }

    fn check_scene(&self, r: &RunPoint, s: &Scene) -> Result<(), SweepError> {
        let n = s.chain.len();
        let err = |key: &str, message: String| SweepError::Key {
            file: self.file.clone(),
            key: key.to_string(),
            message: format!("run {} ({}): {message}", r.index, r.describe()),
        };
        let m = &self.measure;
        for (key, k) in [
            ("[measure].interface", m.interface),
            ("[measure].impurity", m.impurity),
        ] {
            if let Some(k) = k {
                if k == 0 || k >= n {
                    return Err(err(key, format!("bead {k} is outside 1..={}", n - 1)));
                }
            }
        }
        if let Some(d) = m.decay {
            if d.from >= n {
                return Err(err(
                    "[measure].decay.from",
                    format!("bead {} is beyond the chain of {n} beads", d.from),
                ));
            }
        }
        if let Some(mg) = self.stop.margin {
            if mg >= n {
                return Err(err(
                    "[stop].margin",
                    format!("{mg} is not less than the chain's {n} beads"),
                ));
            }
        }
        let needs_frames = m.decay.is_some()
            || m.impurity.is_some()
            || self.stop.margin.is_some()
            || self.stop.steady_state;
        if needs_frames && s.run.every.is_none() {
            return Err(err(
                "[measure]/[stop]",
                "the frame-based measures and stops need frames: the scene has no [run] every (add \"run.every\" to [set])".into(),
            ));
        }
        use crate::snapshot::size::{
            count_text, frame_count_estimate, human_bytes, output_bytes_estimate,
        };
        let frames = frame_count_estimate(0.0, s.run.until, s.run.every);
        let bytes = output_bytes_estimate(n, frames);
        if bytes > self.max_output_bytes as f64 {
            return Err(err(
                "run.every",
                format!(
                    "{} frames of {n} beads (run.until = {:e}, run.every = {:e}), about {} of frame data, above the limit of {} per run: raise run.every or lower run.until (or pass --max-output-bytes N or --force)",
                    count_text(frames),
                    s.run.until,
                    s.run.every.unwrap_or(s.run.until),
                    human_bytes(bytes),
                    human_bytes(self.max_output_bytes as f64)
                ),
            ));
        }
        Ok(())
    }
}

/// Why a scene's TOML table (with overrides written in) gave no scene.
#[derive(Debug)]
pub enum TableError {
    /// The table could not be written as TOML text (the message says why).
    Toml(String),
    /// The scene parser or validator rejected it.
    Scene(scene::SceneError),
}

/// Why a dotted key cannot be written into a scene table ([`set_key`]); names the part walked.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum SetKeyError {
    /// An empty key.
    #[error("empty key")]
    Empty,
    /// The key walks into a value that is not a table.
    #[error("the base scene's `{walked}` is {kind}, not a table")]
    NotTable {
        /// The key parts walked so far.
        walked: String,
        /// What the value is (`an integer`, …).
        kind: &'static str,
    },
    /// An array entry's table lacks the part.
    #[error("no `{walked}.{part}`")]
    Missing {
        /// The key parts walked so far.
        walked: String,
        /// The part not found.
        part: String,
    },
    /// A non-numeric part into an array.
    #[error("`{walked}` is an array: `{part}` must be an index")]
    NotIndex {
        /// The key parts walked so far (the array).
        walked: String,
        /// The part given.
        part: String,
    },
    /// An array index beyond the array.
    #[error("`{walked}` has {len} entries, index {index} is out of range")]
    OutOfRange {
        /// The key parts walked so far (the array).
        walked: String,
        /// Entries of the array.
        len: usize,
        /// The index given.
        index: usize,
    },
    /// The key walks into a value that is neither a table nor an array.
    #[error("the base scene's `{walked}` is {kind}, not a table or array")]
    NotContainer {
        /// The key parts walked so far.
        walked: String,
        /// What the value is.
        kind: &'static str,
    },
}

/// Why [`override_scene`] refused: one line naming the key, or the overrides and the scene
/// error.
#[derive(Debug, thiserror::Error)]
pub enum OverrideError {
    /// A key that is not a dotted scene key.
    #[error("\"{key}\": {message}")]
    KeyShape {
        /// The key.
        key: String,
        /// Why (see [`key_shape_error`]).
        message: String,
    },
    /// A key that cannot be written into the base scene.
    #[error("\"{key}\": {source}")]
    Set {
        /// The key.
        key: String,
        /// Why.
        source: SetKeyError,
    },
    /// The scene could not be written as TOML.
    #[error("({params}): {message}")]
    Toml {
        /// The overrides, `key=value` comma-separated.
        params: String,
        /// The message.
        message: String,
    },
    /// The scene parser or validator rejected the scene.
    #[error("({params}): {source}")]
    Scene {
        /// The overrides, `key=value` comma-separated.
        params: String,
        /// The scene error.
        source: Box<scene::SceneError>,
    },
}

/// Writes the dotted-key `overrides` into a copy of `base`, in order, as [`set_key`]: what a
/// sweep does for each run. The first key that cannot be written gives `(key, reason)`.
pub fn write_overrides<'a>(
    base: &Table,
    overrides: impl IntoIterator<Item = &'a (String, Value)>,
) -> Result<Table, (&'a str, SetKeyError)> {
    let mut t = base.clone();
    for (k, v) in overrides {
        set_key(&mut t, k, v.clone()).map_err(|m| (k.as_str(), m))?;
    }
    Ok(t)
}

/// A scene file's table read by the scene parser and validator (`origin` names it in messages,
/// `base_dir` resolves its CSV files); without a `[scene] name` the scene is called `name`.
pub fn parse_table(
    t: &Table,
    base_dir: &Path,
    origin: &str,
    name: &str,
) -> Result<Scene, TableError> {
    let text = toml::to_string(t)
        .map_err(|e| TableError::Toml(format!("cannot write the run's scene as TOML: {e}")))?;
    let mut s = scene::parse_str(&text, base_dir, origin).map_err(TableError::Scene)?;
    if t.get("scene").and_then(|s| s.get("name")).is_none() {
        s.name = name.to_string();
    }
    Ok(s)
}

/// The message for a key that is not a dotted scene key of at least two parts (`table.key`).
pub fn key_shape_error(k: &str) -> Option<String> {
    let parts: Vec<&str> = k.split('.').collect();
    (parts.len() < 2 || parts.iter().any(|p| p.is_empty())).then(|| {
        "expected a quoted dotted scene key such as \"chain.exponent\" (table.key; a whole table cannot be replaced)".to_string()
    })
}

/// A scene's TOML `base` with the dotted-key `overrides` written in (in order), read by the
/// scene parser and validator, and that TOML text: a sweep's run scene from outside a sweep file
/// (Python's `Scene.with_overrides`), by the same functions and with the same messages. Without a
/// `scene.name` override the scene keeps `name`. Errors are one line naming the key:
/// `"KEY": REASON` when a key is malformed or cannot be written (the sweep file's
/// `[set]."KEY": REASON`), `(KEY=VALUE, ...): SCENE ERROR` when the scene is rejected (an
/// unknown key is the parser's `[table].key: unknown key`).
pub fn override_scene(
    base: &Table,
    overrides: &[(String, Value)],
    base_dir: &Path,
    origin: &str,
    name: &str,
) -> Result<(Scene, String), OverrideError> {
    for (k, _) in overrides {
        if let Some(message) = key_shape_error(k) {
            return Err(OverrideError::KeyShape {
                key: k.clone(),
                message,
            });
        }
    }
    let t = write_overrides(base, overrides).map_err(|(k, source)| OverrideError::Set {
        key: k.to_string(),
        source,
    })?;
    let describe = RunPoint {
        index: 0,
        params: overrides.to_vec(),
    }
    .describe();
    let scene = parse_table(&t, base_dir, origin, name).map_err(|e| match e {
        TableError::Toml(message) => OverrideError::Toml {
            params: describe,
            message,
        },
        TableError::Scene(source) => OverrideError::Scene {
            params: describe,
            source: Box::new(source),
        },
    })?;
    Ok((scene, toml::to_string(&t).unwrap_or_default()))
}

/// Writes `value` at the dotted `key` of `root`: parts walk into tables (created when missing)
/// and numeric parts index arrays.
pub fn set_key(root: &mut Table, key: &str, value: Value) -> Result<(), SetKeyError> {
    let parts: Vec<&str> = key.split('.').collect();
    let (last, path) = parts.split_last().ok_or(SetKeyError::Empty)?;
    let mut cur: &mut Value = root
        .entry(parts[0].to_string())
        .or_insert_with(|| Value::Table(Table::new()));
    let mut walked = parts[0].to_string();
    for p in &path[1..] {
        cur = step(cur, p, &walked, true)?;
        walked = format!("{walked}.{p}");
    }
    match cur {
        Value::Table(t) => {
            t.insert(last.to_string(), value);
            Ok(())
        }
        Value::Array(_) => {
            let slot = step(cur, last, &walked, false)?;
            *slot = value;
            Ok(())
        }
        other => Err(SetKeyError::NotTable {
            walked,
            kind: super::type_name(other),
        }),
    }
}

fn step<'a>(
    cur: &'a mut Value,
    p: &str,
    walked: &str,
    create: bool,
) -> Result<&'a mut Value, SetKeyError> {
    match cur {
        Value::Table(t) => {
            if create {
                Ok(t.entry(p.to_string())
                    .or_insert_with(|| Value::Table(Table::new())))
            } else {
                t.get_mut(p).ok_or_else(|| SetKeyError::Missing {
                    walked: walked.to_string(),
                    part: p.to_string(),
                })
            }
        }
        Value::Array(a) => {
            let len = a.len();
            let i: usize = p.parse().map_err(|_| SetKeyError::NotIndex {
                walked: walked.to_string(),
                part: p.to_string(),
            })?;
            a.get_mut(i).ok_or_else(|| SetKeyError::OutOfRange {
                walked: walked.to_string(),
                len,
                index: i,
            })
        }
        other => Err(SetKeyError::NotContainer {
            walked: walked.to_string(),
            kind: super::type_name(other),
        }),
    }
}

/// Most runs a sweep may expand to (every run's scene is built before any run starts).
pub const MAX_RUNS: u64 = 100_000;

/// The message when a sweep expands to more than [`MAX_RUNS`] runs
/// (`max(points, 1) × Π grid lengths × max(seeds, 1)`, computed before anything is expanded).
pub(crate) fn too_many_runs(
    grid: &[(String, Vec<Value>)],
    points: usize,
    seeds: Option<usize>,
) -> Option<String> {
    let total = grid
        .iter()
        .map(|(_, v)| v.len())
        .chain([points.max(1), seeds.unwrap_or(1)])
        .try_fold(1u64, |acc, n| acc.checked_mul(n as u64));
    if total.is_some_and(|t| t <= MAX_RUNS) {
        return None;
    }
    let shown = total.map_or("more than 2^64".into(), |t| t.to_string());
    Some(format!(
        "the sweep expands to {shown} runs ([[point]] x [grid] x [seeds]), above the limit of {MAX_RUNS} runs per sweep file: split it into several sweep files"
    ))
}
