//! `beadchain::sweep`: parsing and its errors, expansion order, scene overrides, execution with
//! error rows, resuming (byte-identical), shards + merge (byte-identical), spec changes refused.

use beadchain::sweep::csv::{read_result, split_fields};
use beadchain::sweep::exec::partial_path;
use beadchain::sweep::expand::set_key;
use beadchain::sweep::{merge, run_sweep, Shard, SweepError, SweepOptions, SweepSpec};
use std::path::{Path, PathBuf};
use toml::Value;

/// A small sweep on the dimensionless striker preset: 4 x 2 grid x 2 seeds = 16 runs of 30 beads
/// with random masses `1 + eps r` from bead 5 on.
const SMALL: &str = include_str!("common/small_sweep.toml");

fn spec(text: &str) -> Result<SweepSpec, SweepError> {
    SweepSpec::parse_str(text, Path::new("."), "test.toml")
}

fn opts(out: &Path, jobs: usize) -> SweepOptions {
    SweepOptions {
        out: out.to_path_buf(),
        jobs: Some(jobs),
        shard: None,
        max_runs: None,
        timing: false,
    }
}

fn no_progress(_: usize, _: usize) {}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap()
}

#[test]
fn bad_sweep_files_fail_naming_file_and_key() {
    let cases: &[(&str, &str)] = &[
        ("scene = \"striker\"\nfoo = 1\n", "test.toml: foo: unknown key"),
        ("[grid]\n\"chain.exponent\" = [2.5]\n", "test.toml: scene: missing"),
        ("scene = \"nope\"\n", "test.toml: scene: \"nope\": no scene file"),
        (
            "scene = \"striker\"\n[grid]\n\"chain.exponent\" = []\n",
            "test.toml: [grid].\"chain.exponent\": empty list",
        ),
        (
            "scene = \"striker\"\n[grid]\n\"chain.exponent\" = 2.5\n",
            "test.toml: [grid].\"chain.exponent\": expected a list",
        ),
        (
            "scene = \"striker\"\n[grid]\nchain = [1]\n",
            "test.toml: [grid].\"chain\": expected a quoted dotted scene key",
        ),
        (
            "scene = \"striker\"\n[set]\n\"chain.exponent\" = 3.0\n[grid]\n\"chain.exponent\" = [2.5]\n",
            "test.toml: [grid].\"chain.exponent\": also set in [set]",
        ),
        (
            "scene = \"striker\"\n[seeds]\nvalues = [1]\n",
            "test.toml: [seeds].key: missing",
        ),
        (
            "scene = \"striker\"\n[seeds]\nkey = \"scene.seed\"\nvalues = [1, -2]\n",
            "test.toml: [seeds].values[1]: expected a non-negative integer",
        ),
        (
            "scene = \"striker\"\n[measure]\ndecay = 3\n",
            "test.toml: [measure].decay: expected true/false or a table",
        ),
        ("scene = \"striker\"\n[stop]\nmargins = 3\n", "test.toml: [stop].margins: unknown key"),
        ("scene = \"striker\"\n[grid\n", "test.toml:2: malformed TOML"),
    ];
    for (text, want) in cases {
        let e = spec(text).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.starts_with(want), "{text:?}: got {e:?}, want {want:?}");
    }
}

/// Regression: errors under `[measure].decay` and `[measure].fragments` named the key
/// `[measure].decay].from` (a stray bracket) before sweep files were read through serde structs.
#[test]
fn measure_sub_key_errors_name_the_key_without_a_stray_bracket() {
    let cases: &[(&str, &str)] = &[
        (
            "[measure]\ndecay = { from = -1 }\n",
            "test.toml: [measure].decay.from: expected a non-negative integer",
        ),
        (
            "[measure]\ndecay = { foo = 1 }\n",
            "test.toml: [measure].decay.foo: unknown key",
        ),
        (
            "[measure]\nfragments = { gap_tol = \"x\" }\n",
            "test.toml: [measure].fragments.gap_tol: expected",
        ),
    ];
    for (table, want) in cases {
        let text = format!("scene = \"striker\"\n{table}");
        let e = spec(&text).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.starts_with(want), "{text:?}: got {e:?}, want {want:?}");
    }
}

#[test]
fn scene_errors_fail_before_any_run() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r.csv");
    let cases: &[(&str, &str)] = &[
        (
            "[grid]\n\"chain.exponent\" = [2.5, 0.5]\n",
            "test.toml: run 1 (chain.exponent=0.5): scene striker: [chain].exponent: contact 0: exponent must be > 1",
        ),
        (
            "[grid]\n\"chain.beadz\" = [3]\n",
            "test.toml: run 0 (chain.beadz=3): scene striker: [chain].beadz: unknown key",
        ),
        (
            "[grid]\n\"chain.exponent\" = [\"x\"]\n",
            "test.toml: run 0 (chain.exponent=x): scene striker: [chain].exponent: expected a number",
        ),
        (
            "[set]\n\"chain.exponent.base\" = 2.5\n",
            "test.toml: [set].\"chain.exponent.base\": the base scene's `chain.exponent` is a number, not a table",
        ),
        (
            "[measure]\ninterface = 100\n",
            "test.toml: [measure].interface: run 0 (): bead 100 is outside 1..=99",
        ),
        (
            "[set]\n\"run.every\" = 1.0\n[stop]\nmargin = 200\n",
            "test.toml: [stop].margin: run 0 (): 200 is not less than",
        ),
    ];
    for (body, want) in cases {
        let s = spec(&format!("scene = \"striker\"\n{body}")).unwrap();
        let e = run_sweep(&s, &opts(&out, 1), &no_progress)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default();
        assert!(e.starts_with(want), "{body:?}: got {e:?}, want {want:?}");
        assert!(
            !out.exists() && !partial_path(&out).exists(),
            "{body:?}: nothing written"
        );
    }
}

#[test]
fn set_key_walks_tables_and_arrays() {
    let mut t: toml::Table = toml::from_str(
        "[chain]\nexponent = { base = 3.0, segments = [{ from = 5, value = 2.5 }] }\n",
    )
    .unwrap();
    set_key(&mut t, "chain.exponent.segments.0.value", Value::Float(3.5)).unwrap();
    set_key(&mut t, "walls.left.exponent", Value::Float(2.0)).unwrap();
    let seg = &t["chain"]["exponent"]["segments"][0];
    assert_eq!(seg["value"].as_float(), Some(3.5));
    assert_eq!(seg["from"].as_integer(), Some(5));
    assert_eq!(t["walls"]["left"]["exponent"].as_float(), Some(2.0));
    let e = set_key(&mut t, "chain.exponent.segments.1.value", Value::Float(1.0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("has 1 entries, index 1"), "{e}");
    let e = set_key(&mut t, "chain.exponent.segments.x", Value::Float(1.0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("must be an index"), "{e}");
}

#[test]
fn expansion_order_points_grid_seeds() {
    let s = spec(
        "scene = \"striker\"\n[grid]\n\"initial.striker\" = [1.0, 2.0]\n\"chain.exponent\" = [2.5, 3.0, 3.5]\n\
         [[point]]\n\"chain.mass\" = 1.0\n[[point]]\n\"chain.prefactor\" = 2.0\n\
         [seeds]\nkey = \"scene.seed\"\nvalues = [7, 8]\n",
    )
    .unwrap();
    assert_eq!(
        s.param_columns(),
        [
            "chain.exponent",
            "initial.striker",
            "chain.mass",
            "chain.prefactor",
            "scene.seed"
        ]
    );
    let runs = s.runs();
    assert_eq!(runs.len(), 2 * 3 * 2 * 2);
    let d: Vec<String> = runs.iter().map(|r| r.describe()).collect();
    assert_eq!(
        d[0],
        "chain.exponent=2.5, initial.striker=1.0, chain.mass=1.0, scene.seed=7"
    );
    assert_eq!(
        d[1],
        "chain.exponent=2.5, initial.striker=1.0, chain.mass=1.0, scene.seed=8"
    );
    assert_eq!(
        d[2],
        "chain.exponent=2.5, initial.striker=2.0, chain.mass=1.0, scene.seed=7"
    );
    assert_eq!(
        d[4],
        "chain.exponent=3.0, initial.striker=1.0, chain.mass=1.0, scene.seed=7"
    );
    assert_eq!(
        d[12],
        "chain.exponent=2.5, initial.striker=1.0, chain.prefactor=2.0, scene.seed=7"
    );
    assert!(runs.iter().enumerate().all(|(i, r)| r.index == i));
    // The overrides reach the resolved scene.
    let sc = s.scene_for(&runs[23]).unwrap();
    assert_eq!((sc.seed, sc.v0[0], sc.chain.exponent[3]), (8, 2.0, 3.5));
    assert!(sc.chain.prefactor.iter().all(|a| *a == 2.0));
}

#[test]
fn sweep_rows_measure_and_are_deterministic_across_jobs() {
    let dir = tempfile::tempdir().unwrap();
    let s = spec(SMALL).unwrap();
    let a = dir.path().join("a.csv");
    let b = dir.path().join("b.csv");
    let sa = run_sweep(&s, &opts(&a, 1), &no_progress).unwrap();
    run_sweep(&s, &opts(&b, 2), &no_progress).unwrap();
    assert_eq!(read(&a), read(&b), "jobs 1 and 2 give identical bytes");
    assert!(
        sa.complete && sa.runs == 16 && sa.ran == 16 && sa.failed == 0,
        "{sa:?}"
    );
    assert!(!partial_path(&a).exists());
    let f = read_result(&a, false).unwrap();
    assert!(
        f.spec_line.starts_with(&format!(
            "# beadchain sweep spec={:016x} runs=16 inputs=",
            s.hash
        )),
        "{}",
        f.spec_line
    );
    let cols = split_fields(&f.columns).unwrap();
    assert_eq!(
        cols,
        [
            "run",
            "chain.mass.random.eps",
            "initial.striker",
            "scene.seed",
            "status",
            "t_end",
            "energy_error",
            "steps",
            "events",
            "left_fraction",
            "gamma",
            "gamma_se",
            "fragments"
        ]
    );
    let col = |name: &str| cols.iter().position(|c| c == name).unwrap();
    for (i, row) in &f.rows {
        let r = split_fields(row).unwrap();
        assert_eq!(r[col("status")], "ok", "run {i}: {row}");
        let num = |c: &str| r[col(c)].parse::<f64>().unwrap();
        // stopped at bead 26 well before until = 40 (wave speed ~1 bead per time unit)
        assert!(num("t_end") < 40.0 && num("t_end") > 5.0, "run {i}: {row}");
        // energy conservation: rtol 1e-8 default gives < 1e-6 relative (abs tolerance 1e-6)
        assert!(num("energy_error") < 1e-6, "run {i}: {row}");
        assert!(num("steps") > 0.0 && num("events") > 0.0, "run {i}: {row}");
        // the wave has passed bead 15: most energy right of it (rel. tolerance: < 20 % left)
        assert!(num("left_fraction") < 0.2, "run {i}: {row}");
        assert!(num("fragments") >= 1.0, "run {i}: {row}");
        // {:e} printing round-trips exactly
        assert_eq!(format!("{:e}", num("gamma")), r[col("gamma")]);
    }
    // Mass disorder makes the leading wave decay: eps = 0.4 vs eps = 0 (same striker, seed);
    // the uniform chain's wave keeps its energy (|gamma| < 1e-3 per bead, absolute).
    let gamma = |i: usize| {
        split_fields(&f.rows[&i]).unwrap()[col("gamma")]
            .parse::<f64>()
            .unwrap()
    };
    assert!(gamma(0).abs() < 1e-3, "gamma eps=0: {}", gamma(0));
    assert!(gamma(12) > 5e-3, "gamma eps=0.4: {}", gamma(12));
}

#[test]
fn failing_runs_give_error_rows() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c.csv");
    // The dense engine refuses hard contacts: that run fails, the hybrid one runs.
    let s = spec(
        "scene = \"newtons_cradle_hard\"\n[grid]\n\"run.engine\" = [\"dense\", \"hybrid\"]\n\
         [measure]\nfragments = true\n",
    )
    .unwrap();
    let sum = run_sweep(&s, &opts(&out, 2), &no_progress).unwrap();
    assert_eq!((sum.runs, sum.failed, sum.complete), (2, 1, true));
    let f = read_result(&out, false).unwrap();
    let r0 = split_fields(&f.rows[&0]).unwrap();
    assert!(
        r0[2].starts_with("error: invalid run configuration: the scene declares hard"),
        "{r0:?}"
    );
    assert!(r0[3..].iter().all(|x| x.is_empty()), "{r0:?}");
    let r1 = split_fields(&f.rows[&1]).unwrap();
    assert_eq!(r1[2], "ok");
    // Newton's cradle: the last bead leaves alone (2 fragments at least).
    assert!(r1[7].parse::<usize>().unwrap() >= 2, "{r1:?}");
}

#[test]
fn resume_after_interruption_gives_identical_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let s = spec(SMALL).unwrap();
    let full = dir.path().join("full.csv");
    run_sweep(&s, &opts(&full, 2), &no_progress).unwrap();
    let out = dir.path().join("res.csv");
    let part = partial_path(&out);
    let mut o = opts(&out, 2);
    o.max_runs = Some(5);
    let a = run_sweep(&s, &o, &no_progress).unwrap();
    assert!(
        !a.complete && a.ran == 5 && !out.exists() && part.exists(),
        "{a:?}"
    );
    // Cut the partial file in the middle of its last row (a write interrupted by a kill).
    let text = read(&part);
    std::fs::write(&part, &text[..text.len() - 7]).unwrap();
    o.max_runs = Some(6);
    let b = run_sweep(&s, &o, &no_progress).unwrap();
    assert_eq!((b.resumed, b.ran, b.complete), (4, 6, false), "{b:?}");
    o.max_runs = None;
    let c = run_sweep(&s, &o, &no_progress).unwrap();
    assert_eq!((c.resumed, c.ran, c.complete), (10, 6, true), "{c:?}");
    assert_eq!(read(&out), read(&full));
    assert!(!part.exists());
}

#[test]
fn changed_spec_or_foreign_rows_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.csv");
    let s = spec(SMALL).unwrap();
    let mut o = opts(&out, 1);
    o.max_runs = Some(2);
    run_sweep(&s, &o, &no_progress).unwrap();
    let changed = spec(&SMALL.replace("margin = 4", "margin = 5")).unwrap();
    assert_ne!(changed.hash, s.hash);
    let e = run_sweep(&changed, &o, &no_progress)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("x.csv.partial:1: written by a different sweep spec"),
        "{e}"
    );
    // Comments and spacing do not change the hash.
    let same = spec(&SMALL.replace("[stop]", "# a comment\n[stop]  ")).unwrap();
    assert_eq!(same.hash, s.hash);
    // A partial file of another shard is refused.
    o.shard = Some(Shard { k: 2, m: 3 });
    let e = run_sweep(&s, &o, &no_progress).unwrap_err().to_string();
    assert!(e.contains("run 0 is not a run of this sweep/shard"), "{e}");
    // --timing changes the columns.
    o.shard = None;
    o.timing = true;
    let e = run_sweep(&s, &o, &no_progress).unwrap_err().to_string();
    assert!(e.contains("x.csv.partial:2: its columns differ"), "{e}");
}

#[test]
fn shards_merge_to_the_unsharded_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let s = spec(SMALL).unwrap();
    let full = dir.path().join("full.csv");
    run_sweep(&s, &opts(&full, 1), &no_progress).unwrap();
    let mut shards: Vec<PathBuf> = Vec::new();
    for k in 1..=3 {
        let p = dir.path().join(format!("r.{k}of3.csv"));
        let mut o = opts(&p, 1);
        o.shard = Some(format!("{k}/3").parse().unwrap());
        let sum = run_sweep(&s, &o, &no_progress).unwrap();
        assert_eq!(sum.runs, [6, 5, 5][k - 1]);
        shards.push(p);
    }
    let merged = dir.path().join("merged.csv");
    // Shard order does not matter.
    shards.reverse();
    let m = merge(&merged, &shards, false).unwrap();
    assert_eq!((m.rows, m.missing.len()), (16, 0));
    assert_eq!(read(&merged), read(&full));
    // A missing shard is an error (nothing written) unless allowed.
    let two = dir.path().join("two.csv");
    let e = merge(&two, &shards[..2], false).unwrap_err().to_string();
    assert!(e.contains("6 of 16 runs are in no shard: 0, 3, 6"), "{e}");
    assert!(!two.exists());
    let m = merge(&two, &shards[..2], true).unwrap();
    assert_eq!((m.rows, m.missing.len()), (10, 6));
    // The same shard twice, or a shard of another sweep, is refused.
    let e = merge(&two, &[shards[0].clone(), shards[0].clone()], true)
        .unwrap_err()
        .to_string();
    assert!(e.contains("is also in"), "{e}");
    let other = dir.path().join("other.csv");
    let s2 = spec(&SMALL.replace("values = [3, 4]", "values = [3, 5]")).unwrap();
    let mut o = opts(&other, 1);
    o.max_runs = Some(0);
    o.shard = Some(Shard { k: 1, m: 16 });
    run_sweep(&s2, &o, &no_progress).unwrap();
    std::fs::rename(partial_path(&other), &other).unwrap();
    let e = merge(&two, &[shards[0].clone(), other], true)
        .unwrap_err()
        .to_string();
    assert!(e.contains("other.csv:1: its spec line differs"), "{e}");
    assert!("0/3".parse::<Shard>().is_err() && "4/3".parse::<Shard>().is_err());
    assert!("3".parse::<Shard>().is_err());
}

/// The defect: `merge` and `sweep` wrote `OUT.meta` first and `OUT` second, so when `OUT` could
/// not be replaced (a symbolic link, a directory, an immutable file) the command failed with
/// `OUT.meta` already overwritten, describing a table `OUT` did not hold (and `sweep` ran every
/// run before it found out). Both paths are now checked first.
#[test]
fn a_result_that_cannot_be_written_leaves_its_sidecar_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let s = spec(SMALL).unwrap();
    let shard = dir.path().join("s.csv");
    run_sweep(&s, &opts(&shard, 1), &no_progress).unwrap();
    let meta = |p: &Path| PathBuf::from(format!("{}.meta", p.display()));
    // a symbolic link, and a directory, as OUT; an old sidecar beside each
    let target = dir.path().join("target.csv");
    std::fs::write(&target, "OTHER\n").unwrap();
    let link = dir.path().join("link.csv");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let adir = dir.path().join("d.csv");
    std::fs::create_dir(&adir).unwrap();
    for out in [&link, &adir] {
        std::fs::write(meta(out), "OLDMETA\n").unwrap();
        let e = merge(out, std::slice::from_ref(&shard), false)
            .unwrap_err()
            .to_string();
        assert!(e.starts_with(&format!("{}: ", out.display())), "{e}");
        let mut o = opts(out, 1);
        o.max_runs = Some(1);
        let e = run_sweep(&s, &o, &no_progress).unwrap_err().to_string();
        assert!(
            e.contains("symbolic link") || e.contains("is a directory"),
            "{e}"
        );
        assert_eq!(read(&meta(out)), "OLDMETA\n", "{}", out.display());
        assert!(
            !partial_path(out).exists(),
            "sweep ran before it checked its output"
        );
    }
    assert_eq!(read(&target), "OTHER\n");
}

#[test]
fn example_sweep_files_parse() {
    for f in [
        "data/sweeps/reflection_grid.toml",
        "data/sweeps/disorder_gamma.toml",
    ] {
        let s = SweepSpec::load(Path::new(f)).unwrap();
        let runs = s.check_all().unwrap();
        assert_eq!(runs.len(), 9, "{f}");
    }
}

/// Before: line 1 of `OUT` was `# beadchain sweep spec=...` (so `pandas.read_csv(OUT)` failed
/// without `comment="#"`/`skiprows=1`), and swept floats were written `1e-1`, `5e-1`.
#[test]
fn sweep_csv_header_is_the_first_line_and_values_are_written_as_given() {
    let dir = tempfile::tempdir().unwrap();
    let s = spec(SMALL).unwrap();
    let out = dir.path().join("p.csv");
    run_sweep(&s, &opts(&out, 2), &no_progress).unwrap();
    let text = read(&out);
    let first = text.lines().next().unwrap();
    assert!(
        first.starts_with("run,chain.mass.random.eps,initial.striker,scene.seed,status,"),
        "{first}"
    );
    assert!(!text.contains('#'), "{text}");
    // The spec line is in the sidecar, and merge/resume read it from there.
    // (then one content key per row: tests/sweep_content.rs)
    let meta = read(&dir.path().join("p.csv.meta"));
    assert!(
        meta.lines().next().unwrap().starts_with(&format!(
            "# beadchain sweep spec={:016x} runs=16 inputs=",
            s.hash
        )),
        "{meta}"
    );
    // line 2: the provenance of the build that wrote it (tests/provenance.rs)
    assert!(
        meta.lines().nth(1).unwrap().starts_with("# beadchain "),
        "{meta}"
    );
    assert_eq!(meta.lines().count(), 18, "{meta}");
    // Values as written in the sweep file: [0.0, 0.1, 0.2, 0.4] x [1.0, 0.5], seeds 3, 4.
    let f = read_result(&out, false).unwrap();
    let params = |i: usize| split_fields(&f.rows[&i]).unwrap()[1..4].to_vec();
    assert_eq!(params(0), ["0.0", "1.0", "3"]);
    assert_eq!(params(7), ["0.1", "0.5", "4"]);
    assert_eq!(params(15), ["0.4", "0.5", "4"]);
    // Every row has the header's field count (what pandas needs without options).
    let ncol = split_fields(first).unwrap().len();
    assert!(text.lines().all(|l| split_fields(l).unwrap().len() == ncol));
    // Without its sidecar the file is not taken for a sweep result by merge.
    std::fs::remove_file(dir.path().join("p.csv.meta")).unwrap();
    let e = merge(&dir.path().join("m.csv"), &[out], false)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("p.csv.meta: cannot read the sweep's spec sidecar of"),
        "{e}"
    );
}

/// A base scene file with malformed TOML: the message carried toml's multi-line report, which
/// the CLI printed as one line full of literal `\n` (an adversarial review). Now one line,
/// placed as `beadchain run` places it (`file:line:column`).
#[test]
fn malformed_base_scene_is_reported_on_one_line() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("bad.toml"), "[chain\nbeads = 3\n").unwrap();
    let file = d.path().join("sw.toml");
    let text = "scene = \"bad.toml\"\n[grid]\n\"chain.exponent\" = [2.5, 3.0]\n";
    std::fs::write(&file, text).unwrap();
    let e = SweepSpec::load(&file).expect_err("refused").to_string();
    assert!(
        e.ends_with(
            "scene: \"bad.toml\":1:7: malformed TOML: invalid table header; expected `.`, `]`"
        ),
        "{e}"
    );
    assert!(!e.contains('\n'), "{e}");
}
