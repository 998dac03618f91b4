//! Run-to-run determinism of the snapshot bytes written by `beadchain run` (both engines):
//! frames, header and event log identical; whole files identical without `--timing`.

mod common;

use common::{assert_ok, bc};

/// 4 beads struck at v = 1, frames at t = 0, 0.5, 1, 1.5, 2 (5 frames).
const TINY: &str =
    "[chain]\nbeads = 4\n[initial]\nstriker = 1.0\n[run]\nuntil = 2.0\nevery = 0.5\n";

/// Sections `(tag, payload)` of a snapshot (walking the section headers).
fn sections(b: &[u8]) -> Vec<(String, Vec<u8>)> {
    let mut out = Vec::new();
    let mut pos = 12;
    while pos + 16 <= b.len() {
        let tag = String::from_utf8_lossy(&b[pos..pos + 4]).to_string();
        let len = u64::from_le_bytes(b[pos + 4..pos + 12].try_into().unwrap()) as usize;
        out.push((tag, b[pos + 16..pos + 16 + len].to_vec()));
        pos += 16 + len;
    }
    out
}

/// Runs the tiny scene with `engine` in two fresh directories (same relative command line, so
/// the recorded command is identical) and returns both files.
fn twice(engine: &str) -> (Vec<u8>, Vec<u8>) {
    let mut files = Vec::new();
    for _ in 0..2 {
        let d = tempfile::tempdir().expect("tempdir");
        std::fs::write(d.path().join("s.toml"), TINY).expect("write");
        let o = bc(
            d.path(),
            &["run", "s.toml", "--engine", engine, "--out", "o.snap"],
        );
        assert_ok(&o);
        files.push(std::fs::read(d.path().join("o.snap")).unwrap());
    }
    let b = files.pop().unwrap();
    (files.pop().unwrap(), b)
}

/// Names the sections that differ between two snapshots.
fn differing_sections(a: &[u8], b: &[u8]) -> Vec<String> {
    let (sa, sb) = (sections(a), sections(b));
    let mut out = Vec::new();
    if sa.len() != sb.len() {
        out.push(format!("section count {} vs {}", sa.len(), sb.len()));
    }
    for (i, ((ta, pa), (_, pb))) in sa.iter().zip(&sb).enumerate() {
        if pa != pb {
            let first = pa.iter().zip(pb).position(|(x, y)| x != y);
            out.push(format!(
                "section {i} {ta:?}: payload {} vs {} bytes, first difference at payload byte {first:?}",
                pa.len(),
                pb.len()
            ));
        }
    }
    out
}

/// Frames, header and event log are byte-identical across runs of the same scene (both
/// engines); only the STATS section may differ.
#[test]
fn frames_header_and_events_are_deterministic() {
    for engine in ["hybrid", "dense"] {
        let (a, b) = twice(engine);
        let diff = differing_sections(&a, &b);
        assert!(
            diff.iter().all(|d| d.contains("\"STAT\"")),
            "{engine}: {diff:?}"
        );
        println!("{engine}: differing sections: {diff:?}");
    }
}

/// Whole files byte-identical (issue 4, "Determinism"): the wall-clock time is only stored
/// with `--timing`.
#[test]
fn same_scene_gives_identical_bytes() {
    for engine in ["hybrid", "dense"] {
        let (a, b) = twice(engine);
        assert!(
            a == b,
            "{engine}: files differ: {:?}",
            differing_sections(&a, &b)
        );
    }
}
