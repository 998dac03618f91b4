//! Resuming a sweep by content (issue 36, item 3): a rerun skips the runs whose result the
//! finished `OUT` already holds (content keys in `OUT.meta`), rewrites nothing when nothing
//! changed, and runs again exactly the runs whose scene (or measures) changed.

use beadchain::sweep::csv::{read_keys, read_result};
use beadchain::sweep::{merge, run_sweep, Shard, SweepOptions, SweepSpec};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::SystemTime;

/// 4 x 2 grid x 2 seeds = 16 runs of 30 beads (random masses from bead 5 on), as tests/sweep.rs.
const SMALL: &str = include_str!("common/small_sweep.toml");

fn spec_in(text: &str, dir: &Path) -> SweepSpec {
    SweepSpec::parse_str(text, dir, "test.toml").unwrap()
}

fn spec(text: &str) -> SweepSpec {
    spec_in(text, Path::new("."))
}

fn opts(out: &Path) -> SweepOptions {
    SweepOptions {
        out: out.to_path_buf(),
        jobs: Some(2),
        shard: None,
        max_runs: None,
        timing: false,
    }
}

fn none(_: usize, _: usize) {}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap()
}

fn meta(p: &Path) -> PathBuf {
    PathBuf::from(format!("{}.meta", p.display()))
}

fn mtime(p: &Path) -> SystemTime {
    std::fs::metadata(p).unwrap().modified().unwrap()
}

#[test]
fn rerun_of_a_finished_sweep_runs_nothing_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.csv");
    let s = spec(SMALL);
    let first = run_sweep(&s, &opts(&out), &none).unwrap();
    assert_eq!((first.ran, first.skipped, first.written), (16, 0, true));
    let (csv, m) = (read(&out), read(&meta(&out)));
    let keys = read_keys(&out);
    assert_eq!(keys.len(), 16, "{m}");
    // every run has its own scene (eps = 0 runs of seeds 3 and 4 differ in the stored seed)
    let distinct: std::collections::BTreeSet<_> = keys.values().collect();
    assert_eq!(distinct.len(), 16, "{m}");
    let (t_csv, t_meta) = (mtime(&out), mtime(&meta(&out)));
    std::thread::sleep(std::time::Duration::from_millis(20));
    let again = run_sweep(&s, &opts(&out), &none).unwrap();
    assert_eq!(
        (
            again.runs,
            again.resumed,
            again.skipped,
            again.ran,
            again.complete
        ),
        (16, 0, 16, 0, true),
        "{again:?}"
    );
    assert!(!again.written, "{again:?}");
    assert_eq!(read(&out), csv);
    assert_eq!(read(&meta(&out)), m);
    assert_eq!((mtime(&out), mtime(&meta(&out))), (t_csv, t_meta));
}

#[test]
fn a_changed_value_reruns_only_the_runs_it_changes() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.csv");
    run_sweep(&spec(SMALL), &opts(&out), &none).unwrap();
    let before = read_result(&out, false).unwrap();
    // eps 0.4 -> 0.3: runs 12..=15 (the last eps, 2 strikers x 2 seeds) change
    let changed_text = SMALL.replace("0.2, 0.4]", "0.2, 0.3]");
    let changed = spec(&changed_text);
    let sum = run_sweep(&changed, &opts(&out), &none).unwrap();
    assert_eq!(
        (sum.skipped, sum.ran, sum.written),
        (12, 4, true),
        "{sum:?}"
    );
    let after = read_result(&out, false).unwrap();
    for i in 0..12 {
        assert_eq!(after.rows[&i], before.rows[&i], "run {i}");
    }
    for i in 12..16 {
        assert!(
            after.rows[&i].starts_with(&format!("{i},0.3,")),
            "{}",
            after.rows[&i]
        );
        assert_ne!(after.rows[&i], before.rows[&i], "run {i}");
    }
    // the same bytes as a fresh run of the changed sweep (CSV and sidecar)
    let fresh = dir.path().join("fresh.csv");
    run_sweep(&changed, &opts(&fresh), &none).unwrap();
    assert_eq!(read(&out), read(&fresh));
    assert_eq!(read(&meta(&out)), read(&meta(&fresh)));
    // reordered grid values: nothing runs, the rows move to their new indices
    let reordered = spec(&changed_text.replace("[0.0, 0.1, 0.2, 0.3]", "[0.3, 0.2, 0.1, 0.0]"));
    let sum = run_sweep(&reordered, &opts(&out), &none).unwrap();
    assert_eq!((sum.skipped, sum.ran), (16, 0), "{sum:?}");
    let moved = read_result(&out, false).unwrap();
    let tail = |row: &str| {
        row.split_once(",0.")
            .unwrap()
            .1
            .split_once(',')
            .unwrap()
            .1
            .to_string()
    };
    assert_eq!(tail(&moved.rows[&0]), tail(&after.rows[&12]));
    // a changed measure changes every key: everything runs again
    let sum = run_sweep(
        &spec(&changed_text.replace("margin = 4", "margin = 5")),
        &opts(&out),
        &none,
    )
    .unwrap();
    assert_eq!((sum.skipped, sum.ran), (0, 16), "{sum:?}");
}

#[test]
fn a_changed_csv_file_of_the_scene_reruns_its_runs() {
    // The spec hash covers the sweep file and the base scene's text, not the CSV files the scene
    // reads: the content key covers the resolved scene, so a new mass file reruns every run.
    let dir = tempfile::tempdir().unwrap();
    let masses = |m: f64| {
        (0..10)
            .map(|i| format!("{}\n", if i == 5 { m } else { 1.0 }))
            .collect::<String>()
    };
    std::fs::write(dir.path().join("m.csv"), masses(1.0)).unwrap();
    std::fs::write(
        dir.path().join("base.toml"),
        "[chain]\nmass = { file = \"m.csv\" }\nexponent = 2.5\n[initial]\nstriker = 1.0\n[run]\nuntil = 20.0\n",
    )
    .unwrap();
    let text = "scene = \"base.toml\"\n[grid]\n\"initial.striker\" = [1.0, 0.5]\n[measure]\nfragments = true\n";
    let out = dir.path().join("m.out.csv");
    let s = spec_in(text, dir.path());
    assert_eq!(run_sweep(&s, &opts(&out), &none).unwrap().ran, 2);
    assert_eq!(run_sweep(&s, &opts(&out), &none).unwrap().skipped, 2);
    std::fs::write(dir.path().join("m.csv"), masses(2.0)).unwrap();
    let s2 = spec_in(text, dir.path());
    assert_eq!(s2.hash, s.hash, "the spec hash does not see the CSV file");
    let sum = run_sweep(&s2, &opts(&out), &none).unwrap();
    assert_eq!((sum.skipped, sum.ran), (0, 2), "{sum:?}");
}

/// The defect: an interrupted sweep (`OUT.partial`) resumed after a CSV file its scene reads had
/// changed kept the rows computed from the old file, and wrote them into `OUT` under the new
/// content keys, so every later rerun skipped them as up to date. The partial file's first line
/// now carries a hash of its runs' content keys; such a partial file is refused, naming why.
#[test]
fn a_partial_sweep_written_before_a_csv_file_changed_is_not_resumed() {
    let dir = tempfile::tempdir().unwrap();
    let masses = |m: f64| format!("{m}\n").repeat(10);
    std::fs::write(dir.path().join("m.csv"), masses(1.0)).unwrap();
    std::fs::write(
        dir.path().join("base.toml"),
        "[chain]\nmass = { file = \"m.csv\" }\n[initial]\nstriker = 1.0\n[run]\nuntil = 10.0\n",
    )
    .unwrap();
    let text = "scene = \"base.toml\"\n[grid]\n\"initial.striker\" = [0.5, 1.0, 1.5, 2.0]\n";
    let out = dir.path().join("r.csv");
    let interrupted = SweepOptions {
        max_runs: Some(2),
        ..opts(&out)
    };
    let first = run_sweep(&spec_in(text, dir.path()), &interrupted, &none).unwrap();
    assert_eq!((first.ran, first.complete), (2, false));
    std::fs::write(dir.path().join("m.csv"), masses(3.0)).unwrap();
    let e = run_sweep(&spec_in(text, dir.path()), &opts(&out), &none).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("r.csv.partial:1: its runs' content keys differ from this sweep's: a file its scene reads changed (a CSV file), or another beadchain version wrote it"),
        "{msg}"
    );
    assert!(!out.exists(), "nothing written");
    // the same inputs resume as before; so does a partial file of an earlier build, whose first
    // line has no inputs hash (the review found it refused as if a CSV file had changed)
    std::fs::write(dir.path().join("m.csv"), masses(1.0)).unwrap();
    let partial = beadchain::sweep::exec::partial_path(&out);
    let text_of = std::fs::read_to_string(&partial).unwrap();
    let (first, rest) = text_of.split_once('\n').unwrap();
    let legacy = first.split(" inputs=").next().unwrap();
    std::fs::write(&partial, format!("{legacy}\n{rest}")).unwrap();
    let sum = run_sweep(&spec_in(text, dir.path()), &opts(&out), &none).unwrap();
    assert_eq!((sum.resumed, sum.ran, sum.written), (2, 2, true), "{sum:?}");
    // and give the bytes of a fresh sweep
    let fresh = dir.path().join("fresh.csv");
    run_sweep(&spec_in(text, dir.path()), &opts(&fresh), &none).unwrap();
    assert_eq!(read(&out), read(&fresh));
}

#[test]
fn old_results_without_keys_and_merged_shards() {
    let dir = tempfile::tempdir().unwrap();
    let s = spec(SMALL);
    // A result of an older beadchain (spec line only in OUT.meta): every run runs again.
    let out = dir.path().join("old.csv");
    run_sweep(&s, &opts(&out), &none).unwrap();
    let m = read(&meta(&out));
    std::fs::write(meta(&out), format!("{}\n", m.lines().next().unwrap())).unwrap();
    let sum = run_sweep(&s, &opts(&out), &none).unwrap();
    assert_eq!((sum.skipped, sum.ran), (0, 16), "{sum:?}");
    assert_eq!(read(&meta(&out)), m, "the keys are written again");
    // Shards keep their keys; merge joins them into the unsharded sidecar, and the unsharded
    // sweep run on the merged file skips everything.
    let mut shards = Vec::new();
    for k in 1..=2 {
        let p = dir.path().join(format!("s{k}.csv"));
        let mut o = opts(&p);
        o.shard = Some(Shard { k, m: 2 });
        run_sweep(&s, &o, &none).unwrap();
        assert_eq!(read_keys(&p).len(), 8);
        shards.push(p);
    }
    let merged = dir.path().join("merged.csv");
    merge(&merged, &shards, false).unwrap();
    assert_eq!(read(&meta(&merged)), m);
    assert_eq!(read(&merged), read(&out));
    let sum = run_sweep(&s, &opts(&merged), &none).unwrap();
    assert_eq!(
        (sum.skipped, sum.ran, sum.written),
        (16, 0, false),
        "{sum:?}"
    );
    // --timing adds a column: the old rows are not taken (nothing to compare wall times with)
    let mut o = opts(&merged);
    o.timing = true;
    assert_eq!(run_sweep(&s, &o, &none).unwrap().ran, 16);
}

#[test]
fn cli_prints_the_skipped_runs() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("sw.toml"), SMALL).unwrap();
    let run = || {
        let o = Command::new(env!("CARGO_BIN_EXE_beadchain"))
            .args(["sweep", "sw.toml", "--out", "o.csv", "--jobs", "2"])
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8(o.stdout).unwrap()
    };
    let a = run();
    assert!(
        a.contains(
            "16 runs: 0 resumed, 0 skipped (result already in o.csv), 16 run now, 0 with errors"
        ),
        "{a}"
    );
    assert!(a.contains("wrote o.csv"), "{a}");
    let csv = read(&dir.path().join("o.csv"));
    let b = run();
    assert!(
        b.contains(
            "16 runs: 0 resumed, 16 skipped (result already in o.csv), 0 run now, 0 with errors"
        ),
        "{b}"
    );
    assert!(b.contains("o.csv is up to date (unchanged)"), "{b}");
    assert_eq!(read(&dir.path().join("o.csv")), csv);
}
