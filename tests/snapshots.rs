//! Snapshot format: round trip, determinism, layout, event blocks, golden v1 file (damaged
//! files: `snapshot_damage.rs`; exports: `snapshot_exports.rs`).
//!
//! Float comparisons here are bit-exact (absolute and relative tolerance 0) unless stated:
//! the format stores raw IEEE-754 bits and the CSV export prints round-trip decimals.

use beadchain::snapshot::{Frame, Header, Snapshot, SnapshotError, SnapshotWriter, FORMAT_VERSION};
use std::path::{Path, PathBuf};

mod snapshot_support;
use snapshot_support::*;

#[test]
fn round_trip_is_bit_identical() {
    let (_d, p, fr) = sample();
    let s = Snapshot::open(&p).expect("open");
    assert!(s.is_complete());
    assert!(s.warnings().is_empty(), "{:?}", s.warnings());
    assert_eq!(s.header(), &header(4));
    assert_eq!(s.header().format_version, FORMAT_VERSION);
    assert_eq!(s.frame_count(), 5);
    for (k, f) in fr.iter().enumerate() {
        assert_eq!(s.frame_time(k).unwrap().to_bits(), f.t.to_bits());
        assert_frame_eq(&s.frame(k).unwrap(), f);
    }
    // Random access in reverse order works as well.
    assert_frame_eq(&s.frame(3).unwrap(), &fr[3]);
    assert_frame_eq(&s.frame(0).unwrap(), &fr[0]);
    assert_eq!(s.events(), &events()[..]);
    assert_eq!(s.summary(), Some(&summary()));
    s.verify().expect("verify");
    assert!(matches!(
        s.frame(5),
        Err(SnapshotError::FrameOutOfRange {
            index: 5,
            count: 5,
            ..
        })
    ));
}

#[test]
fn same_inputs_give_identical_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let (a, b) = (dir.path().join("a.snap"), dir.path().join("b.snap"));
    write(&a, &header(6), &frames(6, 7));
    write(&b, &header(6), &frames(6, 7));
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
}

#[test]
fn layout_matches_documentation() {
    let (_d, p, _) = sample();
    let bytes = std::fs::read(&p).unwrap();
    assert_eq!(&bytes[..8], b"BEADCHN\0");
    assert_eq!(u32::from_le_bytes(bytes[8..12].try_into().unwrap()), 4); // format version 4
    let secs = sections(&bytes);
    let tags: Vec<&[u8; 4]> = secs.iter().map(|(_, t, _)| t).collect();
    let mut want = vec![b"HEAD"];
    want.extend([b"FRAM"; 5]);
    want.extend([b"EVTB", b"EVIX", b"STAT", b"INDX", b"END\0"]);
    assert_eq!(tags, want);
    for (_, t, len) in &secs {
        if t == b"FRAM" {
            assert_eq!(*len, 24 + 16 * 4); // frame number, t, dissipated energy, u[4], v[4]
        }
    }
    let (end_at, _, _) = secs[secs.len() - 1];
    assert_eq!(end_at as usize + 24, bytes.len());
    let index_at = u64::from_le_bytes(bytes[end_at as usize + 16..].try_into().unwrap());
    assert_eq!(index_at, secs[secs.len() - 2].0);
}

/// Event blocks written between frames read back as one log, in order, both through the EVENT
/// INDEX (finished file) and by a scan (END damaged); blocks swapped in place are an error in
/// either path, never a reordered log.
#[test]
fn event_blocks_between_frames_read_back_in_order() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("blocks.snap");
    let fr = frames(4, 3);
    let ev = events();
    let mut w = SnapshotWriter::create(&p, &header(4)).unwrap();
    w.write_events(&ev[..1]).unwrap();
    w.write_frame(fr[0].t, &fr[0].u, &fr[0].v).unwrap();
    w.write_events(&[]).unwrap(); // nothing: no section
    w.write_frame(fr[1].t, &fr[1].u, &fr[1].v).unwrap();
    w.write_events(&ev[1..2]).unwrap();
    w.write_frame(fr[2].t, &fr[2].u, &fr[2].v).unwrap();
    assert_eq!(w.event_blocks_written(), 2);
    w.finish(&ev[2..], &summary()).unwrap();
    let bytes = std::fs::read(&p).unwrap();
    let tags: Vec<[u8; 4]> = sections(&bytes).iter().map(|(_, t, _)| *t).collect();
    let want: Vec<&[u8; 4]> = vec![
        b"HEAD", b"EVTB", b"FRAM", b"FRAM", b"EVTB", b"FRAM", b"EVTB", b"EVIX", b"STAT", b"INDX",
        b"END\0",
    ];
    assert_eq!(tags.iter().collect::<Vec<_>>(), want);
    let s = Snapshot::open(&p).unwrap();
    assert!(s.is_complete());
    assert_eq!(s.events(), &ev[..]);
    // scan path: damage END
    let mut b = bytes.clone();
    let last = b.len() - 1;
    b[last] ^= 0xFF;
    std::fs::write(&p, &b).unwrap();
    let s = Snapshot::open(&p).unwrap();
    assert!(!s.is_complete());
    assert_eq!(s.events(), &ev[..]);
    assert_eq!(s.frame_count(), 3);
    // blocks 0 and 1 (same length) swapped: the EVENT INDEX no longer lists them in order
    let secs = sections(&bytes);
    let (b0, b1) = (secs[1], secs[4]);
    let range = |x: (u64, [u8; 4], u64)| x.0 as usize..(x.0 + 16 + x.2) as usize;
    assert_eq!(b0.2, b1.2);
    let mut swapped = bytes.clone();
    swapped[range(b0)].copy_from_slice(&bytes[range(b1)]);
    swapped[range(b1)].copy_from_slice(&bytes[range(b0)]);
    for damage_end in [false, true] {
        let mut b = swapped.clone();
        if damage_end {
            let last = b.len() - 1;
            b[last] ^= 0xFF;
        }
        std::fs::write(&p, &b).unwrap();
        match Snapshot::open(&p) {
            Ok(s) => panic!("swapped blocks read as {:?}", s.events()),
            Err(e) => assert!(e.to_string().contains("EVENT"), "{e}"),
        }
    }
}

fn golden_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/golden/v1.snap")
}

/// The exact contents of `data/golden/v1.snap` (tiny: 3 beads, 2 frames).
fn golden_fixture() -> (Header, Vec<Frame>) {
    let mut h = header(3);
    h.crate_version = "golden-v1".into();
    h.created_by = "tests/snapshots.rs write_golden_v1".into();
    let fr = vec![
        Frame {
            t: 0.0,
            u: vec![0.0, 0.0, 0.0],
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
    (h, fr)
}

/// Writes the golden file. Run once when a format version is introduced:
/// `cargo test --test snapshots -- --ignored write_golden_v1`
#[test]
#[ignore]
fn write_golden_v1() {
    let (h, fr) = golden_fixture();
    std::fs::create_dir_all(golden_path().parent().unwrap()).unwrap();
    write(&golden_path(), &h, &fr);
}

#[test]
fn golden_v1_still_reads() {
    let s = Snapshot::open(&golden_path()).expect("golden v1 file");
    let (h, fr) = golden_fixture();
    assert!(s.is_complete() && s.warnings().is_empty());
    assert_eq!(s.header().format_version, 1);
    assert_eq!(
        s.header(),
        &Header {
            format_version: 1,
            build_commit: None,
            ..h
        }
    );
    assert_eq!(s.frame_count(), 2);
    for (k, f) in fr.iter().enumerate() {
        assert_frame_eq(&s.frame(k).unwrap(), f);
    }
    assert_eq!(s.events(), &events()[..]);
    assert_eq!(s.summary(), Some(&summary()));
}

#[test]
fn current_writer_reproduces_golden_v1_while_format_is_v1() {
    if FORMAT_VERSION != 1 {
        return; // a newer writer legitimately writes different bytes
    }
    let (h, fr) = golden_fixture();
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("g.snap");
    write(&p, &h, &fr);
    assert_eq!(
        std::fs::read(&p).unwrap(),
        std::fs::read(golden_path()).unwrap()
    );
}
