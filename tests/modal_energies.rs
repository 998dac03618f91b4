//! Modal energy analysis (issue 35, part 3; `beadchain::studies::modal`,
//! `beadchain::analysis::modal`, `beadchain modes --snapshot`):
//!
//! - Parseval: with mass-orthonormal modes `Σ_j E_j = ½ vᵀMv + ½ (u−u*)ᵀK(u−u*)` for any state,
//!   on random seeded chains (walls or free ends, open contacts, a field) and random states;
//! - a small-amplitude run started in one linear mode keeps its energy in that mode (the
//!   engine's run, read back from the snapshot by the command line);
//! - a run of another chain (bead count) is a one-line error naming the file, and nothing is
//!   written.
#![allow(clippy::needless_range_loop)] // bead and mode indices in lock-step, as in the formulas

mod common;

use beadchain::model::{Chain, Wall};
use beadchain::studies::modal::ModalBasis;
use beadchain::studies::modes::{linearize, solve};
use common::npy::{parse_npy, parse_zip};
use common::{assert_ok, bc, Rng};

/// A random chain: masses in [0.5, 2), exponents in [2.1, 3.5), prefactors in [0.5, 2),
/// overlaps in [−0.005, 0.05) (some contacts open), each wall present at random, a random
/// field on half of them.
fn random_chain(rng: &mut Rng, nb: usize) -> Chain {
    let wall = |rng: &mut Rng| {
        (rng.unit() < 0.5).then(|| Wall {
            exponent: 2.5,
            prefactor: 1.0,
            precompression: rng.range(0.0, 0.05),
            restitution: None,
        })
    };
    Chain {
        mass: (0..nb).map(|_| rng.range(0.5, 2.0)).collect(),
        exponent: (1..nb).map(|_| rng.range(2.1, 3.5)).collect(),
        prefactor: (1..nb).map(|_| rng.range(0.5, 2.0)).collect(),
        precompression: Some((1..nb).map(|_| rng.range(-0.005, 0.05)).collect()),
        field: (rng.unit() < 0.5).then(|| (0..nb).map(|_| rng.range(-0.1, 0.1)).collect()),
        left_wall: wall(rng),
        right_wall: wall(rng),
        hard: None,
        damping: None,
    }
}

#[test]
fn modal_energies_sum_to_the_harmonic_energy_for_any_state() {
    let mut rng = Rng(0x5eed_0036);
    for trial in 0..10 {
        let nb = 5 + 11 * trial;
        let chain = random_chain(&mut rng, nb);
        let state: Vec<f64> = (0..nb).map(|_| rng.range(-0.01, 0.01)).collect();
        let lin = linearize(&chain, &state).unwrap();
        let modes = solve(&lin, None).unwrap();
        let basis = ModalBasis::new(&lin, &modes, &state).unwrap();
        let mut e = vec![0.0; nb];
        for sample in 0..5 {
            // Displacements and velocities of every scale, unrelated to any mode.
            let s = 10f64.powi(sample - 3);
            let u: Vec<f64> = state.iter().map(|x| x + s * rng.range(-1.0, 1.0)).collect();
            let v: Vec<f64> = (0..nb).map(|_| s * rng.range(-1.0, 1.0)).collect();
            basis.energies_into(&u, &v, &mut e);
            let sum: f64 = e.iter().sum();
            let h = basis.harmonic_energy(&u, &v);
            assert!(
                (sum - h).abs() <= 1e-12 * h,
                "trial {trial} ({nb} beads), sample {sample}: Σ E_j {sum:e} vs harmonic {h:e} (abs tol 0, rel tol 1e-12)"
            );
        }
    }
}

/// 16-bead precompressed dimer between soft walls (the `dimer_dispersion` chain, shorter)
/// started at equilibrium plus linear mode 5 of amplitude `1e-7` (the static overlaps are
/// 0.117), run by the dense engine at rtol 1e-12 for about 8 periods of the mode.
const SINGLE_MODE: &str = "[chain]\nbeads = 16\nmass = { alternate = [1.0, 0.5] }\n\
     precompression_force = 0.1\n[walls]\nleft = {}\nright = {}\n\
     [initial]\nequilibrium = true\nmode = { index = 5, amplitude = 1e-7 }\n\
     [run]\nuntil = 40.0\nevery = 0.25\nengine = \"dense\"\nmethod = \"dop853\"\nrtol = 1e-12\natol = 1e-20\n";

/// Parses the `--energies` CSV: the header's columns and the rows.
fn read_csv(path: &std::path::Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse::<f64>().unwrap()).collect())
        .collect();
    (head, rows)
}

#[test]
fn a_single_mode_run_keeps_its_energy_in_that_mode() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("c.toml"), SINGLE_MODE).unwrap();
    assert_ok(&bc(d.path(), &["run", "c.toml", "--out", "r.snap"]));
    let o = bc(
        d.path(),
        &[
            "modes",
            "c.toml",
            "--snapshot",
            "r.snap",
            "--energies",
            "e.csv",
        ],
    );
    assert_ok(&o);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("modal energies of r.snap: 161 frames from t = 0 to 40, 16 modes")
            && text.contains("most energetic modes (fraction): 5 (1.000000)")
            && text.contains("wrote e.csv"),
        "{text}"
    );
    let (head, rows) = read_csv(&d.path().join("e.csv"));
    let mut want: Vec<String> = vec!["t".into()];
    want.extend((0..16).map(|j| format!("E_{j}")));
    want.extend(["harmonic".into(), "energy".into()]);
    assert_eq!(head, want);
    assert_eq!(rows.len(), 161);
    let e5 = rows[0][1 + 5];
    assert!(e5 > 0.0);
    let (mut leak, mut drift, mut parseval, mut anharm) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for r in &rows {
        let e = &r[1..17];
        let others = (0..16).filter(|&j| j != 5).fold(0.0f64, |m, j| m.max(e[j]));
        leak = leak.max(others / e[5]);
        drift = drift.max((e[5] - e5).abs() / e5);
        let sum: f64 = e.iter().sum();
        parseval = parseval.max((sum - r[17]).abs() / r[17]);
        anharm = anharm.max((r[18] - r[17]).abs());
    }
    // Measured: leak 3.5e-13, drift 4.0e-11, Parseval 2.3e-15, |energy − harmonic| 4.0e-17
    // (E_5 = 4.7e-14; the chain's energy is 0.0795, so the difference of two energies carries
    // a round-off of a few 1e-17).
    assert!(
        leak <= 1e-9,
        "largest other mode {leak:e} of E_5 (abs tol 0, rel tol 1e-9)"
    );
    assert!(
        drift <= 1e-8,
        "E_5 varies by {drift:e} (abs tol 0, rel tol 1e-8)"
    );
    assert!(
        parseval <= 1e-12,
        "Σ E_j vs harmonic {parseval:e} (abs tol 0, rel tol 1e-12)"
    );
    // The harmonic energy differs from the chain's by the cubic terms, O(A/δ) ~ 1e-6 relative,
    // below the round-off of the chain's energy (25 ulps of 0.0795).
    assert!(
        anharm <= 2e-16 + 1e-5 * e5,
        "harmonic vs full energy {anharm:e} (abs tol 2e-16, rel tol 1e-5)"
    );
}

#[test]
fn energies_npz_holds_the_frames_and_modes() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("c.toml"), SINGLE_MODE).unwrap();
    assert_ok(&bc(d.path(), &["run", "c.toml", "--out", "r.snap"]));
    let o = bc(
        d.path(),
        &[
            "modes",
            "c.toml",
            "--snapshot",
            "r.snap",
            "--window",
            "1.5:3",
            "--energies",
            "e.npz",
        ],
    );
    assert_ok(&o);
    let zip = parse_zip(&std::fs::read(d.path().join("e.npz")).unwrap());
    let (shape, index) = parse_npy(&zip["index.npy"]);
    let m = index.len();
    assert!(
        m > 0 && m < 16 && index.contains(&8.0),
        "window modes {index:?}"
    );
    assert_eq!(shape, vec![m]);
    let (shape, _) = parse_npy(&zip["energy.npy"]);
    assert_eq!(shape, vec![161, m]);
    for name in ["t", "harmonic", "total"] {
        let (shape, _) = parse_npy(&zip[&format!("{name}.npy")]);
        assert_eq!(shape, vec![161], "{name}");
    }
    let (_, omega) = parse_npy(&zip["omega.npy"]);
    assert!(omega.iter().all(|w| (1.5..=3.0).contains(w)), "{omega:?}");
}

#[test]
fn a_run_of_another_chain_is_a_one_line_error_naming_the_file() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("c.toml"), SINGLE_MODE).unwrap();
    let short = SINGLE_MODE.replace("beads = 16", "beads = 12");
    std::fs::write(d.path().join("short.toml"), short).unwrap();
    assert_ok(&bc(d.path(), &["run", "short.toml", "--out", "short.snap"]));
    let cases: [(&[&str], &str); 3] = [
        (
            &[
                "modes",
                "c.toml",
                "--snapshot",
                "short.snap",
                "--energies",
                "e.csv",
                "--out",
                "m.npz",
            ],
            "short.snap: the run has 12 beads, the chain of the modes 16: modal energies need a run of the same chain",
        ),
        (
            &[
                "modes",
                "c.toml",
                "--snapshot",
                "short.snap",
                "--energies",
                "e.txt",
            ],
            "e.txt: --energies: expected a .csv or .npz file name",
        ),
        (
            &[
                "modes",
                "c.toml",
                "--snapshot",
                "short.snap",
                "--energies",
                "m.npz",
                "--out",
                "m.npz",
            ],
            "m.npz: --energies: is also the --out file",
        ),
    ];
    for (args, want) in cases {
        let o = bc(d.path(), args);
        assert!(!o.status.success(), "{args:?} succeeded");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(want) && err.trim().lines().count() == 1,
            "{args:?}: {err}"
        );
        for f in ["e.csv", "e.txt", "m.npz"] {
            assert!(!d.path().join(f).exists(), "{args:?} wrote {f}");
        }
    }
    // --energies needs --snapshot.
    let o = bc(d.path(), &["modes", "c.toml", "--energies", "e.csv"]);
    assert!(!o.status.success());
}
