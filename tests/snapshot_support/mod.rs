//! Shared fixtures of the snapshot tests (`snapshots.rs`, `snapshot_damage.rs`,
//! `snapshot_exports.rs`): a small scene, header, frames, events and run summary, a writer
//! helper and the section walker.
#![allow(dead_code)]

use beadchain::integrate::{Method, Stats};
use beadchain::model::Chain;
use beadchain::scene::{Engine, RunSettings, Scene};
use beadchain::snapshot::{
    EventKind, EventRecord, Frame, Header, RunSummary, SnapshotWriter, PREAMBLE_LEN,
};
use std::path::{Path, PathBuf};

pub fn scene(n: usize) -> Scene {
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
        units: None,
    }
}

pub fn header(n: usize) -> Header {
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
pub fn frames(n: usize, count: usize) -> Vec<Frame> {
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
            Frame {
                t,
                u,
                v,
                dissipated: Some(0.0),
            }
        })
        .collect()
}

pub fn events() -> Vec<EventRecord> {
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

pub fn summary() -> RunSummary {
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

pub fn write(path: &Path, h: &Header, fr: &[Frame]) {
    let mut w = SnapshotWriter::create(path, h).expect("create");
    for f in fr {
        w.write_frame(f.t, &f.u, &f.v).expect("write_frame");
    }
    w.finish(&events(), &summary()).expect("finish");
}

pub fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

pub fn assert_frame_eq(a: &Frame, b: &Frame) {
    assert_eq!(a.t.to_bits(), b.t.to_bits(), "t differs");
    assert!(same_bits(&a.u, &b.u), "u differs");
    assert!(same_bits(&a.v, &b.v), "v differs");
}

/// A finished 4-bead, 5-frame file in a fresh temporary directory.
pub fn sample() -> (tempfile::TempDir, PathBuf, Vec<Frame>) {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = dir.path().join("run.snap");
    let fr = frames(4, 5);
    write(&p, &header(4), &fr);
    (dir, p, fr)
}

/// Byte offsets of the sections of a file (walking the section headers).
pub fn sections(bytes: &[u8]) -> Vec<(u64, [u8; 4], u64)> {
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
