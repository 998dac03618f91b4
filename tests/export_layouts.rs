//! `beadchain export` layouts (issue 14): the format follows the `--out` extension when
//! `--format` is absent, and `--layout wide` writes one row per frame — `.npz` (zip of `.npy`:
//! `t`, `u`, `v` and the chain arrays), `.npy` `(F, 2N+1)`, `.csv` `t,u0..,v0..`. Every file is
//! read back here (zip central directory, NPY header and data parsed in Rust) and compared bit
//! for bit with the snapshot; with python3 + numpy available, `numpy.load` reads the `.npz` too.

mod common;

use common::bc;
use common::npy::{parse_npy, parse_zip};

use beadchain::snapshot::Snapshot;
use std::path::Path;
use std::process::{Command, Output};

fn ok(o: &Output) {
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// 4 beads, precompressed chain (so the chain arrays are not trivial), 5 frames.
const SCENE: &str = "[chain]\nbeads = 4\nmass = [1.0, 2.0, 1.5, 1.0]\nprecompression = 0.01\n[initial]\nstriker = 1.0\n[run]\nuntil = 2.0\nevery = 0.5\n";

fn setup() -> (tempfile::TempDir, Snapshot) {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("s.toml"), SCENE).unwrap();
    ok(&bc(d.path(), &["run", "s.toml", "--out", "s.snap", "-q"]));
    let snap = Snapshot::open(&d.path().join("s.snap")).unwrap();
    (d, snap)
}

#[test]
fn export_wide_npz_holds_t_u_v_and_the_chain_arrays() {
    let (d, snap) = setup();
    // Format from the extension: no --format, no --layout.
    ok(&bc(d.path(), &["export", "s.snap", "--out", "w.npz"]));
    let z = parse_zip(&std::fs::read(d.path().join("w.npz")).unwrap());
    let names: Vec<&str> = z.keys().map(String::as_str).collect();
    assert_eq!(
        names,
        [
            "exponent.npy",
            "mass.npy",
            "precompression.npy",
            "prefactor.npy",
            "provenance.npy",
            "t.npy",
            "u.npy",
            "v.npy"
        ]
    );
    let (f, n) = (snap.frame_count(), 4);
    assert_eq!(f, 5);
    let (ts, t) = parse_npy(&z["t.npy"]);
    let (us, u) = parse_npy(&z["u.npy"]);
    let (vs, v) = parse_npy(&z["v.npy"]);
    assert_eq!((ts, us, vs), (vec![f], vec![f, n], vec![f, n]));
    for k in 0..f {
        let fr = snap.frame(k).unwrap();
        assert_eq!(t[k].to_bits(), fr.t.to_bits(), "t of frame {k}");
        assert_eq!(&u[k * n..(k + 1) * n], fr.u.as_slice(), "u of frame {k}");
        assert_eq!(&v[k * n..(k + 1) * n], fr.v.as_slice(), "v of frame {k}");
    }
    let chain = &snap.header().scene.chain;
    assert_eq!(parse_npy(&z["mass.npy"]), (vec![n], chain.mass.clone()));
    assert_eq!(
        parse_npy(&z["exponent.npy"]),
        (vec![n - 1], chain.exponent.clone())
    );
    assert_eq!(
        parse_npy(&z["prefactor.npy"]),
        (vec![n - 1], chain.prefactor.clone())
    );
    assert_eq!(
        parse_npy(&z["precompression.npy"]),
        (vec![n - 1], vec![0.01; n - 1])
    );
    // Without precompression the array is zeros.
    ok(&bc(
        d.path(),
        &["run", "striker", "--until", "1", "--out", "p.snap", "-q"],
    ));
    ok(&bc(
        d.path(),
        &["export", "p.snap", "--out", "p.npz", "--frame", "last"],
    ));
    let z = parse_zip(&std::fs::read(d.path().join("p.npz")).unwrap());
    assert_eq!(
        parse_npy(&z["precompression.npy"]),
        (vec![99], vec![0.0; 99])
    );
    assert_eq!(parse_npy(&z["u.npy"]).0, vec![1, 100]);
    python_check(&d.path().join("w.npz"), &snap);
}

/// `numpy.load` of the archive, when python3 with numpy is installed (skipped otherwise).
fn python_check(npz: &Path, snap: &Snapshot) {
    let probe = Command::new("python3")
        .args(["-c", "import numpy"])
        .output();
    if !probe.is_ok_and(|o| o.status.success()) {
        eprintln!("python3 with numpy not available: numpy.load check skipped");
        return;
    }
    let last = snap.frame(snap.frame_count() - 1).unwrap();
    let script = format!(
        "import numpy as np\nz = np.load({:?})\nassert z['u'].shape == (5, 4) and z['t'].shape == (5,)\nassert z['u'][-1].tolist() == {:?}\nassert z['mass'].tolist() == [1.0, 2.0, 1.5, 1.0]\n",
        npz.display().to_string(),
        last.u
    );
    let o = Command::new("python3")
        .args(["-c", &script])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn export_wide_npy_and_csv_have_one_row_per_frame() {
    let (d, snap) = setup();
    let n = 4;
    ok(&bc(
        d.path(),
        &["export", "s.snap", "--out", "w.npy", "--layout", "wide"],
    ));
    let (shape, a) = parse_npy(&std::fs::read(d.path().join("w.npy")).unwrap());
    assert_eq!(shape, vec![5, 2 * n + 1]);
    for k in 0..5 {
        let fr = snap.frame(k).unwrap();
        let row = &a[k * (2 * n + 1)..(k + 1) * (2 * n + 1)];
        assert_eq!(row[0].to_bits(), fr.t.to_bits());
        assert_eq!(&row[1..=n], fr.u.as_slice());
        assert_eq!(&row[n + 1..], fr.v.as_slice());
    }
    ok(&bc(
        d.path(),
        &["export", "s.snap", "--out", "w.csv", "--layout", "wide"],
    ));
    let text = std::fs::read_to_string(d.path().join("w.csv")).unwrap();
    let lines: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert_eq!(lines[0], "t,u0,u1,u2,u3,v0,v1,v2,v3");
    assert_eq!(lines.len(), 6);
    let fr = snap.frame(4).unwrap();
    let last: Vec<f64> = lines[5].split(',').map(|x| x.parse().unwrap()).collect();
    assert_eq!(last[0], fr.t);
    assert_eq!(
        &last[1..=n],
        fr.u.as_slice(),
        "CSV values round-trip exactly"
    );
    assert_eq!(&last[n + 1..], fr.v.as_slice());
}

#[test]
fn export_format_follows_the_out_extension() {
    let (d, snap) = setup();
    // Long layout stays the default: .npy from the extension is the (rows, 5) table.
    ok(&bc(d.path(), &["export", "s.snap", "--out", "l.npy"]));
    let (shape, a) = parse_npy(&std::fs::read(d.path().join("l.npy")).unwrap());
    assert_eq!(shape, vec![5 * 4, 5]);
    let fr = snap.frame(2).unwrap();
    let row = &a[(2 * 4 + 3) * 5..(2 * 4 + 4) * 5];
    assert_eq!(row, [2.0, fr.t, 3.0, fr.u[3], fr.v[3]]);
    ok(&bc(d.path(), &["export", "s.snap", "--out", "l.csv"]));
    let text = std::fs::read_to_string(d.path().join("l.csv")).unwrap();
    assert!(text.starts_with("# beadchain "), "{text}");
    assert!(text.contains("\nframe,t,bead,u,v\n"), "{text}");
    // --format wins over the extension.
    ok(&bc(
        d.path(),
        &["export", "s.snap", "--out", "x.npy", "--format", "csv"],
    ));
    let text = std::fs::read_to_string(d.path().join("x.npy")).unwrap();
    assert!(text.contains("\nframe,t,bead,u,v\n"), "{text}");
}

#[test]
fn export_npz_with_long_layout_is_refused_without_output() {
    let (d, _) = setup();
    let o = bc(
        d.path(),
        &["export", "s.snap", "--out", "x.npz", "--layout", "long"],
    );
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(
        e.starts_with("beadchain: error: --layout long: the npz format holds the wide layout only"),
        "{e}"
    );
    assert!(!d.path().join("x.npz").exists());
    let o = bc(d.path(), &["export", "s.snap", "--format", "npz"]);
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.starts_with("beadchain: error: --format npz needs --out PATH"),
        "{e}"
    );
    println!(
        "npz with long layout | `beadchain export s.snap --out x.npz --layout long` | {}",
        e.trim_end()
    );
}
