//! Output selection of `run` (issue 14), read back: exports of a subset (long and wide layouts,
//! NPY/NPZ) label the real bead indices, `analyze` and `plot` refuse a subset naming what is
//! missing, `inspect` reports the selection.

mod common;
mod output_selection_support;

use beadchain::snapshot::Snapshot;
use common::bc;
use common::npy::{parse_npy, parse_zip};
use output_selection_support::*;
use std::path::Path;

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
    csv_exports_of_the_subset(d.path(), &full);
    numpy_exports_of_the_subset(d.path(), &full);
}

/// Wide and long CSV of `sub.snap`: the real bead indices, values equal to the full run's.
fn csv_exports_of_the_subset(d: &Path, full: &Snapshot) {
    let last = full.frame(20).unwrap();
    // wide CSV: columns t,u10,u12,…,u95; values equal the full run's columns bit for bit
    let o = bc(
        d,
        &["export", "sub.snap", "--layout", "wide", "--frame", "last"],
    );
    ok(&o);
    let text = String::from_utf8(o.stdout).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
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
    let o = bc(d, &["export", "sub.snap", "--frame", "last"]);
    ok(&o);
    let text = String::from_utf8(o.stdout).unwrap();
    let rows: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
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
}

/// Wide and long NPY and the NPZ of `sub.snap`: shapes, bead indices, values.
fn numpy_exports_of_the_subset(d: &Path, full: &Snapshot) {
    let last = full.frame(20).unwrap();
    // wide NPY: (F, 1 + 6)
    ok(&bc(
        d,
        &["export", "sub.snap", "--layout", "wide", "--out", "w.npy"],
    ));
    let (shape, data) = parse_npy(&std::fs::read(d.join("w.npy")).unwrap());
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
        d,
        &["export", "sub.snap", "--out", "l.npy", "--frame", "0"],
    ));
    let (shape, data) = parse_npy(&std::fs::read(d.join("l.npy")).unwrap());
    assert_eq!(shape, [6, 4]);
    assert_eq!(
        data.chunks(4).map(|r| r[2] as usize).collect::<Vec<_>>(),
        SUB_BEADS
    );
    // NPZ: t, u (F, 6), beads (6,), chain arrays whole; no v
    ok(&bc(d, &["export", "sub.snap", "--out", "w.npz"]));
    let z = parse_zip(&std::fs::read(d.join("w.npz")).unwrap());
    let names: Vec<&str> = z.keys().map(String::as_str).collect();
    assert_eq!(
        names,
        [
            "beads.npy",
            "exponent.npy",
            "mass.npy",
            "precompression.npy",
            "prefactor.npy",
            "provenance.npy",
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
