//! `Scene`: a resolved, validated scene (the library's [`beadchain::scene::Scene`]) with the
//! resolved per-bead and per-contact arrays and, for physical scenes, the unit conversion.
//!
//! Every way to make one goes through the library's parser and validator
//! ([`beadchain::scene::parse_str`], [`beadchain::scene::load`], [`beadchain::scene::preset`]),
//! so a scene built from Python values (the Python layer passes them as tables of plain values,
//! [`beadchain::scene::parse::parse_table`]) gets the same checks and the same one-line messages
//! as a scene file given to the CLI.

use crate::SceneError as PySceneError;
use beadchain::names::Named;
use beadchain::scene::{self, Scene as LibScene, SceneError};
use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};
use std::path::Path;

/// A validated scene (chain, initial state, run settings).
#[pyclass(module = "beadchain._beadchain", frozen)]
pub struct Scene {
    pub(crate) scene: LibScene,
    pub(crate) warnings: Vec<String>,
}

pub(crate) fn scene_err(e: SceneError) -> PyErr {
    PySceneError::new_err(e.to_string())
}

impl Scene {
    /// A scene as a snapshot stored it (validated when it ran; warnings not repeated).
    pub(crate) fn unchecked(scene: LibScene) -> Self {
        Self {
            scene,
            warnings: Vec::new(),
        }
    }

    pub(crate) fn new(scene: LibScene) -> PyResult<Self> {
        let warnings = scene::validate(&scene).map_err(scene_err)?;
        Ok(Self { scene, warnings })
    }

    /// A parsed scene: the construction's warnings (the gaps `[initial] equilibrium = true`
    /// leaves) first, then the validator's, as the CLI prints them.
    fn parsed(parsed: scene::Parsed) -> PyResult<Self> {
        let mut s = Self::new(parsed.scene)?;
        let mut warnings = parsed.warnings;
        warnings.append(&mut s.warnings);
        s.warnings = warnings;
        Ok(s)
    }
}

fn array<'py>(py: Python<'py>, x: &[f64]) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, x)
}

#[pymethods]
impl Scene {
    /// Parses scene TOML text; `origin` names it in messages (its stem is the default scene
    /// name), `base_dir` resolves `{ file = ... }` CSVs.
    #[staticmethod]
    #[pyo3(signature = (text, origin="scene", base_dir="."))]
    fn _from_text(text: &str, origin: &str, base_dir: &str) -> PyResult<Self> {
        Self::parsed(
            scene::parse::parse_full(text, Path::new(base_dir), origin).map_err(scene_err)?,
        )
    }

    /// A scene from Python values: `tables` is the document as a dict of tables (`{"chain":
    /// {"mass": [...], ...}, "walls": {...}}`) of plain values (bool, int, float, str, lists and
    /// str-keyed dicts; the Python layer makes NumPy values plain and leaves out what is None),
    /// read by the same parser and validator as scene text ([`scene::parse::parse_table`]).
    /// `origin` names it in messages (its stem is the default scene name), `base_dir` resolves
    /// `{ file = ... }` CSVs. A value that is not one raises `TypeError` naming its key
    /// (`scene: [chain].mass: ...`). Returns the scene and the TOML text of `tables` (its
    /// source, as `Scene.source`, `with_overrides` and pickling keep it).
    #[staticmethod]
    #[pyo3(signature = (tables, origin="scene", base_dir="."))]
    fn _from_tables(
        tables: &Bound<'_, PyDict>,
        origin: &str,
        base_dir: &str,
    ) -> PyResult<(Self, String)> {
        let type_err = |key: String, why: String| {
            pyo3::exceptions::PyTypeError::new_err(format!("{origin}: {key}: {why}"))
        };
        let mut root = toml::Table::new();
        for (name, items) in tables.iter() {
            let name: String = name
                .extract()
                .map_err(|_| type_err(format!("{name}"), "table names must be strings".into()))?;
            let items = items.cast::<PyDict>().map_err(|_| {
                type_err(
                    format!("[{name}]"),
                    "expected a dict (the table's keys)".into(),
                )
            })?;
            let mut table = toml::Table::new();
            for (k, v) in items.iter() {
                let k: String = k.extract().map_err(|_| {
                    type_err(
                        format!("[{name}]"),
                        format!("keys must be strings, got {k}"),
                    )
                })?;
                let value =
                    toml_value(&v, 0).map_err(|why| type_err(format!("[{name}].{k}"), why))?;
                table.insert(k, value);
            }
            root.insert(name, toml::Value::Table(table));
        }
        let text = toml::to_string(&root).map_err(|e| {
            PySceneError::new_err(format!(
                "{origin}: the scene cannot be written as TOML ({e})"
            ))
        })?;
        let parsed =
            scene::parse::parse_table(root, Path::new(base_dir), origin).map_err(scene_err)?;
        Ok((Self::parsed(parsed)?, text))
    }

    /// Loads a scene file, or a preset when no file of that name exists (as the CLI does).
    #[staticmethod]
    fn _load(spec: &str) -> PyResult<Self> {
        Self::parsed(scene::load_full(spec).map_err(scene_err)?)
    }

    /// A built-in preset by name (`presets()` lists them).
    #[staticmethod]
    fn _preset(name: &str) -> PyResult<Self> {
        Self::parsed(scene::presets::preset_full(name).map_err(scene_err)?)
    }

    /// Scene name.
    #[getter]
    fn name(&self) -> &str {
        &self.scene.name
    }

    /// Free-text description (physical scenes record their unit scales in it).
    #[getter]
    fn description(&self) -> &str {
        &self.scene.description
    }

    /// Number of beads N.
    #[getter]
    fn n_beads(&self) -> usize {
        self.scene.chain.len()
    }

    /// Seed of the scene's random builders.
    #[getter]
    fn seed(&self) -> u64 {
        self.scene.seed
    }

    /// The validator's warnings (exponent below 2, nothing moving, every > until).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// Initial displacements u(0), shape (N,).
    #[getter]
    fn u0<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, &self.scene.u0)
    }

    /// Initial velocities v(0), shape (N,).
    #[getter]
    fn v0<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, &self.scene.v0)
    }

    /// The `[run]` settings as resolved (None: the documented default applies).
    #[getter]
    fn run_settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let r = &self.scene.run;
        let d = PyDict::new(py);
        d.set_item("until", r.until)?;
        d.set_item("every", r.every)?;
        d.set_item("rtol", r.rtol)?;
        d.set_item("atol", r.atol)?;
        d.set_item("method", r.method.map(|m| m.name()))?;
        d.set_item("engine", r.engine.map(|e| e.name()))?;
        Ok(d)
    }

    /// The resolved chain: arrays in computer units (see the Python `Chain`).
    #[getter]
    fn _chain<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let c = &self.scene.chain;
        let d = PyDict::new(py);
        d.set_item("mass", array(py, &c.mass))?;
        d.set_item("exponent", array(py, &c.exponent))?;
        d.set_item("prefactor", array(py, &c.prefactor))?;
        d.set_item(
            "precompression",
            c.precompression.as_deref().map(|x| array(py, x)),
        )?;
        d.set_item("field", c.field.as_deref().map(|x| array(py, x)))?;
        let wall = |w: &Option<beadchain::model::Wall>| -> PyResult<Option<Bound<'py, PyDict>>> {
            let Some(w) = w else { return Ok(None) };
            let d = PyDict::new(py);
            d.set_item("exponent", w.exponent)?;
            d.set_item("prefactor", w.prefactor)?;
            d.set_item("precompression", w.precompression)?;
            d.set_item("hard", w.restitution.is_some())?;
            d.set_item("restitution", w.restitution)?;
            Ok(Some(d))
        };
        d.set_item("left_wall", wall(&c.left_wall)?)?;
        d.set_item("right_wall", wall(&c.right_wall)?)?;
        match &c.damping {
            Some(dm) => {
                d.set_item("law", dm.law.name())?;
                d.set_item("damping", array(py, &dm.contact))?;
                d.set_item("damping_walls", (dm.left_wall, dm.right_wall))?;
            }
            None => {
                d.set_item("law", "elastic")?;
                d.set_item("damping", py.None())?;
                d.set_item("damping_walls", py.None())?;
            }
        }
        match &c.hard {
            Some(h) => {
                let r: Vec<f64> = h
                    .restitution
                    .iter()
                    .map(|x| x.unwrap_or(f64::NAN))
                    .collect();
                d.set_item("hard_restitution", array(py, &r))?;
                d.set_item("collapse_interval", h.collapse_interval)?;
            }
            None => {
                d.set_item("hard_restitution", py.None())?;
                d.set_item("collapse_interval", py.None())?;
            }
        }
        Ok(d)
    }

    /// Unit scales of a physical scene ([`beadchain::scene::Scene::units`], full precision; the
    /// values the CLI's `--units si` uses): `{"beta": s, "m0": kg, "mu": .., "n0": ..}`; None when dimensionless.
    #[getter]
    fn _units<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        let Some(s) = beadchain::plot::units::scene_scales(&self.scene) else {
            return Ok(None);
        };
        let d = PyDict::new(py);
        d.set_item("beta", s.time)?;
        d.set_item("m0", s.mass)?;
        d.set_item("mu", s.mu)?;
        d.set_item("n0", s.n0)?;
        Ok(Some(d))
    }

    /// The resolved scene as TOML text (every array written out; parses back to this scene).
    fn to_toml(&self) -> String {
        scene::show::to_toml(&self.scene)
    }

    /// This scene's TOML `text` (its source) with dotted-key `overrides` written in, in order, by
    /// the sweep's functions (`beadchain::sweep::expand::override_scene`): the same key walk,
    /// parser, validator and messages as a sweep's run scenes. `base_dir` resolves CSV files;
    /// the name stays unless `scene.name` is set. Returns the scene and its TOML text.
    fn _with_overrides(
        &self,
        text: &str,
        overrides: Vec<(String, Bound<'_, PyAny>)>,
        base_dir: &str,
    ) -> PyResult<(Self, String)> {
        const WHAT: &str = "with_overrides";
        let base: toml::Table = toml::from_str(text).map_err(|e| {
            PySceneError::new_err(format!(
                "{WHAT}: the scene's source text is not TOML ({})",
                e.message()
            ))
        })?;
        let mut kv = Vec::with_capacity(overrides.len());
        for (k, v) in overrides {
            let value = toml_value(&v, 0).map_err(|why| {
                pyo3::exceptions::PyTypeError::new_err(format!("{WHAT}: \"{k}\": {why}"))
            })?;
            kv.push((k, value));
        }
        let name = &self.scene.name;
        let (s, text) =
            beadchain::sweep::expand::override_scene(&base, &kv, Path::new(base_dir), name, name)
                .map_err(|m| PySceneError::new_err(format!("{WHAT}: {m}")))?;
        Ok((Self::new(s)?, text))
    }

    /// The source of the scene that ran: `text` (the source of the scene given to `run()` or
    /// `Simulation`) with this scene's `[run]` `until` (when `until`) and `every` (when
    /// `every`) written in, in place of what the text gave (their `_si` twins removed: the
    /// values are in computer units). None when the text is not TOML or cannot be written.
    fn _ran_source(&self, text: &str, until: bool, every: bool) -> Option<String> {
        use toml::Value;
        let mut root: toml::Table = toml::from_str(text).ok()?;
        let Value::Table(run) = root
            .entry("run")
            .or_insert_with(|| Value::Table(toml::Table::new()))
        else {
            return None;
        };
        let r = &self.scene.run;
        if until {
            run.remove("until_si");
            run.insert("until".into(), Value::Float(r.until));
        }
        if every {
            run.remove("every_si");
            match r.every {
                Some(x) => run.insert("every".into(), Value::Float(x)),
                None => run.remove("every"),
            };
        }
        toml::to_string(&root).ok()
    }

    /// The scene as bytes for pickling (bincode of the resolved scene, its `[output]` selection
    /// and its warnings: every field exactly, whatever its contact law or origin).
    fn _state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        let state = (&self.scene, &self.scene.run.output, &self.warnings);
        let b = bincode::serde::encode_to_vec(state, bincode::config::standard())
            .map_err(|e| PySceneError::new_err(format!("{}: pickle: {e}", self.scene.name)))?;
        Ok(PyBytes::new(py, &b))
    }

    /// The scene [`Scene::_state`] wrote.
    #[staticmethod]
    fn _from_state(b: &[u8]) -> PyResult<Self> {
        type State = (LibScene, Option<scene::selection::Selection>, Vec<String>);
        let ((mut scene, output, warnings), _): (State, usize) =
            bincode::serde::decode_from_slice(b, bincode::config::standard()).map_err(|e| {
                PySceneError::new_err(format!("unpickle Scene: not a scene state ({e})"))
            })?;
        scene.run.output = output;
        Ok(Self { scene, warnings })
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene(name={:?}, n_beads={}, until={})",
            self.scene.name,
            self.scene.chain.len(),
            self.scene.run.until
        )
    }
}

/// A Python value as a TOML value (bool, int, float, str, lists and str-keyed dicts of them;
/// NumPy values are made plain by the Python layer first).
fn toml_value(v: &Bound<'_, PyAny>, depth: usize) -> Result<toml::Value, String> {
    use pyo3::types::{PyBool, PyFloat, PyInt, PyString, PyTuple};
    use toml::Value;
    if depth > 32 {
        return Err("nested more than 32 levels deep".into());
    }
    if v.is_instance_of::<PyBool>() {
        return Ok(Value::Boolean(
            v.extract::<bool>().map_err(|e| e.to_string())?,
        ));
    }
    if v.is_instance_of::<PyInt>() {
        let i: i64 = v
            .extract()
            .map_err(|_| format!("the integer {v} does not fit in 64 bits"))?;
        return Ok(Value::Integer(i));
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(Value::Float(v.extract::<f64>().map_err(|e| e.to_string())?));
    }
    if v.is_instance_of::<PyString>() {
        return Ok(Value::String(
            v.extract::<String>().map_err(|e| e.to_string())?,
        ));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items: Vec<Bound<'_, PyAny>> = v
            .try_iter()
            .map_err(|e| e.to_string())?
            .collect::<PyResult<_>>()
            .map_err(|e| e.to_string())?;
        return items
            .iter()
            .map(|x| toml_value(x, depth + 1))
            .collect::<Result<Vec<_>, _>>()
            .map(Value::Array);
    }
    if let Ok(d) = v.cast::<PyDict>() {
        let mut t = toml::Table::new();
        for (k, x) in d.iter() {
            let k: String = k
                .extract()
                .map_err(|_| format!("dict keys must be strings, got {k:?}"))?;
            t.insert(k, toml_value(&x, depth + 1)?);
        }
        return Ok(Value::Table(t));
    }
    let ty = v
        .get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string());
    Err(format!(
        "expected a number, string, bool, list or dict, got {ty}"
    ))
}

/// The built-in presets: a list of `(name, description)`.
#[pyfunction]
pub fn presets<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
    let items: Vec<(&str, &str)> = scene::presets()
        .iter()
        .map(|p| (p.name, p.description))
        .collect();
    PyList::new(py, items)
}

/// The TOML text of a built-in preset (None for an unknown name).
#[pyfunction]
pub fn _preset_toml(name: &str) -> Option<&'static str> {
    scene::presets()
        .iter()
        .find(|p| p.name == name)
        .map(|p| p.toml)
}

/// The preset names nearest to `name` (the CLI's "did you mean"; empty when none is near).
#[pyfunction]
pub fn _nearest_presets(name: &str) -> Vec<&'static str> {
    beadchain::suggest::nearest(name, scene::presets().iter().map(|p| p.name))
}
