//! `beadchain sweep --shard` and `merge`: shards run on different inputs are not merged, and a
//! shard does not overwrite rows of other runs of its sweep (found by a review of the sweep
//! commands).

mod common;
use common::bc;

const SCENE: &str =
    "[scene]\nname = \"mscene\"\n[chain]\nbeads = 20\nmass = { file = \"mass.csv\" }\n\
                     [initial]\nstriker = 1.0\n[run]\nuntil = 10.0\nevery = 1.0\n";
const SWEEP: &str = "scene = \"sc.toml\"\n[grid]\n\"initial.striker\" = [1.0, 2.0, 3.0, 4.0]\n\
                     [measure]\ninterface = 10\n";

/// Runs `beadchain ARGS` in `p`; it must succeed.
fn ok(p: &std::path::Path, args: &[&str]) {
    let o = bc(p, args);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// A directory with the scene, the sweep file `sweep` and masses 1.
fn setup(sweep: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("sc.toml"), SCENE).unwrap();
    std::fs::write(dir.path().join("sw.toml"), sweep).unwrap();
    masses(dir.path(), 1.0);
    dir
}

fn masses(dir: &std::path::Path, m: f64) {
    std::fs::write(dir.join("mass.csv"), format!("{m}\n").repeat(20)).unwrap();
}

/// The defect: `merge` compared the shards' spec lines only (a hash of the sweep file and base
/// scene text), so shards run before and after a CSV file the scene reads changed (masses 1,
/// then 2) were merged into one result, exit 0, half its rows from other inputs. The finished
/// result's spec line now carries the hash of every run's content key (`inputs=`), and `merge`
/// refuses shards whose hashes differ.
#[test]
fn merge_refuses_shards_run_on_different_inputs() {
    let dir = setup(SWEEP);
    let p = dir.path();
    ok(
        p,
        &[
            "sweep", "sw.toml", "--shard", "1/2", "--out", "s.1.csv", "-q",
        ],
    );
    ok(
        p,
        &[
            "sweep", "sw.toml", "--shard", "2/2", "--out", "s.2.csv", "-q",
        ],
    );
    ok(p, &["merge", "same.csv", "s.1.csv", "s.2.csv"]);
    masses(p, 2.0);
    ok(
        p,
        &[
            "sweep", "sw.toml", "--shard", "2/2", "--out", "s.2.csv", "-q",
        ],
    );
    let o = bc(p, &["merge", "merged.csv", "s.1.csv", "s.2.csv"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("s.2.csv") && err.contains("content keys differ from"),
        "{err}"
    );
    assert!(!p.join("merged.csv").exists());
}

/// Drops the `inputs=` of a shard's spec line, as a beadchain before it wrote them.
fn as_older_binary(meta: &std::path::Path) {
    let text = std::fs::read_to_string(meta).unwrap();
    let first = text.lines().next().unwrap();
    let old = first.split(" inputs=").next().unwrap();
    std::fs::write(meta, text.replacen(first, old, 1)).unwrap();
}

/// A review's follow-up: with the first shard listed from an older beadchain (no `inputs=`),
/// the other shards were compared with it alone and two run on different inputs passed; they
/// are now compared with the first shard that has a hash, and the merged result carries it.
#[test]
fn merge_compares_inputs_past_a_first_shard_without_them() {
    let dir = setup(&SWEEP.replace("4.0]", "4.0, 5.0, 6.0]"));
    let p = dir.path();
    ok(
        p,
        &[
            "sweep", "sw.toml", "--shard", "1/3", "--out", "t.1.csv", "-q",
        ],
    );
    ok(
        p,
        &[
            "sweep", "sw.toml", "--shard", "2/3", "--out", "t.2.csv", "-q",
        ],
    );
    as_older_binary(&p.join("t.1.csv.meta"));
    masses(p, 2.0);
    ok(
        p,
        &[
            "sweep", "sw.toml", "--shard", "3/3", "--out", "t.3.csv", "-q",
        ],
    );
    let o = bc(p, &["merge", "m.csv", "t.1.csv", "t.2.csv", "t.3.csv"]);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("t.3.csv") && err.contains("differ from"),
        "{err}"
    );
    // on the same inputs the older shard merges, and the result carries the others' hash
    masses(p, 1.0);
    ok(
        p,
        &[
            "sweep", "sw.toml", "--shard", "3/3", "--out", "t.3.csv", "-q",
        ],
    );
    ok(p, &["merge", "m.csv", "t.1.csv", "t.2.csv", "t.3.csv"]);
    let meta = std::fs::read_to_string(p.join("m.csv.meta")).unwrap();
    assert!(meta.lines().next().unwrap().contains(" inputs="), "{meta}");
}

/// The defect: a `--shard` run whose `--out` held this sweep's whole result (or another
/// shard's) rewrote it with the shard's rows alone, dropping the others without a word. It is
/// now refused before anything runs, and the file is left as it was.
#[test]
fn a_shard_does_not_overwrite_other_runs_of_its_sweep() {
    let dir = setup(SWEEP);
    let p = dir.path();
    let o = bc(p, &["sweep", "sw.toml", "--out", "r.csv", "-q"]);
    assert_eq!(o.status.code(), Some(0));
    let before = std::fs::read(p.join("r.csv")).unwrap();
    let o = bc(
        p,
        &["sweep", "sw.toml", "--shard", "1/2", "--out", "r.csv", "-q"],
    );
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("r.csv")
            && err.contains("holds 2 rows of this sweep that shard 1/2 does not run"),
        "{err}"
    );
    assert_eq!(std::fs::read(p.join("r.csv")).unwrap(), before);
    // a shard's own file is its own to rewrite
    let o = bc(
        p,
        &["sweep", "sw.toml", "--shard", "1/2", "--out", "s.csv", "-q"],
    );
    assert_eq!(o.status.code(), Some(0));
    let o = bc(
        p,
        &["sweep", "sw.toml", "--shard", "1/2", "--out", "s.csv", "-q"],
    );
    assert_eq!(o.status.code(), Some(0));
}
