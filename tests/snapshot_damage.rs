//! Damaged and foreign snapshot files: wrong magic, newer versions, truncation, flipped bytes,
//! corrupted lengths, an unfinished writer. Every failure is an error naming the file and
//! section, never wrong numbers or a huge allocation.

use beadchain::snapshot::{Snapshot, SnapshotError, SnapshotWriter, FORMAT_VERSION, PREAMBLE_LEN};

mod snapshot_support;
use snapshot_support::*;

#[test]
fn wrong_magic_and_empty_file() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("x.snap");
    std::fs::write(&p, b"hello, this is not a snapshot at all").unwrap();
    let e = Snapshot::open(&p).unwrap_err();
    assert!(matches!(e, SnapshotError::NotSnapshot { .. }), "{e}");
    assert!(e.to_string().contains("x.snap") && e.to_string().contains("not a beadchain snapshot"));
    std::fs::write(&p, b"").unwrap();
    assert!(matches!(
        Snapshot::open(&p),
        Err(SnapshotError::NotSnapshot { .. })
    ));
    let missing = Snapshot::open(&dir.path().join("missing.snap")).unwrap_err();
    assert!(
        matches!(missing, SnapshotError::Io { .. }) && missing.to_string().contains("missing.snap")
    );
}

#[test]
fn newer_version_is_rejected() {
    let (_d, p, _) = sample();
    let mut bytes = std::fs::read(&p).unwrap();
    bytes[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
    std::fs::write(&p, &bytes).unwrap();
    let e = Snapshot::open(&p).unwrap_err();
    assert!(
        matches!(e, SnapshotError::UnsupportedVersion { found, .. } if found == FORMAT_VERSION + 1),
        "{e}"
    );
    assert!(e.to_string().contains("newer"), "{e}");
    bytes[8..12].copy_from_slice(&0u32.to_le_bytes());
    std::fs::write(&p, &bytes).unwrap();
    assert!(matches!(
        Snapshot::open(&p),
        Err(SnapshotError::UnsupportedVersion { found: 0, .. })
    ));
}

/// Every prefix of a file either fails to open with an error, or opens with exactly the frames
/// that are whole in the prefix (bit-identical) and a warning saying where it stopped.
#[test]
fn every_truncation_keeps_whole_frames() {
    let (d, p, fr) = sample();
    let bytes = std::fs::read(&p).unwrap();
    let secs = sections(&bytes);
    let header_end = (secs[0].0 + 16 + secs[0].2) as usize;
    let frame_ends: Vec<usize> = secs
        .iter()
        .filter(|(_, t, _)| t == b"FRAM")
        .map(|(o, _, l)| (o + 16 + l) as usize)
        .collect();
    let q = d.path().join("cut.snap");
    for cut in 0..bytes.len() {
        std::fs::write(&q, &bytes[..cut]).unwrap();
        match Snapshot::open(&q) {
            Err(e) => assert!(cut < header_end, "cut {cut}: unexpected error {e}"),
            Ok(s) => {
                assert!(
                    cut >= header_end,
                    "cut {cut}: opened a file without a whole header"
                );
                let whole = frame_ends.iter().filter(|&&e| e <= cut).count();
                assert_eq!(s.frame_count(), whole, "cut {cut}");
                assert!(!s.is_complete());
                assert!(!s.warnings().is_empty(), "cut {cut}: no warning");
                assert!(s.warnings()[0].contains("cut.snap"), "{:?}", s.warnings());
                for (k, f) in fr.iter().enumerate().take(whole) {
                    assert_frame_eq(&s.frame(k).unwrap(), f);
                }
            }
        }
    }
    // A cut inside frame 3 says so, with the byte and the number of frames kept.
    let cut = frame_ends[3] - 10;
    std::fs::write(&q, &bytes[..cut]).unwrap();
    let s = Snapshot::open(&q).unwrap();
    let w = s.warnings().join("\n");
    assert!(
        w.contains("truncated") && w.contains("FRAME #3") && w.contains("kept 3 whole frames"),
        "{w}"
    );
    assert!(w.contains(&format!("byte {cut}")), "{w}");
}

#[test]
fn flipped_frame_byte_names_the_section() {
    let (_d, p, fr) = sample();
    let mut bytes = std::fs::read(&p).unwrap();
    let secs = sections(&bytes);
    let (at, _, _) = secs[3]; // FRAME #2
    bytes[at as usize + 16 + 20] ^= 0x01;
    std::fs::write(&p, &bytes).unwrap();
    let s = Snapshot::open(&p).expect("open still works: frames are checked on read");
    let e = s.frame(2).unwrap_err();
    assert!(
        matches!(&e, SnapshotError::ChecksumMismatch { section, .. } if section == "FRAME #2"),
        "{e}"
    );
    assert!(
        e.to_string()
            .contains("checksum mismatch in section FRAME #2"),
        "{e}"
    );
    assert_frame_eq(&s.frame(1).unwrap(), &fr[1]);
    assert!(s.verify().is_err());
}

#[test]
fn flipped_header_byte_is_an_error() {
    let (_d, p, _) = sample();
    let mut bytes = std::fs::read(&p).unwrap();
    bytes[PREAMBLE_LEN as usize + 40] ^= 0x10;
    std::fs::write(&p, &bytes).unwrap();
    let e = Snapshot::open(&p).unwrap_err();
    assert!(
        matches!(&e, SnapshotError::ChecksumMismatch { section, .. } if section == "HEADER"),
        "{e}"
    );
}

/// Flip every byte in turn, in a finished file (INDEX path) and in one cut before EVENTS
/// (scan path): the reader either reports an error or returns exactly the original numbers,
/// at the original frame numbers. It never returns a wrong number and never panics.
#[test]
fn no_single_byte_corruption_yields_wrong_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("f.snap");
    let fr = frames(2, 3);
    write(&p, &header(2), &fr);
    let full = std::fs::read(&p).unwrap();
    let events_at = sections(&full)[4].0 as usize;
    let q = dir.path().join("g.snap");
    for bytes in [&full[..], &full[..events_at]] {
        for i in 0..bytes.len() {
            let mut b = bytes.to_vec();
            b[i] ^= 0xA5;
            std::fs::write(&q, &b).unwrap();
            let Ok(s) = Snapshot::open(&q) else { continue };
            assert!(s.frame_count() <= fr.len());
            for (k, want) in fr.iter().enumerate().take(s.frame_count()) {
                if let Ok(f) = s.frame(k) {
                    assert_frame_eq(&f, want);
                }
            }
            if !s.events().is_empty() {
                assert_eq!(s.events(), &events()[..], "byte {i}");
            }
            if let Some(sum) = s.summary() {
                assert_eq!(sum, &summary(), "byte {i}");
            }
            assert_eq!(s.header(), &header(2), "byte {i}");
        }
    }
}

#[test]
fn corrupted_length_is_an_error_not_an_allocation() {
    let (d, p, _) = sample();
    let bytes = std::fs::read(&p).unwrap();
    let secs = sections(&bytes);
    let q = d.path().join("len.snap");
    let set_len = |b: &mut Vec<u8>, at: u64, len: u64| {
        b[at as usize + 4..at as usize + 12].copy_from_slice(&len.to_le_bytes());
    };
    // FRAME #1 in a finished file: open works (index), reading that frame fails.
    let mut b = bytes.clone();
    set_len(&mut b, secs[2].0, u64::MAX);
    std::fs::write(&q, &b).unwrap();
    let s = Snapshot::open(&q).unwrap();
    let e = s.frame(1).unwrap_err();
    assert!(
        matches!(&e, SnapshotError::AbsurdLength { section, .. } if section == "FRAME #1"),
        "{e}"
    );
    // Same in a file without INDEX/END (scan path): open fails.
    let cut = secs[6].0 as usize; // start of the EVENT BLOCK
    std::fs::write(&q, &b[..cut]).unwrap();
    assert!(matches!(
        Snapshot::open(&q),
        Err(SnapshotError::AbsurdLength { .. })
    ));
    // HEADER, event and STATS lengths.
    for (sec, name) in [
        (0usize, "HEADER"),
        (6, "EVENT BLOCK #0"),
        (7, "EVENT INDEX"),
        (8, "STATS"),
    ] {
        let mut b = bytes.clone();
        set_len(&mut b, secs[sec].0, u64::MAX);
        std::fs::write(&q, &b).unwrap();
        let e = Snapshot::open(&q).unwrap_err();
        assert!(
            matches!(&e, SnapshotError::AbsurdLength { section, .. } if section == name),
            "{name}: {e}"
        );
    }
    // A smaller but wrong length inside the file is caught by the checksum (covers the length).
    let mut b = bytes.clone();
    set_len(&mut b, secs[6].0, secs[6].2 - 1);
    std::fs::write(&q, &b).unwrap();
    assert!(Snapshot::open(&q).is_err());
}

#[test]
fn unfinished_writer_leaves_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("never.snap");
    {
        let mut w = SnapshotWriter::create(&p, &header(3)).unwrap();
        w.write_frame(0.0, &[0.0; 3], &[1.0, 0.0, 0.0]).unwrap();
        assert!(w.temp_path().exists());
        // Wrong frame shape: an error, and the writer is then dropped.
        let e = w.write_frame(1.0, &[0.0; 2], &[0.0; 3]).unwrap_err();
        assert!(
            matches!(
                e,
                SnapshotError::FrameShape {
                    expected: 3,
                    u_len: 2,
                    ..
                }
            ),
            "{e}"
        );
    }
    assert!(!p.exists());
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "temporary file left behind"
    );
}
