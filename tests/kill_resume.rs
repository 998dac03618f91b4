//! Kill `beadchain run` with SIGKILL at seeded random moments, resume from its checkpoint, and
//! compare the finished snapshot byte for byte with a run that was never interrupted (both
//! engines). Also SIGINT: the run writes a checkpoint, exits 130 and says how to resume.

use rand::{Rng, SeedableRng};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

const BIN: &str = env!("CARGO_BIN_EXE_beadchain");

fn scene(dir: &Path, engine: &str) {
    let (beads, until) = if engine == "dense" {
        (300, 250.0)
    } else {
        (6000, 5000.0)
    };
    std::fs::write(
        dir.join("s.toml"),
        format!(
            "[chain]\nbeads = {beads}\n[initial]\nstriker = 1.0\n[run]\nuntil = {until}\nevery = 5.0\nengine = \"{engine}\"\n"
        ),
    )
    .expect("write scene");
}

fn run_args() -> [&'static str; 6] {
    [
        "run",
        "s.toml",
        "--out",
        "o.snap",
        "--checkpoint-every",
        "10",
    ]
}

fn reference(dir: &Path) -> Vec<u8> {
    let st = Command::new(BIN)
        .args(run_args())
        .current_dir(dir)
        .stdout(Stdio::null())
        .status()
        .expect("runs");
    assert!(st.success());
    std::fs::read(dir.join("o.snap")).expect("reference output")
}

#[test]
fn kill_and_resume_gives_identical_bytes() {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2026);
    for engine in ["dense", "hybrid"] {
        let ref_dir = tempfile::tempdir().expect("tempdir");
        scene(ref_dir.path(), engine);
        let t0 = std::time::Instant::now();
        let want = reference(ref_dir.path());
        let full = t0.elapsed().as_secs_f64();
        let mut resumed = 0;
        for trial in 0..3 {
            let dir = tempfile::tempdir().expect("tempdir");
            scene(dir.path(), engine);
            let mut child = Command::new(BIN)
                .args(run_args())
                .current_dir(dir.path())
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .expect("spawns");
            let delay = full * (0.2 + 0.6 * rng.random::<f64>());
            std::thread::sleep(Duration::from_secs_f64(delay));
            let _ = child.kill(); // SIGKILL
            let _ = child.wait();
            let ckpt = dir.path().join("o.snap.ckpt");
            let resumes = ckpt.exists();
            if resumes {
                let st = Command::new(BIN)
                    .args(["resume", "o.snap.ckpt"])
                    .current_dir(dir.path())
                    .stdout(Stdio::null())
                    .status()
                    .expect("resume runs");
                assert!(st.success(), "{engine} trial {trial}: resume failed");
                resumed += 1;
                assert!(!ckpt.exists(), "the finished run removes its checkpoint");
            } else if !dir.path().join("o.snap").exists() {
                // killed before the first checkpoint: run again from the start
                reference(dir.path());
            }
            let got = std::fs::read(dir.path().join("o.snap")).expect("output");
            assert!(
                got == want,
                "{engine} trial {trial} (killed after {delay:.2} s): bytes differ"
            );
            let leftovers: Vec<_> = std::fs::read_dir(dir.path())
                .expect("list")
                .filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.contains(".tmp-") && !n.contains(".ckpt.tmp-"))
                .collect();
            // (a SIGKILL before the first checkpoint leaves the output's temporary file, and one
            // during a checkpoint write leaves that write's temporary: nothing can clean up
            // after SIGKILL. A resumed run reuses and renames the output's temporary.)
            if resumes {
                assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
            }
        }
        assert!(
            resumed >= 1,
            "{engine}: no trial was killed mid-run (runs too fast?)"
        );
    }
}

#[test]
fn sigint_writes_checkpoint_and_says_how_to_resume() {
    let dir = tempfile::tempdir().expect("tempdir");
    scene(dir.path(), "dense");
    let t0 = std::time::Instant::now();
    let want = reference(dir.path());
    let full = t0.elapsed().as_secs_f64();
    std::fs::remove_file(dir.path().join("o.snap")).expect("rm");
    let child = Command::new(BIN)
        .args(run_args())
        .current_dir(dir.path())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawns");
    std::thread::sleep(Duration::from_secs_f64(full * 0.4));
    let st = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill -INT");
    assert!(st.success());
    let out = child.wait_with_output().expect("waits");
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(130), "{err}");
    assert!(err.contains("beadchain resume o.snap.ckpt"), "{err}");
    let st = Command::new(BIN)
        .args(["resume", "o.snap.ckpt"])
        .current_dir(dir.path())
        .stdout(Stdio::null())
        .status()
        .expect("resumes");
    assert!(st.success());
    assert!(std::fs::read(dir.path().join("o.snap")).expect("output") == want);
}
