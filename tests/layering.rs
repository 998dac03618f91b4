//! The layering of `src/` (docs/architecture.md): which top-level module may import which, and
//! no import cycles between the files of one module.
//!
//! The test reads every `.rs` file under `src/`, collects the paths it names (`use` trees and
//! inline `crate::…`/`super::…`/`beadchain::…` paths, comments skipped) and checks:
//!
//! 1. **Layers.** Every top-level module has a layer ([`LAYERS`]); a module imports only modules
//!    of lower layers, except the pairs listed in [`EXCEPTIONS`] (known upward imports, each with
//!    the reason it remains). The binary (`src/main.rs`, `src/cli/`) is the top layer `cli`.
//! 2. **No file cycles inside a module.** Between the files of one top-level module, no file
//!    imports one that (directly or through others) imports it back. A parent module file
//!    (`mod.rs`) and its own children are not counted as a cycle: the parent declares and
//!    re-exports its children, the children use the parent's types.
//!
//! The checker itself is tested on small synthetic trees (an upward import and a two-file cycle
//! must be reported), so the checks on the real tree can fail.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Layer of every top-level module: a module may import only modules of a lower layer.
/// Read bottom-up: the chain model, its linear algebra and integrators, scene files, the
/// engines, the snapshot format, what reads runs and frames, experiments, the command line.
const LAYERS: &[(&str, u32)] = &[
    ("model", 0),       // chain, contact laws, energies: imports nothing of the crate
    ("files", 0),       // file-safety helpers (atomic outputs, temporaries, limited reads)
    ("names", 0),       // named closed sets (method, engine, ...): one list, one parser
    ("provenance", 0),  // version, build commit and date recorded in every output
    ("linalg", 1),      // tridiagonal/banded solvers
    ("integrate", 2),   // Radau IIA, DOP853, Verlet, auto
    ("studies", 2),     // solitary waves, linear modes, bands, static equilibrium
    ("scene", 3),       // TOML scenes → Scene (model + run settings)
    ("engine", 4),      // dense and hybrid engines, observers
    ("suggest", 4),     // "did you mean": nearest preset names (reads scene's preset list)
    ("snapshot", 5),    // binary format: header (scene, run config), frames, events, checkpoints
    ("analysis", 6),    // observables from states, frames and event logs
    ("export", 6),      // snapshot → CSV/NPY/NPZ, `inspect`
    ("progress", 6),    // progress bar observer
    ("check", 7),       // hybrid vs dense comparison
    ("experiments", 7), // the paper's experiments: build scenes, run engines, analyse
    ("plot", 7),        // figures of snapshots and CSV tables
    ("accuracy", 8),    // work-precision study (runs engines, plots)
    ("sweep", 8),       // parameter sweeps (runs experiments' watched runs)
    ("prelude", 9),     // the front door: re-exports for `use beadchain::prelude::*`
    ("cli", 9),         // the binary
];

/// Upward imports that remain, `(from, to, reason)`. A new upward import fails the test; remove
/// a row when its import is gone (the test prints a note for a row no longer needed).
const EXCEPTIONS: &[(&str, &str, &str)] = &[];

/// File cycles that remain inside a module, `(file, file, reason)`, in the lead's area.
const FILE_CYCLE_EXCEPTIONS: &[(&str, &str, &str)] = &[];

/// One source file: its crate (`lib` or `bin`), its module path in that crate, its text.
struct Source {
    rel: String,
    krate: &'static str,
    module: Vec<String>,
    text: String,
}

/// Module path of a file relative to `src/` (`scene/parse.rs` → `[scene, parse]`,
/// `snapshot/mod.rs` → `[snapshot]`), and its crate: `main.rs` and `cli/` belong to the binary.
fn module_of(rel: &str) -> (&'static str, Vec<String>) {
    let stem = rel.strip_suffix(".rs").unwrap_or(rel);
    let mut parts: Vec<String> = stem.split('/').map(str::to_string).collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    match parts.first().map(String::as_str) {
        Some("main") => ("bin", Vec::new()),
        Some("lib") => ("lib", Vec::new()),
        // `cli_*.rs` at the top: the binary's modules before they moved into `src/cli/`.
        Some(c) if c == "cli" || c.starts_with("cli_") => ("bin", parts),
        _ => ("lib", parts),
    }
}

/// Top-level module (layer name) of a file: the first path segment; `accuracy_tests.rs` (the
/// `#[path]` test module of `accuracy.rs`) counts as `accuracy`, the binary as `cli`.
fn top_of(src: &Source) -> Option<String> {
    if src.krate == "bin" {
        return Some("cli".to_string());
    }
    let first = src.module.first()?;
    Some(first.strip_suffix("_tests").unwrap_or(first).to_string())
}

fn read_tree(root: &Path) -> Vec<Source> {
    let mut out = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
            .map(|e| e.expect("directory entry").path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                let rel = p
                    .strip_prefix(root)
                    .expect("under src")
                    .to_string_lossy()
                    .replace('\\', "/");
                let text = std::fs::read_to_string(&p).expect("source text");
                out.push(source(&rel, text));
            }
        }
    }
    out
}

fn source(rel: &str, text: String) -> Source {
    let (krate, module) = module_of(rel);
    Source {
        rel: rel.to_string(),
        krate,
        module,
        text,
    }
}

/// The code of a file without comments (line comments and block comments; string literals
/// are kept, which is harmless: they do not hold `crate::` paths followed by code).
fn strip_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let b = text.as_bytes();
    let (mut i, mut depth) = (0, 0usize);
    while i < b.len() {
        if b[i..].starts_with(b"/*") {
            depth += 1;
            i += 2;
        } else if depth > 0 && b[i..].starts_with(b"*/") {
            depth -= 1;
            i += 2;
        } else if depth > 0 {
            i += 1;
        } else if b[i..].starts_with(b"//") {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else {
            let ch = text[i..].chars().next().expect("char");
            out.push(ch);
            i += ch.len_utf8();
        }
    }
    out
}

fn is_ident(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Every path a file names: `use` trees expanded (`use a::{b, c::d}` → `a::b`, `a::c::d`) and
/// inline paths (`crate::files::read_text(…)`), as segment lists starting at `crate`, `super`,
/// `self` or `beadchain`.
fn paths_in(code: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let roots = ["crate", "super", "self", "beadchain"];
    let chars: Vec<char> = code.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        let boundary = i == 0 || !(is_ident(chars[i - 1]) || chars[i - 1] == ':');
        if boundary && is_ident(chars[i]) {
            let start = i;
            while i < chars.len() && is_ident(chars[i]) {
                i += 1;
            }
            let word: String = chars[start..i].iter().collect();
            if roots.contains(&word.as_str()) && chars[i..].starts_with(&[':', ':']) {
                i = expand(&chars, i, vec![word], &mut out);
            }
        } else {
            i += 1;
        }
    }
    out
}

/// Expands the rest of a path after `prefix` (at `::` or the end), pushing full paths; returns
/// the index after the path (or use tree).
fn expand(chars: &[char], mut i: usize, prefix: Vec<String>, out: &mut Vec<Vec<String>>) -> usize {
    let mut path = prefix;
    loop {
        if !chars[i..].starts_with(&[':', ':']) {
            out.push(path);
            return i;
        }
        i += 2;
        while i < chars.len() && chars[i].is_whitespace() {
            i += 1;
        }
        if i < chars.len() && chars[i] == '{' {
            i += 1;
            loop {
                while i < chars.len() && (chars[i].is_whitespace() || chars[i] == ',') {
                    i += 1;
                }
                if i >= chars.len() || chars[i] == '}' {
                    out.push(path.clone());
                    return i + 1;
                }
                let start = i;
                while i < chars.len() && (is_ident(chars[i]) || chars[i] == '*') {
                    i += 1;
                }
                let mut sub = path.clone();
                sub.push(chars[start..i].iter().collect());
                i = expand(chars, i, sub, out);
                while i < chars.len() && !matches!(chars[i], ',' | '}') {
                    i += 1; // ` as Name`
                }
            }
        }
        let start = i;
        while i < chars.len() && is_ident(chars[i]) {
            i += 1;
        }
        if start == i {
            out.push(path);
            return i;
        }
        path.push(chars[start..i].iter().collect());
    }
}

/// The module a path refers to, in the file's crate or (for `beadchain::` in the binary) in the
/// library: `(crate, module path)`; `super`/`self` resolve from the file's module.
fn target(src: &Source, path: &[String]) -> Option<(&'static str, Vec<String>)> {
    let (krate, mut module, rest) = match path.first()?.as_str() {
        "crate" => (src.krate, Vec::new(), &path[1..]),
        "beadchain" => ("lib", Vec::new(), &path[1..]),
        "self" | "super" => {
            let mut m = src.module.clone();
            let mut k = 0;
            while k < path.len() && (path[k] == "super" || path[k] == "self") {
                if path[k] == "super" {
                    m.pop()?;
                }
                k += 1;
            }
            (src.krate, m, &path[k..])
        }
        _ => return None,
    };
    module.extend(rest.iter().cloned());
    Some((krate, module))
}

/// The longest prefix of `module` that is a file of the tree.
fn resolve<'a>(
    files: &'a BTreeMap<(&'static str, Vec<String>), usize>,
    krate: &'static str,
    module: &[String],
) -> Option<&'a usize> {
    (0..=module.len())
        .rev()
        .find_map(|n| files.get(&(krate, module[..n].to_vec())))
}

/// Edges between files (indices into `tree`), and between top-level modules with the files
/// that cause them.
struct Graph {
    files: BTreeSet<(usize, usize)>,
    tops: BTreeMap<(String, String), BTreeSet<String>>,
}

fn graph(tree: &[Source]) -> Graph {
    let index: BTreeMap<(&'static str, Vec<String>), usize> = tree
        .iter()
        .enumerate()
        .map(|(i, s)| ((s.krate, s.module.clone()), i))
        .collect();
    let mut g = Graph {
        files: BTreeSet::new(),
        tops: BTreeMap::new(),
    };
    for (i, src) in tree.iter().enumerate() {
        let from_top = top_of(src);
        for path in paths_in(&strip_comments(&src.text)) {
            let Some((krate, module)) = target(src, &path) else {
                continue;
            };
            if krate != src.krate || path[0] == "beadchain" {
                // The binary importing the library: a top-level edge only.
                if let (Some(f), Some(t)) = (&from_top, module.first()) {
                    let t = t.strip_suffix("_tests").unwrap_or(t).to_string();
                    if *f != t && index.contains_key(&("lib", vec![t.clone()])) {
                        g.tops
                            .entry((f.clone(), t))
                            .or_default()
                            .insert(src.rel.clone());
                    }
                }
                continue;
            }
            let Some(&j) = resolve(&index, krate, &module) else {
                continue;
            };
            if j == i {
                continue;
            }
            g.files.insert((i, j));
            if let (Some(f), Some(t)) = (&from_top, top_of(&tree[j])) {
                if *f != t && krate == "lib" {
                    g.tops
                        .entry((f.clone(), t))
                        .or_default()
                        .insert(src.rel.clone());
                }
            }
        }
    }
    g
}

fn layer(name: &str) -> Option<u32> {
    LAYERS.iter().find(|(n, _)| *n == name).map(|(_, l)| *l)
}

/// Every top-level import that goes to the same or a higher layer and is not an exception.
fn layer_violations(g: &Graph) -> Vec<String> {
    let mut bad = Vec::new();
    for ((from, to), files) in &g.tops {
        let (Some(lf), Some(lt)) = (layer(from), layer(to)) else {
            bad.push(format!(
                "{from} -> {to}: module without a layer in LAYERS ({files:?})"
            ));
            continue;
        };
        let excepted = EXCEPTIONS.iter().any(|(f, t, _)| f == from && t == to);
        if lt >= lf && !excepted {
            bad.push(format!(
                "{from} (layer {lf}) imports {to} (layer {lt}) in {}",
                files.iter().cloned().collect::<Vec<_>>().join(", ")
            ));
        }
    }
    bad
}

/// True when one module path is the other's ancestor (a `mod.rs` and its own children).
fn related(a: &[String], b: &[String]) -> bool {
    a.starts_with(b) || b.starts_with(a)
}

/// Cycles between files of one top-level module (parent/child pairs not counted), each as the
/// list of files around it.
fn file_cycles(tree: &[Source], g: &Graph) -> Vec<Vec<String>> {
    let mut next: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for &(a, b) in &g.files {
        let (sa, sb) = (&tree[a], &tree[b]);
        if sa.krate == sb.krate && top_of(sa) == top_of(sb) && !related(&sa.module, &sb.module) {
            next.entry(a).or_default().push(b);
        }
    }
    let mut cycles = Vec::new();
    let mut seen_cycle = BTreeSet::new();
    for &start in next.keys() {
        // Depth-first search for a path back to `start` through files greater than `start`
        // (each cycle is found once, from its smallest file).
        let mut stack = vec![(start, vec![start])];
        let mut visited = BTreeSet::new();
        while let Some((at, path)) = stack.pop() {
            for &n in next.get(&at).into_iter().flatten() {
                if n == start {
                    let names: Vec<String> = path.iter().map(|&k| tree[k].rel.clone()).collect();
                    if seen_cycle.insert(names.clone()) {
                        cycles.push(names);
                    }
                } else if n > start && visited.insert(n) {
                    let mut p = path.clone();
                    p.push(n);
                    stack.push((n, p));
                }
            }
        }
    }
    cycles
}

/// The tree checked: `src/` of this package, or the directory named by `LAYERING_SRC` (to run
/// the checks on another checkout's `src/`).
fn src_tree() -> Vec<Source> {
    match std::env::var_os("LAYERING_SRC") {
        Some(dir) => read_tree(Path::new(&dir)),
        None => read_tree(&Path::new(env!("CARGO_MANIFEST_DIR")).join("src")),
    }
}

#[test]
fn top_level_modules_import_only_lower_layers() {
    let tree = src_tree();
    let g = graph(&tree);
    // The parser sees the real imports (a few known downward edges).
    for (from, to) in [
        ("sweep", "analysis"),
        ("cli", "snapshot"),
        ("engine", "integrate"),
    ] {
        assert!(
            g.tops.contains_key(&(from.into(), to.into())),
            "{from} -> {to} not found"
        );
    }
    let bad = layer_violations(&g);
    assert!(bad.is_empty(), "upward imports:\n{}", bad.join("\n"));
    for (from, to, why) in EXCEPTIONS {
        if !g.tops.contains_key(&(from.to_string(), to.to_string())) {
            eprintln!("note: exception {from} -> {to} ({why}) is no longer needed: remove it");
        }
    }
    // Every top-level module of the library has a layer.
    let tops: BTreeSet<String> = tree.iter().filter_map(top_of).collect();
    for t in &tops {
        assert!(
            layer(t).is_some(),
            "src/{t}: add it to LAYERS (and docs/architecture.md)"
        );
    }
}

#[test]
fn no_file_imports_one_that_imports_it_back() {
    let tree = src_tree();
    let g = graph(&tree);
    let cycles: Vec<Vec<String>> = file_cycles(&tree, &g)
        .into_iter()
        .filter(|c| {
            !FILE_CYCLE_EXCEPTIONS.iter().any(|(a, b, _)| {
                c.len() == 2 && c.contains(&a.to_string()) && c.contains(&b.to_string())
            })
        })
        .collect();
    let text: Vec<String> = cycles.iter().map(|c| c.join(" -> ")).collect();
    assert!(cycles.is_empty(), "import cycles:\n{}", text.join("\n"));
}

/// The CLI's children never import `cli/mod.rs` (it only parses and dispatches).
#[test]
fn cli_children_do_not_import_the_dispatcher() {
    let tree = src_tree();
    let g = graph(&tree);
    for &(a, b) in &g.files {
        if tree[b].rel == "cli/mod.rs" {
            panic!("{} imports cli/mod.rs", tree[a].rel);
        }
    }
}

fn synthetic(files: &[(&str, &str)]) -> Vec<Source> {
    files
        .iter()
        .map(|(r, t)| source(r, t.to_string()))
        .collect()
}

/// The checker reports an upward import (scene importing analysis) and accepts the downward one.
#[test]
fn layering_check_reports_an_upward_import() {
    let tree = synthetic(&[
        ("lib.rs", "pub mod scene; pub mod analysis; pub mod model;"),
        (
            "scene/mod.rs",
            "use crate::model::Chain;\n// crate::analysis in a comment\n",
        ),
        (
            "analysis/mod.rs",
            "use crate::{model::Chain, scene::{self, Scene}};",
        ),
        ("model/mod.rs", ""),
    ]);
    assert!(layer_violations(&graph(&tree)).is_empty());
    let tree = synthetic(&[
        ("lib.rs", ""),
        (
            "scene/mod.rs",
            "fn f() { crate::analysis::wave::detect(); }",
        ),
        ("analysis/mod.rs", ""),
        ("analysis/wave.rs", ""),
    ]);
    let bad = layer_violations(&graph(&tree));
    assert_eq!(bad.len(), 1, "{bad:?}");
    assert!(
        bad[0].starts_with("scene (layer 3) imports analysis (layer 6)"),
        "{bad:?}"
    );
}

/// The checker reports a two-file cycle between siblings (as scene/parse ↔ scene/presets was),
/// but not a parent `mod.rs` and its child.
#[test]
fn cycle_check_reports_a_sibling_cycle() {
    let tree = synthetic(&[
        (
            "scene/mod.rs",
            "mod parse; mod presets; pub use parse::parse_str;",
        ),
        ("scene/parse.rs", "use super::{presets, Scene};"),
        ("scene/presets.rs", "use super::parse::parse_str;"),
    ]);
    let cycles = file_cycles(&tree, &graph(&tree));
    assert_eq!(
        cycles,
        vec![vec![
            "scene/parse.rs".to_string(),
            "scene/presets.rs".to_string()
        ]]
    );
    let tree = synthetic(&[
        ("scene/mod.rs", "mod load; mod parse; mod presets;"),
        ("scene/load.rs", "use super::{parse::parse_str, presets};"),
        ("scene/parse.rs", "use super::Scene;"),
        ("scene/presets.rs", "use super::parse::parse_str;"),
    ]);
    assert!(file_cycles(&tree, &graph(&tree)).is_empty());
}
