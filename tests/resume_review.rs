//! Checkpoint and resume defects of review B (D1, D3–D7 and the minor one; D2 is an engine
//! defect, `tests/checkpoint_resume.rs::resume_until_the_checkpoint_frame_writes_it_once`):
//! a resumed file's header names the end time that ran, a failed final write keeps what a
//! resume needs, `run` and `resume` refuse before computing what the end would refuse or
//! what would destroy another run, and a checkpoint continues beside itself.

use beadchain::snapshot::ckpt::{read_checkpoint, write_checkpoint};
use beadchain::snapshot::{read_header, Snapshot};
use std::path::Path;
use std::process::{Child, Command, Output, Stdio};
use std::time::{Duration, Instant};

const BIN: &str = env!("CARGO_BIN_EXE_beadchain");

/// A dense run long enough to be interrupted (200 beads to t = 1e6).
const LONG: &str =
    "[chain]\nbeads = 200\n[initial]\nstriker = 1.0\n[run]\nuntil = 1e6\nengine = \"dense\"\n";

fn bc(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("start beadchain")
}

fn err(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).to_string()
}

/// Exit 2, one `beadchain: error:` line containing every needle.
fn assert_refused(o: &Output, needles: &[&str]) {
    let e = err(o);
    assert_eq!(o.status.code(), Some(2), "stderr: {e}");
    assert_eq!(e.trim_end().lines().count(), 1, "not one line: {e}");
    assert!(e.starts_with("beadchain: error: "), "{e}");
    for n in needles {
        assert!(e.contains(n), "message lacks {n:?}: {e}");
    }
}

/// Starts `run SCENE --out o.snap --checkpoint-every 1` in `dir` (scene text `text`) and waits
/// for its first checkpoint.
fn start_run(dir: &Path, text: &str) -> Child {
    std::fs::write(dir.join("s.toml"), text).expect("write scene");
    let child = Command::new(BIN)
        .args([
            "run",
            "s.toml",
            "--out",
            "o.snap",
            "--checkpoint-every",
            "1",
        ])
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let t0 = Instant::now();
    while !dir.join("o.snap.ckpt").exists() {
        assert!(t0.elapsed().as_secs() < 120, "no checkpoint after 120 s");
        std::thread::sleep(Duration::from_millis(10));
    }
    child
}

/// [`start_run`] of [`LONG`], stopped with SIGINT: the time of its checkpoint.
fn interrupted_run(dir: &Path) -> f64 {
    let child = start_run(dir, LONG);
    let st = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill -INT");
    assert!(st.success());
    let out = child.wait_with_output().expect("wait");
    assert_eq!(out.status.code(), Some(130), "{}", err(&out));
    read_checkpoint(&dir.join("o.snap.ckpt"))
        .expect("checkpoint")
        .engine
        .time()
}

fn temps(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .expect("list")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains(".tmp-"))
        .collect();
    v.sort();
    v
}

/// D3: after `resume --until T` the header still named the original end time (1e6 here,
/// while the frames ran to T): readers (`inspect`, Python's `scene`) showed the wrong run.
/// Now the finished file's header holds `run.until = T`, and the file reads back whole.
#[test]
fn resume_until_records_the_end_time_in_the_header() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    let t = interrupted_run(p);
    let end = t + 1.5;
    let o = bc(p, &["resume", "o.snap.ckpt", "--until", &format!("{end}")]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let h = read_header(&p.join("o.snap")).expect("header");
    assert_eq!(
        h.scene.run.until, end,
        "the header names the end time that ran"
    );
    let s = Snapshot::open(&p.join("o.snap")).expect("reads back");
    assert_eq!(s.frame_times().last().copied(), Some(end));
    assert_eq!(s.header().scene.run.until, end);
}

/// D1: a final write that failed (here the rename: a directory was put at the output path
/// during the run) removed the temporary output the kept checkpoint continues, so the run could
/// not be resumed. Now both are kept, the one-line error says how to resume, and once the
/// directory is gone `resume` finishes the run with the bytes of a run never disturbed.
#[test]
fn a_failed_final_write_keeps_the_checkpoint_and_its_output() {
    let text =
        "[chain]\nbeads = 200\n[initial]\nstriker = 1.0\n[run]\nuntil = 4000\nevery = 10\nengine = \"dense\"\n";
    let r = tempfile::tempdir().expect("tempdir");
    std::fs::write(r.path().join("s.toml"), text).expect("scene");
    let args = [
        "run",
        "s.toml",
        "--out",
        "o.snap",
        "--checkpoint-every",
        "1",
    ];
    let o = bc(r.path(), &args); // the same command line: the header records it
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let want = std::fs::read(r.path().join("o.snap")).expect("reference");
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    let child = start_run(p, text);
    std::fs::create_dir(p.join("o.snap")).expect("mkdir at the output path");
    let o = child.wait_with_output().expect("wait");
    assert_refused(&o, &["o.snap.ckpt", "is intact", "beadchain resume"]);
    assert_eq!(temps(p).len(), 1, "the temporary output is kept");
    read_checkpoint(&p.join("o.snap.ckpt")).expect("the checkpoint is kept");
    std::fs::remove_dir(p.join("o.snap")).expect("rmdir");
    let o = bc(p, &["resume", "o.snap.ckpt", "-q"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(std::fs::read(p.join("o.snap")).expect("output") == want);
    assert!(temps(p).is_empty() && !p.join("o.snap.ckpt").exists());
}

/// D1: `run --out DIR` computed the whole run and then failed at the rename ("Is a
/// directory"). Now it is refused before anything is computed or written.
#[test]
fn run_refuses_an_output_directory_before_computing() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    std::fs::create_dir(p.join("d.snap")).expect("mkdir");
    std::fs::write(p.join("s.toml"), LONG).expect("scene");
    let t0 = Instant::now();
    let o = bc(
        p,
        &[
            "run",
            "s.toml",
            "--out",
            "d.snap",
            "--checkpoint-every",
            "10",
        ],
    );
    assert_refused(&o, &["d.snap", "is a directory"]);
    assert!(t0.elapsed().as_secs() < 20, "refused before the run");
    assert!(!p.join("d.snap.ckpt").exists() && temps(p).is_empty());
}

/// D6: `run --checkpoint-every` into an output whose earlier run was interrupted replaced that
/// run's checkpoint with its own and removed it at its end: the earlier run was lost. Now it is
/// refused, naming the checkpoint; both the checkpoint and its temporary output stay.
#[test]
fn run_with_checkpoints_refuses_an_earlier_runs_checkpoint() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    interrupted_run(p);
    let ckpt = std::fs::read(p.join("o.snap.ckpt")).expect("checkpoint");
    let before = temps(p);
    let o = bc(
        p,
        &[
            "run",
            "striker",
            "--out",
            "o.snap",
            "--checkpoint-every",
            "1",
        ],
    );
    assert_refused(&o, &["o.snap.ckpt", "beadchain resume", "remove"]);
    assert_eq!(std::fs::read(p.join("o.snap.ckpt")).unwrap(), ckpt);
    assert_eq!(temps(p), before);
    assert!(!p.join("o.snap").exists());
}

/// D6, without `--checkpoint-every`: such a run goes on beside an earlier run's checkpoint
/// (and leaves it, with a note, when it finishes), but a SIGINT made it write its own
/// checkpoint over the earlier one. Now the stop fails the run (exit 2, one line naming the
/// checkpoint) and the earlier run's checkpoint and temporary output stay resumable.
#[test]
fn an_interrupted_run_without_checkpoints_keeps_an_earlier_runs_checkpoint() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    interrupted_run(p);
    let ckpt = std::fs::read(p.join("o.snap.ckpt")).expect("checkpoint");
    let before = temps(p);
    // a run of many seconds without checkpoints (`LONG` takes a fraction of a second)
    let big =
        "[chain]\nbeads = 2000\n[initial]\nstriker = 1.0\n[run]\nuntil = 1e6\nengine = \"dense\"\n";
    std::fs::write(p.join("big.toml"), big).expect("scene");
    let mut child = Command::new(BIN)
        .args(["run", "big.toml", "--out", "o.snap"])
        .current_dir(p)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let t0 = Instant::now();
    while temps(p).len() < 2 {
        assert!(
            t0.elapsed().as_secs() < 60,
            "the second run started no output"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    std::thread::sleep(Duration::from_millis(500)); // its signal handler is installed
    let st = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill -INT");
    assert!(st.success());
    let t1 = Instant::now();
    while child.try_wait().expect("wait").is_none() {
        if t1.elapsed().as_secs() > 60 {
            let _ = child.kill();
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    let o = child.wait_with_output().expect("wait");
    assert_refused(
        &o,
        &["o.snap.ckpt", "earlier interrupted run", "kept as it was"],
    );
    assert_eq!(std::fs::read(p.join("o.snap.ckpt")).unwrap(), ckpt);
    assert_eq!(temps(p), before);
}

/// D5: `resume` renamed its output over a symbolic link at the output path (which `run`
/// refuses), and over a directory only after computing. Now both are refused first, with the
/// link, the directory and the run left as they were.
#[test]
fn resume_refuses_a_symbolic_link_or_directory_at_the_output() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    interrupted_run(p);
    std::fs::write(p.join("target.txt"), "keep").expect("target");
    std::os::unix::fs::symlink("target.txt", p.join("o.snap")).expect("symlink");
    let o = bc(p, &["resume", "o.snap.ckpt", "--until", "1e9"]);
    assert_refused(&o, &["o.snap.ckpt", "symbolic link", "target.txt"]);
    let link = std::fs::symlink_metadata(p.join("o.snap")).expect("link");
    assert!(link.file_type().is_symlink(), "the link is kept");
    assert_eq!(std::fs::read(p.join("target.txt")).unwrap(), b"keep");
    std::fs::remove_file(p.join("o.snap")).expect("rm link");
    std::fs::create_dir(p.join("o.snap")).expect("mkdir");
    let o = bc(p, &["resume", "o.snap.ckpt", "--until", "1e9"]);
    assert_refused(&o, &["o.snap.ckpt", "is a directory"]);
    assert!(p.join("o.snap.ckpt").exists() && temps(p).len() == 1);
}

/// D4: `resume` of the checkpoint of a run still going wrote into the temporary file that run
/// was writing. Now it is refused while the process named in the temporary's name is alive,
/// and while another resume writes it (the temporary file's lock).
#[test]
fn resume_refuses_while_the_run_is_still_going() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    let mut child = start_run(p, LONG);
    let o = bc(p, &["resume", "o.snap.ckpt", "--until", "1e9"]);
    let pid = child.id().to_string();
    let _ = child.kill();
    let _ = child.wait();
    assert_refused(&o, &["o.snap.ckpt", "still going", &pid]);
    // A resume still going (the PID in the temporary's name is the dead run's): its lock.
    let temp = p.join(temps(p).pop().expect("temporary output"));
    let mut first = Command::new(BIN)
        .args(["resume", "o.snap.ckpt", "--until", "1e9", "-q"])
        .current_dir(p)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("spawn");
    let fds = format!("/proc/{}/fd", first.id());
    let holds = || {
        std::fs::read_dir(&fds)
            .map(|d| {
                d.flatten()
                    .any(|e| std::fs::read_link(e.path()).is_ok_and(|l| l == temp))
            })
            .unwrap_or(false)
    };
    let t0 = Instant::now();
    while !holds() && t0.elapsed().as_secs() < 60 {
        std::thread::sleep(Duration::from_millis(10));
    }
    let o = bc(p, &["resume", "o.snap.ckpt", "--until", "1e9"]);
    let _ = first.kill();
    let _ = first.wait();
    assert_refused(&o, &["o.snap", "another beadchain process is writing it"]);
}

/// D7: a checkpoint copied to another directory resumed into the original directory (its
/// recorded absolute paths). Now, without the temporary output beside it, it is refused; with
/// it (the run's directory copied whole), the run continues beside the copy, the original
/// directory untouched.
#[test]
fn a_copied_checkpoint_resumes_beside_itself_or_is_refused() {
    let a = tempfile::tempdir().expect("tempdir");
    let t = interrupted_run(a.path());
    let b = tempfile::tempdir().expect("tempdir");
    let (pa, pb) = (a.path(), b.path());
    std::fs::copy(pa.join("o.snap.ckpt"), pb.join("o.snap.ckpt")).expect("copy");
    let end = format!("{}", t + 1.0);
    let o = bc(pb, &["resume", "o.snap.ckpt", "--until", &end]);
    assert_refused(&o, &["o.snap.ckpt", "another directory", "not beside it"]);
    let temp = temps(pa).pop().expect("temporary output");
    std::fs::copy(pa.join(&temp), pb.join(&temp)).expect("copy temp");
    let o = bc(pb, &["resume", "o.snap.ckpt", "--until", &end]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(err(&o).contains("continuing into"), "{}", err(&o));
    assert!(pb.join("o.snap").is_file(), "output beside the copy");
    assert!(
        !pa.join("o.snap").exists(),
        "nothing written in the original"
    );
    assert_eq!(temps(pa), [temp], "the original run is untouched");
    assert!(pa.join("o.snap.ckpt").exists());
}

/// Minor: a resumed run that fails the same way every time (here its step budget is already
/// spent) said its checkpoint "can be resumed again". Now it says resuming fails the same way.
#[test]
fn a_deterministic_resume_failure_does_not_promise_another_resume() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    interrupted_run(p);
    let path = p.join("o.snap.ckpt");
    let mut ck = read_checkpoint(&path).expect("checkpoint");
    ck.config.max_steps = Some(1);
    write_checkpoint(&path, &ck).expect("rewrite");
    let o = bc(p, &["resume", "o.snap.ckpt", "--until", "1e9"]);
    assert_refused(&o, &["o.snap.ckpt", "fails the same way"]);
    assert!(!err(&o).contains("can be resumed again"), "{}", err(&o));
    assert!(path.exists() && temps(p).len() == 1, "kept as it was");
}
