//! Scene files through the library API: value forms, builders, physical units, presets (bad
//! input: `scene_errors.rs`).

use beadchain::scene::{self, load, parse_str, preset, presets, validate};

mod scene_support;
use scene_support::*;

#[test]
fn every_preset_parses_validates_and_matches_its_table_entry() {
    assert!(
        presets().len() >= 19,
        "expected the paper presets, got {}",
        presets().len()
    );
    assert!(presets().iter().any(|p| p.name == "striker"));
    for p in presets() {
        let s = preset(p.name).unwrap_or_else(|e| panic!("preset {}: {e}", p.name));
        let w = validate(&s).unwrap_or_else(|e| panic!("preset {}: {e}", p.name));
        assert!(w.is_empty(), "preset {} warnings: {w:?}", p.name);
        assert_eq!(s.name, p.name);
        assert!(s.description.starts_with(p.description), "{}", p.name);
        let t: toml::Table = toml::from_str(p.toml).expect("preset TOML");
        let st = t["scene"].as_table().expect("[scene]");
        assert_eq!(
            st["name"].as_str(),
            Some(p.name),
            "file name vs [scene].name"
        );
        assert_eq!(
            st["description"].as_str(),
            Some(p.description),
            "table vs file description"
        );
        assert!(s.run.until > 0.0 && s.run.every.is_some(), "{}", p.name);
        // load() falls back to presets when no such file exists.
        assert_eq!(load(p.name).expect("load preset"), s);
    }
}

#[test]
fn preset_files_on_disk_equal_the_embedded_ones() {
    for p in presets() {
        let path = format!("{}/data/scenes/{}.toml", env!("CARGO_MANIFEST_DIR"), p.name);
        let text = std::fs::read_to_string(&path).expect("preset file");
        assert_eq!(text, p.toml, "{path}");
        let from_file = load(&path).expect("load file");
        assert_eq!(from_file.chain, preset(p.name).expect("preset").chain);
    }
}

#[test]
fn default_striker_scene() {
    let s = preset("striker").expect("striker");
    assert_eq!(s.chain.len(), 100);
    assert_eq!(s.v0[0], 1.0);
    assert!(s.v0[1..].iter().all(|v| *v == 0.0));
    assert!(s.u0.iter().all(|u| *u == 0.0));
    assert!(s.chain.exponent.iter().all(|n| *n == 2.5));
    assert!(s.chain.precompression.is_none() && s.chain.field.is_none());
    assert!(s.chain.left_wall.is_none() && s.chain.right_wall.is_none());
    assert_eq!(s.seed, 0);
}

#[test]
fn the_issue_minimum_scene_works_with_all_three_forms() {
    let dir = tempfile::tempdir().expect("tempdir");
    let v: Vec<String> = (0..5).map(|i| format!("{}", 0.5 * i as f64)).collect();
    std::fs::write(dir.path().join("velocity.csv"), v.join("\n") + "\n").expect("write");
    std::fs::write(
        dir.path().join("mass.csv"),
        "# masses\n1.0\n2.0\n\n3.0\n4.0\n5.0\n",
    )
    .expect("write");
    let text = r#"
[chain]
beads = 5
mass = { file = "mass.csv" }
exponent = [2.5, 3.0, 3.5, 4.0]
prefactor = 0.4
precompression = 0.0
[initial]
velocity = { file = "velocity.csv" }
displacement = 0.0
[run]
until = 150.0
"#;
    let s = parse_str(text, dir.path(), "min.toml").expect("parse");
    assert_eq!(s.name, "min");
    assert_eq!(s.chain.mass, vec![1.0, 2.0, 3.0, 4.0, 5.0]);
    assert_eq!(s.chain.exponent, vec![2.5, 3.0, 3.5, 4.0]);
    assert_eq!(s.chain.prefactor, vec![0.4; 4]);
    assert_eq!(
        s.chain.precompression, None,
        "explicit all-zero precompression maps to None"
    );
    assert_eq!(s.v0, vec![0.0, 0.5, 1.0, 1.5, 2.0]);
    assert_eq!(s.u0, vec![0.0; 5]);
    assert_eq!(s.run.until, 150.0);
    // The same files through load() resolve relative to the scene file, from any cwd.
    let scene_path = dir.path().join("min.toml");
    std::fs::write(&scene_path, text).expect("write scene");
    let loaded = load(scene_path.to_str().expect("utf8 path")).expect("load");
    assert_eq!(loaded.chain, s.chain);
    // Per-contact arrays from files too, and `beads` inferred from the first explicit array.
    std::fs::write(dir.path().join("n.csv"), "3.0\n3.5\n").expect("write");
    let s = parse_str(
        "[chain]\nexponent = { file = \"n.csv\" }\n[run]\nuntil = 1.0\n",
        dir.path(),
        "x.toml",
    )
    .expect("parse");
    assert_eq!(s.chain.len(), 3);
    assert_eq!(s.chain.exponent, vec![3.0, 3.5]);
}

#[test]
fn interface_segments_and_impurities_set_the_right_contacts() {
    let s = ok(&format!(
        "[chain]\nbeads = 150\nexponent = {{ base = 3.0, segments = [{{ from = 50, value = 3.5 }}] }}\n{RUN}"
    ));
    assert_eq!(s.chain.exponent.len(), 149);
    assert!(s.chain.exponent[..50].iter().all(|n| *n == 3.0));
    assert!(s.chain.exponent[50..].iter().all(|n| *n == 3.5));
    let p = preset("interface_3.0_3.5").expect("preset");
    assert_eq!(p.chain.exponent, s.chain.exponent);

    let s = ok(&format!(
        "[chain]\nbeads = 100\nexponent = {{ base = 4.0, impurity = {{ at = 50, s = 5, value = 2.5 }} }}\n{RUN}"
    ));
    for (k, n) in s.chain.exponent.iter().enumerate() {
        let want = if (50..55).contains(&k) { 2.5 } else { 4.0 };
        assert_eq!(*n, want, "contact {k}");
    }
    // Inclusive `to`, several segments in file order, array base.
    let s = ok(&format!(
        "[chain]\nbeads = 6\nprefactor = {{ base = [1, 2, 3, 4, 5], segments = [{{ from = 1, to = 2, value = 9 }}, {{ from = 2, to = 2, value = 7 }}] }}\n{RUN}"
    ));
    assert_eq!(s.chain.prefactor, vec![1.0, 9.0, 7.0, 4.0, 5.0]);
}

#[test]
fn alternation_is_periodic_from_start() {
    let s = ok(&format!(
        "[chain]\nbeads = 9\nexponent = {{ alternate = [2.5, 3.0] }}\n{RUN}"
    ));
    let want: Vec<f64> = (0..8).map(|k| if k % 2 == 0 { 2.5 } else { 3.0 }).collect();
    assert_eq!(s.chain.exponent, want);
    let s = ok(&format!(
        "[chain]\nbeads = 9\nexponent = {{ base = 2.0, alternate = [4.0, 5.0, 6.0], start = 3 }}\n{RUN}"
    ));
    assert_eq!(
        s.chain.exponent,
        vec![2.0, 2.0, 2.0, 4.0, 5.0, 6.0, 4.0, 5.0]
    );
}

fn disorder(seed: u64) -> Vec<f64> {
    ok(&format!(
        "[scene]\nseed = {seed}\n[chain]\nbeads = 1000\nexponent = {{ random = {{ mean = 2.5, eps = 0.04 }}, start = 20 }}\n{RUN}"
    ))
    .chain
    .exponent
}

#[test]
fn random_exponents_are_in_range_seeded_and_reproducible() {
    let a = disorder(1);
    assert_eq!(a.len(), 999);
    assert!(
        a[..20].iter().all(|n| *n == 2.5),
        "contacts 0..19 monodisperse"
    );
    assert!(a[20..].iter().all(|n| (2.46..2.54).contains(n)), "n̄ ± ε");
    assert_eq!(a, disorder(1), "same seed, same chain");
    let b = disorder(2);
    assert_ne!(a[20..], b[20..], "different seeds differ");
    // Uniform on [−ε, ε): sample mean within 0.005 of n̄ (≈ 7 standard errors of 7.4e-4).
    let mean = a[20..].iter().sum::<f64>() / 979.0;
    assert!(close(mean, 2.5, 5e-3, 0.0), "mean {mean}");
    // Spread covers the interval: min/max within 0.002 of the ends (979 draws).
    let lo = a[20..].iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = a[20..].iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    assert!(lo < 2.462 && hi > 2.538, "range [{lo}, {hi}]");
    // The preset is this exact chain (seed 1), and other keys do not shift the stream.
    assert_eq!(
        preset("disorder_2.5_0.04").expect("preset").chain.exponent,
        a
    );
    let with_mass = ok(&format!(
        "[scene]\nseed = 1\n[chain]\nbeads = 1000\nmass = {{ random = {{ mean = 1.0, eps = 0.1 }} }}\nexponent = {{ random = {{ mean = 2.5, eps = 0.04 }}, start = 20 }}\n{RUN}"
    ));
    assert_eq!(with_mass.chain.exponent, a);
    assert!(with_mass.chain.mass.iter().all(|m| (0.9..1.1).contains(m)));
}

#[test]
fn gaussian_perturbation_respects_min_and_sigma() {
    let text = |seed: u64, base: f64| {
        format!("[scene]\nseed = {seed}\n[chain]\nbeads = 4001\nexponent = {{ base = {base}, gaussian = {{ sigma = 0.1, min = 2.0 }} }}\n{RUN}")
    };
    let s = ok(&text(3, 3.0)).chain.exponent;
    let mean = s.iter().sum::<f64>() / s.len() as f64;
    let sd = (s.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (s.len() - 1) as f64).sqrt();
    // 4000 draws: standard error of the mean 0.0016, of the s.d. ~1.1%; tolerances 5x that.
    assert!(close(mean, 3.0, 8e-3, 0.0), "mean {mean}");
    assert!(close(sd, 0.1, 0.0, 0.06), "sd {sd}");
    assert_eq!(ok(&text(3, 3.0)).chain.exponent, s, "reproducible");
    // Close to the bound: every value redrawn above 2.0 (eq. B.1 constraint n > 2).
    let near = ok(&text(4, 2.02)).chain.exponent;
    assert!(near.iter().all(|n| *n > 2.0));
    assert!(near.iter().any(|n| *n > 2.1), "perturbation applied");
    // Perturbed interface preset: values differ from the clean interface but stay > 2.
    let p = preset("interface_3.5_3.0_perturbed")
        .expect("preset")
        .chain
        .exponent;
    assert!(p.iter().all(|n| *n > 2.0));
    assert!(
        p[..50].iter().all(|n| (3.3..3.7).contains(n)),
        "8 sigma around 3.5"
    );
    assert!(
        p[50..].iter().all(|n| (2.8..3.2).contains(n)),
        "8 sigma around 3.0"
    );
}

#[test]
fn tapered_radii_drive_masses_and_prefactors() {
    let s = preset("tapered").expect("tapered");
    let r = |i: usize| {
        if i < 20 {
            1.0
        } else {
            0.95f64.powi(i as i32 - 20)
        }
    };
    for i in 0..60 {
        // abs 0, rel 1e-12: same formula, different evaluation order.
        assert!(close(s.chain.mass[i], r(i).powi(3), 0.0, 1e-12), "bead {i}");
    }
    for k in 0..59 {
        let want = (2.0 * r(k) * r(k + 1) / (r(k) + r(k + 1))).sqrt();
        assert!(close(s.chain.prefactor[k], want, 0.0, 1e-12), "contact {k}");
    }
    assert_eq!(
        s.chain.prefactor[0], 1.0,
        "R = 1 reproduces the plain prefactor"
    );
}

#[test]
fn mass_and_composite_interfaces() {
    let s = preset("composite_mass_exponent").expect("preset");
    assert!(s.chain.mass[..51].iter().all(|m| *m == 1.0));
    assert!(s.chain.mass[51..].iter().all(|m| *m == 0.5));
    assert!(s.chain.exponent[..50].iter().all(|n| *n == 3.0));
    assert!(s.chain.exponent[50..].iter().all(|n| *n == 2.5));
}

#[test]
fn pulses_and_strikers_from_both_ends() {
    let s = preset("rectangular_pulse").expect("pulse");
    assert!(s.v0[..5].iter().all(|v| *v == 1.0) && s.v0[5..].iter().all(|v| *v == 0.0));
    let s = preset("two_strikers").expect("two");
    assert_eq!((s.v0[0], s.v0[100]), (1.0, -1.0));
    assert!(s.v0[1..100].iter().all(|v| *v == 0.0));
    // Order: velocity, then pulse, then strikers.
    let s = ok(&format!(
        "[chain]\nbeads = 4\n[initial]\nvelocity = 0.1\npulse = {{ beads = 2, velocity = 0.5 }}\nstriker = 2.0\nstriker_right = 3.0\n{RUN}"
    ));
    assert_eq!(s.v0, vec![2.0, 0.5, 0.1, -3.0]);
}

#[test]
fn fields_precompression_and_walls_are_declared_effects() {
    let s = ok(&format!(
        "[chain]\nbeads = 3\nmass = [1, 2, 3]\n[field]\ngravity = 2.0\n{RUN}"
    ));
    assert_eq!(s.chain.field, Some(vec![-2.0, -4.0, -6.0]), "W = −m g");
    let s = ok(&format!(
        "[chain]\nbeads = 3\n[field]\nforce = [0.5, 0, 0]\ngravity = 1.0\n{RUN}"
    ));
    assert_eq!(
        s.chain.field,
        Some(vec![-0.5, -1.0, -1.0]),
        "force and gravity add"
    );
    let s = ok(&format!("[chain]\nbeads = 3\n[field]\nforce = 0.0\n{RUN}"));
    assert_eq!(s.chain.field, None, "all-zero field maps to None");
    let s = ok(&format!(
        "[chain]\nbeads = 3\nprecompression = [0.0, 0.01]\n{RUN}"
    ));
    assert_eq!(s.chain.precompression, Some(vec![0.0, 0.01]));
    let s = ok(&format!(
        "[chain]\nbeads = 3\nexponent = [2.5, 3.0]\nprefactor = [1.0, 2.0]\n[walls]\nright = {{}}\nleft = {{ exponent = 4.0, precompression = -0.1 }}\n{RUN}"
    ));
    let l = s.chain.left_wall.expect("left");
    let r = s.chain.right_wall.expect("right");
    assert_eq!(
        (l.exponent, l.prefactor, l.precompression),
        (4.0, 1.0, -0.1)
    );
    assert_eq!(
        (r.exponent, r.prefactor, r.precompression),
        (3.0, 2.0, 0.0),
        "end-contact defaults"
    );
    let g = preset("gravity_on_wall").expect("gravity");
    // Static equilibrium: each contact's force carries the weight above it (rel 1e-12).
    let c = &g.chain;
    let lw = c.left_wall.as_ref().expect("wall");
    let f_wall = 2.5 * (lw.precompression - g.u0[0]).powf(1.5);
    assert!(close(f_wall, 6.0, 0.0, 1e-12), "wall carries 6 g: {f_wall}");
    for k in 0..5 {
        let f = 2.5 * (g.u0[k] - g.u0[k + 1]).powf(1.5);
        assert!(close(f, (5 - k) as f64, 0.0, 1e-12), "contact {k}: {f}");
    }
}

#[test]
fn run_settings_and_scene_table() {
    let s = ok("[scene]\nname = \"x\"\ndescription = \"d\"\nseed = 42\n[chain]\nbeads = 2\n[run]\nuntil = 5\nevery = 0.5\nrtol = 1e-6\natol = 1e-9\nmethod = \"dop853\"\nengine = \"hybrid\"\n");
    assert_eq!(
        (s.name.as_str(), s.description.as_str(), s.seed),
        ("x", "d", 42)
    );
    assert_eq!(s.run.until, 5.0);
    assert_eq!(s.run.every, Some(0.5));
    assert_eq!((s.run.rtol, s.run.atol), (Some(1e-6), Some(1e-9)));
    assert_eq!(s.run.method, Some(beadchain::integrate::Method::Dop853));
    assert_eq!(s.run.engine, Some(scene::Engine::Hybrid));
}

#[test]
fn physical_units_match_table_1_and_the_paper_scaling() {
    let s = preset("hertz_spheres_physical").expect("physical");
    let m_si = scene::units::sphere_mass(4e-3, 7650.0);
    // Table 1: 2.05 g. Exact: 7650·4/3·π·(4 mm)³ = 2.05083 g (abs 1e-8 kg).
    assert!(close(m_si, 2.05083e-3, 1e-8, 0.0), "mass {m_si} kg");
    let d = scene::units::hertz_d(2.26e11, 0.3, 2.26e11, 0.3);
    let a_si = scene::units::hertz_prefactor(4e-3, 4e-3, d);
    assert!(close(a_si, 2.961766e9, 0.0, 1e-6), "a = {a_si}");
    let sc = scene::UnitScales::paper(m_si, 1e9, 2.5);
    assert!(close(sc.time, 9.057222e-7, 0.0, 1e-6), "beta = {}", sc.time);
    // Computer units: mass 1, prefactor ã/n0 = 2.961766/2.5 (rel 1e-6).
    assert!(s.chain.mass.iter().all(|m| close(*m, 1.0, 0.0, 1e-12)));
    assert!(s
        .chain
        .prefactor
        .iter()
        .all(|a| close(*a, 1.1847065, 0.0, 1e-6)));
    // 0.11 m/s → 9.963e-8 computer units, i.e. the paper's "1e7" is 1e-7 (rel 1e-4).
    assert!(
        close(s.v0[0], 9.962944e-8, 0.0, 1e-6),
        "striker {}",
        s.v0[0]
    );
    assert!(close(sc.velocity(0.1104091), 1e-7, 0.0, 1e-6));
    assert!(
        close(s.run.until, 2.2e-3 / 9.057222e-7, 0.0, 1e-6),
        "until {}",
        s.run.until
    );
    assert!(
        s.description.contains("time unit 9.057"),
        "{}",
        s.description
    );
    // SI time scale: masses in kg, prefactors in SI, velocities in m/s.
    let si = ok("[units]\nsystem = \"physical\"\ntime_scale = \"si\"\nradius = 4e-3\nyoung = 2.26e11\npoisson = 0.3\ndensity = 7650\n[chain]\nbeads = 3\n[initial]\nstriker_si = 0.11\n[walls]\nright = {}\n[run]\nuntil_si = 1e-3\n");
    assert!(close(si.chain.mass[0], m_si, 0.0, 1e-12));
    assert!(close(si.chain.prefactor[0], a_si, 0.0, 1e-12));
    assert_eq!(si.v0[0], 0.11);
    assert_eq!(si.run.until, 1e-3);
    let wall = si.chain.right_wall.expect("wall");
    // Sphere–flat Hertz: 2/(5D)·sqrt(R) = sqrt(2)·a_sphere-sphere for equal spheres (rel 1e-12).
    assert!(close(wall.prefactor, a_si * 2f64.sqrt(), 0.0, 1e-12));
    // Gravity in SI: g̃ = g β², W = −m̃ g̃.
    let g = ok("[units]\nsystem = \"physical\"\nradius = 4e-3\nyoung = 2.26e11\npoisson = 0.3\ndensity = 7650\n[chain]\nbeads = 2\n[field]\ngravity_si = 9.81\n[run]\nuntil = 1\n");
    let w = g.chain.field.expect("field");
    let beta = (m_si / 2.5e9).sqrt();
    assert!(close(w[0], -9.81 * beta * beta, 0.0, 1e-9), "W {}", w[0]);
}

#[test]
fn mixed_exponent_presets_use_the_paper_units() {
    for name in [
        "interface_3.0_3.5",
        "interface_3.0_2.5",
        "periodic_2.5_3.0",
        "impurity_s1_3.0_2.5",
        "disorder_2.5_0.04",
    ] {
        let s = preset(name).expect("preset");
        // Prefactor held at the sphere value ã/n0 = 1.1847065 for every exponent (rel 1e-6).
        assert!(
            s.chain
                .prefactor
                .iter()
                .all(|a| close(*a, 1.1847065, 0.0, 1e-6)),
            "{name}"
        );
        assert!(s.chain.mass.iter().all(|m| *m == 1.0), "{name}");
        // Striker 0.11 m/s = 9.963e-8 computer units (rel 1e-6).
        assert!(
            close(s.v0[0], 9.962944e-8, 0.0, 1e-6),
            "{name}: {}",
            s.v0[0]
        );
    }
}

// ---------------------------------------------------------------- bad input, one per class
