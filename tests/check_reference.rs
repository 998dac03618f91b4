//! `beadchain check` where the reference's own error, not the scene, separates its runs at
//! rtol and rtol/100 (`src/check.rs` module docs), found by an adversarial review against an
//! independent SciPy integration.

use beadchain::check::check;
use beadchain::engine::RunConfig;
use beadchain::scene;
use std::path::Path;

/// The defect: on this 4-bead scene (gaps, a soft wall, a field) the dense engine's DOP853 is
/// 3000·rtol off at rtol 1e-10 (its steps cross contact kinks; the hybrid engine is 10·rtol
/// off), so its runs at rtol and rtol/100 differ by 900·rtol and `check` widened its
/// trajectory bound to 10× that, 9000·rtol, letting a hybrid error of that size pass. The
/// hybrid engine at rtol and rtol/100 agrees to 3·rtol, so the check now names the
/// reference's error and judges the trajectory against the reference at rtol/100, within
/// `tol` = 1000·rtol (measured: 4.6·rtol).
#[test]
fn check_tells_the_references_own_error_from_the_scenes_sensitivity() {
    let s = scene::parse_str(
        include_str!("common/kinked_four.toml"),
        Path::new("."),
        "kinked_four",
    )
    .unwrap();
    let mut cfg = RunConfig::from_scene(&s);
    cfg.rtol = 1e-10;
    cfg.atol = 1e-14;
    let tol = 1000.0 * cfg.rtol;
    let rep = check(&s, &s, &cfg, tol).unwrap();
    let spread = rep
        .hybrid_spread
        .expect("the reference's own error is found");
    assert!(spread <= 100.0 * cfg.rtol, "{spread:e}");
    assert!(!rep.sensitive);
    let traj = &rep.criteria[0];
    assert!(traj.what.contains("at rtol/100"), "{}", traj.what);
    assert!(traj.bound <= tol, "{traj:?}");
    assert!(traj.value <= 50.0 * cfg.rtol, "{traj:?}");
    assert!(rep.passed());
}
