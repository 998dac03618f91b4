//! `beadchain breather SCENE --frequency W`: a discrete breather of the scene's chain by
//! shooting on the period map, continued in frequency from a linear mode, its Floquet
//! multipliers, and the solution as a scene (library: [`beadchain::experiments::breather`],
//! [`beadchain::experiments::floquet`]).

use super::common::load_scene;
use anyhow::{anyhow, bail, Result};
use beadchain::experiments::breather::{continue_to, Breather, Shooter};
use beadchain::experiments::floquet::floquet;
use std::path::PathBuf;

/// Arguments of `beadchain breather`.
#[derive(clap::Args, Debug)]
pub struct BreatherArgs {
    /// Scene file or preset name (a conservative chain of soft contacts with walls).
    pub scene: String,
    /// Target angular frequency (computer units), e.g. in a band gap.
    #[arg(long)]
    pub frequency: f64,
    /// The linear mode the branch starts from (index, 0 = lowest) [default: the mode whose
    /// frequency is nearest the target].
    #[arg(long)]
    pub mode: Option<usize>,
    /// Starting amplitude: the displacement of the mode's largest bead from equilibrium.
    #[arg(long, default_value = "1e-3")]
    pub seed_amplitude: f64,
    /// Largest frequency step of the continuation (halved where Newton fails).
    #[arg(long, default_value = "0.02")]
    pub step: f64,
    /// Newton's tolerance on max |v(T/2)|.
    #[arg(long, default_value = "1e-11")]
    pub tol: f64,
    /// Relative tolerance of the dense engine (DOP853) for the period map.
    #[arg(long, default_value = "1e-12")]
    pub rtol: f64,
    /// Skip the Floquet multipliers (4N runs of one period).
    #[arg(long)]
    pub no_floquet: bool,
    /// Print every multiplier, not only the summary.
    #[arg(long)]
    pub list: bool,
    /// Write the breather as a scene (TOML: the base scene with the breather's initial state,
    /// the dense engine at --rtol, `until` = --periods periods).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Periods the saved scene runs for.
    #[arg(long, default_value = "100")]
    pub periods: f64,
}

fn check_args(a: &BreatherArgs) -> Result<()> {
    let pos = |x: f64| x.is_finite() && x > 0.0;
    if !pos(a.frequency) {
        bail!(
            "--frequency {}: expected a finite frequency > 0",
            a.frequency
        );
    }
    for (name, x) in [
        ("--seed-amplitude", a.seed_amplitude),
        ("--step", a.step),
        ("--tol", a.tol),
        ("--rtol", a.rtol),
        ("--periods", a.periods),
    ] {
        if !pos(x) {
            bail!("{name} {x}: expected a finite value > 0");
        }
    }
    Ok(())
}

/// The mode nearest the target frequency.
fn nearest_mode(sh: &Shooter, w: f64) -> Result<usize> {
    let mut best = (0, f64::INFINITY);
    for k in 0..sh.len() {
        let (wk, _) = sh.mode(k).map_err(|e| anyhow!("{e}"))?;
        if (wk - w).abs() < best.1 {
            best = (k, (wk - w).abs());
        }
    }
    Ok(best.0)
}

/// `beadchain breather`.
pub fn cmd_breather(a: BreatherArgs) -> Result<i32> {
    check_args(&a)?;
    let scene = load_scene(&a.scene)?;
    if let Some(p) = &a.out {
        let inputs = super::files::labelled_scene_inputs(&a.scene);
        super::files::check_output_before_work(p, "--out", &inputs)?;
    }
    let sh = Shooter::new(&scene, a.rtol).map_err(|e| anyhow!("{e}"))?;
    let k = match a.mode {
        Some(k) => k,
        None => nearest_mode(&sh, a.frequency)?,
    };
    let (wk, _) = sh.mode(k).map_err(|e| anyhow!("{}: {e}", scene.name))?;
    outln!(
        "breather of {}: {} beads, from linear mode {k} (omega {wk:.9}) to omega {}",
        scene.name,
        sh.len(),
        a.frequency
    );
    let start = sh.from_mode(k, a.seed_amplitude, a.tol).map_err(|e| {
        let advice = if e.to_string().contains("did not converge") {
            " (a smaller --seed-amplitude starts nearer the linear mode)"
        } else {
            ""
        };
        anyhow!(
            "{}: seed at amplitude {}: {e}{advice}",
            scene.name,
            a.seed_amplitude
        )
    })?;
    outln!(
        "seed: amplitude {:.3e}, omega {:.12} (mode {wk:.12}: shift {:.3e})",
        a.seed_amplitude,
        start.frequency(),
        start.frequency() - wk
    );
    let path =
        continue_to(&sh, start, wk, a.frequency, a.step, a.tol).map_err(|e| anyhow!("{e}"))?;
    let b = &path[path.len() - 1];
    report(&sh, b, path.len() - 1)?;
    if !a.no_floquet {
        report_floquet(&sh, b, a.list)?;
    }
    if let Some(p) = &a.out {
        let text = beadchain::scene::show::to_toml(&sh.scene_of(b, a.periods, 20));
        super::files::clean_stale_temps(p);
        beadchain::snapshot::write_atomically(p, |w| {
            std::io::Write::write_all(w, text.as_bytes()).map_err(|e| {
                beadchain::snapshot::SnapshotError::Io {
                    path: p.clone(),
                    action: "write".to_string(),
                    source: e,
                }
            })
        })?;
        outln!(
            "wrote {} (beadchain run {} runs it)",
            p.display(),
            p.display()
        );
    }
    Ok(0)
}

/// The solution's lines: frequency, period, energy, amplitude, localisation, residuals.
fn report(sh: &Shooter, b: &Breather, steps: usize) -> Result<()> {
    let res = sh.period_residual(b).map_err(|e| anyhow!("{e}"))?;
    let du: Vec<f64> = b.u.iter().zip(&sh.u_eq).map(|(u, e)| u - e).collect();
    let centre = (0..du.len())
        .max_by(|&i, &j| du[i].abs().total_cmp(&du[j].abs()))
        .unwrap_or(0);
    outln!(
        "solution: omega {:.12}, period {:.12} after {steps} continuation steps ({} engine runs)",
        b.frequency(),
        b.period,
        sh.runs.get()
    );
    outln!(
        "amplitude {:.6e} (bead {centre}), participation ratio {:.4}, energy above equilibrium {:.6e}",
        sh.amplitude(&b.u),
        beadchain::studies::modes::participation_ratio(&du),
        sh.energy_above_equilibrium(&b.u)
    );
    outln!(
        "residuals: half-period max|v(T/2)| {:.3e}, period map max|x(T) - x(0)| {res:.3e}",
        b.half_residual
    );
    Ok(())
}

/// The Floquet lines: stability, largest modulus, reciprocity, the pair at 1.
fn report_floquet(sh: &Shooter, b: &Breather, list: bool) -> Result<()> {
    let f = floquet(sh, b, 1e-5).map_err(|e| anyhow!("{e}"))?;
    let (mean, prod) = f.unit_pair_error();
    outln!(
        "Floquet multipliers: {} ({}), largest |lambda| other than the pair at 1: {:.12}",
        f.multipliers.len(),
        if f.stable(1e-6) {
            "linearly stable: all on the unit circle to 1e-6"
        } else {
            "unstable: a multiplier off the unit circle"
        },
        f.max_modulus()
    );
    outln!(
        "reciprocal pairs to {:.3e}; pair at 1: |mean - 1| {mean:.3e}, |product - 1| {prod:.3e}; |M xdot - xdot|/|xdot| {:.3e}, |gradH M - gradH|/|gradH| {:.3e}",
        f.reciprocity_error(),
        f.flow_residual,
        f.energy_residual
    );
    if list {
        outln!("re  im  modulus");
        for (re, im) in &f.multipliers {
            outln!("{re:.12e} {im:.12e} {:.12}", re.hypot(*im));
        }
    }
    Ok(())
}
