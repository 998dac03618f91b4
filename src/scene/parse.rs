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
}

/// [`parse_str`], with the bead material and the construction's warnings ([`Parsed`]).
pub fn parse_full(text: &str, base_dir: &Path, origin: &str) -> Result<Parsed, SceneError> {
    let origin = one_line(origin);
    let root: Table = toml::from_str(text).map_err(|e| syntax_error(&origin, text, &e))?;
    let parsed = build(&root, base_dir, &origin)?;
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
fn build(root: &Table, base_dir: &Path, origin: &str) -> Result<Parsed, SceneError> {
    let pre = Ctx {
        file: origin,
        base_dir,
        seed: 0,
    };
    let (scene_t, seed) = tables::scene_table(&pre, root)?;
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
    let damping = damping(ctx, &t, &walls, (&inertia, &exponent), scales)?;
    let [left_wall, right_wall] = walls;
    let (run, hard) = settings::run_settings(ctx, root, &t, scales, len.nb)?;
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
    Ok(Parsed {
        scene,
        material,
        warnings,
    })
}

/// The contact law's damping (`[chain] law`, `damping`, …, and the walls'), given the chain's
/// masses, prefactors and material (`inertia`) and exponents.
fn damping(
    ctx: &Ctx,
    t: &tables::Tables,
    walls: &[Option<crate::model::Wall>; 2],
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
    super::damping::parse(ctx, t.chain, t.walls, walls, arrays, scales)
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
