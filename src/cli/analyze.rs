//! `beadchain analyze`: a one-screen summary of a snapshot (counts, energies, the leading
//! wave's speed and decay fit, the interface split), the per-frame leading-wave table with
//! `--frames`, or everything as JSON with `--json`. The computation is the library's
//! [`beadchain::analysis::summary`] ([`summarize`], also behind Python's `analyze()`); this file
//! reads the snapshot and formats the result; the collision rate and a gas's kinetic
//! temperature are [`super::analyze_gas`]'s.
//!
//! Energies are shown as fractions of the reference `E_ref = max(|E0|, S)`, with `S` the gross
//! energy scale of the first and last frames ([`beadchain::model::Chain::energy_scale`]: every
//! part counted positive), the scale `run` uses for its relative energy change
//! ([`beadchain::model::relative_energy_change`]). For a chain with only kinetic and contact
//! energy, `E_ref = E0`. The text output never prints a non-finite number or an empty range:
//! what cannot be computed is named with the reason.

use super::analyze_gas::GasReport;
use anyhow::{Context, Result};
use beadchain::analysis::summary::{ratio, InterfaceSplit};
use beadchain::analysis::{summarize, Summary, SummaryError, SummaryOptions};
use beadchain::scene::UnitScales;
use beadchain::snapshot::{Frame, Snapshot};
use std::fmt::Write as _;
use std::path::PathBuf;

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
    /// Also report the gas observables: kinetic temperature per frame, velocity distribution
    /// [default: only for a scene with walls and gaps].
    #[arg(long)]
    pub gas: bool,
}

fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:e}")
    } else {
        "null".into()
    }
}

/// `x` with `prec` decimals, or in scientific notation with `prec − 1` when its magnitude is
/// below 1e-3 (and not 0) or at least 1e6: a fraction of 9e-7 read `0.000001`, a fit prefactor
/// of 5e-128 `0.000000`, one of 3e55 a wall of 56 digits.
fn fixed(x: f64, prec: usize) -> String {
    if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e6) {
        format!("{x:.p$e}", p = prec.saturating_sub(1))
    } else {
        format!("{x:.prec$}")
    }
}

/// `x` formatted ([`fixed`]), or "not computed: `why`".
fn or_why(x: Option<f64>, prec: usize, why: &str) -> String {
    match x {
        Some(v) => fixed(v, prec),
        None => format!("not computed ({why})"),
    }
}

/// Runs `beadchain analyze`; returns the exit code.
pub fn cmd_analyze(args: AnalyzeArgs) -> Result<i32> {
    let (a, units, gas) = analyze(&args)?;
    let o = if args.json {
        json(&a, &super::analyze_gas::json(&gas))
    } else {
        let mut o = summary(&args, &a);
        if let Some(u) = units {
            let j = u.mass / (u.time * u.time);
            let _ = writeln!(
                o,
                "in SI: t = {:.6e} s to {:.6e} s, energy initial {:.6e} J, final {:.6e} J (time unit {:.6e} s, mass unit {:.6e} kg)",
                a.t_first * u.time,
                a.t_last * u.time,
                a.e0 * j,
                a.e_end * j,
                u.time,
                u.mass
            );
            let mut more = Vec::new();
            if let Ok(e) = &a.e_in {
                more.push(format!("incoming wave energy {:.6e} J", e * j));
            }
            if let Ok(v) = &a.speed {
                more.push(format!("speed {:.6e} beads per s", v.value / u.time));
            }
            if let Some(i) = &a.interface {
                more.push(format!(
                    "interface energy left {:.6e} J, right {:.6e} J",
                    i.left * j,
                    i.right * j
                ));
            }
            if !more.is_empty() {
                let _ = writeln!(o, "in SI: {}", more.join(", "));
            }
        }
        o.push_str(&super::analyze_gas::text(&gas, args.frames));
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

/// Reads the snapshot (every bead, both fields) and summarizes its frames and event log.
fn analyze(args: &AnalyzeArgs) -> Result<(Summary, Option<UnitScales>, GasReport)> {
    for (flag, x) in [("--fit-from", args.fit_from), ("--fit-to", args.fit_to)] {
        if let Some(x) = x.filter(|x| !x.is_finite()) {
            anyhow::bail!("{flag} {x}: expected a finite bead position");
        }
    }
    let snap =
        Snapshot::open(&args.snapshot).with_context(|| format!("{}", args.snapshot.display()))?;
    for w in snap.warnings() {
        eprintln!("beadchain: warning: {w}");
    }
    snap.require_full("analyze needs every bead and both fields (energies, leading wave)")?;
    let chain = &snap.header().scene.chain;
    let mut frames: Vec<Frame> = Vec::with_capacity(snap.frame_count());
    for k in 0..snap.frame_count() {
        frames.push(snap.frame(k)?);
    }
    let views: Vec<_> = frames
        .iter()
        .map(|f| (f.t, f.u.as_slice(), f.v.as_slice()))
        .collect();
    let opts = SummaryOptions {
        interface: args.interface,
        fit_from: args.fit_from,
        fit_to: args.fit_to,
    };
    let units = snap.header().scene.units;
    let summary = summarize(chain, &views, &opts).map_err(|e| match e {
        SummaryError::NoFrames => {
            anyhow::anyhow!("{}: the snapshot holds no frame", args.snapshot.display())
        }
        SummaryError::Interface { .. } => anyhow::anyhow!("--{e}"),
        other => anyhow::anyhow!("{}: {other}", args.snapshot.display()),
    })?;
    let gas = args.gas || super::analyze_gas::is_gas(chain);
    let gas = super::analyze_gas::report(&snap, &frames, gas);
    Ok((summary, units, gas))
}

fn summary(args: &AnalyzeArgs, a: &Summary) -> String {
    let mut o = String::new();
    let _ = writeln!(
        o,
        "{}: {} beads, {} frames, t = {} to {}",
        args.snapshot.display(),
        a.n,
        a.frames,
        a.t_first,
        a.t_last
    );
    let rel = a.relative_change();
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
        let why = if a.e0 > 0.0 {
            "the field's energy −Σ W·u, counted positive in E_ref, offsets it"
        } else {
            "it is not a positive total"
        };
        format!(
            "the energy scale E_ref = {:.6e} (not E0 = {:.6e}: {why})",
            a.e_ref, a.e0
        )
    };
    let _ = writeln!(o, "energy fractions below are of {scale_note}");
    leading_summary(&mut o, a);
    let frag = &a.fragmentation;
    let right_most: Vec<String> = frag
        .fragments
        .iter()
        .rev()
        .take(5)
        .map(|f| format!("{}..{}: {:.4e}", f.first, f.last, f.velocity))
        .collect();
    let _ = writeln!(
        o,
        "final state: {} open gaps, {} fragments{}, steady state (appendix A): {}",
        frag.gaps,
        frag.fragments.len(),
        if right_most.is_empty() {
            String::new()
        } else {
            format!(" (right-most: {})", right_most.join(", "))
        },
        if a.steady { "yes" } else { "no" }
    );
    if let Some(i) = &a.interface {
        iface_summary(&mut o, a, i);
    }
    o
}

fn leading_summary(o: &mut String, a: &Summary) {
    let no_ref = "energy scale 0";
    match (a.track.first(), a.track.last()) {
        (Some(p), Some(q)) => {
            let _ = writeln!(
                o,
                "leading wave (pulse: beads above 0.1% of its peak |v|; energy eq. 13): in {} of {} frames; last at t = {:.6e}: beads {} to {}, peak bead {} (v = {:.6e}), position {:.3}, energy {:.6e} ({} of E_ref)",
                a.track.len(),
                a.frames,
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
        match &a.e_in {
            Ok(e) => format!("{e:.9e} ({} of E_ref)", or_why(a.fraction(*e), 6, no_ref)),
            Err(why) => format!("not computed ({why})"),
        }
    );
    let (x0, x1) = a.fit_range;
    match &a.speed {
        Ok(s) => {
            let (c, m) = (s.value, s.points);
            let _ = writeln!(o, "speed: {c:.6e} beads per unit time (least squares over {m} frames, positions {x0} to {x1})");
        }
        Err(e) => {
            let _ = writeln!(o, "speed: not computed: {e}");
        }
    }
    match &a.decay {
        Ok(f) => {
            let _ = writeln!(
                o,
                "decay fit E/E_ref = a exp(-gamma x) over positions {x0} to {x1} ({} points): a = {}, gamma = {:.6e} +- {:.2e} per bead, R^2 = {:.4}",
                f.n, fixed(f.a, 6), f.gamma, f.gamma_stderr, f.r2
            );
        }
        Err(e) => {
            let _ = writeln!(o, "decay fit: not computed: {e}");
        }
    }
}

fn iface_summary(o: &mut String, a: &Summary, i: &InterfaceSplit) {
    let t = i.t;
    let why = "total energy 0";
    let _ = writeln!(
        o,
        "interface at bead {} (final frame t = {t}): E_left = {:.6e} ({} of total), E_right = {:.6e} ({})",
        i.k,
        i.left,
        or_why(i.left_fraction(), 6, why),
        i.right,
        or_why(i.right_fraction(), 6, why)
    );
    let _ = writeln!(
        o,
        "  largest reflected pulse: {}; |v_out/v_in| = {}",
        match i.reflected {
            Some(p) => format!(
                "beads {} to {}, energy {:.6e} ({} of E_ref)",
                p.first,
                p.last,
                i.reflected_energy,
                or_why(a.fraction(i.reflected_energy), 6, "energy scale 0")
            ),
            None => "none (no left-moving pulse left of the interface)".into(),
        },
        match i.velocity_ratio() {
            Ok(r) => format!(
                "{:.4e} / {:.4e} = {} ({})",
                i.v_out,
                i.v_in,
                fixed(r, 6),
                match i.velocity.sampling_error() {
                    0.0 => "the frames sample both peaks exactly".to_string(),
                    e => format!(
                        "relative error from the frames' sampling of the peaks: about {e:.0e}"
                    ),
                }
            ),
            Err(e) => format!("not computed ({e})"),
        }
    );
}

fn frames_table(a: &Summary) -> String {
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
            a.fraction(p.energy).map_or("-".into(), |r| fixed(r, 6))
        );
    }
    if a.track.is_empty() {
        o.push_str("(no frame has a right-moving pulse)\n");
    }
    o
}

fn json(a: &Summary, gas: &str) -> String {
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
        num(a.e0), num(a.e_end), num(a.e_ref), a.e_in.as_ref().map_or("null".into(), |e| num(*e)),
        a.fragmentation.gaps, a.fragmentation.fragments.len(), a.steady
    );
    if let Some(i) = &a.interface {
        let r = |x: Option<f64>| x.map_or("null".into(), num);
        let _ = write!(
            o,
            ",\n  \"interface\": {{\"k\": {}, \"t\": {}, \"energy_left\": {}, \"energy_right\": {}, \"reflected_fraction\": {}, \"reflected_wave_energy\": {}, \"v_in\": {}, \"v_out\": {}, \"velocity_ratio\": {}, \"velocity_ratio_error\": {}, \"velocity_ratio_sampling_error\": {}}}",
            i.k, num(i.t), num(i.left), num(i.right), r(i.left_fraction()), num(i.reflected_energy),
            num(i.v_in), num(i.v_out), r(i.velocity_ratio().ok()),
            i.velocity_ratio().err().map_or("null".into(), |e| format!("\"{e}\"")),
            r(i.velocity_ratio().ok().map(|_| i.velocity.sampling_error()))
        );
    }
    let (x0, x1) = a.fit_range;
    match &a.decay {
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
    match &a.speed {
        Ok(v) => {
            let _ = write!(
                o,
                ",\n  \"speed\": {{\"value\": {}, \"points\": {}}}",
                num(v.value),
                v.points
            );
        }
        Err(e) => {
            let _ = write!(o, ",\n  \"speed\": {{\"error\": \"{e}\"}}");
        }
    }
    o.push_str(gas);
    o.push_str("\n}\n");
    o
}
