//! Fuzzing without nightly: proptest-driven mutation of scene files and snapshot files.
//!
//! - `fuzz_scene_parser`: every preset's TOML and a few hand-written scenes (with CSV files),
//!   mutated by byte flips, truncation, insertions/deletions, numbers replaced by `nan`, `inf`,
//!   `1e400`, huge integers, wrong types, random keys/tables and whole lines. Property: parsing
//!   (`scene::parse_str`, and `scene::load` of the raw bytes written to a file) never panics;
//!   an error is one line naming the origin file; a parsed scene passes `scene::validate`, its
//!   warnings are one line each, and its arrays are consistent and finite.
//! - `fuzz_snapshot_reader`: small valid snapshots (one with an inconsistent header), mutated by
//!   bit flips, byte writes, truncation, insert/delete, length-field corruption, section swaps,
//!   duplication and deletion, and payload edits with a recomputed CRC ("forged"). Property:
//!   `Snapshot::open`, `frame(k)` for every k, `export_csv`, `export_npy` and `inspect` never
//!   panic; no single allocation exceeds 8 MiB; unless the mutation forged a checksum, every
//!   frame read successfully holds the original numbers at its original index, and the header,
//!   event log and summary are the original ones when present.
//!
//! Budget and seed: see `tests/fuzz_support/mod.rs` (`BEADCHAIN_FUZZ_CASES`, default 200 per
//! target; `large` = time-boxed; `BEADCHAIN_FUZZ_SEED`). Long run:
//! `BEADCHAIN_FUZZ_CASES=large cargo test --release --test fuzz_inputs -- --nocapture`.

mod fuzz_support;

use beadchain::export::{export_csv, export_npy, inspect, FrameSel};
use beadchain::integrate::{Method, Stats};
use beadchain::model::{Chain, Wall};
use beadchain::scene::{self, Engine, RunSettings, Scene};
use beadchain::snapshot::{
    EventKind, EventRecord, Frame, Header, RunSummary, Snapshot, SnapshotWriter, PREAMBLE_LEN,
};
use fuzz_support::{fuzz, largest_alloc, reset_largest_alloc, CountingAlloc};
use proptest::prelude::*;
use proptest::sample::Index;
use proptest::test_runner::TestCaseError;
use std::path::Path;

#[global_allocator]
static ALLOC: CountingAlloc = CountingAlloc;

// ---------------------------------------------------------------------------------------------
// Scene parser
// ---------------------------------------------------------------------------------------------

/// Hand-written small scenes covering every table, value form and builder.
const SMALL_SCENES: &[&str] = &[
    "[chain]\nbeads = 3\n[initial]\nstriker = 1.0\n[run]\nuntil = 1.0\n",
    r#"[scene]
name = "small"
seed = 3
[chain]
mass = [1.0, 2.0, 1.0]
exponent = [2.5, 3.0]
prefactor = { base = 1.0, impurity = { at = 1, s = 1, value = 0.5 } }
precompression = [0.0, 0.1]
radius = { base = 1.0, taper = { q = 0.1, from = 1 } }
[initial]
displacement = 0.0
velocity = [0.0, 0.0, -0.5]
pulse = { beads = 2, velocity = 1.0 }
[field]
force = [0.0, 0.0, -1.0]
[walls]
left = { exponent = 2.5, prefactor = 1.0, precompression = 0.0 }
right = { exponent = 2.5 }
[run]
until = 2.0
every = 0.5
rtol = 1e-6
atol = 1e-9
method = "dop853"
engine = "hybrid"
"#,
    r#"[chain]
mass = { file = "m.csv" }
exponent = { random = { mean = 2.5, eps = 0.1 }, start = 1, gaussian = { sigma = 0.01, min = 1.5 } }
prefactor = { alternate = [1.0, 2.0], segments = [{ from = 1, to = 1, value = 0.5 }] }
[initial]
striker_right = 1.0
[run]
until = 1
"#,
    r#"[units]
system = "physical"
radius = [4.0e-3, 4.0e-3, 3.0e-3, 4.0e-3]
young = 2.26e11
poisson = 0.3
density = { file = "rho.csv" }
mu = 1e9
wall_young = 2.0e11
[chain]
exponent = { base = 3.0, segments = [{ from = 2, value = 2.5 }] }
[walls]
right = { prefactor_si = 1e9 }
[field]
gravity_si = 9.81
[initial]
striker_si = 0.11
[run]
until_si = 1e-4
every_si = 2e-5
"#,
];

/// Replacements for a number (or any value).
const VALUES: &[&str] = &[
    "nan",
    "-nan",
    "inf",
    "-inf",
    "+inf",
    "-1",
    "0",
    "-0.0",
    "1e400",
    "-1e400",
    "1e-400",
    "5e-324",
    "99999999999999999999",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551616",
    "10000001",
    "10000000",
    "2",
    "1",
    "1.0000000000000002",
    "0x10",
    "1_000",
    "\"2.5\"",
    "true",
    "[]",
    "[1.0]",
    "[nan, inf]",
    "[1, \"a\"]",
    "{}",
    "{ file = \"m.csv\" }",
    "{ file = \"bad.csv\" }",
    "{ file = \"missing.csv\" }",
    "{ file = \"\" }",
    "{ base = 1.0, taper = { q = 1.5, from = 0 } }",
    "{ alternate = [] }",
    "{ random = { mean = 2.5, eps = 10 } }",
    "{ gaussian = { sigma = 1e300, min = 1e300 } }",
    "{ segments = [{ from = 5, to = 2, value = 1 }] }",
    "{ impurity = { at = 99999999999, s = 5, value = 1 } }",
    "{ impurity = [{ at = 0, s = 9223372036854775807, value = 1 }] }",
    "1979-05-27",
    "'x'",
    "{ base = [1.0, 2.0], start = -3 }",
    "{ taper = { q = 0.5, from = 18446744073709551615 } }",
];

/// Lines inserted anywhere (tables, keys, bad values).
const LINES: &[&str] = &[
    "[bogus]",
    "foo = 1",
    "[chain]",
    "beads = 3",
    "beads = 1",
    "beads = 0",
    "beads = -5",
    "beads = 10000001",
    "beads = 2.5",
    "[walls]",
    "left = {}",
    "right = { exponent = 0.5 }",
    "[walls.left]",
    "exponent = 1e400",
    "[field]",
    "gravity = nan",
    "force = [1, 2]",
    "[units]",
    "system = \"physical\"",
    "system = \"martian\"",
    "time_scale = \"si\"",
    "[initial]",
    "pulse = { beads = 99999, velocity = 1 }",
    "pulse = { beads = 0 }",
    "striker = inf",
    "striker_si = 0.11",
    "[run]",
    "until = 0",
    "until = -1",
    "every = 0",
    "rtol = 1",
    "atol = 0",
    "method = \"euler\"",
    "engine = \"warp\"",
    "until_si = 1e-3",
    "[[chain]]",
    "mass = { file = \"m.csv\" }",
    "exponent = { file = \"../../../../etc/hostname\" }",
    "seed = -1",
    "seed = 9223372036854775807",
    "[scene]",
    "name = \"a\\nb\\u0000\"",
    "description = \"\"\"multi\nline\"\"\"",
    "a.b.c = 1",
    "\"[chain]\" = 2",
    "[chain.mass]",
];

#[derive(Clone, Debug)]
enum TextMut {
    FlipBit(Index, u8),
    Truncate(Index),
    Insert(Index, String),
    Delete(Index, usize),
    ReplaceNumber(Index, Index),
    ReplaceValue(Index, Index),
    InsertLine(Index, Index),
    DuplicateLine(Index),
    SwapLines(Index, Index),
}

fn text_mut() -> impl Strategy<Value = TextMut> {
    prop_oneof![
        (any::<Index>(), 0u8..8).prop_map(|(i, b)| TextMut::FlipBit(i, b)),
        any::<Index>().prop_map(TextMut::Truncate),
        (any::<Index>(), "[ -~\n\t]{1,8}|[\\[\\]{}=\",.#'\n]{1,3}")
            .prop_map(|(i, s)| TextMut::Insert(i, s)),
        (any::<Index>(), 1usize..24).prop_map(|(i, n)| TextMut::Delete(i, n)),
        (any::<Index>(), any::<Index>()).prop_map(|(i, v)| TextMut::ReplaceNumber(i, v)),
        (any::<Index>(), any::<Index>()).prop_map(|(i, v)| TextMut::ReplaceValue(i, v)),
        (any::<Index>(), any::<Index>()).prop_map(|(i, v)| TextMut::InsertLine(i, v)),
        any::<Index>().prop_map(TextMut::DuplicateLine),
        (any::<Index>(), any::<Index>()).prop_map(|(i, j)| TextMut::SwapLines(i, j)),
    ]
}

/// Byte ranges of numeric tokens (runs of `0-9.eE+-_` holding a digit).
fn numbers(t: &[u8]) -> Vec<(usize, usize)> {
    let is_num = |c: u8| c.is_ascii_digit() || b".eE+-_".contains(&c);
    let mut out = Vec::new();
    let mut i = 0;
    while i < t.len() {
        if is_num(t[i]) {
            let s = i;
            while i < t.len() && is_num(t[i]) {
                i += 1;
            }
            if t[s..i].iter().any(u8::is_ascii_digit) {
                out.push((s, i));
            }
        } else {
            i += 1;
        }
    }
    out
}

/// Byte ranges of lines (without the newline).
fn lines(t: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut s = 0;
    for (i, &c) in t.iter().enumerate() {
        if c == b'\n' {
            out.push((s, i));
            s = i + 1;
        }
    }
    out.push((s, t.len()));
    out
}

fn apply_text(t: &mut Vec<u8>, m: &TextMut) {
    let pos = |i: &Index, t: &Vec<u8>| i.index(t.len() + 1);
    match m {
        TextMut::FlipBit(i, b) if !t.is_empty() => {
            let p = i.index(t.len());
            t[p] ^= 1 << b;
        }
        TextMut::FlipBit(..) => {}
        TextMut::Truncate(i) => t.truncate(pos(i, t)),
        TextMut::Insert(i, s) => {
            let p = pos(i, t);
            t.splice(p..p, s.bytes());
        }
        TextMut::Delete(i, n) => {
            let p = pos(i, t);
            let e = (p + n).min(t.len());
            t.drain(p..e);
        }
        TextMut::ReplaceNumber(i, v) => {
            let nums = numbers(t);
            if !nums.is_empty() {
                let (s, e) = nums[i.index(nums.len())];
                t.splice(s..e, v.get(VALUES).bytes());
            }
        }
        TextMut::ReplaceValue(i, v) => {
            let ls: Vec<_> = lines(t)
                .into_iter()
                .filter(|&(s, e)| t[s..e].contains(&b'='))
                .collect();
            if !ls.is_empty() {
                let (s, e) = ls[i.index(ls.len())];
                let eq = s + t[s..e].iter().position(|&c| c == b'=').unwrap_or(0) + 1;
                t.splice(eq..e, format!(" {}", v.get(VALUES)).bytes());
            }
        }
        TextMut::InsertLine(i, v) => {
            let ls = lines(t);
            let (s, _) = ls[i.index(ls.len())];
            t.splice(s..s, format!("{}\n", v.get(LINES)).bytes());
        }
        TextMut::DuplicateLine(i) => {
            let ls = lines(t);
            let (s, e) = ls[i.index(ls.len())];
            let mut line = t[s..e].to_vec();
            line.push(b'\n');
            t.splice(s..s, line);
        }
        TextMut::SwapLines(i, j) => {
            let ls = lines(t);
            let (a, b) = (ls[i.index(ls.len())], ls[j.index(ls.len())]);
            let (a, b) = if a.0 <= b.0 { (a, b) } else { (b, a) };
            if a.1 < b.0 {
                let first = t[a.0..a.1].to_vec();
                let second = t[b.0..b.1].to_vec();
                t.splice(b.0..b.1, first);
                t.splice(a.0..a.1, second);
            }
        }
    }
}

/// Every seed text: each preset's TOML, then the hand-written scenes.
fn scene_corpus() -> Vec<String> {
    scene::presets()
        .iter()
        .map(|p| p.toml.to_string())
        .chain(SMALL_SCENES.iter().map(|s| s.to_string()))
        .collect()
}

/// A directory with the CSV files the hand-written scenes (and `VALUES`) refer to.
fn scene_dir() -> tempfile::TempDir {
    let d = tempfile::tempdir().expect("tempdir");
    let w = |name: &str, text: &str| std::fs::write(d.path().join(name), text).expect("write");
    w("m.csv", "# masses\n1.0\n\n2.0\n1.5\n");
    w("rho.csv", "7650\n7650\n2700\n7650\n");
    w("bad.csv", "1.0\nabc\n");
    d
}

/// The scene properties: one-line errors naming `origin`; a parsed scene validates and is
/// consistent.
fn check_scene_result(
    r: Result<Scene, scene::SceneError>,
    origin: &str,
) -> Result<(), TestCaseError> {
    match r {
        Err(e) => {
            let msg = e.to_string();
            prop_assert!(
                !msg.contains('\n') && !msg.contains('\r'),
                "multi-line: {msg:?}"
            );
            prop_assert!(msg.contains(origin), "error does not name {origin}: {msg}");
        }
        Ok(s) => {
            let warnings = scene::validate(&s);
            prop_assert!(
                warnings.is_ok(),
                "parsed scene fails validate: {warnings:?}"
            );
            for w in warnings.unwrap_or_default() {
                prop_assert!(
                    !w.contains('\n') && !w.contains('\r'),
                    "multi-line warning {w:?}"
                );
            }
            let n = s.chain.len();
            prop_assert!(n >= 2);
            prop_assert_eq!(s.chain.exponent.len(), n - 1);
            prop_assert_eq!(s.chain.prefactor.len(), n - 1);
            prop_assert!(s.u0.len() == n && s.v0.len() == n);
            let finite = s
                .chain
                .mass
                .iter()
                .chain(&s.chain.exponent)
                .chain(&s.chain.prefactor)
                .chain(&s.u0)
                .chain(&s.v0)
                .all(|x| x.is_finite());
            prop_assert!(finite, "non-finite value in a parsed scene");
            prop_assert!(
                s.run.until > 0.0 && s.run.until.is_finite(),
                "until {}",
                s.run.until
            );
        }
    }
    Ok(())
}

#[test]
fn scene_corpus_parses() {
    let d = scene_dir();
    for (k, text) in scene_corpus().iter().enumerate() {
        let r = scene::parse_str(text, d.path(), "seed.toml");
        assert!(r.is_ok(), "seed scene {k} does not parse: {r:?}");
    }
}

#[test]
fn fuzz_scene_parser() {
    let corpus = scene_corpus();
    let d = scene_dir();
    let file = d.path().join("case.toml");
    let file_str = file.to_string_lossy().to_string();
    let strategy = (any::<Index>(), prop::collection::vec(text_mut(), 1..6));
    let cases = fuzz("scene_parser", strategy, |(src, muts)| {
        let mut bytes = src.get(&corpus).as_bytes().to_vec();
        for m in &muts {
            apply_text(&mut bytes, m);
        }
        let text = String::from_utf8_lossy(&bytes);
        check_scene_result(
            scene::parse_str(&text, d.path(), "fuzz_scene.toml"),
            "fuzz_scene.toml",
        )?;
        std::fs::write(&file, &bytes).map_err(|e| TestCaseError::fail(e.to_string()))?;
        check_scene_result(scene::load(&file_str), &file_str)
    });
    assert!(cases > 0);
}

// ---------------------------------------------------------------------------------------------
// Snapshot reader
// ---------------------------------------------------------------------------------------------

const N_BEADS: usize = 3;
const N_FRAMES: usize = 4;
/// Largest single allocation the reader may make on a (small) mutated file.
const ALLOC_LIMIT: usize = 8 << 20;

fn snap_scene() -> Scene {
    Scene {
        name: "fuzz".into(),
        description: "fuzzed snapshot".into(),
        chain: Chain {
            mass: vec![1.0, 2.0, 1.0],
            exponent: vec![2.5, 3.0],
            prefactor: vec![1.0, 0.5],
            precompression: Some(vec![0.0, 0.1]),
            field: None,
            left_wall: Some(Wall {
                exponent: 2.5,
                prefactor: 1.0,
                precompression: 0.0,
            }),
            right_wall: None,
        },
        u0: vec![0.0; N_BEADS],
        v0: vec![1.0, 0.0, 0.0],
        run: RunSettings {
            until: 3.0,
            every: Some(1.0),
            ..Default::default()
        },
        seed: 9,
    }
}

fn snap_frames() -> Vec<Frame> {
    (0..N_FRAMES)
        .map(|k| Frame {
            t: k as f64,
            u: (0..N_BEADS).map(|i| 1e-7 * (i + 10 * k) as f64).collect(),
            v: (0..N_BEADS)
                .map(|i| -0.25 * (i * k) as f64 - 1e-9)
                .collect(),
        })
        .collect()
}

fn snap_events() -> Vec<EventRecord> {
    vec![
        EventRecord {
            t: 0.5,
            contact: 0,
            kind: EventKind::Close,
            rel_velocity: 1.0,
            peak_overlap: 0.0,
        },
        EventRecord {
            t: 1.5,
            contact: 1,
            kind: EventKind::Open,
            rel_velocity: -0.5,
            peak_overlap: 2e-3,
        },
    ]
}

fn snap_summary() -> RunSummary {
    RunSummary {
        stats: Stats {
            steps: 10,
            rhs_evals: 70,
            ..Default::default()
        },
        t_end: 3.0,
        energy_initial: 0.5,
        energy_final: 0.5,
        events_by_kind: vec![("close".into(), 1), ("open".into(), 1)],
        largest_cluster: 2,
        notes: vec!["note".into()],
        ..Default::default()
    }
}

/// Base files: 0 = consistent header; 1 = a header whose chain has no beads (`n_beads = 3`
/// but `mass = []`), as a buggy or foreign writer could produce with valid checksums.
fn snap_headers() -> Vec<Header> {
    let good = Header::new(
        snap_scene(),
        Engine::Dense,
        Method::Radau5,
        1e-8,
        1e-10,
        "fuzz".into(),
    );
    let mut empty_chain = good.clone();
    empty_chain.scene.chain.mass.clear();
    empty_chain.scene.chain.exponent.clear();
    empty_chain.scene.chain.prefactor.clear();
    empty_chain.scene.chain.precompression = None;
    vec![good, empty_chain]
}

fn snap_bytes(dir: &Path, h: &Header) -> Vec<u8> {
    let p = dir.join("base.snap");
    let mut w = SnapshotWriter::create(&p, h).expect("create");
    for f in snap_frames() {
        w.write_frame(f.t, &f.u, &f.v).expect("frame");
    }
    w.finish(&snap_events(), &snap_summary()).expect("finish");
    std::fs::read(&p).expect("read back")
}

/// Section ranges `(start, end)` of the current bytes, walking the headers while they fit.
fn section_ranges(b: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut pos = PREAMBLE_LEN as usize;
    while pos + 16 <= b.len() {
        let len = u64::from_le_bytes(b[pos + 4..pos + 12].try_into().unwrap_or([0; 8]));
        let end = (len as usize)
            .checked_add(pos + 16)
            .filter(|&e| e <= b.len() && len < (1 << 32));
        let Some(end) = end else { break };
        out.push((pos, end));
        pos = end;
    }
    out
}

/// Recomputes the CRC of the section at `start` (tag ‖ length ‖ payload).
fn fix_crc(b: &mut [u8], start: usize, end: usize) {
    let mut h = crc32fast::Hasher::new();
    h.update(&b[start..start + 12]);
    h.update(&b[start + 16..end]);
    let crc = h.finalize();
    b[start + 12..start + 16].copy_from_slice(&crc.to_le_bytes());
}

#[derive(Clone, Debug)]
enum SnapMut {
    FlipBit(Index, u8),
    SetByte(Index, u8),
    Truncate(Index),
    Insert(Index, Vec<u8>),
    Delete(Index, usize),
    /// Overwrite a section's length field (optionally re-checksummed: forged).
    SetLen(Index, u64, bool),
    /// Overwrite 8 bytes anywhere with a u64 (e.g. an INDEX offset or a bincode length).
    SetU64(Index, u64),
    Swap(Index, Index),
    Duplicate(Index),
    Remove(Index),
    /// Change a payload byte and recompute that section's CRC (forged).
    Forge(Index, Index, u8),
    Append(Vec<u8>),
}

fn interesting_u64() -> impl Strategy<Value = u64> {
    prop_oneof![
        any::<u64>(),
        0u64..64,
        Just(u64::MAX),
        Just(u64::MAX - 15),
        Just(1 << 32),
        Just(1 << 48),
        Just((1 << 48) - 1),
        Just(56),
        Just(40),
        (0u64..4096).prop_map(|x| x * 8),
    ]
}

fn snap_mut() -> impl Strategy<Value = SnapMut> {
    prop_oneof![
        3 => (any::<Index>(), 0u8..8).prop_map(|(i, b)| SnapMut::FlipBit(i, b)),
        1 => (any::<Index>(), any::<u8>()).prop_map(|(i, b)| SnapMut::SetByte(i, b)),
        2 => any::<Index>().prop_map(SnapMut::Truncate),
        1 => (any::<Index>(), prop::collection::vec(any::<u8>(), 1..9))
            .prop_map(|(i, v)| SnapMut::Insert(i, v)),
        1 => (any::<Index>(), 1usize..40).prop_map(|(i, n)| SnapMut::Delete(i, n)),
        2 => (any::<Index>(), interesting_u64(), any::<bool>())
            .prop_map(|(i, v, f)| SnapMut::SetLen(i, v, f)),
        1 => (any::<Index>(), interesting_u64()).prop_map(|(i, v)| SnapMut::SetU64(i, v)),
        2 => (any::<Index>(), any::<Index>()).prop_map(|(i, j)| SnapMut::Swap(i, j)),
        1 => any::<Index>().prop_map(SnapMut::Duplicate),
        1 => any::<Index>().prop_map(SnapMut::Remove),
        1 => (any::<Index>(), any::<Index>(), any::<u8>()).prop_map(|(s, i, b)| SnapMut::Forge(s, i, b)),
        1 => prop::collection::vec(any::<u8>(), 1..40).prop_map(SnapMut::Append),
    ]
}

/// The mutation recomputed a checksum: the file is a forgery, not a damaged file.
const FORGED: u8 = 1;
/// Whole sections were removed, swapped or duplicated: frames carry no index of their own, so
/// e.g. frames 0 and 1 swapped and the file cut after the first is indistinguishable from a
/// one-frame file (found by the fuzzer). The reader catches what the time order and the INDEX
/// reveal; the property then is "no invented numbers".
const REORDERED: u8 = 2;

/// Applies `m`; returns [`FORGED`] / [`REORDERED`] flags.
fn apply_snap(b: &mut Vec<u8>, m: &SnapMut) -> u8 {
    let secs = section_ranges(b);
    let sec = |i: &Index| (!secs.is_empty()).then(|| secs[i.index(secs.len())]);
    match m {
        SnapMut::FlipBit(i, bit) if !b.is_empty() => {
            let p = i.index(b.len());
            b[p] ^= 1 << bit;
        }
        SnapMut::SetByte(i, v) if !b.is_empty() => {
            let p = i.index(b.len());
            b[p] = *v;
        }
        SnapMut::FlipBit(..) | SnapMut::SetByte(..) => {}
        SnapMut::Truncate(i) => b.truncate(i.index(b.len() + 1)),
        SnapMut::Insert(i, v) => {
            let p = i.index(b.len() + 1);
            b.splice(p..p, v.iter().copied());
        }
        SnapMut::Delete(i, n) => {
            let p = i.index(b.len() + 1);
            let e = (p + n).min(b.len());
            b.drain(p..e);
        }
        SnapMut::SetLen(i, v, forge) => {
            if let Some((s, e)) = sec(i) {
                b[s + 4..s + 12].copy_from_slice(&v.to_le_bytes());
                if *forge {
                    // CRC over the new length and the old payload bytes.
                    let mut h = crc32fast::Hasher::new();
                    h.update(&b[s..s + 12]);
                    h.update(&b[s + 16..e]);
                    let crc = h.finalize();
                    b[s + 12..s + 16].copy_from_slice(&crc.to_le_bytes());
                    return FORGED;
                }
            }
        }
        SnapMut::SetU64(i, v) if b.len() >= 8 => {
            let p = i.index(b.len() - 7);
            b[p..p + 8].copy_from_slice(&v.to_le_bytes());
        }
        SnapMut::SetU64(..) => {}
        SnapMut::Swap(i, j) => {
            if let (Some(x), Some(y)) = (sec(i), sec(j)) {
                let (x, y) = if x.0 <= y.0 { (x, y) } else { (y, x) };
                if x.1 <= y.0 && x != y {
                    let first = b[x.0..x.1].to_vec();
                    let second = b[y.0..y.1].to_vec();
                    b.splice(y.0..y.1, first);
                    b.splice(x.0..x.1, second);
                    return REORDERED;
                }
            }
        }
        SnapMut::Duplicate(i) => {
            if let Some((s, e)) = sec(i) {
                let copy = b[s..e].to_vec();
                b.splice(e..e, copy);
                return REORDERED;
            }
        }
        SnapMut::Remove(i) => {
            if let Some((s, e)) = sec(i) {
                b.drain(s..e);
                return REORDERED;
            }
        }
        SnapMut::Forge(i, j, v) => {
            if let Some((s, e)) = sec(i) {
                if e > s + 16 {
                    let p = s + 16 + j.index(e - s - 16);
                    b[p] = *v;
                    fix_crc(b, s, e);
                    return FORGED;
                }
            }
        }
        SnapMut::Append(v) => b.extend_from_slice(v),
    }
    0
}

fn same_frame(a: &Frame, b: &Frame) -> bool {
    let bits = |x: &[f64], y: &[f64]| {
        x.len() == y.len() && x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits())
    };
    a.t.to_bits() == b.t.to_bits() && bits(&a.u, &b.u) && bits(&a.v, &b.v)
}

/// Opens the mutated file and reads everything; checks the reader's guarantees.
fn check_snapshot(path: &Path, base_header: &Header, flags: u8) -> Result<(), TestCaseError> {
    let forged = flags & FORGED != 0;
    let orig = snap_frames();
    reset_largest_alloc();
    let Ok(s) = Snapshot::open(path) else {
        prop_assert!(
            largest_alloc() <= ALLOC_LIMIT,
            "open allocated {}",
            largest_alloc()
        );
        return Ok(());
    };
    let n = s.header().n_beads as usize;
    for k in 0..s.frame_count() {
        if let Ok(f) = s.frame(k) {
            prop_assert!(
                f.u.len() == n && f.v.len() == n,
                "frame {k} has the wrong shape"
            );
            if forged {
                continue;
            }
            if flags & REORDERED != 0 {
                // Renumbering is possible, invented numbers are not.
                let known = orig.iter().any(|o| same_frame(&f, o));
                prop_assert!(known, "frame {k} holds numbers never written: {f:?}");
            } else {
                prop_assert!(
                    k < orig.len(),
                    "frame {k} beyond the {} written",
                    orig.len()
                );
                prop_assert!(
                    same_frame(&f, &orig[k]),
                    "frame {k} holds wrong numbers: {f:?}"
                );
            }
        }
    }
    for sel in [FrameSel::All, FrameSel::Last] {
        let mut csv = Vec::new();
        if export_csv(&s, sel, &mut csv).is_ok() && sel == FrameSel::All {
            let rows = csv.iter().filter(|&&c| c == b'\n').count();
            prop_assert_eq!(rows, 1 + n * s.frame_count());
        }
        let _ = export_npy(&s, sel, &mut Vec::new());
    }
    let chain = s.header().scene.chain.clone();
    let _report = inspect(&s, &chain);
    prop_assert!(
        largest_alloc() <= ALLOC_LIMIT,
        "allocated {}",
        largest_alloc()
    );
    if !forged {
        prop_assert_eq!(s.header(), base_header);
        if !s.events().is_empty() {
            prop_assert_eq!(s.events(), &snap_events()[..]);
        }
        if let Some(sum) = s.summary() {
            prop_assert_eq!(sum, &snap_summary());
        }
    }
    Ok(())
}

#[test]
fn fuzz_snapshot_reader() {
    let d = tempfile::tempdir().expect("tempdir");
    let headers = snap_headers();
    let bases: Vec<Vec<u8>> = headers.iter().map(|h| snap_bytes(d.path(), h)).collect();
    let file = d.path().join("case.snap");
    let strategy = (
        prop_oneof![4 => Just(0usize), 1 => Just(1usize)],
        prop::collection::vec(snap_mut(), 1..5),
    );
    let cases = fuzz("snapshot_reader", strategy, |(base, muts)| {
        let mut bytes = bases[base].clone();
        let mut flags = 0;
        for m in &muts {
            flags |= apply_snap(&mut bytes, m);
        }
        std::fs::write(&file, &bytes).map_err(|e| TestCaseError::fail(e.to_string()))?;
        check_snapshot(&file, &headers[base], flags)
    });
    assert!(cases > 0);
}

/// Regression (found by `fuzz_snapshot_reader`): a FRAME section duplicated in place made the
/// scan read frame 0's numbers as frame 1 (END/INDEX no longer line up, so the reader scans).
#[test]
fn duplicated_frame_section_is_not_read_as_the_next_frame() {
    let d = tempfile::tempdir().unwrap();
    let base = snap_bytes(d.path(), &snap_headers()[0]);
    let secs = section_ranges(&base);
    let (s, e) = secs[1]; // FRAME #0
    let mut b = base.clone();
    b.splice(e..e, base[s..e].to_vec());
    let p = d.path().join("dup.snap");
    std::fs::write(&p, &b).unwrap();
    let r = Snapshot::open(&p);
    assert!(r.is_err(), "duplicated frame accepted");
    let msg = r.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(
        msg.contains("dup.snap") && msg.contains("FRAME #1"),
        "{msg}"
    );
    // Same without INDEX/END (unfinished file): the time order catches it.
    let events_at = section_ranges(&b)[N_FRAMES + 2].0;
    std::fs::write(&p, &b[..events_at]).unwrap();
    assert!(
        Snapshot::open(&p).is_err(),
        "duplicated frame accepted without INDEX"
    );
}

/// Regression (found by `fuzz_snapshot_reader`): two FRAME sections swapped in a file without
/// END/INDEX were read at each other's frame numbers; frames are now required to increase in
/// time, and a whole INDEX met during a scan must agree with the frames before it.
#[test]
fn swapped_or_removed_frame_sections_are_an_error_not_renumbered() {
    let d = tempfile::tempdir().unwrap();
    let base = snap_bytes(d.path(), &snap_headers()[0]);
    let secs = section_ranges(&base);
    let (f1, f2) = (secs[2], secs[3]);
    let mut swapped = base.clone();
    swapped.splice(f2.0..f2.1, base[f1.0..f1.1].to_vec());
    swapped.splice(f1.0..f1.1, base[f2.0..f2.1].to_vec());
    let p = d.path().join("swap.snap");
    let events_at = secs[N_FRAMES + 1].0;
    std::fs::write(&p, &swapped[..events_at]).unwrap();
    assert!(
        Snapshot::open(&p).is_err(),
        "swapped frames accepted in a scan"
    );
    // Frame #1 removed, END damaged: the scan meets the INDEX listing 4 frames.
    let mut removed = base.clone();
    removed.drain(f1.0..f1.1);
    let last = removed.len() - 1;
    removed[last] ^= 0xFF;
    std::fs::write(&p, &removed).unwrap();
    let r = Snapshot::open(&p);
    let msg = r.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(msg.contains("INDEX lists 4 frames"), "{msg}");
}
