//! `beadchain analyze`: a one-screen summary of a snapshot (counts, energies, the leading
//! wave's speed and decay fit, the interface split), the per-frame leading-wave table with
//! `--frames`, or everything as JSON with `--json` (library: `beadchain::analysis`).
//!
//! Energies are shown as fractions of the reference `E_ref = max(|E0|, S)`, with `S` the gross
//! energy scale of the first and last frames ([`beadchain::model::Chain::energy_scale`]: every
//! part counted positive), the scale `run` uses for its relative energy change
//! ([`beadchain::model::relative_energy_change`]). For a chain with only kinetic and contact
//! energy, `E_ref = E0`. The text output never prints a non-finite number or an empty range:
//! what cannot be computed is named with the reason.
//!
//! - Leading wave: the right-most right-moving pulse (eq. 13 energy), tracked per frame.
//! - Speed: least-squares slope of its energy-weighted position against time (beads per unit
//!   time), over the frames inside the fit range.
//! - Decay: `E/E_ref = a exp(−γ x)` over positions in `[fit-from, fit-to]` (at least
//!   [`MIN_FIT_POINTS`] frames).

use anyhow::{Context, Result};
use beadchain::analysis::{
    detect_pulses, energy_split, fit_exponential, fragmentation, is_steady_state, track_leading,
    velocity_ratio, wave_energy, ExpFit, TrackPoint, WaveOptions,
};
use beadchain::snapshot::{Frame, Snapshot};
use std::fmt::Write as _;
use std::path::PathBuf;

/// Fewest leading-wave points for the speed and decay fits.
pub const MIN_FIT_POINTS: usize = 3;

/// Arguments of `beadchain analyze`.
#[derive(clap::Args, Debug)]
pub struct AnalyzeArgs {
    /// Snapshot file.
    pub snapshot: PathBuf,
    /// Interface bead k: reflected/transmitted energy split and |v_out/v_in|.
    #[arg(long)]
    pub interface: Option<usize>,
    /// Print JSON instead of tables.
    #[arg(long)]
    pub json: bool,
    /// Also print the per-frame leading-wave table.
    #[arg(long)]
    pub frames: bool,
    /// Fit the decay over leading-wave positions >= this bead [default: 20, or k + 10].
    #[arg(long)]
    pub fit_from: Option<f64>,
    /// ... and <= this bead [default: N - 10].
    #[arg(long)]
    pub fit_to: Option<f64>,
}

/// The interface split (final frame).
struct Iface {
    k: usize,
    left: f64,
    right: f64,
    refl: Option<(usize, usize)>,
    e_refl: f64,
    v_in: f64,
    v_out: f64,
}

/// Everything `analyze` reports.
struct Analysis {
    n: usize,
    frames: Vec<Frame>,
    track: Vec<TrackPoint>,
    e0: f64,
    e_end: f64,
    e_ref: f64,
    range: (f64, f64),
    fit: Result<ExpFit, String>,
    speed: Result<(f64, usize), String>,
    e_in: Option<f64>,
    gaps: usize,
    fragment_count: usize,
    fragments: Vec<String>,
    steady: bool,
    iface: Option<Iface>,
}

fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:e}")
    } else {
        "null".into()
    }
}

/// `x / d` when `d > 0` (and the result is finite).
fn ratio(x: f64, d: f64) -> Option<f64> {
    let r = x / d;
    (d > 0.0 && r.is_finite()).then_some(r)
}

/// `x` formatted, or "not computed: `why`".
fn or_why(x: Option<f64>, prec: usize, why: &str) -> String {
    match x {
        Some(v) => format!("{v:.prec$}"),
        None => format!("not computed ({why})"),
    }
}

/// Runs `beadchain analyze`; returns the exit code.
pub fn cmd_analyze(args: AnalyzeArgs) -> Result<i32> {
    let a = analyze(&args)?;
    let o = if args.json {
        json(&a)
    } else {
        let mut o = summary(&args, &a);
        if args.frames {
            o.push_str(&frames_table(&a));
        } else {
            o.push_str("(per-frame leading-wave table: --frames)\n");
        }
        o
    };
    out!("{o}");
    Ok(0)
}

fn analyze(args: &AnalyzeArgs) -> Result<Analysis> {
    let snap =
        Snapshot::open(&args.snapshot).with_context(|| format!("{}", args.snapshot.display()))?;
    for w in snap.warnings() {
        eprintln!("beadchain: warning: {w}");
    }
    snap.require_full("analyze needs every bead and both fields (energies, leading wave)")?;
    let chain = snap.header().scene.chain.clone();
    let n = chain.len();
    let mut frames: Vec<Frame> = Vec::with_capacity(snap.frame_count());
    for k in 0..snap.frame_count() {
        frames.push(snap.frame(k)?);
    }
    let (first, last) = match (frames.first(), frames.last()) {
        (Some(f), Some(l)) => (f.clone(), l.clone()),
        _ => anyhow::bail!("the snapshot holds no frame"),
    };
    let k_if = args.interface.filter(|&k| k >= 1 && k < n);
    if args.interface.is_some() && k_if.is_none() {
        anyhow::bail!("--interface must be in 1..{n}");
    }
    let opts = WaveOptions::default();
    let e0 = chain.energy(&first.u, &first.v);
    let e_end = chain.energy(&last.u, &last.v);
    let e_ref = e0.abs().max(
        chain
            .energy_scale(&first.u, &first.v)
            .max(chain.energy_scale(&last.u, &last.v)),
    );
    let track = track_leading(
        &chain,
        frames.iter().map(|f| (f.t, f.u.as_slice(), f.v.as_slice())),
        &opts,
    );
    let x0 = args
        .fit_from
        .unwrap_or(k_if.map_or(20.0, |k| k as f64 + 10.0));
    let x1 = args.fit_to.unwrap_or(n as f64 - 10.0);
    let (fit, speed) = fits(&track, (x0, x1), e_ref, n);
    let e_in = incoming_energy(&track, k_if);
    let frag = fragmentation(&chain, &last.u, &last.v, 0.0);
    let steady = is_steady_state(&chain, &last.u, &last.v, 1e-5);
    let iface = k_if.map(|k| interface(&chain, &frames, &last, k, &opts));
    Ok(Analysis {
        n,
        track,
        e0,
        e_end,
        e_ref,
        range: (x0, x1),
        fit,
        speed,
        e_in,
        gaps: frag.gaps,
        fragment_count: frag.fragments.len(),
        fragments: frag
            .fragments
            .iter()
            .rev()
            .take(5)
            .map(|f| format!("{}..{}: {:.4e}", f.first, f.last, f.velocity))
            .collect(),
        steady,
        iface,
        frames,
    })
}

/// Incoming-wave energy: the leading wave once developed (position >= 10 beads, or k/2), in
/// the last frame before it reaches the interface `k` (or the first such frame without one).
fn incoming_energy(track: &[TrackPoint], k_if: Option<usize>) -> Option<f64> {
    let developed = k_if.map_or(10.0, |k| (k as f64 / 2.0).min(10.0));
    let mut before = track
        .iter()
        .filter(|p| p.position >= developed && k_if.is_none_or(|k| p.pulse.last + 2 < k));
    if k_if.is_some() {
        before.next_back()
    } else {
        before.next()
    }
    .map(|p| p.energy)
}

/// The energy split at bead `k` in the final frame, the largest reflected pulse, and the
/// velocity ratio over all frames.
fn interface(
    chain: &beadchain::model::Chain,
    frames: &[Frame],
    last: &Frame,
    k: usize,
    opts: &WaveOptions,
) -> Iface {
    let s = energy_split(chain, &last.u, &last.v, k);
    let vr = velocity_ratio(frames.iter().map(|f| f.v.as_slice()), k, (k / 2).min(20), 3);
    // reflected solitary wave: the largest left-moving pulse left of k in the final frame
    let refl = detect_pulses(&last.v, opts)
        .into_iter()
        .filter(|p| p.peak_velocity < 0.0 && p.last < k)
        .max_by(|a, b| a.peak_velocity.abs().total_cmp(&b.peak_velocity.abs()));
    Iface {
        k,
        left: s.left,
        right: s.right,
        refl: refl.map(|p| (p.first, p.last)),
        e_refl: refl.map_or(0.0, |p| {
            wave_energy(chain, &last.u, &last.v, p.first, p.last)
        }),
        v_in: vr.v_in,
        v_out: vr.v_out,
    }
}

/// The decay fit and the speed fit over the leading-wave points inside `[x0, x1]`; an error
/// names what could not be computed and why.
fn fits(
    track: &[TrackPoint],
    (x0, x1): (f64, f64),
    e_ref: f64,
    n: usize,
) -> (Result<ExpFit, String>, Result<(f64, usize), String>) {
    let defaults = "default: positions 20 (or k + 10) to N - 10; set --fit-from/--fit-to";
    // comparisons written so that NaN counts as "not ordered" / "not positive"
    let (ordered, end_inside, positive) = (x0 <= x1, x1 >= 0.0, e_ref > 0.0);
    let why = if !ordered && !end_inside {
        Some(format!(
            "the chain has {n} beads, too few for the fit range ({defaults})"
        ))
    } else if !ordered {
        Some(format!(
            "the fit range starts at position {x0}, after its end {x1} (chain of {n} beads; {defaults})"
        ))
    } else if !positive {
        Some("the energy scale is 0 (the chain is at rest)".to_string())
    } else {
        None
    };
    if let Some(w) = why {
        return (Err(w.clone()), Err(w));
    }
    let pts: Vec<&TrackPoint> = track
        .iter()
        .filter(|p| p.position >= x0 && p.position <= x1)
        .collect();
    if pts.len() < MIN_FIT_POINTS {
        let w = format!(
            "the leading wave is in positions {x0} to {x1} in {} of {} frames with a leading wave, fewer than {MIN_FIT_POINTS}",
            pts.len(),
            track.len()
        );
        return (Err(w.clone()), Err(w));
    }
    let x: Vec<f64> = pts.iter().map(|p| p.position).collect();
    let e: Vec<f64> = pts.iter().map(|p| p.energy / e_ref).collect();
    let fit = fit_exponential(&x, &e)
        .map_err(|e| e.to_string())
        .and_then(|f| {
            if [f.a, f.gamma, f.gamma_stderr, f.r2]
                .iter()
                .all(|v| v.is_finite())
            {
                Ok(f)
            } else {
                Err("the log-linear fit is degenerate (all points at one position)".into())
            }
        });
    let t: Vec<f64> = pts.iter().map(|p| p.t).collect();
    (fit, slope(&t, &x).map(|c| (c, pts.len())))
}

/// Least-squares slope of `y` against `x`.
fn slope(x: &[f64], y: &[f64]) -> Result<f64, String> {
    let m = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / m, y.iter().sum::<f64>() / m);
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let c = sxy / sxx;
    if sxx > 0.0 && c.is_finite() {
        Ok(c)
    } else {
        Err("all its frames are at one time".into())
    }
}

fn summary(args: &AnalyzeArgs, a: &Analysis) -> String {
    let mut o = String::new();
    let (f0, fl) = (&a.frames[0], &a.frames[a.frames.len() - 1]);
    let _ = writeln!(
        o,
        "{}: {} beads, {} frames, t = {} to {}",
        args.snapshot.display(),
        a.n,
        a.frames.len(),
        f0.t,
        fl.t
    );
    let rel = ratio((a.e_end - a.e0).abs(), a.e_ref);
    let _ = writeln!(
        o,
        "energy: initial {:.9e}, final {:.9e}, relative change {}",
        a.e0,
        a.e_end,
        rel.map_or_else(
            || format!(
                "not computed (energy scale 0), absolute change {:.3e}",
                (a.e_end - a.e0).abs()
            ),
            |r| format!("{r:.3e}")
        )
    );
    let scale_note = if a.e0 > 0.0 && a.e_ref - a.e0 <= 1e-6 * a.e_ref {
        "E0".to_string()
    } else if a.e_ref.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        "E_ref: none (the energy scale is 0: the chain is at rest), so they are not computed"
            .to_string()
    } else {
        format!(
            "the energy scale E_ref = {:.6e} (E0 = {:.6e} is not a positive total)",
            a.e_ref, a.e0
        )
    };
    let _ = writeln!(o, "energy fractions below are of {scale_note}");
    leading_summary(&mut o, a);
    let _ = writeln!(
        o,
        "final state: {} open gaps, {} fragments{}, steady state (appendix A): {}",
        a.gaps,
        a.fragment_count,
        if a.fragments.is_empty() {
            String::new()
        } else {
            format!(" (right-most: {})", a.fragments.join(", "))
        },
        if a.steady { "yes" } else { "no" }
    );
    if let Some(i) = &a.iface {
        iface_summary(&mut o, a, i, fl.t);
    }
    o
}

fn leading_summary(o: &mut String, a: &Analysis) {
    let no_ref = "energy scale 0";
    match (a.track.first(), a.track.last()) {
        (Some(p), Some(q)) => {
            let _ = writeln!(
                o,
                "leading wave (pulse: beads above 0.1% of its peak |v|; energy eq. 13): in {} of {} frames; last at t = {:.6e}: beads {} to {}, peak bead {} (v = {:.6e}), position {:.3}, energy {:.6e} ({} of E_ref)",
                a.track.len(),
                a.frames.len(),
                q.t,
                q.pulse.first,
                q.pulse.last,
                q.pulse.peak_bead,
                q.pulse.peak_velocity,
                q.position,
                q.energy,
                or_why(ratio(q.energy, a.e_ref), 6, no_ref)
            );
            let _ = writeln!(
                o,
                "  first seen at t = {:.6e}, position {:.3}",
                p.t, p.position
            );
        }
        _ => {
            let _ = writeln!(o, "leading wave: none (no frame has a right-moving pulse)");
        }
    }
    let _ = writeln!(
        o,
        "incoming wave energy: {}",
        match a.e_in {
            Some(e) => format!(
                "{e:.9e} ({} of E_ref)",
                or_why(ratio(e, a.e_ref), 6, no_ref)
            ),
            None =>
                "not computed (the leading wave never reaches 10 beads before the interface)".into(),
        }
    );
    let (x0, x1) = a.range;
    match &a.speed {
        Ok((c, m)) => {
            let _ = writeln!(o, "speed: {c:.6e} beads per unit time (least squares over {m} frames, positions {x0} to {x1})");
        }
        Err(e) => {
            let _ = writeln!(o, "speed: not computed: {e}");
        }
    }
    match &a.fit {
        Ok(f) => {
            let _ = writeln!(
                o,
                "decay fit E/E_ref = a exp(-gamma x) over positions {x0} to {x1} ({} points): a = {:.6}, gamma = {:.6e} +- {:.2e} per bead, R^2 = {:.4}",
                f.n, f.a, f.gamma, f.gamma_stderr, f.r2
            );
        }
        Err(e) => {
            let _ = writeln!(o, "decay fit: not computed: {e}");
        }
    }
}

fn iface_summary(o: &mut String, a: &Analysis, i: &Iface, t: f64) {
    let total = i.left + i.right;
    let why = "total energy 0";
    let _ = writeln!(
        o,
        "interface at bead {} (final frame t = {t}): E_left = {:.6e} ({} of total), E_right = {:.6e} ({})",
        i.k,
        i.left,
        or_why(ratio(i.left, total), 6, why),
        i.right,
        or_why(ratio(i.right, total), 6, why)
    );
    let _ = writeln!(
        o,
        "  largest reflected pulse: {}; |v_out/v_in| = {}",
        match i.refl {
            Some((p, q)) => format!(
                "beads {p} to {q}, energy {:.6e} ({} of E_ref)",
                i.e_refl,
                or_why(ratio(i.e_refl, a.e_ref), 6, "energy scale 0")
            ),
            None => "none (no left-moving pulse left of the interface)".into(),
        },
        match ratio(i.v_out, i.v_in.abs()) {
            Some(r) => format!("{:.4e} / {:.4e} = {r:.6}", i.v_out, i.v_in),
            None => "not computed (no incoming velocity before the interface)".into(),
        }
    );
}

fn frames_table(a: &Analysis) -> String {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "leading wave per frame (pulse: beads above 0.1% of its peak |v|; energy eq. 13 with 1/2 m v^2):"
    );
    let _ = writeln!(
        o,
        "{:>14} {:>6} {:>11} {:>5} {:>14} {:>14} {:>10}",
        "t", "peak", "position", "width", "peak v", "energy", "E/E_ref"
    );
    for p in &a.track {
        let _ = writeln!(
            o,
            "{:>14.6e} {:>6} {:>11.3} {:>5} {:>14.6e} {:>14.6e} {:>10}",
            p.t,
            p.pulse.peak_bead,
            p.position,
            p.pulse.width(),
            p.pulse.peak_velocity,
            p.energy,
            ratio(p.energy, a.e_ref).map_or("-".into(), |r| format!("{r:.6}"))
        );
    }
    if a.track.is_empty() {
        o.push_str("(no frame has a right-moving pulse)\n");
    }
    o
}

fn json(a: &Analysis) -> String {
    let mut o = String::from("{\n  \"leading_wave\": [");
    for (i, p) in a.track.iter().enumerate() {
        let _ = write!(
            o,
            "{}\n    {{\"t\": {}, \"peak_bead\": {}, \"first\": {}, \"last\": {}, \"position\": {}, \"peak_velocity\": {}, \"energy\": {}}}",
            if i > 0 { "," } else { "" },
            num(p.t), p.pulse.peak_bead, p.pulse.first, p.pulse.last,
            num(p.position), num(p.pulse.peak_velocity), num(p.energy)
        );
    }
    let _ = write!(
        o,
        "\n  ],\n  \"energy_initial\": {},\n  \"energy_final\": {},\n  \"energy_reference\": {},\n  \"wave_energy_in\": {},\n  \"gaps_final\": {},\n  \"fragments_final\": {},\n  \"steady_state_final\": {}",
        num(a.e0), num(a.e_end), num(a.e_ref), a.e_in.map_or("null".into(), num), a.gaps, a.fragment_count, a.steady
    );
    if let Some(i) = &a.iface {
        let t = a.frames[a.frames.len() - 1].t;
        let total = i.left + i.right;
        let r = |x: Option<f64>| x.map_or("null".into(), num);
        let _ = write!(
            o,
            ",\n  \"interface\": {{\"k\": {}, \"t\": {}, \"energy_left\": {}, \"energy_right\": {}, \"reflected_fraction\": {}, \"reflected_wave_energy\": {}, \"v_in\": {}, \"v_out\": {}, \"velocity_ratio\": {}}}",
            i.k, num(t), num(i.left), num(i.right), r(ratio(i.left, total)), num(i.e_refl),
            num(i.v_in), num(i.v_out), r(ratio(i.v_out, i.v_in.abs()))
        );
    }
    let (x0, x1) = a.range;
    match &a.fit {
        Ok(f) => {
            let _ = write!(
                o,
                ",\n  \"decay_fit\": {{\"from\": {}, \"to\": {}, \"points\": {}, \"a\": {}, \"gamma\": {}, \"gamma_stderr\": {}, \"r2\": {}}}",
                num(x0), num(x1), f.n, num(f.a), num(f.gamma), num(f.gamma_stderr), num(f.r2)
            );
        }
        Err(e) => {
            let _ = write!(o, ",\n  \"decay_fit\": {{\"error\": \"{e}\"}}");
        }
    }
    o.push_str("\n}\n");
    o
}
