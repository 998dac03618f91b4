//! Named colour maps for `--cmap` (issue 14).
//!
//! Every map is a function of `s ∈ [0, 1]` ([`Cmap::at`]); signed data (space–time velocities)
//! use `s = (v/max|v| + 1)/2`, so a diverging map puts `v = 0` at its neutral centre and a
//! sequential one runs from the most negative to the most positive velocity. The maps:
//! `coolwarm` (Moreland's smooth cool–warm, [`super::colormap::diverging`], the space–time
//! default), `bwr` (straight lines in sRGB from blue through white to red), `viridis`
//! ([`super::colormap::sequential`], the parameter-map default) and `gray` (black to white).

use super::colormap::{diverging, sequential, NO_DATA};
use super::PlotError;
use plotters::style::RGBColor;

/// A colour map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cmap {
    /// Moreland's cool–warm (diverging).
    CoolWarm,
    /// Blue–white–red (diverging, linear in sRGB).
    Bwr,
    /// Viridis (sequential).
    Viridis,
    /// Black to white (sequential).
    Gray,
}

/// The names `--cmap` accepts, in [`Cmap`] order.
pub const CMAP_NAMES: &[&str] = &["coolwarm", "bwr", "viridis", "gray"];

impl Cmap {
    /// The map called `name` (case-insensitive); an unknown name is an error listing the maps.
    pub fn parse(name: &str) -> Result<Cmap, PlotError> {
        match name.to_ascii_lowercase().as_str() {
            "coolwarm" => Ok(Cmap::CoolWarm),
            "bwr" => Ok(Cmap::Bwr),
            "viridis" => Ok(Cmap::Viridis),
            "gray" | "grey" => Ok(Cmap::Gray),
            _ => Err(PlotError::Input(format!(
                "--cmap {name}: unknown colour map (available: {})",
                CMAP_NAMES.join(", ")
            ))),
        }
    }

    /// The colour at `s ∈ [0, 1]` (clamped); NaN gives [`NO_DATA`].
    pub fn at(&self, s: f64) -> RGBColor {
        if s.is_nan() {
            return NO_DATA;
        }
        let s = s.clamp(0.0, 1.0);
        let lerp = |a: f64, b: f64, f: f64| (a + f * (b - a)).round() as u8;
        match self {
            Cmap::CoolWarm => diverging(2.0 * s - 1.0),
            Cmap::Viridis => sequential(s),
            Cmap::Gray => {
                let g = lerp(0.0, 255.0, s);
                RGBColor(g, g, g)
            }
            Cmap::Bwr => {
                if s < 0.5 {
                    let f = s * 2.0;
                    RGBColor(lerp(0.0, 255.0, f), lerp(0.0, 255.0, f), 255)
                } else {
                    let f = (s - 0.5) * 2.0;
                    RGBColor(255, lerp(255.0, 0.0, f), lerp(255.0, 0.0, f))
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_ends() {
        for (k, n) in CMAP_NAMES.iter().enumerate() {
            let c = Cmap::parse(n).unwrap();
            assert_eq!(c, [Cmap::CoolWarm, Cmap::Bwr, Cmap::Viridis, Cmap::Gray][k]);
        }
        let e = Cmap::parse("jet").unwrap_err().to_string();
        assert!(
            e.contains("--cmap jet") && e.contains("viridis, gray"),
            "{e}"
        );
        assert_eq!(Cmap::Bwr.at(0.5), RGBColor(255, 255, 255));
        assert_eq!(Cmap::Gray.at(0.0), RGBColor(0, 0, 0));
        assert_eq!(Cmap::CoolWarm.at(1.0), diverging(1.0));
    }
}
