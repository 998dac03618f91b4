//! Fuzzing the scene parser without nightly: proptest-driven mutation of scene files.
//!
//! Every preset's TOML and a few hand-written scenes (with CSV files), mutated by byte flips,
//! truncation, insertions/deletions, numbers replaced by `nan`, `inf`, `1e400`, huge integers,
//! wrong types, random keys/tables and whole lines. Property: parsing (`scene::parse_str`, and
//! `scene::load` of the raw bytes written to a file) never panics; an error is one line naming
//! the origin file; a parsed scene passes `scene::validate`, its warnings are one line each,
//! and its arrays are consistent and finite.
//!
//! Budget and seed: see `tests/fuzz_support/mod.rs` (`BEADCHAIN_FUZZ_CASES`, default 200 per
//! target; `large` = time-boxed; `BEADCHAIN_FUZZ_SEED`). Long run:
//! `BEADCHAIN_FUZZ_CASES=large cargo test --release --test fuzz_scenes -- --nocapture`.

mod fuzz_support;

use beadchain::scene::{self, Scene};
use fuzz_support::{fuzz, CountingAlloc};
use proptest::prelude::*;
use proptest::sample::Index;
use proptest::test_runner::TestCaseError;

#[global_allocator]
static ALLOC: CountingAlloc = CountingAlloc;
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
