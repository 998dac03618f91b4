//! `run --stop-when-fragmented`: the run ends at the first output frame at which no pair of beads
//! can ever collide again, and the fragments are printed.
//!
//! The run is [`beadchain::analysis::run_until_fragmented`]: the test is
//! [`beadchain::analysis::final_fragments`] on each frame's state, every contact open
//! (`δ < 0`), or touching (`δ = 0`) and not approaching, and `v_i ≤ v_{i+1}` along the chain.
//! It needs a chain without field and walls (either can bring beads together again), so such
//! scenes are refused before any file is written ([`check_scene`]). The engine pauses at frames
//! only (pausing changes no byte of the run), so a run that never fragments writes the same
//! snapshot as without the option. When it stops, the frame at that time is the snapshot's last
//! frame and the snapshot is finished as usual (its run summary has `t_end` = that time and a
//! note saying why it ended).

use anyhow::{bail, Result};
use beadchain::analysis::Fragmented;
use beadchain::engine::RunConfig;
use beadchain::scene::Scene;
use std::io::Write;

/// Fragments printed one per line; beyond this, their count.
const PRINT_AT_MOST: usize = 100;

/// Why the last frame of a run that never fragmented is not fragmented: contacts that overlap,
/// contacts whose velocities decrease (`v_i > v_{i+1}`), and the largest such decrease.
pub struct Blockers {
    /// Contacts with `δ > 0`.
    pub overlapping: usize,
    /// Contacts with `v_i > v_{i+1}`.
    pub approaching: usize,
    /// The largest `v_i − v_{i+1}` (0 when none).
    pub fastest: f64,
}

/// The [`Blockers`] of a state.
pub fn blockers(scene: &Scene, u: &[f64], v: &[f64]) -> Blockers {
    let mut b = Blockers {
        overlapping: 0,
        approaching: 0,
        fastest: 0.0,
    };
    for c in 0..v.len().saturating_sub(1) {
        if scene.chain.overlap(c, u[c], u[c + 1]) > 0.0 {
            b.overlapping += 1;
        }
        if v[c] > v[c + 1] {
            b.approaching += 1;
            b.fastest = b.fastest.max(v[c] - v[c + 1]);
        }
    }
    b
}

/// Refuses `--stop-when-fragmented` for a scene with a field or walls (one line naming the key).
pub fn check_scene(spec: &str, scene: &Scene) -> Result<()> {
    let c = &scene.chain;
    if c.left_wall.is_some() || c.right_wall.is_some() {
        bail!(
            "{spec}: --stop-when-fragmented: the scene has walls ([walls]), which can always send a bead back; the stop needs free ends"
        );
    }
    if c.field.is_some() {
        bail!(
            "{spec}: --stop-when-fragmented: the scene has a field ([field]), which can always bring beads together again; the stop needs a chain without field"
        );
    }
    Ok(())
}

/// The snapshot note of a run that stopped because it fragmented.
pub fn note(f: &Fragmented, until: f64) -> String {
    format!(
        "stopped at t = {} (until = {until}) by --stop-when-fragmented: no pair can collide again; {} fragments",
        f.t,
        f.fragments.len()
    )
}

/// Prints the stop and the fragments (bead range, total mass, centre-of-mass velocity; SI
/// beside the computer units for a physical scene), or that the run never fragmented.
pub fn print(
    w: &mut dyn Write,
    scene: &Scene,
    cfg: &RunConfig,
    f: Option<&Fragmented>,
    last: (&[f64], &[f64]),
) -> Result<()> {
    let Some(f) = f else {
        let b = blockers(scene, last.0, last.1);
        writeln!(
            w,
            "stop when fragmented: not reached by t = {}: at the last frame {} contacts overlap and {} have v_i > v_(i+1) (largest difference {:.3e}; the test is exact: a decrease at the level of the run's velocity errors counts too)",
            cfg.until, b.overlapping, b.approaching, b.fastest
        )?;
        return Ok(());
    };
    writeln!(
        w,
        "fragmented at t = {} (until = {}): every contact open or touching at equal velocity, velocities non-decreasing along the chain; no pair can collide again",
        f.t, cfg.until
    )?;
    let units = scene.units;
    let si_head = if units.is_some() { "; SI: kg, m/s" } else { "" };
    writeln!(
        w,
        "{} fragments (beads first..=last, total mass, centre-of-mass velocity; computer units{si_head}):",
        f.fragments.len()
    )?;
    for g in f.fragments.iter().take(PRINT_AT_MOST) {
        write!(
            w,
            "  beads {}..={}: mass {:.9e}, velocity {:.9e}",
            g.first, g.last, g.mass, g.velocity
        )?;
        if let Some(u) = units {
            write!(
                w,
                " (SI: {:.6e} kg, {:.6e} m/s)",
                g.mass * u.mass,
                g.velocity / u.time
            )?;
        }
        writeln!(w)?;
    }
    if f.fragments.len() > PRINT_AT_MOST {
        writeln!(
            w,
            "  ... {} more (the snapshot's last frame holds every bead)",
            f.fragments.len() - PRINT_AT_MOST
        )?;
    }
    Ok(())
}
