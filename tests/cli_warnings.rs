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
    let scene =
        "[chain]\nbeads = 4\nexponent = 1.5\n[initial]\nstriker = 1.0\n[run]\nuntil = 1.0\n";
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

/// 10 Table-1 steel beads (R = 4 mm, Y = 226 GPa, ρ = 7650 kg/m³) with `initial` as given.
fn steel(initial: &str, run: &str) -> String {
    format!(
        "[scene]\nname = \"steel\"\n[units]\nsystem = \"physical\"\nradius = 4e-3\nyoung = 2.26e11\npoisson = 0.3\ndensity = 7650.0\n[chain]\nbeads = 10\n[initial]\n{initial}\n[run]\n{run}\n"
    )
}

/// Runs `beadchain run` on a scene text (or `args` with a preset) and returns stderr's lines.
fn run_scene(text: &str, extra: &[&str]) -> Vec<String> {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("steel.toml"), text).expect("write");
    let mut args = vec!["run", "steel.toml", "--quiet"];
    args.extend_from_slice(extra);
    let o = bc(dir.path(), &args);
    assert_ok(&o);
    stderr_lines(&o)
}

/// The defect: `striker = 0.11` meant as m/s ran without a word at 0.11/β = 121 450 m/s.
#[test]
fn physical_scene_warns_on_a_striker_faster_than_sound() {
    let lines = run_scene(&steel("striker = 0.11", "until_si = 1e-5"), &[]);
    assert_eq!(lines.len(), 2, "{lines:?}");
    assert_eq!(
        lines[0],
        "beadchain: warning: steel: [initial].striker: bead 0 moves at 1.2145e5 m/s (0.11 computer units), faster than the sound speed sqrt(Y/ρ) = 5.4353e3 m/s of its material: plain velocities are computer units; for m/s write `striker_si = 0.11`"
    );
    assert!(
        lines[1].contains("would press contact 0 by 9.1801e-2 m"),
        "{lines:?}"
    );
    // The same speed given as m/s: no warning.
    let quiet = run_scene(&steel("striker_si = 0.11", "until_si = 1e-4"), &[]);
    assert!(quiet.is_empty(), "{quiet:?}");
}

/// Below the sound speed (3 312 m/s) but the collision would overlap the beads by more than a
/// radius: δ_max = (μ w²/(2a))^{1/n} = (0.5 · 0.003² / (2 · 1.18471))^0.4 m = 5.15 mm > 4 mm.
#[test]
fn physical_scene_warns_on_a_striker_overlap_larger_than_a_radius() {
    let lines = run_scene(&steel("striker = 0.003", "until_si = 1e-5"), &[]);
    assert_eq!(
        lines,
        vec!["beadchain: warning: steel: [initial].striker: bead 0 at 3.3123e3 m/s (0.003 computer units) would press contact 0 by 5.1455e-3 m, more than the bead radius 4.0000e-3 m: plain velocities are computer units; for m/s write `striker_si = 0.003`"]
    );
}

/// An initial displacement of 1 cm (lengths are metres) overlaps contact 0 by more than R.
#[test]
fn physical_scene_warns_on_an_initial_overlap_larger_than_a_radius() {
    let init = "striker_si = 0.1\ndisplacement = { base = 0.0, segments = [{ from = 0, to = 0, value = 0.01 }] }";
    let lines = run_scene(&steel(init, "until_si = 1e-7"), &[]);
    assert_eq!(lines.len(), 2, "{lines:?}");
    // the end time was given as `until_si`: the warning names that key, in seconds, without the
    // units advice (it named `[run].until` and advised `until_si`, which the scene uses)
    assert!(
        lines[1].ends_with(
            "[run].until_si: 1.0000e-7 s is shorter than one contact time of the fastest initial collision (3.6657e-5 s, contact 0)"
        ),
        "{lines:?}"
    );
    assert_eq!(
        lines[..1],
        ["beadchain: warning: steel: [initial].displacement: contact 0 (beads 0–1) starts overlapping by 1.0000e-2 m, more than the bead radius 4.0000e-3 m (lengths are metres; [chain].precompression counts too)"]
    );
}

/// The defect: `run hertz_spheres_physical --until 1e-3 --every 1e-4` meant as seconds ran
/// 0.9 ns ("events: none") without a word.
#[test]
fn until_in_a_physical_scene_warns_when_shorter_than_a_contact() {
    let dir = tempfile::tempdir().expect("tempdir");
    let args = [
        "run",
        "hertz_spheres_physical",
        "--quiet",
        "--until",
        "1e-3",
        "--every",
        "1e-4",
    ];
    let o = bc(dir.path(), &args);
    assert_ok(&o);
    assert_eq!(
        stderr_lines(&o),
        vec!["beadchain: warning: hertz_spheres_physical: --until: 0.001 (9.0572e-10 s) is shorter than one contact time of the fastest initial collision (3.9709e1 = 3.5965e-5 s, contact 0): plain times are computer units; for seconds use `until_si` or `--until-si`"]
    );
    let o = bc(
        dir.path(),
        &[
            "run",
            "hertz_spheres_physical",
            "--quiet",
            "--until-si",
            "1e-4",
        ],
    );
    assert_ok(&o);
    assert!(stderr_lines(&o).is_empty(), "{:?}", stderr_lines(&o));
    // Seconds too short: named as given, no advice on units (it advised `--until-si`).
    let args = [
        "run",
        "hertz_spheres_physical",
        "--quiet",
        "--until-si",
        "1e-6",
    ];
    let o = bc(dir.path(), &args);
    assert_ok(&o);
    assert_eq!(
        stderr_lines(&o),
        vec!["beadchain: warning: hertz_spheres_physical: --until-si: 1.0000e-6 s is shorter than one contact time of the fastest initial collision (3.5965e-5 s, contact 0)"]
    );
    // A dimensionless scene never gets these warnings (its units are the user's).
    let o = bc(
        dir.path(),
        &["run", "striker", "--quiet", "--until", "1e-3"],
    );
    assert_ok(&o);
    assert!(stderr_lines(&o).is_empty(), "{:?}", stderr_lines(&o));
}

/// `run --help` says the unit of `--until` and `--every`.
#[test]
fn run_help_says_until_and_every_are_computer_units() {
    let o = bc(std::path::Path::new("."), &["run", "--help"]);
    assert_ok(&o);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("End time, computer units; --until-si for seconds"),
        "{text}"
    );
    assert!(
        text.contains("Output interval, computer units; --every-si for seconds"),
        "{text}"
    );
}

/// The number after `marker` in `text` (up to the next space or comma).
fn number_after(text: &str, marker: &str) -> f64 {
    let rest = &text[text
        .find(marker)
        .unwrap_or_else(|| panic!("{marker:?} in {text}"))
        + marker.len()..];
    let end = rest.find([' ', ',', ')']).unwrap_or(rest.len());
    rest[..end]
        .parse()
        .unwrap_or_else(|e| panic!("{marker:?}: {e}: {rest}"))
}

/// `run`, `inspect` and `analyze` print a physical scene's time and energy in SI beside the
/// computer units: t = 1e-4 s and E = ½ m v² of the 0.11 m/s striker (m = ρ 4/3 π R³).
#[test]
fn physical_run_inspect_and_analyze_print_si_time_and_energy() {
    let dir = tempfile::tempdir().expect("tempdir");
    let m = 7650.0 * 4.0 / 3.0 * std::f64::consts::PI * 4e-3_f64.powi(3);
    let e_si = 0.5 * m * 0.11 * 0.11;
    let close = |x: f64, want: f64, what: &str| {
        assert!(
            (x - want).abs() <= 1e-6 * want,
            "{what}: {x} vs {want} (rel 1e-6)"
        );
    };
    let o = bc(
        dir.path(),
        &[
            "run",
            "hertz_spheres_physical",
            "--quiet",
            "--until-si",
            "1e-4",
            "--out",
            "h.snap",
        ],
    );
    assert_ok(&o);
    let run = String::from_utf8_lossy(&o.stdout).to_string();
    close(number_after(&run, "in SI: t = "), 1e-4, "run t");
    close(number_after(&run, "s, energy "), e_si, "run E0");
    let o = bc(dir.path(), &["inspect", "h.snap"]);
    assert_ok(&o);
    let ins = String::from_utf8_lossy(&o.stdout).to_string();
    close(number_after(&ins, "s .. "), 1e-4, "inspect t");
    let energy_line = &ins[ins.find("energy:").expect("energy line")..];
    close(number_after(energy_line, "(SI: "), e_si, "inspect E0");
    let o = bc(dir.path(), &["analyze", "h.snap"]);
    assert_ok(&o);
    let an = String::from_utf8_lossy(&o.stdout).to_string();
    close(number_after(&an, " s to "), 1e-4, "analyze t");
    close(number_after(&an, "energy initial "), e_si, "analyze E0");
}

/// The collision estimate of the warnings: n = 2 is a harmonic half period, t_c = π δ_max / w
/// with δ_max = w sqrt(μ/(2a)); n = 2.5 against a quadrature of ∫₀¹ dx/√(1−xⁿ).
#[test]
fn collision_time_matches_the_closed_form_and_a_quadrature() {
    use beadchain::model::collision::collision;
    let (mu, w, a) = (0.5, 0.3, 1.7);
    let (d, tc) = collision(mu, w, 2.0, a);
    let d2 = w * (mu / (2.0 * a)).sqrt();
    assert!((d - d2).abs() <= 1e-14 * d2, "δ {d} vs {d2} (rel 1e-14)");
    let t2 = std::f64::consts::PI * d2 / w;
    assert!(
        (tc - t2).abs() <= 1e-13 * t2,
        "t_c {tc} vs {t2} (rel 1e-13)"
    );
    // x = 1 − y²: ∫₀¹ 2y/√(1−(1−y²)ⁿ) dy, smooth (2/√n at y = 0); Simpson, 4000 intervals.
    let n: f64 = 2.5;
    let f = |y: f64| {
        if y == 0.0 {
            2.0 / n.sqrt()
        } else {
            2.0 * y / (1.0 - (1.0 - y * y).powf(n)).sqrt()
        }
    };
    let k = 4000;
    let h = 1.0 / k as f64;
    let s: f64 = (0..=k)
        .map(|i| {
            let c = if i == 0 || i == k {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            c * f(i as f64 * h)
        })
        .sum::<f64>()
        * h
        / 3.0;
    let (d, tc) = collision(mu, w, n, a);
    let want = 2.0 * d / w * s;
    assert!(
        (tc - want).abs() <= 1e-9 * want,
        "t_c {tc} vs quadrature {want} (rel 1e-9)"
    );
}

/// No preset, run as written, trips a plausibility warning (they would be false alarms).
#[test]
fn presets_run_as_written_give_no_plausibility_warning() {
    use beadchain::scene::{plausible, presets};
    for p in presets::presets() {
        let (s, m) = presets::preset_with_material(p.name).expect("preset");
        let w = plausible::warnings(&s, m.as_ref(), s.run.until, "[run].until");
        assert!(w.is_empty(), "{}: {w:?}", p.name);
    }
}

/// Before (issue 36): `[run] every = 5` with `until = 2` warned, `--every 5` did not. Now the
/// option gets the key's warning, named; the scene's own values still warn once, and a
/// `--until` below the scene's `every` (a quick look at a preset) is not warned about.
#[test]
fn every_option_past_until_warns_like_the_toml_key() {
    let dir = tempfile::tempdir().expect("tempdir");
    let base = "[chain]\nbeads = 4\n[initial]\nstriker = 1.0\n[run]\nuntil = 2.0\n";
    std::fs::write(dir.path().join("t.toml"), base).expect("write");
    std::fs::write(dir.path().join("e.toml"), format!("{base}every = 1.5\n")).expect("write");
    std::fs::write(dir.path().join("k.toml"), format!("{base}every = 5\n")).expect("write");
    let run = |args: &[&str]| {
        let o = bc(dir.path(), args);
        assert_ok(&o);
        stderr_lines(&o)
    };
    assert_eq!(
        run(&["run", "k.toml", "-q", "--out", "k.snap"]),
        ["beadchain: warning: k: [run].every: 5 > until 2: only the first and last frame"]
    );
    assert_eq!(
        run(&["run", "t.toml", "-q", "--out", "t.snap", "--every", "5"]),
        ["beadchain: warning: t: --every: 5 > until 2: only the first and last frame"]
    );
    assert_eq!(
        run(&["run", "e.toml", "-q", "--out", "e.snap", "--until", "1", "--every", "3"]),
        ["beadchain: warning: e: --every: 3 > --until 1: only the first and last frame"]
    );
    assert!(run(&["run", "e.toml", "-q", "--out", "f.snap", "--until", "1"]).is_empty());
    assert!(run(&["run", "t.toml", "-q", "--out", "u.snap", "--every", "0.5"]).is_empty());
}

/// The defect: the frame-cap and output-size refusals of `run` named the end time
/// `[run].until` with its value in computer units, also when it was given in seconds
/// (`[run].until_si`, `--until-si`): a key the scene does not have and a value the user never
/// wrote. They name the key or option given, with the value as given (seconds) and in computer
/// units (the unit of `every` and of the `--every` they suggest).
#[test]
fn end_time_in_seconds_is_named_as_given_in_frame_cap_and_output_size_errors() {
    let dir = tempfile::tempdir().expect("tempdir");
    // until_si = 1e-4 s is 110.409… computer units for these beads
    let scene = steel("striker_si = 0.11", "until_si = 1e-4\nevery_si = 1e-6");
    std::fs::write(dir.path().join("steel.toml"), scene).expect("write");
    let cases: [(&[&str], &str); 4] = [
        (
            &["--frames-max", "3"],
            "frames ([run].until_si = 1.0000e-4 s = 110.4",
        ),
        (
            &["--frames-max", "3", "--until-si", "2e-4"],
            "frames (--until-si = 2.0000e-4 s = 220.8",
        ),
        (
            &["--max-output-bytes", "1000"],
            ": [run].until_si = 1.0000e-4 s = 110.4",
        ),
        (
            &["--max-output-bytes", "1000", "--until-si", "2e-4"],
            "lower --until-si, or pass",
        ),
    ];
    for (extra, want) in cases {
        let e = refused_run_of_steel(dir.path(), extra, want);
        assert!(
            !e.contains("[run].until ") && !e.contains("[run].until="),
            "{e}"
        );
        let files = std::fs::read_dir(dir.path()).expect("dir").count();
        assert_eq!(files, 1, "nothing written beside the scene");
    }
}

/// The defect: a command-line option the engine refuses (`--rtol 0`, `--until 0`, `--engine
/// dense` on hard contacts) was reported under the scene's `[scene].name`, not the file the
/// command named, unlike every other error of `run` and `check`.
#[test]
fn refused_run_options_name_the_scene_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = "[scene]\nname = \"other\"\n[chain]\nbeads = 4\n[initial]\nstriker = 1.0\n[run]\nuntil = 2.0\n";
    std::fs::write(dir.path().join("s.toml"), scene).expect("write");
    for (cmd, opt, want) in [
        (
            "run",
            "--rtol=0",
            "s.toml: invalid run configuration: rtol = 0 must be in (0, 1)",
        ),
        (
            "run",
            "--until=0",
            "s.toml: invalid run configuration: until = 0 must be positive and finite",
        ),
        (
            "check",
            "--rtol=2",
            "s.toml: invalid run configuration: rtol = 2 must be in (0, 1)",
        ),
    ] {
        let o = bc(dir.path(), &[cmd, "s.toml", opt]);
        assert_eq!(o.status.code(), Some(2), "{cmd} {opt}");
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(e, format!("beadchain: error: {want}\n"), "{cmd} {opt}");
        assert_eq!(
            std::fs::read_dir(dir.path()).expect("dir").count(),
            1,
            "nothing written"
        );
    }
}

/// The defect: a scene file whose own `[run]` chose an engine or method that cannot run it
/// (`engine = "dense"` with hard contacts, `method = "verlet"` with damped contacts) was refused
/// under its `[scene].name`, advising `--engine hybrid` also for a method. It names the file
/// and the key now; the command line still overrides the key (a review of a first fix, which
/// refused such scenes while reading them, found `--engine hybrid` refused too).
#[test]
fn scenes_own_run_engine_or_method_that_cannot_run_it_is_named_and_overridable() {
    let dir = tempfile::tempdir().expect("tempdir");
    let hard = "[scene]\nname = \"other\"\n[chain]\nbeads = 5\n[hard]\ncontacts = \"all\"\n[initial]\nstriker = 1.0\n[run]\nuntil = 5.0\nengine = \"dense\"\n";
    let damped = "[chain]\nbeads = 5\nlaw = \"viscoelastic\"\nrestitution = 0.9\nimpact_speed = 1.0\n[initial]\nstriker = 1.0\n[run]\nuntil = 5.0\nmethod = \"verlet\"\n";
    std::fs::write(dir.path().join("hd.toml"), hard).expect("write");
    std::fs::write(dir.path().join("vd.toml"), damped).expect("write");
    for (file, want) in [
        ("hd.toml", "hd.toml: [run].engine: \"dense\" cannot run this scene: it declares hard contacts or walls, which only the hybrid engine handles (set engine = \"hybrid\" or pass --engine hybrid)"),
        ("vd.toml", "vd.toml: [run].method: \"verlet\" does not integrate velocity-dependent (damped) contacts; set method = \"auto\", \"dop853\" or \"radau5\", or pass --method"),
    ] {
        let o = bc(dir.path(), &["run", file]);
        assert_eq!(o.status.code(), Some(2), "{file}");
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(e, format!("beadchain: error: {want}\n"), "{file}");
        assert_eq!(std::fs::read_dir(dir.path()).expect("dir").count(), 2, "nothing written");
    }
    for args in [
        &[
            "run", "hd.toml", "--engine", "hybrid", "--out", "h.snap", "--quiet",
        ][..],
        &[
            "run", "vd.toml", "--method", "dop853", "--out", "v.snap", "--quiet",
        ][..],
        &["scene", "show", "vd.toml"][..],
    ] {
        let o = bc(dir.path(), args);
        assert_ok(&o);
    }
    // an option the engine refuses still names the option's value, under the file
    let o = bc(dir.path(), &["run", "vd.toml", "--method", "verlet"]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        e.starts_with("beadchain: error: vd.toml: invalid run configuration: method verlet"),
        "{e}"
    );
}

/// The defect: `--until-si -1` was converted first and refused as `until = -1104091.3… must be
/// positive and finite` (computer units, under a key the command line did not use), after a
/// warning that the run is shorter than one contact. The option is checked as given.
#[test]
fn non_positive_si_times_on_the_command_line_are_refused_as_given() {
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = steel("striker_si = 0.11", "until_si = 1e-4");
    std::fs::write(dir.path().join("steel.toml"), scene).expect("write");
    for (opt, x) in [
        ("--until-si", "-1"),
        ("--every-si", "0"),
        ("--until-si", "nan"),
    ] {
        let o = bc(dir.path(), &["run", "steel.toml", &format!("{opt}={x}")]);
        assert_eq!(o.status.code(), Some(2), "{opt}");
        let e = String::from_utf8_lossy(&o.stderr);
        let x = if x == "nan" { "NaN" } else { x };
        assert_eq!(
            e,
            format!("beadchain: error: {opt}: must be a finite number > 0 (seconds), got {x}\n")
        );
    }
}

/// The defect: the output-size refusal always named `[run].every` and advised "raise
/// [run].every (or --every)", also when the interval came from `--every`, `--every-si` or
/// `[run].every_si`, with its value in computer units; the frame-cap refusal likewise showed an
/// interval given in seconds in computer units. Both name the interval as given now.
#[test]
fn output_interval_is_named_as_given_in_output_size_and_frame_cap_errors() {
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = steel("striker_si = 0.11", "until_si = 1e-4\nevery_si = 1e-6");
    std::fs::write(dir.path().join("steel.toml"), scene).expect("write");
    let size = ["--max-output-bytes", "1000"];
    let cases: [(&[&str], &str); 4] = [
        (
            &size,
            "steel.toml: [run].every_si: the output would be about ",
        ),
        (&size, "every = 1.0000e-6 s = 1.10409"),
        (
            &size,
            "raise [run].every_si (or --every-si), lower [run].until_si",
        ),
        (
            &["--max-output-bytes", "1000", "--every", "2"],
            "steel.toml: --every: the output would be about ",
        ),
    ];
    for (extra, want) in cases {
        refused_run_of_steel(dir.path(), extra, want);
    }
    let o = bc(
        dir.path(),
        &[
            "run",
            "steel.toml",
            "--frames-max",
            "3",
            "--every-si",
            "2e-6",
        ],
    );
    let e = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(e.contains(", every = 2.0000e-6 s = 2.208"), "{e}");
    assert_eq!(
        std::fs::read_dir(dir.path()).expect("dir").count(),
        1,
        "nothing written"
    );
}

/// `run steel.toml --quiet EXTRA` in `dir`: refused (exit 2) with one line holding `want`.
fn refused_run_of_steel(dir: &std::path::Path, extra: &[&str], want: &str) -> String {
    let mut args = vec!["run", "steel.toml", "--quiet"];
    args.extend_from_slice(extra);
    let o = bc(dir, &args);
    assert_eq!(o.status.code(), Some(2), "{extra:?}");
    let e = String::from_utf8_lossy(&o.stderr).to_string();
    assert!(e.contains(want) && e.lines().count() == 1, "{extra:?}: {e}");
    e
}
