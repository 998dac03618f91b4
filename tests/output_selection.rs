//! Output selection of `run` (issue 14) on the command line: `--beads`, `--fields`,
//! `--frames-max`; frames equal the full run's columns bit for bit, sizes, resume, every reader
//! (inspect, export layouts, analyze/plot refusals: `tests/output_selection_readers.rs`), bad
//! input. The snapshot side (format version 3, golden files, grammar) is in
//! `tests/output_selection_format.rs`.

mod common;
mod output_selection_support;

use beadchain::snapshot::select::parse_beads;
use beadchain::snapshot::{Fields, Frame, Snapshot};
use common::bc;
use output_selection_support::*;
use rand::{Rng, SeedableRng};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

// ---- the selection itself ----------------------------------------------------------------------

#[test]
fn selected_frames_equal_columns_of_a_full_run() {
    let d = tempfile::tempdir().unwrap();
    for engine in ["hybrid", "dense"] {
        ok(&run_striker(d.path(), "full.snap", &["--engine", engine]));
        let full = Snapshot::open(&d.path().join("full.snap")).unwrap();
        for (beads, fields) in [
            ("3,10:20,90:100:3", "u"),
            ("0:100:7", "v"),
            ("", "u"),
            ("99,0", "v,u"),
        ] {
            let mut extra = vec!["--engine", engine, "--fields", fields];
            if !beads.is_empty() {
                extra.extend(["--beads", beads]);
            }
            ok(&run_striker(d.path(), "sub.snap", &extra));
            let sub = Snapshot::open(&d.path().join("sub.snap")).unwrap();
            let sel = sub.selection().clone();
            let want = if beads.is_empty() {
                None
            } else {
                Some(parse_beads(beads, 100).unwrap().unwrap())
            };
            assert_eq!(sel.beads, want, "{beads}");
            assert_eq!(sel.fields, Fields::parse(fields).unwrap());
            assert_eq!(sub.frame_count(), full.frame_count());
            assert_eq!(sub.frame_count(), 21);
            assert_eq!(sub.events(), full.events(), "same run, same events");
            for k in 0..full.frame_count() {
                let (f, g) = (full.frame(k).unwrap(), sub.frame(k).unwrap());
                let m = sel.bead_count(100) as usize;
                let pick = |xs: &[f64], on: bool| -> Vec<f64> {
                    (0..m)
                        .filter(|_| on)
                        .map(|j| xs[sel.bead(j) as usize])
                        .collect()
                };
                let want = Frame {
                    t: f.t,
                    u: pick(&f.u, sel.fields.has_u()),
                    v: pick(&f.v, sel.fields.has_v()),
                    dissipated: f.dissipated,
                };
                assert_eq!(bits(&g), bits(&want), "{engine} {beads} {fields} frame {k}");
            }
        }
    }
}

#[test]
fn file_size_shrinks_by_the_stored_values() {
    let d = tempfile::tempdir().unwrap();
    ok(&run_striker(d.path(), "full.snap", &[]));
    ok(&run_striker(
        d.path(),
        "sub.snap",
        &["--beads", "0:100:4", "--fields", "u"],
    ));
    let full = std::fs::read(d.path().join("full.snap")).unwrap();
    let sub = std::fs::read(d.path().join("sub.snap")).unwrap();
    // 21 frames; a frame stores 2·100 values in full, 25·1 with the selection: every other
    // section is the same but the HEADER (selection, command line).
    let frames = 21u64;
    let saved = frames * 8 * (200 - 25);
    let header_diff = header_len(&sub) as i64 - header_len(&full) as i64;
    assert_eq!(
        full.len() as i64 - sub.len() as i64,
        saved as i64 - header_diff,
        "file sizes {} and {}",
        full.len(),
        sub.len()
    );
    // Each FRAME section: 16 (section header) + 16 (k, t) + 8·values bytes.
    let frame_bytes = |values: u64| frames * (32 + 8 * values);
    assert_eq!(frame_bytes(200) - frame_bytes(25), saved);
}

#[test]
fn size_limit_counts_only_the_stored_values() {
    let d = tempfile::tempdir().unwrap();
    // Estimate (snapshot::size): 12 + 4096 + 64·100 + 80 fixed, 22 frames × (48 + 8·values):
    // 2·100 values → 46844 bytes; 10·1 values → 13404 bytes; 10·2 values → 15164 bytes.
    let limit = ["--max-output-bytes", "20000"];
    let o = run_striker(d.path(), "full.snap", &limit);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("(22 frames of 100 beads"),
        "{}",
        stderr(&o)
    );
    assert!(!d.path().join("full.snap").exists());
    let mut args = limit.to_vec();
    args.extend(["--beads", "0:10", "--fields", "v"]);
    ok(&run_striker(d.path(), "sub.snap", &args));
    let size = std::fs::metadata(d.path().join("sub.snap")).unwrap().len();
    assert!(size < 20000, "{size}");
    let o = run_striker(
        d.path(),
        "sub2.snap",
        &["--max-output-bytes", "10000", "--beads", "0:10"],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("(22 frames of 20 stored values of 100 beads"),
        "{}",
        stderr(&o)
    );
}

// ---- resume ------------------------------------------------------------------------------------

/// A 3000-bead striker run with checkpoints, storing every 100th bead's velocity.
fn resume_args() -> Vec<&'static str> {
    vec![
        "run",
        "s.toml",
        "--out",
        "o.snap",
        "-q",
        "--checkpoint-every",
        "10",
        "--beads",
        "0:3000:100",
        "--fields",
        "v",
        "--frames-max",
        "600",
    ]
}

fn resume_scene(dir: &Path) {
    let scene =
        "[chain]\nbeads = 3000\n[initial]\nstriker = 1.0\n[run]\nuntil = 2500.0\nevery = 5.0\n";
    std::fs::write(dir.join("s.toml"), scene).unwrap();
}

/// Starts the run, waits for its first checkpoint, sends SIGINT: `true` when it stopped with a
/// checkpoint (exit 130), `false` when it finished first.
fn interrupt(dir: &Path, delay: Duration) -> bool {
    let child = Command::new(env!("CARGO_BIN_EXE_beadchain"))
        .args(resume_args())
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawns");
    let t0 = Instant::now();
    while !dir.join("o.snap.ckpt").exists() && t0.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(2));
    }
    std::thread::sleep(delay);
    let st = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill -INT");
    let out = child.wait_with_output().expect("waits");
    match out.status.code() {
        Some(130) => true,
        Some(0) if !st.success() || !dir.join("o.snap.ckpt").exists() => false,
        c => panic!("exit {c:?}: {}", stderr(&out)),
    }
}

#[test]
fn resume_continues_with_the_selection() {
    let want_dir = tempfile::tempdir().unwrap();
    resume_scene(want_dir.path());
    ok(&bc(want_dir.path(), &resume_args()));
    let want = std::fs::read(want_dir.path().join("o.snap")).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(14);
    let mut resumed = 0;
    for _ in 0..4 {
        let d = tempfile::tempdir().unwrap();
        resume_scene(d.path());
        let delay = Duration::from_millis(rng.random_range(0..200));
        if !interrupt(d.path(), delay) {
            continue;
        }
        // The checkpoint holds the full state (every bead), separate from the frames.
        let ck = beadchain::snapshot::ckpt::read_checkpoint(&d.path().join("o.snap.ckpt")).unwrap();
        assert_eq!((ck.scene.chain.len(), ck.writer.n_beads), (3000, 3000));
        // --until beyond the --frames-max the run was started with: refused, still resumable.
        let o = bc(d.path(), &["resume", "o.snap.ckpt", "--until", "5000"]);
        assert_eq!(o.status.code(), Some(2));
        assert_eq!(
            stderr(&o),
            "beadchain: error: o.snap.ckpt: --until: the run would write 1001 frames (--until = 5000, every = 5), more than the cap of 600 frames its output was started with (--frames-max or [output].frames_max); pass --until 2995 or less (the run is unchanged and can still be resumed)\n"
        );
        ok(&bc(d.path(), &["resume", "o.snap.ckpt"]));
        let got = std::fs::read(d.path().join("o.snap")).unwrap();
        assert!(
            got == want,
            "the resumed output differs from the run never interrupted"
        );
        resumed += 1;
    }
    assert!(resumed >= 1, "no run was interrupted before it finished");
    let s = Snapshot::open(&want_dir.path().join("o.snap")).unwrap();
    assert_eq!(s.selection().bead_count(3000), 30);
    assert_eq!(s.frame(3).unwrap().v.len(), 30);
}

// ---- readers: export, inspect, analyze, plot ---------------------------------------------------

#[test]
fn frames_max_refuses_a_run_that_writes_more_and_names_the_every_that_fits() {
    use beadchain::snapshot::size::frame_count;
    let d = tempfile::tempdir().unwrap();
    let o = run_striker(d.path(), "o.snap", &["--frames-max", "10"]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    let prefix = "beadchain: error: striker: --frames-max: the run would write 21 frames (--until = 20, every = 1), more than --frames-max 10; use --every ";
    assert!(
        e.starts_with(prefix) && e.ends_with(" or larger, or raise --frames-max\n"),
        "{e}"
    );
    assert_eq!(
        std::fs::read_dir(d.path()).unwrap().count(),
        0,
        "nothing written"
    );
    let every: f64 = e[prefix.len()..]
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    // The suggestion is until/(K−1) = 20/9 to within 1 ulp, and it fits exactly.
    let rel = (every - 20.0 / 9.0).abs() / (20.0 / 9.0);
    assert!(
        rel <= 2.3e-16,
        "every {every} (relative deviation {rel:e}, tolerance 2.3e-16)"
    );
    assert_eq!(frame_count(20.0, Some(every)), 10.0);
    let shorter = every * (1.0 - 1e-12);
    assert_eq!(
        frame_count(20.0, Some(shorter)),
        11.0,
        "nothing smaller fits"
    );
    let e_text = every.to_string();
    let args = [
        "run",
        "striker",
        "--until",
        "20",
        "--every",
        &e_text,
        "-q",
        "--out",
        "o.snap",
        "--frames-max",
        "10",
    ];
    ok(&bc(d.path(), &args));
    let s = Snapshot::open(&d.path().join("o.snap")).unwrap();
    assert_eq!(s.frame_count(), 10);
    assert_eq!(s.selection().frames_max, Some(10));
    // The boundary: exactly K frames is allowed.
    ok(&run_striker(d.path(), "p.snap", &["--frames-max", "21"]));
    assert_eq!(
        Snapshot::open(&d.path().join("p.snap"))
            .unwrap()
            .frame_count(),
        21
    );
}

// ---- bad input ---------------------------------------------------------------------------------

#[test]
fn bad_selections_are_one_line_errors_naming_the_option() {
    let cases: [(&[&str], &str); 11] = [
        (&["--beads", "100"], "--beads: bead 100 is out of range: the chain has 100 beads (indices 0 to 99)"),
        (&["--beads", "90:101"], "--beads: range '90:101' is out of range: the chain has 100 beads (indices 0 to 99; B may be at most N)"),
        (&["--beads", ""], "--beads: empty selection: give bead indices or ranges A:B"),
        (&["--beads", "5:5"], "--beads: '5:5' selects no bead (A:B is half-open: A < B)"),
        (&["--beads", "3,1:5"], "--beads: bead 3 is selected twice"),
        (&["--beads", "1,,2"], "--beads: invalid item '': expected a bead index I, a range A:B or A:B:STEP (0-based, B excluded)"),
        (&["--beads", "0:10:0"], "--beads: '0:10:0': STEP must be at least 1"),
        (&["--beads", "-3"], "--beads: invalid item '-3': expected a bead index I, a range A:B or A:B:STEP (0-based, B excluded)"),
        (&["--fields", "w"], "--fields: unknown field 'w': expected u, v or u,v (displacements, velocities)"),
        (&["--fields", "u,u"], "--fields: field u is given twice"),
        (&["--frames-max", "1"], "--frames-max: must be at least 2 (a run writes its first and its last frame), got 1"),
    ];
    for (args, msg) in cases {
        let d = tempfile::tempdir().unwrap();
        let o = run_striker(d.path(), "o.snap", args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert_eq!(
            stderr(&o),
            format!("beadchain: error: striker: {msg}\n"),
            "{args:?}"
        );
        assert_eq!(
            std::fs::read_dir(d.path()).unwrap().count(),
            0,
            "{args:?}: nothing written"
        );
    }
}

#[test]
fn a_rejected_selection_never_overwrites_an_existing_snapshot() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("o.snap"), b"previous").unwrap();
    let o = run_striker(d.path(), "o.snap", &["--beads", "7,7"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(std::fs::read(d.path().join("o.snap")).unwrap(), b"previous");
}

/// The size note before a large run (≥ 16 MiB) counts the stored values only: 10⁴ beads ×
/// 202 frames is 31.4 MiB in full (`tests/cli_values.rs`), 16.0 MiB with `u` only (noted), and
/// 0.2 MiB for every 100th bead's `v` (not noted). `--max-steps 1` stops the runs at once.
#[test]
fn size_note_counts_only_the_stored_values() {
    let d = tempfile::tempdir().unwrap();
    let scene =
        "[chain]\nbeads = 10000\n[initial]\nstriker = 1.0\n[run]\nuntil = 20.0\nevery = 0.1\n";
    std::fs::write(d.path().join("big.toml"), scene).unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["run", "big.toml", "--out", "big.snap", "--max-steps", "1"];
        args.extend_from_slice(extra);
        stderr(&bc(d.path(), &args))
    };
    let e = run(&["--fields", "u"]);
    assert!(
        e.contains("beadchain: note: the snapshot will be about 16.0 MiB (202 frames storing beads all (10000 of 10000), fields u)\n"),
        "{e}"
    );
    let e = run(&["--beads", "0:10000:100", "--fields", "v"]);
    assert!(!e.contains("note:"), "{e}");
    assert!(!d.path().join("big.snap").exists());
}
