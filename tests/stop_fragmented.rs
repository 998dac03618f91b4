//! `run --stop-when-fragmented` (issue 33): the run ends at the first output frame at which no
//! pair can collide again, the snapshot is complete (its last frame is that time, `inspect`
//! reads it), and the fragments printed are those of that frame, computed here independently.
//! Scenes with walls or a field are refused with one line and no file.

mod common;

use beadchain::snapshot::Snapshot;
use common::{assert_ok, bc};
use std::path::Path;

/// `|a − b| ≤ abs + rel·|b|`.
fn close(a: f64, b: f64, abs: f64, rel: f64) -> bool {
    (a - b).abs() <= abs + rel * b.abs()
}

/// Runs `toml` with `--stop-when-fragmented`; stdout and the snapshot.
fn run_stop(dir: &Path, toml: &str) -> (String, Snapshot) {
    std::fs::write(dir.join("c.toml"), toml).unwrap();
    let o = bc(
        dir,
        &[
            "run",
            "c.toml",
            "--out",
            "c.snap",
            "-q",
            "--stop-when-fragmented",
        ],
    );
    assert_ok(&o);
    let snap = Snapshot::open(&dir.join("c.snap")).expect("a complete snapshot");
    (String::from_utf8(o.stdout).unwrap(), snap)
}

/// The test's own predicate: no overlap, `v_i ≤ v_{i+1}`; fragments split at every contact
/// that is not touching at equal velocity: `(first, last, mass, velocity)`.
fn fragments(m: &[f64], u: &[f64], v: &[f64], pre: f64) -> Option<Vec<(usize, usize, f64, f64)>> {
    let mut out = Vec::new();
    let mut first = 0;
    for i in 0..v.len() {
        let end = i + 1 == v.len() || {
            let delta = pre + u[i] - u[i + 1];
            if delta > 0.0 || v[i] > v[i + 1] {
                return None;
            }
            !(delta == 0.0 && v[i] == v[i + 1])
        };
        if end {
            let mass: f64 = m[first..=i].iter().sum();
            let p: f64 = (first..=i).map(|k| m[k] * v[k]).sum();
            out.push((first, i, mass, p / mass));
            first = i + 1;
        }
    }
    Some(out)
}

/// The printed fragment lines: (first, last, mass, velocity).
fn printed(out: &str) -> Vec<(usize, usize, f64, f64)> {
    out.lines()
        .filter_map(|l| l.trim().strip_prefix("beads "))
        .map(|l| {
            let (range, rest) = l.split_once(": mass ").unwrap();
            let (a, b) = range.split_once("..=").unwrap();
            let (mass, vel) = rest.split_once(", velocity ").unwrap();
            let vel = vel.split_whitespace().next().unwrap();
            (
                a.parse().unwrap(),
                b.parse().unwrap(),
                mass.parse().unwrap(),
                vel.parse().unwrap(),
            )
        })
        .collect()
}

/// Checks the stop against the snapshot: last frame = the stop time < until, fragmented there
/// and at no frame before, the printed fragments equal the test's (masses and velocities to
/// abs 1e-12, rel 1e-8: printed with 10 digits), the summary's end time and note, `inspect`.
fn check_stop(dir: &Path, out: &str, snap: &Snapshot, until: f64) -> Vec<(usize, usize, f64, f64)> {
    let chain = &snap.header().scene.chain;
    let pre = chain.precompression.as_ref().map_or(0.0, |d| d[0]);
    let k = snap.frame_count() - 1;
    let last = snap.frame(k).unwrap();
    assert!(last.t < until, "stopped early: {} < {until}", last.t);
    assert!(
        out.contains(&format!("fragmented at t = {} (until = {until})", last.t)),
        "{out}"
    );
    let want = fragments(&chain.mass, &last.u, &last.v, pre).expect("fragmented at the stop");
    for j in 0..k {
        let f = snap.frame(j).unwrap();
        assert!(
            fragments(&chain.mass, &f.u, &f.v, pre).is_none(),
            "frame {j} already fragmented"
        );
    }
    let got = printed(out);
    assert_eq!(got.len(), want.len(), "{out}");
    for (g, w) in got.iter().zip(&want) {
        assert_eq!((g.0, g.1), (w.0, w.1), "{out}");
        assert!(
            close(g.2, w.2, 1e-12, 1e-8) && close(g.3, w.3, 1e-12, 1e-8),
            "{g:?} vs {w:?}"
        );
    }
    let summary = snap.summary().expect("finished");
    assert_eq!(summary.t_end, last.t);
    assert!(
        summary
            .notes
            .iter()
            .any(|n| n.contains("--stop-when-fragmented")),
        "{:?}",
        summary.notes
    );
    let i = bc(dir, &["inspect", "c.snap"]);
    assert_ok(&i);
    assert!(String::from_utf8_lossy(&i.stdout).contains("stopped at t ="));
    want
}

#[test]
fn run_stops_when_a_two_bead_collision_is_over() {
    let d = tempfile::tempdir().unwrap();
    let toml = "[chain]\nbeads = 2\n[initial]\nstriker = 1.0\n[run]\nuntil = 100.0\nevery = 0.5\n";
    let (out, snap) = run_stop(d.path(), toml);
    let f = check_stop(d.path(), &out, &snap, 100.0);
    // Equal masses exchange velocities: 0 and 1 (abs 1e-6: the hybrid engine at rtol 1e-8).
    assert_eq!(f.len(), 2);
    assert!(
        close(f[0].3, 0.0, 1e-6, 0.0) && close(f[1].3, 1.0, 1e-6, 0.0),
        "{f:?}"
    );
    // The collision lasts about 1.7 time units; the stop is within a few frames of it.
    assert!(snap.frame_count() <= 10, "{} frames", snap.frame_count());
}

#[test]
fn run_stops_when_a_heavy_to_light_chain_flies_apart() {
    // Masses 1, 0.8, 0.64, ...: every bead leaves faster than the one behind it.
    let d = tempfile::tempdir().unwrap();
    let toml = "[chain]\nbeads = 10\nmass = { base = 1.0, taper = { q = 0.2 } }\n\
                [initial]\nstriker = 1.0\n[run]\nuntil = 1000.0\nevery = 1.0\n";
    let (out, snap) = run_stop(d.path(), toml);
    let f = check_stop(d.path(), &out, &snap, 1000.0);
    assert_eq!(f.len(), 10, "every bead on its own: {f:?}");
    assert!(f.windows(2).all(|w| w[0].3 <= w[1].3));
}

#[test]
fn touching_beads_at_equal_velocity_are_one_fragment() {
    // Bead 0 leaves to the left; beads 1 and 2 touch (overlap 0) at rest: fragmented at t = 0,
    // fragments {0} and {1, 2} (mass 3).
    let d = tempfile::tempdir().unwrap();
    let toml = "[chain]\nbeads = 3\nmass = [1.0, 1.0, 2.0]\nprecompression = [-0.5, 0.0]\n\
                [initial]\nvelocity = [-1.0, 0.0, 0.0]\n[run]\nuntil = 10.0\nevery = 1.0\n";
    let (out, snap) = run_stop(d.path(), toml);
    assert_eq!(snap.frame_count(), 1);
    assert_eq!(
        printed(&out),
        vec![(0, 0, 1.0, -1.0), (1, 2, 3.0, 0.0)],
        "{out}"
    );
    assert_ok(&bc(d.path(), &["inspect", "c.snap"]));
}

#[test]
fn a_run_that_never_fragments_writes_the_same_frames() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let o = bc(
        p,
        &[
            "run",
            "striker",
            "--until",
            "20",
            "--out",
            "a.snap",
            "-q",
            "--stop-when-fragmented",
        ],
    );
    assert_ok(&o);
    assert!(String::from_utf8_lossy(&o.stdout)
        .contains("stop when fragmented: not reached by t = 20: at the last frame "));
    assert_ok(&bc(
        p,
        &["run", "striker", "--until", "20", "--out", "b.snap", "-q"],
    ));
    for extra in [&[][..], &["--events"][..]] {
        let ex = |f: &str| {
            let mut a = vec!["export", f, "--out", "-"];
            a.extend_from_slice(extra);
            // the provenance comments name each file's own command line
            let text = String::from_utf8(bc(p, &a).stdout).unwrap();
            text.lines()
                .filter(|l| !l.starts_with('#'))
                .map(|l| format!("{l}\n"))
                .collect::<String>()
        };
        assert_eq!(ex("a.snap"), ex("b.snap"), "frames/events {extra:?}");
    }
}

#[test]
fn stop_when_fragmented_refuses_walls_and_fields() {
    let d = tempfile::tempdir().unwrap();
    for (scene, key) in [
        ("wall_reflection", "[walls]"),
        ("gravity_on_wall", "[walls]"),
        ("granular_gas", "[walls]"),
    ] {
        let o = bc(
            d.path(),
            &["run", scene, "--out", "x.snap", "--stop-when-fragmented"],
        );
        assert_eq!(o.status.code(), Some(2), "{scene}");
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(e.lines().count(), 1, "{e}");
        assert!(
            e.contains("--stop-when-fragmented") && e.contains(key),
            "{e}"
        );
        assert!(!d.path().join("x.snap").exists());
    }
    let field = "[chain]\nbeads = 3\n[field]\ngravity = 1.0\n[initial]\nstriker = 1.0\n[run]\nuntil = 5.0\n";
    std::fs::write(d.path().join("f.toml"), field).unwrap();
    let o = bc(
        d.path(),
        &["run", "f.toml", "--out", "x.snap", "--stop-when-fragmented"],
    );
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.contains("f.toml: --stop-when-fragmented: the scene has a field ([field])"),
        "{e}"
    );
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(std::fs::read_dir(d.path()).unwrap().all(|e| {
        let n = e.unwrap().file_name();
        n == "f.toml"
    }));
}
