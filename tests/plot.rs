//! `beadchain plot` through the library API (and the binary for the error contract): output
//! files and formats, determinism, the space–time map's colours at known pulses, profiles,
//! traces, the energy fit, CSV maps and their error paths, marching squares on analytic fields.

mod common;

use beadchain::integrate::Method;
use beadchain::plot::{
    self, contour::marching_squares, energy, profile, trace, BeadRange, Cmap, EnergyOptions, Map,
    MapOptions, Scale, Spacetime, SpacetimeOptions, TimeRange, Units,
};
use beadchain::scene::{Engine, Scene};
use beadchain::snapshot::{Header, Snapshot, SnapshotWriter};
use std::path::{Path, PathBuf};
use std::process::Command;

const N: usize = 40;

/// Strikers from both ends of a 40-bead chain (n = 2.5, a = 1): bead 0 at +1, bead 39 at −1.
/// Until the pulses meet (bead ~20), the left pulse has v > 0 and the right one v < 0.
fn two_strikers() -> Scene {
    let mut sc = common::striker(N, 2.5, 1.0, 1.0, 30.0);
    sc.v0[N - 1] = -1.0;
    sc.name = "two_strikers_test".into();
    sc
}

/// Runs `scene` (hybrid radau5, frames every 0.25) into `dir/run.snap`; returns the path and
/// the recorded frames.
fn snapshot(dir: &Path, scene: &Scene) -> (PathBuf, beadchain::engine::Recorder) {
    let mut cfg = common::config(Engine::Hybrid, Method::Radau5, 1e-8, 1e-10, scene.run.until);
    cfg.every = Some(0.25);
    let (_, rec) = common::run(scene, &cfg);
    let path = dir.join("run.snap");
    let h = Header::new(
        scene.clone(),
        Engine::Hybrid,
        Method::Radau5,
        1e-8,
        1e-10,
        "tests/plot.rs".into(),
    );
    let mut w = SnapshotWriter::create(&path, &h).expect("create snapshot");
    for k in 0..rec.t.len() {
        w.write_frame(rec.t[k], &rec.u[k], &rec.v[k])
            .expect("frame");
    }
    w.finish(&[], &Default::default()).expect("finish");
    (path, rec)
}

/// Index of the largest `|v|` among `v[range]`.
fn peak(v: &[f64], range: std::ops::Range<usize>) -> usize {
    range
        .max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs()))
        .expect("non-empty")
}

fn rgb_at(buf: &[u8], w: u32, (x, y): (u32, u32)) -> (u8, u8, u8) {
    let k = (y as usize * w as usize + x as usize) * 3;
    (buf[k], buf[k + 1], buf[k + 2])
}

#[test]
fn spacetime_colours_encode_sign_at_known_pulses() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (path, rec) = snapshot(dir.path(), &two_strikers());
    let snap = Snapshot::open(&path).expect("open");
    // a frame where the left pulse peaks near bead 10 (and the right one near bead 29)
    let k = (0..rec.t.len())
        .find(|&k| peak(&rec.v[k], 0..N / 2) >= 10)
        .expect("the pulse reaches bead 10");
    let (t, v) = (rec.t[k], &rec.v[k]);
    let (pl, pr) = (peak(v, 0..N / 2), peak(v, N / 2..N));
    assert!(
        v[pl] > 0.0 && v[pr] < 0.0,
        "pulse signs {} {}",
        v[pl],
        v[pr]
    );
    for scale in [Scale::Linear, Scale::Log] {
        let opts = SpacetimeOptions {
            scale,
            ..Default::default()
        };
        let st = Spacetime::from_snapshot(&snap, &opts).expect("spacetime");
        // 40 beads and 121 frames fit the plot area: one cell per (bead, frame), exact values
        assert_eq!((st.x.n, st.y.n), (N, rec.t.len()));
        assert_eq!(st.cell(pl as f64, t), v[pl]);
        assert_eq!(st.cell(pr as f64, t), v[pr]);
        let (buf, (w, _)) = plot::render_rgb(&st).expect("render");
        let red = rgb_at(&buf, w, st.pixel(pl as f64, t));
        let blue = rgb_at(&buf, w, st.pixel(pr as f64, t));
        assert!(
            red.0 as i32 > red.2 as i32 + 60,
            "{scale:?}: v > 0 must be red: {red:?}"
        );
        assert!(
            blue.2 as i32 > blue.0 as i32 + 60,
            "{scale:?}: v < 0 must be blue: {blue:?}"
        );
        // the middle bead at t = 0 is at rest: neutral grey (channels within 4 of each other)
        let g = rgb_at(&buf, w, st.pixel(20.0, 0.0));
        let spread = [g.0, g.1, g.2].iter().max().unwrap() - [g.0, g.1, g.2].iter().min().unwrap();
        assert!(
            spread <= 4 && g.0 > 200,
            "{scale:?}: rest must be grey: {g:?}"
        );
    }
}

#[test]
fn spacetime_downsampling_keeps_narrow_pulses_and_bounds_cells() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (path, rec) = snapshot(dir.path(), &two_strikers());
    let snap = Snapshot::open(&path).expect("open");
    // a 300x200 image has a plot area of 85x95 px: 121 frames are binned onto 95 rows
    let opts = SpacetimeOptions {
        size: (300, 200),
        beads: "5:34".parse().unwrap(),
        t: "1:20".parse().unwrap(),
        ..Default::default()
    };
    let st = Spacetime::from_snapshot(&snap, &opts).expect("spacetime");
    let (_, _, pw, ph) = st.layout().plot_rect();
    assert!(st.x.n <= pw as usize && st.y.n <= ph as usize);
    assert_eq!(st.cells.len(), st.x.n * st.y.n);
    // the map's max |v| equals the largest |v| of the selection (binning keeps maxima)
    let frames = TimeRange::frames(&opts.t, &rec.t).unwrap();
    let vmax = frames
        .flat_map(|k| rec.v[k][5..=34].iter().map(|v| v.abs()).collect::<Vec<_>>())
        .fold(0.0, f64::max);
    assert_eq!(st.vmax, vmax);
    let cmax = st
        .cells
        .iter()
        .filter(|c| c.is_finite())
        .fold(0.0f64, |m, c| m.max(c.abs()));
    assert_eq!(cmax, vmax);
}

#[test]
fn outputs_formats_and_identical_svg_bytes() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (path, _) = snapshot(dir.path(), &two_strikers());
    let snap = Snapshot::open(&path).expect("open");
    let st = Spacetime::from_snapshot(&snap, &SpacetimeOptions::default()).expect("spacetime");
    let files = plot::write_figure(&st, &dir.path().join("st")).expect("write");
    assert_eq!(files.len(), 2);
    let png = std::fs::read(dir.path().join("st.png")).expect("png written");
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    let svg = std::fs::read_to_string(dir.path().join("st.svg")).expect("svg written");
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    // the cells are one embedded PNG, not a rectangle per pixel
    assert!(svg.contains("data:png;base64") || svg.contains("data:image/png;base64"));
    assert!(svg.len() < 400_000, "svg is {} bytes", svg.len());
    // same input, same bytes (a second figure built from scratch)
    let st2 = Spacetime::from_snapshot(&snap, &SpacetimeOptions::default()).expect("again");
    assert_eq!(plot::render_svg(&st2).expect("svg"), svg);
    plot::write_figure(&st2, &dir.path().join("st2.png")).expect("png");
    assert_eq!(std::fs::read(dir.path().join("st2.png")).unwrap(), png);
    // no temporary files left
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");
}

#[test]
fn profile_trace_energy() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut sc = common::striker(60, 2.5, 1.0, 1.0, 60.0);
    sc.name = "striker_test".into();
    let (path, rec) = snapshot(dir.path(), &sc);
    let snap = Snapshot::open(&path).expect("open");
    let p = profile::profile(
        &snap,
        &plot::ProfileOptions {
            times: vec![10.0, 20.1],
            beads: BeadRange::default(),
            units: Units::Computer,
            size: (900, 650),
        },
    )
    .expect("profile");
    assert_eq!(p.series.len(), 2);
    // 20.1 -> the frame at t = 20 (frames every 0.25)
    assert!(
        p.series[1].name.starts_with("t = 20 "),
        "{}",
        p.series[1].name
    );
    let k = rec.t.iter().position(|&t| t == 20.0).expect("frame at 20");
    assert_eq!(p.series[1].points[7], (7.0, rec.v[k][7]));
    plot::write_figure(&p, &dir.path().join("p.svg")).expect("write");

    let tr = trace::trace(
        &snap,
        &plot::TraceOptions {
            beads: vec![3, 30],
            t: "5:".parse().unwrap(),
            units: Units::Computer,
            size: (900, 650),
        },
    )
    .expect("trace");
    assert_eq!(tr.series[1].name, "bead 30");
    assert_eq!(tr.series[0].points[0], (5.0, rec.v[20][3]));
    assert_eq!(tr.series[0].points.len(), rec.t.len() - 20);

    let e = energy::energy(
        &snap,
        &EnergyOptions {
            from: Some(10),
            to: Some(50),
            ..Default::default()
        },
    )
    .expect("energy");
    assert_eq!(e.fits.len(), 1);
    assert_eq!(
        e.fits[0].range,
        beadchain::analysis::FitRange::inclusive(10.0, 50.0)
    );
    let fit = e.fits[0].fit.as_ref().expect("fit");
    // a uniform chain conserves the solitary wave: |γ| below 1e-3 per bead (absolute)
    assert!(fit.gamma.abs() < 1e-3, "{fit:?}");
    assert!(
        e.chart.series[1].name.contains("γ ="),
        "{}",
        e.chart.series[1].name
    );
    plot::write_figure(&e, &dir.path().join("e.png")).expect("write");
}

#[test]
fn snapshot_selection_errors_name_the_problem() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (path, _) = snapshot(dir.path(), &two_strikers());
    let snap = Snapshot::open(&path).expect("open");
    let st = |beads: &str, t: &str| {
        Spacetime::from_snapshot(
            &snap,
            &SpacetimeOptions {
                beads: beads.parse().unwrap(),
                t: t.parse().unwrap(),
                ..Default::default()
            },
        )
        .map(|_| ())
        .unwrap_err()
        .to_string()
    };
    // half-open A:B, as `run --beads` (5:40 is beads 5 to 39, the chain's last)
    assert!(st("5:41", ":").contains("'5:41' is out of range"));
    assert!(st("9:3", ":").contains("selects no bead"));
    assert!(st(":", "100:200").contains("outside the run"));
    let e = trace::trace(
        &snap,
        &plot::TraceOptions {
            beads: vec![1, 77],
            t: TimeRange::default(),
            units: Units::Computer,
            size: (900, 650),
        },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("bead 77"), "{e}");
    let e = profile::profile(
        &snap,
        &plot::ProfileOptions {
            times: vec![31.0],
            beads: BeadRange::default(),
            units: Units::Computer,
            size: (900, 650),
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("time 31") && e.contains("outside the run"),
        "{e}"
    );
    let missing = Snapshot::open(&dir.path().join("nope.snap"))
        .unwrap_err()
        .to_string();
    assert!(missing.contains("nope.snap"), "{missing}");
}

fn opts(x: &str, y: &str, z: &str) -> MapOptions {
    MapOptions {
        x: x.into(),
        y: y.into(),
        z: z.into(),
        log_z: false,
        contour: None,
        cmap: Cmap::Viridis,
        size: (700, 500),
    }
}

#[test]
fn csv_map_grid_warnings_and_errors() {
    let dir = tempfile::tempdir().expect("tempdir");
    let csv = dir.path().join("sweep.csv");
    // uneven x spacing (2.5, 3, 4); one failed run (empty z) on line 5, one non-numeric on 8
    std::fs::write(
        &csv,
        "n1,n2,refl\n2.5,2.5,0\n3,2.5,0.1\n4,2.5,0.3\n2.5,3,\n3,3,0.1\n4,3,0.05\n2.5,3.5,abc\n",
    )
    .unwrap();
    let m = Map::from_csv(&csv, &opts("n1", "n2", "refl")).expect("map");
    assert_eq!(m.xs, vec![2.5, 3.0, 4.0]);
    assert_eq!(m.ys, vec![2.5, 3.0]);
    assert_eq!(m.z[2], 0.3);
    assert!(m.z[3].is_nan() && m.z[4] == 0.1);
    assert_eq!(m.warnings.len(), 2, "{:?}", m.warnings);
    assert!(m.warnings[0].contains("line 5") && m.warnings[0].contains("sweep.csv"));
    assert!(m.warnings[1].contains("line 8"));
    assert_eq!(plot::map::edges(&m.xs), vec![2.25, 2.75, 3.5, 4.5]);
    let e = Map::from_csv(&csv, &opts("n1", "n3", "refl"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("`n3`") && e.contains("sweep.csv"), "{e}");
    let e = Map::from_csv(&dir.path().join("none.csv"), &opts("a", "b", "c"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("none.csv"), "{e}");
    let mut o = opts("n1", "n2", "refl");
    o.contour = Some(0.2);
    let m = Map::from_csv(&csv, &o).expect("map");
    let segs = &m.contour.as_ref().unwrap().1;
    // square 3..4 x 2.5..3 (corners 0.1, 0.3, 0.05, 0.1) crosses 0.2 on its bottom edge at
    // x = 3.5 (linear interpolation, exact to 1e-12 absolute); the square with the NaN is skipped
    assert!(segs
        .iter()
        .flatten()
        .any(|p| (p.0 - 3.5).abs() < 1e-12 && p.1 == 2.5));
    let files = plot::write_figure(&m, &dir.path().join("map")).expect("write");
    assert_eq!(files.len(), 2);
    let mut o = opts("n1", "n2", "refl");
    o.log_z = true;
    let m = Map::from_csv(&csv, &o).expect("log map");
    // z = 0 is skipped with --log-z too
    assert_eq!(m.warnings.len(), 3, "{:?}", m.warnings);
}

#[test]
fn marching_squares_on_analytic_fields() {
    // circle: z = x² + y², level 0.25 -> radius 0.5, grid step 0.05
    let g: Vec<f64> = (0..=40).map(|k| -1.0 + 0.05 * k as f64).collect();
    let z: Vec<f64> = g
        .iter()
        .flat_map(|y| g.iter().map(move |x| x * x + y * y))
        .collect();
    let segs = marching_squares(&g, &g, &z, 0.25);
    let mut len = 0.0;
    for s in &segs {
        for p in s {
            let r = (p.0 * p.0 + p.1 * p.1).sqrt();
            // linear interpolation of a quadratic: |r − 0.5| < 3e-3 (absolute, 0.6 % relative)
            assert!((r - 0.5).abs() < 3e-3, "{p:?} at r = {r}");
        }
        len += ((s[1].0 - s[0].0).powi(2) + (s[1].1 - s[0].1).powi(2)).sqrt();
    }
    // polygon inscribed in the circle: perimeter within 1 % (relative) of π
    assert!(
        (len - std::f64::consts::PI).abs() < 0.01 * std::f64::consts::PI,
        "{len}"
    );
    // uneven grid, plane z = x: the line x = 2 exactly (1e-12 absolute)
    let xs = [0.0, 1.0, 3.0];
    let ys = [0.0, 0.5, 2.0];
    let z: Vec<f64> = ys.iter().flat_map(|_| xs.iter().copied()).collect();
    let segs = marching_squares(&xs, &ys, &z, 2.0);
    assert_eq!(segs.len(), 2);
    assert!(segs.iter().flatten().all(|p| (p.0 - 2.0).abs() < 1e-12));
    // saddle: two segments, and a NaN corner suppresses its square
    let s = marching_squares(&[0.0, 1.0], &[0.0, 1.0], &[1.0, 0.0, 0.0, 1.0], 0.5);
    assert_eq!(s.len(), 2);
    let s = marching_squares(&[0.0, 1.0], &[0.0, 1.0], &[1.0, f64::NAN, 0.0, 1.0], 0.5);
    assert!(s.is_empty());
}

/// Before (issue 36): `--beads 0:40` was half-open for `run`, inclusive for `plot spacetime`
/// ("bead 40 is out of range" on this 40-bead chain) and refused by `plot trace` (comma list
/// only: "invalid digit found in string"). Now every command reads `run --beads`' grammar.
#[test]
fn plot_beads_take_the_run_grammar() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (path, _) = snapshot(dir.path(), &two_strikers());
    let snap = path.to_string_lossy().into_owned();
    let bc = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_beadchain"))
            .args(args)
            .current_dir(dir.path())
            .output()
            .expect("run beadchain")
    };
    for args in [
        &[
            "plot",
            "spacetime",
            &snap,
            "--beads",
            "0:40",
            "--out",
            "s.svg",
        ][..],
        &[
            "plot", "profile", &snap, "--times", "5", "--beads", "0:40", "--out", "p.svg",
        ],
        &["plot", "trace", &snap, "--beads", "0:3", "--out", "t.svg"],
        &[
            "plot",
            "trace",
            &snap,
            "--beads",
            "1,20:40:10",
            "--out",
            "u.svg",
        ],
    ] {
        let o = bc(args);
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    // A:B is beads A to B-1 in every plot
    let s = Snapshot::open(&path).expect("open");
    let st = |b: &str| {
        let opts = SpacetimeOptions {
            beads: b.parse().unwrap(),
            ..Default::default()
        };
        Spacetime::from_snapshot(&s, &opts).map(|f| f.x.n)
    };
    assert_eq!(st("0:40").unwrap(), N);
    assert_eq!(st("5:15").unwrap(), 10);
    assert_eq!(
        plot::bead_list("0:3", N).unwrap(),
        [0, 1, 2],
        "trace beads 0:3"
    );
    let o = bc(&[
        "plot",
        "spacetime",
        &snap,
        "--beads",
        "0:40:2",
        "--out",
        "x.svg",
    ]);
    let e = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("one contiguous range A:B"), "{e}");
}

#[test]
fn cli_errors_are_one_line_and_leave_no_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (path, _) = snapshot(dir.path(), &two_strikers());
    let snap = path.to_string_lossy().into_owned();
    let cases: &[(&[&str], &str)] = &[
        (
            &["plot", "spacetime", &snap, "--beads", "3:99"],
            "'3:99' is out of range",
        ),
        (&["plot", "spacetime", "missing.snap"], "missing.snap"),
        (&["plot", "spacetime", &snap, "--out", "x.jpg"], ".jpg"),
        (&["plot", "trace", &snap, "--beads", "1,50"], "bead 50"),
        (&["plot", "profile", &snap, "--times", "99"], "time 99"),
        (
            &[
                "plot", "map", "none.csv", "--x", "a", "--y", "b", "--z", "c",
            ],
            "none.csv",
        ),
    ];
    for (args, needle) in cases {
        let o = Command::new(env!("CARGO_BIN_EXE_beadchain"))
            .args(*args)
            .current_dir(dir.path())
            .output()
            .expect("run beadchain");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        let names: Vec<String> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, vec!["run.snap".to_string()], "{args:?}");
    }
    let o = Command::new(env!("CARGO_BIN_EXE_beadchain"))
        .args(["plot", "spacetime", &snap, "--scale", "log", "--out", "ok"])
        .current_dir(dir.path())
        .output()
        .expect("run beadchain");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dir.path().join("ok.png").exists() && dir.path().join("ok.svg").exists());
}
