//! Modal energies of a run's frames (issue 35, part 3; FPUT-style analysis): every frame
//! projected on the linear modes of a chain, `E_j = ½ (q̇_j² + ω_j² q_j²)` with
//! `q_j = x_jᵀ M (u − u*)`, `q̇_j = x_jᵀ M v` ([`crate::studies::modal`], which states
//! Parseval's identity `Σ_j E_j = ½ vᵀ M v + ½ (u − u*)ᵀ K (u − u*)`), with that harmonic
//! energy and the chain's full energy above `u*` at rest ([`crate::model::Chain::energy`]) per
//! frame. One code path for `beadchain modes --snapshot` and Python's `modal_energies`.

use crate::model::Chain;
use crate::snapshot::{Frame, Snapshot, SnapshotError};
use crate::studies::modal::ModalBasis;

/// Why the frames could not be projected.
#[derive(Debug, thiserror::Error)]
pub enum ModalError {
    /// The snapshot could not be read (names the file).
    #[error(transparent)]
    Snapshot(#[from] SnapshotError),
    /// The frames do not fit the chain (bead count, stored fields): one line naming the file
    /// or run.
    #[error("{0}")]
    Mismatch(String),
}

/// The modal energies of every frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModalEnergies {
    /// Number of modes per frame (M).
    pub modes: usize,
    /// Frame times (F).
    pub t: Vec<f64>,
    /// `E_j` of every frame, row-major (F × M).
    pub energy: Vec<f64>,
    /// `½ vᵀ M v + ½ (u − u*)ᵀ K (u − u*)` of every frame (F).
    pub harmonic: Vec<f64>,
    /// The chain's energy (contacts, walls, field, kinetic) minus that of `u*` at rest (F).
    pub total: Vec<f64>,
}

impl ModalEnergies {
    /// `E_j` of frame `k` (M values).
    pub fn row(&self, k: usize) -> &[f64] {
        &self.energy[k * self.modes..(k + 1) * self.modes]
    }

    fn with_capacity(modes: usize, frames: usize) -> Self {
        Self {
            modes,
            t: Vec::with_capacity(frames),
            energy: Vec::with_capacity(frames * modes),
            harmonic: Vec::with_capacity(frames),
            total: Vec::with_capacity(frames),
        }
    }

    /// Appends the frame `(t, u, v)` (already checked against `basis`).
    fn push(&mut self, chain: &Chain, basis: &ModalBasis, e0: f64, (t, u, v): Frameref<'_>) {
        let k = self.t.len();
        self.energy.resize((k + 1) * self.modes, 0.0);
        basis.energies_into(u, v, &mut self.energy[k * self.modes..]);
        self.t.push(t);
        self.harmonic.push(basis.harmonic_energy(u, v));
        self.total.push(chain.energy(u, v) - e0);
    }
}

/// A frame's time, displacements and velocities.
type Frameref<'a> = (f64, &'a [f64], &'a [f64]);

/// The mismatch of a run of `n` beads with the chain of `basis`, naming `what` (the file).
fn check_beads(basis: &ModalBasis, n: usize, what: &str) -> Result<(), ModalError> {
    if n == basis.beads() {
        return Ok(());
    }
    Err(ModalError::Mismatch(format!(
        "{what}: the run has {n} beads, the chain of the modes {}: modal energies need a run of the same chain",
        basis.beads()
    )))
}

/// Every frame of `snap` (every bead and both fields stored) projected on `basis`, a basis of
/// `chain` (whose energy gives [`ModalEnergies::total`]).
pub fn project_snapshot(
    snap: &Snapshot,
    chain: &Chain,
    basis: &ModalBasis,
) -> Result<ModalEnergies, ModalError> {
    let what = snap.path().display().to_string();
    snap.require_full("modal energies need every bead and both fields")?;
    check_beads(basis, snap.header().n_beads as usize, &what)?;
    let frames = snap.frame_count();
    let e0 = chain.potential_energy(&basis.state);
    let mut out = ModalEnergies::with_capacity(basis.modes(), frames);
    let mut f = Frame::default();
    for k in 0..frames {
        snap.read_frame_into(k, &mut f)?;
        basis
            .check_state(&f.u, &f.v, &format!("{what}: frame {k}"))
            .map_err(|e| ModalError::Mismatch(e.to_string()))?;
        out.push(chain, basis, e0, (f.t, &f.u, &f.v));
    }
    Ok(out)
}

/// Frames held in memory (`t`: F times; `u`, `v`: F × N row-major, N = the beads of `basis`)
/// projected on `basis`; `what` names the run in errors.
pub fn project_frames(
    chain: &Chain,
    basis: &ModalBasis,
    t: &[f64],
    u: &[f64],
    v: &[f64],
    what: &str,
) -> Result<ModalEnergies, ModalError> {
    let f = t.len();
    let n = basis.beads();
    if f == 0 || u.len() != v.len() || !u.len().is_multiple_of(f) {
        return Err(ModalError::Mismatch(format!(
            "{what}: expected u and v of {f} frames of {n} beads, got {} and {} values",
            u.len(),
            v.len()
        )));
    }
    check_beads(basis, u.len() / f, what)?;
    let e0 = chain.potential_energy(&basis.state);
    let mut out = ModalEnergies::with_capacity(basis.modes(), f);
    for (k, &tk) in t.iter().enumerate() {
        let r = k * n..(k + 1) * n;
        out.push(chain, basis, e0, (tk, &u[r.clone()], &v[r]));
    }
    Ok(out)
}
