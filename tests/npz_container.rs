//! The `.npz` container (issue 34, formats through crates): every `.npz` is written by the `zip`
//! crate through `export::npz`. Checked here: identical inputs give identical bytes (fixed
//! timestamps, no compression), an independent reader (the `zip` crate's `ZipArchive`) finds
//! every entry, stored, with the `.npy` shape expected, the size computed before writing equals
//! the archive's, and an archive beyond 4 GiB is refused before a byte is written.

mod common;

use common::bc;
use common::npy::{parse_npy, parse_zip};

use beadchain::export::npz::{self, write_npz_arrays};
use beadchain::export::wide::{export_npz, npz_bytes_of};
use beadchain::export::{ExportUnits, FrameSel};
use beadchain::snapshot::Snapshot;
use std::collections::BTreeMap;
use std::io::{Cursor, Read};
use std::process::Output;

fn ok(o: &Output) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
}

/// 4 beads, precompressed, 5 frames.
const SCENE: &str = "[chain]\nbeads = 4\nmass = [1.0, 2.0, 1.5, 1.0]\nprecompression = 0.01\n[initial]\nstriker = 1.0\n[run]\nuntil = 2.0\nevery = 0.5\n";

fn setup(run_args: &[&str]) -> (tempfile::TempDir, Snapshot) {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("s.toml"), SCENE).unwrap();
    let mut args = vec!["run", "s.toml", "--out", "s.snap", "-q"];
    args.extend(run_args);
    ok(&bc(d.path(), &args));
    let snap = Snapshot::open(&d.path().join("s.snap")).unwrap();
    (d, snap)
}

/// The entries of `bytes` read by the `zip` crate: name → (data), each checked to be stored,
/// dated 1980-01-01 00:00 and CRC-verified (the reader checks the CRC at the end of the data).
fn read_with_zip_crate(bytes: &[u8]) -> BTreeMap<String, Vec<u8>> {
    let mut a = zip::ZipArchive::new(Cursor::new(bytes)).unwrap();
    let mut out = BTreeMap::new();
    for i in 0..a.len() {
        let mut f = a.by_index(i).unwrap();
        let name = f.name().unwrap().to_string();
        assert_eq!(f.compression(), zip::CompressionMethod::Stored, "{name}");
        let t = f.last_modified().unwrap();
        assert_eq!((t.year(), t.month(), t.day()), (1980, 1, 1), "{name}");
        assert_eq!((t.hour(), t.minute(), t.second()), (0, 0, 0), "{name}");
        let mut data = Vec::new();
        f.read_to_end(&mut data).unwrap();
        out.insert(name, data);
    }
    out
}

fn export(snap: &Snapshot) -> Vec<u8> {
    let mut out = Vec::new();
    let units = ExportUnits::computer();
    export_npz(snap, FrameSel::All, &units, "beadchain export", &mut out).unwrap();
    out
}

#[test]
fn two_exports_of_one_snapshot_are_identical_and_read_back_by_the_zip_crate() {
    let (_d, snap) = setup(&[]);
    let (a, b) = (export(&snap), export(&snap));
    assert_eq!(a, b, "identical inputs give identical bytes");
    let (f, n) = (snap.frame_count(), 4);
    let z = read_with_zip_crate(&a);
    assert_eq!(z, parse_zip(&a), "both readers see the same entries");
    let shapes: Vec<(&str, Vec<usize>)> = z
        .iter()
        .filter(|(name, _)| name.as_str() != "provenance.npy")
        .map(|(name, data)| (name.as_str(), parse_npy(data).0))
        .collect();
    assert_eq!(
        shapes,
        [
            ("exponent.npy", vec![n - 1]),
            ("mass.npy", vec![n]),
            ("precompression.npy", vec![n - 1]),
            ("prefactor.npy", vec![n - 1]),
            ("t.npy", vec![f]),
            ("u.npy", vec![f, n]),
            ("v.npy", vec![f, n]),
        ]
    );
    let prov = &z["provenance.npy"];
    let hl = u16::from_le_bytes([prov[8], prov[9]]) as usize;
    assert_eq!((10 + hl) % 64, 0);
    assert!(std::str::from_utf8(&prov[10..10 + hl])
        .unwrap()
        .contains("'shape': ()"));
    // The size checked against 4 GiB before writing is the archive's, to the byte.
    let planned = npz_bytes_of(f as u64, n as u64, snap.selection())
        + npz::entry_bytes("provenance.npy", prov.len() as u64);
    assert_eq!(planned, a.len() as u64);
}

#[test]
fn output_selection_export_holds_beads_and_the_stored_field_only() {
    let (_d, snap) = setup(&["--beads", "1:3", "--fields", "v"]);
    let a = export(&snap);
    assert_eq!(a, export(&snap));
    let z = read_with_zip_crate(&a);
    let f = snap.frame_count();
    assert!(!z.contains_key("u.npy"));
    assert_eq!(parse_npy(&z["beads.npy"]), (vec![2], vec![1.0, 2.0]));
    assert_eq!(parse_npy(&z["v.npy"]).0, vec![f, 2]);
    assert_eq!(parse_npy(&z["mass.npy"]).0, vec![4]);
    let planned = npz_bytes_of(f as u64, 4, snap.selection())
        + npz::entry_bytes("provenance.npy", z["provenance.npy"].len() as u64);
    assert_eq!(planned, a.len() as u64);
}

#[test]
fn cli_export_to_the_same_path_twice_gives_identical_files() {
    let (d, _snap) = setup(&[]);
    let args = ["export", "s.snap", "--out", "w.npz"];
    ok(&bc(d.path(), &args));
    let first = std::fs::read(d.path().join("w.npz")).unwrap();
    ok(&bc(d.path(), &args));
    assert_eq!(first, std::fs::read(d.path().join("w.npz")).unwrap());
    // Standard output (not seekable) gets the same archive.
    let o = bc(
        d.path(),
        &["export", "s.snap", "--format", "npz", "--out", "-"],
    );
    ok(&o);
    let z = read_with_zip_crate(&o.stdout);
    assert_eq!(z.len(), 8);
    let mut files = read_with_zip_crate(&first);
    let mut piped = z;
    // Only the command line recorded in the provenance differs.
    files.remove("provenance.npy");
    piped.remove("provenance.npy");
    assert_eq!(files, piped);
}

#[test]
fn shared_writer_gives_identical_bytes_and_exact_shapes() {
    let x: Vec<f64> = (0..12).map(|i| i as f64 * 0.5).collect();
    let arrays: Vec<(&str, Vec<u64>, &[f64])> = vec![
        ("a", vec![12], &x),
        ("b", vec![3, 4], &x),
        ("c", vec![2, 3, 2], &x),
        ("empty", vec![0], &[]),
    ];
    let mut a = Vec::new();
    let mut b = Vec::new();
    write_npz_arrays(&arrays, &mut a).unwrap();
    write_npz_arrays(&arrays, &mut b).unwrap();
    assert_eq!(a, b);
    let z = read_with_zip_crate(&a);
    assert_eq!(parse_npy(&z["a.npy"]), (vec![12], x.clone()));
    assert_eq!(parse_npy(&z["b.npy"]), (vec![3, 4], x.clone()));
    assert_eq!(parse_npy(&z["c.npy"]), (vec![2, 3, 2], x.clone()));
    assert_eq!(parse_npy(&z["empty.npy"]), (vec![0], vec![]));
    let planned: u64 = z
        .iter()
        .map(|(name, data)| npz::entry_bytes(name, data.len() as u64))
        .sum::<u64>()
        + npz::END_BYTES;
    assert_eq!(planned, a.len() as u64);
}

#[test]
fn an_archive_beyond_4_gib_is_refused_before_anything_is_written() {
    // The shape alone makes it too large: the size check runs before the data is looked at.
    let arrays: Vec<(&str, Vec<u64>, &[f64])> = vec![("huge", vec![1 << 29], &[])];
    let mut out = Vec::new();
    let e = write_npz_arrays(&arrays, &mut out).unwrap_err();
    assert!(e.to_string().contains("beyond the 4 GiB"), "{e}");
    assert!(out.is_empty());
    assert!(npz_bytes_of(1 << 27, 4, &Default::default()) > npz::ZIP_LIMIT);
}
