//! SI units on the command line (issue 13): `run --until-si/--every-si` take seconds for a
//! physical scene (divided by its time unit β, paper eq. 10), and `export --units si` writes
//! t·β (s), u (m), v/β (m/s), mass·m0 (kg), prefactor·m0/β² (J/mⁿ), event times and relative
//! velocities likewise. Dimensionless scenes refuse both with one line naming the option; nothing
//! is written.

mod common;

use beadchain::snapshot::Snapshot;
use common::npy::{parse_npy, parse_zip};
use common::{assert_ok, bc};
use std::process::Output;

fn stderr_line(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).trim().to_string()
}

fn refused(o: &Output, starts: &str) {
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(e.starts_with(starts), "{e}");
}

/// `|a − b| ≤ atol + rtol·|b|`.
fn close(a: f64, b: f64, atol: f64, rtol: f64) -> bool {
    (a - b).abs() <= atol + rtol * b.abs()
}

const UNTIL_SI: f64 = 1e-4;
const EVERY_SI: f64 = 2.5e-5;

/// The physical preset run to 1e-4 s with frames every 2.5e-5 s.
fn physical_run(d: &std::path::Path) -> Snapshot {
    let (until, every) = (UNTIL_SI.to_string(), EVERY_SI.to_string());
    let args = [
        "run",
        "hertz_spheres_physical",
        "--until-si",
        until.as_str(),
        "--every-si",
        every.as_str(),
        "--out",
        "p.snap",
        "-q",
    ];
    assert_ok(&bc(d, &args));
    Snapshot::open(&d.join("p.snap")).unwrap()
}

#[test]
fn until_si_and_every_si_are_seconds_of_a_physical_scene() {
    let d = tempfile::tempdir().unwrap();
    let snap = physical_run(d.path());
    let beta = snap.header().scene.units.expect("physical scene").time;
    assert!(close(beta, 9.057222e-7, 0.0, 1e-6), "beta {beta}");
    assert_eq!(snap.frame_count(), 5, "t = 0, 1/4, 1/2, 3/4, 1 × 1e-4 s");
    for k in 0..snap.frame_count() {
        let t = snap.frame(k).unwrap().t;
        let want = k as f64 * EVERY_SI / beta;
        assert!(close(t, want, 0.0, 1e-14), "frame {k}: t {t} vs {want}");
    }
    let last = snap.frame(4).unwrap().t;
    assert!(close(last, UNTIL_SI / beta, 0.0, 1e-15), "{last}");
}

/// The defect: `until_si = 5e-3` with `every_si = 2.5e-4` (20 intervals) wrote 22 frames, not
/// 21: after division by β, `20·every` fell one ulp short of `until`, so a frame was written
/// there and the last one an ulp later (a spurious zero-length interval in every per-frame
/// analysis). A `k·every` within a few ulps of `until` is now the last frame, and the size
/// estimate (`frame_count`) counts the same.
#[test]
fn a_whole_number_of_intervals_in_seconds_ends_on_one_last_frame() {
    use beadchain::engine::RunConfig;
    use beadchain::snapshot::size::frame_count;
    let d = tempfile::tempdir().unwrap();
    let args = [
        "run",
        "hertz_spheres_physical",
        "--until-si",
        "5e-3",
        "--every-si",
        "2.5e-4",
        "--out",
        "p.snap",
        "-q",
    ];
    assert_ok(&bc(d.path(), &args));
    let snap = Snapshot::open(&d.path().join("p.snap")).unwrap();
    let beta = snap.header().scene.units.expect("physical scene").time;
    let (until, every) = (5e-3 / beta, 2.5e-4 / beta);
    assert!(20.0 * every < until, "the case: 20·every is below until");
    assert_eq!(snap.frame_count(), 21);
    let t: Vec<f64> = (0..21).map(|k| snap.frame(k).unwrap().t).collect();
    assert_eq!(t[20], until);
    assert_eq!(t[19], 19.0 * every);
    assert_eq!(frame_count(until, Some(every)), 21.0);
    let mut cfg = RunConfig::from_scene(&snap.header().scene);
    (cfg.until, cfg.every) = (until, Some(every));
    assert_eq!(
        (cfg.frame_time(19), cfg.frame_time(20)),
        (19.0 * every, until)
    );
}

#[test]
fn until_si_on_a_dimensionless_scene_is_refused() {
    let d = tempfile::tempdir().unwrap();
    for option in ["--until-si", "--every-si"] {
        let o = bc(
            d.path(),
            &["run", "striker", option, "1", "--out", "s.snap"],
        );
        let want = format!(
            "beadchain: error: {option}: scene `striker` is dimensionless (computer units only)"
        );
        refused(&o, &want);
        let class = format!("{option} on a dimensionless scene");
        println!(
            "{class} | `beadchain run striker {option} 1` | {}",
            stderr_line(&o)
        );
    }
    let o = bc(
        d.path(),
        &["run", "striker", "--until-si", "1", "--until", "3"],
    );
    // a parser error: its first line, then clap's usage (issue 36: the whole message is kept)
    assert_eq!(o.status.code(), Some(2));
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.starts_with("beadchain: error: the argument '--until-si <UNTIL_SI>' cannot be used with '--until <UNTIL>'\n"), "{e}");
    assert!(e.contains("Usage: beadchain run"), "{e}");
    assert!(
        std::fs::read_dir(d.path()).unwrap().next().is_none(),
        "nothing written"
    );
}

#[test]
fn export_units_si_converts_frames_chain_and_events() {
    let d = tempfile::tempdir().unwrap();
    let snap = physical_run(d.path());
    let sc = snap.header().scene.units.unwrap();
    let (beta, m0) = (sc.time, sc.mass);
    for (out, units) in [("c.npz", "computer"), ("s.npz", "si")] {
        assert_ok(&bc(
            d.path(),
            &["export", "p.snap", "--out", out, "--units", units],
        ));
    }
    let c = parse_zip(&std::fs::read(d.path().join("c.npz")).unwrap());
    let s = parse_zip(&std::fs::read(d.path().join("s.npz")).unwrap());
    let arr = |z: &std::collections::BTreeMap<String, Vec<u8>>, k: &str| parse_npy(&z[k]).1;
    let chain = &snap.header().scene.chain;
    // Computer units: the snapshot's bits; SI: the documented factors, exactly as computed.
    for k in 0..snap.frame_count() {
        let f = snap.frame(k).unwrap();
        assert_eq!(arr(&c, "t.npy")[k].to_bits(), f.t.to_bits());
        assert_eq!(arr(&s, "t.npy")[k].to_bits(), (f.t * beta).to_bits());
        let n = f.v.len();
        for j in 0..n {
            assert_eq!(arr(&s, "u.npy")[k * n + j].to_bits(), f.u[j].to_bits());
            assert_eq!(
                arr(&s, "v.npy")[k * n + j].to_bits(),
                (f.v[j] / beta).to_bits()
            );
        }
    }
    // Hand-computed: t = 1e-4 s at the last frame; Table-1 bead mass 4/3·π·R³·ρ.
    let t_last = *arr(&s, "t.npy").last().unwrap();
    assert!(close(t_last, UNTIL_SI, 0.0, 1e-14), "{t_last}");
    let m_bead = 4.0 / 3.0 * std::f64::consts::PI * 0.004f64.powi(3) * 7650.0;
    for (m, mc) in arr(&s, "mass.npy").iter().zip(&chain.mass) {
        assert!(close(*m, m_bead, 0.0, 1e-12), "mass {m} kg vs {m_bead}");
        assert_eq!(m.to_bits(), (mc * m0).to_bits());
    }
    for (a, ac) in arr(&s, "prefactor.npy").iter().zip(&chain.prefactor) {
        assert_eq!(a.to_bits(), (ac * m0 / (beta * beta)).to_bits());
    }
    assert_eq!(arr(&s, "exponent.npy"), arr(&c, "exponent.npy"));
    // The event log: t and the relative velocity converted, the overlap a length.
    let ev = |units: &str| {
        let o = bc(
            d.path(),
            &["export", "p.snap", "--events", "--units", units],
        );
        assert_ok(&o);
        String::from_utf8(o.stdout).unwrap()
    };
    let (ec, es) = (ev("computer"), ev("si"));
    assert!(ec.lines().count() > 1, "the run logs events");
    let body = |t: &str| {
        t.lines()
            .filter(|l| !l.starts_with('#'))
            .skip(1)
            .map(String::from)
            .collect::<Vec<_>>()
    };
    for (lc, ls) in body(&ec).iter().zip(&body(&es)) {
        let c: Vec<&str> = lc.split(',').collect();
        let s: Vec<&str> = ls.split(',').collect();
        let num = |x: &str| x.parse::<f64>().unwrap();
        assert_eq!(num(s[0]).to_bits(), (num(c[0]) * beta).to_bits());
        assert_eq!(num(s[3]).to_bits(), (num(c[3]) / beta).to_bits());
        assert_eq!((s[1], s[2], s[4]), (c[1], c[2], c[4]));
    }
}

#[test]
fn export_units_si_of_a_dimensionless_scene_is_refused() {
    let d = tempfile::tempdir().unwrap();
    assert_ok(&bc(
        d.path(),
        &["run", "striker", "--out", "s.snap", "-q", "--until", "5"],
    ));
    let o = bc(
        d.path(),
        &["export", "s.snap", "--units", "si", "--out", "s.npz"],
    );
    refused(
        &o,
        "beadchain: error: s.snap: --units si: scene `striker` is dimensionless",
    );
    assert!(!d.path().join("s.npz").exists());
    println!(
        "export --units si of a dimensionless scene | `beadchain export s.snap --units si --out s.npz` | {}",
        String::from_utf8_lossy(&o.stderr).trim()
    );
}

/// The number after `key` on the line of `text` that contains `line`, up to the next space.
fn number_after(text: &str, line: &str, key: &str) -> f64 {
    let l = text
        .lines()
        .find(|l| l.contains(line))
        .unwrap_or_else(|| panic!("{text}"));
    let rest = l
        .split(key)
        .nth(1)
        .unwrap_or_else(|| panic!("{key} in {l}"));
    let x = rest.trim_start().split([' ', ',', ')']).next().unwrap();
    x.parse().unwrap_or_else(|_| panic!("{x} in {l}"))
}

/// The defect: `analyze` printed a physical scene's collision rate per bead and kinetic
/// temperature range, and `inspect` its dissipated energy, in computer units only, where the
/// docs promise SI beside them (scenes.md: "`run`, `inspect` and `analyze` print a physical
/// scene's times and energies in SI"). Each SI figure is now the computer figure times its
/// scale (rel 1e-6, the printed digits).
#[test]
fn analyze_and_inspect_give_every_rate_and_energy_in_si_too() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let gas = "[units]\nsystem = \"physical\"\nradius = 4.0e-3\nyoung = 2.26e11\npoisson = 0.3\n\
               density = 7650.0\n[chain]\nbeads = 12\nprecompression = -1.0e-4\n\
               [walls]\nleft = { precompression = -1.0e-4 }\nright = { precompression = -1.0e-4 }\n\
               [initial]\nvelocity_si = [0.3, -0.2, 0.5, -0.1, 0.0, 0.4, -0.3, 0.2, -0.5, 0.1, 0.25, -0.15]\n\
               [run]\nuntil_si = 5e-3\nevery_si = 5e-4\n";
    std::fs::write(d.join("gas.toml"), gas).unwrap();
    assert_ok(&bc(d, &["run", "gas.toml", "--out", "gas.snap", "-q"]));
    let snap = Snapshot::open(&d.join("gas.snap")).unwrap();
    let u = snap.header().scene.units.unwrap();
    let j = u.mass / (u.time * u.time);
    let o = bc(d, &["analyze", "gas.snap", "--gas"]);
    assert_ok(&o);
    let text = String::from_utf8_lossy(&o.stdout).to_string();
    let l = text
        .lines()
        .find(|l| l.starts_with("collisions ("))
        .unwrap();
    let pb: f64 = l
        .split(", ")
        .find(|p| p.contains("per bead"))
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let pb_si = number_after(l, "per bead", "per bead per unit time (SI:");
    assert!(close(pb_si, pb / u.time, 0.0, 1e-6), "{l}");
    let lo = number_after(&text, "kinetic temperature", "range ");
    let lo_si = number_after(&text, "kinetic temperature", &format!("range {lo:.6e} ("));
    assert!(close(lo_si, lo * j, 0.0, 1e-6), "{text}");
    let damped =
        "[units]\nsystem = \"physical\"\nradius = 4.0e-3\nyoung = 2.26e11\npoisson = 0.3\n\
                  density = 7650.0\n[chain]\nbeads = 2\nlaw = \"viscoelastic\"\nrestitution = 0.7\n\
                  impact_speed_si = 0.5\n[initial]\nstriker_si = 0.5\n[run]\nuntil_si = 1e-4\n\
                  every_si = 1e-5\n";
    std::fs::write(d.join("dm.toml"), damped).unwrap();
    assert_ok(&bc(d, &["run", "dm.toml", "--out", "dm.snap", "-q"]));
    let o = bc(d, &["inspect", "dm.snap"]);
    let text = String::from_utf8_lossy(&o.stdout).to_string();
    let e_d = number_after(&text, "dissipated:", "dissipated:");
    let e_d_si = number_after(&text, "dissipated:", "(SI:");
    // ½·(m/2)·w²·(1 − e²) for the striker at 0.5 m/s and e = 0.7 (rel 1e-6)
    let m = 4.0 / 3.0 * std::f64::consts::PI * 4.0e-3f64.powi(3) * 7650.0;
    assert!(
        close(e_d_si, 0.5 * (m / 2.0) * 0.25 * (1.0 - 0.49), 0.0, 1e-6),
        "{text}"
    );
    assert!(close(e_d_si, e_d * j, 0.0, 1e-6), "{text}");
}
