//! `beadchain scene show`: the resolved scene as TOML (parses back to the same scene, bit for
//! bit) and as CSV.

use beadchain::scene::{parse_str, preset, presets, show};
use std::path::Path;
use std::process::Command;

fn bits(xs: &[f64]) -> Vec<u64> {
    xs.iter().map(|x| x.to_bits()).collect()
}

/// Every preset (physical units, random builders, walls, fields and hard contacts among them)
/// shown as TOML parses back to the same chain, initial state and run settings.
#[test]
fn every_preset_round_trips_through_scene_show_toml() {
    for p in presets() {
        let s = preset(p.name).expect("preset");
        let text = show::to_toml(&s);
        let back = parse_str(&text, Path::new("."), "shown.toml")
            .unwrap_or_else(|e| panic!("{}: shown TOML does not parse: {e}\n{text}", p.name));
        let (a, b) = (&s.chain, &back.chain);
        assert_eq!(bits(&a.mass), bits(&b.mass), "{}: mass", p.name);
        assert_eq!(bits(&a.exponent), bits(&b.exponent), "{}: exponent", p.name);
        assert_eq!(
            bits(&a.prefactor),
            bits(&b.prefactor),
            "{}: prefactor",
            p.name
        );
        assert_eq!(
            a.precompression.as_deref().map(bits),
            b.precompression.as_deref().map(bits),
            "{}: precompression",
            p.name
        );
        assert_eq!(a.field.as_deref().map(bits), b.field.as_deref().map(bits));
        assert_eq!(a.left_wall, b.left_wall, "{}: left wall", p.name);
        assert_eq!(a.right_wall, b.right_wall, "{}: right wall", p.name);
        assert_eq!(a.hard, b.hard, "{}: hard contacts", p.name);
        assert_eq!(bits(&s.u0), bits(&back.u0), "{}: u0", p.name);
        assert_eq!(bits(&s.v0), bits(&back.v0), "{}: v0", p.name);
        assert_eq!(s.run, back.run, "{}: run settings", p.name);
    }
}

/// The CSV has a header and one row per bead; contact columns are empty on the last bead.
#[test]
fn scene_show_csv_has_one_row_per_bead() {
    let exe = env!("CARGO_BIN_EXE_beadchain");
    let o = Command::new(exe)
        .args(["scene", "show", "interface_3.0_2.5", "--format", "csv"])
        .output()
        .expect("run");
    assert_eq!(o.status.code(), Some(0));
    let text = String::from_utf8(o.stdout).expect("utf-8");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        "bead,mass,u0,v0,force,exponent,prefactor,precompression,restitution"
    );
    assert_eq!(lines.len(), 151, "header + 150 beads");
    // contact 50 is the first of the n2 = 2.5 side (preset docs)
    let row: Vec<&str> = lines[51].split(',').collect();
    assert_eq!(row[0], "50");
    assert_eq!(row[5], "2.5");
    assert!(lines[150].ends_with(",,,,"), "{}", lines[150]);
    let bad = Command::new(exe)
        .args(["scene", "show", "no_such_scene"])
        .output()
        .expect("run");
    assert_ne!(bad.status.code(), Some(0));
    assert_eq!(
        String::from_utf8_lossy(&bad.stderr).trim().lines().count(),
        1
    );
}
