//! Output files never destroy inputs or runs (issue 11, items 8–11 and 16): a rejected
//! `resume --until` keeps the run resumable, `resume` works from any directory, `--out` is never
//! an input, a symbolic link or renamed over a device, stale temporaries of dead runs are
//! removed, and a closed standard output ends the program quietly.

use std::path::Path;
use std::process::{Command, Output, Stdio};

const BIN: &str = env!("CARGO_BIN_EXE_beadchain");

/// 4 beads struck at v = 1, frames at t = 0, 0.5, 1, 1.5, 2 (5 frames).
const TINY: &str =
    "[chain]\nbeads = 4\n[initial]\nstriker = 1.0\n[run]\nuntil = 2.0\nevery = 0.5\n";

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
fn assert_refused(o: &Output, needles: &[&str]) -> String {
    let e = err(o);
    assert_eq!(o.status.code(), Some(2), "stderr: {e}");
    assert_eq!(e.trim_end().lines().count(), 1, "not one line: {e}");
    assert!(e.starts_with("beadchain: error: "), "{e}");
    for n in needles {
        assert!(e.contains(n), "message lacks {n:?}: {e}");
    }
    e.trim_end().to_string()
}

/// A dense run long enough to be interrupted (200 beads to t = 1e6, checkpoint every 1),
/// started in `dir` with `--out o.snap`; SIGINT once the first checkpoint exists. Returns the
/// time of the checkpoint written at the interrupt.
fn interrupted_run(dir: &Path) -> f64 {
    let long =
        "[chain]\nbeads = 200\n[initial]\nstriker = 1.0\n[run]\nuntil = 1e6\nengine = \"dense\"\n";
    interrupted_run_of(dir, long, &[])
}

/// [`interrupted_run`] of the scene `text` with `extra` arguments for `run`.
fn interrupted_run_of(dir: &Path, text: &str, extra: &[&str]) -> f64 {
    std::fs::write(dir.join("long.toml"), text).expect("write scene");
    let mut args = vec![
        "run",
        "long.toml",
        "--out",
        "o.snap",
        "--checkpoint-every",
        "1",
    ];
    args.extend_from_slice(extra);
    let child = Command::new(BIN)
        .args(&args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let ckpt = dir.join("o.snap.ckpt");
    let t0 = std::time::Instant::now();
    while !ckpt.exists() {
        assert!(t0.elapsed().as_secs() < 120, "no checkpoint after 120 s");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let st = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .expect("kill -INT");
    assert!(st.success());
    let out = child.wait_with_output().expect("wait");
    let e = err(&out);
    assert_eq!(out.status.code(), Some(130), "{e}");
    // "beadchain: interrupted at t = T: checkpoint written to ..."
    let t = e
        .split("interrupted at t = ")
        .nth(1)
        .and_then(|r| r.split(':').next())
        .and_then(|s| s.trim().parse::<f64>().ok())
        .unwrap_or_else(|| panic!("no interrupt time in {e:?}"));
    assert!(t > 0.0 && t.is_finite(), "{t}");
    t
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

/// A byte of the unfinished output damaged between the interruption and the resume: before,
/// `resume` carried it into the finished file, renamed it into place and exited 0, and every
/// reader then refused the file (an adversarial review). Now the sections up to the
/// checkpoint's mark are verified first: exit 2 naming the damaged section, no output.
#[test]
fn resume_refuses_a_damaged_unfinished_output() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    interrupted_run(p);
    let temp = p.join(&temps(p)[0]);
    let mut bytes = std::fs::read(&temp).unwrap();
    // magic (8), version (4), HEADER: tag u32, length u64, crc u32, payload; then a FRAME
    let header_len = u64::from_le_bytes(bytes[16..24].try_into().unwrap()) as usize;
    let k = 28 + header_len + 16 + 4;
    assert!(k < bytes.len(), "a frame after the header");
    bytes[k] ^= 0x40;
    std::fs::write(&temp, &bytes).unwrap();
    let o = bc(p, &["resume", "o.snap.ckpt"]);
    let e = err(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("checksum mismatch in section FRAME #0"), "{e}");
    assert!(!p.join("o.snap").exists(), "no output");
}

/// A finished run removed `OUT.ckpt` even when it was another, interrupted run's checkpoint
/// (an adversarial review): that run could no longer be resumed, and its temporary output
/// stayed behind. Now only a run's own checkpoint is removed; another's is named in a note.
#[test]
fn a_finished_run_keeps_another_runs_checkpoint() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    interrupted_run(p);
    let ckpt = std::fs::read(p.join("o.snap.ckpt")).unwrap();
    let o = bc(p, &["run", "striker", "--out", "o.snap", "-q"]);
    let e = err(&o);
    assert_eq!(o.status.code(), Some(0), "{e}");
    assert!(
        e.contains("o.snap.ckpt is the checkpoint of an earlier interrupted run"),
        "{e}"
    );
    assert_eq!(
        std::fs::read(p.join("o.snap.ckpt")).unwrap(),
        ckpt,
        "checkpoint kept"
    );
}

#[test]
fn rejected_resume_until_keeps_the_run_resumable() {
    let d = tempfile::tempdir().expect("tempdir");
    let t = interrupted_run(d.path());
    let before = temps(d.path());
    assert_eq!(before.len(), 1, "one temporary output: {before:?}");
    let below = format!("{}", t * 0.5);
    for bad in ["0", "nan", "inf", "-1", below.as_str()] {
        let o = bc(
            d.path(),
            &["resume", "o.snap.ckpt", &format!("--until={bad}")],
        );
        assert_refused(&o, &["o.snap.ckpt", "--until", "can still be resumed"]);
        assert_eq!(
            temps(d.path()),
            before,
            "--until {bad} touched the temporary"
        );
        assert!(d.path().join("o.snap.ckpt").exists());
    }
    // The run still continues: finish it shortly after the checkpoint.
    let end = format!("{}", t + 0.5);
    let o = bc(d.path(), &["resume", "o.snap.ckpt", "--until", &end]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let info = bc(d.path(), &["inspect", "o.snap"]);
    assert_eq!(info.status.code(), Some(0), "{}", err(&info));
    assert!(String::from_utf8_lossy(&info.stdout).contains("complete"));
    assert!(temps(d.path()).is_empty(), "{:?}", temps(d.path()));
}

/// The defect: `resume`'s frame-cap and output-size refusals advised `--every`, `--frames-max`
/// and `[run].every`, which `resume` does not take (the interval and the cap are the unfinished
/// output's), and named the original end time `[run].until` in computer units even when the
/// scene gave it in seconds.
#[test]
fn resume_refusals_advise_only_what_resume_can_change() {
    let d = tempfile::tempdir().expect("tempdir");
    let long =
        "[chain]\nbeads = 200\n[initial]\nstriker = 1.0\n[run]\nuntil = 1e6\nengine = \"dense\"\n";
    let caps = ["--every", "1000", "--frames-max", "1001"];
    interrupted_run_of(d.path(), long, &caps);
    let o = bc(d.path(), &["resume", "o.snap.ckpt", "--until", "2e6"]);
    let e = assert_refused(&o, &["o.snap.ckpt: --until: the run would write 2001 frames (--until = 2000000, every = 1000), more than the cap of 1001 frames its output was started with", "pass --until 1000000 or less", "can still be resumed"]);
    assert!(!e.contains("--every") && !e.contains("raise"), "{e}");
    let o = bc(
        d.path(),
        &["resume", "o.snap.ckpt", "--max-output-bytes", "100"],
    );
    let e = assert_refused(&o, &["the original run's end time = 1000000, every = 1000), above the limit of 100 bytes: pass an earlier --until, or --max-output-bytes N or --force"]);
    assert!(!e.contains("[run]") && !e.contains("--every"), "{e}");
    assert!(d.path().join("o.snap.ckpt").exists());
    // A physical scene's end time is shown in seconds too (the scene gave `until_si`).
    let d = tempfile::tempdir().expect("tempdir");
    let steel = "[units]\nsystem = \"physical\"\nradius = 4e-3\nyoung = 2.26e11\npoisson = 0.3\ndensity = 7650.0\n[chain]\nbeads = 200\n[initial]\nstriker = 0.01\n[run]\nuntil_si = 1.0\nengine = \"dense\"\n";
    interrupted_run_of(d.path(), steel, &[]);
    let o = bc(
        d.path(),
        &["resume", "o.snap.ckpt", "--max-output-bytes", "100"],
    );
    assert_refused(
        &o,
        &[
            "(3 frames of 200 beads: the original run's end time = 1.0000e0 s = 1104091.31",
            " computer units, every = none (first and last frame))",
        ],
    );
}

/// The defect: a tab in a file name was printed raw in error lines (the frame-cap, output-size
/// and output-is-an-input refusals, every snapshot reader), and a newline became a space, so
/// the line did not show the name as it is; `analyze` named a missing snapshot twice.
#[test]
fn error_lines_escape_control_characters_in_file_names() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    // named: a scene without a name takes its file's stem, which a tab makes no file name
    let named = format!("[scene]\nname = \"t\"\n{TINY}");
    std::fs::write(p.join("a\tb.toml"), named).expect("write scene");
    let cases: [&[&str]; 3] = [
        &["run", "a\tb.toml", "--frames-max", "3"],
        &["run", "a\tb.toml", "--max-output-bytes", "100"],
        &["run", "a\tb.toml", "--out", "a\tb.toml"],
    ];
    for args in cases {
        let e = assert_refused(&bc(p, args), &["beadchain: error: a\\tb.toml: "]);
        assert!(!e.contains('\t'), "{args:?}: {e}");
    }
    for cmd in ["analyze", "export", "inspect"] {
        let o = bc(p, &[cmd, "c\td.snap"]);
        let e = assert_refused(&o, &["beadchain: error: c\\td.snap: opening snapshot: "]);
        assert_eq!(e.matches("d.snap").count(), 1, "{cmd}: {e}");
    }
    assert_eq!(
        bc(p, &["run", "a\tb.toml", "--out", "o.snap"])
            .status
            .code(),
        Some(0)
    );
    let o = bc(p, &["export", "o.snap", "--out", "g\nh/x.csv"]);
    assert_refused(&o, &["g\\nh/x.csv"]);
}

#[test]
fn resume_works_from_another_working_directory() {
    let d = tempfile::tempdir().expect("tempdir");
    let t = interrupted_run(d.path());
    let elsewhere = tempfile::tempdir().expect("tempdir");
    let ckpt = d.path().join("o.snap.ckpt");
    let end = format!("{}", t + 0.5);
    let o = bc(
        elsewhere.path(),
        &["resume", ckpt.to_str().unwrap(), "--until", &end],
    );
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(
        d.path().join("o.snap").is_file(),
        "output not in the run's directory"
    );
    assert!(!ckpt.exists());
    assert!(
        std::fs::read_dir(elsewhere.path())
            .unwrap()
            .next()
            .is_none(),
        "files written into the other working directory"
    );
}

#[test]
fn out_equal_to_an_input_is_refused() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    let with_csv = TINY.replace("beads = 4\n", "beads = 4\nmass = { file = \"m.csv\" }\n");
    std::fs::write(p.join("s.toml"), TINY).unwrap();
    std::fs::write(p.join("c.toml"), with_csv).unwrap();
    std::fs::write(p.join("m.csv"), "1\n1\n1\n1\n").unwrap();
    std::fs::write(
        p.join("sw.toml"),
        "scene = \"s.toml\"\n[grid]\n\"chain.exponent\" = [2.5, 3.0]\n",
    )
    .unwrap();
    let o = bc(p, &["run", "s.toml", "--out", "o.snap"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let keep: Vec<(&str, Vec<u8>)> = ["s.toml", "c.toml", "m.csv", "sw.toml", "o.snap"]
        .iter()
        .map(|f| (*f, std::fs::read(p.join(f)).unwrap()))
        .collect();
    let cases: [(&[&str], &str); 6] = [
        (&["run", "s.toml", "--out", "s.toml"], "scene file"),
        (&["run", "s.toml", "--out", "./s.toml"], "scene file"),
        (&["run", "c.toml", "--out", "m.csv"], "CSV file"),
        (&["sweep", "sw.toml", "--out", "sw.toml"], "sweep file"),
        (&["sweep", "sw.toml", "--out", "s.toml"], "scene file"),
        (&["export", "o.snap", "--out", "o.snap"], "snapshot"),
    ];
    for (args, kind) in cases {
        let o = bc(p, args);
        let line = assert_refused(&o, &["--out", kind, "refusing to overwrite an input"]);
        println!("{} | {line}", args.join(" "));
    }
    for (f, bytes) in keep {
        assert_eq!(std::fs::read(p.join(f)).unwrap(), bytes, "{f} changed");
    }
    assert!(temps(p).is_empty(), "{:?}", temps(p));
}

/// `sweep` and `merge` write `OUT` and `OUT.meta`: before, only `OUT` was checked against
/// the inputs, so `merge a.csv.meta a.csv` replaced shard `a.csv`'s meta file by the merged
/// CSV, and a sweep whose base scene is `b.meta` run with `--out b` replaced the scene.
#[test]
fn out_meta_equal_to_an_input_is_refused() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    std::fs::write(p.join("b.meta"), TINY).unwrap();
    std::fs::write(
        p.join("sw.toml"),
        "scene = \"b.meta\"\n[grid]\n\"chain.exponent\" = [2.5, 3.0]\n",
    )
    .unwrap();
    std::fs::write(p.join("a.csv"), "run\n").unwrap();
    std::fs::write(p.join("a.csv.meta"), "spec\n").unwrap();
    let keep: Vec<(&str, Vec<u8>)> = ["b.meta", "sw.toml", "a.csv", "a.csv.meta"]
        .iter()
        .map(|f| (*f, std::fs::read(p.join(f)).unwrap()))
        .collect();
    let cases: [(&[&str], &[&str]); 2] = [
        (
            &["sweep", "sw.toml", "--out", "b"],
            &["--out", "scene file"],
        ),
        (&["merge", "a.csv.meta", "a.csv"], &["OUT", "meta file"]),
    ];
    for (args, needles) in cases {
        let o = bc(p, args);
        let mut needles = needles.to_vec();
        needles.push("refusing to overwrite an input");
        let line = assert_refused(&o, &needles);
        println!("{} | {line}", args.join(" "));
    }
    for (f, bytes) in keep {
        assert_eq!(std::fs::read(p.join(f)).unwrap(), bytes, "{f} changed");
    }
}

#[cfg(unix)]
#[test]
fn out_symlink_is_refused_not_replaced() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    std::fs::write(p.join("s.toml"), TINY).unwrap();
    std::fs::write(p.join("target.snap"), b"keep").unwrap();
    std::os::unix::fs::symlink("target.snap", p.join("link.snap")).unwrap();
    std::os::unix::fs::symlink("nowhere.snap", p.join("dangling.snap")).unwrap();
    for link in ["link.snap", "dangling.snap"] {
        let o = bc(p, &["run", "s.toml", "--out", link]);
        let line = assert_refused(&o, &[link, "is a symbolic link", "refusing to replace it"]);
        println!("{link} | {line}");
        let m = std::fs::symlink_metadata(p.join(link)).unwrap();
        assert!(m.file_type().is_symlink(), "{link} was replaced");
    }
    assert_eq!(std::fs::read(p.join("target.snap")).unwrap(), b"keep");
    assert!(!p.join("nowhere.snap").exists());
    assert!(temps(p).is_empty(), "{:?}", temps(p));
}

#[cfg(unix)]
#[test]
fn out_character_device_is_written_through() {
    use std::os::unix::fs::FileTypeExt;
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    std::fs::write(p.join("s.toml"), TINY).unwrap();
    // Before: the rename onto /dev/null failed (or, as root, replaced the device by a file).
    let o = bc(p, &["run", "s.toml", "--out", "/dev/null"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let m = std::fs::metadata("/dev/null").unwrap();
    assert!(
        m.file_type().is_char_device(),
        "/dev/null is no longer a device"
    );
    let o = bc(
        p,
        &[
            "run",
            "s.toml",
            "--out",
            "/dev/null",
            "--checkpoint-every",
            "1",
        ],
    );
    assert_refused(&o, &["--checkpoint-every", "stream"]);
    // A snapshot to /dev/stdout (a pipe here) is the whole file; the summary goes to stderr.
    let o = bc(p, &["run", "s.toml", "--out", "/dev/stdout"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(err(&o).contains("wrote /dev/stdout"), "{}", err(&o));
    std::fs::write(p.join("piped.snap"), &o.stdout).unwrap();
    let snap = beadchain::snapshot::Snapshot::open(&p.join("piped.snap")).expect("valid");
    assert!(snap.is_complete() && snap.warnings().is_empty());
    assert_eq!(snap.frame_count(), 5);
    // `export --out -` and a pipe behind /dev/stdout are the stream.
    let o = bc(p, &["run", "s.toml", "--out", "o.snap"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    let a = bc(p, &["export", "o.snap", "--out", "-"]);
    let b = bc(p, &["export", "o.snap"]);
    let c = bc(p, &["export", "o.snap", "--out", "/dev/stdout"]);
    assert_eq!(a.status.code(), Some(0), "{}", err(&a));
    assert_eq!(c.status.code(), Some(0), "{}", err(&c));
    assert_eq!(a.stdout, b.stdout);
    assert_eq!(c.stdout, b.stdout);
    // 4 provenance comment lines, the column header, 5 frames of 4 beads
    assert_eq!(
        b.stdout.iter().filter(|&&x| x == b'\n').count(),
        4 + 1 + 5 * 4
    );
    assert!(!p.join("-").exists());
    assert!(temps(p).is_empty(), "{:?}", temps(p));
}

#[test]
fn scene_name_with_a_path_is_refused() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path().join("w");
    std::fs::create_dir(&p).unwrap();
    for name in ["../x", "a/b", "..", "a\\\\b"] {
        let text = format!("[scene]\nname = \"{name}\"\n{TINY}");
        std::fs::write(p.join("s.toml"), text).unwrap();
        let o = bc(&p, &["run", "s.toml"]);
        let line = assert_refused(&o, &["s.toml", "[scene].name", "not a plain file name"]);
        println!("{name} | {line}");
    }
    assert!(
        !d.path().join("x.snap").exists(),
        "wrote outside the directory"
    );
    assert_eq!(std::fs::read_dir(&p).unwrap().count(), 1);
}

/// A newline in `[scene].name` split the warnings that carry the name and the exports' one-line
/// `# scene:` comment over two lines (the binary before accepted it and wrote a snapshot whose
/// file name holds the newline); a control character is refused like a path.
#[test]
fn scene_name_with_a_control_character_is_refused() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    for name in ["evil\\nname", "tab\\there", "bell\\u0007"] {
        let text = format!("[scene]\nname = \"{name}\"\n{TINY}");
        std::fs::write(p.join("s.toml"), text).unwrap();
        let o = bc(p, &["run", "s.toml"]);
        let line = assert_refused(&o, &["s.toml", "[scene].name", "not a plain file name"]);
        assert!(line.contains("control character"), "{line}");
    }
    assert_eq!(std::fs::read_dir(p).unwrap().count(), 1);
}

#[test]
fn stale_temp_of_a_dead_process_is_removed() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    std::fs::write(p.join("s.toml"), TINY).unwrap();
    // PIDs above 2^22 (the kernel's pid_max limit) cannot exist; this test process is alive.
    let dead = ".o.snap.tmp-4294967295-0";
    let live = format!(".o.snap.tmp-{}-3", std::process::id());
    let other = ".other.snap.tmp-4294967295-0";
    for f in [dead, live.as_str(), other] {
        std::fs::write(p.join(f), b"partial").unwrap();
    }
    let o = bc(p, &["run", "s.toml", "--out", "o.snap"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(!p.join(dead).exists(), "stale temporary kept");
    assert!(
        p.join(&live).exists(),
        "a live process's temporary was removed"
    );
    assert!(
        p.join(other).exists(),
        "another output's temporary was removed"
    );
    // export (write_atomically) cleans its own output's stale temporaries too
    std::fs::write(p.join(".x.csv.tmp-4294967295-1"), b"partial").unwrap();
    let o = bc(p, &["export", "o.snap", "--out", "x.csv"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(!p.join(".x.csv.tmp-4294967295-1").exists());
}

/// Before (issue 36, item 11): a later run removed a killed run's `.NAME.tmp-PID-K`
/// silently. Now each removal is a note on stderr naming the file and the process.
#[test]
fn stale_temp_removal_is_said() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    std::fs::write(p.join("s.toml"), TINY).unwrap();
    let dead = ".o.snap.tmp-4294967295-0";
    std::fs::write(p.join(dead), b"partial").unwrap();
    let o = bc(p, &["run", "s.toml", "--out", "o.snap", "-q"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(!p.join(dead).exists(), "stale temporary kept");
    let want = format!(
        "beadchain: note: removed ./{dead}, the partial output of an interrupted run (process 4294967295, no longer running)"
    );
    assert_eq!(err(&o).trim_end(), want);
    // nothing to remove: nothing said
    let o = bc(p, &["run", "s.toml", "--out", "o.snap", "-q"]);
    assert_eq!(err(&o), "");
    // export and plot say it too
    std::fs::write(p.join(".x.csv.tmp-4294967295-1"), b"partial").unwrap();
    let o = bc(p, &["export", "o.snap", "--out", "x.csv"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(
        err(&o).contains("removed ./.x.csv.tmp-4294967295-1"),
        "{}",
        err(&o)
    );
    std::fs::write(p.join(".e.svg.tmp-4294967295-2"), b"partial").unwrap();
    let o = bc(p, &["plot", "spacetime", "o.snap", "--out", "e.svg"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    assert!(
        err(&o).contains("removed ./.e.svg.tmp-4294967295-2"),
        "{}",
        err(&o)
    );
}

/// Runs `BIN args | true` with the program started 0.3 s after the reader (`true`) has exited,
/// so its first write meets a closed pipe, as with `| head` once head has what it wants.
/// Returns the program's exit code (bash `PIPESTATUS`) on stdout and its stderr.
fn closed_early(dir: &Path, args: &[&str]) -> Output {
    let script = format!(
        "{{ sleep 0.3; exec '{BIN}' {}; }} | true; echo ${{PIPESTATUS[0]}}",
        args.join(" ")
    );
    Command::new("bash")
        .args(["-c", &script])
        .current_dir(dir)
        .output()
        .expect("bash")
}

#[test]
fn closed_stdout_exits_quietly() {
    let d = tempfile::tempdir().expect("tempdir");
    let p = d.path();
    let big = "[chain]\nbeads = 200\n[initial]\nstriker = 1.0\n[run]\nuntil = 20.0\nevery = 0.5\n";
    std::fs::write(p.join("big.toml"), big).unwrap();
    let o = bc(p, &["run", "big.toml", "--out", "big.snap"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
    for args in [
        &["scenes"][..],
        &["export", "big.snap"][..],
        &["analyze", "big.snap", "--json"][..],
        &["inspect", "big.snap"][..],
    ] {
        // Before: exit 101 with a panic ("failed printing to stdout: Broken pipe"), or for
        // export exit 2 with "error: writing output: Broken pipe".
        let o = closed_early(p, args);
        let e = err(&o);
        let code = String::from_utf8_lossy(&o.stdout).trim().to_string();
        assert_eq!(code, "0", "{args:?}: exit {code}: {e}");
        assert!(e.is_empty(), "{args:?}: stderr {e:?}");
    }
}
