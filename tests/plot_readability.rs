//! Readability of the figures (issue 36, item 10), one regression test per defect:
//!
//! - `plot map` labelled its axes with the raw sweep keys (`chain.exponent.segments.0.value`);
//! - its colour bar was ticked at 0, 1/4, …, 1 of the data range (0.133, 0.265, 0.397, 0.529);
//! - the third line of `plot profile` (and `trace`, `energy`) was yellow on white;
//! - the accuracy plot's lines and legend swatches were 1–2 px wide, and every engine/method pair
//!   got its own colour only, so hybrid auto and dense verlet could not be told apart.
//!
//! Colours and widths are read back from the SVG (`<polyline stroke=… stroke-width=…>`), so they
//! are checked with or without a font; the text checks need one (skipped with a note without).

mod common;
mod plot_support;

use beadchain::accuracy::{AccuracyReport, AccuracyRow, ReferenceInfo};
use beadchain::integrate::Method;
use beadchain::plot::{self, profile, ticks, BeadRange, Cmap, Map, MapOptions, Units};
use beadchain::scene::Engine;
use beadchain::snapshot::Snapshot;
use plot_support::*;

/// WCAG 2 contrast ratio of an sRGB colour against white (1 = invisible, 21 = black).
fn contrast_on_white((r, g, b): (u8, u8, u8)) -> f64 {
    let lin = |c: u8| {
        let c = c as f64 / 255.0;
        if c <= 0.03928 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let l = 0.2126 * lin(r) + 0.7152 * lin(g) + 0.0722 * lin(b);
    1.05 / (l + 0.05)
}

/// `(stroke colour, stroke width)` of every `<polyline>` of an SVG whose stroke is not a grey
/// (axes, grid and frames are grey or black; data lines and legend swatches are coloured).
fn coloured_polylines(svg: &str) -> Vec<((u8, u8, u8), f64)> {
    let attr = |tag: &str, name: &str| -> Option<String> {
        let key = format!(" {name}=\"");
        let a = tag.find(&key)? + key.len();
        Some(tag[a..a + tag[a..].find('"')?].to_string())
    };
    svg.split("<polyline")
        .skip(1)
        .filter_map(|t| {
            let tag = &t[..t.find("/>")?];
            let hex = attr(tag, "stroke")?;
            let h = |k: usize| u8::from_str_radix(&hex[k..k + 2], 16).ok();
            let rgb = (h(1)?, h(3)?, h(5)?);
            let width: f64 = attr(tag, "stroke-width")?.parse().ok()?;
            (rgb.0 != rgb.1 || rgb.1 != rgb.2).then_some((rgb, width))
        })
        .collect()
}

/// A value is round when it is `m · 10^k` with `m` in {1, 2, 5} times an integer, i.e. a
/// multiple of a step `{1, 2, 5} · 10^k` no finer than a tenth of the span (relative 1e-9).
fn is_round(v: f64, span: f64) -> bool {
    if v == 0.0 {
        return true;
    }
    let k = (span / 10.0).log10().floor() as i32;
    [1.0, 2.0, 5.0, 10.0, 20.0, 50.0].iter().any(|m| {
        let step = m * 10f64.powi(k);
        let q = v / step;
        (q - q.round()).abs() < 1e-9 * q.abs().max(1.0)
    })
}

#[test]
fn map_axis_labels_of_dotted_keys_are_readable() {
    // before: the axes said `chain.exponent.base` and `chain.exponent.segments.0.value`
    let pts: Vec<(f64, f64, f64)> = [2.5f64, 3.0, 3.5]
        .iter()
        .flat_map(|&a| [2.5, 3.0, 3.5].map(|b| (a, b, (a - b).max(0.0) / 2.0)))
        .collect();
    let opts = MapOptions {
        x: "chain.exponent.base".into(),
        y: "chain.exponent.segments.0.value".into(),
        z: "left_fraction".into(),
        log_z: false,
        contour: None,
        cmap: Cmap::Viridis,
        size: (700, 500),
    };
    let m = Map::from_points(&pts, &opts).expect("map");
    assert_eq!(m.x_desc, "exponent n (base)");
    assert_eq!(m.y_desc, "exponent n (segment 0)");
    // names the key table does not know are kept as written
    for (key, want) in [
        ("chain.exponent.random.eps", "exponent n (random ε)"),
        ("chain.mass.segments.1.value", "mass m (segment 1)"),
        ("initial.striker_si", "striker velocity v0 (SI)"),
        ("scene.seed", "seed"),
        ("gamma", "decay rate γ"),
        ("dn", "dn"),
        ("walls.left.frobnicate", "walls.left.frobnicate"),
    ] {
        assert_eq!(plot::keys::readable(key), want, "{key}");
    }
    // the CLI: readable defaults, and --xlabel/--ylabel/--zlabel replace them
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let mut csv =
        String::from("chain.exponent.base,chain.exponent.segments.0.value,left_fraction\n");
    for (x, y, z) in &pts {
        csv.push_str(&format!("{x},{y},{z}\n"));
    }
    std::fs::write(d.join("refl.csv"), csv).unwrap();
    let keys = [
        "--x",
        "chain.exponent.base",
        "--y",
        "chain.exponent.segments.0.value",
        "--z",
        "left_fraction",
    ];
    let mut args = vec!["plot", "map", "refl.csv"];
    args.extend(keys);
    ok(d, &[args.as_slice(), &["--out", "a.svg"]].concat());
    args.extend([
        "--xlabel",
        "n1",
        "--ylabel",
        "n2",
        "--zlabel",
        "E_refl / E_in",
    ]);
    ok(d, &[args.as_slice(), &["--out", "b.svg"]].concat());
    let (Some(a), Some(b)) = (texts(&d.join("a.svg")), texts(&d.join("b.svg"))) else {
        return;
    };
    assert!(a.iter().any(|s| s == "exponent n (segment 0)"), "{a:?}");
    // the colour bar's label, in lines that fit its strip
    assert!(a.iter().any(|s| s == "left fraction"), "{a:?}");
    assert!(a.iter().any(|s| s == "E_left/E_total"), "{a:?}");
    assert!(!a.iter().any(|s| s.contains("segments.0")), "{a:?}");
    for want in ["n1", "n2", "E_refl / E_in"] {
        assert!(b.iter().any(|s| s == want), "{want}: {b:?}");
    }
}

#[test]
fn map_colour_bar_ticks_are_round() {
    // before: a z range 0.001 … 0.529 was ticked 0.001, 0.133, 0.265, 0.397, 0.529
    for &(lo, hi) in &[
        (0.001, 0.529),
        (0.0, 0.798),
        (-0.11, 0.055),
        (3.2e-7, 9.9e-6),
        (12.0, 13.7),
        (-2.0, 2.0),
    ] {
        let t = ticks::colorbar_ticks(lo, hi, false);
        assert!(t.len() >= 3 && t.len() <= 7, "{lo}..{hi}: {t:?}");
        for &(s, v) in &t {
            assert!(is_round(v, hi - lo), "{lo}..{hi}: {v} in {t:?}");
            // the tick sits at its value's place on the bar (1e-12 relative)
            assert!((s - (v - lo) / (hi - lo)).abs() < 1e-12, "{v}: {s}");
            assert!((-1e-12..=1.0 + 1e-12).contains(&s), "{v}: {s}");
        }
    }
    // log colouring (the bar spans log10 z): decades, or 1-2-5 values within one decade
    for &(lo, hi) in &[(1e-6, 0.3), (0.02, 0.09), (0.13, 0.17)] {
        let t = ticks::colorbar_ticks(f64::log10(lo), f64::log10(hi), true);
        assert!(t.len() >= 2, "{lo}..{hi}: {t:?}");
        for &(s, v) in &t {
            assert!(v >= lo * (1.0 - 1e-12) && v <= hi * (1.0 + 1e-12), "{v}");
            assert!(is_round(v, v), "{lo}..{hi}: {v} in {t:?}");
            let want = (v.log10() - lo.log10()) / (hi.log10() - lo.log10());
            assert!((s - want).abs() < 1e-12, "{v}: {s}");
        }
    }
    // the drawn map: its colour-bar labels are those values
    let pts = [
        (0.0, 0.0, 0.001),
        (1.0, 0.0, 0.2),
        (0.0, 1.0, 0.3),
        (1.0, 1.0, 0.529),
    ];
    let opts = MapOptions {
        x: "x".into(),
        y: "y".into(),
        z: "z".into(),
        log_z: false,
        contour: None,
        cmap: Cmap::Viridis,
        size: (700, 500),
    };
    let m = Map::from_points(&pts, &opts).expect("map");
    let dir = tempfile::tempdir().expect("tempdir");
    let svg = dir.path().join("m.svg");
    plot::write_figure(&m, &svg).expect("write");
    let Some(l) = texts(&svg) else { return };
    for want in ["0.1", "0.2", "0.3", "0.4", "0.5"] {
        assert!(l.iter().any(|s| s == want), "{want}: {l:?}");
    }
    assert!(!l.iter().any(|s| s == "0.133" || s == "0.265"), "{l:?}");
}

#[test]
fn profile_line_colours_contrast_with_white() {
    // before: the third line (plotters' Palette99: red, green, yellow, …) was #FFE119, contrast
    // 1.3 on white; every line now has at least the 3:1 of WCAG 2.1 for graphics
    let dir = tempfile::tempdir().expect("tempdir");
    let frames: Vec<(f64, Vec<f64>)> = (0..10)
        .map(|k| {
            let mut v = vec![0.0; 60];
            v[5 * k + 2] = 1.0;
            (k as f64, v)
        })
        .collect();
    let path = write_snap(dir.path(), "p.snap", &chain60(), &frames);
    let snap = Snapshot::open(&path).expect("open");
    let p = profile::profile(
        &snap,
        &plot::ProfileOptions {
            times: (0..10).map(|k| k as f64).collect(),
            beads: BeadRange::default(),
            units: Units::Computer,
            size: (900, 650),
        },
    )
    .expect("profile");
    let svg = plot::render_svg(&p).expect("svg");
    let lines = coloured_polylines(&svg);
    assert!(lines.len() >= 10, "{lines:?}");
    let mut colours: Vec<(u8, u8, u8)> = lines.iter().map(|l| l.0).collect();
    for &c in &colours {
        let r = contrast_on_white(c);
        assert!(r >= 3.0, "line colour {c:?}: contrast {r:.2} on white");
    }
    // ten lines, ten colours
    colours.sort();
    colours.dedup();
    assert_eq!(colours.len(), 10, "{colours:?}");
}

/// A synthetic report: two tolerances for every engine × method, errors falling with time.
fn report() -> AccuracyReport {
    let mut rows = Vec::new();
    for (ie, engine) in [Engine::Hybrid, Engine::Dense].into_iter().enumerate() {
        for (im, method) in [Method::Auto, Method::Radau5, Method::Dop853, Method::Verlet]
            .into_iter()
            .enumerate()
        {
            for k in 0..2 {
                let e = 10f64.powi(-3 - 2 * k - im as i32);
                rows.push(AccuracyRow {
                    engine,
                    method,
                    rtol: e,
                    atol: e / 100.0,
                    verlet_dt: None,
                    failure: None,
                    is_reference: false,
                    err_u: e,
                    err_v: e,
                    error: e,
                    energy_error: e,
                    ke_error: e,
                    wall_seconds: 0.01 * (1 + ie + k as usize) as f64,
                    steps: 1,
                    rejected: 0,
                    rhs_evals: 1,
                    events: 0,
                    bead_steps: 1,
                });
            }
        }
    }
    AccuracyReport {
        scene: "synthetic".into(),
        beads: 10,
        until: 1.0,
        tau: 1.0,
        reference: ReferenceInfo {
            rtol: 1e-12,
            check_rtol: 1e-11,
            check_err_u: 1e-12,
            check_err_v: 1e-12,
            wall_seconds: 1.0,
        },
        rows,
        notes: vec![],
        files: vec![],
    }
}

#[test]
fn accuracy_plot_lines_are_thick_and_tell_engines_apart() {
    // before: lines 2 px, legend swatches 1 px, eight colours for eight lines (hybrid auto red,
    // dense verlet magenta, indistinguishable in the legend)
    let (s, _png, _text) = beadchain::accuracy::plot::render_plots(&report()).expect("plots");
    let lines = coloured_polylines(&s);
    assert!(!lines.is_empty());
    for &(c, w) in &lines {
        assert!(w >= 3.0, "line {c:?} is {w} px wide");
        let r = contrast_on_white(c);
        assert!(r >= 3.0, "line colour {c:?}: contrast {r:.2} on white");
    }
    // colour by method (4 colours), engine by line style: dense lines are dashed, i.e. drawn as
    // many short pieces, so each method's colour has far more dense pieces than the 3 solid
    // hybrid polylines (line, legend swatch) it would have otherwise
    let mut colours: Vec<(u8, u8, u8)> = lines.iter().map(|l| l.0).collect();
    colours.sort();
    colours.dedup();
    assert_eq!(colours.len(), 4, "{colours:?}");
    for c in &colours {
        let n = lines.iter().filter(|l| l.0 == *c).count();
        assert!(n >= 6, "colour {c:?}: {n} pieces (no dashed dense line)");
    }
    // hybrid markers are circles, dense markers squares (8 points each, plus legend marks)
    let circles = s.matches("<circle").count();
    let rects = s.matches("<rect").count();
    assert!(circles >= 8 + 4, "{circles} circles");
    assert!(rects >= 8 + 4, "{rects} rects");
}
