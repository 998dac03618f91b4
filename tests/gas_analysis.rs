//! `beadchain analyze` reports the collision rate from the event log and, for a gas (walls and
//! gaps) or with `--gas`, the kinetic temperature per frame and the velocity distribution
//! (issue 33). Every number is checked against one computed here, independently, from the
//! snapshot's frames and event log (read through the library's reader), with other formulas
//! where there is one (the temperature as `(Σ m v² − (Σ m v)²/Σ m)/N`).

mod common;

use beadchain::engine::events::EventKind;
use beadchain::snapshot::Snapshot;
use common::{assert_ok, bc};
use std::path::Path;

/// A small gas: 60 beads, random masses and velocities (seeded), gaps of 1, soft walls.
const GAS: &str = "[scene]\nname = \"gas\"\nseed = 3\n[chain]\nbeads = 60\n\
    mass = { random = { mean = 1.0, eps = 0.9 } }\nprecompression = -1.0\n\
    [initial]\nvelocity = { random = { mean = 0.0, eps = 1.0 } }\n\
    [walls]\nleft = { precompression = -1.0 }\nright = { precompression = -1.0 }\n\
    [run]\nuntil = 40.0\nevery = 1.0\n";

/// `|a − b| ≤ abs + rel·|b|`.
fn close(a: f64, b: f64, abs: f64, rel: f64) -> bool {
    (a - b).abs() <= abs + rel * b.abs()
}

/// The text after `"key": ` in `s`, up to the next `,`, `}` or `]`.
fn field<'a>(s: &'a str, key: &str) -> &'a str {
    let pat = format!("\"{key}\": ");
    let at = s.find(&pat).unwrap_or_else(|| panic!("no {key} in {s}")) + pat.len();
    let rest = &s[at..];
    let end = rest.find([',', '}', ']']).unwrap_or(rest.len());
    rest[..end].trim()
}

fn num(s: &str, key: &str) -> f64 {
    field(s, key)
        .parse()
        .unwrap_or_else(|_| panic!("{key}: {}", field(s, key)))
}

fn run_gas(dir: &Path, extra: &[&str]) -> Snapshot {
    std::fs::write(dir.join("gas.toml"), GAS).unwrap();
    let mut args = vec!["run", "gas.toml", "--out", "gas.snap", "-q"];
    args.extend_from_slice(extra);
    assert_ok(&bc(dir, &args));
    Snapshot::open(&dir.join("gas.snap")).expect("snapshot")
}

fn analyze(dir: &Path, args: &[&str]) -> String {
    let mut a = vec!["analyze", "gas.snap"];
    a.extend_from_slice(args);
    let o = bc(dir, &a);
    assert_ok(&o);
    String::from_utf8(o.stdout).expect("utf-8")
}

/// Independent velocity moments: mean, population std, excess kurtosis, 8-bin histogram with
/// edges `mean + k·std`, `k = −3 … 3`.
fn moments(v: &[f64]) -> (f64, f64, f64, Vec<u64>) {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n;
    let std = var.sqrt();
    let m4 = v.iter().map(|x| ((x - mean) / std).powi(4)).sum::<f64>() / n;
    let mut hist = vec![0u64; 8];
    for &x in v {
        let above = (-3..=3).filter(|&k| x >= mean + k as f64 * std).count();
        hist[above] += 1;
    }
    (mean, std, m4 - 3.0, hist)
}

#[test]
fn analyze_reports_the_collision_rate_and_the_kinetic_temperature_of_a_gas() {
    let d = tempfile::tempdir().unwrap();
    let snap = run_gas(d.path(), &[]);
    let json = analyze(d.path(), &["--json"]);
    let n = snap.header().n_beads as usize;
    let mass = snap.header().scene.chain.mass.clone();
    let frames: Vec<_> = (0..snap.frame_count())
        .map(|k| snap.frame(k).unwrap())
        .collect();
    let (t0, t1) = (frames[0].t, frames[frames.len() - 1].t);
    // Collisions: close + hard_collision events in [t0, t1]; walls apart. Exact counts.
    let ev = snap.events();
    let pair = ev
        .iter()
        .filter(|e| matches!(e.kind, EventKind::Close | EventKind::HardCollision))
        .filter(|e| e.t >= t0 && e.t <= t1)
        .count();
    let wall = ev.iter().filter(|e| e.kind == EventKind::WallClose).count();
    assert!(pair > 50, "a gas collides: {pair} collisions");
    let coll = &json[json.find("\"collisions\"").unwrap()..];
    assert_eq!(field(coll, "pair"), pair.to_string());
    assert_eq!(field(coll, "wall"), wall.to_string());
    // Rate per unit time and per bead: abs 1e-12, rel 1e-12 (one division each).
    let rate = pair as f64 / (t1 - t0);
    assert!(close(num(coll, "rate"), rate, 1e-12, 1e-12), "{coll}");
    let per_bead = rate / n as f64;
    assert!(close(num(coll, "rate_per_bead"), per_bead, 1e-12, 1e-12));
    // Temperature per frame: (Σ m v² − (Σ m v)²/Σ m)/N, abs 1e-12, rel 1e-10 (cancellation
    // between the two sums of this form, not of the one analyze uses).
    let gas = &json[json.find("\"gas\"").expect("a gas gets the gas part")..];
    let rows: Vec<&str> = gas.split("{\"t\": ").skip(1).collect();
    assert_eq!(rows.len(), frames.len());
    let mut total = 0u64;
    let mut prev = f64::NEG_INFINITY;
    for (row, f) in rows.iter().zip(&frames) {
        let t: f64 = row.split(',').next().unwrap().parse().unwrap();
        assert_eq!(t, f.t);
        let mv: f64 = mass.iter().zip(&f.v).map(|(m, v)| m * v).sum();
        let mv2: f64 = mass.iter().zip(&f.v).map(|(m, v)| m * v * v).sum();
        let m: f64 = mass.iter().sum();
        let temp = (mv2 - mv * mv / m) / n as f64;
        let got = num(row, "T_kin");
        assert!(close(got, temp, 1e-12, 1e-10), "t = {t}: {got} vs {temp}");
        // Collisions in (t_prev, t]: exact.
        let c = ev
            .iter()
            .filter(|e| matches!(e.kind, EventKind::Close | EventKind::HardCollision))
            .filter(|e| e.t > prev && e.t <= f.t)
            .count();
        assert_eq!(field(row, "collisions"), c.to_string(), "t = {t}");
        total += c as u64;
        prev = f.t;
    }
    assert_eq!(total, pair as u64, "the intervals add up to the total");
    // Velocity distribution at the first and last frame: abs 1e-12, rel 1e-9; counts exact.
    for (key, f) in [
        ("velocity_first", &frames[0]),
        ("velocity_last", &frames[rows.len() - 1]),
    ] {
        let s = &gas[gas.find(key).unwrap()..];
        let (mean, std, kurt, hist) = moments(&f.v);
        assert!(close(num(s, "mean"), mean, 1e-12, 1e-9), "{key} mean");
        assert!(close(num(s, "std"), std, 1e-12, 1e-9), "{key} std");
        assert!(close(num(s, "excess_kurtosis"), kurt, 1e-12, 1e-9), "{key}");
        let h = &s[s.find('[').unwrap() + 1..s.find(']').unwrap()];
        let got: Vec<u64> = h.split(", ").map(|x| x.parse().unwrap()).collect();
        assert_eq!(got, hist, "{key} histogram");
    }
    // The uniform initial velocities: excess kurtosis near −1.2 (60 draws: abs 0.3).
    let k0 = num(
        &gas[gas.find("velocity_first").unwrap()..],
        "excess_kurtosis",
    );
    assert!(close(k0, -1.2, 0.3, 0.0), "uniform draws: kurtosis {k0}");
}

#[test]
fn analyze_text_names_units_and_shows_the_gas_part_only_for_gases_or_when_asked() {
    let d = tempfile::tempdir().unwrap();
    run_gas(d.path(), &[]);
    let s = analyze(d.path(), &[]);
    assert!(
        s.contains("collisions (close and hard_collision events between beads, t = 0 to 40): "),
        "{s}"
    );
    assert!(s.contains("per unit time"), "{s}");
    assert!(s.contains("kinetic temperature T_kin = (1/N) sum_i m_i (v_i - v_cm)^2 (an energy, k_B = 1; computer units)"), "{s}");
    assert!(s.contains("excess kurtosis"), "{s}");
    let f = analyze(d.path(), &["--frames"]);
    assert!(
        f.contains("kinetic temperature and collisions per frame"),
        "{f}"
    );
    // A striker chain is no gas: collision rate, no temperature unless --gas.
    assert_ok(&bc(
        d.path(),
        &["run", "striker", "--out", "s.snap", "-q", "--until", "20"],
    ));
    let a = bc(d.path(), &["analyze", "s.snap"]);
    let a = String::from_utf8_lossy(&a.stdout).to_string();
    assert!(a.contains("collisions (close and hard_collision"), "{a}");
    assert!(!a.contains("kinetic temperature"), "{a}");
    let g = bc(d.path(), &["analyze", "s.snap", "--gas"]);
    assert!(String::from_utf8_lossy(&g.stdout).contains("kinetic temperature T_kin"));
    // The dense engine logs no events: the rate is not computed, and says why.
    let dense = run_gas(d.path(), &["--engine", "dense", "--until", "2"]);
    assert!(dense.events().is_empty());
    let t = analyze(d.path(), &[]);
    assert!(
        t.contains("collisions: not computed (the dense engine logs no events"),
        "{t}"
    );
    assert!(analyze(d.path(), &["--json"]).contains("\"rate\": null"));
}

/// A physical scene's rate is also printed per second: `R/β`, abs 0, rel 1e-6 (7 printed
/// digits).
#[test]
fn analyze_prints_a_physical_scenes_collision_rate_in_si() {
    let d = tempfile::tempdir().unwrap();
    assert_ok(&bc(
        d.path(),
        &["run", "hertz_spheres_physical", "--out", "h.snap", "-q"],
    ));
    let beta = Snapshot::open(&d.path().join("h.snap"))
        .unwrap()
        .header()
        .scene
        .units
        .expect("physical")
        .time;
    let o = bc(d.path(), &["analyze", "h.snap"]);
    let s = String::from_utf8_lossy(&o.stdout).to_string();
    let line = s.lines().find(|l| l.starts_with("collisions (")).expect(&s);
    let after = |pat: &str| -> f64 {
        let at = line.find(pat).unwrap_or_else(|| panic!("{pat}: {line}")) + pat.len();
        line[at..]
            .split_whitespace()
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    let (rate, si) = (after("rate "), after("(SI: "));
    assert!(rate > 0.0, "{line}");
    assert!(close(si, rate / beta, 0.0, 1e-6), "{si} vs {}", rate / beta);
    // The velocity distribution's mean and std in m/s beside them (`v/β`, rel 1e-6): the module
    // docs promised them and they were missing.
    let o = bc(d.path(), &["analyze", "h.snap", "--gas"]);
    let s = String::from_utf8_lossy(&o.stdout).to_string();
    let line = s
        .lines()
        .find(|l| l.starts_with("  last frame (t = "))
        .expect(&s);
    for key in ["mean ", "std "] {
        let at = line.find(key).unwrap() + key.len();
        let mut w = line[at..].split_whitespace();
        let v: f64 = w.next().unwrap().trim_end_matches(',').parse().unwrap();
        let si: f64 = w.next().unwrap().trim_start_matches('(').parse().unwrap();
        assert!(close(si, v / beta, 0.0, 1e-6), "{key}{line}");
    }
}

/// The `granular_gas` preset: T_kin at t = 0 is the scene's own `(1/N) Σ m (v − v_cm)²` (abs
/// 1e-12, rel 1e-10), the run collides, and the walls are hit.
#[test]
fn granular_gas_preset_reports_its_initial_temperature() {
    let scene = beadchain::scene::preset("granular_gas").expect("preset");
    let n = scene.chain.len() as f64;
    let m: f64 = scene.chain.mass.iter().sum();
    let p: f64 = scene
        .chain
        .mass
        .iter()
        .zip(&scene.v0)
        .map(|(a, b)| a * b)
        .sum();
    let vcm = p / m;
    let t0: f64 = scene
        .chain
        .mass
        .iter()
        .zip(&scene.v0)
        .map(|(a, v)| a * (v - vcm).powi(2))
        .sum::<f64>()
        / n;
    let d = tempfile::tempdir().unwrap();
    assert_ok(&bc(
        d.path(),
        &[
            "run",
            "granular_gas",
            "--out",
            "gas.snap",
            "-q",
            "--until",
            "30",
        ],
    ));
    let json = analyze(d.path(), &["--json"]);
    let gas = &json[json.find("\"gas\"").unwrap()..];
    assert!(
        close(num(gas, "T_kin"), t0, 1e-12, 1e-10),
        "{} vs {t0}",
        num(gas, "T_kin")
    );
    let coll = &json[json.find("\"collisions\"").unwrap()..];
    assert!(
        num(coll, "pair") > 1000.0 && num(coll, "wall") > 0.0,
        "{coll}"
    );
}

/// The defect: a bounce off a hard wall was logged as `hard_collision` with the bead index as
/// its contact, so `analyze` counted it as a collision between beads (and a reader could not
/// tell the left wall's bounce from the contact between beads 0 and 1). Two equal beads, gaps
/// of 1 to each other and to two elastic hard walls, `v = (1, 0)`, worked out by hand: the beads
/// swap velocities at t = 1, 3, 7, 9, 13, 15 and bounce off the walls at t = 2 (right), 5
/// (left), 8, 11, 14, 17 (period 6) until t = 18.5.
#[test]
fn hard_wall_bounces_are_wall_collisions_not_collisions_between_beads() {
    let d = tempfile::tempdir().unwrap();
    let wall = "{ hard = true, restitution = 1.0, precompression = -1.0 }";
    let scene = format!(
        "[chain]\nbeads = 2\nprecompression = -1.0\n[initial]\nvelocity = [1.0, 0.0]\n\
         [hard]\ncontacts = \"all\"\nrestitution = 1.0\n[walls]\nleft = {wall}\nright = {wall}\n\
         [run]\nuntil = 18.5\nevery = 0.5\n"
    );
    std::fs::write(d.path().join("box.toml"), scene).unwrap();
    assert_ok(&bc(
        d.path(),
        &["run", "box.toml", "--out", "gas.snap", "-q"],
    ));
    let s = Snapshot::open(&d.path().join("gas.snap")).unwrap();
    let got: Vec<(f64, u64, EventKind)> = s
        .events()
        .iter()
        .map(|e| (e.t, e.contact, e.kind))
        .collect();
    let (pair, wall) = (EventKind::HardCollision, EventKind::WallClose);
    let want = [
        (1.0, 0, pair),
        (2.0, 1, wall),
        (3.0, 0, pair),
        (5.0, 0, wall),
        (7.0, 0, pair),
        (8.0, 1, wall),
        (9.0, 0, pair),
        (11.0, 0, wall),
        (13.0, 0, pair),
        (14.0, 1, wall),
        (15.0, 0, pair),
        (17.0, 0, wall),
    ];
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(want) {
        // times: abs 1e-12 (free flights of integer lengths at unit speed)
        assert!(
            close(g.0, w.0, 1e-12, 0.0) && (g.1, g.2) == (w.1, w.2),
            "{got:?}"
        );
    }
    let json = analyze(d.path(), &["--json"]);
    assert_eq!(
        (num(&json, "pair"), num(&json, "wall")),
        (6.0, 6.0),
        "{json}"
    );
    // a wall event's rel_velocity is the bead's velocity, as a soft wall's: +1 into the right
    // wall, −1 into the left one (abs 1e-12)
    for e in s.events().iter().filter(|e| e.kind == EventKind::WallClose) {
        let want = if e.contact == 1 { 1.0 } else { -1.0 };
        assert!(close(e.rel_velocity, want, 1e-12, 0.0), "{e:?}");
    }
}

/// The defect: for a dense-engine run (no event log) the summary said "not computed", but the
/// per-frame table printed 0 collisions and a rate of 0 in every frame, and the JSON gave
/// `"pair": 0, "wall": 0` and `"collisions": 0` per frame: unknown counts shown as zeros.
#[test]
fn dense_runs_show_unknown_collision_counts_as_unknown_not_zero() {
    let d = tempfile::tempdir().unwrap();
    run_gas(d.path(), &["--engine", "dense", "--until", "2"]);
    let json = analyze(d.path(), &["--json"]);
    assert_eq!(
        (field(&json, "pair"), field(&json, "wall")),
        ("null", "null"),
        "{json}"
    );
    let gas = &json[json.find("\"gas\"").expect("gas part")..];
    assert_eq!(gas.matches("\"collisions\": null").count(), 3, "{gas}");
    assert!(!gas.contains("\"collisions\": 0"), "{gas}");
    let table = analyze(d.path(), &["--frames"]);
    let head = "kinetic temperature and collisions per frame";
    let rows: Vec<&str> = table[table.find(head).unwrap()..]
        .lines()
        .skip(2)
        .take(3)
        .collect();
    for r in &rows {
        let cols: Vec<&str> = r.split_whitespace().collect();
        assert_eq!(&cols[2..], ["-", "-"], "{table}");
    }
}
