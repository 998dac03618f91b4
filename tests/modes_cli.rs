//! `beadchain modes` and `beadchain plot dispersion` (issue 35, part 3): the `.npz` holds the
//! closed-form frequencies of a precompressed chain between walls, the summary states the
//! boundary conditions and zero-stiffness contacts, the dispersion prints the dimer's gap.

mod common;

use common::npy::{parse_npy, parse_zip};
use common::{assert_ok, bc};
use std::f64::consts::PI;

/// Uniform chain of 30 beads (m = 1), n = 2.5, a = 1, Δ = 0.04, walls of the same law and
/// overlap: fixed ends with `K = n (n−1) a Δ^{n−2}`, at rest already.
const FIXED: &str =
    "[chain]\nbeads = 30\nprecompression = 0.04\n[walls]\nleft = { precompression = 0.04 }\n\
                     right = { precompression = 0.04 }\n[run]\nuntil = 1.0\n";

#[test]
fn modes_npz_holds_the_closed_form_frequencies() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("c.toml"), FIXED).unwrap();
    let o = bc(d.path(), &["modes", "c.toml", "--out", "m.npz"]);
    assert_ok(&o);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("left end: fixed through the soft wall"),
        "{text}"
    );
    assert!(
        text.contains("contacts with zero stiffness: none"),
        "{text}"
    );
    let zip = parse_zip(&std::fs::read(d.path().join("m.npz")).unwrap());
    let (shape, omega) = parse_npy(&zip["omega.npy"]);
    assert_eq!(shape, vec![30]);
    let (shape, _) = parse_npy(&zip["shapes.npy"]);
    assert_eq!(shape, vec![30, 30]);
    let k = 2.5 * 1.5 * 0.04f64.sqrt();
    let w0 = 2.0 * k.sqrt();
    for (j, w) in omega.iter().enumerate() {
        let exact = w0 * ((j + 1) as f64 * PI / 62.0).sin();
        assert!(
            (w - exact).abs() <= 1e-12 * w0,
            "mode {j}: {w} vs {exact} (abs tol 1e-12·ω_max)"
        );
    }
    let (_, counts) = parse_npy(&zip["dos_counts.npy"]);
    assert_eq!(counts.iter().sum::<f64>(), 30.0);
    // A window keeps the modes inside it.
    let o = bc(
        d.path(),
        &["modes", "c.toml", "--window", "0:0.5", "--list"],
    );
    assert_ok(&o);
    let text = String::from_utf8_lossy(&o.stdout);
    let inside = omega.iter().filter(|w| **w <= 0.5).count();
    assert!(
        text.contains(&format!("modes with omega in [0, 0.5]: {inside}")),
        "{text}"
    );
}

#[test]
fn modes_of_a_sonic_vacuum_say_so() {
    let o = bc(std::path::Path::new("."), &["modes", "striker"]);
    assert_ok(&o);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("left end: free (no wall)"), "{text}");
    assert!(
        text.contains("sonic vacuum") && text.contains("99 of 99"),
        "{text}"
    );
}

#[test]
fn dispersion_of_a_dimer_prints_its_gap_and_draws_it() {
    let d = tempfile::tempdir().unwrap();
    let dimer = FIXED.replace(
        "beads = 30\n",
        "beads = 30\nmass = { alternate = [1.0, 0.5] }\n",
    );
    std::fs::write(d.path().join("d.toml"), dimer).unwrap();
    let o = bc(
        d.path(),
        &[
            "plot",
            "dispersion",
            "d.toml",
            "--out",
            "disp.svg",
            "--points",
            "11",
        ],
    );
    assert_ok(&o);
    let text = String::from_utf8_lossy(&o.stdout);
    let k = 2.5 * 1.5 * 0.04f64.sqrt();
    let (lo, hi) = ((2.0 * k).sqrt(), (2.0 * k / 0.5).sqrt());
    assert!(
        text.contains(&format!("gap: omega from {lo:.12e} to {hi:.12e}")),
        "{text}\n{lo:.12e} {hi:.12e}"
    );
    assert!(d.path().join("disp.svg").is_file());
    // A chain without a period needs --cell.
    let random = FIXED.replace(
        "beads = 30\n",
        "beads = 30\nmass = { random = { mean = 1.0, eps = 0.3 } }\n",
    );
    std::fs::write(d.path().join("r.toml"), random).unwrap();
    let o = bc(
        d.path(),
        &["plot", "dispersion", "r.toml", "--out", "r.svg"],
    );
    assert_eq!(o.status.code(), Some(2), "bad input exits 2");
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("no period found") && e.contains("--cell"), "{e}");
}

/// A free chain squeezed by two opposite forces: one rigid-translation mode (ω² ≈ 1e-16).
const SQUEEZED: &str = "[chain]\nbeads = 8\nmass = [1.0, 2.0, 1.0, 0.5, 1.0, 3.0, 1.0, 1.2]\n\
     [field]\nforce = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0]\n[initial]\nequilibrium = true\n\
     [run]\nuntil = 10.0\n";

#[test]
fn zero_mode_count_does_not_depend_on_the_window() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("s.toml"), SQUEEZED).unwrap();
    for extra in [&[][..], &["--window", "0:1e-3"][..]] {
        let mut args = vec!["modes", "s.toml"];
        args.extend_from_slice(extra);
        let o = bc(d.path(), &args);
        assert_ok(&o);
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(
            text.contains("omega_max^2): 1\n"),
            "{extra:?}: one zero mode expected\n{text}"
        );
    }
}

#[test]
fn empty_window_says_no_modes_not_every_mode_at_zero() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("c.toml"), FIXED).unwrap();
    // the closed-form band of FIXED tops out at 2·sqrt(K) ≈ 1.55: nothing above 5
    let o = bc(d.path(), &["modes", "c.toml", "--window", "5:6"]);
    assert_ok(&o);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("modes with omega in [5, 6]: 0"), "{text}");
    assert!(
        text.contains("density of states: no modes in the window")
            && !text.contains("every mode at omega = 0"),
        "{text}"
    );
}

#[test]
fn bins_out_of_range_are_refused_before_any_work() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("c.toml"), FIXED).unwrap();
    for bins in ["0", "1000000000000000"] {
        let o = bc(
            d.path(),
            &["modes", "c.toml", "--bins", bins, "--out", "m.npz"],
        );
        assert_eq!(o.status.code(), Some(2), "--bins {bins}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("--bins"), "--bins {bins}: {err}");
        assert!(!d.path().join("m.npz").exists());
    }
}

#[test]
fn dispersion_start_beyond_the_chain_is_named() {
    let d = tempfile::tempdir().unwrap();
    let o = bc(
        d.path(),
        &[
            "plot",
            "dispersion",
            "dimer_dispersion",
            "--start",
            "100000",
            "--out",
            "x.png",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("the cell's first bead 100000 (start) is past the last contact"),
        "{err}"
    );
}
