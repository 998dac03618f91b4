//! `beadchain validate --quick`: a reduced, deterministic version of `validation/REPORT.md`
//! (the paper's Secs. 3, 5.1, 5.2), a few seconds in release. Each [`Check`] compares one of our
//! numbers with the paper's statement and an acceptance range chosen from that statement.

use super::paper::{
    collapse_point, disorder_gamma, impurity_ratio, interface_run, paper_gamma, reflection_grid,
    PaperError,
};

/// One reproduced quantity.
#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    /// What is compared (and the paper's section/figure).
    pub name: String,
    /// Our value.
    pub ours: f64,
    /// The paper's value or statement.
    pub paper: String,
    /// Accepted range `[lo, hi]` for `ours`.
    pub range: (f64, f64),
    /// Hybrid-engine failures met (the dense engine was used instead).
    pub fallbacks: usize,
}

impl Check {
    /// Is `ours` inside the accepted range?
    pub fn pass(&self) -> bool {
        self.ours >= self.range.0 && self.ours <= self.range.1
    }
}

fn check(name: &str, ours: f64, paper: String, range: (f64, f64), fallbacks: usize) -> Check {
    Check {
        name: name.into(),
        ours,
        paper,
        range,
        fallbacks,
    }
}

/// Which checks to run: `tiny` runs only the cheapest (interface 3.0 → 2.5 and one impurity), for
/// tests.
pub fn quick_checks(tiny: bool) -> Result<Vec<Check>, PaperError> {
    let mut out = Vec::new();
    reflection_and_impurity(&mut out)?;
    if tiny {
        return Ok(out);
    }
    secondary_pulses_and_long_impurity(&mut out)?;
    collapse_and_disorder(&mut out)?;
    Ok(out)
}

/// `1` when the hybrid engine failed and the dense one was used (the table's fallback column).
fn fb(f: &Option<String>) -> usize {
    usize::from(f.is_some())
}

/// Sec. 3.2 (interface 3.0 → 2.5: reflection, near-rectangular transmitted pulse) and Sec. 5.1
/// (impurity s = 1): the `tiny` set.
fn reflection_and_impurity(out: &mut Vec<Check>) -> Result<(), PaperError> {
    // Sec. 3.2: 3.0 -> 2.5, strong reflection and a near-rectangular transmitted pulse.
    let r = interface_run(3.0, 2.5, 150, 50)?;
    let refl = r
        .pulses
        .iter()
        .filter(|(p, _)| p.peak_velocity < 0.0 && p.peak_bead > 5)
        .map(|(_, e)| *e)
        .fold(0.0, f64::max);
    let f = fb(&r.info.hybrid_failure);
    out.push(check(
        "3.0->2.5: reflected pulse energy / E (Fig. 6)",
        refl,
        "significant reflection".into(),
        (0.3, 0.7),
        f,
    ));
    out.push(check(
        "3.0->2.5: near-rectangular transmitted pulse, beads (Fig. 6)",
        r.plateau.map_or(0.0, |p| p.1 as f64),
        "8-9 beads".into(),
        (7.0, 10.0),
        f,
    ));
    // Sec. 5.1: impurity of s = 1 with n = 4, dn = -1.5 -> two-body value 1/3.
    let (ratio, info) = impurity_ratio(4.0, 1, -1.5)?;
    out.push(check(
        "impurity n=4 s=1 dn=-1.5: |v_out/v_in| (Fig. 18)",
        ratio,
        "two-body m on 2m: 1/3".into(),
        (1.0 / 3.0 * 0.97, 1.0 / 3.0 * 1.03),
        fb(&info.hybrid_failure),
    ));
    Ok(())
}

/// Sec. 3.1 (interface 3.0 → 3.5: secondary pulses) and Sec. 5.1 (impurity s = 5).
fn secondary_pulses_and_long_impurity(out: &mut Vec<Check>) -> Result<(), PaperError> {
    // Sec. 3.1: 3.0 -> 3.5, secondary pulses an order of magnitude smaller.
    let r = interface_run(3.0, 3.5, 150, 50)?;
    let f = fb(&r.info.hybrid_failure);
    let primary = r
        .pulses
        .iter()
        .map(|(p, _)| p.peak_velocity)
        .fold(0.0, f64::max);
    let secondary = r
        .pulses
        .iter()
        .filter(|(p, _)| p.peak_velocity > 0.0 && p.peak_velocity < primary)
        .map(|(p, _)| p.peak_velocity)
        .fold(0.0, f64::max);
    out.push(check(
        "3.0->3.5: secondary transmitted / primary peak v (Fig. 4)",
        secondary / primary,
        "about 1/10".into(),
        (0.02, 0.3),
        f,
    ));
    out.push(check(
        "3.0->3.5: reflected / primary transmitted peak v (Fig. 4)",
        r.v_out / primary,
        "about 1/10".into(),
        (0.01, 0.3),
        f,
    ));
    // Sec. 5.1: s = 5 -> 5/7.
    let (ratio, info) = impurity_ratio(4.0, 5, -1.5)?;
    out.push(check(
        "impurity n=4 s=5 dn=-1.5: |v_out/v_in| (Fig. 18)",
        ratio,
        "two-body m on 6m: 5/7".into(),
        (5.0 / 7.0 * 0.97, 5.0 / 7.0 * 1.03),
        fb(&info.hybrid_failure),
    ));
    Ok(())
}

/// Sec. 3.2 (collapse point of the `E_refl` grid) and Sec. 5.2 (decay rate in a disordered
/// chain against eq. 21).
fn collapse_and_disorder(out: &mut Vec<Check>) -> Result<(), PaperError> {
    // Sec. 3.2: collapse point on a 4 x 4 grid (120 beads).
    let ns = [2.5, 3.0, 3.5, 4.0];
    let (pts, fbs) = reflection_grid(&ns, 120, 50)?;
    out.push(check(
        "collapse point p of zeta = (n1-p)/(n2-p), 4x4 grid (Fig. 7)",
        collapse_point(&pts).map_or(f64::NAN, |c| c.0),
        "1.65".into(),
        (1.4, 2.2),
        fbs,
    ));
    // Sec. 5.2: disorder n = 2.5 + 0.04 r, N = 200.
    let (fit, info) = disorder_gamma(2.5, 0.04, 1, 200)?;
    let g = paper_gamma(0.04, 2.5);
    out.push(check(
        "disorder n=2.5 eps=0.04 N=200: gamma / eq. 21 (Table 2)",
        fit.gamma / g,
        format!("gamma = {g:.4e} (ratio 1)"),
        (0.67, 1.5),
        fb(&info.hybrid_failure),
    ));
    Ok(())
}

/// The checks as a Markdown table (deterministic: no timings).
pub fn checks_markdown(checks: &[Check]) -> String {
    let mut s = String::from(
        "| check | ours | paper | accepted | dense fallbacks | verdict |\n|---|---|---|---|---|---|\n",
    );
    for c in checks {
        s.push_str(&format!(
            "| {} | {:.4} | {} | [{:.4}, {:.4}] | {} | {} |\n",
            c.name.replace('|', "\\|"),
            c.ours,
            c.paper,
            c.range.0,
            c.range.1,
            c.fallbacks,
            if c.pass() { "agrees" } else { "DIFFERS" }
        ));
    }
    s
}
