//! `beadchain plot` axes (issue 14), read back from the SVG text (`<text>` elements): labels
//! with units (computer units, SI for physical scenes), readable ticks (no rounding noise for
//! zero), title/label overrides, colour maps, side-by-side panels with a shared colour scale,
//! and the error messages (the energy plot: `tests/plot_energy.rs`).
//!
//! Text needs a TrueType font at run time (CI installs DejaVu Sans); without one the figures
//! have no text and the text assertions are skipped with a note (the numeric ones still run).

mod common;
mod plot_support;

use beadchain::plot::{self, trace, Panels, SpacetimeOptions, Units};
use beadchain::snapshot::Snapshot;
use plot_support::*;
use std::path::{Path, PathBuf};

#[test]
fn zero_tick_is_labelled_zero_not_rounding_noise() {
    // before: `plot profile two_strikers.snap --times 10` labelled the zero tick `-1.11e-16`
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    ok(d, &["run", "two_strikers", "--out", "ts.snap", "-q"]);
    ok(
        d,
        &[
            "plot", "profile", "ts.snap", "--times", "10", "--out", "p.svg",
        ],
    );
    ok(
        d,
        &[
            "plot", "trace", "ts.snap", "--beads", "50,49", "--out", "t.svg",
        ],
    );
    for f in ["p.svg", "t.svg"] {
        let Some(l) = texts(&d.join(f)) else { return };
        let nums = numbers(&l);
        let big = nums.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(l.iter().any(|s| s == "0"), "{f}: {l:?}");
        for v in &nums {
            // a nonzero tick is at least 1e-9 of the largest (absolute), and short
            assert!(
                *v == 0.0 || v.abs() > 1e-9 * big,
                "{f}: noise label {v}: {l:?}"
            );
        }
        assert!(
            l.iter()
                .filter(|s| s.parse::<f64>().is_ok())
                .all(|s| s.len() <= 6),
            "{f}: {l:?}"
        );
    }
}

#[test]
fn axis_labels_name_units_on_every_plot_kind() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    ok(d, &["run", "two_strikers", "--out", "ts.snap", "-q"]);
    std::fs::write(
        d.join("g.csv"),
        "n1,n2,refl\n2.5,2.5,0\n3,2.5,0.1\n2.5,3,0.2\n3,3,0.3\n",
    )
    .unwrap();
    let cases: &[(&[&str], &[&str])] = &[
        (
            &["plot", "spacetime", "ts.snap", "--out", "s.svg"],
            &[
                "bead index i",
                "time t (computer units)",
                "(computer units)",
            ],
        ),
        (
            &[
                "plot", "profile", "ts.snap", "--times", "20", "--out", "p.svg",
            ],
            &["bead index i", "velocity v (computer units)"],
        ),
        (
            &["plot", "trace", "ts.snap", "--beads", "3", "--out", "t.svg"],
            &["time t (computer units)", "velocity v (computer units)"],
        ),
        (
            &["plot", "energy", "ts.snap", "--out", "e.svg"],
            &[
                "position x of the leading wave (energy-weighted, beads)",
                "energy ratio E_wave / E_0 (dimensionless)",
            ],
        ),
        (
            &[
                "plot", "map", "g.csv", "--x", "n1", "--y", "n2", "--z", "refl", "--out", "m.svg",
            ],
            &["n1", "n2", "refl"],
        ),
    ];
    for (args, want) in cases {
        ok(d, args);
        let Some(l) = texts(&d.join(args[args.len() - 1])) else {
            return;
        };
        for w in *want {
            assert!(l.iter().any(|s| s == w), "{args:?}: no `{w}` in {l:?}");
        }
    }
}

#[test]
fn title_axis_labels_and_cmap_options() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    ok(d, &["run", "two_strikers", "--out", "ts.snap", "-q"]);
    let over = [
        "--title",
        "Fig. 3 (a)",
        "--xlabel",
        "site n",
        "--ylabel",
        "speed",
    ];
    for kind in [
        &["spacetime", "ts.snap", "--cmap", "bwr"][..],
        &["profile", "ts.snap", "--times", "5"],
        &["trace", "ts.snap", "--beads", "2"],
        &["energy", "ts.snap"],
    ] {
        let args = [&["plot"][..], kind, &over, &["--out", "f.svg"]].concat();
        ok(d, &args);
        let Some(l) = texts(&d.join("f.svg")) else {
            return;
        };
        for w in ["Fig. 3 (a)", "site n", "speed"] {
            assert!(l.iter().any(|s| s == w), "{kind:?}: no `{w}` in {l:?}");
        }
    }
    fails(
        d,
        &[
            "plot",
            "spacetime",
            "ts.snap",
            "--cmap",
            "jet",
            "--out",
            "x.png",
        ],
        "--cmap jet: unknown colour map (available: coolwarm, bwr, viridis, gray)",
    );
}

/// The time unit β (s) of Table 1 steel (paper eq. 10), computed here from the material:
/// `β = sqrt(m0 / (μ n0))`, m0 = ρ 4/3 π R³, μ = 10⁹, n0 = 2.5.
fn beta_table1() -> f64 {
    let m0 = 7650.0 * 4.0 / 3.0 * std::f64::consts::PI * 4.0e-3f64.powi(3);
    (m0 / (1e9 * 2.5)).sqrt()
}

/// `phys.snap` in `d`: the `hertz_spheres_physical` preset with frames every 100 computer time
/// units up to 2000, bead 3 moving at 1e-7 (computer units) rising linearly to 2e-7.
fn physical_snapshot(d: &Path) -> PathBuf {
    let scene = beadchain::scene::preset("hertz_spheres_physical").expect("preset");
    let n = scene.chain.mass.len();
    let frames: Vec<(f64, Vec<f64>)> = (0..=20)
        .map(|k| {
            let mut v = vec![0.0; n];
            v[3] = 1e-7 * (1.0 + k as f64 / 20.0);
            (100.0 * k as f64, v)
        })
        .collect();
    write_snap(d, "phys.snap", &scene, &frames)
}

#[test]
fn si_units_convert_axes_of_physical_scenes() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let path = physical_snapshot(d);
    let snap = Snapshot::open(&path).expect("open");
    let beta = beta_table1();
    assert!((beta - 9.0572e-7).abs() < 1e-10, "β = {beta}");
    let tr = trace::trace(
        &snap,
        &plot::TraceOptions {
            beads: vec![3],
            t: Default::default(),
            units: Units::Si,
            size: (900, 650),
        },
    )
    .expect("trace");
    // t = 2000 β s, v = 2e-7 / β m/s: relative 2e-6 (β is stored with 7 significant digits)
    let (t, v) = *tr.series[0].points.last().unwrap();
    assert!((t - 2000.0 * beta).abs() < 2e-6 * 2000.0 * beta, "t = {t}");
    assert!((v - 2e-7 / beta).abs() < 2e-6 * 2e-7 / beta, "v = {v}");
    assert_eq!(
        (tr.x_desc.as_str(), tr.y_desc.as_str()),
        ("time t (s)", "velocity v (m/s)")
    );
    ok(
        d,
        &[
            "plot",
            "trace",
            "phys.snap",
            "--beads",
            "3",
            "--units",
            "si",
            "--out",
            "t.svg",
        ],
    );
    if let Some(l) = texts(&d.join("t.svg")) {
        assert!(l.iter().any(|s| s == "time t (s)"), "{l:?}");
        assert!(l.iter().any(|s| s == "velocity v (m/s)"), "{l:?}");
        // the ticks are in seconds and m/s: the largest tick of each axis lies in the data's
        // top half (t up to 1.81e-3 s, v up to 0.221 m/s), far from computer-unit values
        let nums = numbers(&l);
        let tmax = 2000.0 * beta;
        let vmax = 2e-7 / beta;
        assert!(nums.iter().any(|x| *x > 0.5 * tmax && *x <= tmax), "{l:?}");
        assert!(
            nums.iter().any(|x| *x > 0.5 * vmax && *x <= 1.1 * vmax),
            "{l:?}"
        );
        assert!(nums.iter().all(|x| *x < 1.0), "computer-unit tick in {l:?}");
    }
    ok(
        d,
        &[
            "plot",
            "spacetime",
            "phys.snap",
            "--units",
            "si",
            "--out",
            "s.svg",
        ],
    );
    if let Some(l) = texts(&d.join("s.svg")) {
        assert!(
            l.iter().any(|s| s == "time t (s)") && l.iter().any(|s| s == "(m/s)"),
            "{l:?}"
        );
    }
}

/// `--units si` on a dimensionless scene is refused, naming the scene.
#[test]
fn si_units_are_refused_for_dimensionless_scenes() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    // a dimensionless scene has no SI axes
    write_snap(
        d,
        "dimless.snap",
        &chain60(),
        &decaying_pulse(60, 30, 0.1, 0.1),
    );
    for kind in ["spacetime", "energy"] {
        fails(
            d,
            &[
                "plot",
                kind,
                "dimless.snap",
                "--units",
                "si",
                "--out",
                "x.png",
            ],
            "dimless.snap: --units si: scene `axes_test` is dimensionless",
        );
    }
}

#[test]
fn panels_share_one_colour_scale() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let frames = |vmax: f64| -> Vec<(f64, Vec<f64>)> {
        (0..10)
            .map(|k| {
                let mut v = vec![0.0; 60];
                v[k] = vmax;
                v[59 - k] = -0.5 * vmax;
                (k as f64, v)
            })
            .collect()
    };
    let a = write_snap(d, "a.snap", &chain60(), &frames(1.0));
    let b = write_snap(d, "b.snap", &chain60(), &frames(2.0));
    let snaps = [Snapshot::open(&a).unwrap(), Snapshot::open(&b).unwrap()];
    let p = Panels::from_snapshots(&snaps, &SpacetimeOptions::default(), None).expect("panels");
    assert_eq!(p.panels.len(), 2);
    assert!(p.panels.iter().all(|q| q.vmax == 2.0));
    // equal plot areas; only the last panel has the colour bar
    let r: Vec<_> = p.panels.iter().map(|q| q.layout().plot_rect()).collect();
    assert_eq!((r[0].2, r[0].3), (r[1].2, r[1].3));
    assert_eq!((p.panels[0].colorbar, p.panels[1].colorbar), (false, true));
    ok(
        d,
        &[
            "plot",
            "spacetime",
            "a.snap",
            "b.snap",
            "--title",
            "Both",
            "--out",
            "ab.svg",
        ],
    );
    if let Some(l) = texts(&d.join("ab.svg")) {
        assert!(l.iter().any(|s| s == "a.snap: axes_test"), "{l:?}");
        assert!(l.iter().any(|s| s == "b.snap: axes_test"), "{l:?}");
        assert_eq!(l.iter().filter(|s| *s == "all panels").count(), 1, "{l:?}");
        assert_eq!(l.iter().filter(|s| *s == "Both").count(), 1, "{l:?}");
        // the shared scale runs to max|v| = 2 over both panels (no negative bead or time tick)
        assert!(
            l.iter().any(|s| s == "-2") && l.iter().any(|s| s == "-1"),
            "{l:?}"
        );
    }
    fails(
        d,
        &[
            "plot",
            "spacetime",
            "a.snap",
            "b.snap",
            "a.snap",
            "--width",
            "500",
            "--out",
            "x.png",
        ],
        "--width 500: too narrow for 3 panels",
    );
}

#[test]
fn two_frame_one_frame_and_constant_runs_get_sensible_axes() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let mut v = vec![0.0; 60];
    v[5] = 0.3;
    write_snap(
        d,
        "two.snap",
        &chain60(),
        &[(0.0, v.clone()), (50.0, v.clone())],
    );
    write_snap(d, "one.snap", &chain60(), &[(7.0, v.clone())]);
    // two frames: the time axis is [0, 50], no negative time
    let snap = Snapshot::open(&d.join("two.snap")).unwrap();
    let st =
        beadchain::plot::Spacetime::from_snapshot(&snap, &SpacetimeOptions::default()).unwrap();
    assert_eq!(st.time_axis().extent(), (0.0, 50.0));
    ok(d, &["plot", "spacetime", "two.snap", "--out", "two.svg"]);
    ok(d, &["plot", "spacetime", "one.snap", "--out", "one.svg"]);
    // a constant trace (v = 0.3 at both frames): a padded, nonzero-width axis around 0.3
    ok(
        d,
        &[
            "plot", "trace", "two.snap", "--beads", "5", "--out", "c.svg",
        ],
    );
    let snap1 = Snapshot::open(&d.join("one.snap")).unwrap();
    let st1 =
        beadchain::plot::Spacetime::from_snapshot(&snap1, &SpacetimeOptions::default()).unwrap();
    let (t0, t1) = st1.time_axis().extent();
    // one frame: one computer time unit centred on t = 7 (no `every` in the scene)
    assert!(
        (t0 - 6.5).abs() < 1e-12 && (t1 - 7.5).abs() < 1e-12,
        "{t0} {t1}"
    );
    let Some(l) = texts(&d.join("two.svg")) else {
        return;
    };
    // negative numbers are colour-bar values (|v| <= 0.3), never times
    let nums = numbers(&l);
    assert!(nums.iter().all(|x| *x >= -0.3), "negative tick: {l:?}");
    assert!(l.iter().any(|s| s == "50"), "{l:?}");
    let c = texts(&d.join("c.svg")).unwrap();
    let mut y: Vec<f64> = numbers(&c)
        .into_iter()
        .filter(|x| *x > 0.2 && *x < 0.4)
        .collect();
    y.sort_by(f64::total_cmp);
    y.dedup();
    assert!(
        y.len() >= 3 && y.contains(&0.3),
        "constant series axis: {c:?}"
    );
}
