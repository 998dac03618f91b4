//! `beadchain plot animate` (issue 36, item 6): the GIF decodes (with the `gif` crate) to the
//! expected frame count, size and delay; the frames differ and the peak marker moves right with
//! the solitary wave of the `striker` preset; `--every`/`--frames-max` give the stated counts; the
//! y limits are fixed over the run; bad input exits 2 with one line and leaves no file.

mod common;
mod plot_support;

use beadchain::plot::layout::Layout;
use beadchain::plot::{AnimateOptions, Animation, Field, Units};
use beadchain::snapshot::{Frame, Snapshot};
use plot_support::{fails, ok};
use std::path::Path;

/// A decoded GIF: its size and each frame's delay (1/100 s) and RGBA pixels.
struct Gif {
    size: (u32, u32),
    frames: Vec<(u16, Vec<u8>)>,
}

fn decode(path: &Path) -> Gif {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let file = std::fs::File::open(path).expect("GIF written");
    let mut d = opts.read_info(file).expect("GIF header");
    let size = (d.width() as u32, d.height() as u32);
    let mut frames = Vec::new();
    while let Some(f) = d.read_next_frame().expect("GIF frame") {
        // every frame covers the whole image
        assert_eq!((f.left, f.top), (0, 0));
        assert_eq!((f.width as u32, f.height as u32), size);
        frames.push((f.delay, f.buffer.to_vec()));
    }
    Gif { size, frames }
}

/// `run striker` (100 beads, frames at t = 0, 1, …, 100) into `dir/s.snap`.
fn striker(dir: &Path) {
    ok(dir, &["run", "striker", "--out", "s.snap", "-q"]);
}

fn animate(dir: &Path, out: &str, extra: &[&str]) -> Gif {
    let mut args = vec!["plot", "animate", "s.snap", "--out", out];
    args.extend_from_slice(extra);
    ok(dir, &args);
    decode(&dir.join(out))
}

#[test]
fn gif_has_one_frame_per_snapshot_frame_at_the_given_size_and_rate() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    striker(d);
    let g = animate(
        d,
        "a.gif",
        &["--width", "400", "--height", "300", "--fps", "10"],
    );
    assert_eq!(g.size, (400, 300));
    assert_eq!(
        g.frames.len(),
        101,
        "101 frames (t = 0..100), under the 200 cap"
    );
    assert!(g.frames.iter().all(|f| f.0 == 10), "10 fps = 10/100 s");
    // a name without extension gets .gif; other fields draw too
    ok(
        d,
        &[
            "plot", "animate", "s.snap", "--out", "e", "--field", "energy",
        ],
    );
    assert_eq!(decode(&d.join("e.gif")).frames.len(), 101);
    let g = animate(d, "u.gif", &["--field", "u", "--frames-max", "3"]);
    assert_eq!((g.size, g.frames.len()), ((900, 650), 3));
    assert!(g.frames.iter().all(|f| f.0 == 5), "default 20 fps");
}

#[test]
fn every_and_frames_max_give_the_stated_counts() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    striker(d);
    let small = ["--width", "300", "--height", "200"];
    let count = |out: &str, opts: &[&str]| {
        let args: Vec<&str> = opts.iter().chain(&small).copied().collect();
        animate(d, out, &args).frames.len()
    };
    assert_eq!(count("a.gif", &["--frames-max", "7"]), 7);
    assert_eq!(
        count("b.gif", &["--every", "10"]),
        11,
        "t = 0, 10, ..., 100"
    );
    assert_eq!(count("c.gif", &["--every", "10", "--frames-max", "4"]), 4);
    assert_eq!(count("d.gif", &["--t", "20:29"]), 10);
    assert_eq!(count("e.gif", &["--frames-max", "1"]), 1);
}

/// Mean pixel column of the red peak marker (`line_color(1)` = (214, 39, 40); ±40 per channel
/// for the palette and the circle's edge), `None` when there is none.
fn marker_column(rgba: &[u8], w: u32) -> Option<f64> {
    let (mut sum, mut n) = (0.0, 0usize);
    for (p, px) in rgba.chunks_exact(4).enumerate() {
        let near = |c: u8, r: u8| (c as i32 - r as i32).abs() <= 40;
        if near(px[0], 214) && near(px[1], 39) && near(px[2], 40) {
            sum += (p % w as usize) as f64;
            n += 1;
        }
    }
    (n > 0).then(|| sum / n as f64)
}

#[test]
fn frames_differ_and_the_peak_marker_follows_the_wave() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    striker(d);
    // until t = 70 (the wave reaches the far end at t ≈ 82)
    let (w, h) = (600, 300);
    let g = animate(
        d,
        "a.gif",
        &["--t", "0:70", "--width", "600", "--height", "300"],
    );
    assert_eq!(g.frames.len(), 71);
    for k in 1..g.frames.len() {
        assert_ne!(
            g.frames[k - 1].1,
            g.frames[k].1,
            "frames {} and {k} equal",
            k - 1
        );
    }
    // the marker sits on the bead of largest |v| of each frame: x range -0.5..99.5 over the
    // plot area's columns
    let (x0, _, pw, _) = Layout::new((w, h), false).plot_rect();
    let bead_of = |col: f64| (col - x0 as f64) / pw as f64 * 100.0 - 0.5;
    let snap = Snapshot::open(&d.join("s.snap")).expect("open");
    let mut f = Frame::default();
    let mut last = f64::NEG_INFINITY;
    for (k, (_, rgba)) in g.frames.iter().enumerate() {
        let col = marker_column(rgba, w).unwrap_or_else(|| panic!("frame {k}: no marker"));
        snap.read_frame_into(k, &mut f).expect("frame");
        let peak = (0..100)
            .max_by(|&a, &b| f.v[a].abs().total_cmp(&f.v[b].abs()))
            .unwrap();
        // 1.5 beads (7 px): pixel rounding, and the circle clipped at the left edge at t = 0
        let bead = bead_of(col);
        assert!(
            (bead - peak as f64).abs() <= 1.5,
            "frame {k}: marker at bead {bead:.2}, peak at {peak}"
        );
        // it moves right: never back by more than 1.5 beads (ties between neighbours)
        assert!(bead >= last - 1.5, "frame {k}: {bead:.2} after {last:.2}");
        last = last.max(bead);
    }
    // at t = 70 the wave is near bead 1.21 * 70 ≈ 85 (docs of the preset); ±10 beads
    assert!((last - 85.0).abs() <= 10.0, "last marker at bead {last:.2}");
}

#[test]
fn y_limits_are_fixed_over_the_run_and_cover_every_frame() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    striker(d);
    let snap = Snapshot::open(&d.join("s.snap")).expect("open");
    let opts = AnimateOptions {
        field: Field::Velocity,
        beads: Default::default(),
        t: Default::default(),
        every: 1,
        frames_max: 20,
        fps: 20,
        units: Units::Computer,
        size: (600, 400),
    };
    let a = Animation::from_snapshot(&snap, &opts).expect("animation");
    assert_eq!(a.frames.len(), 20);
    let (lo, hi) = a
        .frames
        .iter()
        .flat_map(|f| &f.points)
        .fold((0.0_f64, 0.0_f64), |(l, h), p| (l.min(p.1), h.max(p.1)));
    // the striker's v = 1 at t = 0 is the largest; 6 % margin (exact to 1e-12)
    assert!((hi - 1.0).abs() < 1e-12, "{hi}");
    let (y0, y1) = a.y_range;
    let pad = 0.06 * (hi - lo);
    assert!((y1 - (hi + pad)).abs() < 1e-12 && (y0 - (lo - pad)).abs() < 1e-12);
    assert!(a.frame_title(&a.frames[1]).contains(", t = "));
}

#[test]
fn bad_input_exits_2_with_one_line_and_no_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    striker(d);
    let base = ["plot", "animate", "s.snap"];
    let run = |extra: &[&str], needle: &str| {
        let args: Vec<&str> = base.iter().chain(extra).copied().collect();
        fails(d, &args, needle);
    };
    run(&["--out", "x.mp4"], "--out x.mp4");
    run(&["--out", "x.png"], ".png");
    run(&["--out", "x.gif", "--beads", "5:5"], "--beads 5:5");
    run(&["--out", "x.gif", "--beads", "90:200"], "--beads 90:200");
    run(&["--out", "x.gif", "--fps", "0"], "--fps 0");
    run(&["--out", "x.gif", "--t", "500:600"], "--t 500:600");
    run(&["--out", "x.gif", "--width", "10"], "--width 10");
    fails(
        d,
        &["plot", "animate", "none.snap", "--out", "x.gif"],
        "none.snap",
    );
}
