//! Snapshot format: round trip, determinism, damaged files, exports, golden v1 file.
//!
//! Float comparisons here are bit-exact (absolute and relative tolerance 0) unless stated:
//! the format stores raw IEEE-754 bits and the CSV export prints round-trip decimals.

use beadchain::export::{export_csv, export_events_csv, export_npy, inspect, npy_header, FrameSel};
use beadchain::integrate::{Method, Stats};
use beadchain::model::Chain;
use beadchain::scene::{Engine, RunSettings, Scene};
use beadchain::snapshot::write_atomically;
use beadchain::snapshot::{
    EventKind, EventRecord, Frame, Header, RunSummary, Snapshot, SnapshotError, SnapshotWriter,
    FORMAT_VERSION, PREAMBLE_LEN,
};
use std::path::{Path, PathBuf};

fn scene(n: usize) -> Scene {
    let mut v0 = vec![0.0; n];
    v0[0] = 1.0;
    Scene {
        name: "unit".into(),
        description: "test chain".into(),
        chain: Chain {
            mass: vec![1.0; n],
            exponent: vec![2.5; n - 1],
            prefactor: vec![0.4; n - 1],
            precompression: None,
            field: None,
            left_wall: None,
            right_wall: None,
            hard: None,
            damping: None,
        },
        u0: vec![0.0; n],
        v0,
        run: RunSettings {
            until: 10.0,
            every: Some(1.0),
            ..Default::default()
        },
        seed: 42,
    }
}

fn header(n: usize) -> Header {
    Header::new(
        scene(n),
        Engine::Dense,
        Method::Radau5,
        1e-8,
        1e-10,
        "beadchain run test.toml".into(),
    )
}

/// Deterministic frames with awkward values (tiny, subnormal, negative zero, NaN payload).
fn frames(n: usize, count: usize) -> Vec<Frame> {
    (0..count)
        .map(|k| {
            let t = 0.1 * k as f64 + 1e-17;
            let u = (0..n)
                .map(|i| match (i + k) % 5 {
                    0 => 1e-7 * (i as f64 + 0.1 * k as f64),
                    1 => -0.0,
                    2 => 5e-324 * (k as f64 + 1.0),
                    3 => (0.1 + 0.2) * (i as f64) * 1e300,
                    _ => -1.0 / 3.0 * (k as f64 + 1.0),
                })
                .collect();
            let v = (0..n)
                .map(|i| {
                    if i == 1 && k == 1 {
                        f64::from_bits(0x7ff8_0000_0000_1234)
                    } else {
                        (i as f64).sin() * 1e-7
                    }
                })
                .collect();
            Frame { t, u, v }
        })
        .collect()
}

fn events() -> Vec<EventRecord> {
    vec![
        EventRecord {
            t: 0.5,
            contact: 0,
            kind: EventKind::Close,
            rel_velocity: 1.0,
            peak_overlap: 0.0,
        },
        EventRecord {
            t: 1.25,
            contact: 0,
            kind: EventKind::Open,
            rel_velocity: -0.99,
            peak_overlap: 1.5e-3,
        },
        EventRecord {
            t: 2.0,
            contact: 2,
            kind: EventKind::WallClose,
            rel_velocity: 0.3,
            peak_overlap: 0.0,
        },
    ]
}

fn summary() -> RunSummary {
    RunSummary {
        stats: Stats {
            steps: 120,
            rejected: 3,
            rhs_evals: 900,
            jac_evals: 40,
            factorizations: 41,
            newton_iters: 300,
            newton_failures: 1,
            bead_steps: 480,
        },
        wall_seconds: 0.25,
        t_end: 10.0,
        energy_initial: 0.5,
        energy_final: 0.5000000001,
        momentum_initial: 1.0,
        momentum_final: 1.0,
        events_by_kind: vec![
            ("close".into(), 1),
            ("open".into(), 1),
            ("wall_close".into(), 1),
        ],
        largest_cluster: 3,
        notes: vec!["a note".into()],
    }
}

fn write(path: &Path, h: &Header, fr: &[Frame]) {
    let mut w = SnapshotWriter::create(path, h).expect("create");
    for f in fr {
        w.write_frame(f.t, &f.u, &f.v).expect("write_frame");
    }
    w.finish(&events(), &summary()).expect("finish");
}

fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

fn assert_frame_eq(a: &Frame, b: &Frame) {
    assert_eq!(a.t.to_bits(), b.t.to_bits(), "t differs");
    assert!(same_bits(&a.u, &b.u), "u differs");
    assert!(same_bits(&a.v, &b.v), "v differs");
}

/// A finished 4-bead, 5-frame file in a fresh temporary directory.
fn sample() -> (tempfile::TempDir, PathBuf, Vec<Frame>) {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = dir.path().join("run.snap");
    let fr = frames(4, 5);
    write(&p, &header(4), &fr);
    (dir, p, fr)
}

/// Byte offsets of the sections of a file (walking the section headers).
fn sections(bytes: &[u8]) -> Vec<(u64, [u8; 4], u64)> {
    let mut out = Vec::new();
    let mut pos = PREAMBLE_LEN as usize;
    while pos + 16 <= bytes.len() {
        let tag: [u8; 4] = bytes[pos..pos + 4].try_into().unwrap();
        let len = u64::from_le_bytes(bytes[pos + 4..pos + 12].try_into().unwrap());
        out.push((pos as u64, tag, len));
        pos += 16 + len as usize;
    }
    out
}

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
    assert_eq!(u32::from_le_bytes(bytes[8..12].try_into().unwrap()), 3); // format version 3
    let secs = sections(&bytes);
    let tags: Vec<&[u8; 4]> = secs.iter().map(|(_, t, _)| t).collect();
    let mut want = vec![b"HEAD"];
    want.extend([b"FRAM"; 5]);
    want.extend([b"EVTB", b"EVIX", b"STAT", b"INDX", b"END\0"]);
    assert_eq!(tags, want);
    for (_, t, len) in &secs {
        if t == b"FRAM" {
            assert_eq!(*len, 16 + 16 * 4); // frame number, t, u[4], v[4]
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

#[test]
fn csv_export_header_rows_and_round_trip() {
    let (_d, p, fr) = sample();
    let s = Snapshot::open(&p).unwrap();
    let mut out = Vec::new();
    export_csv(&s, FrameSel::All, &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("frame,t,bead,u,v"));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 5 * 4);
    for row in rows {
        let c: Vec<&str> = row.split(',').collect();
        assert_eq!(c.len(), 5);
        let (k, i): (usize, usize) = (c[0].parse().unwrap(), c[2].parse().unwrap());
        let parse = |x: &str| x.parse::<f64>().unwrap();
        assert_eq!(parse(c[1]).to_bits(), fr[k].t.to_bits(), "{row}");
        assert_eq!(parse(c[3]).to_bits(), fr[k].u[i].to_bits(), "{row}");
        let v = parse(c[4]);
        assert!(
            v.to_bits() == fr[k].v[i].to_bits() || (v.is_nan() && fr[k].v[i].is_nan()),
            "{row}"
        );
    }
    let mut last = Vec::new();
    export_csv(&s, FrameSel::Last, &mut last).unwrap();
    assert_eq!(String::from_utf8(last).unwrap().lines().count(), 1 + 4);
    let e = export_csv(&s, FrameSel::Index(9), &mut Vec::new()).unwrap_err();
    assert!(
        e.to_string().contains("frame 9") && e.to_string().contains("5 frames"),
        "{e}"
    );
}

#[test]
fn frame_selector_parsing() {
    assert_eq!("first".parse::<FrameSel>(), Ok(FrameSel::First));
    assert_eq!("last".parse::<FrameSel>(), Ok(FrameSel::Last));
    assert_eq!("all".parse::<FrameSel>(), Ok(FrameSel::All));
    assert_eq!("17".parse::<FrameSel>(), Ok(FrameSel::Index(17)));
    for bad in ["-1", "", "1.5", "lastt"] {
        let e = bad.parse::<FrameSel>().unwrap_err();
        assert!(e.to_string().contains("invalid frame selector"), "{e}");
    }
}

#[test]
fn npy_header_and_data() {
    for rows in [0u64, 1, 20, 123_456_789] {
        let h = npy_header(rows, 5);
        assert_eq!(&h[..8], b"\x93NUMPY\x01\x00");
        let hl = u16::from_le_bytes([h[8], h[9]]) as usize;
        assert_eq!(h.len(), 10 + hl);
        assert_eq!(h.len() % 64, 0);
        assert_eq!(*h.last().unwrap(), b'\n');
        let dict = std::str::from_utf8(&h[10..]).unwrap();
        assert!(
            dict.starts_with(&format!(
                "{{'descr': '<f8', 'fortran_order': False, 'shape': ({rows}, 5), }}"
            )),
            "{dict}"
        );
    }
    let (d, p, fr) = sample();
    let s = Snapshot::open(&p).unwrap();
    let mut out = Vec::new();
    export_npy(&s, FrameSel::All, &mut out).unwrap();
    let h = npy_header(20, 5);
    assert_eq!(&out[..h.len()], &h[..]);
    let data: Vec<f64> = out[h.len()..]
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert_eq!(data.len(), 20 * 5);
    for (r, row) in data.chunks_exact(5).enumerate() {
        let (k, i) = (r / 4, r % 4);
        assert_eq!([row[0], row[2]], [k as f64, i as f64]);
        assert!(
            same_bits(&row[1..2], &[fr[k].t]) && same_bits(&row[3..5], &[fr[k].u[i], fr[k].v[i]])
        );
    }
    // numpy.load, when numpy is installed.
    let npy = d.path().join("out.npy");
    write_atomically(&npy, |w| export_npy(&s, FrameSel::All, w)).unwrap();
    let have_numpy = std::process::Command::new("python3")
        .args(["-c", "import numpy"])
        .stderr(std::process::Stdio::null())
        .status()
        .map(|st| st.success())
        .unwrap_or(false);
    if !have_numpy {
        println!("note: numpy not available; skipped numpy.load check (header checked in Rust)");
        return;
    }
    let script = "import numpy,sys; a=numpy.load(sys.argv[1]); assert a.shape==(20,5) and a.dtype=='<f8', (a.shape,a.dtype); assert a[7,0]==1 and a[7,2]==3; print('ok')";
    let o = std::process::Command::new("python3")
        .args(["-c", script])
        .arg(&npy)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn events_csv() {
    let (_d, p, _) = sample();
    let s = Snapshot::open(&p).unwrap();
    let mut out = Vec::new();
    export_events_csv(&s, &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "t,contact,kind,rel_velocity,peak_overlap");
    assert_eq!(lines.len(), 1 + events().len());
    assert_eq!(lines[2], "1.25,0,open,-0.99,0.0015");
    assert_eq!(lines[3], "2,2,wall_close,0.3,0");
}

#[test]
fn inspect_reports_frames_and_energy() {
    let (_d, p, _) = sample();
    let s = Snapshot::open(&p).unwrap();
    let report = inspect(&s, &s.header().scene.chain);
    for want in [
        "frames:      5",
        "time span:",
        "energy:      first frame",
        "energy change",
        "radau5",
        "seed 42",
        "complete",
    ] {
        assert!(report.contains(want), "missing {want:?} in\n{report}");
    }
    // Energy of the first frame, computed independently (abs/rel tolerance 0: same formula).
    let f0 = s.frame(0).unwrap();
    let e0 = s.header().scene.chain.energy(&f0.u, &f0.v);
    assert!(
        report.contains(&format!("first frame {e0}"))
            || report.contains(&format!("first frame {e0:e}")),
        "{report}"
    );
}

#[test]
fn write_atomically_leaves_nothing_on_error() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("out.csv");
    let e = write_atomically(&p, |w| {
        w.write_all(b"partial")?;
        Err(SnapshotError::NoFrames {
            path: "in.snap".into(),
        })
    })
    .unwrap_err();
    assert!(matches!(e, SnapshotError::NoFrames { .. }));
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    write_atomically(&p, |w| Ok(w.write_all(b"done")?)).unwrap();
    assert_eq!(std::fs::read(&p).unwrap(), b"done");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

// ---- golden file of format version 1 ------------------------------------------------------

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
        },
        Frame {
            t: 2.5,
            u: vec![1.5e-7, -2.0e-8, 3.0],
            v: vec![-0.25, 0.125, 1.0 / 3.0],
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
