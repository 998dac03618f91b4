//! The README and the paper's figure numbers (issue 36, item 9).
//!
//! - The README is a quick start: at most 150 lines, the two set-up commands that `.ci/run`
//!   runs, a link to the benchmark page, and no preset count that disagrees with the presets.
//! - Every "Fig. N" the project cites (README, docs, examples, sweeps, presets, code comments,
//!   validation report) is checked against the paper: a line that names a known subject (the
//!   3.0 → 2.5 interface, the `(n1, n2)` reflection grid, …) may cite only that subject's figures,
//!   and no line cites a figure the paper does not have. The figure table below is checked
//!   against the paper's `.tex` (the order of its `figure` environments) when the file is found
//!   (`$BEADCHAIN_PAPER`, or `../shared/paper-hertz-like-interfaces.tex` beside the repository).

use std::path::{Path, PathBuf};

/// The paper's figures in order (number = position + 1): their `\label`s.
const FIGURES: [&str; 28] = [
    "fig:chain",
    "fig:wavelength",
    "fig:interface",
    "fig3",
    "fig4",
    "fig:large_small",
    "fig:reflected_energy_rel",
    "fig:reflectedCollapsed",
    "fig:periodic_chain",
    "fig:periodic_pairs",
    "fig:periodic_decay",
    "fig:periodicity_decay_rates",
    "fig:periodic_resonance",
    "fig:periodic_resonance2",
    "fig:impurity",
    "fig:impurity_example",
    "fig:bead_pairs",
    "fig:sparticlereflection",
    "fig:n_random",
    "fig:decay",
    "fig:exponential_decay",
    "fig:decay_rates",
    "fig:transfer",
    "fig:NMinterface",
    "fig:reflected_energy_relNM",
    "fig:convergence",
    "fig:stabilitysmalllarge",
    "fig:stabilitylargesmall",
];

/// Subjects: lower-case phrases naming one of the paper's results, and the figures that show it.
const SUBJECTS: &[(&[&str], &[u32])] = &[
    (&["wavelength"], &[2]),
    (
        &[
            "3.0 -> 3.5",
            "3.0 → 3.5",
            "3.0->3.5",
            "interface_3.0_3.5",
            "gap timings",
        ],
        &[4, 5],
    ),
    (
        &[
            "3.0 -> 2.5",
            "3.0 → 2.5",
            "3.0->2.5",
            "interface_3.0_2.5",
            "large_small",
        ],
        &[6],
    ),
    (&["(n1, n2)", "reflection_grid", "left_fraction"], &[7]),
    (&["ζ", "zeta", "collapse"], &[7, 8]),
    (&["periodic"], &[9, 10, 11, 12, 13, 14]),
    (&["2.5/3.0", "periodic_2.5_3.0", "pairwise"], &[10]),
    (&["2.5/2.555", "periodic_decay"], &[11, 12]),
    (&["breath", "2.635", "4.0/5.0"], &[13, 14]),
    (&["impurity example", "n_imp = 3.5"], &[16]),
    (&["collective impurity", "impurity_s5"], &[17, 18]),
    (&["v_out/v_in", "v_ratio"], &[18]),
    (&["disorder", "random exponents"], &[19, 20, 21, 22, 23]),
    (&["transfer"], &[23]),
    (&["composite", "mass–exponent", "mass-exponent"], &[24, 25]),
    (&["3.5 -> 3.0", "3.5 → 3.0", "perturbed"], &[28]),
];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The figure numbers cited on a line: `Fig. 6`, `Figs. 4–5`, `Figs. 10, 11, 13, 14`,
/// `Figs. 16 and 17`, `Figs. 15/17`, `Figure 3` (ranges expanded).
fn cited(line: &str) -> Vec<u32> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(a) = rest.find("Fig") {
        rest = &rest[a + 3..];
        let s = rest.trim_start_matches("ure").trim_start_matches('s');
        let s = s.trim_start_matches('.').trim_start_matches(' ');
        let mut s = s;
        let mut prev: Option<u32> = None;
        let mut range = false;
        loop {
            let digits: String = s.chars().take_while(|c| c.is_ascii_digit()).collect();
            let Ok(n) = digits.parse::<u32>() else { break };
            match (range, prev) {
                (true, Some(p)) if p < n => out.extend(p + 1..=n),
                _ => out.push(n),
            }
            prev = Some(n);
            s = &s[digits.len()..];
            let sep = [", ", " and ", "–", "-", "/"].into_iter().find(|sep| {
                s.starts_with(sep) && s[sep.len()..].starts_with(|c: char| c.is_ascii_digit())
            });
            let Some(sep) = sep else { break };
            range = sep == "–" || sep == "-";
            s = &s[sep.len()..];
        }
    }
    out
}

/// The text files that cite the paper's figures.
fn cited_files() -> Vec<PathBuf> {
    let r = root();
    let mut files = vec![
        r.join("README.md"),
        r.join("validation/REPORT.md"),
        r.join("validation/figures/make.sh"),
        r.join("validation/quick/quick.md"),
    ];
    for (dir, ext) in [
        ("docs", "md"),
        ("examples", "py"),
        ("data/sweeps", "toml"),
        ("data/scenes", "toml"),
        ("src", "rs"),
        ("benches", "rs"),
        ("tests", "rs"),
        ("python", "py"),
        ("python", "md"),
    ] {
        walk(&r.join(dir), ext, &mut files);
    }
    files.retain(|f| !f.ends_with("tests/docs_consistency.rs"));
    files
}

/// Files under `dir` (recursively, skipping hidden and build directories) ending in `.ext`.
fn walk(dir: &Path, ext: &str, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let mut entries: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for p in entries {
        let name = p
            .file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into());
        if name.starts_with('.') || name == "target" {
            continue;
        }
        if p.is_dir() {
            walk(&p, ext, out);
        } else if p.extension().is_some_and(|e| e == ext) {
            out.push(p);
        }
    }
}

/// Every line citing a figure the paper lacks, or a figure its subject is not shown in.
fn bad_references(path: &Path, text: &str) -> Vec<String> {
    let mut bad = Vec::new();
    for (k, line) in text.lines().enumerate() {
        let figs = cited(line);
        if figs.is_empty() {
            continue;
        }
        let at = format!("{}:{}: {}", path.display(), k + 1, line.trim());
        if let Some(f) = figs.iter().find(|&&f| f == 0 || f as usize > FIGURES.len()) {
            bad.push(format!("{at}\n    Fig. {f}: the paper has Figs. 1–28"));
            continue;
        }
        let lower = line.to_lowercase();
        let mut allowed: Vec<u32> = Vec::new();
        let mut subjects: Vec<&str> = Vec::new();
        for (phrases, figures) in SUBJECTS {
            if let Some(p) = phrases.iter().find(|p| lower.contains(*p)) {
                allowed.extend(figures.iter());
                subjects.push(p);
            }
        }
        if subjects.is_empty() {
            continue;
        }
        let wrong: Vec<u32> = figs.into_iter().filter(|f| !allowed.contains(f)).collect();
        if !wrong.is_empty() {
            bad.push(format!(
                "{at}\n    cites Fig. {wrong:?}; {subjects:?} is in Fig. {allowed:?}"
            ));
        }
    }
    bad
}

#[test]
fn figure_references_match_the_paper() {
    // before: the reflection grid was "Fig. 6" in the sweep file and "Fig. 7" in the README;
    // the 3.0 → 2.5 interface "Fig. 5" in validation/REPORT.md and "Fig. 6" in the presets
    let files = cited_files();
    assert!(files.len() > 50, "{} files", files.len());
    let mut bad = Vec::new();
    let mut n = 0;
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap_or_default();
        n += text.lines().filter(|l| !cited(l).is_empty()).count();
        bad.extend(bad_references(f.strip_prefix(root()).unwrap_or(f), &text));
    }
    assert!(n > 100, "only {n} lines cite figures: is the scan broken?");
    assert!(
        bad.is_empty(),
        "{} bad references:\n{}",
        bad.len(),
        bad.join("\n")
    );
}

#[test]
fn figure_citations_are_parsed() {
    assert_eq!(cited("paper Fig. 6, label fig:large_small"), vec![6]);
    assert_eq!(cited("(Figs. 4-5, labels fig3 and fig4)"), vec![4, 5]);
    assert_eq!(cited("Figs. 3–7) and Fig. 18"), vec![3, 4, 5, 6, 7, 18]);
    assert_eq!(cited("Figs. 10, 11, 13, 14, bottom"), vec![10, 11, 13, 14]);
    assert_eq!(cited("Figs. 16 and 17; Figs. 15/17"), vec![16, 17, 15, 17]);
    assert_eq!(cited("Figure 3 shows"), vec![3]);
    assert!(cited("Fig. (a) and figures").is_empty());
    let bad = bad_references(Path::new("x"), "grid over (n1, n2) (paper Fig. 6)");
    assert_eq!(bad.len(), 1, "{bad:?}");
    assert!(bad_references(Path::new("x"), "(n1, n2) and ζ (Figs. 7–8)").is_empty());
    assert_eq!(bad_references(Path::new("x"), "see Fig. 29").len(), 1);
}

#[test]
fn figure_table_follows_the_paper() {
    let candidates = [
        std::env::var_os("BEADCHAIN_PAPER").map(PathBuf::from),
        Some(root().join("../shared/paper-hertz-like-interfaces.tex")),
    ];
    let Some(tex) = candidates
        .into_iter()
        .flatten()
        .find_map(|p| std::fs::read_to_string(p).ok())
    else {
        eprintln!(
            "note: paper-hertz-like-interfaces.tex not found: the figure table is not checked"
        );
        return;
    };
    // every figure environment (figure and figure*, one counter) with its label, in order
    let mut labels = Vec::new();
    for env in tex.split("\\begin{figure").skip(1) {
        let body = &env[..env.find("\\end{figure").expect("closed figure")];
        let a = body.find("\\label{").expect("labelled figure") + 7;
        labels.push(body[a..a + body[a..].find('}').unwrap()].to_string());
    }
    assert_eq!(labels, FIGURES, "the paper's figures, in order");
}

/// The README's line count and the two set-up commands.
#[test]
fn readme_is_a_short_quick_start() {
    // before: 285 lines, with the benchmark history of every session
    let readme = std::fs::read_to_string(root().join("README.md")).expect("README.md");
    let n = readme.lines().count();
    assert!(n <= 150, "README.md has {n} lines (at most 150)");
    let ci = std::fs::read_to_string(root().join(".ci/run")).expect(".ci/run");
    for cmd in ["cargo run --release -- run striker", "cargo test --release"] {
        assert!(readme.contains(cmd), "README lacks `{cmd}`");
    }
    // .ci/run runs the same two (the main job through --manifest-path, from a scratch directory)
    assert!(
        ci.contains("cargo test --release"),
        ".ci/run lacks the test command"
    );
    assert!(ci.contains("-- run striker"), ".ci/run lacks the main job");
    assert!(
        readme.contains("docs/benchmarks.md"),
        "README lacks the benchmark link"
    );
    // a preset count, if stated, is the real one ("the 24 presets")
    let presets = beadchain::scene::presets::presets().len();
    let words: Vec<&str> = readme.split_whitespace().collect();
    for w in words.windows(2) {
        if w[1].trim_matches(|c: char| !c.is_alphanumeric()) == "presets" {
            if let Ok(k) = w[0].parse::<usize>() {
                assert_eq!(k, presets, "README: \"{} {}\"", w[0], w[1]);
            }
        }
    }
}
