//! What the command line says (issue 36): when it is used wrongly (item 7), the parser's whole
//! message (missing arguments by name, the valid values, "did you mean", the usage line), the
//! command list for a bare `beadchain`, and the nearest preset name for a misspelled one; and
//! `inspect` of a run without `--timing` (item 11).
//!
//! Before: main.rs kept only the first line of clap's message, so `beadchain` printed the
//! description line, `run` "the following required arguments were not provided:" without
//! them, and `--method rk45`, `plot spacetim`, `--evry` got neither values nor tips; a
//! misspelled preset listed all presets.

mod common;

use common::bc;
use std::path::Path;
use std::process::Output;

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

/// Exit 2, first line `beadchain: error: …` holding `first`, and every needle somewhere in the
/// message; nothing on standard output, no file written.
fn usage_error(args: &[&str], first: &str, needles: &[&str]) -> String {
    let d = tempfile::tempdir().expect("tempdir");
    let o = bc(d.path(), args);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
    assert!(o.stdout.is_empty(), "{args:?}: stdout not empty");
    assert!(!e.contains("panicked"), "{args:?}: {e}");
    let line = e.lines().next().unwrap_or_default();
    assert!(line.starts_with("beadchain: error: "), "{args:?}: {e}");
    assert!(
        line.contains(first),
        "{args:?}: first line lacks {first:?}: {e}"
    );
    for n in needles {
        assert!(e.contains(n), "{args:?}: message lacks {n:?}: {e}");
    }
    assert_eq!(std::fs::read_dir(d.path()).unwrap().count(), 0, "{args:?}");
    e
}

#[test]
fn bare_beadchain_prints_the_command_list() {
    let o = bc(Path::new("."), &[]);
    let e = stderr(&o);
    // clap's convention for a missing subcommand: the help on stderr, usage-error exit code
    assert_eq!(o.status.code(), Some(2), "{e}");
    for n in [
        "Usage: beadchain",
        "Commands:",
        "run",
        "plot",
        "analyze",
        "--help",
    ] {
        assert!(e.contains(n), "lacks {n:?}: {e}");
    }
    assert!(!e.contains("error:"), "{e}");
    // the same for a command group without its subcommand
    let o = bc(Path::new("."), &["plot"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    for n in ["spacetime", "trace", "energy"] {
        assert!(e.contains(n), "plot: lacks {n:?}: {e}");
    }
}

#[test]
fn missing_required_argument_is_named() {
    usage_error(
        &["run"],
        "the following required arguments were not provided",
        &["<SCENE>", "Usage: beadchain run"],
    );
}

#[test]
fn invalid_method_lists_the_valid_methods() {
    usage_error(
        &["run", "striker", "--method", "rk45"],
        "invalid value 'rk45' for '--method <METHOD>'",
        &["[possible values: auto, radau5, dop853, verlet]"],
    );
}

#[test]
fn misspelled_subcommand_and_option_get_did_you_mean() {
    usage_error(
        &["plot", "spacetim"],
        "unrecognized subcommand 'spacetim'",
        &["similar subcommand exists: 'spacetime'"],
    );
    usage_error(
        &["run", "striker", "--evry", "10"],
        "unexpected argument '--evry'",
        &["similar argument exists: '--every'", "Usage:"],
    );
}

#[test]
fn misspelled_preset_suggests_the_nearest_name() {
    let d = tempfile::tempdir().expect("tempdir");
    for (spec, want) in [
        ("strikr", "did you mean `striker`?"),
        ("two_striker", "did you mean `two_strikers`?"),
        ("interface_3.0_3.6", "did you mean `interface_3.0_3.5`?"),
        ("gapped", "did you mean `gapped_chain`?"),
    ] {
        let o = bc(d.path(), &["run", spec]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{spec}: {e}");
        assert_eq!(e.trim_end().lines().count(), 1, "{spec}: {e}");
        assert!(
            e.starts_with(&format!(
                "beadchain: error: {spec}: no such scene file, and no preset of that name"
            )),
            "{spec}: {e}"
        );
        assert!(e.contains(want), "{spec}: {e}");
        // the nearest name only, not the whole list
        assert!(
            !e.contains("granular_gas"),
            "{spec}: lists every preset: {e}"
        );
    }
    // nothing close: no guess, a pointer to the list
    let o = bc(d.path(), &["run", "nothere.toml"]);
    let e = stderr(&o);
    assert!(!e.contains("did you mean"), "{e}");
    assert!(e.contains("`beadchain scenes` lists the presets"), "{e}");
    // `accuracy` and `check` load scenes the same way
    let o = bc(d.path(), &["check", "strikr"]);
    assert!(
        stderr(&o).contains("did you mean `striker`?"),
        "{}",
        stderr(&o)
    );
}

/// Before (item 11): `inspect` of a run without `--timing` printed "wall 0.000 s" and then
/// "note: wall time not recorded".
#[test]
fn inspect_says_wall_time_not_recorded_once() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    let tiny = "[chain]\nbeads = 4\n[initial]\nstriker = 1.0\n[run]\nuntil = 2.0\n";
    std::fs::write(p.join("s.toml"), tiny).expect("write");
    for (args, timed) in [
        (&["run", "s.toml", "-q", "--out", "a.snap"][..], false),
        (
            &["run", "s.toml", "-q", "--out", "b.snap", "--timing"],
            true,
        ),
    ] {
        let o = bc(p, args);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let o = bc(p, &["inspect", args[4]]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        let out = String::from_utf8_lossy(&o.stdout);
        let run = out
            .lines()
            .find(|l| l.starts_with("run:"))
            .unwrap_or_else(|| panic!("no run line: {out}"));
        if timed {
            assert!(
                run.contains(", wall ") && run.contains(" s, energy"),
                "{run}"
            );
            assert!(!out.contains("not recorded"), "{out}");
        } else {
            assert!(
                run.contains(", wall time not recorded (see --timing),"),
                "{run}"
            );
            assert!(!out.contains("wall 0"), "{out}");
            // (and the date, on its own provenance line: tests/provenance.rs)
            let others: String = out.lines().filter(|l| !l.starts_with("created:")).collect();
            assert_eq!(others.matches("not recorded").count(), 1, "{out}");
        }
    }
}

/// Found by an adversarial review: `analyze --fit-from nan` exited 0; `validate --quick --out
/// FILE` ran every check for a minute, then failed with "File exists (os error 17)"; `plot
/// profile --times -1` named neither the file nor the option. Each is now one line, exit 2,
/// naming them, before any work.
#[test]
fn bad_options_are_named_before_the_work() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    let o = bc(p, &["run", "striker", "--out", "s.snap", "-q"]);
    assert_eq!(o.status.code(), Some(0));
    std::fs::write(p.join("f.md"), "").unwrap();
    let cases: [(&[&str], &str); 3] = [
        (
            &["analyze", "s.snap", "--fit-from", "nan"],
            "--fit-from NaN: expected a finite bead position",
        ),
        (
            &["validate", "--quick", "--out", "f.md"],
            "f.md: --out: is a file; give a directory",
        ),
        (
            &[
                "plot", "profile", "s.snap", "--times", "-1", "--out", "p.png",
            ],
            "s.snap: --times: time -1 is outside the run",
        ),
    ];
    for (args, want) in cases {
        let t0 = std::time::Instant::now();
        let o = bc(p, args);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
        assert!(e.contains(want), "{args:?}: {e}");
        assert!(
            t0.elapsed().as_secs_f64() < 5.0,
            "{args:?}: refused before the work"
        );
    }
    assert!(!p.join("p.png").exists());
}
