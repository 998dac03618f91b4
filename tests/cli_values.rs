//! Command-line values: negative numbers reach the validator (its message, not the parser's
//! "unexpected argument"), and an rtol below what f64 can deliver gets a warning.

mod common;

use common::bc as beadchain;

/// Before: `--every -1` failed with "unexpected argument '-1' found"; `--until -5` likewise.
#[test]
fn negative_every_is_a_value_with_the_validators_error() {
    let d = tempfile::tempdir().expect("tempdir");
    for (flag, value, needle) in [
        ("--every", "-1", "every = -1 must be positive and finite"),
        ("--until", "-5", "until = -5 must be positive and finite"),
        ("--rtol", "-1e-8", "rtol = -0.00000001 must be in (0, 1)"),
    ] {
        let o = beadchain(
            d.path(),
            &["run", "striker", flag, value, "--out", "x.snap"],
        );
        let err = String::from_utf8_lossy(&o.stderr);
        println!("{flag} {value}: {err}");
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(needle), "{flag} {value}: {err}");
        assert!(!d.path().join("x.snap").exists(), "output written");
    }
}

#[test]
fn rtol_below_f64_reach_is_warned() {
    let d = tempfile::tempdir().expect("tempdir");
    let o = beadchain(
        d.path(),
        &[
            "run", "striker", "--rtol", "1e-15", "--until", "5", "--out", "x.snap",
        ],
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(
        err.contains("warning: rtol = 1e-15 is below what f64 arithmetic can deliver"),
        "{err}"
    );
}

/// The snapshot size estimate is printed before a run whose output is large (≥ 16 MiB): here
/// 10⁴ beads × 201 frames × 16 bytes ≈ 31 MiB (the estimate counts one frame of margin, as the
/// output limit does); a small run and `-q` print nothing.
#[test]
fn large_output_size_is_announced_before_the_run() {
    let d = tempfile::tempdir().expect("tempdir");
    std::fs::write(
        d.path().join("big.toml"),
        "[chain]\nbeads = 10000\n[initial]\nstriker = 1.0\n[run]\nuntil = 20.0\nevery = 0.1\n",
    )
    .expect("write");
    let o = beadchain(d.path(), &["run", "big.toml", "--out", "big.snap"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(
        err.contains("note: the snapshot will be about 31.4 MiB (202 frames of 10000 beads)"),
        "{err}"
    );
    let q = beadchain(d.path(), &["run", "big.toml", "--out", "q.snap", "-q"]);
    assert!(!String::from_utf8_lossy(&q.stderr).contains("note:"));
    let small = beadchain(d.path(), &["run", "striker", "--out", "s.snap"]);
    assert!(!String::from_utf8_lossy(&small.stderr).contains("note:"));
}

/// The run summary and the snapshot's notes say when closings happened at tolerance-level
/// speeds (before: silent), and name the option to tighten. Beads 600, 604, … 696 drift into
/// their neighbours at 2e-6: below `30·atol·V` = 9e-6 at `--atol 3e-7`, above it at the
/// default atol.
#[test]
fn slow_closings_are_reported_by_run_and_inspect() {
    let dir = tempfile::tempdir().expect("tempdir");
    let v: Vec<String> = (0..1000)
        .map(|k| {
            if (600..700).step_by(4).any(|j| j == k) {
                "2e-6"
            } else {
                "0.0"
            }
        })
        .map(String::from)
        .collect();
    let scene = format!(
        "[chain]\nbeads = 1000\nexponent = 2.5\nprefactor = 1.0\n\
         [initial]\nvelocity = [{}]\nstriker = 1.0\n[run]\nuntil = 866.446\n",
        v.join(", ")
    );
    std::fs::write(dir.path().join("s.toml"), scene).expect("write");
    let args = [
        "run", "s.toml", "--rtol", "3e-5", "--atol", "3e-7", "--out", "s.snap",
    ];
    let out = common::bc(dir.path(), &args);
    common::assert_ok(&out);
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .find(|l| l.starts_with("warning: "))
        .unwrap_or_else(|| panic!("no warning in\n{text}"));
    assert!(
        line.contains("closings at relative speeds below 30x"),
        "{line}"
    );
    assert!(line.contains("smaller atol"), "{line}");
    let inspect = common::bc(dir.path(), &["inspect", "s.snap"]);
    common::assert_ok(&inspect);
    let info = String::from_utf8_lossy(&inspect.stdout);
    assert!(
        info.contains("closings at relative speeds below 30x"),
        "{info}"
    );
    // At the default atol the drift closings are not counted as slow. (A shallow-collision
    // warning is printed: at rtol 3e-5, 188 collisions of this scene lose more than rtol of
    // their energy below the contact threshold.)
    let quiet = common::bc(
        dir.path(),
        &["run", "s.toml", "--rtol", "3e-5", "--out", "d.snap"],
    );
    common::assert_ok(&quiet);
    let text = String::from_utf8_lossy(&quiet.stdout);
    assert!(!text.contains("closings at relative speeds"), "{text}");
}

/// Before (issue 36): `accuracy` defaulted to atol = rtol/100 while `run` uses rtol/10⁴, so the
/// study's "hybrid auto 1e-8" row (707 steps on striker) was not what `run --rtol 1e-8` does
/// (920 steps). Now a row's atol and step count are the run's.
#[test]
fn accuracy_rows_use_the_atol_and_steps_of_run() {
    let d = tempfile::tempdir().expect("tempdir");
    let o = beadchain(
        d.path(),
        &[
            "accuracy",
            "striker",
            "--until",
            "20",
            "--engines",
            "hybrid",
            "--methods",
            "auto",
            "--rtols",
            "1e-6,1e-8",
            "--out",
            "acc",
            "-q",
        ],
    );
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let csv = std::fs::read_to_string(d.path().join("acc/accuracy.csv")).expect("csv");
    let header: Vec<&str> = csv.lines().next().expect("header").split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).expect(name);
    for rtol in ["1e-6", "1e-8"] {
        let row: Vec<&str> = csv
            .lines()
            .map(|l| l.split(',').collect::<Vec<_>>())
            .find(|r| r[0] == "hybrid" && r[1] == "auto" && r[2].parse() == rtol.parse::<f64>())
            .unwrap_or_else(|| panic!("no hybrid auto {rtol} row in\n{csv}"));
        let o = beadchain(
            d.path(),
            &[
                "run", "striker", "--until", "20", "--engine", "hybrid", "--method", "auto",
                "--rtol", rtol, "--out", "r.snap", "-q",
            ],
        );
        let out = String::from_utf8_lossy(&o.stdout);
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        // "striker: 100 beads, engine hybrid, method auto, rtol 1e-8, atol 1e-12"
        let atol: f64 = out
            .split("atol ")
            .nth(1)
            .and_then(|s| s.split_whitespace().next())
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("no atol in {out}"));
        // "t = 20 in 0.0100 s: 920 steps (3 rejected), ..."
        let steps: u64 = out
            .split(" steps (")
            .next()
            .and_then(|s| s.rsplit(' ').next())
            .and_then(|s| s.parse().ok())
            .unwrap_or_else(|| panic!("no steps in {out}"));
        let row_atol: f64 = row[col("atol")].parse().expect("atol");
        // the same number, written by two formatters: equal to 1e-12 relative
        assert!(
            (row_atol - atol).abs() <= 1e-12 * atol,
            "rtol {rtol}: atol {row_atol} vs run's {atol}"
        );
        assert_eq!(
            row[col("steps")],
            steps.to_string(),
            "rtol {rtol}: steps vs run's\n{out}"
        );
    }
}
