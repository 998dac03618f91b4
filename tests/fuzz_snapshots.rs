//! Fuzzing the snapshot reader without nightly: proptest-driven mutation of snapshot files.
//!
//! Small valid snapshots (one with an inconsistent header), mutated by bit flips, byte writes,
//! truncation, insert/delete, length-field corruption, section swaps, duplication and deletion,
//! and payload edits with a recomputed CRC ("forged"). Property: `Snapshot::open`, `frame(k)`
//! for every k, `export_csv`, `export_npy` and `inspect` never panic; no single allocation
//! exceeds 8 MiB; unless the mutation forged a checksum, every frame read successfully holds the
//! original numbers at its original index, and the header, event log and summary are the
//! original ones when present.
//!
//! Budget and seed: see `tests/fuzz_support/mod.rs`. Long run:
//! `BEADCHAIN_FUZZ_CASES=large cargo test --release --test fuzz_snapshots -- --nocapture`.

mod fuzz_support;

use beadchain::export::{export_csv, export_npy, inspect, ExportUnits, FrameSel};
use beadchain::integrate::{Method, Stats};
use beadchain::model::{Chain, Wall};
use beadchain::scene::{Engine, RunSettings, Scene};
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
                restitution: None,
            }),
            right_wall: None,
            hard: None,
            damping: None,
        },
        u0: vec![0.0; N_BEADS],
        v0: vec![1.0, 0.0, 0.0],
        run: RunSettings {
            until: 3.0,
            every: Some(1.0),
            ..Default::default()
        },
        seed: 9,
        units: None,
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
            dissipated: Some(0.0),
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

/// Sets the length field of section `s..e` to `v`; with `forge`, also its CRC (over the new
/// length and the old payload bytes), returning [`FORGED`].
fn set_len(b: &mut [u8], (s, e): (usize, usize), v: u64, forge: bool) -> u8 {
    b[s + 4..s + 12].copy_from_slice(&v.to_le_bytes());
    if !forge {
        return 0;
    }
    let mut h = crc32fast::Hasher::new();
    h.update(&b[s..s + 12]);
    h.update(&b[s + 16..e]);
    let crc = h.finalize();
    b[s + 12..s + 16].copy_from_slice(&crc.to_le_bytes());
    FORGED
}

/// Swaps two distinct, non-overlapping sections ([`REORDERED`]); otherwise leaves `b` alone.
fn swap_sections(b: &mut Vec<u8>, x: (usize, usize), y: (usize, usize)) -> u8 {
    let (x, y) = if x.0 <= y.0 { (x, y) } else { (y, x) };
    if x.1 > y.0 || x == y {
        return 0;
    }
    let first = b[x.0..x.1].to_vec();
    let second = b[y.0..y.1].to_vec();
    b.splice(y.0..y.1, first);
    b.splice(x.0..x.1, second);
    REORDERED
}

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
                return set_len(b, (s, e), *v, *forge);
            }
        }
        SnapMut::SetU64(i, v) if b.len() >= 8 => {
            let p = i.index(b.len() - 7);
            b[p..p + 8].copy_from_slice(&v.to_le_bytes());
        }
        SnapMut::SetU64(..) => {}
        SnapMut::Swap(i, j) => {
            if let (Some(x), Some(y)) = (sec(i), sec(j)) {
                return swap_sections(b, x, y);
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
            // Every FRAME carries its own number (D2 fix), so even after sections were swapped,
            // duplicated or removed a frame read at index k is the frame written as k.
            let _ = flags & REORDERED;
            {
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
        if export_csv(&s, sel, &ExportUnits::computer(), &mut csv).is_ok() && sel == FrameSel::All {
            let rows = csv
                .split(|&c| c == b'\n')
                .filter(|l| !l.is_empty() && l[0] != b'#')
                .count();
            prop_assert_eq!(rows, 1 + n * s.frame_count());
        }
        let _ = export_npy(&s, sel, &ExportUnits::computer(), &mut Vec::new());
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
    assert!(
        msg.contains("INDEX lists 4 frames") || msg.contains("holds frame number 2, expected 1"),
        "{msg}"
    );
}

/// Regression for D2 (found by `fuzz_snapshot_reader`): frames 0 and 1 swapped and the file cut
/// right after the first one used to read as a valid one-frame file holding frame 1's numbers
/// at index 0; the frame number stored in every FRAME now rejects it.
#[test]
fn swapped_then_cut_frame_is_not_read_at_the_wrong_index() {
    let d = tempfile::tempdir().unwrap();
    let base = snap_bytes(d.path(), &snap_headers()[0]);
    let secs = section_ranges(&base);
    let (f0, f1) = (secs[1], secs[2]);
    let mut b = base[..f0.0].to_vec();
    b.extend_from_slice(&base[f1.0..f1.1]);
    let p = d.path().join("d2.snap");
    std::fs::write(&p, &b).unwrap();
    let msg = Snapshot::open(&p)
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(msg.contains("holds frame number 1, expected 0"), "{msg}");
}
