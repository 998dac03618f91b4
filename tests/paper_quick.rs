//! Tiny subset of `beadchain validate --quick` through the library (release: well under 30 s):
//! interface 3.0 -> 2.5 (strong reflection, 8-9 bead plateau) and the s = 1 impurity two-body
//! limit (paper Secs. 3.2 and 5.1).

use beadchain::experiments::quick::{checks_markdown, quick_checks};

#[test]
fn tiny_quick_checks_agree_with_the_paper() {
    let checks = quick_checks(true).expect("the generated scenes run");
    assert_eq!(checks.len(), 3);
    for c in &checks {
        // acceptance ranges are part of each check (e.g. impurity: 1/3 within ±3 % relative)
        assert!(c.pass(), "{}", checks_markdown(&checks));
    }
    // deterministic: a second run gives the identical table
    let again = quick_checks(true).expect("second run");
    assert_eq!(checks_markdown(&checks), checks_markdown(&again));
}
