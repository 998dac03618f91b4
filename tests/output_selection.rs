//! Output selection of `run` (issue 14) on the command line: `--beads`, `--fields`,
//! `--frames-max`; frames equal the full run's columns bit for bit, sizes, resume, every reader
//! (inspect, export layouts, analyze/plot refusals), bad input. The snapshot side (format
//! version 3, golden files, grammar) is in `tests/output_selection_format.rs`.

mod common;

use beadchain::snapshot::select::parse_beads;
use beadchain::snapshot::{Fields, Frame, Snapshot};
use common::bc;
use rand::{Rng, SeedableRng};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

// ---- helpers ---------------------------------------------------------------------------------

fn bits(f: &Frame) -> Vec<u64> {
    std::iter::once(f.t.to_bits())
        .chain(f.u.iter().map(|x| x.to_bits()))
        .chain(f.v.iter().map(|x| x.to_bits()))
        .collect()
}

fn ok(o: &Output) {
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// `beadchain run striker` (the 100-bead preset) to t = 20 with frames every 1, plus `extra`.
fn run_striker(dir: &Path, out: &str, extra: &[&str]) -> Output {
    let mut args = vec![
        "run", "striker", "--until", "20", "--every", "1", "-q", "--out", out,
    ];
    args.extend_from_slice(extra);
    bc(dir, &args)
}

/// Payload length of the HEADER section (bytes 16..24 of the file).
fn header_len(bytes: &[u8]) -> u64 {
    u64::from_le_bytes(bytes[16..24].try_into().unwrap())
}

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
            "beadchain: error: o.snap.ckpt: --until: the run would write 1001 frames (--until = 5000, every = 5), more than --frames-max 600; use --every 8.347245409015025 or larger, or raise --frames-max\n"
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

fn u16le(b: &[u8], at: usize) -> usize {
    u16::from_le_bytes([b[at], b[at + 1]]) as usize
}

fn u32le(b: &[u8], at: usize) -> usize {
    u32::from_le_bytes(b[at..at + 4].try_into().unwrap()) as usize
}

/// Shape and data of a v1.0 little-endian float64 `.npy`.
fn parse_npy(b: &[u8]) -> (Vec<usize>, Vec<f64>) {
    assert_eq!(&b[..8], b"\x93NUMPY\x01\x00");
    let hl = u16le(b, 8);
    let dict = std::str::from_utf8(&b[10..10 + hl]).unwrap();
    let shape = dict
        .split("'shape': (")
        .nth(1)
        .unwrap()
        .split(')')
        .next()
        .unwrap();
    let shape: Vec<usize> = shape
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.parse().unwrap())
        .collect();
    let data: Vec<f64> = b[10 + hl..]
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect();
    assert_eq!(data.len(), shape.iter().product::<usize>(), "{dict}");
    (shape, data)
}

/// The stored entries of a zip, through its central directory.
fn parse_zip(b: &[u8]) -> BTreeMap<String, Vec<u8>> {
    let end = b.len() - 22;
    assert_eq!(u32le(b, end), 0x0605_4b50);
    let mut at = u32le(b, end + 16);
    let mut out = BTreeMap::new();
    for _ in 0..u16le(b, end + 10) {
        let size = u32le(b, at + 20);
        let (nl, xl, cl) = (u16le(b, at + 28), u16le(b, at + 30), u16le(b, at + 32));
        let local = u32le(b, at + 42);
        let name = String::from_utf8(b[at + 46..at + 46 + nl].to_vec()).unwrap();
        let data_at = local + 30 + u16le(b, local + 26) + u16le(b, local + 28);
        out.insert(name, b[data_at..data_at + size].to_vec());
        at += 46 + nl + xl + cl;
    }
    out
}

/// A striker run storing beads 10, 12, …, 18 and 95 (field u), and the full run beside it.
fn subset_and_full(d: &Path) -> (Snapshot, Snapshot) {
    ok(&run_striker(d, "full.snap", &[]));
    ok(&run_striker(
        d,
        "sub.snap",
        &["--beads", "95,10:20:2", "--fields", "u"],
    ));
    let open = |n: &str| Snapshot::open(&d.join(n)).unwrap();
    (open("sub.snap"), open("full.snap"))
}

const SUB_BEADS: [usize; 6] = [10, 12, 14, 16, 18, 95];

#[test]
fn export_of_a_subset_labels_the_real_bead_indices() {
    let d = tempfile::tempdir().unwrap();
    let (_, full) = subset_and_full(d.path());
    let last = full.frame(20).unwrap();
    // wide CSV: columns t,u10,u12,…,u95; values equal the full run's columns bit for bit
    let o = bc(
        d.path(),
        &["export", "sub.snap", "--layout", "wide", "--frame", "last"],
    );
    ok(&o);
    let text = String::from_utf8(o.stdout).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,u10,u12,u14,u16,u18,u95"));
    let row: Vec<f64> = lines
        .next()
        .unwrap()
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    let want: Vec<f64> = std::iter::once(20.0)
        .chain(SUB_BEADS.map(|i| last.u[i]))
        .collect();
    assert_eq!(
        row.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        want.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    );
    // long CSV: frame,t,bead,u with the real index in `bead`
    let o = bc(d.path(), &["export", "sub.snap", "--frame", "last"]);
    ok(&o);
    let text = String::from_utf8(o.stdout).unwrap();
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(rows[0], "frame,t,bead,u");
    assert_eq!(rows.len(), 7);
    for (r, i) in rows[1..].iter().zip(SUB_BEADS) {
        let c: Vec<&str> = r.split(',').collect();
        assert_eq!(&c[..3], &["20", "20", &i.to_string()[..]]);
        assert_eq!(
            c[3].parse::<f64>().unwrap().to_bits(),
            last.u[i].to_bits(),
            "bead {i}"
        );
    }
    // wide NPY: (F, 1 + 6)
    ok(&bc(
        d.path(),
        &["export", "sub.snap", "--layout", "wide", "--out", "w.npy"],
    ));
    let (shape, data) = parse_npy(&std::fs::read(d.path().join("w.npy")).unwrap());
    assert_eq!(shape, [21, 7]);
    for k in 0..21 {
        let f = full.frame(k).unwrap();
        let want: Vec<u64> = std::iter::once(f.t)
            .chain(SUB_BEADS.map(|i| f.u[i]))
            .map(f64::to_bits)
            .collect();
        let got: Vec<u64> = data[7 * k..7 * k + 7].iter().map(|x| x.to_bits()).collect();
        assert_eq!(got, want, "frame {k}");
    }
    // long NPY: (rows, 4) = frame, t, bead, u
    ok(&bc(
        d.path(),
        &["export", "sub.snap", "--out", "l.npy", "--frame", "0"],
    ));
    let (shape, data) = parse_npy(&std::fs::read(d.path().join("l.npy")).unwrap());
    assert_eq!(shape, [6, 4]);
    assert_eq!(
        data.chunks(4).map(|r| r[2] as usize).collect::<Vec<_>>(),
        SUB_BEADS
    );
    // NPZ: t, u (F, 6), beads (6,), chain arrays whole; no v
    ok(&bc(d.path(), &["export", "sub.snap", "--out", "w.npz"]));
    let z = parse_zip(&std::fs::read(d.path().join("w.npz")).unwrap());
    let names: Vec<&str> = z.keys().map(String::as_str).collect();
    assert_eq!(
        names,
        [
            "beads.npy",
            "exponent.npy",
            "mass.npy",
            "precompression.npy",
            "prefactor.npy",
            "t.npy",
            "u.npy"
        ]
    );
    let (shape, b) = parse_npy(&z["beads.npy"]);
    assert_eq!((shape, b), (vec![6], SUB_BEADS.map(|i| i as f64).to_vec()));
    let (shape, u) = parse_npy(&z["u.npy"]);
    assert_eq!(shape, [21, 6]);
    assert_eq!(u[20 * 6 + 5].to_bits(), last.u[95].to_bits());
    assert_eq!(parse_npy(&z["mass.npy"]).0, [100]);
}

#[test]
fn analyze_and_plot_refuse_a_subset_naming_what_is_missing() {
    let d = tempfile::tempdir().unwrap();
    subset_and_full(d.path());
    let stored =
        "sub.snap: frames store beads 10:20:2,95 (6 of 100), fields u only (run --beads/--fields)";
    let o = bc(d.path(), &["analyze", "sub.snap"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        stderr(&o),
        format!("beadchain: error: {stored}; analyze needs every bead and both fields (energies, leading wave)\n")
    );
    let o = bc(d.path(), &["plot", "energy", "sub.snap", "--out", "e.png"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        stderr(&o),
        format!("beadchain: error: {stored}; plot needs every bead and both fields\n")
    );
    assert!(!d.path().join("e.png").exists());
    ok(&bc(d.path(), &["analyze", "full.snap"]));
}

#[test]
fn inspect_reports_the_selection() {
    let d = tempfile::tempdir().unwrap();
    subset_and_full(d.path());
    let o = bc(d.path(), &["inspect", "sub.snap"]);
    ok(&o);
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(
        text.contains("format:      version 4 (this build reads 1..=4), complete"),
        "{text}"
    );
    assert!(
        text.contains(
            "stored:      beads 10:20:2,95 (6 of 100), fields u (run --beads/--fields)\n"
        ),
        "{text}"
    );
    assert!(
        text.contains("energy:      not available: sub.snap: frames store"),
        "{text}"
    );
    assert!(text.contains("frames:      21\n"), "{text}");
    let full = String::from_utf8(bc(d.path(), &["inspect", "full.snap"]).stdout).unwrap();
    assert!(
        !full.contains("stored:") && full.contains("energy:      first frame"),
        "{full}"
    );
}

// ---- --frames-max ------------------------------------------------------------------------------

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
