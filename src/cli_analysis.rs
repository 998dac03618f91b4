//! `beadchain analyze`: leading-wave table, energies, interface split and decay fit of a
//! snapshot (library: `beadchain::analysis`).

use anyhow::{Context, Result};
use beadchain::analysis::{
    detect_pulses, energy_split, fit_exponential, fragmentation, is_steady_state, track_leading,
    velocity_ratio, wave_energy, WaveOptions,
};
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
    /// Fit the decay over leading-wave positions >= this bead [default: 20, or k + 10].
    #[arg(long)]
    pub fit_from: Option<f64>,
    /// ... and <= this bead [default: N - 10].
    #[arg(long)]
    pub fit_to: Option<f64>,
}

fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:e}")
    } else {
        "null".into()
    }
}

/// Runs `beadchain analyze`; returns the exit code.
pub fn cmd_analyze(args: AnalyzeArgs) -> Result<i32> {
    let snap =
        Snapshot::open(&args.snapshot).with_context(|| format!("{}", args.snapshot.display()))?;
    for w in snap.warnings() {
        eprintln!("beadchain: warning: {w}");
    }
    let chain = snap.header().scene.chain.clone();
    let n = chain.len();
    let mut frames: Vec<Frame> = Vec::with_capacity(snap.frame_count());
    for k in 0..snap.frame_count() {
        frames.push(snap.frame(k)?);
    }
    let last = frames
        .last()
        .context("the snapshot holds no frame")?
        .clone();
    let opts = WaveOptions::default();
    let e0 = chain.energy(&frames[0].u, &frames[0].v);
    let e_end = chain.energy(&last.u, &last.v);
    let track = track_leading(
        &chain,
        frames.iter().map(|f| (f.t, f.u.as_slice(), f.v.as_slice())),
        &opts,
    );
    // incoming-wave energy: the leading wave's largest energy before the interface (or overall)
    let k_if = args.interface.filter(|&k| k >= 1 && k < n);
    if args.interface.is_some() && k_if.is_none() {
        anyhow::bail!("--interface must be in 1..{n}");
    }
    let x0 = args
        .fit_from
        .unwrap_or(k_if.map_or(20.0, |k| k as f64 + 10.0));
    let x1 = args.fit_to.unwrap_or(n as f64 - 10.0);
    let pts: Vec<_> = track
        .iter()
        .filter(|p| p.position >= x0 && p.position <= x1)
        .collect();
    let fit = fit_exponential(
        &pts.iter().map(|p| p.position).collect::<Vec<_>>(),
        &pts.iter().map(|p| p.energy / e0).collect::<Vec<_>>(),
    );
    // incoming-wave energy: the leading wave once developed (position >= 10 beads, or k/2), in
    // the last frame before it reaches the interface (or the first such frame without one)
    let developed = k_if.map_or(10.0, |k| (k as f64 / 2.0).min(10.0));
    let mut before = track
        .iter()
        .filter(|p| p.position >= developed && k_if.is_none_or(|k| p.pulse.last + 2 < k));
    let e_in = if k_if.is_some() {
        before.next_back()
    } else {
        before.next()
    }
    .map_or(f64::NAN, |p| p.energy);
    let frag = fragmentation(&chain, &last.u, &last.v, 0.0);
    let steady = is_steady_state(&chain, &last.u, &last.v, 1e-5);

    let mut o = String::new();
    let j = args.json;
    if j {
        o.push_str("{\n  \"leading_wave\": [");
        for (i, p) in track.iter().enumerate() {
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
            "\n  ],\n  \"energy_initial\": {},\n  \"energy_final\": {},\n  \"wave_energy_in\": {},\n  \"gaps_final\": {},\n  \"fragments_final\": {},\n  \"steady_state_final\": {}",
            num(e0), num(e_end), num(e_in), frag.gaps, frag.fragments.len(), steady
        );
    } else {
        let _ = writeln!(
            o,
            "{}: {} beads, {} frames, t = {} .. {}",
            args.snapshot.display(),
            n,
            frames.len(),
            frames[0].t,
            last.t
        );
        let _ = writeln!(
            o,
            "leading wave (pulse: beads above 0.1% of its peak |v|; energy eq. 13 with 1/2 m v^2):"
        );
        let _ = writeln!(
            o,
            "{:>14} {:>6} {:>11} {:>5} {:>14} {:>14} {:>10}",
            "t", "peak", "position", "width", "peak v", "energy", "E/E0"
        );
        for p in &track {
            let _ = writeln!(
                o,
                "{:>14.6e} {:>6} {:>11.3} {:>5} {:>14.6e} {:>14.6e} {:>10.6}",
                p.t,
                p.pulse.peak_bead,
                p.position,
                p.pulse.width(),
                p.pulse.peak_velocity,
                p.energy,
                p.energy / e0
            );
        }
        let _ = writeln!(
            o,
            "energy: initial {e0:.9e}, final {e_end:.9e} (relative change {:.3e}); incoming wave {e_in:.9e} ({:.6} of E0)",
            beadchain::model::relative_energy_change(
                e0,
                e_end,
                chain
                    .energy_scale(&frames[0].u, &frames[0].v)
                    .max(chain.energy_scale(&last.u, &last.v))
            ),
            e_in / e0
        );
        let vmax: Vec<String> = frag
            .fragments
            .iter()
            .rev()
            .take(5)
            .map(|f| format!("{}..{}: {:.4e}", f.first, f.last, f.velocity))
            .collect();
        let _ = writeln!(
            o,
            "final state: {} open gaps, {} fragments (right-most: {}), steady state (appendix A): {}",
            frag.gaps,
            frag.fragments.len(),
            vmax.join(", "),
            if steady { "yes" } else { "no" }
        );
    }
    if let Some(k) = k_if {
        let s = energy_split(&chain, &last.u, &last.v, k);
        let vr = velocity_ratio(frames.iter().map(|f| f.v.as_slice()), k, (k / 2).min(20), 3);
        // reflected solitary wave: the left-most left-moving pulse in the final frame
        let refl = detect_pulses(&last.v, &opts)
            .into_iter()
            .filter(|p| p.peak_velocity < 0.0 && p.last < k)
            .max_by(|a, b| a.peak_velocity.abs().total_cmp(&b.peak_velocity.abs()));
        let e_refl_wave = refl.map_or(0.0, |p| {
            wave_energy(&chain, &last.u, &last.v, p.first, p.last)
        });
        if j {
            let _ = write!(
                o,
                ",\n  \"interface\": {{\"k\": {k}, \"t\": {}, \"energy_left\": {}, \"energy_right\": {}, \"reflected_fraction\": {}, \"reflected_wave_energy\": {}, \"v_in\": {}, \"v_out\": {}, \"velocity_ratio\": {}}}",
                num(last.t), num(s.left), num(s.right), num(s.left / s.total()), num(e_refl_wave),
                num(vr.v_in), num(vr.v_out), num(vr.ratio())
            );
        } else {
            let _ = writeln!(
                o,
                "interface at bead {k} (final frame t = {}): E_left = {:.6e} ({:.6} of total), E_right = {:.6e} ({:.6})",
                last.t,
                s.left,
                s.left / s.total(),
                s.right,
                s.right / s.total()
            );
            let _ = writeln!(
                o,
                "  largest reflected pulse: energy {:.6e} ({:.6} of E0){}; |v_out/v_in| = {:.4e} / {:.4e} = {:.6}",
                e_refl_wave,
                e_refl_wave / e0,
                refl.map_or(String::new(), |p| format!(", beads {}..{}", p.first, p.last)),
                vr.v_out,
                vr.v_in,
                vr.ratio()
            );
        }
    }
    match (&fit, j) {
        (Ok(f), true) => {
            let _ = write!(
                o,
                ",\n  \"decay_fit\": {{\"from\": {}, \"to\": {}, \"points\": {}, \"a\": {}, \"gamma\": {}, \"gamma_stderr\": {}, \"r2\": {}}}",
                num(x0), num(x1), f.n, num(f.a), num(f.gamma), num(f.gamma_stderr), num(f.r2)
            );
        }
        (Err(e), true) => {
            let _ = write!(o, ",\n  \"decay_fit\": {{\"error\": \"{e}\"}}");
        }
        (Ok(f), false) => {
            let _ = writeln!(
                o,
                "decay fit E/E0 = a exp(-gamma x) over positions {x0}..{x1} ({} points): a = {:.6}, gamma = {:.6e} +- {:.2e} per bead, R^2 = {:.4}",
                f.n, f.a, f.gamma, f.gamma_stderr, f.r2
            );
        }
        (Err(e), false) => {
            let _ = writeln!(o, "decay fit over positions {x0}..{x1}: {e}");
        }
    }
    if j {
        o.push_str("\n}\n");
    }
    out!("{o}");
    Ok(0)
}

/// Arguments of `beadchain validate`.
#[derive(clap::Args, Debug)]
pub struct ValidateArgs {
    /// Run the reduced checks (a few seconds); the full report is
    /// `cargo bench --bench paper_validation -- all` (validation/REPORT.md).
    #[arg(long)]
    pub quick: bool,
    /// Directory for `quick.md` (the table; deterministic).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs `beadchain validate --quick`; exit code 1 when a check is outside its range.
pub fn cmd_validate(args: ValidateArgs) -> Result<i32> {
    use beadchain::analysis::quick::{checks_markdown, quick_checks};
    if !args.quick {
        anyhow::bail!(
            "only --quick is implemented here; the full report: cargo bench --bench paper_validation -- all (see validation/REPORT.md)"
        );
    }
    let t0 = std::time::Instant::now();
    let checks = quick_checks(false)?;
    let table = checks_markdown(&checks);
    out!("{table}");
    if let Some(dir) = &args.out {
        std::fs::create_dir_all(dir).with_context(|| format!("{}", dir.display()))?;
        let path = dir.join("quick.md");
        std::fs::write(&path, &table).with_context(|| format!("{}", path.display()))?;
        outln!("wrote {}", path.display());
    }
    let failed = checks.iter().filter(|c| !c.pass()).count();
    outln!(
        "{} checks, {failed} outside their range, {:.1} s",
        checks.len(),
        t0.elapsed().as_secs_f64()
    );
    Ok(i32::from(failed > 0))
}
