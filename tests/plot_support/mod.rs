//! Shared helpers of the plot axis tests (`plot_axes.rs`, `plot_energy.rs`): snapshots written
//! from frames, the `<text>` labels of an SVG, running the binary, small test chains.
#![allow(dead_code)]

use super::common;
use beadchain::plot::font;
use beadchain::scene::{Engine, Scene};
use beadchain::snapshot::{Header, SnapshotWriter};
use std::path::{Path, PathBuf};

/// Writes `scene` with the given frames `(t, v)` (all displacements 0) to `dir/name`.
pub fn write_snap(dir: &Path, name: &str, scene: &Scene, frames: &[(f64, Vec<f64>)]) -> PathBuf {
    let path = dir.join(name);
    let h = Header::new(
        scene.clone(),
        Engine::Hybrid,
        beadchain::integrate::Method::Radau5,
        1e-8,
        1e-10,
        "tests/plot_axes.rs".into(),
    );
    let mut w = SnapshotWriter::create(&path, &h).expect("create snapshot");
    let u = vec![0.0; scene.chain.mass.len()];
    for (t, v) in frames {
        w.write_frame(*t, &u, v).expect("frame");
    }
    w.finish(&[], &Default::default()).expect("finish");
    path
}

/// The text of every `<text>` element of an SVG file, or `None` (with a note) without a font.
pub fn texts(svg: &Path) -> Option<Vec<String>> {
    if !font::font_available() {
        eprintln!("note: no font file: the SVG text assertions are skipped");
        return None;
    }
    let s = std::fs::read_to_string(svg).expect("svg written");
    let mut out = Vec::new();
    let mut rest = s.as_str();
    while let Some(a) = rest.find("<text") {
        let body = &rest[a..];
        let open = body.find('>').expect("tag end") + 1;
        let close = body.find("</text>").expect("closing tag");
        let t = body[open..close].trim().replace("&amp;", "&");
        out.push(t);
        rest = &body[close..];
    }
    Some(out)
}

/// The labels that are numbers.
pub fn numbers(labels: &[String]) -> Vec<f64> {
    labels
        .iter()
        .filter_map(|l| l.parse::<f64>().ok())
        .collect()
}

/// Runs the binary and asserts success.
pub fn ok(dir: &Path, args: &[&str]) {
    common::assert_ok(&common::bc(dir, args));
}

/// Runs the binary, expects exit 2 with one line naming `needle`, and no file written.
pub fn fails(dir: &Path, args: &[&str], needle: &str) {
    let before = std::fs::read_dir(dir).unwrap().count();
    let o = common::bc(dir, args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
    assert!(err.starts_with("beadchain: error: "), "{err}");
    assert!(err.contains(needle), "{args:?}: {err}");
    assert_eq!(std::fs::read_dir(dir).unwrap().count(), before, "{args:?}");
}

/// A 60-bead unit-mass chain (dimensionless).
pub fn chain60() -> Scene {
    let mut sc = common::striker(60, 2.5, 1.0, 1.0, 60.0);
    sc.name = "axes_test".into();
    sc
}

/// Frames of a single-bead pulse at bead `k` (frame `k`, t = k) whose energy `½ v²` (unit
/// mass) is `exp(−γ₁ k)` before bead `kk` and `exp(−γ₁ kk − γ₂ (k − kk))` from it on.
pub fn decaying_pulse(n: usize, kk: usize, g1: f64, g2: f64) -> Vec<(f64, Vec<f64>)> {
    (0..n)
        .map(|k| {
            let e = if k < kk {
                (-g1 * k as f64).exp()
            } else {
                (-g1 * kk as f64 - g2 * (k - kk) as f64).exp()
            };
            let mut v = vec![0.0; n];
            v[k] = (2.0 * e).sqrt();
            (k as f64, v)
        })
        .collect()
}
