//! `beadchain plot dispersion SCENE`: the band structure of a periodic chain's unit cell
//! linearised about its static equilibrium (library: [`beadchain::studies::bands`],
//! [`beadchain::plot::dispersion`]); prints the band edges and gaps, and draws `ω(q)`.

use super::modes::{state_of, About};
use super::plot_out::{written, Out};
use anyhow::{anyhow, Result};
use beadchain::studies::bands::{bands, cell_of};
use beadchain::studies::modes::linearize;
use std::path::Path;

/// Arguments of `plot dispersion`.
#[derive(clap::Args, Debug)]
pub struct DispersionArgs {
    /// Scene file or preset name (a periodic chain: a unit cell repeated).
    scene: String,
    /// Beads per unit cell [default: the smallest period of the masses and contact
    /// stiffnesses].
    #[arg(long)]
    cell: Option<usize>,
    /// First bead of the unit cell.
    #[arg(long, default_value_t = 0)]
    start: usize,
    /// Wavenumbers sampled from 0 to pi.
    #[arg(long, default_value_t = 201, value_parser = clap::value_parser!(u32).range(2..=beadchain::studies::bands::MAX_POINTS as i64))]
    points: u32,
    /// Linearise about the static equilibrium or the initial state.
    #[arg(long, value_enum, default_value = "equilibrium")]
    about: About,
    #[command(flatten)]
    out: Out,
}

/// `beadchain plot dispersion`.
pub fn cmd_dispersion(a: DispersionArgs) -> Result<i32> {
    let scene = super::common::load_scene(&a.scene)?;
    let path = a.out.path(Path::new(&scene.name), "dispersion");
    for (f, _) in beadchain::plot::output_paths(&path)? {
        super::files::check_not_input(&f, "--out", &super::files::labelled_scene_inputs(&a.scene))?;
    }
    let (u, about, _) = state_of(&scene, a.about)?;
    let lin = linearize(&scene.chain, &u).map_err(|e| anyhow!("{}: {e}", scene.name))?;
    let cell = cell_of(&lin, a.cell, a.start).map_err(|e| anyhow!("{}: {e}", scene.name))?;
    let b = bands(&cell, a.points as usize);
    outln!(
        "dispersion of {}: unit cell of {} beads from bead {}, linearised about {about}",
        scene.name,
        cell.mass.len(),
        a.start
    );
    if cell.stiffness.iter().all(|k| *k == 0.0) {
        outln!("every contact of the cell has zero stiffness (sonic vacuum): omega = 0 for all q");
    }
    for (k, (lo, hi)) in b.edges.iter().enumerate() {
        outln!("band {k}: omega from {lo:.12e} to {hi:.12e}");
    }
    let gaps = b.gaps();
    if gaps.is_empty() {
        outln!("gaps: none");
    }
    for (lo, hi) in &gaps {
        outln!(
            "gap: omega from {lo:.12e} to {hi:.12e} (width {:.6e})",
            hi - lo
        );
    }
    let mut fig = beadchain::plot::dispersion::dispersion(
        &b,
        &format!(
            "{}: dispersion of a {}-bead cell",
            scene.name,
            cell.mass.len()
        ),
        a.out.size()?,
    );
    a.out
        .labels()
        .apply(&mut fig.title, &mut fig.x_desc, &mut fig.y_desc);
    written(&fig, &path)
}
