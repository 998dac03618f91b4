//! Reading sweep files (format in the [`super`] module docs). The file's shape is declared in
//! types read through serde: [`SweepFile`] (top level, unknown keys refused), [`Seeds`] and
//! [`Measure`], [`super::Decay`], [`Stop`] (`deny_unknown_fields`), each value read in the form the
//! format allows (functions below; a wrong form is refused with our message). The override tables
//! `[set]`, `[grid]`, `[[point]]` keep free dotted keys (TOML tables), checked here: key shape,
//! non-empty lists, each key set in one place only. Every error names the sweep file and the key
//! (the serde path as the file writes it: `[stop].margin`, `[seeds].values[1]`, `[[point]] 2`).

use super::{expand, fnv1a, type_name, Measure, Stop, SweepError, SweepSpec};
use crate::scene::presets;
use serde::de::value::{MapAccessDeserializer, SeqAccessDeserializer};
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::Deserialize;
use serde_path_to_error::Segment;
use std::fmt;
use std::marker::PhantomData;
use std::path::{Path, PathBuf};
use toml::{Table, Value};

/// A sweep file as written.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepFile {
    #[serde(default, deserialize_with = "scene")]
    scene: Option<String>,
    #[serde(default, deserialize_with = "table")]
    set: Table,
    #[serde(default, deserialize_with = "table")]
    grid: Table,
    #[serde(default, deserialize_with = "points")]
    point: Vec<Tbl>,
    #[serde(default, deserialize_with = "section")]
    seeds: Option<Seeds>,
    #[serde(default, deserialize_with = "section")]
    measure: Option<Measure>,
    #[serde(default, deserialize_with = "section")]
    stop: Option<Stop>,
}

/// `[seeds]` as written (both keys required, checked after reading for our messages).
#[derive(Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct Seeds {
    #[serde(default, deserialize_with = "seed_key")]
    key: Option<String>,
    #[serde(default, deserialize_with = "seed_values")]
    values: Option<Vec<Seed>>,
}

/// Top-level keys whose value is a table: their key is written `[set]`.
const SECTIONS: &[&str] = &["set", "grid", "seeds", "measure", "stop"];

/// The key of the one-key table a TOML date is read as (not a key of ours: dropped from paths).
const DATE: &str = "$__toml_private_datetime";

impl SweepSpec {
    /// Reads and checks a sweep file (the base scene is resolved relative to it).
    pub fn load(path: &Path) -> Result<SweepSpec, SweepError> {
        let file = path.display().to_string();
        let text = crate::files::read_text(path).map_err(|e| SweepError::Io {
            file: file.clone(),
            action: "cannot read sweep file".into(),
            reason: e.to_string(),
        })?;
        let dir = path.parent().unwrap_or(Path::new("."));
        Self::parse_str(&text, dir, &file)
    }

    /// Parses sweep text; `dir` resolves a scene path, `file` names the sweep in messages.
    pub fn parse_str(text: &str, dir: &Path, file: &str) -> Result<SweepSpec, SweepError> {
        let key_err = |key: &str, message: String| SweepError::Key {
            file: file.to_string(),
            key: key.to_string(),
            message,
        };
        let e: &KeyErr = &key_err;
        // The parsed table is hashed; the typed read parses the text again (dates stay dates).
        let root = root_table(text, file)?;
        let f: SweepFile = serde_path_to_error::deserialize(toml::Deserializer::new(text))
            .map_err(|err| serde_error(file, &err))?;
        let scene_spec = f
            .scene
            .ok_or_else(|| key_err("scene", "missing (base scene: preset or file)".into()))?;
        let (base_text, base_dir) = base_scene(&scene_spec, dir)
            .map_err(|m| key_err("scene", format!("\"{scene_spec}\": {m}")))?;
        let base: Table = toml::from_str(&base_text).map_err(|e| {
            // one line, placed as a scene file's own error is (`file:line:column`)
            let (line, col) = e.span().map_or((0, 0), |s| {
                let before = &base_text[..s.start.min(base_text.len())];
                let line_start = before.rfind('\n').map_or(0, |i| i + 1);
                (
                    before.matches('\n').count() + 1,
                    before[line_start..].chars().count() + 1,
                )
            });
            let msg = e.message().trim().replace('\n', "; ");
            key_err(
                "scene",
                format!("\"{scene_spec}\":{line}:{col}: malformed TOML: {msg}"),
            )
        })?;
        let set = overrides("[set]", &f.set, e)?;
        let grid = grid(&f.grid, e)?;
        let points = (f.point.iter().enumerate())
            .map(|(i, p)| overrides(&format!("[[point]] {i}"), &p.0, e))
            .collect::<Result<Vec<_>, _>>()?;
        let seeds = f.seeds.map(|s| seeds(s, e)).transpose()?;
        let n_seeds = seeds.as_ref().map(|(_, v)| v.len());
        if let Some(m) = expand::too_many_runs(&grid, points.len(), n_seeds) {
            return Err(key_err("[grid]", m));
        }
        check_claims(&set, &grid, &points, &seeds, e)?;
        let canon = format!(
            "{}\n#--scene--\n{}",
            toml::to_string(&root).unwrap_or_else(|_| text.to_string()),
            toml::to_string(&base).unwrap_or_else(|_| base_text.clone())
        );
        Ok(SweepSpec {
            file: file.to_string(),
            scene_spec,
            base,
            base_dir,
            set,
            grid,
            points,
            seeds,
            measure: f.measure.unwrap_or_default(),
            stop: f.stop.unwrap_or_default(),
            hash: fnv1a(canon.as_bytes()),
            max_output_bytes: crate::snapshot::size::DEFAULT_MAX_OUTPUT_BYTES,
        })
    }
}

/// The sweep file's TOML (hashed as parsed).
fn root_table(text: &str, file: &str) -> Result<Table, SweepError> {
    toml::from_str(text).map_err(|e| {
        let line = e.span().map_or(0, |s| {
            text[..s.start.min(text.len())].matches('\n').count() + 1
        });
        SweepError::Csv {
            file: file.to_string(),
            line,
            message: format!("malformed TOML: {}", e.message().trim().replace('\n', "; ")),
        }
    })
}

/// A serde error of the typed read: its path written as the file writes keys (`[stop].margin`,
/// `[seeds].values[1]`, `[[point]] 2`, `scene`), serde's "unknown field" in our words.
fn serde_error(file: &str, err: &serde_path_to_error::Error<toml::de::Error>) -> SweepError {
    let segments: Vec<&Segment> = (err.path().iter())
        .filter(|s| !matches!(s, Segment::Map { key } if key == DATE))
        .collect();
    let key = match segments.as_slice() {
        [Segment::Map { key }] if SECTIONS.contains(&key.as_str()) => format!("[{key}]"),
        [Segment::Map { key }, Segment::Seq { index }] if key == "point" => {
            format!("[[point]] {index}")
        }
        [only] => only.to_string(),
        [first, rest @ ..] => rest.iter().fold(format!("[{first}]"), |k, s| match s {
            Segment::Seq { index } => format!("{k}[{index}]"),
            s => format!("{k}.{s}"),
        }),
        [] => String::new(),
    };
    let m = err.inner().message();
    let message = match m
        .strip_prefix("unknown field `")
        .and_then(|r| r.split_once(", expected "))
    {
        Some((_, allowed)) => format!(
            "unknown key (expected one of: {})",
            allowed
                .trim_start_matches("one of ")
                .replace('`', "")
                .replace(" or ", ", ")
        ),
        None => m.to_string(),
    };
    SweepError::Key {
        file: file.to_string(),
        key,
        message,
    }
}

/// A scene key a sweep sets: quoted and dotted (`"chain.exponent"`).
fn check_key(where_: &str, k: &str, e: &KeyErr) -> Result<(), SweepError> {
    match expand::key_shape_error(k) {
        Some(m) => Err(e(&format!("{where_}.\"{k}\""), m)),
        None => Ok(()),
    }
}

/// The overrides of a `[set]` or `[[point]]` table.
fn overrides(where_: &str, t: &Table, e: &KeyErr) -> Result<Vec<(String, Value)>, SweepError> {
    let mut out = Vec::new();
    for (k, v) in t {
        check_key(where_, k, e)?;
        out.push((k.clone(), v.clone()));
    }
    Ok(out)
}

/// `[grid]`: each key with its non-empty list of values.
fn grid(t: &Table, e: &KeyErr) -> Result<Vec<(String, Vec<Value>)>, SweepError> {
    let mut grid = Vec::new();
    for (k, v) in t {
        check_key("[grid]", k, e)?;
        let key = format!("[grid].\"{k}\"");
        match v {
            Value::Array(a) if a.is_empty() => return Err(e(&key, "empty list of values".into())),
            Value::Array(a) => grid.push((k.clone(), a.clone())),
            v => {
                return Err(e(
                    &key,
                    format!("expected a list of values, got {}", type_name(v)),
                ))
            }
        }
    }
    Ok(grid)
}

/// `[seeds]`: the scene key (quoted, dotted) and its non-empty list of seeds.
fn seeds(s: Seeds, e: &KeyErr) -> Result<(String, Vec<Value>), SweepError> {
    let key = s.key.ok_or_else(|| {
        e(
            "[seeds].key",
            "missing: name the scene key the seed goes to, e.g. \"scene.seed\"".into(),
        )
    })?;
    let values = s
        .values
        .ok_or_else(|| e("[seeds].values", "missing".into()))?;
    if values.is_empty() {
        return Err(e("[seeds].values", "empty list of seeds".into()));
    }
    check_key("[seeds].key", &key, e)?;
    Ok((key, values.into_iter().map(|v| v.0).collect()))
}

/// A key may be set by only one of `[set]`, `[grid]`, `[[point]]`, `[seeds]`.
fn check_claims(
    set: &[(String, Value)],
    grid: &[(String, Vec<Value>)],
    points: &[Vec<(String, Value)>],
    seeds: &Option<(String, Vec<Value>)>,
    e: &KeyErr,
) -> Result<(), SweepError> {
    // (key, section, point, order in which a run writes it): keys of different points never
    // clash; a run writes [set], then the grid's, the points' and the seeds' columns
    let mut claims: Vec<(&str, &str, usize, (u8, usize))> = Vec::new();
    claims.extend(
        set.iter()
            .enumerate()
            .map(|(i, (k, _))| (k.as_str(), "[set]", 0, (0, i))),
    );
    claims.extend(
        grid.iter()
            .enumerate()
            .map(|(i, (k, _))| (k.as_str(), "[grid]", 0, (1, i))),
    );
    // the points' columns come in sorted order (`SweepSpec::param_columns`)
    let mut point_cols: Vec<&str> = points.iter().flatten().map(|(k, _)| k.as_str()).collect();
    point_cols.sort_unstable();
    point_cols.dedup();
    for (j, p) in points.iter().enumerate() {
        for (k, _) in p {
            let col = point_cols.binary_search(&k.as_str()).unwrap_or(0);
            claims.push((k.as_str(), "[[point]]", j, (2, col)));
        }
    }
    if let Some((k, _)) = seeds {
        claims.push((k.as_str(), "[seeds]", 0, (3, 0)));
    }
    for (i, &(k, by, j, at)) in claims.iter().enumerate() {
        for &(o, first, p, o_at) in &claims[..i] {
            let same_run = first != by || p == j;
            let message = if o == k && first != by {
                format!("also set in {first}")
            } else if !same_run || o == k {
                continue;
            } else if (part_of(o, k) && o_at < at) || (part_of(k, o) && at < o_at) {
                // the whole is written after its part, which it replaces
                let (whole, part) = if part_of(o, k) { (k, o) } else { (o, k) };
                format!(
                    "overlaps {first}.\"{o}\": \"{whole}\" is written after \"{part}\" and \
                     replaces it"
                )
            } else {
                continue;
            };
            return Err(e(
                &format!("{by}.\"{k}\""),
                format!("{message} (each key may be set in one place only)"),
            ));
        }
    }
    Ok(())
}

/// Whether dotted key `part` names a part of the value `whole` names
/// (`chain.exponent.random.eps` of `chain.exponent`).
fn part_of(part: &str, whole: &str) -> bool {
    part.strip_prefix(whole)
        .is_some_and(|rest| rest.starts_with('.'))
}

/// Why the base scene of a sweep cannot be had.
#[derive(Debug, thiserror::Error)]
enum BaseSceneError {
    /// The scene file exists but cannot be read.
    #[error("cannot read {}: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// Neither a file nor a preset.
    #[error("no scene file {} and no preset of that name{hint}", path.display())]
    NotFound {
        /// The path tried.
        path: PathBuf,
        /// A "did you mean" hint (may be empty).
        hint: String,
    },
}

/// TOML text and base directory of the base scene: a file relative to `dir`, else a preset.
fn base_scene(spec: &str, dir: &Path) -> Result<(String, PathBuf), BaseSceneError> {
    let path = dir.join(spec);
    if path.is_file() {
        let text = crate::files::read_text(&path).map_err(|source| BaseSceneError::Read {
            path: path.clone(),
            source,
        })?;
        let base = path.parent().unwrap_or(Path::new(".")).to_path_buf();
        return Ok((text, base));
    }
    match presets::presets().iter().find(|p| p.name == spec) {
        Some(p) => Ok((p.toml.to_string(), PathBuf::from("."))),
        None => Err(BaseSceneError::NotFound {
            hint: crate::suggest::preset_hint(spec),
            path,
        }),
    }
}

type KeyErr<'a> = dyn Fn(&str, String) -> SweepError + 'a;

/// Reads one TOML value and checks its form (`Err`: the message after the key).
fn form<'de, D: Deserializer<'de>, T>(
    d: D,
    check: impl FnOnce(Value) -> Result<T, String>,
) -> Result<T, D::Error> {
    check(Value::deserialize(d)?).map_err(de::Error::custom)
}

/// A string (`what` names it in the message).
fn string<'de, D: Deserializer<'de>>(d: D, what: &str) -> Result<Option<String>, D::Error> {
    form(d, |v| match v {
        Value::String(s) => Ok(Some(s)),
        v => Err(format!("expected {what}, got {}", type_name(&v))),
    })
}

/// `scene = "preset or file"`.
fn scene<'de, D: Deserializer<'de>>(d: D) -> Result<Option<String>, D::Error> {
    string(d, "a preset name or file")
}

/// `[seeds].key`.
fn seed_key<'de, D: Deserializer<'de>>(d: D) -> Result<Option<String>, D::Error> {
    string(d, "a string")
}

/// `[set]`, `[grid]`, one `[[point]]`: a table of overrides.
fn table<'de, D: Deserializer<'de>>(d: D) -> Result<Table, D::Error> {
    form(d, |v| match v {
        Value::Table(t) => Ok(t),
        v => Err(format!("expected a table, got {}", type_name(&v))),
    })
}

/// One `[[point]]` table.
#[derive(Deserialize)]
struct Tbl(#[serde(deserialize_with = "table")] Table);

/// One seed: a non-negative integer, kept as written.
struct Seed(Value);

impl<'de> Deserialize<'de> for Seed {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        form(d, |v| match v {
            Value::Integer(s) if s >= 0 => Ok(Seed(v)),
            v => Err(format!("expected a non-negative integer, got {v}")),
        })
    }
}

/// A non-negative integer (bead indices, counts).
pub(super) fn non_neg<'de, D: Deserializer<'de>, T: From<usize>>(d: D) -> Result<T, D::Error> {
    form(d, |v| match v {
        Value::Integer(i) if i >= 0 => Ok(T::from(i as usize)),
        v => Err(format!("expected a non-negative integer, got {v}")),
    })
}

/// A finite number (an integer is taken as a float).
fn finite<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    form(d, |v| match v {
        Value::Float(x) if x.is_finite() => Ok(x),
        Value::Integer(i) => Ok(i as f64),
        v => Err(format!("expected a finite number, got {v}")),
    })
}

/// `[measure].decay.jump`: a factor > 1.
pub(super) fn jump<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    let jump = finite(d)?;
    if jump <= 1.0 {
        return Err(de::Error::custom(format!("must be > 1, got {jump}")));
    }
    Ok(jump)
}

/// `[measure].fragments = true | false | { gap_tol = G }` (G >= 0, default 0).
pub(super) fn fragments<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
    #[derive(Default, Deserialize)]
    #[serde(deny_unknown_fields)]
    struct Fragments {
        #[serde(default, deserialize_with = "gap_tol")]
        gap_tol: f64,
    }
    fn gap_tol<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        let g = finite(d)?;
        if g < 0.0 {
            return Err(de::Error::custom(format!("must be >= 0, got {g}")));
        }
        Ok(g)
    }
    Ok(toggle::<D, Fragments>(d)?.map(|f| f.gap_tol))
}

/// `true` or `false`.
pub(super) fn flag<'de, D: Deserializer<'de>>(d: D) -> Result<bool, D::Error> {
    form(d, |v| match v {
        Value::Boolean(b) => Ok(b),
        v => Err(format!("expected true or false, got {}", type_name(&v))),
    })
}

/// A table read into `T` (`[seeds]`, `[measure]`, `[stop]`).
fn section<'de, D: Deserializer<'de>, T: Deserialize<'de> + Default>(
    d: D,
) -> Result<Option<T>, D::Error> {
    d.deserialize_any(Form::<T>::new("a table", false, false))
}

/// `true` (`T`'s defaults), `false` (`None`) or a table read into `T` (`[measure].decay`).
pub(super) fn toggle<'de, D: Deserializer<'de>, T: Deserialize<'de> + Default>(
    d: D,
) -> Result<Option<T>, D::Error> {
    d.deserialize_any(Form::<T>::new("true/false or a table", true, false))
}

/// `[[point]]` tables.
fn points<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<Tbl>, D::Error> {
    let points = d.deserialize_any(Form::<Vec<Tbl>>::new("[[point]] tables", false, true))?;
    Ok(points.unwrap_or_default())
}

/// `[seeds].values`: a list of seeds.
fn seed_values<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Vec<Seed>>, D::Error> {
    d.deserialize_any(Form::new("a list of integers", false, true))
}

/// The form of a table or list value (`flag`: `true`/`false` too, `list`: an array, not a
/// table). Another form is refused with "expected {what}, got {type}"; a table or list is read
/// on through serde, so errors inside keep their key path.
struct Form<T> {
    what: &'static str,
    flag: bool,
    list: bool,
    read: PhantomData<T>,
}

impl<T> Form<T> {
    fn new(what: &'static str, flag: bool, list: bool) -> Self {
        Form {
            what,
            flag,
            list,
            read: PhantomData,
        }
    }

    fn refuse<E: de::Error>(&self, got: &str) -> E {
        E::custom(format!("expected {}, got {got}", self.what))
    }
}

impl<'de, T: Deserialize<'de> + Default> Visitor<'de> for Form<T> {
    type Value = Option<T>;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str(self.what)
    }

    fn visit_bool<E: de::Error>(self, b: bool) -> Result<Option<T>, E> {
        match self.flag {
            true => Ok(b.then(T::default)),
            false => Err(self.refuse("a boolean")),
        }
    }

    fn visit_i64<E: de::Error>(self, _: i64) -> Result<Option<T>, E> {
        Err(self.refuse("an integer"))
    }

    fn visit_f64<E: de::Error>(self, _: f64) -> Result<Option<T>, E> {
        Err(self.refuse("a number"))
    }

    fn visit_str<E: de::Error>(self, _: &str) -> Result<Option<T>, E> {
        Err(self.refuse("a string"))
    }

    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Option<T>, A::Error> {
        match self.list {
            true => T::deserialize(SeqAccessDeserializer::new(seq)).map(Some),
            false => Err(self.refuse("an array")),
        }
    }

    /// A TOML date arrives as a table of one key, [`DATE`]: refused as a date.
    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Option<T>, A::Error> {
        if self.list {
            let date = map.next_key::<String>()?.is_some_and(|k| k == DATE);
            return Err(self.refuse(if date { "a date" } else { "a table" }));
        }
        T::deserialize(MapAccessDeserializer::new(map))
            .map(Some)
            .map_err(
                |e| match e.to_string().contains(&format!("unknown field `{DATE}`")) {
                    true => self.refuse("a date"),
                    false => e,
                },
            )
    }
}
