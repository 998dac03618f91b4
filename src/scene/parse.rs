//! Reading scene files: TOML text → [`Scene`], with every key checked (unknown keys are errors)
//! and every message naming the file and key path. The key reference is in the `scene` module
//! docs; value forms and builders are in [`super::values`], physical units in [`super::units`].

use super::error::{one_line, SceneError};
use super::plausible::BeadMaterial;
use super::validate::validate_in;
use super::values::{Ctx, Per};
use super::{arrays, initial, material, settings, statics, tables, walls, Scene};
use crate::model::Chain;
use std::path::Path;
use toml::Table;

pub use super::arrays::{DEFAULT_EXPONENT, MAX_BEADS};
pub use super::material::{DEFAULT_MASS, DEFAULT_PREFACTOR};

/// Parse scene text. `base_dir` resolves `{ file = ... }` CSVs; `origin` names the file in
/// messages (its stem is the default scene name). The result is validated.
pub fn parse_str(text: &str, base_dir: &Path, origin: &str) -> Result<Scene, SceneError> {
    parse_with_material(text, base_dir, origin).map(|(scene, _)| scene)
}

/// [`parse_str`], with the SI bead material of a physical scene (`[units]` radius, young,
/// density; `None` otherwise), which the resolved scene does not keep: the plausibility
/// warnings of [`super::plausible`] need it.
pub fn parse_with_material(
    text: &str,
    base_dir: &Path,
    origin: &str,
) -> Result<(Scene, Option<BeadMaterial>), SceneError> {
    parse_full(text, base_dir, origin).map(|p| (p.scene, p.material))
}

/// A parsed scene with what the resolved [`Scene`] does not keep.
#[derive(Clone, Debug)]
pub struct Parsed {
    /// The resolved, validated scene.
    pub scene: Scene,
    /// The SI bead material of a physical scene ([`parse_with_material`]).
    pub material: Option<BeadMaterial>,
    /// Warnings of the construction, one line each naming the file and key (the gaps that
    /// `[initial] equilibrium = true` leaves); [`super::validate`] adds those of the scene.
    pub warnings: Vec<String>,
    /// The key that gave the end time, `[run].until` or `[run].until_si` (seconds), which the
    /// resolved scene holds in computer units: warnings about the end time name it.
    pub until_key: &'static str,
    /// The key that gave the output interval, `[run].every` or `[run].every_si` (seconds).
    pub every_key: &'static str,
}

/// [`parse_str`], with the bead material and the construction's warnings ([`Parsed`]).
pub fn parse_full(text: &str, base_dir: &Path, origin: &str) -> Result<Parsed, SceneError> {
    let origin = one_line(origin);
    let root: Table = toml::from_str(text).map_err(|e| syntax_error(&origin, text, &e))?;
    parse_table(root, base_dir, &origin)
}

/// [`parse_full`] of an already parsed TOML document (the Python package's `Scene(...)` passes
/// its keywords as tables): the same construction, checks and messages as the text, which
/// [`parse_full`] reads into a [`Table`] and hands here. `origin` names the scene in messages
/// (its stem is the default scene name), `base_dir` resolves `{ file = ... }` CSVs. The result
/// is validated.
pub fn parse_table(root: Table, base_dir: &Path, origin: &str) -> Result<Parsed, SceneError> {
    let origin = one_line(origin);
    let parsed = build(root, base_dir, &origin)?;
    validate_in(&parsed.scene, &origin)?;
    Ok(parsed)
}

/// Convert a TOML error into a one-line error with 1-based line/column.
fn syntax_error(file: &str, text: &str, e: &toml::de::Error) -> SceneError {
    let (line, column) = match e.span() {
        Some(span) => {
            let mut end = span.start.min(text.len());
            while !text.is_char_boundary(end) {
                end -= 1;
            }
            let upto = &text[..end];
            let line = upto.matches('\n').count() + 1;
            let col = upto.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            (line, col)
        }
        None => (0, 0),
    };
    let mut message = one_line(&e.message().trim().replace('\n', "; "));
    if let Some(key) = super::error::key_at_line(text, line) {
        message = format!("{key}: {message}");
    }
    SceneError::Syntax {
        file: file.to_string(),
        line,
        column,
        message,
    }
}

/// Builds the scene from the parsed TOML, table by table, in the order their errors are
/// reported: tables and units system ([`super::tables`]), array keys and chain length
/// ([`super::arrays`]), masses and prefactors ([`super::material`]), initial state and field
/// ([`super::initial`]), walls ([`super::walls`]) and damping ([`super::damping`]), run settings
/// with `[hard]` and `[output]` ([`super::settings`]).
fn build(root: Table, base_dir: &Path, origin: &str) -> Result<Parsed, SceneError> {
    let pre = Ctx {
        file: origin,
        base_dir,
        seed: 0,
    };
    let (root, scene_t, seed) = tables::scene_table(&pre, root)?;
    let ctx = &Ctx {
        file: origin,
        base_dir,
        seed,
    };
    let t = tables::read_tables(ctx, root, scene_t)?;
    let physical = tables::unit_system(ctx, &t)?;
    let specs = arrays::read_specs(ctx, &t)?;
    let len = arrays::chain_length(ctx, &t, &specs)?;
    let exponent = len.resolve(
        ctx,
        &specs.exponent,
        "[chain].exponent",
        Per::Contact,
        DEFAULT_EXPONENT,
    )?;
    let inertia = material::inertia(ctx, &t, &specs, len, physical)?;
    let scales = match inertia.scales {
        Some(sc) => Some(sc),
        None => tables::computer_scales(ctx, &t)?,
    };
    let pre_force = statics::precompression_force(ctx, &t, scales)?;
    let precompression = match pre_force {
        Some(f) => Some(statics::precompression_of(f, &exponent, &inertia.prefactor)),
        None => precompression(ctx, &specs, len)?,
    };
    let (u0, v0) = initial::initial_state(ctx, &t, &specs, len, physical, scales)?;
    let field = initial::field(ctx, &t, &specs, len, scales, &inertia.mass)?;
    let defaults = walls::WallDefaults {
        len,
        exponent: &exponent,
        prefactor: &inertia.prefactor,
        scales,
        material: inertia.material.as_ref(),
        physical,
        precompression_force: pre_force,
    };
    let walls = walls::walls(ctx, &t, &defaults)?;
    let damping = damping(ctx, &t.chain, &walls, (&inertia, &exponent), scales)?;
    let [left_wall, right_wall] = walls.map(|w| w.map(|(wall, _)| wall));
    let (run, hard) = settings::run_settings(ctx, &t, scales, len.nb)?;
    let (name, description) = settings::name_and_description(ctx, &t, origin, scales)?;
    let material = inertia.material.map(bead_material);
    let mut scene = Scene {
        name,
        description,
        chain: Chain {
            mass: inertia.mass,
            exponent,
            prefactor: inertia.prefactor,
            precompression,
            field,
            left_wall,
            right_wall,
            hard,
            damping,
        },
        u0,
        v0,
        run,
        seed,
        units: scales,
    };
    super::solitary::apply(ctx, &t, physical, scales, &mut scene)?;
    super::hard::default_collapse_interval(&mut scene);
    let warnings = statics::apply(ctx, &t, &mut scene)?;
    let until_key = match t.run.until_si {
        Some(_) => "[run].until_si",
        None => "[run].until",
    };
    let every_key = match t.run.every_si {
        Some(_) => "[run].every_si",
        None => "[run].every",
    };
    Ok(Parsed {
        scene,
        material,
        warnings,
        until_key,
        every_key,
    })
}

/// The contact law's damping (`[chain] law`, `damping`, …, and the walls'), given the chain's
/// masses, prefactors and material (`inertia`) and exponents.
fn damping(
    ctx: &Ctx,
    chain: &tables::ChainKeys,
    walls: &[Option<(crate::model::Wall, tables::WallKeys)>; 2],
    (inertia, exponent): (&material::Inertia, &[f64]),
    scales: Option<super::units::UnitScales>,
) -> Result<Option<crate::model::Damping>, SceneError> {
    let arrays = super::damping::ChainArrays {
        mass: &inertia.mass,
        exponent,
        prefactor: &inertia.prefactor,
        material_a: inertia
            .material
            .as_ref()
            .and_then(|m| m.viscous_a.as_deref()),
    };
    super::damping::parse(ctx, chain, walls, arrays, scales)
}

/// `[chain].precompression` per contact, `None` when absent or zero everywhere (the chain then
/// skips the term).
/// The SI bead material of a physical scene, as `scene show` and the plausibility checks read it.
fn bead_material(m: material::Material) -> BeadMaterial {
    BeadMaterial {
        radius: m.radius,
        young: m.young,
        density: m.density,
    }
}

fn precompression(
    ctx: &Ctx,
    specs: &arrays::Specs,
    len: arrays::Len,
) -> Result<Option<Vec<f64>>, SceneError> {
    Ok(match &specs.precompression {
        Some(s) => {
            let p = s.resolve(ctx, "[chain].precompression", len.nc, Per::Contact, 0.0)?;
            p.iter().any(|x| *x != 0.0).then_some(p)
        }
        None => None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use toml::Value;

    /// A scene file's text and the same document built in Rust as a [`Table`] (per-bead array,
    /// builder with segments, walls, units and run tables): [`parse_table`] gives the scene,
    /// material and warnings of [`parse_full`], and its errors are the text's too.
    #[test]
    fn parse_table_equals_parse_full_of_the_same_document() {
        let mass: Vec<f64> = (0..12).map(|i| 1.0 + f64::from(i) / 7.0).collect();
        let text = format!(
            "[scene]\nseed = 3\n\
             [chain]\nmass = {mass:?}\n\
             exponent = {{ base = 3.0, segments = [{{ from = 5, value = 2.5 }}] }}\n\
             [initial]\nstriker = 0.7\n\
             [run]\nuntil = 4.0\nevery = 0.5\n\
             [walls]\nright = {{ exponent = 2.5 }}\n"
        );
        let t = |items: Vec<(&str, Value)>| {
            Value::Table(items.into_iter().map(|(k, v)| (k.to_string(), v)).collect())
        };
        let root = match t(vec![
            ("scene", t(vec![("seed", Value::Integer(3))])),
            (
                "chain",
                t(vec![
                    (
                        "mass",
                        Value::Array(mass.iter().map(|&m| Value::Float(m)).collect()),
                    ),
                    (
                        "exponent",
                        t(vec![
                            ("base", Value::Float(3.0)),
                            (
                                "segments",
                                Value::Array(vec![t(vec![
                                    ("from", Value::Integer(5)),
                                    ("value", Value::Float(2.5)),
                                ])]),
                            ),
                        ]),
                    ),
                ]),
            ),
            ("initial", t(vec![("striker", Value::Float(0.7))])),
            (
                "run",
                t(vec![
                    ("until", Value::Float(4.0)),
                    ("every", Value::Float(0.5)),
                ]),
            ),
            (
                "walls",
                t(vec![("right", t(vec![("exponent", Value::Float(2.5))]))]),
            ),
        ]) {
            Value::Table(root) => root,
            _ => unreachable!(),
        };
        let here = Path::new(".");
        let a = parse_full(&text, here, "c.toml").unwrap();
        let b = parse_table(root.clone(), here, "c.toml").unwrap();
        assert_eq!(a.scene, b.scene);
        assert_eq!(a.scene.name, "c");
        assert_eq!(a.scene.chain.mass, mass);
        assert_eq!(format!("{:?}", a.material), format!("{:?}", b.material));
        assert_eq!(a.warnings, b.warnings);

        // A bad value: the same one-line message from both.
        let mut bad = root.clone();
        bad["run"]
            .as_table_mut()
            .unwrap()
            .insert("until".into(), Value::Float(f64::NAN));
        let text_bad = text.replace("until = 4.0", "until = nan");
        let ea = parse_full(&text_bad, here, "c.toml")
            .unwrap_err()
            .to_string();
        let eb = parse_table(bad.clone(), here, "c.toml")
            .unwrap_err()
            .to_string();
        assert_eq!(ea, eb);
        assert!(ea.starts_with("c.toml: [run].until: "), "{ea}");
    }
}
