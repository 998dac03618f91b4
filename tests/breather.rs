//! Discrete breathers (issue 35, part 4): half-period shooting with the dense engine, the
//! continuation from a linear mode, the period map's residual and the Floquet multipliers
//! (`beadchain::experiments::breather`, `::floquet`).
//!
//! A 12-bead precompressed dimer chain (masses 1 and 0.5, n = 2.5, every contact at force 0.1,
//! soft walls: the `dimer_dispersion` preset, shorter) keeps every test a few seconds.

use beadchain::engine::{run, Recorder, RunConfig};
use beadchain::experiments::breather::{continue_to, max_diff, Breather, Shooter};
use beadchain::experiments::floquet::floquet;
use beadchain::scene::{parse::parse_str, preset, Scene};
use beadchain::studies::modes::participation_ratio;
use std::path::Path;

fn dimer(beads: usize) -> Scene {
    let text = format!(
        "[scene]\nname = \"dimer{beads}\"\n[chain]\nbeads = {beads}\nmass = {{ alternate = [1.0, 0.5] }}\n\
         precompression_force = 0.1\n[walls]\nleft = {{}}\nright = {{}}\n[initial]\nequilibrium = true\n\
         [run]\nuntil = 10.0\n"
    );
    parse_str(&text, Path::new("."), "test").expect("dimer scene")
}

/// The lowest optical mode (index N/2): the lower edge of the optical band of a finite chain.
fn optical_edge(sh: &Shooter) -> (usize, f64) {
    let k = sh.len() / 2;
    (k, sh.mode(k).unwrap().0)
}

#[test]
fn small_amplitude_frequency_tends_to_the_band_edge() {
    let sc = dimer(12);
    let sh = Shooter::new(&sc, 1e-12).unwrap();
    let (k, wk) = optical_edge(&sh);
    let mut shifts = Vec::new();
    for amp in [1e-3, 2e-3, 4e-3] {
        let b = sh.from_mode(k, amp, 1e-12).unwrap();
        let shift = b.frequency() - wk;
        eprintln!(
            "amp {amp:e}: omega {:.12} (mode {wk:.12}), shift {shift:.3e}, it {}",
            b.frequency(),
            b.iterations
        );
        shifts.push(shift);
    }
    // Soft nonlinearity: the frequency falls into the gap, the shift ∝ A² (ratio 4 per doubling,
    // within 10 %), so it tends to the mode's frequency as A → 0.
    assert!(shifts.iter().all(|s| *s < 0.0), "shifts {shifts:?}");
    for w in shifts.windows(2) {
        let r = w[1] / w[0];
        assert!((r - 4.0).abs() < 0.4, "shift ratio {r} (expected 4 ± 0.4)");
    }
}

/// The gap breather of the 16-bead dimer at omega = 2.25 (below the finite chain's lowest
/// optical mode 2.2744 and the infinite chain's optical edge 2.2649: in the gap), continued from
/// the lowest optical mode in steps of 0.01.
fn gap_breather() -> (Shooter, Breather, f64) {
    let sh = Shooter::new(&dimer(16), 1e-12).unwrap();
    let (k, wk) = optical_edge(&sh);
    let start = sh.from_mode(k, 1e-3, 1e-11).unwrap();
    let path = continue_to(&sh, start, wk, 2.25, 0.01, 1e-11).unwrap();
    let b = path.last().unwrap().clone();
    (sh, b, wk)
}

#[test]
fn gap_breather_is_periodic_localised_and_stable() {
    let (sh, b, wk) = gap_breather();
    let res = sh.period_residual(&b).unwrap();
    let amp = sh.amplitude(&b.u);
    let du: Vec<f64> = b.u.iter().zip(&sh.u_eq).map(|(u, e)| u - e).collect();
    let (pr, pr_mode) = (
        participation_ratio(&du),
        participation_ratio(&sh.mode(sh.len() / 2).unwrap().1),
    );
    eprintln!("omega {:.12} (edge {wk:.6}), amplitude {amp:.4e}, residual {res:.3e}, participation {pr:.4} (mode {pr_mode:.4}), runs {}", b.frequency(), sh.runs.get());
    assert!(
        (b.frequency() - 2.25).abs() < 1e-12,
        "omega {}",
        b.frequency()
    );
    // The full period map returns to the start (max-norm over u and v).
    assert!(res <= 1e-10, "period-map residual {res:.3e} > 1e-10");
    // A breather, not the trivial state: amplitude grown from 1e-3, more localised than the mode.
    assert!(amp > 0.05, "amplitude {amp:e}");
    assert!(
        pr < 0.8 * pr_mode,
        "participation {pr} vs the mode's {pr_mode}"
    );
    let f = floquet(&sh, &b, 1e-5).unwrap();
    let (mean, prod) = f.unit_pair_error();
    eprintln!("reciprocity {:.3e}, unit pair mean {mean:.3e} product {prod:.3e}, flow {:.3e}, energy {:.3e}, max|λ| {:.12}", f.reciprocity_error(), f.flow_residual, f.energy_residual, f.max_modulus());
    assert_eq!(f.multipliers.len(), 32);
    assert!(
        f.reciprocity_error() <= 1e-8,
        "reciprocity {:.3e}",
        f.reciprocity_error()
    );
    assert!(
        mean <= 1e-8 && prod <= 1e-8,
        "pair at 1: mean {mean:.3e}, product {prod:.3e}"
    );
    // The pair at 1 is a Jordan block: its two computed values split by about the square root
    // of the monodromy's error (1 ± 6.5e-6i), so it is checked by what is well conditioned: its
    // mean and product (above) and its two vectors, the time shift (right: M ẋ = ẋ, measured
    // 2.7e-10) and the energy (left: ∇Hᵀ M = ∇Hᵀ, measured 1.5e-10), each to 1e-8 (the time
    // shift's was 1e-7, measured 3.5e-9, when ẋ came from a short run instead of the forces).
    assert!(
        f.flow_residual <= 1e-8,
        "M xdot - xdot: {:.3e}",
        f.flow_residual
    );
    assert!(
        f.energy_residual <= 1e-8,
        "gradH M - gradH: {:.3e}",
        f.energy_residual
    );
    assert!(f.stable(1e-6), "max |λ| = {}", f.max_modulus());
}

#[test]
fn stable_breather_returns_after_100_periods() {
    let (sh, b, _) = gap_breather();
    let zero = vec![0.0; b.u.len()];
    let (u, v) = sh.flow(&b.u, &zero, 100.0 * b.period).unwrap();
    let d = max_diff(&u, &b.u).max(max_diff(&v, &zero));
    eprintln!("after 100 periods: {d:.3e}");
    assert!(
        d <= 1e-8,
        "after 100 periods the state is {d:.3e} from the start"
    );
}

#[test]
fn the_linear_seed_is_not_periodic_at_large_amplitude() {
    // The checks can fail: the linear mode scaled to the breather's amplitude, with the linear
    // period, is far from periodic (residual > 1e-4), and Newton's correction is what closes it.
    let (sh, b, wk) = gap_breather();
    let (_, x) = sh.mode(sh.len() / 2).unwrap();
    let amp = sh.amplitude(&b.u);
    let xm = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let u: Vec<f64> = (0..x.len()).map(|i| sh.u_eq[i] + amp * x[i] / xm).collect();
    let seed = Breather {
        u,
        period: 2.0 * std::f64::consts::PI / wk,
        half_residual: 0.0,
        iterations: 0,
    };
    let res = sh.period_residual(&seed).unwrap();
    eprintln!("linear seed residual {res:.3e}");
    assert!(res > 1e-4, "residual of the linear seed {res:.3e}");
}

/// The `dimer_gap_breather` preset (this file's 16-bead gap breather at omega = 2.25, stored as
/// explicit displacements) run as written (dense engine, DOP853, rtol 1e-12, 20 frames a
/// period): one period in (frame 20) the state equals the start within 1e-10 (max-norm over u and
/// v; measured 5e-13) and after 100 periods (the last frame) within 1e-8, while half a period in
/// it is more than 1e-2 away (the check discriminates). Its displacements are the breather this
/// file computes, within 1e-9.
#[test]
fn preset_gap_breather_runs_periodic() {
    let s = preset("dimer_gap_breather").expect("preset");
    let mut rec = Recorder::default();
    run(&s, &RunConfig::from_scene(&s), &mut rec).expect("run");
    let period = 2.0 * std::f64::consts::PI / 2.25;
    assert_eq!(rec.t.len(), 2001);
    let dist = |k: usize| max_diff(&rec.u[k], &rec.u[0]).max(max_diff(&rec.v[k], &rec.v[0]));
    let (one, hundred, half) = (dist(20), dist(2000), dist(10));
    eprintln!("after 1 period {one:.3e}, 100 periods {hundred:.3e}, half a period {half:.3e}");
    assert!(
        (rec.t[20] - period).abs() <= 1e-12 * period,
        "t {}",
        rec.t[20]
    );
    assert!((rec.t[2000] - 100.0 * period).abs() <= 1e-12 * 100.0 * period);
    assert!(one <= 1e-10, "after one period: {one:.3e}");
    assert!(hundred <= 1e-8, "after 100 periods: {hundred:.3e}");
    assert!(half > 1e-2, "half a period: {half:.3e}");
    let (_, b, _) = gap_breather();
    let d = max_diff(&s.u0, &b.u);
    assert!(d <= 1e-9, "preset vs computed breather: {d:.3e}");
}
