//! `beadchain::sweep`: which keys a sweep may set together, and measures that cannot be made
//! (a velocity ratio the frames do not resolve or that has no window, the dense engine's
//! events) written as errors or empty fields, never as numbers.

use beadchain::sweep::csv::{read_result, split_fields};
use beadchain::sweep::{run_sweep, SweepError, SweepOptions, SweepSpec};
use std::path::Path;

fn spec(text: &str) -> Result<SweepSpec, SweepError> {
    SweepSpec::parse_str(text, Path::new("."), "test.toml")
}

/// The rows of a sweep run into a temporary file, split into fields.
fn rows(text: &str) -> Vec<Vec<String>> {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.csv");
    let opts = SweepOptions {
        out: out.clone(),
        jobs: Some(1),
        shard: None,
        max_runs: None,
        timing: false,
    };
    run_sweep(&spec(text).unwrap(), &opts, &|_, _| {}).unwrap();
    let f = read_result(&out, false).unwrap();
    f.rows.values().map(|r| split_fields(r).unwrap()).collect()
}

const DISORDER: &str = "scene = \"disorder_2.5_0.04\"\n[set]\n\"chain.beads\" = 60\n\
                        \"run.until\" = 100.0\n\"run.every\" = 20.0\n";

/// The defect: keys that overlap by prefix passed the one-place check, which compared whole
/// keys, so a `[[point]]`'s `chain.exponent` replaced the grid's `chain.exponent.random.eps`
/// (and a grid's `chain.exponent` the `[set]` one) and the CSV labelled byte-identical rows
/// with values that had no effect.
#[test]
fn sweep_keys_whose_whole_replaces_their_part_are_refused() {
    let e = spec(&format!(
        "{DISORDER}[grid]\n\"chain.exponent.random.eps\" = [0.02, 0.08]\n\
         [[point]]\n\"chain.exponent\" = 3.0\n"
    ))
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("[[point]].\"chain.exponent\": overlaps [grid].\"chain.exponent.random.eps\""),
        "{e}"
    );
    let e = spec(&format!(
        "{DISORDER}\"chain.exponent.random.eps\" = 0.5\n[grid]\n\"chain.exponent\" = [2.5, 3.0]\n"
    ))
    .unwrap_err()
    .to_string();
    assert!(e.contains("\"chain.exponent\" is written after"), "{e}");
    // the whole first, then a part of it: each run writes both, the part last (kept)
    let s = spec(&format!(
        "{DISORDER}\"chain.exponent\" = {{ random = {{ mean = 2.5, eps = 0.0 }} }}\n\
         [grid]\n\"chain.exponent.random.eps\" = [0.02, 0.08]\n"
    ))
    .unwrap();
    let a = s.scene_for(&s.runs()[0]).unwrap().chain.exponent;
    let b = s.scene_for(&s.runs()[1]).unwrap().chain.exponent;
    assert_ne!(a, b);
    // a review's follow-up: a point's whole and part are written in sorted order (the whole
    // first) whatever order the points come in; a point with only the part listed first was
    // refused
    let part = "[[point]]\n\"chain.exponent.random.eps\" = 0.02\n";
    let both = "[[point]]\n\"chain.exponent\" = { random = { mean = 2.5, eps = 0.0 } }\n\
                \"chain.exponent.random.eps\" = 0.08\n";
    for points in [format!("{part}{both}"), format!("{both}{part}")] {
        let s = spec(&format!("{DISORDER}{points}")).unwrap();
        let runs = s.runs();
        let eps = |i: usize| s.scene_for(&runs[i]).unwrap().chain.exponent;
        assert_ne!(eps(0), eps(1));
    }
}

/// A striker into 30 beads; `impurity = 12` (window beads 6..9), frames every `every`.
fn striker(every: f64, engine: &str) -> String {
    format!(
        "scene = \"striker\"\n[set]\n\"chain.beads\" = 30\n\"run.until\" = 20.0\n\
         \"run.every\" = {every:?}\n[grid]\n\"run.engine\" = [\"{engine}\"]\n[measure]\nimpurity = 12\n"
    )
}

/// The defect: `v_ratio` was the ratio of the largest samples however sparse the frames. With
/// a frame every 5 time units the pulse (a few beads wide, about a bead per unit time) passes
/// each bead between two frames; the row is now an error and the field empty. Every 0.05
/// resolves it.
#[test]
fn sweep_v_ratio_of_peaks_the_frames_miss_is_an_error() {
    let r = &rows(&striker(0.05, "hybrid"))[0];
    assert_eq!(r[2], "ok", "{r:?}");
    assert!(r.last().unwrap().parse::<f64>().is_ok(), "{r:?}");
    let r = &rows(&striker(5.0, "hybrid"))[0];
    assert!(
        r[2].starts_with("error: v_ratio: not resolved by the frames: v_in"),
        "{r:?}"
    );
    assert_eq!(r.last().unwrap(), "", "{r:?}");
}

/// The defect: `impurity = K` with `K ≤ 6` has an empty window (`min(K/2, 20)..K−3`), and the
/// row said `ok` with `v_ratio` NaN (0/0).
#[test]
fn sweep_v_ratio_without_a_window_is_an_error_not_nan() {
    let text = striker(0.05, "hybrid").replace("impurity = 12", "impurity = 6");
    let r = &rows(&text)[0];
    assert_eq!(
        r[2], "error: v_ratio: no incoming velocity before the interface",
        "{r:?}"
    );
    assert_eq!(r.last().unwrap(), "", "{r:?}");
}

/// The defect: the dense engine logs no events, yet its rows said `events` 0 (the hybrid row
/// of the same run: 47). The field is now empty.
#[test]
fn sweep_dense_rows_leave_events_empty() {
    let r = &rows(&striker(0.05, "dense").replace("impurity = 12", "fragments = true"))[0];
    assert_eq!(r[2], "ok", "{r:?}");
    // run, engine, status, t_end, energy_error, steps, events, fragments
    assert!(r[5].parse::<u64>().unwrap() > 0, "{r:?}");
    assert_eq!(r[6], "", "{r:?}");
    let r = &rows(&striker(0.05, "hybrid").replace("impurity = 12", "fragments = true"))[0];
    assert!(r[6].parse::<u64>().unwrap() > 0, "{r:?}");
}
