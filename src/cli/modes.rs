//! `beadchain modes SCENE`: the linear modes of a chain about its static equilibrium (or its
//! initial state), their participation ratios and density of states, optionally as `.npz`
//! (library: [`beadchain::studies::modes`], [`beadchain::studies::equilibrium`]); with
//! `--snapshot RUN.snap`, the energy of each mode in each frame of a run ([`super::modal`]).

use super::common::load_scene;
use super::modal;
use anyhow::{anyhow, bail, Result};
use beadchain::scene::Scene;
use beadchain::studies::equilibrium::equilibrium;
use beadchain::studies::modal::ModalBasis;
use beadchain::studies::modes::{density_of_states, linearize, solve, Linearized, Modes};
use clap::ValueEnum;
use std::path::PathBuf;

/// The state the chain is linearised about.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq)]
pub enum About {
    /// The static equilibrium under the scene's walls and field (as `[initial] equilibrium`).
    Equilibrium,
    /// The scene's initial displacements (its precompression overlaps at `u = 0`).
    Initial,
}

/// Arguments of `beadchain modes`.
#[derive(clap::Args, Debug)]
pub struct ModesArgs {
    /// Scene file or preset name.
    pub scene: String,
    /// Write the modes as .npz: omega, omega2, index, shapes (N, M), participation, dos_edges,
    /// dos_counts, mass, overlap, stiffness, wall_stiffness, state (dos_edges run from 0 to the
    /// largest frequency, or from 0 to 1 where no mode has one: every mode at omega = 0, or
    /// none in the --window).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Linearise about the static equilibrium or the initial state.
    #[arg(long, value_enum, default_value = "equilibrium")]
    pub about: About,
    /// Only the modes with angular frequency in LO:HI (computer units) [default: all].
    #[arg(long, value_name = "LO:HI")]
    pub window: Option<String>,
    /// Bins of the density-of-states histogram (from 0 to the largest frequency), 1 to
    /// 1000000 [default: ceil(sqrt(N))].
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=beadchain::studies::modes::MAX_BINS as i64))]
    pub bins: Option<u32>,
    /// Print every mode (index, omega, participation ratio), not only the summary.
    #[arg(long)]
    pub list: bool,
    /// A run of the scene's chain (every bead, both fields): the energy of each mode in each
    /// of its frames, relative to the state linearised about (modal energy analysis).
    #[arg(long, value_name = "RUN.snap")]
    pub snapshot: Option<PathBuf>,
    /// Write the modal energies of --snapshot (.csv: t,E_<index>...,harmonic,energy; .npz:
    /// t, index, omega, energy (frames, modes), harmonic, total).
    #[arg(long, value_name = "FILE", requires = "snapshot")]
    pub energies: Option<PathBuf>,
}

/// `LO:HI` → `(lo, hi)`.
fn parse_window(w: &str) -> Result<(f64, f64)> {
    let (lo, hi) = w
        .split_once(':')
        .ok_or_else(|| anyhow!("--window {w}: expected LO:HI"))?;
    let num = |s: &str| -> Result<f64> {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite() && *x >= 0.0)
            .ok_or_else(|| anyhow!("--window {w}: `{s}` is not a finite frequency >= 0"))
    };
    let (lo, hi) = (num(lo)?, num(hi)?);
    if lo > hi {
        bail!("--window {w}: LO must not exceed HI");
    }
    Ok((lo, hi))
}

/// The state to linearise about, its description and (at equilibrium) a line on its forces:
/// the walls' and the contacts that carry none (gaps or touching beads).
pub fn state_of(scene: &Scene, about: About) -> Result<(Vec<f64>, &'static str, Option<String>)> {
    match about {
        About::Initial => Ok((
            scene.u0.clone(),
            "the initial state (the scene's displacements and precompression overlaps)",
            None,
        )),
        About::Equilibrium => {
            let eq = equilibrium(&scene.chain, &scene.u0, None).map_err(|e| {
                anyhow!(
                    "{}: static equilibrium: {e} (use --about initial)",
                    scene.name
                )
            })?;
            let wall = |f: Option<f64>| f.map_or("no wall".to_string(), |f| format!("{f:.6e}"));
            let gaps: Vec<String> = eq.gaps.iter().take(10).map(|c| c.to_string()).collect();
            let more = if eq.gaps.len() > 10 { ", ..." } else { "" };
            let line = format!(
                "static equilibrium: wall forces left {}, right {}; contacts without force (apart or just touching): {}",
                wall(eq.wall_force[0]),
                wall(eq.wall_force[1]),
                if gaps.is_empty() {
                    "none".to_string()
                } else {
                    format!("{} ({}{more})", eq.gaps.len(), gaps.join(", "))
                }
            );
            Ok((
                eq.u,
                "the static equilibrium under the walls and field",
                Some(line),
            ))
        }
    }
}

/// `beadchain modes`.
pub fn cmd_modes(a: ModesArgs) -> Result<i32> {
    let scene = load_scene(&a.scene)?;
    let window = a.window.as_deref().map(parse_window).transpose()?;
    let energies = a
        .energies
        .as_deref()
        .map(|p| check_energies_out(p, &a))
        .transpose()?;
    if let Some(p) = &a.out {
        let mut inputs = super::files::labelled_scene_inputs(&a.scene);
        inputs.extend(a.snapshot.iter().map(|s| ("snapshot", s.clone())));
        super::files::check_output_before_work(p, "--out", &inputs)?;
    }
    let (u, about, forces) = state_of(&scene, a.about)?;
    let lin = linearize(&scene.chain, &u).map_err(|e| anyhow!("{}: {e}", scene.name))?;
    let modes = solve(&lin, window).map_err(|e| anyhow!("{}: {e}", scene.name))?;
    // The run is read before anything is written: a bad pairing leaves no output.
    let projected = match &a.snapshot {
        Some(snap) => {
            let basis =
                ModalBasis::new(&lin, &modes, &u).map_err(|e| anyhow!("{}: {e}", scene.name))?;
            let e = modal::project_run(&scene, &basis, snap)?;
            Some((snap, basis, e))
        }
        None => None,
    };
    let nb = lin.mass.len();
    let bins = a
        .bins
        .map_or((nb as f64).sqrt().ceil() as usize, |b| b as usize)
        .max(1);
    let (edges, counts) = density_of_states(&modes.omega, bins);
    summary(&scene, &lin, &modes, about, window)?;
    if let Some(line) = forces {
        outln!("{line}");
    }
    if modes.omega.is_empty() {
        outln!("density of states: no modes in the window");
    } else if modes.omega.iter().all(|w| *w == 0.0) {
        outln!("density of states: every mode at omega = 0");
    } else {
        outln!(
            "density of states: {bins} bins of width {:.6e} from 0 to {:.6e}",
            edges[1] - edges[0],
            edges[bins]
        );
    }
    if a.list {
        list(&modes)?;
    }
    if let Some(p) = &a.out {
        write_npz(p, &lin, &modes, &u, (&edges, &counts))?;
        outln!("wrote {}", p.display());
    }
    if let Some((snap, basis, e)) = projected {
        modal::summary(snap, &basis, &e)?;
        if let (Some(p), Some(format)) = (&a.energies, energies) {
            modal::write(p, format, &basis, &modes.omega, &e)?;
            outln!("wrote {}", p.display());
        }
    }
    Ok(0)
}

/// `--list`: every mode's index, frequency and participation ratio.
fn list(modes: &Modes) -> Result<()> {
    outln!("mode  omega  participation");
    for k in 0..modes.omega.len() {
        outln!(
            "{} {:.12e} {:.6}",
            modes.index[k],
            modes.omega[k],
            modes.participation[k]
        );
    }
    Ok(())
}

/// `--energies PATH`: its format, and that it is neither an input (scene, snapshot) nor the
/// `--out` file.
fn check_energies_out(p: &std::path::Path, a: &ModesArgs) -> Result<modal::EnergiesFormat> {
    let format = modal::energies_format(p)?;
    let mut inputs = super::files::labelled_scene_inputs(&a.scene);
    if let Some(s) = &a.snapshot {
        inputs.push(("snapshot", s.clone()));
    }
    super::files::check_not_input(p, "--energies", &inputs)?;
    if a.out
        .as_deref()
        .is_some_and(|o| o == p || beadchain::files::same_file(p, o))
    {
        bail!(
            "{}: --energies: is also the --out file (choose another output name)",
            p.display()
        );
    }
    Ok(format)
}

/// The summary lines: state, boundary conditions, open contacts, frequencies, localisation.
fn summary(
    scene: &Scene,
    lin: &Linearized,
    m: &Modes,
    about: &str,
    w: Option<(f64, f64)>,
) -> Result<()> {
    let nb = lin.mass.len();
    outln!(
        "modes of {}: {nb} beads, linearised about {about}",
        scene.name
    );
    outln!("left end: {}", lin.ends[0].describe());
    outln!("right end: {}", lin.ends[1].describe());
    let open = lin.open_contacts();
    if open.is_empty() {
        outln!("contacts with zero stiffness: none");
    } else {
        let list: Vec<String> = open.iter().take(10).map(|c| c.to_string()).collect();
        let more = if open.len() > 10 { ", ..." } else { "" };
        outln!(
            "contacts with zero stiffness (overlap <= 0, sonic vacuum: no linear coupling): {} of {} ({}{more})",
            open.len(),
            nb - 1,
            list.join(", ")
        );
    }
    match w {
        Some((lo, hi)) => outln!("modes with omega in [{lo}, {hi}]: {}", m.omega.len()),
        None => outln!("modes: {}", m.omega.len()),
    }
    if m.omega.is_empty() {
        return Ok(());
    }
    let top = m.omega2_max;
    let zeros = m.omega2.iter().filter(|x| x.abs() <= 1e-12 * top).count();
    outln!(
        "omega: lowest {:.6e}, highest {:.6e}; zero modes (|omega^2| <= 1e-12 omega_max^2): {zeros}",
        m.omega[0],
        m.omega[m.omega.len() - 1]
    );
    let (k, pmin) = m
        .participation
        .iter()
        .enumerate()
        .fold(
            (0, f64::INFINITY),
            |b, (k, p)| if *p < b.1 { (k, *p) } else { b },
        );
    let mean = m.participation.iter().sum::<f64>() / m.participation.len() as f64;
    outln!(
        "participation ratio: mean {mean:.4}, smallest {pmin:.4} (mode {}, omega {:.6e}); 1/N = {:.4}",
        m.index[k],
        m.omega[k],
        1.0 / nb as f64
    );
    Ok(())
}

/// Writes the `.npz` (see [`ModesArgs::out`]).
fn write_npz(
    p: &std::path::Path,
    lin: &Linearized,
    m: &Modes,
    u: &[f64],
    (edges, counts): (&[f64], &[f64]),
) -> Result<()> {
    let nb = lin.mass.len() as u64;
    let k = m.omega.len() as u64;
    // shapes[i, j]: bead i of mode j.
    let mut shapes = Vec::with_capacity((nb * k) as usize);
    for i in 0..nb as usize {
        shapes.extend(m.shapes.iter().map(|x| x[i]));
    }
    let index: Vec<f64> = m.index.iter().map(|&i| i as f64).collect();
    let walls = [lin.ends[0].stiffness(), lin.ends[1].stiffness()];
    let arrays: Vec<(&str, Vec<u64>, &[f64])> = vec![
        ("omega", vec![k], &m.omega),
        ("omega2", vec![k], &m.omega2),
        ("index", vec![k], &index),
        ("shapes", vec![nb, k], &shapes),
        ("participation", vec![k], &m.participation),
        ("dos_edges", vec![edges.len() as u64], edges),
        ("dos_counts", vec![counts.len() as u64], counts),
        ("mass", vec![nb], &lin.mass),
        ("overlap", vec![nb - 1], &lin.overlap),
        ("stiffness", vec![nb - 1], &lin.stiffness),
        ("wall_stiffness", vec![2], &walls),
        ("state", vec![nb], u),
    ];
    super::files::clean_stale_temps(p);
    beadchain::snapshot::write_atomically(p, |w| {
        beadchain::export::npz::write_npz_arrays(&arrays, w)
    })?;
    Ok(())
}
