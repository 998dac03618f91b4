//! Reading sweep files (format in the [`super`] module docs): the base scene, the overrides of
//! `[set]`, `[grid]`, `[[point]]` and `[seeds]` (each key in one place only), `[measure]` and
//! `[stop]`. Every error names the sweep file and the key.

use super::{expand, fnv1a, type_name, Decay, Measure, Stop, SweepError, SweepSpec};
use crate::scene::presets;
use std::path::{Path, PathBuf};
use toml::{Table, Value};

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
        let root = root_table(text, file)?;
        let scene_spec = scene_key(&root, e)?;
        let (base_text, base_dir) = base_scene(&scene_spec, dir)
            .map_err(|m| key_err("scene", format!("\"{scene_spec}\": {m}")))?;
        let base: Table = toml::from_str(&base_text)
            .map_err(|e| key_err("scene", format!("\"{scene_spec}\": malformed TOML: {e}")))?;
        let set = match table(&root, "set", e)? {
            Some(t) => overrides("[set]", t, e)?,
            None => Vec::new(),
        };
        let grid = grid(&root, e)?;
        let points = points(&root, e)?;
        let seeds = match table(&root, "seeds", e)? {
            None => None,
            Some(t) => Some(parse_seeds(t, e)?),
        };
        if let Some((k, _)) = &seeds {
            check_key("[seeds].key", k, e)?;
        }
        let n_seeds = seeds.as_ref().map(|(_, v)| v.len());
        if let Some(m) = expand::too_many_runs(&grid, points.len(), n_seeds) {
            return Err(key_err("[grid]", m));
        }
        check_claims(&set, &grid, &points, &seeds, e)?;
        let measure = match table(&root, "measure", e)? {
            Some(t) => parse_measure(t, e)?,
            None => Measure::default(),
        };
        let stop = match table(&root, "stop", e)? {
            Some(t) => parse_stop(t, e)?,
            None => Stop::default(),
        };
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
            measure,
            stop,
            hash: fnv1a(canon.as_bytes()),
            max_output_bytes: crate::snapshot::size::DEFAULT_MAX_OUTPUT_BYTES,
        })
    }
}

/// The sweep file's TOML, its top-level keys checked.
fn root_table(text: &str, file: &str) -> Result<Table, SweepError> {
    let root: Table = toml::from_str(text).map_err(|e| {
        let line = e.span().map_or(0, |s| {
            text[..s.start.min(text.len())].matches('\n').count() + 1
        });
        SweepError::Csv {
            file: file.to_string(),
            line,
            message: format!("malformed TOML: {}", e.message().trim().replace('\n', "; ")),
        }
    })?;
    const TOP: &[&str] = &["scene", "set", "grid", "point", "seeds", "measure", "stop"];
    for k in root.keys() {
        if !TOP.contains(&k.as_str()) {
            return Err(SweepError::Key {
                file: file.to_string(),
                key: k.to_string(),
                message: format!("unknown key (expected one of: {})", TOP.join(", ")),
            });
        }
    }
    Ok(root)
}

/// `scene = "preset or file"`.
fn scene_key(root: &Table, e: &KeyErr) -> Result<String, SweepError> {
    match root.get("scene") {
        Some(Value::String(s)) => Ok(s.clone()),
        Some(v) => Err(e(
            "scene",
            format!("expected a preset name or file, got {}", type_name(v)),
        )),
        None => Err(e("scene", "missing (base scene: preset or file)".into())),
    }
}

/// A top-level table of the sweep (`None` when absent).
fn table<'a>(root: &'a Table, name: &str, e: &KeyErr) -> Result<Option<&'a Table>, SweepError> {
    match root.get(name) {
        None => Ok(None),
        Some(Value::Table(t)) => Ok(Some(t)),
        Some(v) => Err(e(
            &format!("[{name}]"),
            format!("expected a table, got {}", type_name(v)),
        )),
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
fn grid(root: &Table, e: &KeyErr) -> Result<Vec<(String, Vec<Value>)>, SweepError> {
    let mut grid = Vec::new();
    if let Some(t) = table(root, "grid", e)? {
        for (k, v) in t {
            check_key("[grid]", k, e)?;
            let key = format!("[grid].\"{k}\"");
            match v {
                Value::Array(a) if a.is_empty() => {
                    return Err(e(&key, "empty list of values".into()))
                }
                Value::Array(a) => grid.push((k.clone(), a.clone())),
                v => {
                    return Err(e(
                        &key,
                        format!("expected a list of values, got {}", type_name(v)),
                    ))
                }
            }
        }
    }
    Ok(grid)
}

/// `[[point]]` tables, each a list of overrides.
fn points(root: &Table, e: &KeyErr) -> Result<Vec<Vec<(String, Value)>>, SweepError> {
    let mut points = Vec::new();
    match root.get("point") {
        None => {}
        Some(Value::Array(a)) => {
            for (i, p) in a.iter().enumerate() {
                let w = format!("[[point]] {i}");
                match p {
                    Value::Table(t) => points.push(overrides(&w, t, e)?),
                    v => return Err(e(&w, format!("expected a table, got {}", type_name(v)))),
                }
            }
        }
        Some(v) => {
            return Err(e(
                "point",
                format!("expected [[point]] tables, got {}", type_name(v)),
            ))
        }
    }
    Ok(points)
}

/// A key may be set by only one of `[set]`, `[grid]`, `[[point]]`, `[seeds]`.
fn check_claims(
    set: &[(String, Value)],
    grid: &[(String, Vec<Value>)],
    points: &[Vec<(String, Value)>],
    seeds: &Option<(String, Vec<Value>)>,
    e: &KeyErr,
) -> Result<(), SweepError> {
    let mut claims: Vec<(&str, &str)> = Vec::new();
    claims.extend(set.iter().map(|(k, _)| (k.as_str(), "[set]")));
    claims.extend(grid.iter().map(|(k, _)| (k.as_str(), "[grid]")));
    for p in points {
        claims.extend(p.iter().map(|(k, _)| (k.as_str(), "[[point]]")));
    }
    if let Some((k, _)) = seeds {
        claims.push((k.as_str(), "[seeds]"));
    }
    for (i, (k, by)) in claims.iter().enumerate() {
        if let Some((_, first)) = claims[..i].iter().find(|(o, b)| o == k && b != by) {
            return Err(e(
                &format!("{by}.\"{k}\""),
                format!("also set in {first} (each key may be set in one place only)"),
            ));
        }
    }
    Ok(())
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

fn check_table_keys(t: &Table, name: &str, allowed: &[&str], e: &KeyErr) -> Result<(), SweepError> {
    for k in t.keys() {
        if !allowed.contains(&k.as_str()) {
            return Err(e(
                &format!("[{name}].{k}"),
                format!("unknown key (expected one of: {})", allowed.join(", ")),
            ));
        }
    }
    Ok(())
}

fn get_usize(t: &Table, name: &str, key: &str, e: &KeyErr) -> Result<Option<usize>, SweepError> {
    match t.get(key) {
        None => Ok(None),
        Some(Value::Integer(i)) if *i >= 0 => Ok(Some(*i as usize)),
        Some(v) => Err(e(
            &format!("[{name}].{key}"),
            format!("expected a non-negative integer, got {v}"),
        )),
    }
}

fn get_f64(t: &Table, name: &str, key: &str, e: &KeyErr) -> Result<Option<f64>, SweepError> {
    match t.get(key) {
        None => Ok(None),
        Some(Value::Float(x)) if x.is_finite() => Ok(Some(*x)),
        Some(Value::Integer(i)) => Ok(Some(*i as f64)),
        Some(v) => Err(e(
            &format!("[{name}].{key}"),
            format!("expected a finite number, got {v}"),
        )),
    }
}

fn parse_seeds(t: &Table, e: &KeyErr) -> Result<(String, Vec<Value>), SweepError> {
    check_table_keys(t, "seeds", &["key", "values"], e)?;
    let key = match t.get("key") {
        Some(Value::String(s)) => s.clone(),
        Some(v) => {
            return Err(e(
                "[seeds].key",
                format!("expected a string, got {}", type_name(v)),
            ))
        }
        None => {
            return Err(e(
                "[seeds].key",
                "missing: name the scene key the seed goes to, e.g. \"scene.seed\"".into(),
            ))
        }
    };
    let values = match t.get("values") {
        Some(Value::Array(a)) if a.is_empty() => {
            return Err(e("[seeds].values", "empty list of seeds".into()))
        }
        Some(Value::Array(a)) => a.clone(),
        Some(v) => {
            return Err(e(
                "[seeds].values",
                format!("expected a list of integers, got {}", type_name(v)),
            ))
        }
        None => return Err(e("[seeds].values", "missing".into())),
    };
    for (i, v) in values.iter().enumerate() {
        if !matches!(v, Value::Integer(s) if *s >= 0) {
            return Err(e(
                &format!("[seeds].values[{i}]"),
                format!("expected a non-negative integer, got {v}"),
            ));
        }
    }
    Ok((key, values))
}

fn parse_measure(t: &Table, e: &KeyErr) -> Result<Measure, SweepError> {
    const M: &str = "measure";
    check_table_keys(t, M, &["interface", "impurity", "decay", "fragments"], e)?;
    let decay = match t.get("decay") {
        None | Some(Value::Boolean(false)) => None,
        Some(Value::Boolean(true)) => Some(Decay::default()),
        Some(Value::Table(d)) => {
            check_table_keys(d, "measure].decay", &["from", "e0_bead", "jump"], e)?;
            let def = Decay::default();
            let jump = get_f64(d, "measure].decay", "jump", e)?.unwrap_or(def.jump);
            if jump <= 1.0 {
                return Err(e(
                    "[measure].decay.jump",
                    format!("must be > 1, got {jump}"),
                ));
            }
            Some(Decay {
                from: get_usize(d, "measure].decay", "from", e)?.unwrap_or(def.from),
                e0_bead: get_usize(d, "measure].decay", "e0_bead", e)?.unwrap_or(def.e0_bead),
                jump,
            })
        }
        Some(v) => {
            return Err(e(
                "[measure].decay",
                format!("expected true/false or a table, got {}", type_name(v)),
            ))
        }
    };
    let fragments = match t.get("fragments") {
        None | Some(Value::Boolean(false)) => None,
        Some(Value::Boolean(true)) => Some(0.0),
        Some(Value::Table(f)) => {
            check_table_keys(f, "measure].fragments", &["gap_tol"], e)?;
            let g = get_f64(f, "measure].fragments", "gap_tol", e)?.unwrap_or(0.0);
            if g < 0.0 {
                return Err(e(
                    "[measure].fragments.gap_tol",
                    format!("must be >= 0, got {g}"),
                ));
            }
            Some(g)
        }
        Some(v) => {
            return Err(e(
                "[measure].fragments",
                format!("expected true/false or a table, got {}", type_name(v)),
            ))
        }
    };
    Ok(Measure {
        interface: get_usize(t, M, "interface", e)?,
        impurity: get_usize(t, M, "impurity", e)?,
        decay,
        fragments,
    })
}

fn parse_stop(t: &Table, e: &KeyErr) -> Result<Stop, SweepError> {
    check_table_keys(t, "stop", &["margin", "steady_state"], e)?;
    let steady_state = match t.get("steady_state") {
        None => false,
        Some(Value::Boolean(b)) => *b,
        Some(v) => {
            return Err(e(
                "[stop].steady_state",
                format!("expected true or false, got {}", type_name(v)),
            ))
        }
    };
    Ok(Stop {
        margin: get_usize(t, "stop", "margin", e)?,
        steady_state,
    })
}
