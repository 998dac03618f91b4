//! Exact solitary waves as initial condition (`[initial].solitary`, issue 35 part 1): the wave
//! of the discrete chain travels unchanged, at constant speed, without radiation; its speed
//! follows `c ∝ v_m^{(n−2)/n}`; `⟨K⟩/⟨E⟩ = n/(n+2)` (virial theorem); head-on collisions of
//! equal waves stay mirror-symmetric; scenes that do not support the wave are refused.
//! Measured figures over wider ranges: `validation/solitary.sh`.

mod common;
use beadchain::engine::{Recorder, RunConfig};
use beadchain::integrate::Method;
use beadchain::linalg::SolverKind;
use beadchain::scene::{parse_str, Engine, Scene};
use beadchain::studies::solitary::{UnitProfile, Wave};
use std::path::Path;

/// A uniform dimensionless chain of `nb` beads with the given `[initial].solitary` value.
fn scene(nb: usize, n: f64, solitary: &str) -> Scene {
    let text = format!(
        "[chain]\nbeads = {nb}\nexponent = {n}\nprefactor = 0.7\nmass = 1.3\n[initial]\nsolitary = {solitary}\n[run]\nuntil = 1.0\n"
    );
    parse_str(&text, Path::new("."), "test.toml").expect("scene parses")
}

/// Dense DOP853 run (rtol 1e-13, atol 1e-15) with frames every `every` up to `until`.
fn run(s: &Scene, until: f64, every: f64) -> Recorder {
    let cfg = RunConfig {
        engine: Engine::Dense,
        method: Method::Dop853,
        rtol: 1e-13,
        atol: 1e-15,
        until,
        every: Some(every),
        solver: SolverKind::Auto,
        max_steps: Some(20_000_000),
    };
    common::run(s, &cfg).1
}

/// The wave the scenes above place (mass 1.3, prefactor 0.7).
fn wave(n: f64, v_m: f64) -> Wave {
    Wave::with_peak_velocity(UnitProfile::compute(n).unwrap(), 1.3, 0.7, v_m).unwrap()
}

/// Centroid `Σ k v_k² / Σ v_k²` of a frame: for the travelling wave it advances by exactly one
/// bead per period `1/c` (its lattice wiggle repeats).
fn centroid(v: &[f64]) -> f64 {
    let (mut a, mut b) = (0.0, 0.0);
    for (k, x) in v.iter().enumerate() {
        a += k as f64 * x * x;
        b += x * x;
    }
    a / b
}

/// A wave launched at bead 50 travels 300 beads: velocity profile unchanged to 1e-9 of `v_m`
/// (frames at integer numbers of bead spacings `j/c`, and against the exact profile at every
/// frame, `1/(4c)` apart), speed constant to 1e-10, radiation behind it below 1e-9 of its energy.
fn travels_unchanged(n: f64, v_m: f64) {
    let (nb, at, travel) = (380, 50, 300);
    let w = wave(n, v_m);
    let s = scene(nb, n, &format!("{{ at = {at}, velocity = {v_m:e} }}"));
    let e0 = s.chain.energy(&s.u0, &s.v0);
    // The placed state carries the wave's energy κ m v_m²: relative 1e-12.
    assert!(
        (e0 / w.energy() - 1.0).abs() < 1e-12,
        "energy {e0} vs {}",
        w.energy()
    );
    let c = w.speed;
    let rec = run(&s, travel as f64 / c, 0.25 / c);
    // Frame after j bead spacings, t = j/c (frames are k/(4c); the last one may repeat `until`).
    let frame = |j: usize| {
        rec.t
            .iter()
            .position(|t| (t * c - j as f64).abs() < 1e-9)
            .expect("frame at j/c")
    };
    let last = frame(travel);
    let (mut shape, mut exact) = (0.0_f64, 0.0_f64);
    for k in 0..nb - travel {
        shape = shape.max((rec.v[last][k + travel] - rec.v[0][k]).abs());
    }
    for (f, t) in rec.t.iter().enumerate() {
        for k in 0..nb {
            exact = exact.max((rec.v[f][k] - w.velocity(k as f64 - at as f64 - c * t)).abs());
        }
    }
    eprintln!(
        "n {n} v_m {v_m:e}: shape {:.2e}, vs exact {:.2e} (of v_m)",
        shape / v_m,
        exact / v_m
    );
    // Profile after 300 bead spacings equals the initial one: absolute 1e-9·v_m.
    assert!(shape <= 1e-9 * v_m, "shape change {shape:e}");
    // Against the exact travelling wave at every frame: absolute 1e-9·v_m.
    assert!(
        exact <= 1e-9 * v_m,
        "deviation from the exact wave {exact:e}"
    );
    // Speed: the centroid advances one bead per 1/c: relative 1e-10 per bead spacing.
    let x: Vec<f64> = (0..=travel).map(|j| centroid(&rec.v[frame(j)])).collect();
    let worst = x
        .windows(2)
        .fold(0.0_f64, |m, p| m.max((p[1] - p[0] - 1.0).abs()));
    eprintln!("  speed: worst |Δx − 1| per bead spacing {worst:.2e}");
    assert!(worst <= 1e-10, "speed not constant: {worst:e}");
    // Radiation: energy of the beads and contacts behind the wave's support, relative 1e-9.
    let lo = at + travel - w.profile.support - 1;
    let (u, v) = (&rec.u[last], &rec.v[last]);
    let mut behind: f64 = (0..lo).map(|k| 0.5 * 1.3 * v[k] * v[k]).sum();
    behind += (0..lo - 1)
        .map(|k| 0.7 * (u[k] - u[k + 1]).max(0.0).powf(n))
        .sum::<f64>();
    eprintln!("  radiation behind: {:.2e} of E", behind / e0);
    assert!(behind <= 1e-9 * e0, "radiation {behind:e} of {e0:e}");
}

#[test]
fn hertz_wave_travels_300_beads_unchanged() {
    travels_unchanged(2.5, 1.0);
}

#[test]
fn steep_and_soft_waves_travel_300_beads_unchanged() {
    travels_unchanged(2.1, 0.3);
    travels_unchanged(8.0, 2.0);
}

/// A review's case: the profiles of n = 24, 26 and 30 were refused as "did not converge" (a
/// spectral tail of 1.1e-15 against the 1e-15 asked for at the finest grid then, 256 points per
/// bead), although the n = 21, 22 and 28 ones were computed and exact.
#[test]
fn steep_waves_beyond_n_20_are_computed_and_travel_unchanged() {
    travels_unchanged(24.0, 1.0);
    travels_unchanged(30.0, 1.0);
}

/// Measured speed (centroid over 6 bead spacings) against `v_m` over 6 decades: `c / v_m^{(n−2)/n}`
/// the same at every `v_m` (relative 1e-9), and equal to the profile's prediction (1e-9).
#[test]
fn speed_follows_one_power_law_over_six_decades() {
    for n in [2.1, 2.5, 3.0, 4.0, 8.0] {
        let mut ratios = Vec::new();
        for v_m in [1e-3, 1e-1, 1e1, 1e3] {
            let w = wave(n, v_m);
            let s = scene(40, n, &format!("{{ at = 17, velocity = {v_m:e} }}"));
            let t = 6.0 / w.speed;
            let rec = run(&s, t, t);
            let c = (centroid(&rec.v[1]) - centroid(&rec.v[0])) / t;
            assert!(
                (c / w.speed - 1.0).abs() < 1e-9,
                "n {n} v_m {v_m}: c {c} vs {}",
                w.speed
            );
            ratios.push(c / v_m.powf((n - 2.0) / n));
        }
        let spread = ratios
            .iter()
            .fold(0.0_f64, |m, r| m.max((r / ratios[0] - 1.0).abs()));
        eprintln!(
            "n {n}: c/v_m^((n-2)/n) = {:.12}, spread {spread:.1e}",
            ratios[0]
        );
        assert!(spread < 1e-9, "n {n}: ratios {ratios:?}");
    }
}

/// `⟨K⟩/⟨E⟩` over one period `1/c` (trapezoid rule on 64 frames, spectrally accurate for the
/// periodic `K(t)`) is `n/(n+2)`: absolute 1e-9.
#[test]
fn kinetic_fraction_follows_the_virial_theorem() {
    for n in [2.1, 2.5, 3.0, 8.0] {
        let w = wave(n, 1.0);
        let s = scene(60, n, "{ at = 25, velocity = 1.0 }");
        let period = 1.0 / w.speed;
        let rec = run(&s, period, period / 64.0);
        let e = s.chain.energy(&s.u0, &s.v0);
        let k: Vec<f64> = rec.v.iter().map(|v| s.chain.kinetic_energy(v)).collect();
        let mean = k[..64].iter().sum::<f64>() / 64.0;
        let (kmin, kmax) = k
            .iter()
            .fold((f64::MAX, 0.0_f64), |(a, b), x| (a.min(*x), b.max(*x)));
        eprintln!(
            "n {n}: <K>/E = {:.12} vs n/(n+2) = {:.12}, difference {:.1e} (K(t)/E in [{:.9}, {:.9}])",
            mean / e,
            w.kinetic_fraction(),
            (mean / e - w.kinetic_fraction()).abs(),
            kmin / e,
            kmax / e
        );
        assert!((mean / e - w.kinetic_fraction()).abs() < 1e-9, "n {n}");
    }
}

/// Two equal waves meeting head-on (beads 30 and 90 of 121): `u_k = −u_{N−1−k}`,
/// `v_k = −v_{N−1−k}` at every frame, absolute 1e-13 of `v_m` and of the largest `|u|`.
#[test]
fn equal_waves_meeting_head_on_stay_symmetric() {
    let nb = 121;
    let s = scene(
        nb,
        2.5,
        "[{ at = 30, velocity = 1.0 }, { at = 90, velocity = 1.0, direction = \"left\" }]",
    );
    let w = wave(2.5, 1.0);
    let rec = run(&s, 80.0 / w.speed, 1.0 / w.speed);
    let umax = s.u0.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let (mut du, mut dv) = (0.0_f64, 0.0_f64);
    for f in 0..rec.t.len() {
        for k in 0..nb {
            du = du.max((rec.u[f][k] + rec.u[f][nb - 1 - k]).abs());
            dv = dv.max((rec.v[f][k] + rec.v[f][nb - 1 - k]).abs());
        }
    }
    eprintln!("head-on: asymmetry u {du:.1e}, v {dv:.1e}");
    // The waves did meet: the centre beads moved.
    assert!(rec.v.iter().any(|v| v[60] != 0.0 || v[59].abs() > 0.1));
    assert!(
        du <= 1e-13 * umax && dv <= 1e-13,
        "asymmetry u {du:e}, v {dv:e}"
    );
}

/// The scene's error for `[chain]`/`[initial]` lines `body`.
fn scene_error(body: &str) -> String {
    let text = format!("{body}\n[run]\nuntil = 1.0\n");
    match parse_str(&text, Path::new("."), "bad.toml") {
        Ok(_) => panic!("accepted: {body}"),
        Err(e) => e.to_string(),
    }
}

/// Refusals name the file, the key and the bead or contact; each is one line.
#[test]
fn unsupported_chains_are_refused_with_the_bead() {
    let cases = [
        ("[chain]\nbeads = 100\nexponent = 2.0\n[initial]\nsolitary = { at = 50, velocity = 1.0 }", "contact 50 has exponent n = 2: solitary waves need n > 2"),
        ("[chain]\nbeads = 100\nexponent = { base = 2.5, segments = [{ from = 55, value = 3.0 }] }\n[initial]\nsolitary = { at = 50, velocity = 1.0 }", "contact 55 (beads 55-56) has exponent 3"),
        ("[chain]\nbeads = 100\nmass = { base = 1.0, segments = [{ from = 45, value = 2.0 }] }\n[initial]\nsolitary = { at = 50, velocity = 1.0 }", "bead 44 has mass 1 (bead 50 has 2)"),
        ("[chain]\nbeads = 100\nprecompression = 0.01\n[initial]\nsolitary = { at = 50, velocity = 1.0 }", "precompression 0.01: only the sonic vacuum"),
        ("[chain]\nbeads = 100\n[field]\ngravity = 1.0\n[initial]\nsolitary = { at = 50, velocity = 1.0 }", "external force -1"),
        ("[chain]\nbeads = 100\n[initial]\nsolitary = { at = 3, velocity = 1.0 }", "[initial].solitary.at: the wave needs beads -5..=11"),
        ("[chain]\nbeads = 100\n[initial]\nsolitary = { at = 100, velocity = 1.0 }", "bead 100 is outside the chain"),
        ("[chain]\nbeads = 100\n[initial]\nsolitary = [{ at = 30, velocity = 1.0 }, { at = 40, velocity = 1.0 }]", "[initial].solitary[1]: its support (beads 32..=48) overlaps the wave of [initial].solitary[0]"),
        ("[chain]\nbeads = 100\n[initial]\nsolitary = { at = 50, velocity_si = 1.0 }", "velocity_si"),
        ("[chain]\nbeads = 100\n[initial]\nsolitary = { at = 50, velocity = 1.0, energy = 1.0 }", "give only one of velocity, energy"),
        ("[chain]\nbeads = 100\n[initial]\nsolitary = { at = 50 }", "missing: give the peak velocity"),
        ("[chain]\nbeads = 100\n[initial]\nsolitary = { at = 50, velocity = -1.0 }", "[initial].solitary.velocity: must be > 0, got -1"),
        ("[chain]\nbeads = 100\n[initial]\nsolitary = { at = 50, velocity = 1.0, direction = \"up\" }", "expected \"right\" or \"left\""),
        ("[chain]\nbeads = 100\n[initial]\nsolitary = 1.0", "expected a table"),
        // a review's case: `equilibrium` replaced the wave's overlaps and kept its velocities
        ("[chain]\nbeads = 100\n[initial]\nsolitary = { at = 50, velocity = 1.0 }\nequilibrium = true", "would drop the wave's overlaps"),
    ];
    for (body, want) in cases {
        let e = scene_error(body);
        assert!(e.starts_with("bad.toml: [initial].solitary"), "{e}");
        assert!(e.contains(want), "expected {want:?} in: {e}");
        assert!(!e.contains('\n'), "one line: {e}");
    }
}

/// `energy = E` places the wave of energy E (relative 1e-12), `direction = "left"` mirrors it,
/// and a physical scene's `velocity_si` is converted with the scene's time scale (relative 1e-12).
#[test]
fn energy_direction_and_si_keys() {
    let s = scene(60, 3.0, "{ at = 30, energy = 2.5, direction = \"left\" }");
    let e = s.chain.energy(&s.u0, &s.v0);
    assert!((e / 2.5 - 1.0).abs() < 1e-12, "energy {e}");
    let peak = s.v0.iter().cloned().fold(f64::MAX, f64::min);
    assert_eq!(
        s.v0[30], peak,
        "left-moving: bead 30 has the most negative velocity"
    );
    let text = "[units]\nsystem = \"physical\"\nradius = 4.0e-3\nyoung = 2.26e11\npoisson = 0.3\ndensity = 7650.0\n\
                [chain]\nbeads = 60\nexponent = 3.0\n[initial]\nsolitary = { at = 30, velocity_si = 0.11 }\n[run]\nuntil = 1.0\n";
    let p = parse_str(text, Path::new("."), "si.toml").unwrap();
    let want = p.units.unwrap().velocity(0.11);
    assert!(
        (p.v0[30] / want - 1.0).abs() < 1e-12,
        "{} vs {want}",
        p.v0[30]
    );
}

/// The wider measurement of `validation/solitary.sh` (ignored in the suite: ~1 min): 300-bead
/// travel for n = 2.1 … 8 and v_m over 6 decades, and the same wave on the hybrid engine.
#[test]
#[ignore]
fn wide_validation() {
    for n in [2.1, 2.5, 3.0, 4.0, 6.0, 8.0] {
        for v_m in [1e-3, 1.0, 1e3] {
            travels_unchanged(n, v_m);
        }
    }
    // The default (hybrid) engine at its tightest practical tolerance, n = 2.5, 100 beads.
    let w = wave(2.5, 1.0);
    let s = scene(150, 2.5, "{ at = 20, velocity = 1.0 }");
    let cfg = RunConfig {
        engine: Engine::Hybrid,
        method: Method::Auto,
        rtol: 1e-12,
        atol: 1e-14,
        until: 100.0 / w.speed,
        every: Some(1.0 / w.speed),
        solver: SolverKind::Auto,
        max_steps: Some(20_000_000),
    };
    let rec = common::run(&s, &cfg).1;
    let last = rec.t.len() - 1;
    let shape = (0..50).fold(0.0_f64, |m, k| {
        m.max((rec.v[last][k + 100] - rec.v[0][k]).abs())
    });
    eprintln!("hybrid engine, n 2.5, 100 beads at rtol 1e-12: shape change {shape:.2e} of v_m");
    assert!(shape <= 1e-9, "hybrid shape change {shape:e}");
}

/// Energy of the beads behind bead `lo` (kinetic) and of the contacts between them.
fn energy_behind(s: &Scene, u: &[f64], v: &[f64], lo: usize) -> f64 {
    let ch = &s.chain;
    let mut e: f64 = (0..lo).map(|k| 0.5 * ch.mass[k] * v[k] * v[k]).sum();
    for k in 0..lo - 1 {
        e += ch.prefactor[k] * (u[k] - u[k + 1]).max(0.0).powf(ch.exponent[k]);
    }
    e
}

/// The preset `solitary_interface_3.0_2.5` reaches the interface (bead 50) with nothing behind
/// it: when its centre is at bead 40, the energy behind bead 30 is below 1e-9 of the total,
/// while the striker of `interface_3.0_2.5` (same energy) leaves more than 1e-4 behind its
/// pulse at the same place (the striker's transient).
#[test]
fn preset_wave_reaches_the_interface_without_a_transient() {
    let s = beadchain::scene::preset("solitary_interface_3.0_2.5").unwrap();
    let ch = &s.chain;
    let p = UnitProfile::compute(3.0).unwrap();
    let w = Wave::with_peak_velocity(p, ch.mass[20], ch.prefactor[20], s.v0[20]).unwrap();
    let t = 20.0 / w.speed;
    let e0 = ch.energy(&s.u0, &s.v0);
    let rec = run(&s, t, t);
    let mine = energy_behind(&s, &rec.u[1], &rec.v[1], 30);
    let striker = beadchain::scene::preset("interface_3.0_2.5").unwrap();
    // The striker's pulse needs about 40/c to reach bead 40 (it starts at bead 0).
    let rs = run(&striker, 2.0 * t, 2.0 * t);
    let e1 = striker.chain.energy(&striker.u0, &striker.v0);
    let at = (0..150)
        .max_by(|&i, &j| rs.v[1][i].total_cmp(&rs.v[1][j]))
        .unwrap();
    let theirs = energy_behind(&striker, &rs.u[1], &rs.v[1], at - 10);
    eprintln!(
        "behind the exact wave: {:.1e} of E; behind the striker's pulse (at bead {at}): {:.1e} of E",
        mine / e0,
        theirs / e1
    );
    assert!(mine <= 1e-9 * e0, "{mine:e} of {e0:e}");
    assert!(
        at > 30 && at < 50 && theirs > 1e-4 * e1,
        "striker: bead {at}, {theirs:e}"
    );
}
