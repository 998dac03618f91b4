//! Units of exported numbers (`beadchain export --units`): the snapshot's computer units, or SI
//! for a physical scene (paper eqs. 10–11, [`crate::scene::units`]).
//!
//! Computer → SI: time `t = t̃ β` (s), velocity `v = ṽ / β` (m/s), displacement and precompression
//! unchanged (lengths are metres in both), mass `m = m̃ m0` (kg), prefactor `a = ã m0 / β²`
//! (J/mⁿ, the energy scale over lengths in metres), exponent unchanged. The event log's
//! relative velocity converts like a velocity, its peak overlap like a length. These are the
//! conversions of the plots (`--units si`) and of the Python package (`Units`), with the scene's
//! full-precision scales ([`Scene::units`]). Computer units multiply and divide by exactly 1, so
//! they write the snapshot's values bit for bit.

use crate::scene::{Scene, UnitScales};
use crate::snapshot::Frame;

/// `--units si` asked of a dimensionless scene (names the scene).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error(
    "--units si: scene `{scene}` is dimensionless (computer units only); SI output needs \
     a physical scene ([units] system = \"physical\")"
)]
pub struct DimensionlessError {
    /// The scene's name.
    pub scene: String,
}

/// Conversion factors from computer units to the exported units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExportUnits {
    /// Exported time per computer time (β in s, or 1).
    pub time: f64,
    /// Computer velocity per exported velocity (β, or 1): `v = ṽ / velocity_div`.
    pub velocity_div: f64,
    /// Exported mass per computer mass (m0 in kg, or 1).
    pub mass: f64,
    /// Exported energy per computer energy (m0 / β² in J, or 1).
    pub energy: f64,
}

impl Default for ExportUnits {
    fn default() -> Self {
        Self::computer()
    }
}

impl ExportUnits {
    /// Computer units: every factor 1.
    pub const fn computer() -> Self {
        ExportUnits {
            time: 1.0,
            velocity_div: 1.0,
            mass: 1.0,
            energy: 1.0,
        }
    }

    /// SI units of a scene with scales `s`.
    pub fn si(s: &UnitScales) -> Self {
        ExportUnits {
            time: s.time,
            velocity_div: s.time,
            mass: s.mass,
            energy: s.mass / (s.time * s.time),
        }
    }

    /// SI units of `scene`; the error names the scene when it is dimensionless.
    pub fn si_of(scene: &Scene) -> Result<Self, DimensionlessError> {
        match scene.units {
            Some(s) if s.time > 0.0 && s.time.is_finite() => Ok(Self::si(&s)),
            _ => Err(DimensionlessError {
                scene: scene.name.clone(),
            }),
        }
    }

    /// Converts a frame read from the snapshot in place.
    pub fn frame(&self, f: &mut Frame) {
        f.t *= self.time;
        for v in &mut f.v {
            *v /= self.velocity_div;
        }
    }

    /// A velocity.
    pub fn velocity(&self, v: f64) -> f64 {
        v / self.velocity_div
    }
}
