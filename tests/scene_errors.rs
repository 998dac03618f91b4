//! Scene files through the library API: one test per bad-input class (each checks the one-line
//! message names the file and key/index).

use beadchain::scene::{load, parse_str, preset, presets, validate, SceneError};
use std::path::Path;

mod scene_support;
use scene_support::*;

#[test]
fn malformed_toml_names_file_line_and_column() {
    let m = err("[chain]\nbeads = 10\nmass = [1.0, 2.0\n[run]\nuntil = 1\n");
    assert_contains(&m, &["t.toml:", "malformed TOML"]);
    assert!(
        m.starts_with("t.toml:3:") || m.starts_with("t.toml:4:"),
        "{m}"
    );
    let m = err("[chain]\nbeads = = 3\n");
    assert_contains(&m, &["t.toml:2:", "malformed TOML"]);
}

#[test]
fn unknown_keys_and_tables_are_named() {
    let m = err(&format!("[chain]\nbeads = 10\nmas = 1.0\n{RUN}"));
    assert_contains(&m, &["t.toml", "[chain].mas", "unknown key", "mass"]);
    let m = err(&format!("[chian]\nbeads = 10\n{RUN}"));
    assert_contains(&m, &["t.toml", "[chian]", "unknown"]);
    let m = err(&format!(
        "[chain]\nbeads = 10\nexponent = {{ base = 3.0, segmnts = [] }}\n{RUN}"
    ));
    assert_contains(&m, &["[chain].exponent.segmnts", "unknown key"]);
    let m = err(&format!(
        "[chain]\nbeads = 10\n[walls]\nleft = {{ exponnent = 2 }}\n{RUN}"
    ));
    assert_contains(&m, &["[walls].left.exponnent"]);
    let m = err(&format!(
        "[chain]\nbeads = 10\n[initial]\nstriker_si = 1.0\n{RUN}"
    ));
    assert_contains(&m, &["[initial].striker_si", "physical"]);
}

#[test]
fn wrong_array_length_names_key_and_counts() {
    let m = err(&format!("[chain]\nbeads = 4\nmass = [1, 1, 1]\n{RUN}"));
    assert_contains(
        &m,
        &["t.toml: [chain].mass: expected 4 values (one per bead), got 3"],
    );
    let m = err(&format!(
        "[chain]\nbeads = 4\nexponent = [3, 3, 3, 3]\n{RUN}"
    ));
    assert_contains(
        &m,
        &[
            "[chain].exponent",
            "expected 3 values (one per contact), got 4",
        ],
    );
    let m = err(&format!(
        "[chain]\nbeads = 4\nexponent = {{ base = 3.0, segments = [{{ from = 2, to = 5, value = 2.5 }}] }}\n{RUN}"
    ));
    assert_contains(&m, &["[chain].exponent.segments[0]", "0..=2"]);
}

#[test]
fn missing_csv_names_the_csv_and_key() {
    let dir = tempfile::tempdir().expect("tempdir");
    let e = parse_str(
        &format!("[chain]\nbeads = 3\nmass = {{ file = \"nope.csv\" }}\n{RUN}"),
        dir.path(),
        "s.toml",
    )
    .expect_err("missing csv");
    assert!(matches!(e, SceneError::CsvIo { .. }), "{e:?}");
    assert_contains(&e.to_string(), &["s.toml", "[chain].mass", "nope.csv"]);
}

#[test]
fn non_number_in_csv_names_its_line() {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("v.csv"), "0.0\n1.5\nabc\n2.0\n").expect("write");
    let e = parse_str(
        &format!("[chain]\nbeads = 4\n[initial]\nvelocity = {{ file = \"v.csv\" }}\n{RUN}"),
        dir.path(),
        "s.toml",
    )
    .expect_err("bad csv");
    let m = e.to_string();
    assert_contains(&m, &["s.toml", "[initial].velocity", "v.csv:3:", "abc"]);
    std::fs::write(dir.path().join("w.csv"), "1.0\nNaN\n").expect("write");
    let e = parse_str(
        &format!("[chain]\nmass = {{ file = \"w.csv\" }}\n{RUN}"),
        dir.path(),
        "s.toml",
    )
    .expect_err("nan csv");
    assert_contains(&e.to_string(), &["w.csv:2:", "finite"]);
}

#[test]
fn nan_and_inf_are_rejected_with_their_key() {
    let m = err(&format!("[chain]\nbeads = 3\nprefactor = nan\n{RUN}"));
    assert_contains(&m, &["t.toml: [chain].prefactor", "finite"]);
    let m = err(&format!(
        "[chain]\nbeads = 3\nmass = [1.0, inf, 1.0]\n{RUN}"
    ));
    assert_contains(&m, &["[chain].mass[1]", "finite"]);
    let m = err("[chain]\nbeads = 3\n[run]\nuntil = inf\n");
    assert_contains(&m, &["[run].until", "finite"]);
    // A resolved scene with a NaN (built in code) fails validate() with the index.
    let mut s = preset("striker").expect("striker");
    s.v0[7] = f64::NAN;
    let m = validate(&s).expect_err("nan").to_string();
    assert_contains(
        &m,
        &["striker: [initial].velocity: bead 7: not a finite number"],
    );
}

#[test]
fn exponent_at_most_one_names_the_contact() {
    let m = err(&format!(
        "[chain]\nbeads = 10\nexponent = {{ base = 2.5, impurity = {{ at = 4, value = 1.0 }} }}\n{RUN}"
    ));
    assert_contains(
        &m,
        &[
            "t.toml: [chain].exponent: contact 4: exponent must be > 1 and at most 10000",
            "got 1",
        ],
    );
    // Below 2 (but > 1) is only a warning.
    let s = ok(&format!(
        "[chain]\nbeads = 4\nexponent = [2.5, 1.8, 2.5]\n[initial]\nstriker = 1.0\n{RUN}"
    ));
    let w = validate(&s).expect("valid");
    assert_eq!(w.len(), 1, "{w:?}");
    assert_contains(&w[0], &["contact 1", "C¹"]);
}

/// An exponent far beyond the tested range ran without a word and gained 150 % of the energy
/// (n = 1e17; an adversarial review): refused, contact and wall alike.
#[test]
fn exponent_beyond_the_tested_range_is_refused() {
    let m = err(&format!(
        "[chain]\nbeads = 4\nexponent = [2.5, 1e17, 2.5]\n[initial]\nstriker = 1.0\n{RUN}"
    ));
    assert_contains(
        &m,
        &[
            "t.toml: [chain].exponent: contact 1: exponent must be > 1 and at most 10000",
            "got 100000000000000000",
        ],
    );
    let m = err(&format!(
        "[chain]\nbeads = 4\n[walls]\nleft = {{ exponent = 2e4 }}\n[initial]\nstriker = 1.0\n{RUN}"
    ));
    assert_contains(
        &m,
        &["[walls].left.exponent: exponent must be > 1 and at most 10000"],
    );
    ok(&format!(
        "[chain]\nbeads = 4\nexponent = 1e4\n[initial]\nstriker = 1.0\n{RUN}"
    ));
}

#[test]
fn mass_at_most_zero_names_the_bead() {
    let m = err(&format!("[chain]\nbeads = 4\nmass = [1, 1, -2, 1]\n{RUN}"));
    assert_contains(
        &m,
        &["t.toml: [chain].mass: bead 2: mass must be > 0, got -2"],
    );
    let m = err(&format!(
        "[chain]\nbeads = 4\nmass = {{ base = 1, segments = [{{ from = 3, value = 0 }}] }}\n{RUN}"
    ));
    assert_contains(&m, &["[chain].mass: bead 3"]);
    let m = err(&format!("[chain]\nbeads = 3\nprefactor = [1, 0]\n{RUN}"));
    assert_contains(&m, &["[chain].prefactor: contact 1: prefactor must be > 0"]);
}

#[test]
fn fewer_than_two_beads_is_an_error() {
    let m = err(&format!("[chain]\nbeads = 1\n{RUN}"));
    assert_contains(&m, &["t.toml: [chain].beads", "at least 2 beads, got 1"]);
    let m = err(&format!("[chain]\nmass = [1.0]\n{RUN}"));
    assert_contains(&m, &["[chain].mass", "at least 2 beads"]);
    let m = err(&format!("[chain]\nbeads = -3\n{RUN}"));
    assert_contains(&m, &["[chain].beads", "non-negative integer"]);
    let m = err(RUN);
    assert_contains(&m, &["[chain].beads", "missing"]);
}

#[test]
fn until_at_most_zero_and_bad_run_settings() {
    let m = err("[chain]\nbeads = 3\n[run]\nuntil = 0.0\n");
    assert_contains(&m, &["t.toml: [run].until", "> 0, got 0"]);
    let m = err("[chain]\nbeads = 3\n[run]\nuntil = -1\n");
    assert_contains(&m, &["[run].until", "got -1"]);
    let m = err("[chain]\nbeads = 3\n");
    assert_contains(&m, &["[run].until", "missing"]);
    let m = err("[chain]\nbeads = 3\n[run]\nuntil = 1\nevery = 0\n");
    assert_contains(&m, &["[run].every"]);
    let m = err("[chain]\nbeads = 3\n[run]\nuntil = 1\nrtol = 1.5\n");
    assert_contains(&m, &["[run].rtol", "(0, 1)"]);
    let m = err("[chain]\nbeads = 3\n[run]\nuntil = 1\nmethod = \"euler\"\n");
    assert_contains(&m, &["[run].method", "radau5"]);
}

#[test]
fn wrong_types_are_named() {
    let m = err(&format!("[chain]\nbeads = 3\nmass = \"heavy\"\n{RUN}"));
    assert_contains(&m, &["[chain].mass", "a string"]);
    let m = err(&format!("chain = 3\n{RUN}"));
    assert_contains(&m, &["[chain]", "expected a table"]);
    let m = err(&format!("[scene]\nseed = -1\n[chain]\nbeads = 3\n{RUN}"));
    assert_contains(&m, &["[scene].seed"]);
}

#[test]
fn load_names_both_file_and_preset_when_neither_exists() {
    let e = load("no_such_scene_xyz.toml").expect_err("missing");
    let m = e.to_string();
    assert_contains(
        &m,
        &[
            "no_such_scene_xyz.toml",
            "no such scene file",
            "preset",
            "striker",
        ],
    );
    let dir = tempfile::tempdir().expect("tempdir");
    let p = dir.path().join("bad.toml");
    std::fs::write(&p, "[chain]\nbeads = 1\n[run]\nuntil = 1\n").expect("write");
    let m = load(p.to_str().expect("utf8"))
        .expect_err("bad")
        .to_string();
    assert_contains(&m, &["bad.toml: [chain].beads"]);
}

#[test]
fn validate_reports_wrong_lengths_of_resolved_scenes() {
    let mut s = preset("striker").expect("striker");
    s.chain.exponent.pop();
    let m = validate(&s).expect_err("length").to_string();
    assert_contains(
        &m,
        &["striker: [chain].exponent: expected 99 values (one per contact), got 98"],
    );
    let mut s = preset("striker").expect("striker");
    s.run.until = f64::NAN;
    assert_contains(
        &validate(&s).expect_err("nan").to_string(),
        &["[run].until"],
    );
}

#[test]
fn mutated_presets_never_panic() {
    use rand::{Rng, SeedableRng};
    // Seeded byte-level mutations of every preset: parsing must return Ok or a one-line Err.
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2024);
    let alphabet = b"=[]{}\",.-+0123456789eEnaif \n#_xyz";
    let mut errors = 0;
    for p in presets() {
        for _ in 0..60 {
            let mut bytes = p.toml.as_bytes().to_vec();
            for _ in 0..rng.random_range(1..4) {
                let i = rng.random_range(0..bytes.len());
                match rng.random_range(0..3) {
                    0 => bytes[i] = alphabet[rng.random_range(0..alphabet.len())],
                    1 => {
                        bytes.remove(i);
                    }
                    _ => bytes.insert(i, alphabet[rng.random_range(0..alphabet.len())]),
                }
            }
            let text = String::from_utf8_lossy(&bytes);
            if let Err(e) = parse_str(&text, Path::new("."), "m.toml") {
                errors += 1;
                let m = e.to_string();
                assert!(!m.contains('\n') && m.starts_with("m.toml"), "{m:?}");
            }
        }
    }
    assert!(
        errors > 100,
        "mutations should mostly break scenes, got {errors} errors"
    );
}

/// Every table of a scene file is a struct of its keys (`deny_unknown_fields`): an unknown key
/// in any of them, top-level or nested, is refused with one line naming the file, the full key
/// path and the keys the table has.
#[test]
fn every_scene_table_refuses_an_unknown_key_naming_file_key_path_and_its_keys() {
    let chain = "[chain]\nbeads = 10\n";
    let units = "[units]\nsystem = \"physical\"\nradius = 4e-3\nyoung = 2.26e11\npoisson = 0.3\ndensity = 7650.0\n";
    // (the document's tables before [run], the key path named, the keys listed)
    let cases: &[(String, &str, &str)] = &[
        (format!("bogus = 1\n{chain}"), "[bogus]", "scene, chain, initial, run, field, walls, units, hard, output"),
        (format!("[scene]\nbogus = 1\n{chain}"), "[scene].bogus", "name, description, seed"),
        (format!("{chain}bogus = 1\n"), "[chain].bogus", "beads, mass, exponent, prefactor, precompression, precompression_force, precompression_force_si, radius, law, damping, damping_si, restitution, impact_speed, impact_speed_si"),
        (format!("{chain}{units}bogus = 1\n"), "[units].bogus", "system, time_scale, radius, young, poisson, density, m0, n0, mu, wall_young, wall_poisson, viscosity_shear, viscosity_bulk, time_unit"),
        (format!("{chain}[initial]\nbogus = 1\n"), "[initial].bogus", "velocity, displacement, striker, striker_right, pulse, velocity_si, striker_si, striker_right_si, solitary, equilibrium, mode"),
        (format!("{chain}[field]\nbogus = 1\n"), "[field].bogus", "force, gravity, force_si, gravity_si"),
        (format!("{chain}[walls]\nbogus = 1\n"), "[walls].bogus", "left, right, force, force_si"),
        (format!("{chain}[walls]\nright = {{ bogus = 1 }}\n"), "[walls].right.bogus", "exponent, prefactor, prefactor_si, precompression, hard, restitution, damping, damping_si"),
        (format!("{chain}[initial]\npulse = {{ bogus = 1 }}\n"), "[initial].pulse.bogus", "beads, velocity, velocity_si"),
        (format!("{chain}[initial]\nmode = {{ bogus = 1 }}\n"), "[initial].mode.bogus", "index, amplitude"),
        ("[chain]\nbeads = 40\n[initial]\nsolitary = [{ at = 20, velocity = 0.1 }, { bogus = 1 }]\n".to_string(), "[initial].solitary[1].bogus", "at, velocity, velocity_si, energy, energy_si, direction"),
        (format!("{chain}[hard]\nbogus = 1\n"), "[hard].bogus", "contacts, restitution, collapse_interval"),
        (format!("{chain}[hard]\ncontacts = {{ bogus = 1 }}\n"), "[hard].contacts.bogus", "from, to"),
        (format!("{chain}[output]\nbogus = 1\n"), "[output].bogus", "beads, fields, frames_max"),
        (format!("{chain}mass = {{ bogus = 1 }}\n"), "[chain].mass.bogus", "base, start, alternate, random, taper, segments, impurity, gaussian"),
        (format!("{chain}mass = {{ file = \"m.csv\", bogus = 1 }}\n"), "[chain].mass.bogus", "file"),
        (format!("{chain}exponent = {{ random = {{ bogus = 1 }} }}\n"), "[chain].exponent.random.bogus", "mean, eps"),
        (format!("{chain}mass = {{ taper = {{ bogus = 1 }} }}\n"), "[chain].mass.taper.bogus", "q, from"),
        (format!("{chain}mass = {{ segments = [{{ bogus = 1 }}] }}\n"), "[chain].mass.segments[0].bogus", "from, to, value"),
        (format!("{chain}mass = {{ impurity = {{ bogus = 1 }} }}\n"), "[chain].mass.impurity.bogus", "at, s, value"),
        (format!(
            "{chain}{}young = {{ base = 2.26e11, gaussian = {{ bogus = 1 }} }}\n",
            units.replace("young = 2.26e11\n", "")
        ), "[units].young.gaussian.bogus", "sigma, min"),
    ];
    for (tables, key, keys) in cases {
        let text = format!("{tables}{RUN}");
        let what = if *key == "[bogus]" {
            "table or key"
        } else {
            "key"
        };
        let want = format!("t.toml: {key}: unknown {what} (expected one of: {keys})");
        assert_eq!(err(&text), want, "{text}");
    }
    // [run] last: the text above ends with it, so its own unknown key is checked apart.
    let m = err(&format!("{chain}[run]\nuntil = 10.0\nbogus = 1\n"));
    assert_eq!(m, "t.toml: [run].bogus: unknown key (expected one of: until, every, until_si, every_si, rtol, atol, method, engine)");
    // A date stays a date through the read (its message says so).
    let m = err(&format!("[scene]\nname = 1979-05-27\n{chain}{RUN}"));
    assert_eq!(m, "t.toml: [scene].name: expected a string, got a date");
}

/// A quoted key may hold the words ", expected " of serde's own message: the list of the
/// table's keys is what follows the message's last ", expected " (the reader split at the first
/// one, so the key's tail leaked into the list: "expected one of: y, expected one of beads, …").
#[test]
fn unknown_key_holding_the_word_expected_lists_the_tables_keys() {
    let chain = "beads, mass, exponent, prefactor, precompression, precompression_force, precompression_force_si, radius, law, damping, damping_si, restitution, impact_speed, impact_speed_si";
    let m = err(&format!("[chain]\nbeads = 4\n\"x, expected y\" = 1\n{RUN}"));
    assert_eq!(
        m,
        format!("t.toml: [chain].x, expected y: unknown key (expected one of: {chain})")
    );
    let m = err(&format!(
        "\"a, expected one of b\" = 1\n[chain]\nbeads = 4\n{RUN}"
    ));
    assert_eq!(
        m,
        "t.toml: [a, expected one of b]: unknown table or key (expected one of: scene, chain, initial, run, field, walls, units, hard, output)"
    );
}

/// A wall's damping keys are named by the same key path as every other wall key
/// (`[walls].left.damping`); the damping reader wrote `[walls.left].damping`.
#[test]
fn wall_damping_errors_name_the_key_path_like_every_wall_key() {
    let m = err(&format!(
        "[chain]\nbeads = 4\n[walls]\nright = {{ damping = 0.1 }}\n{RUN}"
    ));
    assert_eq!(
        m,
        "t.toml: [walls].right.damping: needs a dissipative law ([chain] law = \"viscoelastic\" or \"linear_dashpot\")"
    );
    let m = err(&format!(
        "[chain]\nbeads = 4\nlaw = \"linear_dashpot\"\ndamping = 0.1\n[walls]\nleft = {{ damping = \"x\" }}\n{RUN}"
    ));
    assert_eq!(
        m,
        "t.toml: [walls].left.damping: expected a number, got a string"
    );
}
