//! The `beadchain` binary on bad input: every class exits with code 2, prints ONE line on
//! stderr naming the file and the key/index, never panics, and leaves no output or temporary
//! file behind. Plus the happy path of `run` → `export`/`inspect` and `scenes` (run-to-run
//! determinism of the snapshot bytes: `tests/cli_determinism.rs`).
//!
//! Each bad-input case prints `CLASS | message` (visible with `--nocapture`); those lines are
//! the source of the table in `validation/bad-input.md`.

use std::collections::BTreeSet;
use std::path::Path;
use std::process::{Command, Output};

/// 4 beads struck at v = 1, frames at t = 0, 0.5, 1, 1.5, 2 (5 frames).
const TINY: &str =
    "[chain]\nbeads = 4\n[initial]\nstriker = 1.0\n[run]\nuntil = 2.0\nevery = 0.5\n";
const TINY_BEADS: usize = 4;
const TINY_FRAMES: usize = 5;

fn beadchain(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_beadchain"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("start beadchain")
}

/// Every path under `dir` (recursive, relative), hidden temporaries included.
fn listing(dir: &Path) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("read_dir").flatten() {
            let p = e.path();
            out.insert(p.strip_prefix(dir).unwrap().to_string_lossy().to_string());
            if p.is_dir() {
                stack.push(p);
            }
        }
    }
    out
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

/// Runs `args` in `dir` and checks the bad-input contract; returns the error line.
fn expect_bad(class: &str, dir: &Path, args: &[&str], needles: &[&str]) -> String {
    let before = listing(dir);
    let o = beadchain(dir, args);
    let err = stderr(&o);
    assert!(!err.contains("panicked"), "{class}: panic: {err}");
    assert_eq!(
        o.status.code(),
        Some(2),
        "{class}: exit code; stderr: {err}"
    );
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{class}: stderr is not one line: {err:?}");
    let line = lines[0];
    assert!(line.starts_with("beadchain: error: "), "{class}: {line}");
    for n in needles {
        assert!(
            line.contains(n),
            "{class}: message does not mention {n:?}: {line}"
        );
    }
    assert_eq!(listing(dir), before, "{class}: files left behind");
    println!("{class} | `beadchain {}` | {line}", args.join(" "));
    line.to_string()
}

/// Argument errors found by clap (before `beadchain` code runs): exit 2, no panic, nothing
/// written, the first line is `beadchain: error: …` naming the option, and clap's whole message
/// follows (issue 36: the valid values, "did you mean" and the usage line; main.rs used to keep
/// only the first line).
fn expect_clap_error(class: &str, dir: &Path, args: &[&str], option: &str) {
    let before = listing(dir);
    let o = beadchain(dir, args);
    let err = stderr(&o);
    assert!(!err.contains("panicked"), "{class}: panic: {err}");
    assert_eq!(
        o.status.code(),
        Some(2),
        "{class}: exit code; stderr: {err}"
    );
    let first = err.lines().next().unwrap_or_default();
    assert!(
        first.starts_with("beadchain: error: ") && first.contains(option),
        "{class}: {err}"
    );
    assert!(
        err.contains("try '--help'"),
        "{class}: not clap's whole message: {err}"
    );
    assert_eq!(listing(dir), before, "{class}: files left behind");
    println!(
        "{class} | `beadchain {}` | {}",
        args.join(" "),
        err.trim_end().replace('\n', "⏎")
    );
}

fn scene_dir(files: &[(&str, &str)]) -> tempfile::TempDir {
    let d = tempfile::tempdir().expect("tempdir");
    for (name, text) in files {
        std::fs::write(d.path().join(name), text).expect("write");
    }
    d
}

/// A scene that adds `line` at the top of `[table]` of [`TINY`].
fn tiny_with(table: &str, line: &str) -> String {
    TINY.replace(&format!("[{table}]\n"), &format!("[{table}]\n{line}\n"))
}

/// Bad scene files of the syntax and structure classes: `(class, text, needles)`.
fn bad_structure_cases() -> Vec<(&'static str, String, Vec<&'static str>)> {
    vec![
        (
            "malformed TOML",
            "[chain\nbeads = 4\n".into(),
            vec!["s.toml:1:"],
        ),
        (
            "unknown key",
            tiny_with("chain", "masses = 1.0"),
            vec!["s.toml", "[chain].masses"],
        ),
        (
            "unknown table",
            format!("{TINY}[bogus]\nx = 1\n"),
            vec!["s.toml", "[bogus]"],
        ),
        (
            "wrong array length",
            tiny_with("chain", "mass = [1.0, 1.0, 1.0]"),
            vec!["s.toml", "[chain].mass", "4", "3"],
        ),
        (
            "wrong type",
            tiny_with("chain", "exponent = \"2.5\""),
            vec!["s.toml", "[chain].exponent"],
        ),
        (
            "missing CSV",
            tiny_with("chain", "mass = { file = \"nope.csv\" }"),
            vec!["s.toml", "[chain].mass", "nope.csv"],
        ),
        (
            "non-number in CSV",
            tiny_with("chain", "mass = { file = \"m.csv\" }"),
            vec!["s.toml", "[chain].mass", "m.csv:3"],
        ),
    ]
}

/// Bad scene files of the value classes (non-finite, out of range, missing): `(class, text,
/// needles)`.
fn bad_value_cases() -> Vec<(&'static str, String, Vec<&'static str>)> {
    vec![
        (
            "NaN value",
            tiny_with("chain", "exponent = nan"),
            vec!["s.toml", "[chain].exponent"],
        ),
        (
            "inf in array",
            tiny_with("initial", "velocity = [0.0, inf, 0.0, 0.0]"),
            vec!["s.toml", "[initial].velocity", "1"],
        ),
        (
            "exponent n <= 1",
            tiny_with("chain", "exponent = [2.5, 1.0, 2.5]"),
            vec!["s.toml", "[chain].exponent", "contact 1"],
        ),
        (
            "mass <= 0",
            tiny_with("chain", "mass = [1.0, 1.0, 0.0, 1.0]"),
            vec!["s.toml", "[chain].mass", "bead 2"],
        ),
        (
            "prefactor <= 0",
            tiny_with("chain", "prefactor = -1.0"),
            vec!["s.toml", "[chain].prefactor", "contact 0"],
        ),
        (
            "N < 2",
            TINY.replace("beads = 4", "beads = 1"),
            vec!["s.toml", "[chain].beads"],
        ),
        (
            "until <= 0",
            TINY.replace("until = 2.0", "until = 0.0"),
            vec!["s.toml", "[run].until"],
        ),
        (
            "missing until",
            TINY.replace("until = 2.0\n", ""),
            vec!["s.toml", "[run].until"],
        ),
        (
            "every <= 0",
            TINY.replace("every = 0.5", "every = -1"),
            vec!["s.toml", "[run].every"],
        ),
        (
            "rtol >= 1 in scene",
            tiny_with("run", "rtol = 1.0"),
            vec!["s.toml", "[run].rtol"],
        ),
        (
            "negative seed",
            format!("[scene]\nseed = -1\n{TINY}"),
            vec!["s.toml", "[scene].seed"],
        ),
        (
            "builder range outside chain",
            tiny_with(
                "chain",
                "exponent = { base = 2.5, segments = [{ from = 7, value = 3.0 }] }",
            ),
            vec!["s.toml", "[chain].exponent.segments"],
        ),
        (
            "physical Poisson out of range",
            format!(
                "[units]\nsystem = \"physical\"\nradius = 4e-3\nyoung = 2e11\npoisson = 0.7\n\
                 density = 7650.0\n{TINY}"
            ),
            vec!["s.toml", "[units].poisson"],
        ),
    ]
}

#[test]
fn bad_scene_files() {
    let cases = bad_structure_cases().into_iter().chain(bad_value_cases());
    for (class, text, needles) in cases {
        let d = scene_dir(&[("s.toml", &text), ("m.csv", "1.0\n1.0\nabc\n1.0\n")]);
        expect_bad(class, d.path(), &["run", "s.toml"], &needles);
    }
    let d = tempfile::tempdir().unwrap();
    expect_bad(
        "no such scene",
        d.path(),
        &["run", "nothere.toml"],
        // issue 36: the nearest preset names, or where the list is (no longer the whole list)
        &["nothere.toml", "`beadchain scenes` lists the presets"],
    );
}

#[test]
fn bad_run_arguments() {
    let d = scene_dir(&[("s.toml", TINY)]);
    let p = d.path();
    for (class, flag, value, needle) in [
        ("--rtol 0", "--rtol", "0", "rtol"),
        ("--rtol 1", "--rtol", "1", "rtol"),
        ("--rtol -1e-3", "--rtol=-1e-3", "", "rtol"),
        ("--atol 2", "--atol", "2", "atol"),
        ("--until 0", "--until", "0", "until"),
        ("--until -1", "--until=-1", "", "until"),
        ("--until nan", "--until", "nan", "until"),
        ("--until inf", "--until", "inf", "until"),
        ("--every 0", "--every", "0", "every"),
    ] {
        let mut args = vec!["run", "s.toml", flag];
        if !value.is_empty() {
            args.push(value);
        }
        expect_bad(class, p, &args, &[needle, "s"]);
    }
    expect_clap_error(
        "--rtol not a number",
        p,
        &["run", "s.toml", "--rtol", "abc"],
        "--rtol",
    );
    expect_clap_error(
        "unknown engine",
        p,
        &["run", "s.toml", "--engine", "warp"],
        "--engine",
    );
    expect_clap_error(
        "unknown option",
        p,
        &["run", "s.toml", "--rtoll", "1e-6"],
        "--rtoll",
    );
    expect_bad(
        "--out in a non-existent directory",
        p,
        &["run", "s.toml", "--out", "nodir/x.snap"],
        &["nodir/x.snap"],
    );
    expect_bad(
        "--out names a directory",
        p,
        &["run", "s.toml", "--out", "."],
        &["."],
    );
    expect_bad(
        "--max-steps exceeded",
        p,
        &["run", "s.toml", "--max-steps", "3"],
        &["s"],
    );
}

/// A finished run of the tiny scene in `dir` (`run.snap`).
fn tiny_run(dir: &Path) {
    std::fs::write(dir.join("s.toml"), TINY).unwrap();
    let o = beadchain(dir, &["run", "s.toml", "--out", "run.snap"]);
    assert_eq!(o.status.code(), Some(0), "run failed: {}", stderr(&o));
}

/// Runs [`TINY`] into `run.snap` and writes the damaged and foreign files next to it (a PNG, an
/// empty file, a cut HEADER, a newer version, a flipped HEADER byte, a directory); returns the
/// good snapshot's bytes.
fn write_bad_snapshots(p: &Path) -> Vec<u8> {
    tiny_run(p);
    let snap = std::fs::read(p.join("run.snap")).unwrap();
    std::fs::write(
        p.join("image.png"),
        b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\0\x01",
    )
    .unwrap();
    std::fs::write(p.join("empty.snap"), b"").unwrap();
    std::fs::write(p.join("head.snap"), &snap[..40]).unwrap();
    let mut newer = snap.clone();
    newer[8] = 9;
    std::fs::write(p.join("newer.snap"), &newer).unwrap();
    let mut flipped = snap.clone();
    flipped[30] ^= 0x10; // inside the HEADER payload
    std::fs::write(p.join("flipped.snap"), &flipped).unwrap();
    std::fs::create_dir(p.join("adir")).unwrap();
    snap
}

/// `inspect` and `export` of each file of [`write_bad_snapshots`]: one-line errors naming it.
fn unreadable_snapshots(p: &Path) {
    for cmd in ["inspect", "export"] {
        let c = |class: &str| format!("{cmd}: {class}");
        expect_bad(
            &c("missing snapshot"),
            p,
            &[cmd, "none.snap"],
            &["none.snap"],
        );
        expect_bad(
            &c("foreign file (PNG)"),
            p,
            &[cmd, "image.png"],
            &["image.png", "magic"],
        );
        expect_bad(&c("empty file"), p, &[cmd, "empty.snap"], &["empty.snap"]);
        expect_bad(
            &c("truncated in HEADER"),
            p,
            &[cmd, "head.snap"],
            &["head.snap", "HEADER"],
        );
        expect_bad(
            &c("newer format version"),
            p,
            &[cmd, "newer.snap"],
            &["newer.snap", "9"],
        );
        expect_bad(
            &c("HEADER checksum"),
            p,
            &[cmd, "flipped.snap"],
            &["flipped.snap", "HEADER"],
        );
        expect_bad(&c("a directory"), p, &[cmd, "adir"], &["adir"]);
    }
}

#[test]
fn bad_snapshot_inputs() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let snap = write_bad_snapshots(p);
    unreadable_snapshots(p);
    let e = |class: &str, args: &[&str], needles: &[&str]| expect_bad(class, p, args, needles);
    e(
        "bad --frame",
        &["export", "run.snap", "--frame", "abc"],
        &["--frame", "abc"],
    );
    e(
        "--frame out of range",
        &["export", "run.snap", "--frame", "99"],
        &["run.snap", "frame 99", "5 frames"],
    );
    e(
        "--frame out of range with --out",
        &["export", "run.snap", "--frame", "99", "--out", "x.csv"],
        &["run.snap", "frame 99"],
    );
    e(
        "npy without --out",
        &["export", "run.snap", "--format", "npy"],
        &["--out"],
    );
    e(
        "export --out in a non-existent directory",
        &["export", "run.snap", "--out", "nodir/x.csv"],
        &["nodir/x.csv"],
    );
    e(
        "export --out is a directory",
        &["export", "run.snap", "--out", "adir"],
        &["adir"],
    );
    // A frame damaged inside a finished file: open works (INDEX), exporting it fails.
    let mut frame_hit = snap.clone();
    let last_frame_byte = snap.len() - 200; // inside the frames region of this small file
    frame_hit[last_frame_byte] ^= 0x01;
    std::fs::write(p.join("damaged.snap"), &frame_hit).unwrap();
    let o = beadchain(p, &["export", "damaged.snap", "--out", "y.csv"]);
    println!(
        "export: byte flipped near the end (exit {:?}) | {}",
        o.status.code(),
        stderr(&o).trim()
    );
    assert!(!stderr(&o).contains("panicked"));
    assert!(!p.join("y.csv").exists() || o.status.code() == Some(0));
}

/// A file cut inside the frames keeps its whole frames: exit 0 with a one-line warning.
#[test]
fn truncated_snapshot_keeps_whole_frames() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    tiny_run(p);
    let snap = std::fs::read(p.join("run.snap")).unwrap();
    // Walk the sections (12-byte preamble, then 16-byte headers): event blocks may sit between
    // the frames; cut 10 bytes into the third frame.
    let mut pos = 12;
    let mut frames_seen = 0;
    while frames_seen < 2 || &snap[pos..pos + 4] != b"FRAM" {
        if &snap[pos..pos + 4] == b"FRAM" {
            frames_seen += 1;
        }
        pos += 16 + u64::from_le_bytes(snap[pos + 4..pos + 12].try_into().unwrap()) as usize;
    }
    let cut = pos + 10; // two whole frames and a piece
    std::fs::write(p.join("cut.snap"), &snap[..cut]).unwrap();
    let o = beadchain(p, &["export", "cut.snap"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(err.contains("warning") && err.contains("cut.snap") && err.contains("kept 2 whole"));
    let csv = String::from_utf8_lossy(&o.stdout).to_string();
    // (provenance comment lines first: tests/provenance.rs)
    assert_eq!(
        csv.lines().filter(|l| !l.starts_with('#')).count(),
        1 + 2 * TINY_BEADS
    );
    for l in err.lines() {
        println!("truncated inside FRAME #2 (export, exit 0) | {l}");
    }
    let o = beadchain(p, &["inspect", "cut.snap"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&o.stdout).contains("frames:      2"));
}

#[test]
fn run_export_inspect_scenes() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    tiny_run(p);
    let o = beadchain(p, &["export", "run.snap", "--format", "csv"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let csv = String::from_utf8(o.stdout).unwrap();
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    assert_eq!(lines.next(), Some("frame,t,bead,u,v"));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), TINY_BEADS * TINY_FRAMES);
    assert!(rows.iter().all(|r| r.split(',').count() == 5));
    assert!(rows[0].starts_with("0,0,0,"));
    assert!(rows
        .last()
        .unwrap()
        .starts_with(&format!("4,2,{},", TINY_BEADS - 1)));

    let o = beadchain(
        p,
        &["export", "run.snap", "--format", "npy", "--out", "a.npy"],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let npy = std::fs::read(p.join("a.npy")).unwrap();
    assert!(npy.starts_with(b"\x93NUMPY"));
    let header_len = u16::from_le_bytes([npy[8], npy[9]]) as usize;
    assert_eq!(
        npy.len(),
        10 + header_len + 8 * 5 * TINY_BEADS * TINY_FRAMES
    );

    let o = beadchain(
        p,
        &["export", "run.snap", "--frame", "last", "--out", "last.csv"],
    );
    assert_eq!(o.status.code(), Some(0));
    let last = std::fs::read_to_string(p.join("last.csv")).unwrap();
    assert_eq!(
        last.lines().filter(|l| !l.starts_with('#')).count(),
        1 + TINY_BEADS
    );

    let o = beadchain(p, &["export", "run.snap", "--events"]);
    assert_eq!(o.status.code(), Some(0));
    let ev = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(ev.starts_with("# beadchain "), "{ev}");
    assert!(ev
        .lines()
        .find(|l| !l.starts_with('#'))
        .unwrap()
        .starts_with("t,contact,kind,"));

    let o = beadchain(p, &["inspect", "run.snap"]);
    assert_eq!(o.status.code(), Some(0));
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(
        out.contains(&format!("frames:      {TINY_FRAMES}")),
        "{out}"
    );
    assert!(out.contains("beads:       4"), "{out}");

    let o = beadchain(p, &["scenes"]);
    assert_eq!(o.status.code(), Some(0));
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    assert!(out
        .lines()
        .any(|l| l.split_whitespace().next() == Some("striker")));

    // Nothing but the expected files (no stray temporaries).
    let names = listing(p);
    let want: BTreeSet<String> = ["s.toml", "run.snap", "a.npy", "last.csv"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    assert_eq!(names, want);
}

/// The defect: `export --events` wrote the event log as CSV whatever else was asked: CSV text
/// into `ev.npy` with `--format npy` (numpy then failed on "pickled data"), into `.npz` files,
/// and `--layout`/`--frame 999` were accepted (exit 0). They are refused now; nothing written.
#[test]
fn export_events_refuses_the_options_that_apply_to_frames() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    tiny_run(p);
    let cases: [(&str, &[&str], &[&str]); 5] = [
        (
            "--events --format npy",
            &["--format", "npy", "--out", "ev.npy"],
            &["--events: the event log is written as CSV only, not npy (--format)"],
        ),
        (
            "--events to .npz",
            &["--out", "ev.npz"],
            &["not npz (the --out extension of ev.npz)"],
        ),
        (
            "--events --format npz to stdout",
            &["--format", "npz"],
            &["not npz (--format)"],
        ),
        (
            "--events --layout wide",
            &["--layout", "wide"],
            &["--events: --layout applies to frames"],
        ),
        (
            "--events --frame 999",
            &["--frame", "999"],
            &["--events: --frame applies to frames", "(--frame 999)"],
        ),
    ];
    for (class, extra, needles) in cases {
        let mut args = vec!["export", "run.snap", "--events"];
        args.extend_from_slice(extra);
        expect_bad(class, p, &args, needles);
    }
}
