//! Output selection of `run` (issue 14): `--beads`, `--fields`, `--frames-max`; the selection
//! recorded in the snapshot header (format version 3) and honoured by every reader; old formats
//! still read (golden files in `data/golden/`).

mod common;

use beadchain::integrate::{Method, Stats};
use beadchain::scene::Engine;
use beadchain::snapshot::{
    EventKind, EventRecord, Frame, Header, RunSummary, Snapshot, SnapshotWriter, FORMAT_VERSION,
};
use std::path::{Path, PathBuf};

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
        },
        Frame {
            t: 2.5,
            u: vec![1.5e-7, -2.0e-8, 3.0],
            v: vec![-0.25, 0.125, 1.0 / 3.0],
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
/// `cargo test --release --test output_selection -- --ignored write_golden_v2`
#[test]
#[ignore]
fn write_golden_v2() {
    assert_eq!(FORMAT_VERSION, 2, "only the format-2 writer writes the v2 golden file");
    let (h, frames, events, summary) = golden_v2_fixture();
    let mut w = SnapshotWriter::create(&golden_v2_path(), &h).unwrap();
    w.write_frame(frames[0].t, &frames[0].u, &frames[0].v).unwrap();
    w.write_events(&events[..1]).unwrap();
    w.write_frame(frames[1].t, &frames[1].u, &frames[1].v).unwrap();
    w.finish(&events[1..], &summary).unwrap();
    let s = Snapshot::open(&golden_v2_path()).unwrap();
    assert_eq!(s.header().format_version, 2);
}
