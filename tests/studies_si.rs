//! The rest of issue 35's scene keys: SI twins of the study keys in physical scenes
//! (`[initial] solitary.energy_si`, `[chain] precompression_force_si`, `[walls] force_si`),
//! converted exactly as the units module's own scales say (`E β²/m0`, `W β²/m0`, paper eq. 11),
//! their one-line errors, and the gap warning of `[initial] equilibrium = true` (from the parser
//! and on `beadchain run`'s standard error).

mod common;

use beadchain::scene::{self, parse::parse_full, parse_str, Scene};
use common::{assert_ok, bc};
use std::path::Path;

/// Table-1 steel beads (R = 4 mm, Y = 226 GPa, σ = 0.3, ρ = 7650 kg/m³).
const STEEL: &str = "[units]\nsystem = \"physical\"\nradius = 4.0e-3\nyoung = 2.26e11\npoisson = 0.3\ndensity = 7650.0\n";

/// Relative tolerance of the SI conversions (the 1e-12).
const TOL: f64 = 1e-12;

fn parse(text: &str) -> Scene {
    parse_str(text, Path::new("."), "si.toml").unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn rel(x: f64, want: f64) -> f64 {
    (x - want).abs() / want.abs()
}

/// Force `n a δ^{n−1}` of every contact at the scene's initial state.
fn contact_forces(s: &Scene) -> Vec<f64> {
    let c = &s.chain;
    (0..c.len() - 1)
        .map(|k| {
            let d = c.overlap(k, s.u0[k], s.u0[k + 1]);
            c.exponent[k] * c.prefactor[k] * d.powf(c.exponent[k] - 1.0)
        })
        .collect()
}

/// `energy_si = E` (J) places the wave whose energy is `E β²/m0` computer units, computed here
/// from the scene's scales (relative 1e-12), i.e. `E` joules back in SI; and the same scene as
/// `energy = E β²/m0` written out, bit for bit.
#[test]
fn solitary_energy_si_is_joules() {
    let e_si = 1.0e-5; // about the kinetic energy of the paper's 0.11 m/s striker
    let body = |amount: &str| {
        format!("{STEEL}[chain]\nbeads = 60\nexponent = 3.0\n[initial]\nsolitary = {{ at = 30, {amount} }}\n[run]\nuntil = 1.0\n")
    };
    let s = parse(&body(&format!("energy_si = {e_si:?}")));
    let sc = s.units.expect("physical scene");
    let want = e_si * sc.time * sc.time / sc.mass;
    let e = s.chain.energy(&s.u0, &s.v0);
    assert!(rel(e, want) <= TOL, "energy {e} vs {want} (rel 1e-12)");
    let joules = e * sc.mass / (sc.time * sc.time);
    assert!(rel(joules, e_si) <= TOL, "{joules} J vs {e_si} J");
    let plain = parse(&body(&format!("energy = {want:?}")));
    assert_eq!((&plain.u0, &plain.v0), (&s.u0, &s.v0));
    // The wave differs from a wave of 2 E: the key is read.
    let double = parse(&body(&format!("energy_si = {:?}", 2.0 * e_si)));
    assert!(double.v0[30] > 1.4 * s.v0[30]);
}

/// `precompression_force_si = F` (N): every contact carries `F β²/m0` in computer units
/// (relative 1e-12 from the scales here), `F` newtons back in SI, and the soft walls too; the
/// chain is the one `precompression_force = F β²/m0` gives, bit for bit.
#[test]
fn precompression_force_si_is_newtons() {
    let f_si = 5.0;
    let body = |key: &str| {
        format!("{STEEL}[chain]\nbeads = 10\nexponent = 2.5\n{key}\n[walls]\nleft = {{}}\nright = {{}}\n[initial]\nequilibrium = true\n[run]\nuntil = 1.0\n")
    };
    let s = parse(&body(&format!("precompression_force_si = {f_si:?}")));
    let sc = s.units.expect("physical scene");
    let want = f_si * sc.time * sc.time / sc.mass;
    for (k, f) in contact_forces(&s).into_iter().enumerate() {
        assert!(
            rel(f, want) <= TOL,
            "contact {k}: {f} vs {want} (rel 1e-12)"
        );
        let newtons = f * sc.mass / (sc.time * sc.time);
        assert!(rel(newtons, f_si) <= TOL, "contact {k}: {newtons} N");
    }
    for w in [&s.chain.left_wall, &s.chain.right_wall] {
        let w = w.as_ref().expect("wall");
        let f = w.exponent * w.prefactor * w.precompression.powf(w.exponent - 1.0);
        assert!(rel(f, want) <= TOL, "wall: {f} vs {want}");
    }
    let plain = parse(&body(&format!("precompression_force = {want:?}")));
    assert_eq!(plain.chain, s.chain);
    assert_eq!(plain.u0, s.u0);
}

/// `[walls] force_si = F` (N) with `equilibrium = true`: every contact and both walls carry
/// `F β²/m0` at rest (relative 1e-12), as with `force = F β²/m0`, bit for bit.
#[test]
fn wall_force_si_is_newtons() {
    let f_si = 3.0;
    let body = |key: &str| {
        format!("{STEEL}[chain]\nbeads = 8\nexponent = 2.5\n[walls]\nleft = {{}}\nright = {{}}\n{key}\n[initial]\nequilibrium = true\n[run]\nuntil = 1.0\n")
    };
    let s = parse(&body(&format!("force_si = {f_si:?}")));
    let sc = s.units.expect("physical scene");
    let want = f_si * sc.time * sc.time / sc.mass;
    for (k, f) in contact_forces(&s).into_iter().enumerate() {
        assert!(
            rel(f, want) <= TOL,
            "contact {k}: {f} vs {want} (rel 1e-12)"
        );
    }
    let n = s.chain.len();
    let (wl, wr) = (
        s.chain.left_wall.as_ref().unwrap(),
        s.chain.right_wall.as_ref().unwrap(),
    );
    for (w, d) in [
        (wl, wl.precompression - s.u0[0]),
        (wr, wr.precompression + s.u0[n - 1]),
    ] {
        let f = w.exponent * w.prefactor * d.powf(w.exponent - 1.0);
        assert!(rel(f, want) <= TOL, "wall: {f} vs {want} (rel 1e-12)");
    }
    let plain = parse(&body(&format!("force = {want:?}")));
    assert_eq!(plain.chain, s.chain);
    assert_eq!(plain.u0, s.u0);
}

/// Wrong uses of the SI keys are one-line errors naming the file and the key.
#[test]
fn si_key_errors_name_the_key() {
    let walls = "[walls]\nleft = {}\nright = {}\n";
    let eq = "[initial]\nequilibrium = true\n";
    let cases: Vec<(String, &str)> = vec![
        (format!("[chain]\nbeads = 4\nprecompression_force_si = 1.0\n{walls}"),
         "[chain].precompression_force_si: only allowed in a physical scene"),
        (format!("[chain]\nbeads = 4\n{walls}force_si = 1.0\n{eq}"),
         "[walls].force_si: only allowed in a physical scene"),
        ("[chain]\nbeads = 40\n[initial]\nsolitary = { at = 20, energy_si = 1.0 }".to_string(),
         "[initial].solitary.energy_si: only allowed in a physical scene"),
        (format!("{STEEL}[chain]\nbeads = 4\nprecompression_force = 1.0\nprecompression_force_si = 1.0\n"),
         "[chain].precompression_force_si: give either `precompression_force` or `precompression_force_si`, not both"),
        (format!("{STEEL}[chain]\nbeads = 4\nprecompression = 1e-6\nprecompression_force_si = 1.0\n"),
         "[chain].precompression_force_si: give either `precompression` or `precompression_force_si`, not both"),
        (format!("{STEEL}[chain]\nbeads = 4\nprecompression_force_si = 0.0\n"),
         "[chain].precompression_force_si: must be > 0, got 0"),
        (format!("{STEEL}[chain]\nbeads = 4\n{walls}force = 1.0\nforce_si = 1.0\n{eq}"),
         "[walls].force_si: give either `force` or `force_si`, not both"),
        (format!("{STEEL}[chain]\nbeads = 4\n{walls}force_si = -2.0\n{eq}"),
         "[walls].force_si: must be >= 0 (a compressive force), got -2"),
        (format!("{STEEL}[chain]\nbeads = 4\n{walls}force_si = 2.0\n"),
         "[walls].force_si: needs `[initial] equilibrium = true`"),
        (format!("{STEEL}[chain]\nbeads = 4\n[walls]\nleft = {{}}\nforce_si = 2.0\n{eq}"),
         "[walls].force_si: needs both walls"),
        (format!("{STEEL}[chain]\nbeads = 4\n{walls}force_si = 2.0\nright = {{ precompression = 0.0 }}\n{eq}").replace("right = {}\n", ""),
         "[walls].right.precompression: is set by `[walls].force_si`"),
        (format!("{STEEL}[chain]\nbeads = 60\nexponent = 3.0\n[initial]\nsolitary = {{ at = 30, energy = 1.0, energy_si = 1.0 }}"),
         "[initial].solitary.energy_si: give only one of energy, energy_si"),
        (format!("{STEEL}[chain]\nbeads = 60\nexponent = 3.0\n[initial]\nsolitary = {{ at = 30, energy_si = -1.0 }}"),
         "[initial].solitary.energy_si: must be > 0, got -1"),
        ("[chain]\nbeads = 60\n[initial]\nsolitary = { at = 30, velocity = -1.0 }".to_string(),
         "[initial].solitary.velocity: must be > 0, got -1"),
    ];
    for (body, want) in cases {
        let text = format!("{body}\n[run]\nuntil = 1.0\n");
        let e = match parse_str(&text, Path::new("."), "bad.toml") {
            Ok(_) => panic!("accepted:\n{text}"),
            Err(e) => e.to_string(),
        };
        assert!(e.starts_with("bad.toml: "), "{e}");
        assert!(e.contains(want), "expected {want:?} in: {e}");
        assert!(!e.contains('\n'), "one line: {e}");
    }
}

/// Six beads between two walls, the left three pulled left and the right three pulled right:
/// contact 2 (beads 2-3) carries no force at rest.
const SPLIT: &str = "[scene]\nname = \"split\"\n[chain]\nbeads = 6\n[field]\nforce = [-1.0, -1.0, -1.0, 1.0, 1.0, 1.0]\n\
                     [walls]\nleft = {}\nright = {}\n[initial]\nequilibrium = true\n[run]\nuntil = 10.0\nevery = 1.0\n";

fn warnings(text: &str) -> Vec<String> {
    parse_full(text, Path::new("."), "w.toml")
        .unwrap_or_else(|e| panic!("{e}"))
        .warnings
}

/// The balance's gaps are one warning line naming the contacts and beads (and walls) without
/// force; a chain where every contact is loaded gets none.
#[test]
fn equilibrium_gaps_are_a_warning() {
    let gap = "split: [initial].equilibrium: gaps at rest (no force: the beads are apart or just touching)";
    assert_eq!(warnings(SPLIT), [format!("{gap}: contact 2 (beads 2-3)")]);
    // A free chain without field: every contact unloaded, the first 6 named.
    let free = "[scene]\nname = \"split\"\n[chain]\nbeads = 30\n[initial]\nequilibrium = true\nstriker = 1.0\n[run]\nuntil = 1.0\n";
    assert_eq!(
        warnings(free),
        [format!("{gap}: contacts 0 (beads 0-1), 1 (beads 1-2), 2 (beads 2-3), 3 (beads 3-4), 4 (beads 4-5), 5 (beads 5-6) and 23 more (29 of 29)")]
    );
    // A column on a wall under gravity, below a ceiling it does not reach: loaded contacts, the
    // ceiling apart.
    let column = "[scene]\nname = \"split\"\n[chain]\nbeads = 5\n[field]\ngravity = 1.0\n[walls]\nleft = {}\nright = { precompression = -1.0 }\n[initial]\nequilibrium = true\n[run]\nuntil = 1.0\n";
    assert_eq!(
        warnings(column),
        [format!("{gap}: the right wall (bead 4)")]
    );
    // Loaded everywhere: no warning. Without `equilibrium` the gaps are not computed.
    let loaded = column.replace("right = { precompression = -1.0 }\n", "");
    assert!(warnings(&loaded).is_empty(), "{:?}", warnings(&loaded));
    assert!(warnings(&SPLIT.replace("equilibrium = true", "striker = 1.0")).is_empty());
    // No preset has a gap warning.
    for p in scene::presets() {
        let w = scene::presets::preset_full(p.name)
            .expect("preset")
            .warnings;
        assert!(w.is_empty(), "{}: {w:?}", p.name);
    }
}

/// `beadchain run` prints the gap warning on standard error (once, one line) and runs.
#[test]
fn run_prints_the_gap_warning() {
    let d = tempfile::tempdir().expect("tempdir");
    std::fs::write(d.path().join("split.toml"), SPLIT).expect("write");
    let o = bc(d.path(), &["run", "split.toml", "-q", "--out", "s.snap"]);
    assert_ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("gaps at rest")).collect();
    assert_eq!(
        lines,
        ["beadchain: warning: split: [initial].equilibrium: gaps at rest (no force: the beads are apart or just touching): contact 2 (beads 2-3)"],
        "stderr: {err}"
    );
    assert!(d.path().join("s.snap").exists());
    let o = bc(
        d.path(),
        &["run", "gravity_column_at_rest", "-q", "--out", "g.snap"],
    );
    assert_ok(&o);
    assert!(
        !String::from_utf8_lossy(&o.stderr).contains("gaps at rest"),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Solitary waves on a precompressed support are refused (docs/studies.md: no universal
/// profile for `Δ > 0`), whichever key sets the precompression, with the contact and its `Δ`.
#[test]
fn precompressed_solitary_waves_are_refused() {
    let wave = "[initial]\nsolitary = { at = 50, velocity = 1.0 }\n[run]\nuntil = 1.0\n";
    for (chain, want) in [
        ("[chain]\nbeads = 100\nprecompression_force = 0.1\n", "contact 50 has precompression 0.11696070952851466: only the sonic vacuum (precompression 0) is supported"),
        ("[chain]\nbeads = 100\nprecompression = { base = 0.0, segments = [{ from = 52, to = 52, value = 1e-3 }] }\n", "contact 52 has precompression 0.001: only the sonic vacuum"),
    ] {
        let text = format!("{chain}{wave}");
        let e = match parse_str(&text, Path::new("."), "pre.toml") {
            Ok(_) => panic!("accepted:\n{text}"),
            Err(e) => e.to_string(),
        };
        assert!(e.starts_with("pre.toml: [initial].solitary.at: "), "{e}");
        assert!(e.contains(want), "expected {want:?} in: {e}");
        assert!(!e.contains('\n'), "one line: {e}");
    }
    let steel = format!("{STEEL}[chain]\nbeads = 100\nexponent = 3.0\nprecompression_force_si = 1.0\n[initial]\nsolitary = {{ at = 50, velocity_si = 0.1 }}\n[run]\nuntil = 1.0\n");
    let e = parse_str(&steel, Path::new("."), "pre.toml").expect_err("precompressed");
    assert!(e.to_string().contains("only the sonic vacuum"), "{e}");
}
