//! Snapshot format 4 (issue 12): the HEADER is a named record, not the internal `Scene` through
//! bincode; frames carry the dissipated energy; physical scenes keep their unit scales in full.

mod common;

use beadchain::integrate::Method;
use beadchain::scene::{preset, presets, Engine};
use beadchain::snapshot::header4::{header_from_record, header_record};
use beadchain::snapshot::record::Value;
use beadchain::snapshot::{Header, RunSummary, Snapshot, SnapshotWriter};
use common::{assert_ok, bc};

fn header_of(name: &str) -> Header {
    let scene = preset(name).unwrap();
    Header::new(
        scene,
        Engine::Hybrid,
        Method::Auto,
        1e-8,
        1e-12,
        "test".into(),
    )
}

/// Every preset's resolved scene survives file → reader bit for bit (compared with `==` on the
/// whole struct: every float exactly).
#[test]
fn every_preset_scene_round_trips_through_a_format_4_file() {
    let d = tempfile::tempdir().unwrap();
    for p in presets() {
        let h = header_of(p.name);
        let path = d.path().join(format!("{}.snap", p.name));
        let w = SnapshotWriter::create(&path, &h).unwrap();
        w.finish(&[], &RunSummary::default()).unwrap();
        let s = Snapshot::open(&path).unwrap();
        assert_eq!(s.header().format_version, 4, "{}", p.name);
        assert_eq!(s.header().scene, h.scene, "{}", p.name);
        assert_eq!(s.header(), &h, "{}", p.name);
    }
}

/// Formats 1–3 kept the SI scales only in the description, with seven significant digits:
/// `--units si` and Python's SI arrays were off by up to 5e-7 relative. Format 4 stores them.
#[test]
fn si_time_unit_keeps_full_precision() {
    let d = tempfile::tempdir().unwrap();
    let h = header_of("hertz_spheres_physical");
    let exact = h.scene.units.expect("physical scene");
    let path = d.path().join("p.snap");
    let w = SnapshotWriter::create(&path, &h).unwrap();
    w.finish(&[], &RunSummary::default()).unwrap();
    let got = Snapshot::open(&path).unwrap().header().scene.units.unwrap();
    assert_eq!(
        got.time.to_bits(),
        exact.time.to_bits(),
        "{got:?} vs {exact:?}"
    );
    assert_eq!(got.mass.to_bits(), exact.mass.to_bits());
    // what the description holds is rounded (the old source of the scales)
    let text = &h.scene.description;
    assert!(text.contains("time unit "), "{text}");
}

/// A key this build does not know (a newer writer's physics) is refused, never ignored.
#[test]
fn unknown_header_key_is_refused() {
    let h = header_of("damped_striker");
    let mut rec = header_record(&h);
    assert_eq!(header_from_record(rec.clone()).unwrap(), {
        let mut h4 = h.clone();
        h4.format_version = 4;
        h4
    });
    rec.push(("chain.friction".into(), Value::Real(0.3)));
    let e = header_from_record(rec).unwrap_err().to_string();
    assert!(e.contains("unknown key `chain.friction`"), "{e}");
}

/// A missing or mistyped mandatory key names the key.
#[test]
fn missing_or_mistyped_header_keys_are_named() {
    let h = header_of("striker");
    let rec = header_record(&h);
    let without: Vec<_> = rec
        .iter()
        .filter(|(k, _)| k != "chain.prefactor")
        .cloned()
        .collect();
    let e = header_from_record(without).unwrap_err().to_string();
    assert_eq!(e, "key `chain.prefactor` is missing");
    let mut short = rec.clone();
    for (k, v) in short.iter_mut() {
        if k == "initial.v" {
            *v = Value::Reals(vec![1.0]);
        }
    }
    let e = header_from_record(short).unwrap_err().to_string();
    assert!(
        e.starts_with("key `initial.v` holds 1 values, expected "),
        "{e}"
    );
    let mut typed = rec;
    for (k, v) in typed.iter_mut() {
        if k == "rtol" {
            *v = Value::Text("tight".into());
        }
    }
    let e = header_from_record(typed).unwrap_err().to_string();
    assert_eq!(e, "key `rtol` holds a text, expected a real");
}

/// Frames of a dissipative run carry `E_d(t)`: non-decreasing, and `E + E_d` equals the initial
/// energy to the run's tolerance at every frame; conservative runs store 0.
#[test]
fn frames_carry_the_dissipated_energy() {
    let d = tempfile::tempdir().unwrap();
    let o = bc(
        d.path(),
        &[
            "run",
            "damped_striker",
            "--every",
            "5",
            "-q",
            "--out",
            "d.snap",
        ],
    );
    assert_ok(&o);
    let s = Snapshot::open(&d.path().join("d.snap")).unwrap();
    let chain = &s.header().scene.chain;
    let f0 = s.frame(0).unwrap();
    let e0 = chain.energy(&f0.u, &f0.v);
    assert_eq!(f0.dissipated, Some(0.0));
    let mut prev = 0.0;
    for k in 0..s.frame_count() {
        let f = s.frame(k).unwrap();
        let ed = f.dissipated.expect("format 4 stores it");
        assert!(ed >= prev - 1e-12, "frame {k}: {ed} < {prev} (atol 1e-12)");
        prev = ed;
        let bal = (chain.energy(&f.u, &f.v) + ed - e0).abs();
        // abs 1e-6 + rel 1e-6 of E0 (default rtol 1e-8 with a growing global error)
        assert!(bal <= 1e-6 + 1e-6 * e0, "frame {k}: balance error {bal}");
    }
    assert!(
        prev > 0.05 * e0,
        "the pulse must lose energy: E_d = {prev}, E0 = {e0}"
    );

    let o = bc(
        d.path(),
        &[
            "run", "striker", "--until", "20", "--every", "5", "-q", "--out", "c.snap",
        ],
    );
    assert_ok(&o);
    let s = Snapshot::open(&d.path().join("c.snap")).unwrap();
    for k in 0..s.frame_count() {
        assert_eq!(s.frame(k).unwrap().dissipated, Some(0.0), "frame {k}");
    }
    let o = bc(d.path(), &["inspect", "d.snap"]);
    assert_ok(&o);
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.contains("dissipated:  "), "{text}");
}
