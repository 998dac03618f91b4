//! Exports of snapshots: CSV (long layout), frame selectors, NPY, the events CSV, `inspect`,
//! atomic output files.
//!
//! Float comparisons here are bit-exact (absolute and relative tolerance 0): the CSV export
//! prints round-trip decimals and NPY stores raw IEEE-754 bits.

use beadchain::export::{
    export_csv, export_events_csv, export_npy, inspect, npy_header, ExportUnits, FrameSel,
};
use beadchain::snapshot::{write_atomically, Snapshot, SnapshotError};

mod snapshot_support;
use snapshot_support::*;

#[test]
fn csv_export_header_rows_and_round_trip() {
    let (_d, p, fr) = sample();
    let s = Snapshot::open(&p).unwrap();
    let mut out = Vec::new();
    export_csv(&s, FrameSel::All, &ExportUnits::computer(), &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    // the provenance comments first (tests/provenance.rs): always 4 lines
    assert_eq!(text.lines().take_while(|l| l.starts_with("# ")).count(), 4);
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
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
    export_csv(&s, FrameSel::Last, &ExportUnits::computer(), &mut last).unwrap();
    let last = String::from_utf8(last).unwrap();
    assert_eq!(last.lines().filter(|l| !l.starts_with('#')).count(), 1 + 4);
    let e = export_csv(
        &s,
        FrameSel::Index(9),
        &ExportUnits::computer(),
        &mut Vec::new(),
    )
    .unwrap_err();
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
        let h = npy_header("<f8", &[rows, 5]);
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
    export_npy(&s, FrameSel::All, &ExportUnits::computer(), &mut out).unwrap();
    let h = npy_header("<f8", &[20, 5]);
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
    write_atomically(&npy, |w| {
        export_npy(&s, FrameSel::All, &ExportUnits::computer(), w)
    })
    .unwrap();
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
    export_events_csv(&s, &ExportUnits::computer(), &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
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
