//! `beadchain breather` (issue 35, part 4): the summary lines, the saved scene (it parses and
//! holds the breather as its initial state, which is periodic), and the one-line errors.

mod common;

use beadchain::experiments::breather::{max_diff, Breather, Shooter};
use common::{assert_ok, bc};

/// 12-bead precompressed dimer between soft walls (the `dimer_dispersion` preset, shorter).
const DIMER: &str = "[chain]\nbeads = 12\nmass = { alternate = [1.0, 0.5] }\nprecompression_force = 0.1\n\
                     [walls]\nleft = {}\nright = {}\n[initial]\nequilibrium = true\n[run]\nuntil = 1.0\n";

#[test]
fn breather_writes_a_scene_that_is_periodic() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("c.toml"), DIMER).unwrap();
    let o = bc(
        d.path(),
        &[
            "breather",
            "c.toml",
            "--frequency",
            "2.26",
            "--out",
            "b.toml",
        ],
    );
    assert_ok(&o);
    let text = String::from_utf8_lossy(&o.stdout);
    for line in [
        "from linear mode 6",
        "solution: omega 2.260000000000",
        "linearly stable",
        "wrote b.toml",
    ] {
        assert!(text.contains(line), "missing `{line}` in:\n{text}");
    }
    let scene = beadchain::scene::load(d.path().join("b.toml").to_str().unwrap()).unwrap();
    assert!(scene.v0.iter().all(|v| *v == 0.0));
    let period = 2.0 * std::f64::consts::PI / 2.26;
    assert!(
        (scene.run.until - 100.0 * period).abs() < 1e-9,
        "until {}",
        scene.run.until
    );
    // The saved displacements (shortest round-trip decimals) are a breather: the period map
    // returns to them within 1e-10 (max-norm over u and v).
    let sh = Shooter::new(&scene, 1e-12).unwrap();
    let b = Breather {
        u: scene.u0.clone(),
        period,
        half_residual: 0.0,
        iterations: 0,
    };
    let res = sh.period_residual(&b).unwrap();
    assert!(
        res <= 1e-10,
        "period-map residual of the saved scene {res:.3e}"
    );
    assert!(
        max_diff(&scene.u0, &sh.u_eq) > 1e-2,
        "the saved state is the equilibrium"
    );
}

#[test]
fn breather_errors_are_one_line() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("c.toml"), DIMER).unwrap();
    for (args, want) in [
        (
            vec!["breather", "c.toml", "--frequency", "-1"],
            "--frequency -1: expected a finite frequency > 0",
        ),
        (
            vec!["breather", "c.toml", "--frequency", "2.2", "--mode", "40"],
            "mode 40: the chain has 12 modes",
        ),
        (
            vec!["breather", "damped_striker", "--frequency", "1"],
            "damped_striker: breathers need",
        ),
        (
            vec!["breather", "striker", "--frequency", "1"],
            "striker: the chain has a zero mode",
        ),
    ] {
        let o = bc(d.path(), &args);
        assert!(!o.status.success(), "{args:?} succeeded");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            err.contains(want) && err.trim().lines().count() == 1,
            "{args:?}: {err}"
        );
    }
}

/// The defect of issue 35's audit: a continuation that collapses onto the equilibrium (a fixed
/// point of every period map) was reported as a solution, exit 0, with the scene written. The
/// `dimer_dispersion` chain's nonlinearity is soft at its band edges (the branch from the top
/// optical mode, 2.772, falls in frequency), so nothing continues above the optical band
/// (2.8) nor above an in-band mode (1.6 from the acoustic band's top mode 1.5992, just inside
/// the gap): each is a one-line error, non-zero exit, no file.
#[test]
fn breather_collapsed_to_the_equilibrium_is_refused() {
    let d = tempfile::tempdir().unwrap();
    for (w, edge) in [("2.8", "2.772158"), ("1.6", "1.599206")] {
        let o = bc(
            d.path(),
            &[
                "breather",
                "dimer_dispersion",
                "--frequency",
                w,
                "--out",
                "b.toml",
            ],
        );
        let err = String::from_utf8_lossy(&o.stderr);
        let text = String::from_utf8_lossy(&o.stdout);
        assert_eq!(o.status.code(), Some(2), "omega {w}: {text}\n{err}");
        for want in [
            format!("dimer_dispersion: the continuation to omega = {w} collapsed to the equilibrium at omega = "),
            format!("the branch from the linear mode at omega {edge} exists only below it (its frequency falls as its amplitude grows"),
        ] {
            assert!(err.contains(&want), "omega {w}: missing `{want}` in {err}");
        }
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(!text.contains("solution:"), "{text}");
        assert!(!d.path().join("b.toml").exists(), "omega {w}: wrote b.toml");
    }
}

/// A review's case: linear contacts (n = 2) have no amplitude-dependent frequency, so the seed is
/// the linear mode itself, and the continuation's predictor divided by its zero shift ("non-finite
/// state at t = 0"). A seed whose Newton tolerance is not small against its own velocities (an
/// SI scene's velocities of 1e-9 against the default 1e-11) is refused before Newton.
#[test]
fn breather_without_a_frequency_shift_says_so_instead_of_a_non_finite_state() {
    let d = tempfile::tempdir().unwrap();
    let linear = DIMER.replace("beads = 12\n", "beads = 8\nexponent = 2.0\n");
    std::fs::write(d.path().join("l.toml"), linear).unwrap();
    let o = bc(d.path(), &["breather", "l.toml", "--frequency", "1.9"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("no frequency shift") && !err.contains("non-finite"),
        "{err}"
    );
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    // the seed's velocities omega·A ≈ 1.9e-8, the default --tol 1e-11 is 5e-4 of them
    std::fs::write(d.path().join("c.toml"), DIMER).unwrap();
    let o = bc(
        d.path(),
        &[
            "breather",
            "c.toml",
            "--frequency",
            "2.25",
            "--seed-amplitude",
            "1e-8",
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains("Newton's tolerance 1.0e-11 is not small against the seed's velocities")
            && err.contains("lower --tol"),
        "{err}"
    );
}

/// `--out` in a directory that does not exist, or naming the scene file, is refused before the
/// Newton and Floquet work (it was refused only after it, minutes for a long chain).
#[test]
fn breather_out_is_checked_before_the_computation() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("c.toml"), DIMER).unwrap();
    for (out, want) in [
        ("no/such/dir/b.toml", "directory no/such/dir does not exist"),
        ("c.toml", "refusing to overwrite an input"),
    ] {
        let o = bc(
            d.path(),
            &["breather", "c.toml", "--frequency", "2.25", "--out", out],
        );
        let err = String::from_utf8_lossy(&o.stderr);
        let text = String::from_utf8_lossy(&o.stdout);
        assert_eq!(o.status.code(), Some(2), "{out}: {err}");
        assert!(err.contains(want), "{out}: {err}");
        assert!(
            !text.contains("seed:"),
            "{out}: computed before refusing\n{text}"
        );
    }
}
