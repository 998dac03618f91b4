//! Defects a review of scene files found (2026-11-29): a wall's material taken without the
//! range checks of the beads' (a negative Young's modulus made a plausible prefactor), and
//! per-bead material arrays and per-contact damping arrays that did not give the chain length
//! ("missing (and no array or file gives the chain length)"), as docs/scenes.md says the first
//! explicit array does.

use beadchain::scene::parse_str;
use std::path::Path;

const STEEL: &str = "[units]\nsystem = \"physical\"\nradius = 4e-3\nyoung = 2.26e11\n\
                     poisson = 0.3\ndensity = 7650.0\n";

fn parse(text: &str) -> Result<beadchain::scene::Scene, String> {
    parse_str(text, Path::new("."), "s.toml").map_err(|e| e.to_string())
}

#[test]
fn wall_material_is_checked_as_the_beads_is() {
    let wall = "[chain]\nbeads = 3\n[walls]\nleft = {}\n[run]\nuntil = 1.0\n";
    for (key, want) in [
        (
            "wall_young = -1e13",
            "[units].wall_young: must be a finite modulus > 0 (Pa), got",
        ),
        (
            "wall_young = 0.0",
            "[units].wall_young: must be a finite modulus > 0",
        ),
        (
            "wall_poisson = -3.0",
            "[units].wall_poisson: must be in (-1, 0.5], got -3",
        ),
        (
            "wall_poisson = 0.9",
            "[units].wall_poisson: must be in (-1, 0.5], got 0.9",
        ),
    ] {
        let e = parse(&format!("{STEEL}{key}\n{wall}")).expect_err(key);
        assert!(e.starts_with("s.toml: ") && e.contains(want), "{key}: {e}");
    }
    // in range: accepted
    parse(&format!(
        "{STEEL}wall_young = 2e11\nwall_poisson = 0.25\n{wall}"
    ))
    .expect("steel wall");
}

#[test]
fn material_and_damping_arrays_give_the_chain_length() {
    let young = STEEL.replace("young = 2.26e11", "young = [2.26e11, 2.26e11, 2.26e11]");
    let s = parse(&format!("{young}[run]\nuntil = 1.0\n")).expect("young array");
    assert_eq!(s.chain.len(), 3);
    let poisson = STEEL.replace("poisson = 0.3", "poisson = [0.3, 0.3, 0.3, 0.3]");
    let s = parse(&format!("{poisson}[run]\nuntil = 1.0\n")).expect("poisson array");
    assert_eq!(s.chain.len(), 4);
    // per contact: three dampings, four beads
    let s = parse(
        "[chain]\nlaw = \"viscoelastic\"\ndamping = [0.1, 0.2, 0.3]\n[initial]\nstriker = 1.0\n\
         [run]\nuntil = 1.0\n",
    )
    .expect("damping array");
    assert_eq!(s.chain.len(), 4);
}
