//! `scene show` / `to_toml` round trip (issue 32, item 3): every key a scene can hold — the
//! contact law and its per-contact damping (given directly, from a restitution, or from the
//! material viscosities), wall damping, `[hard]`, `[output]`, the unit scales of a physical
//! scene and the run settings — comes back from `parse(to_toml(scene))` as the same resolved
//! `Scene` (`==`), and both runs write the same frames, bit for bit.

mod common;

use beadchain::engine::RunConfig;
use beadchain::integrate::DEFAULT_RTOL;
use beadchain::scene::{parse_str, preset, presets, show, Scene};
use common::run;
use std::fmt::Write as _;
use std::path::Path;

/// Parses the shown scene (a failure panics with the text).
fn reparse(s: &Scene, what: &str) -> Scene {
    let text = show::to_toml(s);
    parse_str(&text, Path::new("."), "shown.toml")
        .unwrap_or_else(|e| panic!("{what}: shown TOML does not parse: {e}\n{text}"))
}

/// Runs `a` and `b` with the same configuration (`a`'s settings, shortened to `until`) and
/// asserts identical frames, dissipated energies and event logs (bit for bit: `{:?}` of an
/// f64 is its shortest round-trip form).
fn same_run(a: &Scene, b: &Scene, until: f64, what: &str) {
    let mut cfg = RunConfig::from_scene(a);
    cfg.until = until;
    cfg.every = Some(until / 4.0);
    cfg.max_steps = Some(2_000_000);
    if cfg.rtol < DEFAULT_RTOL {
        cfg.rtol = DEFAULT_RTOL;
    }
    let (oa, ra) = run(a, &cfg);
    let (ob, rb) = run(b, &cfg);
    assert_eq!(ra.t.len(), 5, "{what}: frames");
    assert_eq!(format!("{:?}", ra.t), format!("{:?}", rb.t), "{what}: t");
    assert_eq!(format!("{:?}", ra.u), format!("{:?}", rb.u), "{what}: u");
    assert_eq!(format!("{:?}", ra.v), format!("{:?}", rb.v), "{what}: v");
    assert_eq!(
        format!("{:?}", ra.dissipated),
        format!("{:?}", rb.dissipated),
        "{what}: dissipated"
    );
    assert_eq!(
        format!("{:?}", ra.events),
        format!("{:?}", rb.events),
        "{what}: events"
    );
    assert_eq!(oa.energy_final.to_bits(), ob.energy_final.to_bits());
}

/// The defect: `scene show damped_striker` wrote no `law` and no `damping`, so the shown scene
/// ran conservatively (energy 0.5 → 0.5 instead of 0.5 → 0.027).
#[test]
fn scene_show_keeps_the_contact_law() {
    let s = preset("damped_striker").expect("preset");
    let d = s.chain.damping.as_ref().expect("damped_striker is damped");
    let back = reparse(&s, "damped_striker");
    assert_eq!(back.chain.damping.as_ref(), Some(d), "law and coefficients");
    let mut cfg = RunConfig::from_scene(&back);
    cfg.until = 20.0;
    let (out, rec) = run(&back, &cfg);
    let lost = *rec
        .dissipated
        .last()
        .expect("a damped run records its losses");
    // 20 time units of the pulse cross ~20 viscoelastic contacts (e = 0.9): well over 1 % lost.
    assert!(lost > 0.005 * out.energy_initial, "dissipated {lost}");
    same_run(&s, &back, 20.0, "damped_striker");
}

/// A physical scene shown in computer units keeps its SI scales (`[units] system =
/// "computer"`) and its description without a second note on the scales.
#[test]
fn scene_show_keeps_the_unit_scales_of_a_physical_scene() {
    let s = preset("hertz_spheres_physical").expect("preset");
    let back = reparse(&s, "hertz_spheres_physical");
    assert!(s.units.is_some());
    assert_eq!(back.units, s.units);
    assert_eq!(back.description, s.description);
    assert_eq!(back.description.matches("[physical units").count(), 1);
}

/// Every preset: `parse(to_toml(s)) == s`, and the same frames for a fiftieth of its run.
#[test]
fn every_preset_round_trips_to_an_equal_scene_and_run() {
    for p in presets() {
        let s = preset(p.name).expect("preset");
        let back = reparse(&s, p.name);
        assert!(back == s, "{}: resolved scenes differ", p.name);
        same_run(&s, &back, s.run.until / 50.0, p.name);
    }
}

/// A small seeded generator (SplitMix64), so the generated scenes are the same on every host.
struct Gen(u64);

impl Gen {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: u64) -> u64 {
        self.next() % n
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn coin(&mut self) -> bool {
        self.below(2) == 0
    }
}

/// `[chain]` of a dimensionless generated scene: masses, exponents ≥ 2, prefactors,
/// precompression (none with hard contacts: they may not start overlapping), law and damping.
fn gen_chain(g: &mut Gen, o: &mut String, nb: u64, hard: bool) -> Option<&'static str> {
    let _ = writeln!(o, "[chain]\nbeads = {nb}");
    let _ = writeln!(o, "mass = {{ random = {{ mean = 1.0, eps = 0.3 }} }}");
    let _ = match g.below(3) {
        0 => writeln!(o, "exponent = {}", g.uniform(2.0, 3.5)),
        1 => writeln!(o, "exponent = {{ alternate = [2.5, 3.0] }}"),
        _ => writeln!(o, "exponent = {{ random = {{ mean = 2.7, eps = 0.4 }} }}"),
    };
    let _ = writeln!(o, "prefactor = {}", g.uniform(0.5, 2.0));
    if !hard && g.coin() {
        let _ = writeln!(
            o,
            "precompression = {{ random = {{ mean = 0.0, eps = 0.05 }} }}"
        );
    }
    let law = match g.below(3) {
        0 => return None,
        1 => "viscoelastic",
        _ => "linear_dashpot",
    };
    let _ = writeln!(o, "law = \"{law}\"");
    let _ = match g.below(3) {
        0 => writeln!(o, "damping = {}", g.uniform(0.0, 0.1)),
        1 => writeln!(o, "damping = {{ random = {{ mean = 0.05, eps = 0.05 }} }}"),
        _ => writeln!(
            o,
            "restitution = {}\nimpact_speed = 1.0",
            g.uniform(0.6, 1.0)
        ),
    };
    Some(law)
}

/// One generated dimensionless scene (module docs of the test).
fn gen_scene(seed: u64) -> String {
    let mut g = Gen(seed);
    let mut o = String::new();
    let nb = 3 + g.below(10);
    let hard = g.below(3) == 0;
    let _ = writeln!(o, "[scene]\nname = \"gen{seed}\"\nseed = {}", g.below(1000));
    let law = gen_chain(&mut g, &mut o, nb, hard);
    let _ = writeln!(o, "[initial]\nstriker = {}", g.uniform(0.5, 1.5));
    if g.coin() {
        let _ = writeln!(o, "striker_right = {}", g.uniform(0.5, 1.5));
    }
    match g.below(3) {
        0 => {}
        1 => {
            let _ = writeln!(o, "[field]\ngravity = {}", g.uniform(0.1, 1.0));
        }
        _ => {
            let _ = writeln!(
                o,
                "[field]\nforce = {{ random = {{ mean = 0.0, eps = 0.2 }} }}"
            );
        }
    }
    let mut hybrid = hard;
    let _ = writeln!(o, "[walls]");
    for side in ["left", "right"] {
        match g.below(4) {
            0 => {}
            1 => {
                hybrid = true;
                let _ = writeln!(
                    o,
                    "{side} = {{ hard = true, restitution = 0.8, precompression = -0.1 }}"
                );
            }
            2 if law.is_some() => {
                let d = g.uniform(0.0, 0.2);
                let _ = writeln!(o, "{side} = {{ exponent = 2.5, damping = {d} }}");
            }
            _ => {
                let _ = writeln!(o, "{side} = {{ prefactor = 2.0, precompression = -0.05 }}");
            }
        }
    }
    if hard {
        let _ = writeln!(
            o,
            "[hard]\ncontacts = [0, {}]\nrestitution = [0.9, 0.7]",
            nb - 2
        );
    }
    gen_run(&mut g, &mut o, nb, hybrid);
    o
}

/// `[run]` and `[output]` of a generated scene.
fn gen_run(g: &mut Gen, o: &mut String, nb: u64, hybrid: bool) {
    let _ = writeln!(o, "[run]\nuntil = {}\nevery = 0.5", g.uniform(2.0, 6.0));
    let _ = writeln!(o, "rtol = {:e}", [1e-6, 1e-7, 1e-8][g.below(3) as usize]);
    if g.coin() {
        let _ = writeln!(o, "atol = 1e-11");
    }
    let _ = writeln!(
        o,
        "method = \"{}\"",
        ["auto", "dop853", "radau5"][g.below(3) as usize]
    );
    let engine = if hybrid || g.coin() {
        "hybrid"
    } else {
        "dense"
    };
    let _ = writeln!(o, "engine = \"{engine}\"");
    if g.coin() {
        let _ = writeln!(
            o,
            "[output]\nbeads = \"0:{nb}:2\"\nfields = \"v\"\nframes_max = 1000"
        );
    }
}

/// A generated physical scene: material keys, `_si` keys and material viscosities or
/// `damping_si`.
fn gen_physical(seed: u64) -> String {
    let mut g = Gen(seed);
    let nb = 3 + g.below(8);
    let mut o = format!("[scene]\nname = \"phys{seed}\"\ndescription = \"generated\"\n");
    let _ = writeln!(
        o,
        "[units]\nsystem = \"physical\"\nradius = {{ random = {{ mean = 4e-3, eps = 1e-3 }} }}"
    );
    let _ = writeln!(o, "young = 2.26e11\npoisson = 0.3\ndensity = 7650.0");
    let viscous = g.coin();
    if viscous {
        let _ = writeln!(o, "viscosity_shear = 1e3\nviscosity_bulk = 2e3");
    }
    let _ = writeln!(
        o,
        "[chain]\nbeads = {nb}\nexponent = {}",
        g.uniform(2.5, 3.0)
    );
    if viscous {
        let _ = writeln!(o, "law = \"viscoelastic\"");
    } else if g.coin() {
        let _ = writeln!(
            o,
            "law = \"linear_dashpot\"\ndamping_si = {}",
            g.uniform(0.0, 1.0)
        );
    }
    let _ = writeln!(o, "[initial]\nstriker_si = {}", g.uniform(0.05, 0.2));
    if g.coin() {
        let _ = writeln!(o, "[field]\ngravity_si = 9.81");
    }
    if g.coin() {
        let _ = writeln!(o, "[walls]\nright = {{ precompression = -1e-6 }}");
    }
    let _ = writeln!(o, "[run]\nuntil_si = 2e-5\nevery_si = 5e-6");
    o
}

/// Seeded scenes with random laws, damping, walls, hard contacts, output selection, fields and
/// precompression, and physical ones: each shown scene parses to the scene it was shown from
/// and runs the same frames.
#[test]
fn generated_scenes_round_trip_to_an_equal_scene_and_run() {
    let texts = (0..60).map(gen_scene).chain((100..112).map(gen_physical));
    let mut damped = 0;
    for text in texts {
        let s = parse_str(&text, Path::new("."), "gen.toml")
            .unwrap_or_else(|e| panic!("generated scene does not parse: {e}\n{text}"));
        damped += usize::from(s.chain.damping.is_some());
        let back = reparse(&s, &s.name);
        assert!(back == s, "{}: resolved scenes differ\n{text}", s.name);
        same_run(&s, &back, s.run.until, &s.name);
    }
    assert!(damped >= 20, "only {damped} damped scenes generated");
}

/// `[units] system = "computer"` on bad input: a missing or non-positive scale, a material or
/// `_si` key, and `time_unit` in a physical scene are one-line errors naming the key.
#[test]
fn computer_units_system_refuses_missing_scales_and_physical_keys() {
    let base = "[chain]\nbeads = 3\n[initial]\nstriker = 1.0\n[run]\nuntil = 1.0\n[units]\nsystem = \"computer\"\n";
    let err = |extra: &str| {
        let text = format!("{base}{extra}");
        match parse_str(&text, Path::new("."), "c.toml") {
            Ok(_) => panic!("should fail:\n{text}"),
            Err(e) => e.to_string(),
        }
    };
    let m = err("m0 = 1.0\nmu = 1.0\nn0 = 2.5\n");
    assert!(m.starts_with("c.toml: [units].time_unit: required"), "{m}");
    let m = err("m0 = 1.0\ntime_unit = -1.0\nmu = 1.0\nn0 = 2.5\n");
    assert!(
        m.starts_with("c.toml: [units].time_unit: must be > 0, got -1"),
        "{m}"
    );
    let m = err("m0 = 1.0\ntime_unit = 1.0\nmu = 1.0\nn0 = 2.5\nyoung = 1e9\n");
    assert!(
        m.starts_with("c.toml: [units].young: only allowed in a physical scene"),
        "{m}"
    );
    let m = err("m0 = 1.0\ntime_unit = 1.0\nmu = 1.0\nn0 = 2.5\n[field]\ngravity_si = 9.81\n");
    assert!(
        m.starts_with("c.toml: [field].gravity_si: only allowed in a physical scene"),
        "{m}"
    );
    let phys = "[chain]\nbeads = 3\n[units]\nsystem = \"physical\"\nradius = 4e-3\nyoung = 2e11\npoisson = 0.3\ndensity = 7650.0\ntime_unit = 1e-6\n[run]\nuntil = 1.0\n";
    let m = parse_str(phys, Path::new("."), "p.toml")
        .expect_err("time_unit in a physical scene")
        .to_string();
    assert!(
        m.starts_with("p.toml: [units].time_unit: only used with [units] system = \"computer\""),
        "{m}"
    );
}
