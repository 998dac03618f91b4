//! Warnings of the `beadchain` binary on standard error (issue 32): each one line, naming the
//! scene once, the key, and (physical scenes) the value in SI with the key or option to use.

mod common;

use common::{assert_ok, bc};

fn stderr_lines(o: &std::process::Output) -> Vec<String> {
    String::from_utf8_lossy(&o.stderr)
        .lines()
        .map(str::to_string)
        .collect()
}

/// The defect: a scene with `exponent = 1.5` warned `beadchain: warning: n15: n15:
/// [chain].exponent: …`, the scene named twice (the CLI prefixed the name the validator's
/// message already starts with).
#[test]
fn exponent_warning_names_the_scene_once() {
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = "[chain]\nbeads = 4\nexponent = 1.5\n[initial]\nstriker = 1.0\n[run]\nuntil = 1.0\n";
    std::fs::write(dir.path().join("n15.toml"), scene).expect("write");
    let o = bc(dir.path(), &["run", "n15.toml", "--quiet"]);
    assert_ok(&o);
    let lines = stderr_lines(&o);
    assert_eq!(
        lines,
        vec!["beadchain: warning: n15: [chain].exponent: contact 0, 1, 2: exponent < 2 (e.g. 1.5): force not C¹ at contact (steps shrink there)"],
        "stderr"
    );
}
