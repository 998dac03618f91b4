//! Bounded work on hostile or mistaken input (issue 11, items 13–15): output-size limits, no
//! hangs on `/dev/zero`, huge sweep grids, hard scenes in `check` or extreme snapshot values in
//! `plot`, and inputs that used to be accepted or reported unclearly.
//!
//! Each refused case prints `CLASS | command | message` (with `--nocapture`), the source of the
//! rows in `validation/bad-input.md`.

use std::path::Path;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_beadchain");

/// 4 beads struck at v = 1, frames at t = 0, 0.5, 1, 1.5, 2 (5 frames).
const TINY: &str =
    "[chain]\nbeads = 4\n[initial]\nstriker = 1.0\n[run]\nuntil = 2.0\nevery = 0.5\n";

fn bc(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("start beadchain")
}

fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .expect("list")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Exit 2, one `beadchain: error:` line with every needle, nothing written, within `secs`.
fn refused(class: &str, dir: &Path, args: &[&str], needles: &[&str], secs: f64) -> String {
    let before = listing(dir);
    let t0 = Instant::now();
    let o = bc(dir, args);
    let took = t0.elapsed().as_secs_f64();
    let e = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(!e.contains("panicked"), "{class}: {e}");
    assert_eq!(o.status.code(), Some(2), "{class}: stderr {e}");
    assert_eq!(
        e.trim_end().lines().count(),
        1,
        "{class}: not one line: {e}"
    );
    assert!(e.starts_with("beadchain: error: "), "{class}: {e}");
    for n in needles {
        assert!(e.contains(n), "{class}: message lacks {n:?}: {e}");
    }
    assert_eq!(listing(dir), before, "{class}: files left behind");
    assert!(took < secs, "{class}: took {took:.1} s (limit {secs} s)");
    let line = e.trim_end().to_string();
    println!("{class} | `beadchain {}` | {line}", args.join(" "));
    line
}

fn dir_with(files: &[(&str, &str)]) -> tempfile::TempDir {
    let d = tempfile::tempdir().expect("tempdir");
    for (n, t) in files {
        std::fs::write(d.path().join(n), t).expect("write");
    }
    d
}

#[test]
fn oversized_output_is_refused_before_running() {
    let tiny_every = TINY.replace("every = 0.5", "every = 1e-300");
    let far = TINY
        .replace("until = 2.0", "until = 1e300")
        .replace("every = 0.5", "every = 1.0");
    let d = dir_with(&[
        ("s.toml", TINY),
        ("fine.toml", &tiny_every),
        ("far.toml", &far),
    ]);
    let p = d.path();
    // Before: these wrote ~400 MB/s until killed (every = 1e-300, until = 1e300).
    refused(
        "every = 1e-300",
        p,
        &["run", "fine.toml"],
        &[
            "fine.toml",
            "[run].every",
            "2.000e300 frames",
            "above the limit of 10.0 GiB",
            "--force",
        ],
        10.0,
    );
    refused(
        "until = 1e300, every = 1",
        p,
        &["run", "far.toml"],
        &[
            "far.toml",
            "1.000e300 frames",
            "[run].until = 1e300",
            "--max-output-bytes",
        ],
        10.0,
    );
    refused(
        "--every in the wrong unit",
        p,
        &["run", "s.toml", "--until", "2e9", "--every", "1e-3"],
        &["s.toml", "2000000000002 frames", "--until = 2000000000"],
        10.0,
    );
}

#[test]
fn max_output_bytes_and_force_set_the_limit() {
    let d = dir_with(&[("s.toml", TINY)]);
    let p = d.path();
    // The limit applies to the estimate (6 frames of 4 beads is ~5 KiB with the header).
    refused(
        "--max-output-bytes below the estimate",
        p,
        &["run", "s.toml", "--max-output-bytes", "1000"],
        &[
            "s.toml",
            "6 frames of 4 beads",
            "above the limit of 1000 bytes",
        ],
        10.0,
    );
    let o = bc(
        p,
        &[
            "run",
            "s.toml",
            "--max-output-bytes",
            "100000",
            "--out",
            "a.snap",
        ],
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    // The estimate bounds the real size from above; the 5 frame sections alone are 5 x 112 bytes.
    use beadchain::snapshot::size::{frame_count_estimate, output_bytes_estimate};
    let est = output_bytes_estimate(4, frame_count_estimate(0.0, 2.0, Some(0.5)));
    let size = std::fs::metadata(p.join("a.snap")).unwrap().len() as f64;
    assert!(
        size <= est && size >= 5.0 * 112.0,
        "size {size} vs estimate {est}"
    );
    let o = bc(
        p,
        &[
            "run",
            "s.toml",
            "--max-output-bytes",
            "1000",
            "--force",
            "--out",
            "b.snap",
        ],
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn oversized_sweep_run_is_refused_before_any_run() {
    let d = dir_with(&[("s.toml", TINY)]);
    let p = d.path();
    // sweeps: checked per run before any run starts
    std::fs::write(
        p.join("sw.toml"),
        "scene = \"s.toml\"\n[grid]\n\"run.every\" = [0.5, 1e-300]\n",
    )
    .unwrap();
    refused(
        "sweep run with every = 1e-300",
        p,
        &["sweep", "sw.toml"],
        &["sw.toml", "run 1", "run.every", "per run"],
        10.0,
    );
}

#[test]
fn run_of_dev_zero_fails_fast() {
    let d = tempfile::tempdir().expect("tempdir");
    // Before: read /dev/zero forever (killed by a 10 s timeout).
    refused(
        "scene is /dev/zero",
        d.path(),
        &["run", "/dev/zero"],
        &["/dev/zero", "larger than the limit of 256 MiB"],
        20.0,
    );
}

#[test]
fn huge_sweep_grid_is_refused_before_expansion() {
    let values: Vec<String> = (0..2000)
        .map(|i| format!("{}", 2.0 + i as f64 * 1e-4))
        .collect();
    let list = values.join(", ");
    let sweep = format!(
        "scene = \"s.toml\"\n[grid]\n\"chain.exponent\" = [{list}]\n\"initial.striker\" = [{list}]\n"
    );
    let d = dir_with(&[("s.toml", TINY), ("big.toml", &sweep)]);
    refused(
        "2000 x 2000 sweep grid",
        d.path(),
        &["sweep", "big.toml"],
        &["big.toml", "[grid]", "4000000 runs", "limit of 100000"],
        20.0,
    );
}

#[test]
fn plot_of_extreme_values_finishes() {
    use beadchain::scene::{parse_str, Engine};
    use beadchain::snapshot::{Header, RunSummary, SnapshotWriter};
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    let scene = parse_str(TINY, p, "s.toml").expect("scene");
    let header = Header::new(
        scene,
        Engine::Hybrid,
        beadchain::integrate::Method::Radau5,
        1e-8,
        1e-10,
        "crafted".into(),
    );
    let snap = p.join("x.snap");
    let mut w = SnapshotWriter::create(&snap, &header).expect("create");
    for (k, t) in [0.0, 1.0, 2.0].into_iter().enumerate() {
        let big = if k % 2 == 0 { 1e308 } else { -1e308 };
        w.write_frame(t, &[big, -big, 0.0, big], &[-big, big, big, 0.0])
            .expect("frame");
    }
    w.finish(&[], &RunSummary::default()).expect("finish");
    for kind in ["spacetime", "profile", "trace"] {
        let mut args = vec!["plot", kind, "x.snap", "--out"];
        let out = format!("{kind}.png");
        args.push(&out);
        match kind {
            "profile" => args.extend(["--times", "0,1"]),
            "trace" => args.extend(["--beads", "0,1"]),
            _ => {}
        }
        let t0 = Instant::now();
        let mut child = Command::new(BIN)
            .args(&args)
            .current_dir(p)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("spawn");
        let status = loop {
            if let Some(s) = child.try_wait().expect("wait") {
                break s;
            }
            if t0.elapsed() > Duration::from_secs(30) {
                let _ = child.kill();
                panic!("plot {kind}: still running after 30 s (hang)");
            }
            std::thread::sleep(Duration::from_millis(50));
        };
        let mut e = String::new();
        std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut e).unwrap();
        assert!(!e.contains("panicked"), "plot {kind}: {e}");
        // either a figure or a one-line error
        match status.code() {
            Some(0) => assert!(p.join(&out).is_file(), "plot {kind}: no file"),
            Some(2) => assert_eq!(e.trim_end().lines().count(), 1, "{kind}: {e}"),
            c => panic!("plot {kind}: exit {c:?}: {e}"),
        }
        println!(
            "plot {kind} of ±1e308: exit {:?} in {:.2} s {}",
            status.code(),
            t0.elapsed().as_secs_f64(),
            e.trim_end()
        );
    }
}

#[test]
fn invalid_scene_inputs_are_refused() {
    let with = |extra: &str| format!("{TINY}{extra}");
    let cases: [(&str, String, Vec<&str>); 4] = [
        (
            "hard wall with exponent",
            with("[walls]\nleft = { hard = true, exponent = 3.0 }\n"),
            vec!["[walls].left.exponent", "a hard wall has no force law"],
        ),
        (
            "hard wall with prefactor",
            with("[walls]\nright = { hard = true, prefactor = 2.0 }\n"),
            vec!["[walls].right.prefactor", "a hard wall has no force law"],
        ),
        (
            "hard contact listed twice",
            with("[hard]\ncontacts = [1, 1]\n"),
            vec!["[hard].contacts[1]", "contact 1 is listed twice"],
        ),
        (
            "TOML integer overflow",
            format!("[scene]\nseed = 99999999999999999999\n{TINY}"),
            vec!["s.toml:2:", "[scene].seed", "too large"],
        ),
    ];
    for (class, text, needles) in cases {
        let d = dir_with(&[("s.toml", &text)]);
        let mut n = vec!["s.toml"];
        n.extend(needles);
        refused(class, d.path(), &["run", "s.toml"], &n, 10.0);
    }
    let d = dir_with(&[("s.toml", TINY)]);
    for dt in ["0", "nan", "-1", "inf"] {
        refused(
            &format!("--checkpoint-every {dt}"),
            d.path(),
            &["run", "s.toml", &format!("--checkpoint-every={dt}")],
            &[
                "s.toml",
                "--checkpoint-every",
                "must be a finite number > 0",
            ],
            10.0,
        );
    }
}

#[test]
fn csv_with_a_byte_order_mark_is_read() {
    let scene = TINY.replace("beads = 4\n", "beads = 4\nmass = { file = \"m.csv\" }\n");
    let d = dir_with(&[("s.toml", &scene), ("m.csv", "\u{feff}2\n1\n1\n1\n")]);
    // Before: `m.csv:1: expected one number per line, got `\u{feff}2``.
    let o = bc(d.path(), &["run", "s.toml", "--out", "o.snap"]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let snap = beadchain::snapshot::Snapshot::open(&d.path().join("o.snap")).expect("open");
    assert_eq!(snap.header().scene.chain.mass, vec![2.0, 1.0, 1.0, 1.0]);
}

/// A finished 5-frame snapshot of TINY in `dir`, its bytes and the offset of frame 2's payload.
fn snapshot(dir: &Path) -> (Vec<u8>, u64) {
    std::fs::write(dir.join("s.toml"), TINY).unwrap();
    let o = bc(dir, &["run", "s.toml", "--out", "run.snap"]);
    assert_eq!(o.status.code(), Some(0));
    let bytes = std::fs::read(dir.join("run.snap")).unwrap();
    let snap = beadchain::snapshot::Snapshot::open(&dir.join("run.snap")).unwrap();
    let _ = snap.frame(2).unwrap();
    // the FRAME sections are back to back after HEADER: find frame 2 by its tag and number
    let tag = b"FRAM";
    let mut found = Vec::new();
    for i in 0..bytes.len() - 4 {
        if &bytes[i..i + 4] == tag {
            found.push(i as u64);
        }
    }
    assert_eq!(found.len(), 5, "five FRAME tags");
    (bytes, found[2] + 16 + 8 + 8) // header, number, t: first u value
}

#[test]
fn inspect_reports_a_corrupt_frame() {
    let d = tempfile::tempdir().expect("tempdir");
    let (mut bytes, at) = snapshot(d.path());
    bytes[at as usize] ^= 0x40;
    std::fs::write(d.path().join("bad.snap"), &bytes).unwrap();
    let o = bc(d.path(), &["inspect", "bad.snap"]);
    let out = String::from_utf8_lossy(&o.stdout);
    let e = String::from_utf8_lossy(&o.stderr);
    // Before: "version 1 (...), complete", exit 0.
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(out.contains("DAMAGED: 1 of 5 frames"), "{out}");
    assert!(out.contains("damaged:     frame 2: "), "{out}");
    assert!(!out.contains(", complete"), "{out}");
    assert_eq!(e.trim_end().lines().count(), 1, "{e}");
    assert!(
        e.contains("bad.snap: 1 of 5 frames damaged (first: frame 2: "),
        "{e}"
    );
    assert!(e.contains("checksum mismatch"), "{e}");
    println!(
        "inspect: corrupt frame | `beadchain inspect bad.snap` | {}",
        e.trim_end()
    );
    let o = bc(d.path(), &["inspect", "run.snap"]);
    assert_eq!(o.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&o.stdout).contains(", complete"));
}

#[test]
fn analyze_of_a_truncated_snapshot_warns() {
    let d = tempfile::tempdir().expect("tempdir");
    let (bytes, at) = snapshot(d.path());
    std::fs::write(d.path().join("cut.snap"), &bytes[..at as usize]).unwrap();
    let ex = bc(d.path(), &["export", "cut.snap"]);
    let an = bc(d.path(), &["analyze", "cut.snap"]);
    assert_eq!(
        an.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&an.stderr)
    );
    let (ee, ae) = (
        String::from_utf8_lossy(&ex.stderr),
        String::from_utf8_lossy(&an.stderr),
    );
    // Before: analyze printed nothing on stderr.
    assert!(
        ee.contains("beadchain: warning: cut.snap: truncated"),
        "{ee}"
    );
    let warnings = |s: &str| -> Vec<String> {
        s.lines()
            .filter(|l| l.starts_with("beadchain: warning: "))
            .map(String::from)
            .collect()
    };
    assert_eq!(warnings(&ae), warnings(&ee), "analyze: {ae}");
    assert_eq!(warnings(&ae).len(), 2, "{ae}");
}

/// Masses of 1e155 overflow the exact two-body contact: the run wrote NaN displacements into
/// its frames and exited 0 (an adversarial review). Now every frame is checked: exit 2, the
/// bead named, no file.
#[test]
fn non_finite_frame_fails_the_run() {
    let scene = TINY.replace("beads = 4\n", "beads = 4\nmass = 1e155\n");
    let d = dir_with(&[("huge.toml", &scene)]);
    let line = refused(
        "non-finite",
        d.path(),
        &["run", "huge.toml", "--out", "h.snap"],
        &["huge.toml", "state became non-finite", "bead 0"],
        30.0,
    );
    println!("{line}");
}
