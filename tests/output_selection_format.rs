//! Output selection (issue 14), the snapshot side: the selection in the header (format version
//! 3), old formats still read (golden files in `data/golden/`), invalid selections refused, the
//! `--beads` grammar, the exact frame count behind `--frames-max`, and the `[output]` scene keys.
//! The command-line options are tested in `tests/output_selection.rs`.

mod common;

use beadchain::integrate::{Method, Stats};
use beadchain::scene::Engine;
use beadchain::snapshot::select::parse_beads;
use beadchain::snapshot::{
    EventKind, EventRecord, Fields, Frame, Header, RunSummary, Selection, Snapshot, SnapshotWriter,
    FORMAT_VERSION,
};
use common::bc;
use rand::{Rng, SeedableRng};
use std::path::{Path, PathBuf};
use std::process::Output;

// ---- golden file of format version 2 ------------------------------------------------------

fn golden_v2_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/golden/v2.snap")
}

/// The exact contents of `data/golden/v2.snap` (tiny: 3 beads, 2 frames, 2 event blocks).
fn golden_v2_fixture() -> (Header, Vec<Frame>, Vec<EventRecord>, RunSummary) {
    let mut h = Header::new(
        common::striker(3, 2.5, 1.0, 1.0, 2.5),
        Engine::Hybrid,
        Method::Auto,
        1e-8,
        1e-12,
        "tests/output_selection.rs write_golden_v2".into(),
    );
    h.crate_version = "golden-v2".into();
    let frames = vec![
        Frame {
            t: 0.0,
            u: vec![0.0, -0.0, 0.0],
            v: vec![1.0, 0.0, 0.0],
            dissipated: None,
        },
        Frame {
            t: 2.5,
            u: vec![1.5e-7, -2.0e-8, 3.0],
            v: vec![-0.25, 0.125, 1.0 / 3.0],
            dissipated: None,
        },
    ];
    let events = vec![
        EventRecord {
            t: 0.5,
            contact: 0,
            kind: EventKind::Close,
            rel_velocity: 1.0,
            peak_overlap: 0.0,
        },
        EventRecord {
            t: 1.25,
            contact: 1,
            kind: EventKind::Open,
            rel_velocity: -0.99,
            peak_overlap: 1.5e-3,
        },
    ];
    let summary = RunSummary {
        stats: Stats {
            steps: 12,
            rejected: 1,
            ..Stats::default()
        },
        t_end: 2.5,
        energy_initial: 0.5,
        energy_final: 0.5,
        notes: vec!["golden".into()],
        ..RunSummary::default()
    };
    (h, frames, events, summary)
}

/// Writes `data/golden/v2.snap` with the format-2 writer (run once, before format 3):
/// `cargo test --release --test output_selection_format -- --ignored write_golden_v2`
#[test]
#[ignore]
fn write_golden_v2() {
    assert_eq!(
        FORMAT_VERSION, 2,
        "only the format-2 writer writes the v2 golden file"
    );
    let (h, frames, events, summary) = golden_v2_fixture();
    let mut w = SnapshotWriter::create(&golden_v2_path(), &h).unwrap();
    w.write_frame(frames[0].t, &frames[0].u, &frames[0].v)
        .unwrap();
    w.write_events(&events[..1]).unwrap();
    w.write_frame(frames[1].t, &frames[1].u, &frames[1].v)
        .unwrap();
    w.finish(&events[1..], &summary).unwrap();
    let s = Snapshot::open(&golden_v2_path()).unwrap();
    assert_eq!(s.header().format_version, 2);
}

#[test]
fn golden_v2_still_reads() {
    let s = Snapshot::open(&golden_v2_path()).expect("golden v2 file");
    let (h, frames, events, summary) = golden_v2_fixture();
    assert!(s.is_complete() && s.warnings().is_empty());
    assert_eq!(s.header().format_version, 2);
    // Version 2 has no output selection: it reads as every bead and both fields.
    assert_eq!(
        s.header(),
        &Header {
            format_version: 2,
            build_commit: None,
            ..h
        }
    );
    assert!(s.selection().is_full());
    assert_eq!(s.frame_count(), 2);
    for (k, f) in frames.iter().enumerate() {
        assert_eq!(bits(&s.frame(k).unwrap()), bits(f), "frame {k}");
    }
    assert_eq!(s.events(), &events[..]);
    assert_eq!(s.summary(), Some(&summary));
}

#[test]
fn golden_v1_reads_as_full_selection() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/golden/v1.snap");
    let s = Snapshot::open(&p).expect("golden v1 file");
    assert_eq!(s.header().format_version, 1);
    assert_eq!(s.selection(), &Selection::default());
    assert_eq!(s.frame(1).unwrap().u.len(), 3);
}

// ---- golden file of format version 3 with a selection ---------------------------------------

fn golden_v3_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/golden/v3_selection.snap")
}

/// `data/golden/v3_selection.snap`: the v2 fixture's run storing beads 0 and 2, field v, cap 5.
fn golden_v3_selection() -> Selection {
    Selection {
        beads: Some(vec![0, 2]),
        fields: Fields::V,
        frames_max: Some(5),
    }
}

/// Writes `data/golden/v3_selection.snap` (run once, while the format is version 3):
/// `cargo test --release --test output_selection_format -- --ignored write_golden_v3`
#[test]
#[ignore]
fn write_golden_v3() {
    assert_eq!(
        FORMAT_VERSION, 3,
        "only the format-3 writer writes the v3 golden file"
    );
    let (mut h, frames, events, summary) = golden_v2_fixture();
    h.crate_version = "golden-v3".into();
    h.output = golden_v3_selection();
    let mut w = SnapshotWriter::create(&golden_v3_path(), &h).unwrap();
    for f in &frames {
        w.write_frame(f.t, &f.u, &f.v).unwrap();
    }
    w.finish(&events, &summary).unwrap();
}

#[test]
fn golden_v3_selection_still_reads() {
    let s = Snapshot::open(&golden_v3_path()).expect("golden v3 file");
    assert!(s.is_complete() && s.warnings().is_empty());
    assert_eq!(s.header().format_version, 3);
    assert_eq!(s.selection(), &golden_v3_selection());
    let (_, frames, _, _) = golden_v2_fixture();
    for (k, f) in frames.iter().enumerate() {
        let got = s.frame(k).unwrap();
        assert!(got.u.is_empty(), "u is not stored");
        let want = Frame {
            t: f.t,
            u: vec![],
            v: vec![f.v[0], f.v[2]],
            dissipated: None,
        };
        assert_eq!(bits(&got), bits(&want), "frame {k}");
    }
    assert_eq!(s.frame_count(), 2);
}

fn bits(f: &Frame) -> Vec<u64> {
    std::iter::once(f.t.to_bits())
        .chain(f.u.iter().map(|x| x.to_bits()))
        .chain(f.v.iter().map(|x| x.to_bits()))
        .collect()
}

/// Payload length of the HEADER section (bytes 16..24 of the file).
fn header_len(bytes: &[u8]) -> u64 {
    u64::from_le_bytes(bytes[16..24].try_into().unwrap())
}

#[test]
fn frame_count_matches_what_the_engines_write() {
    use beadchain::snapshot::size::frame_count;
    let scene = common::striker(5, 2.5, 1.0, 1.0, 1.0);
    for engine in [Engine::Hybrid, Engine::Dense] {
        for (until, every) in [
            (20.0, Some(1.0)),
            (20.0, Some(3.0)),
            (1.0, Some(0.1)),
            (0.7, Some(0.1)),
            (20.0, Some(25.0)),
            (3.0, None),
        ] {
            let mut cfg = common::config(engine, Method::Dop853, 1e-8, 1e-10, until);
            cfg.every = every;
            let (_, rec) = common::run(&scene, &cfg);
            assert_eq!(
                rec.t.len() as f64,
                frame_count(until, every),
                "{engine:?} until {until} every {every:?}"
            );
        }
    }
}

// ---- grammar -----------------------------------------------------------------------------------

#[test]
fn bead_lists_parse_sorted_and_print_back() {
    let p = |s: &str| parse_beads(s, 100).unwrap();
    assert_eq!(p("0:10:3"), Some(vec![0, 3, 6, 9]));
    assert_eq!(p("97:"), Some(vec![97, 98, 99]));
    assert_eq!(p(":3, 50"), Some(vec![0, 1, 2, 50]));
    assert_eq!(p("20,3,10"), Some(vec![3, 10, 20]));
    assert_eq!(p("0:100"), None, "every bead is stored as 'all'");
    assert_eq!(p("50:,:50"), None);
    // Seeded random selections print as a list that parses back to the same beads.
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1414);
    for _ in 0..200 {
        let n = rng.random_range(1..300u64);
        let list: Vec<u64> = (0..n).filter(|_| rng.random_bool(0.3)).collect();
        if list.is_empty() || list.len() as u64 == n {
            continue;
        }
        let sel = Selection {
            beads: Some(list.clone()),
            ..Selection::default()
        };
        let text = sel.beads_text(n);
        if !text.contains('…') {
            assert_eq!(parse_beads(&text, n).unwrap(), Some(list), "{text}");
        }
    }
}

// ---- invalid selections in the library ---------------------------------------------------------

#[test]
fn writer_refuses_an_invalid_selection_and_reader_calls_it_corrupt() {
    let d = tempfile::tempdir().unwrap();
    let (mut h, ..) = golden_v2_fixture();
    for bad in [vec![2, 0], vec![], vec![0, 3]] {
        h.output.beads = Some(bad.clone());
        let p = d.path().join("bad.snap");
        let e = SnapshotWriter::create(&p, &h).err().expect("refused");
        assert!(
            e.to_string().contains("encoding section HEADER"),
            "{bad:?}: {e}"
        );
        assert_eq!(
            std::fs::read_dir(d.path()).unwrap().count(),
            0,
            "{bad:?}: nothing written"
        );
    }
    // The golden v3 file with its two stored beads swapped (checksum recomputed).
    let mut b = std::fs::read(golden_v3_path()).unwrap();
    let len = header_len(&b) as usize;
    let end = 28 + len; // preamble 12 + section header 16 + payload
                        // payload tail: beads Some(len 2, 0, 2) | fields u32 | frames_max Some(5)
    let beads_at = end - 13 - 16;
    let (x, y) = (
        b[beads_at..beads_at + 8].to_vec(),
        b[beads_at + 8..beads_at + 16].to_vec(),
    );
    b[beads_at..beads_at + 8].copy_from_slice(&y);
    b[beads_at + 8..beads_at + 16].copy_from_slice(&x);
    let mut crc = crc32fast::Hasher::new();
    crc.update(&b[12..24]);
    crc.update(&b[28..end]);
    let crc = crc.finalize();
    b[24..28].copy_from_slice(&crc.to_le_bytes());
    let p = d.path().join("swapped.snap");
    std::fs::write(&p, &b).unwrap();
    let e = Snapshot::open(&p).expect_err("corrupt").to_string();
    assert!(
        e.ends_with("corrupt section HEADER at byte 12: the output selection's beads are not strictly increasing"),
        "{e}"
    );
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

// ---- scene keys: [output] ----------------------------------------------------------------------

const OUTPUT_SCENE: &str = "[chain]\nbeads = 4\n[initial]\nstriker = 1.0\n[run]\nuntil = 2.0\nevery = 0.5\n[output]\nbeads = [2, 0]\nfields = \"v\"\nframes_max = 5\n";

#[test]
fn scene_output_keys_select_and_options_override_them() {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("s.toml"), OUTPUT_SCENE).unwrap();
    ok(&bc(d.path(), &["run", "s.toml", "-q", "--out", "a.snap"]));
    let a = Snapshot::open(&d.path().join("a.snap")).unwrap();
    assert_eq!(a.selection().beads, Some(vec![0, 2]));
    assert_eq!(
        (a.selection().fields, a.selection().frames_max),
        (Fields::V, Some(5))
    );
    assert_eq!(a.frame_count(), 5);
    let args = [
        "run", "s.toml", "-q", "--out", "b.snap", "--beads", "1:", "--fields", "u",
    ];
    ok(&bc(d.path(), &args));
    let b = Snapshot::open(&d.path().join("b.snap")).unwrap();
    assert_eq!(b.selection().beads, Some(vec![1, 2, 3]));
    assert_eq!(
        (b.selection().fields, b.selection().frames_max),
        (Fields::U, Some(5))
    );
    let o = bc(
        d.path(),
        &[
            "run",
            "s.toml",
            "-q",
            "--out",
            "c.snap",
            "--frames-max",
            "4",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(
        stderr(&o),
        "beadchain: error: s.toml: --frames-max: the run would write 5 frames ([run].until = 2, every = 0.5), more than --frames-max 4; use --every 0.6666666666666666 or larger, or raise --frames-max\n"
    );
    assert!(!d.path().join("c.snap").exists());
}

#[test]
fn bad_scene_output_keys_are_one_line_errors_naming_the_key() {
    let cases = [
        ("beads = [2, 0]", "beads = \"9\"", "[output].beads: bead 9 is out of range: the chain has 4 beads (indices 0 to 3)"),
        // the array's bad item is named by its position (it said only "an array with an invalid item")
        ("beads = [2, 0]", "beads = [0, -1]", "[output].beads[1]: expected a bead index (an integer >= 0), got -1"),
        ("fields = \"v\"", "fields = [\"u\", 3]", "[output].fields[1]: expected a field name (a string), got 3"),
        ("beads = [2, 0]", "beads = [1, 1]", "[output].beads: bead 1 is selected twice"),
        ("beads = [2, 0]", "beads = 1.5", "[output].beads: expected a bead index, a string such as \"0:100:10\" or an array of bead indices, got a number"),
        ("fields = \"v\"", "fields = \"w\"", "[output].fields: unknown field 'w': expected u, v or u,v (displacements, velocities)"),
        ("frames_max = 5", "frames_max = 1", "[output].frames_max: must be an integer >= 2 (a run writes its first and its last frame), got 1"),
        ("frames_max = 5", "frame_max = 5", "[output].frame_max: unknown key (expected one of: beads, fields, frames_max)"),
        ("frames_max = 5", "frames_max = 4", "[output].frames_max: the run would write 5 frames ([run].until = 2, every = 0.5), more than [output].frames_max 4; use --every 0.6666666666666666 or larger, or raise [output].frames_max"),
    ];
    for (from, to, msg) in cases {
        let d = tempfile::tempdir().unwrap();
        std::fs::write(d.path().join("s.toml"), OUTPUT_SCENE.replace(from, to)).unwrap();
        let o = bc(d.path(), &["run", "s.toml", "-q", "--out", "o.snap"]);
        assert_eq!(o.status.code(), Some(2), "{to}");
        assert_eq!(
            stderr(&o),
            format!("beadchain: error: s.toml: {msg}\n"),
            "{to}"
        );
        assert!(!d.path().join("o.snap").exists(), "{to}");
    }
}
