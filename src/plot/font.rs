//! Font for plot text, loaded at run time.
//!
//! `plotters` is built with its `ab_glyph` renderer (no system font discovery, no fontconfig):
//! the TrueType file is read from `$BEADCHAIN_FONT` or the first of [`FONT_CANDIDATES`] that
//! exists (DejaVu Sans from Debian's `fonts-dejavu-core`) and registered once per process under
//! [`FAMILY`]. Without one, plots are drawn without any text (lines, cells and markers only).

use plotters::style::FontStyle;
use std::sync::OnceLock;

/// Font files tried in order (after `$BEADCHAIN_FONT`).
pub const FONT_CANDIDATES: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/Library/Fonts/Arial.ttf",
    "C:\\Windows\\Fonts\\arial.ttf",
];

/// Font family name registered with plotters.
pub const FAMILY: &str = "sans-serif";

/// Registers a font once per process; true when text can be drawn.
pub fn font_available() -> bool {
    static OK: OnceLock<bool> = OnceLock::new();
    *OK.get_or_init(|| {
        let env = std::env::var("BEADCHAIN_FONT").ok();
        let paths = env
            .iter()
            .map(String::as_str)
            .chain(FONT_CANDIDATES.iter().copied());
        for p in paths {
            if let Ok(bytes) = std::fs::read(p) {
                // plotters keeps fonts for the process lifetime: leak the bytes once.
                let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                if plotters::style::register_font(FAMILY, FontStyle::Normal, bytes).is_ok() {
                    return true;
                }
            }
        }
        false
    })
}
