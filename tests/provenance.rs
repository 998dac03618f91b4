//! Provenance in every output (issue 36 item 2): the snapshot HEADER records the build commit
//! always and the date only with `--timing` (so plain runs stay byte-identical); `inspect`
//! prints both; CSV exports open with `#` provenance lines, the `.npz` holds a `provenance`
//! entry; the sweep sidecar `OUT.meta` names version and commit without refusing another
//! build's result; files written before (golden `data/golden/v4_no_provenance.snap`) still read.

mod common;

use beadchain::provenance::{is_commit, utc_iso, BUILD_COMMIT, VERSION};
use beadchain::snapshot::Snapshot;
use common::npy::parse_zip;
use common::{assert_ok, bc};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `beadchain ARGS` in `dir` with extra environment variables.
fn bc_env(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_beadchain"));
    c.args(args).current_dir(dir);
    for (k, v) in env {
        c.env(k, v);
    }
    // The caller's environment must not decide what the tests see.
    if !env.iter().any(|(k, _)| *k == "BEADCHAIN_NO_BUILD_COMMIT") {
        c.env_remove("BEADCHAIN_NO_BUILD_COMMIT");
    }
    if !env.iter().any(|(k, _)| *k == "SOURCE_DATE_EPOCH") {
        c.env_remove("SOURCE_DATE_EPOCH");
    }
    c.output().expect("start beadchain")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

const RUN: &[&str] = &["run", "striker", "--until", "2", "-q", "--out", "s.snap"];

/// Runs [`RUN`] (plus `extra`) in a fresh directory; the directory and the snapshot path.
fn run_in(extra: &[&str], env: &[(&str, &str)]) -> (tempfile::TempDir, PathBuf) {
    let d = tempfile::tempdir().unwrap();
    let args: Vec<&str> = RUN.iter().chain(extra).copied().collect();
    assert_ok(&bc_env(d.path(), &args, env));
    let p = d.path().join("s.snap");
    (d, p)
}

#[test]
fn build_commit_is_40_hex_digits_or_unknown() {
    assert!(is_commit(BUILD_COMMIT), "{BUILD_COMMIT}");
    assert!(is_commit("unknown") && is_commit(&format!("{}-dirty", "a".repeat(40))));
    assert!(!is_commit("abc") && !is_commit(&"g".repeat(40)) && !is_commit(""));
    let o = bc(Path::new("."), &["--version"]);
    assert_ok(&o);
    assert_eq!(
        stdout(&o).trim(),
        format!("beadchain {VERSION} (commit {BUILD_COMMIT})")
    );
}

#[test]
fn utc_dates_by_civil_from_days() {
    assert_eq!(utc_iso(0), "1970-01-01T00:00:00Z");
    assert_eq!(utc_iso(951_782_400), "2000-02-29T00:00:00Z");
    assert_eq!(utc_iso(1_795_805_103), "2026-11-27T18:45:03Z");
    assert_eq!(utc_iso(4_107_542_399), "2100-02-28T23:59:59Z");
    assert_eq!(utc_iso(-1), "1969-12-31T23:59:59Z");
}

#[test]
fn plain_runs_record_the_commit_and_no_date_and_stay_identical() {
    let (_a, pa) = run_in(&[], &[]);
    let (_b, pb) = run_in(&[], &[]);
    assert_eq!(std::fs::read(&pa).unwrap(), std::fs::read(&pb).unwrap());
    let s = Snapshot::open(&pa).unwrap();
    assert_eq!(s.header().build_commit.as_deref(), Some(BUILD_COMMIT));
    assert_eq!(s.header().created_at, None);
    let o = bc(pa.parent().unwrap(), &["inspect", "s.snap"]);
    assert_ok(&o);
    let text = stdout(&o);
    assert!(
        text.contains(&format!("\ncommit:      {BUILD_COMMIT}\n")),
        "{text}"
    );
    assert!(
        text.contains("\ncreated:     not recorded (run with --timing to record the date)\n"),
        "{text}"
    );
    assert!(text.contains("\nwritten by:  beadchain "), "{text}");
}

#[test]
fn timing_records_the_utc_date() {
    let (d, p) = run_in(&["--timing"], &[]);
    let at = Snapshot::open(&p).unwrap().header().created_at.clone();
    let at = at.expect("--timing records created_at");
    let b = at.as_bytes();
    assert!(
        at.len() == 20 && b[4] == b'-' && b[10] == b'T' && b[19] == b'Z' && at.starts_with("20"),
        "{at}"
    );
    let o = bc(d.path(), &["inspect", "s.snap"]);
    assert!(stdout(&o).contains(&format!("\ncreated:     {at}\n")));
    // SOURCE_DATE_EPOCH fixes the date (reproducible builds' convention).
    let (_e, p) = run_in(&["--timing"], &[("SOURCE_DATE_EPOCH", "1795805103")]);
    let h = Snapshot::open(&p).unwrap().header().clone();
    assert_eq!(h.created_at.as_deref(), Some("2026-11-27T18:45:03Z"));
}

#[test]
fn no_build_commit_variable_leaves_the_commit_out() {
    let env = [("BEADCHAIN_NO_BUILD_COMMIT", "1")];
    let (d, p) = run_in(&[], &env);
    assert_eq!(Snapshot::open(&p).unwrap().header().build_commit, None);
    let o = bc(d.path(), &["inspect", "s.snap"]);
    assert!(stdout(&o).contains("\ncommit:      not recorded\n"));
}

/// A format-4 file of the beadchain before provenance (no `build_commit`, no `created_at`),
/// written by `beadchain run v4_no_provenance.toml --out v4_no_provenance.snap -q`.
#[test]
fn snapshot_without_provenance_keys_still_reads() {
    let golden = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/golden");
    let s = Snapshot::open(&golden.join("v4_no_provenance.snap")).expect("golden file");
    assert!(s.is_complete() && s.warnings().is_empty());
    let h = s.header();
    assert_eq!((h.format_version, h.build_commit.as_ref()), (4, None));
    assert_eq!(h.created_at, None);
    assert_eq!(h.crate_version, "0.1.0");
    assert_eq!(
        h.created_by,
        "beadchain run s.toml --out v4_no_provenance.snap -q"
    );
    assert_eq!(s.frame_count(), 5);
    // The same scene run now gives the same frames, bit for bit.
    let d = tempfile::tempdir().unwrap();
    std::fs::copy(
        golden.join("v4_no_provenance.toml"),
        d.path().join("s.toml"),
    )
    .unwrap();
    assert_ok(&bc(d.path(), &["run", "s.toml", "--out", "n.snap", "-q"]));
    let n = Snapshot::open(&d.path().join("n.snap")).unwrap();
    assert_eq!(n.header().scene, h.scene);
    for k in 0..5 {
        assert_eq!(n.frame(k).unwrap(), s.frame(k).unwrap(), "frame {k}");
    }
    let o = bc(&golden, &["inspect", "v4_no_provenance.snap"]);
    assert_ok(&o);
    let text = stdout(&o);
    assert!(text.contains("\ncommit:      not recorded\n"), "{text}");
    assert!(
        text.contains("\ncreated:     not recorded (run with"),
        "{text}"
    );
}

#[test]
fn csv_exports_open_with_provenance_comments() {
    let (d, _) = run_in(&["--timing"], &[("SOURCE_DATE_EPOCH", "0")]);
    let head = [
        format!("# beadchain {VERSION} commit {BUILD_COMMIT}"),
        format!(
            "# created_by: {} {}",
            env!("CARGO_BIN_EXE_beadchain"),
            RUN[..].join(" ") + " --timing"
        ),
        "# scene: striker engine hybrid method auto rtol 1e-8 atol 1e-12".to_string(),
        "# created_at: 1970-01-01T00:00:00Z".to_string(),
    ];
    for (args, columns) in [
        (&["export", "s.snap"][..], "frame,t,bead,u,v"),
        (&["export", "s.snap", "--events"][..], "t,contact,kind,"),
        (&["export", "s.snap", "--layout", "wide"][..], "t,u0,u1,"),
    ] {
        let o = bc(d.path(), args);
        assert_ok(&o);
        let text = stdout(&o);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[..4], head[..], "{args:?}");
        assert!(lines[4].starts_with(columns), "{args:?}: {}", lines[4]);
        assert!(!lines[5..].iter().any(|l| l.starts_with('#')));
    }
}

/// Without `--timing` the 4th line says the date is not recorded (always 4 comment lines).
#[test]
fn csv_comments_are_always_four_lines() {
    let (d, _) = run_in(&[], &[]);
    let o = bc(d.path(), &["export", "s.snap", "--frame", "last"]);
    let text = stdout(&o);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[3],
        "# created_at: not recorded (run with --timing to record the date)"
    );
    assert_eq!(lines[4], "frame,t,bead,u,v");
    assert_eq!(lines.len(), 4 + 1 + 100);
}

#[test]
fn npz_export_holds_a_provenance_entry() {
    let (d, _) = run_in(&[], &[]);
    assert_ok(&bc(d.path(), &["export", "s.snap", "--out", "w.npz"]));
    let z = parse_zip(&std::fs::read(d.path().join("w.npz")).unwrap());
    let npy = &z["provenance.npy"];
    let hl = u16::from_le_bytes([npy[8], npy[9]]) as usize;
    let header = std::str::from_utf8(&npy[10..10 + hl]).unwrap();
    let chars: Vec<char> = npy[10 + hl..]
        .chunks(4)
        .map(|c| char::from_u32(u32::from_le_bytes([c[0], c[1], c[2], c[3]])).unwrap())
        .collect();
    assert!(
        header.starts_with(&format!(
            "{{'descr': '<U{}', 'fortran_order': False, 'shape': (), }}",
            chars.len()
        )),
        "{header}"
    );
    let json: String = chars.into_iter().collect();
    assert!(json.starts_with(&format!(
        "{{\"version\": \"{VERSION}\", \"commit\": \"{BUILD_COMMIT}\", \"created_at\": null, \"created_by\": "
    )), "{json}");
    assert!(json.contains("\"scene\": \"striker\", \"engine\": \"hybrid\", \"method\": \"auto\", \"rtol\": 1e-8, \"atol\": 1e-12, \"exported_by\": "), "{json}");
    assert!(json.ends_with(" export s.snap --out w.npz\"}"), "{json}");
    numpy_check(&d.path().join("w.npz"));
}

/// `numpy.load(..., allow_pickle=False)["provenance"]` as JSON, when python3 with numpy is
/// installed (skipped otherwise; python/tests/test_provenance.py runs it with the package).
fn numpy_check(npz: &Path) {
    let probe = Command::new("python3")
        .args(["-c", "import numpy"])
        .output();
    if !probe.is_ok_and(|o| o.status.success()) {
        eprintln!("python3 with numpy not available: numpy.load check skipped");
        return;
    }
    let script = format!(
        "import json, numpy as np\nz = np.load({:?}, allow_pickle=False)\np = z['provenance']\nassert p.shape == () and p.dtype.kind == 'U'\nd = json.loads(str(p))\nassert d['commit'] == {:?} and d['scene'] == 'striker' and d['created_at'] is None, d\nassert d['rtol'] == 1e-8 and d['atol'] == 1e-12\nassert z['u'].shape == (3, 100)\n",
        npz.display().to_string(),
        BUILD_COMMIT
    );
    let o = Command::new("python3")
        .args(["-c", &script])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

const SWEEP: &str = "scene = \"striker\"\n[set]\n\"chain.beads\" = 10\n\"run.until\" = 4.0\n[grid]\n\"initial.striker\" = [1.0, 0.5]\n";

#[test]
fn sweep_meta_names_version_and_commit_and_another_builds_result_is_reused() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("g.toml"), SWEEP).unwrap();
    let args = ["sweep", "g.toml", "--out", "g.csv", "-q"];
    assert_ok(&bc_env(d.path(), &args, &[]));
    let meta_path = d.path().join("g.csv.meta");
    let meta = std::fs::read_to_string(&meta_path).unwrap();
    let lines: Vec<&str> = meta.lines().collect();
    assert!(lines[0].starts_with("# beadchain sweep spec="), "{meta}");
    assert_eq!(
        lines[1],
        format!("# beadchain {VERSION} commit {BUILD_COMMIT}")
    );
    assert!(lines[2].starts_with("# run 0 content="), "{meta}");
    // A result written by another build: reused (not refused), the line brought up to date.
    let other = meta.replace(BUILD_COMMIT, &"0".repeat(40));
    std::fs::write(&meta_path, &other).unwrap();
    let csv = std::fs::read(d.path().join("g.csv")).unwrap();
    let o = bc_env(d.path(), &args, &[]);
    assert_ok(&o);
    let said = String::from_utf8_lossy(&o.stderr).into_owned() + &stdout(&o);
    assert!(said.contains("2 skipped"), "{said}");
    assert_eq!(std::fs::read(d.path().join("g.csv")).unwrap(), csv);
    assert_eq!(std::fs::read_to_string(&meta_path).unwrap(), meta);
    // Without the commit (byte comparisons across builds).
    let o = bc_env(d.path(), &args, &[("BEADCHAIN_NO_BUILD_COMMIT", "1")]);
    assert_ok(&o);
    let meta = std::fs::read_to_string(&meta_path).unwrap();
    assert_eq!(
        meta.lines().nth(1),
        Some(format!("# beadchain {VERSION}").as_str())
    );
}

/// The defects: `run` and `export` took their command line from `std::env::args`, which panics
/// on an argument that is not UTF-8 (`--out $'x\xff.snap'` aborted with a Rust panic), and
/// joined the arguments unquoted, so `created_by` of `--out 'sp ace/o.snap'` could not be run
/// again. Now each argument is one shell word.
#[test]
fn recorded_command_lines_are_shell_words_and_never_panic() {
    use std::os::unix::ffi::OsStrExt;
    let d = tempfile::tempdir().unwrap();
    std::fs::create_dir(d.path().join("sp ace")).unwrap();
    let out = "sp ace/it's.snap";
    assert_ok(&bc(
        d.path(),
        &["run", "striker", "--until", "1", "-q", "--out", out],
    ));
    let s = Snapshot::open(&d.path().join(out)).unwrap();
    let by = &s.header().created_by;
    assert!(
        by.ends_with(" run striker --until 1 -q --out 'sp ace/it'\\''s.snap'"),
        "{by}"
    );
    // exported_by (in the npz's provenance entry, UTF-32 characters): the same quoting
    assert_ok(&bc(d.path(), &["export", out, "--out", "w x.npz"]));
    let z = parse_zip(&std::fs::read(d.path().join("w x.npz")).unwrap());
    let npy = &z["provenance.npy"];
    let hl = u16::from_le_bytes([npy[8], npy[9]]) as usize;
    let json: String = npy[10 + hl..]
        .chunks(4)
        .map(|c| char::from_u32(u32::from_le_bytes([c[0], c[1], c[2], c[3]])).unwrap())
        .collect();
    assert!(
        json.ends_with(r#" export 'sp ace/it'\\''s.snap' --out 'w x.npz'"}"#),
        "{json}"
    );
    let bad = std::ffi::OsStr::from_bytes(b"x\xff.snap");
    let o = Command::new(env!("CARGO_BIN_EXE_beadchain"))
        .args(["run", "striker", "--until", "1", "-q", "--out"])
        .arg(bad)
        .current_dir(d.path())
        .output()
        .unwrap();
    assert_ok(&o);
    let s = Snapshot::open(&d.path().join(bad)).unwrap();
    assert!(
        s.header().created_by.ends_with(" --out 'x\u{fffd}.snap'"),
        "{}",
        s.header().created_by
    );
}
