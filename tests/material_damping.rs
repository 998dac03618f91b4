//! Viscoelastic damping from material constants (issue "open engine"): `[units]
//! viscosity_shear` (η₁) and `viscosity_bulk` (η₂) give each bead Brilliantov et al.'s (1996)
//! `A = (1/3)(3η₂ − η₁)²/(3η₂ + 2η₁) · (1 − ν²)(1 − 2ν)/(Y ν²)`; a contact takes the mean of its
//! beads' `A`. Checked against hand-computed values, against `damping_si = A` (the same scene
//! bit for bit), by the energy balance of a run, and by its errors.

mod common;

use beadchain::engine::RunConfig;
use beadchain::scene::{parse_str, Scene};
use std::path::Path;

fn scene(text: &str) -> Result<Scene, String> {
    parse_str(text, Path::new("."), "m.toml").map_err(|e| e.to_string())
}

/// A physical chain of `beads` steel-like spheres (Y = 2e11 Pa, ν = 0.25), viscosities given as
/// TOML values, struck at 0.11 m/s.
fn physical(beads: usize, shear: &str, bulk: &str) -> String {
    format!(
        "[units]\nsystem = \"physical\"\nradius = 4e-3\nyoung = 2e11\npoisson = 0.25\n\
         density = 7650\nviscosity_shear = {shear}\nviscosity_bulk = {bulk}\n\
         [chain]\nbeads = {beads}\nlaw = \"viscoelastic\"\n[initial]\nstriker_si = 0.11\n\
         [run]\nuntil_si = 2e-4\n"
    )
}

/// `|a − b| ≤ atol + rtol·|b|`.
fn close(a: f64, b: f64, atol: f64, rtol: f64) -> bool {
    (a - b).abs() <= atol + rtol * b.abs()
}

/// A in seconds of every contact of `sc`.
fn contact_a_si(sc: &Scene) -> Vec<f64> {
    let beta = sc.units.expect("physical").time;
    let d = sc.chain.damping.as_ref().expect("damped");
    d.contact.iter().map(|a| a * beta).collect()
}

#[test]
fn viscosities_give_the_brilliantov_constant() {
    // By hand: (1 − ν²)(1 − 2ν)/(Y ν²) = 0.9375·0.5/(2e11·0.0625) = 3.75e-11 Pa⁻¹;
    // η₁ = η₂ = 1500: (3·1500 − 1500)²/(3·1500 + 2·1500)/3 = 9e6/7500/3 = 400 Pa·s → A = 1.5e-8 s.
    let sc = scene(&physical(3, "1500.0", "1500.0")).unwrap();
    for a in contact_a_si(&sc) {
        assert!(close(a, 1.5e-8, 0.0, 1e-14), "A = {a:e} s");
    }
    // η₂ = η₁/3 cancels the bulk term: no damping at all, the power law.
    let none = scene(&physical(3, "1500.0", "500.0")).unwrap();
    assert_eq!(none.chain.damping, None);
}

#[test]
fn mixed_materials_take_the_mean_constant() {
    // Bead 2 has η₁ = η₂ = 3000: 36e6/15000/3 = 800 Pa·s → A = 3e-8 s; contact 1 the mean.
    let sc = scene(&physical(
        3,
        "[1500.0, 1500.0, 3000.0]",
        "[1500.0, 1500.0, 3000.0]",
    ))
    .unwrap();
    let a = contact_a_si(&sc);
    assert!(close(a[0], 1.5e-8, 0.0, 1e-14), "{a:?}");
    assert!(close(a[1], 2.25e-8, 0.0, 1e-14), "{a:?}");
}

#[test]
fn viscosities_equal_the_same_damping_si() {
    let text = physical(5, "1500.0", "1500.0");
    let by_material = scene(&text).unwrap();
    let a = contact_a_si(&by_material)[0];
    let plain = text
        .replace("viscosity_shear = 1500.0\nviscosity_bulk = 1500.0\n", "")
        .replace(
            "law = \"viscoelastic\"\n",
            &format!("law = \"viscoelastic\"\ndamping_si = {a:e}\n"),
        );
    let by_key = scene(&plain).unwrap();
    assert_eq!(by_material.chain.damping, by_key.chain.damping);
}

#[test]
fn material_damped_chain_balances_its_energy() {
    // η = 1.5e5 Pa·s: A = 1.5e-6 s, a few per cent of the contact time.
    let sc = scene(&physical(20, "1.5e5", "1.5e5")).unwrap();
    let mut cfg = RunConfig::from_scene(&sc);
    cfg.rtol = 1e-9;
    cfg.atol = 1e-13 * sc.v0[0].abs();
    cfg.every = Some(cfg.until / 20.0);
    let (out, rec) = common::run(&sc, &cfg);
    let e0 = sc.chain.energy(&sc.u0, &sc.v0);
    assert!(
        out.dissipated > 1e-2 * e0,
        "dissipated {:e} of {e0:e}",
        out.dissipated
    );
    for k in 0..rec.t.len() {
        let e = sc.chain.energy(&rec.u[k], &rec.v[k]) + rec.dissipated[k];
        // abs 0, rel 1e-7 of E0 at rtol 1e-9
        assert!(close(e, e0, 0.0, 1e-7), "frame {k}: {e:e} vs {e0:e}");
    }
}

#[test]
fn viscosity_keys_are_checked() {
    let cases = [
        (
            physical(3, "1500.0", "1500.0").replace("viscosity_bulk = 1500.0\n", ""),
            "[units].viscosity_bulk: missing: the viscoelastic constant needs both viscosity_shear and viscosity_bulk",
        ),
        (
            physical(3, "-1.0", "1500.0"),
            "[units].viscosity_shear: bead 0: must be a finite number >= 0 (Pa·s), got -1",
        ),
        (
            physical(3, "1500.0", "1500.0").replace("poisson = 0.25", "poisson = -0.1"),
            "[units].poisson: bead 0: must be > 0 with viscosities",
        ),
        (
            physical(3, "1500.0", "1500.0").replace("law = \"viscoelastic\"\n", ""),
            "[units].viscosity_shear: the material viscosities give the constant A of [chain] law = \"viscoelastic\"",
        ),
        (
            physical(3, "1500.0", "1500.0").replace("\"viscoelastic\"", "\"linear_dashpot\""),
            "[units].viscosity_shear: the material viscosities give the constant A of [chain] law = \"viscoelastic\"",
        ),
        (
            physical(3, "1500.0", "1500.0")
                .replace("law = \"viscoelastic\"\n", "law = \"viscoelastic\"\ndamping = 0.1\n"),
            "[chain].damping: give either the material viscosities ([units] viscosity_shear, viscosity_bulk) or the contacts' damping, not both",
        ),
        (
            "[units]\nviscosity_shear = 1.0\n[chain]\nbeads = 3\n[initial]\nstriker = 1.0\n[run]\nuntil = 1.0\n".to_string(),
            "[units].viscosity_shear: only allowed in a physical scene",
        ),
    ];
    for (text, want) in cases {
        let e = scene(&text).unwrap_err();
        assert!(e.contains(want), "{e}\n  wanted: {want}");
        assert_eq!(e.lines().count(), 1, "{e}");
        println!("material damping | {e}");
    }
}
