//! Loading a scene by name: a `.toml` file path, else a preset name. Sits above both
//! [`super::parse`] (text → scene) and [`super::presets`] (which parses its embedded text), so
//! neither imports the other back.

use super::error::{one_line, SceneError};
use super::parse::{parse_full, Parsed};
use super::plausible::BeadMaterial;
use super::presets;
use super::Scene;
use std::path::Path;

/// Load a scene: `spec` is a path to a `.toml` file; if no such file exists and `spec` is a
/// preset name, the preset is loaded; otherwise the error names both possibilities.
pub fn load(spec: &str) -> Result<Scene, SceneError> {
    load_with_material(spec).map(|(s, _)| s)
}

/// [`load`], with the SI bead material of a physical scene
/// ([`super::parse::parse_with_material`]).
pub fn load_with_material(spec: &str) -> Result<(Scene, Option<BeadMaterial>), SceneError> {
    load_full(spec).map(|p| (p.scene, p.material))
}

/// [`load`], with the bead material and the warnings of the scene's construction ([`Parsed`]).
pub fn load_full(spec: &str) -> Result<Parsed, SceneError> {
    let path = Path::new(spec);
    if path.exists() {
        let text = crate::files::read_text(path).map_err(|e| SceneError::Io {
            file: one_line(spec),
            reason: one_line(&e.to_string()),
        })?;
        let base = path.parent().unwrap_or(Path::new("."));
        return parse_full(&text, base, spec);
    }
    if presets::presets().iter().any(|p| p.name == spec) {
        return presets::preset_full(spec);
    }
    Err(SceneError::NotFound {
        spec: one_line(spec),
        presets: presets::presets()
            .iter()
            .map(|p| p.name)
            .collect::<Vec<_>>()
            .join(", "),
    })
}
