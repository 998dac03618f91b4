//! `beadchain::analysis::summarize` (the library function behind `beadchain analyze` and
//! Python's `analyze()`) on a small in-memory run: energies, the leading wave's speed, the
//! interface split summing to the total, and its errors (issue 13).

mod common;

use beadchain::analysis::summary::FrameView;
use beadchain::analysis::{summarize, SummaryError, SummaryOptions};
use beadchain::engine::Recorder;
use beadchain::integrate::Method;
use beadchain::model::Chain;
use beadchain::scene::Engine;

/// The striker of `data/scenes/striker.toml` (100 beads, n = 2.5, v0 = 1), frames every 1.0
/// to t = 100.
fn striker_run() -> (Chain, Recorder) {
    let sc = common::striker(100, 2.5, 1.0, 1.0, 100.0);
    let mut cfg = common::config(Engine::Hybrid, Method::Auto, 1e-8, 1e-12, 100.0);
    cfg.every = Some(1.0);
    let (_, rec) = common::run(&sc, &cfg);
    (sc.chain, rec)
}

fn views(rec: &Recorder) -> Vec<FrameView<'_>> {
    rec.t
        .iter()
        .zip(rec.u.iter().zip(&rec.v))
        .map(|(&t, (u, v))| (t, u.as_slice(), v.as_slice()))
        .collect()
}

fn close(x: f64, want: f64, abs: f64, rel: f64) -> bool {
    (x - want).abs() <= abs.max(rel * want.abs())
}

#[test]
fn summarize_of_a_striker_run_finds_the_solitary_wave_speed_and_conserved_energy() {
    let (chain, rec) = striker_run();
    let frames = views(&rec);
    let s = summarize(&chain, &frames, &SummaryOptions::default()).expect("summarizes");
    assert_eq!((s.n, s.frames), (100, 101));
    assert_eq!((s.t_first, s.t_last), (0.0, 100.0));
    // E0 = 1/2 m v0^2 = 0.5 (abs 1e-15, rel 1e-15); the run conserves it to its rtol 1e-8.
    assert!(close(s.e0, 0.5, 1e-15, 1e-15), "e0 {}", s.e0);
    // E_ref = max(|E0|, energy scale of the first and last frames): E_end here.
    assert!(
        close(s.e_ref, s.e0.max(s.e_end), 1e-15, 1e-15),
        "e_ref {}",
        s.e_ref
    );
    assert!(close(s.e_end, 0.5, 0.0, 1e-7), "e_end {}", s.e_end);
    // The striker's solitary wave: 1.21 beads per time unit (data/scenes/striker.toml),
    // within 5 % (absolute 0.06), over the default range 20..90.
    assert_eq!(s.fit_range, (20.0, 90.0));
    let sp = s.speed.as_ref().expect("speed");
    assert!(close(sp.value, 1.21, 0.06, 0.05), "speed {}", sp.value);
    assert!(sp.points >= 3, "{} points", sp.points);
    let fit = s.decay.as_ref().expect("decay fit");
    assert_eq!(fit.n, sp.points);
    // The track holds every frame with a right-moving pulse, positions rising in time.
    assert!(
        s.track.len() >= 90 && s.track.len() <= 101,
        "{}",
        s.track.len()
    );
    assert!(s.track.windows(2).all(|w| w[1].t > w[0].t));
    // The incoming wave (first developed frame) carries most of E0: between 0.9 and 1.0 of it.
    let e_in = *s.e_in.as_ref().expect("incoming energy");
    assert!(
        e_in > 0.9 * s.e0 && e_in <= s.e0 * (1.0 + 1e-9),
        "e_in {e_in}"
    );
    assert!(s.interface.is_none());
}

#[test]
fn summarize_interface_split_sums_to_the_final_energy() {
    let (chain, rec) = striker_run();
    let frames = views(&rec);
    let opts = SummaryOptions {
        interface: Some(50),
        ..Default::default()
    };
    let s = summarize(&chain, &frames, &opts).expect("summarizes");
    let i = s.interface.expect("interface split");
    assert_eq!((i.k, i.t), (50, 100.0));
    // left + right is the final frame's total energy (abs 1e-14, rel 1e-12).
    assert!(
        close(i.left + i.right, s.e_end, 1e-14, 1e-12),
        "{} + {} vs {}",
        i.left,
        i.right,
        s.e_end
    );
    // A uniform chain has no interface: the wave has passed bead 50 by t = 100, nearly all
    // its energy is right of it.
    let right = i.right_fraction().expect("fraction");
    assert!(right > 0.9 && right <= 1.0, "right fraction {right}");
    // The default fit range moves to k + 10.
    assert_eq!(s.fit_range.0, 60.0);
    assert!(i.v_in > 0.0, "v_in {}", i.v_in);
}

#[test]
fn summarize_rejects_a_bad_interface_no_frames_and_short_frames() {
    let (chain, rec) = striker_run();
    let frames = views(&rec);
    for k in [0, 100, 1000] {
        let opts = SummaryOptions {
            interface: Some(k),
            ..Default::default()
        };
        let e = summarize(&chain, &frames, &opts).expect_err("out of range");
        assert_eq!(e, SummaryError::Interface { k, n: 100 });
        assert_eq!(e.to_string(), "interface must be in 1..100");
    }
    let e = summarize(&chain, &[], &SummaryOptions::default()).expect_err("no frame");
    assert_eq!(e, SummaryError::NoFrames);
    let mut short = frames.clone();
    short[3].2 = &rec.v[3][..99];
    let e = summarize(&chain, &short, &SummaryOptions::default()).expect_err("short frame");
    assert_eq!(
        e.to_string(),
        "frame 3: v holds 99 values, the chain has 100 beads"
    );
}

#[test]
fn summarize_of_a_chain_at_rest_names_why_nothing_is_fitted() {
    let sc = common::striker(5, 2.5, 1.0, 0.0, 1.0);
    let (u, v) = (sc.u0.clone(), sc.v0.clone());
    let frames: Vec<FrameView<'_>> = vec![(0.0, &u, &v), (1.0, &u, &v)];
    let s = summarize(&sc.chain, &frames, &SummaryOptions::default()).expect("summarizes");
    assert_eq!(s.e_ref, 0.0);
    assert_eq!(s.relative_change(), None);
    assert!(s.track.is_empty());
    let why = s.speed.expect_err("no speed").to_string();
    assert!(why.contains("the chain has 5 beads, too few"), "{why}");
    assert!(s.decay.is_err() && s.e_in.is_err());
}
