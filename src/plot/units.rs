//! Axis units of the snapshot plots (issue 14): computer units by default, SI with
//! `--units si` for physical scenes.
//!
//! A physical scene (`[units] system = "physical"`) is simulated in the paper's computer units
//! (eqs. 10–11, [`crate::scene::units`]): time `t̃ = t / β`, velocity `ṽ = v β`, lengths in metres,
//! energy `Ẽ = E β² / m0`. The scene carries its scales ([`Scene::units`], stored in full
//! precision by snapshot format 4; older files recover them from the scene description, to seven
//! significant digits), so the plots convert back: `t = t̃ β` (s), `v = ṽ / β` (m/s). Energy
//! ratios `E/E₀` are dimensionless in either system. A dimensionless scene has no SI meaning:
//! `--units si` on it is an error.

use super::PlotError;
use crate::scene::{Scene, UnitScales};
use std::path::Path;

/// Unit system of the axes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Units {
    /// The simulation's computer units (labelled "computer units").
    #[default]
    Computer,
    /// SI (s, m/s, m, J); physical scenes only.
    Si,
}

/// The unit scales of a physical scene, if any (see [`Scene::units`]).
pub fn scene_scales(scene: &Scene) -> Option<UnitScales> {
    scene.units
}

/// Conversion factors and axis labels of one snapshot's plots.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxisUnits {
    /// The system.
    pub units: Units,
    /// Displayed time per computer time (β in s, or 1).
    pub time: f64,
    /// Displayed velocity per computer velocity (1/β in s⁻¹, or 1).
    pub velocity: f64,
}

impl AxisUnits {
    /// Computer units (factors 1).
    pub fn computer() -> Self {
        AxisUnits {
            units: Units::Computer,
            time: 1.0,
            velocity: 1.0,
        }
    }

    /// The units of `scene` (read from `file`) in `units`; SI needs a physical scene.
    pub fn of(scene: &Scene, units: Units, file: &Path) -> Result<Self, PlotError> {
        match units {
            Units::Computer => Ok(Self::computer()),
            Units::Si => match scene_scales(scene) {
                Some(s) if s.time > 0.0 && s.time.is_finite() => Ok(AxisUnits {
                    units,
                    time: s.time,
                    velocity: 1.0 / s.time,
                }),
                _ => Err(PlotError::Input(format!(
                    "{}: --units si: scene `{}` is dimensionless (computer units only); SI axes \
                     need a physical scene ([units] system = \"physical\")",
                    file.display(),
                    scene.name
                ))),
            },
        }
    }

    /// `time t (s)` or `time t (computer units)`.
    pub fn time_label(&self) -> String {
        format!("time t ({})", self.unit("s"))
    }

    /// `velocity v (m/s)` or `velocity v (computer units)`.
    pub fn velocity_label(&self) -> String {
        format!("velocity v ({})", self.unit("m/s"))
    }

    /// The SI unit `si`, or `computer units`.
    pub fn unit(&self, si: &str) -> String {
        match self.units {
            Units::Computer => "computer units".into(),
            Units::Si => si.into(),
        }
    }
}

/// Text overrides of a figure (`--title`, `--xlabel`, `--ylabel`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Labels {
    /// Figure title.
    pub title: Option<String>,
    /// x axis label.
    pub xlabel: Option<String>,
    /// y axis label.
    pub ylabel: Option<String>,
}

impl Labels {
    /// Replaces `title`, `x`, `y` by the overrides given.
    pub fn apply(&self, title: &mut String, x: &mut String, y: &mut String) {
        for (slot, o) in [(title, &self.title), (x, &self.xlabel), (y, &self.ylabel)] {
            if let Some(o) = o {
                *slot = o.clone();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scales_of_a_physical_scene() {
        let mut sc = crate::scene::preset("hertz_spheres_physical").unwrap();
        let s = scene_scales(&sc).expect("physical");
        assert!((s.time - 9.0572e-7).abs() < 1e-10, "{s:?}");
        assert_eq!(s.n0, 2.5);
        sc.units = None;
        assert!(scene_scales(&sc).is_none());
        let e = AxisUnits::of(&sc, Units::Si, Path::new("a.snap")).unwrap_err();
        assert!(e.to_string().starts_with("a.snap: --units si: "), "{e}");
    }
}
