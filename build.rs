//! Embeds the git commit the crate is built from as `BEADCHAIN_BUILD_COMMIT` (read by
//! `src/provenance.rs`): `git rev-parse HEAD` (40 hex digits), with `-dirty` appended when a
//! tracked file differs from it (`git status --porcelain --untracked-files=no`); `unknown`
//! without git or a repository (a wheel built from an sdist copy). `BEADCHAIN_GIT_COMMIT` set at
//! build time overrides both. This script never fails the build: every error gives `unknown`.

use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-env-changed=BEADCHAIN_GIT_COMMIT");
    println!("cargo:rerun-if-changed=build.rs");
    let dir =
        std::env::var_os("CARGO_MANIFEST_DIR").map_or_else(|| PathBuf::from("."), PathBuf::from);
    let commit = match std::env::var("BEADCHAIN_GIT_COMMIT") {
        Ok(c) if !c.trim().is_empty() => clean(c.trim()),
        _ => from_git(&dir).unwrap_or_else(|| "unknown".to_string()),
    };
    println!("cargo:rustc-env=BEADCHAIN_BUILD_COMMIT={commit}");
}

/// Keeps a value printable on one line (it goes into file headers and `--version`).
fn clean(s: &str) -> String {
    s.chars()
        .filter(|c| c.is_ascii_graphic())
        .take(80)
        .collect()
}

/// Runs `git ARGS` in `dir`; its trimmed standard output on success.
fn git(dir: &Path, args: &[&str]) -> Option<String> {
    // No optional locks: `git status` must not rewrite the index (that would rerun this script,
    // and rebuild the crate, on every build).
    let out = Command::new("git")
        .args(args)
        .current_dir(dir)
        .env("GIT_OPTIONAL_LOCKS", "0")
        .output()
        .ok()?;
    if !out.status.success() {
        return None;
    }
    Some(String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// The commit of the repository holding `dir` (`-dirty` when tracked files changed), and the
/// `rerun-if-changed` lines that keep it current; `None` without git or a repository.
fn from_git(dir: &Path) -> Option<String> {
    let git_dir = git(dir, &["rev-parse", "--git-dir"])?;
    // Not a repository of its own (an sdist copy unpacked inside some other repository).
    git(dir, &["ls-files", "--error-unmatch", "Cargo.toml"])?;
    let git_dir = dir.join(git_dir);
    // A worktree's HEAD and index live in its own git dir; the branch refs in the common one.
    let common = git(dir, &["rev-parse", "--git-common-dir"]).map(|c| dir.join(c));
    for p in [git_dir.join("HEAD"), git_dir.join("index")] {
        if p.exists() {
            println!("cargo:rerun-if-changed={}", p.display());
        }
    }
    if let Some(c) = common {
        for p in [c.join("packed-refs"), c.join("refs/heads")] {
            if p.exists() {
                println!("cargo:rerun-if-changed={}", p.display());
            }
        }
    }
    // Edited sources make the build `-dirty` (the crate recompiles for them anyway).
    for p in ["src", "Cargo.toml", "Cargo.lock"] {
        println!("cargo:rerun-if-changed={}", dir.join(p).display());
    }
    let head = git(dir, &["rev-parse", "HEAD"])?;
    if head.len() != 40 || !head.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    let dirty =
        git(dir, &["status", "--porcelain", "--untracked-files=no"]).is_some_and(|s| !s.is_empty());
    Some(if dirty { format!("{head}-dirty") } else { head })
}
