//! Tests of the work–precision study on small striker chains.

use super::*;
use crate::integrate::test_util;
use crate::model::Chain;
use crate::scene::RunSettings;

/// `n` unit-mass beads, exponent 2.5, prefactor 1, bead 0 striking at 1.
fn striker(n: usize, until: f64) -> Scene {
    let (u0, v0) = test_util::striker(n, 1.0);
    Scene {
        name: format!("striker{n}"),
        description: String::new(),
        chain: Chain {
            prefactor: vec![1.0; n - 1],
            ..test_util::uniform_chain(n)
        },
        u0,
        v0,
        run: RunSettings {
            until,
            ..Default::default()
        },
        seed: 0,
        units: None,
    }
}

fn options() -> AccuracyOptions {
    AccuracyOptions {
        engines: vec![Engine::Hybrid, Engine::Dense],
        methods: vec![Method::Radau5, Method::Verlet],
        rtols: vec![1e-5, 1e-7, 1e-9],
        verlet_steps: vec![0.02, 0.01],
        ..AccuracyOptions::default()
    }
}

#[test]
fn study_measures_errors_against_the_reference_and_writes_files() {
    let scene = striker(12, 25.0);
    let dir = tempfile::tempdir().expect("tempdir");
    let mut opts = options();
    opts.out_dir = Some(dir.path().join("acc"));
    let rep = accuracy_study(&scene, &opts).expect("study runs");
    assert_eq!(rep.rows.len(), 2 * (3 + 2));
    assert!(rep.rows.iter().all(|r| r.failure.is_none()));
    // The tightest dense Radau run is the reference: error exactly 0 (deterministic runs).
    let refs: Vec<_> = rep.rows.iter().filter(|r| r.is_reference).collect();
    assert_eq!(refs.len(), 1);
    assert_eq!(refs[0].error, 0.0);
    assert_eq!(rep.reference.rtol, 1e-9);
    assert_eq!(rep.reference.check_rtol, 1e-7);
    // The check run differs from the reference, but little (rel 1e-4 at rtol 1e-7).
    let chk = rep.reference.check_err_u.max(rep.reference.check_err_v);
    assert!(chk > 0.0 && chk < 1e-4, "reference check {chk:e}");
    // Adaptive errors shrink as rtol tightens (hybrid radau5).
    let hyb: Vec<f64> = rep
        .rows
        .iter()
        .filter(|r| r.engine == Engine::Hybrid && r.method == Method::Radau5)
        .map(|r| r.error)
        .collect();
    assert!(hyb[0] > hyb[1] && hyb[1] > hyb[2], "hybrid errors {hyb:?}");
    // Verlet: halving the step divides the error by ≈ 4 (order ≈ 2 with Hertz contacts:
    // allowed 2.5..6).
    let ver: Vec<&AccuracyRow> = rep
        .rows
        .iter()
        .filter(|r| r.engine == Engine::Dense && r.method == Method::Verlet)
        .collect();
    let ratio = ver[0].error / ver[1].error;
    assert!((2.5..=6.0).contains(&ratio), "Verlet error ratio {ratio}");
    let tau = rep.tau;
    // dt = s·τ (rel 1e-15).
    assert!((ver[1].verlet_dt.unwrap_or(0.0) - 0.01 * tau).abs() <= 1e-15 * tau);
    for r in &rep.rows {
        // Chain separated by t = 25 (potential energy ~0): KE error ≈ total energy error
        // (abs 1e-6).
        assert!((r.ke_error - r.energy_error).abs() < 1e-6, "{r:?}");
        assert!(r.wall_seconds > 0.0 && r.steps > 0 && r.bead_steps >= r.steps);
    }
    // Hybrid runs count events; dense ones have none.
    assert!(rep
        .rows
        .iter()
        .all(|r| (r.engine == Engine::Hybrid) == (r.events > 0)));
    // Files: CSV with a header and one line per row; non-empty SVG and PNG.
    let csv = std::fs::read_to_string(dir.path().join("acc/accuracy.csv")).expect("csv");
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], CSV_HEADER);
    assert_eq!(lines.len(), 1 + rep.rows.len());
    let cols = CSV_HEADER.split(',').count();
    assert!(lines.iter().all(|l| l.split(',').count() == cols));
    for f in ["accuracy.svg", "accuracy.png"] {
        let len = std::fs::metadata(dir.path().join("acc").join(f)).map(|m| m.len());
        assert!(len.unwrap_or(0) > 1000, "{f} missing or tiny");
    }
    assert!(format_table(&rep).contains("(reference)"));
}

#[test]
fn separate_reference_tolerance_is_checked_against_the_tightest_study_run() {
    let scene = striker(6, 15.0);
    let mut opts = options();
    opts.engines = vec![Engine::Dense];
    opts.methods = vec![Method::Radau5];
    opts.rtols = vec![1e-6, 1e-8];
    opts.reference_rtol = Some(1e-11);
    let rep = accuracy_study(&scene, &opts).expect("study runs");
    assert_eq!(rep.reference.check_rtol, 1e-8);
    assert!(rep.rows.iter().all(|r| !r.is_reference && r.error > 0.0));
    // Error at rtol 1e-8 below 1e-5 (rel), and above the reference's own level (1e-12).
    assert!(rep.rows[1].error < 1e-5 && rep.rows[1].error > 1e-12);
}

#[test]
fn failed_runs_are_reported_in_their_row() {
    let scene = striker(6, 15.0);
    let mut opts = options();
    opts.engines = vec![Engine::Dense];
    opts.max_steps = Some(2000);
    opts.rtols = vec![1e-4, 1e-5];
    opts.verlet_steps = vec![0.001];
    let rep = accuracy_study(&scene, &opts).expect("study runs");
    let v = rep.rows.iter().find(|r| r.method == Method::Verlet);
    let msg = v.and_then(|r| r.failure.clone()).unwrap_or_default();
    assert!(
        msg.contains("budget"),
        "Verlet at 0.001τ must exceed 2000 steps: {msg}"
    );
    assert!(to_csv(&rep).contains("failed: "));
}

#[test]
fn bad_options_are_typed_errors() {
    let scene = striker(4, 5.0);
    let cases: Vec<AccuracyOptions> = vec![
        AccuracyOptions {
            rtols: vec![],
            ..options()
        },
        AccuracyOptions {
            rtols: vec![2.0],
            ..options()
        },
        AccuracyOptions {
            verlet_steps: vec![0.0],
            ..options()
        },
        AccuracyOptions {
            repeat: 0,
            ..options()
        },
        AccuracyOptions {
            until: Some(f64::NAN),
            ..options()
        },
        AccuracyOptions {
            engines: vec![],
            ..options()
        },
    ];
    for o in cases {
        assert!(
            matches!(accuracy_study(&scene, &o), Err(AccuracyError::Options(_))),
            "expected an options error for {o:?}"
        );
    }
}

#[test]
fn median_of_even_and_odd_lists() {
    assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
    assert_eq!(median(&mut [4.0, 1.0, 2.0, 3.0]), 2.5);
}

#[test]
fn kinetic_energy_error_is_not_reported_before_the_chain_separates() {
    // 30 beads to t = 8: the solitary wave is mid-chain, contacts are compressed, so the
    // appendix-A kinetic-energy measure does not apply (it would read ~0.1-1, not an error).
    let scene = striker(30, 8.0);
    let mut opts = options();
    opts.engines = vec![Engine::Dense];
    opts.methods = vec![Method::Radau5];
    opts.rtols = vec![1e-6, 1e-8];
    let rep = accuracy_study(&scene, &opts).expect("study runs");
    assert!(
        rep.rows.iter().all(|r| r.ke_error.is_nan()),
        "{:?}",
        rep.rows
    );
    assert!(rep.rows.iter().all(|r| r.energy_error < 1e-5));
    assert!(format_table(&rep).contains("n/a"));
}
