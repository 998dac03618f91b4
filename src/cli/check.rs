//! `beadchain check`: prints the report of [`beadchain::check`] and its verdict.

use super::common::{config, overrides, Common};
use anyhow::{Context, Result};
use beadchain::check::{check_with_progress, CheckReport};
use beadchain::engine::RunConfig;
use beadchain::names::Named;
use beadchain::scene::Scene;

/// Arguments of `beadchain check`.
#[derive(clap::Args, Debug)]
pub struct CheckArgs {
    #[command(flatten)]
    pub common: Common,
    /// Allowed trajectory deviation, relative to the largest |v| (for u: to the largest |u|
    /// change), when the scene is not more sensitive than that [default: 1000·rtol].
    #[arg(long)]
    pub tol: Option<f64>,
}

/// Runs `beadchain check`; returns the exit code (1 when the engines disagree).
pub fn cmd_check(a: CheckArgs) -> Result<i32> {
    let p = super::common::load_scene_with_material(&a.common.scene)?;
    let scene = p.scene;
    let base = config(&scene, &overrides(&scene, &a.common)?);
    super::common::warn_implausible(&scene, p.material.as_ref(), p.until_key, &base, &a.common);
    let given = (false, a.common.method.is_some());
    super::common::check_config(&a.common.scene, &scene, &base, given)?;
    if let Some(t) = a.tol.filter(|t| !(t.is_finite() && *t > 0.0)) {
        anyhow::bail!("--tol {t}: expected a finite relative deviation > 0");
    }
    let tol = a.tol.unwrap_or(1000.0 * base.rtol);
    compare(&scene, &base, tol, a.common.quiet)
}

fn print_report(scene: &Scene, cfg: &RunConfig, rep: &CheckReport) -> Result<()> {
    let (h, r) = &rep.runs;
    let dev = &rep.deviation;
    let (umax, vmax) = dev.scale;
    outln!(
        "{}: {} beads, t = {}, method {}, rtol {:e}, atol {:e}; reference: {}",
        scene.name,
        scene.chain.len(),
        cfg.until,
        cfg.method.name(),
        cfg.rtol,
        cfg.atol,
        rep.reference
    );
    let tight = if rep.hybrid_spread.is_some() {
        " at rtol/100"
    } else {
        ""
    };
    let (of_u, of_v, rel) = if rep.at_rest {
        (
            "the length scale",
            "the velocity scale",
            "relative to L, V: the chain is at rest",
        )
    } else {
        (
            "the largest displacement",
            "the largest velocity",
            "relative u, v",
        )
    };
    outln!(
        "max |u_hybrid - u_ref{}| = {:.3e} at bead {} ({:.3e} of {of_u} {umax:.3e})",
        tight,
        dev.du.0,
        dev.du.1,
        dev.rel_u
    );
    outln!(
        "max |v_hybrid - v_ref{}| = {:.3e} at bead {} ({:.3e} of {of_v} {vmax:.3e})",
        tight,
        dev.dv.0,
        dev.dv.1,
        dev.rel_v
    );
    let s = rep.sensitivity.rel_u.max(rep.sensitivity.rel_v);
    outln!(
        "sensitivity: the reference at rtol and at rtol/100 differ by {s:.3e} ({rel}), {:.1e} x rtol",
        s / rep.rtol
    );
    outln!(
        "energy error: hybrid {:.3e}, reference {:.3e}",
        h.relative_energy_error(),
        r.relative_energy_error()
    );
    outln!(
        "wall time: hybrid {:.4} s ({} active bead-steps), reference {:.4} s ({} bead-steps); ratio {:.1}x",
        h.wall_seconds,
        h.stats.bead_steps,
        r.wall_seconds,
        r.stats.bead_steps,
        r.wall_seconds / h.wall_seconds.max(1e-12)
    );
    if let Some(sh) = rep.hybrid_spread {
        outln!(
            "the reference's own error, not the scene: it moves by {:.1e} x rtol from rtol to rtol/100 where the hybrid engine moves by {:.1e} x rtol{}; the trajectory is judged against the reference at rtol/100",
            s / rep.rtol,
            sh / rep.rtol,
            if rep.reference.starts_with("dense") {
                " (the dense engine's steps across contact kinks)"
            } else {
                ""
            }
        );
    }
    if rep.sensitive {
        outln!(
            "scene is sensitive: trajectories separate by {:.1e} x rtol from rtol-level differences, so the final states are not a test; judged on conserved quantities and the leading wave",
            s / rep.rtol
        );
    }
    for c in &rep.criteria {
        let mark = if c.holds() { "ok  " } else { "FAIL" };
        outln!(
            "  {mark} {}: {:.3e} (bound {:.3e})",
            c.what,
            c.value,
            c.bound
        );
    }
    Ok(())
}

/// Runs the check (progress bar on a terminal unless `quiet`); exit code 0 when every
/// criterion holds, 1 otherwise.
fn compare(scene: &Scene, cfg: &RunConfig, tol: f64, quiet: bool) -> Result<i32> {
    let bar = beadchain::progress::RunProgress::new(quiet);
    let rep = check_with_progress(scene, scene, cfg, tol, &bar).context("check run failed")?;
    print_report(scene, cfg, &rep)?;
    if rep.passed() {
        let what = if rep.sensitive {
            "conserved quantities and the leading wave agree"
        } else {
            "hybrid and reference agree"
        };
        outln!("OK: {what} within the bounds above");
        Ok(0)
    } else {
        outln!("FAIL: a criterion above exceeds its bound");
        Ok(1)
    }
}
