//! Modal energy analysis (issue 35, part 3): the energy of each linear mode in a state of the
//! chain, for FPUT-like studies of how energy spreads over the modes during a run.
//!
//! With the modes `K x_j = ω_j² M x_j` about the state `u*` ([`super::modes`]), normalised to
//! `x_jᵀ M x_k = δ_jk`, a state `(u, v)` has the modal coordinates and energies
//!
//! ```text
//! q_j = x_jᵀ M (u − u*),    q̇_j = x_jᵀ M v,    E_j = ½ (q̇_j² + ω_j² q_j²),
//! ```
//!
//! and, the modes being a complete `M`-orthonormal basis (`X Xᵀ M = I`), Parseval's identity
//!
//! ```text
//! Σ_j E_j = ½ vᵀ M v + ½ (u − u*)ᵀ K (u − u*)     (the harmonic energy, eq. H below),
//! ```
//!
//! holds for every state, whatever the nonlinearity makes of it. `ω_j²` is the computed
//! eigenvalue itself (not `max(ω², 0)`), so that the identity holds to round-off also for a
//! zero mode. The harmonic energy (H) uses the tridiagonal stiffness `K` of
//! [`super::modes::Linearized`] directly (contact `c` between beads `c`, `c+1` of stiffness
//! `k_c`, soft walls `k_L`, `k_R`):
//! `½ Σ m_i v_i² + ½ Σ_c k_c (w_c − w_{c+1})² + ½ k_L w_0² + ½ k_R w_{N−1}²`, `w = u − u*`.

use super::modes::{Linearized, Modes};
use super::StudyError;

/// The modal basis of a linearised chain: what [`ModalBasis::energies_into`] projects on.
#[derive(Clone, Debug, PartialEq)]
pub struct ModalBasis {
    /// The state `u*` the chain is linearised about (N).
    pub state: Vec<f64>,
    /// The linearised chain (masses, stiffnesses, walls).
    pub lin: Linearized,
    /// Index of each mode among all N (0 = lowest).
    pub index: Vec<usize>,
    /// `ω_j²` of each mode (the eigenvalue, round-off included).
    pub omega2: Vec<f64>,
    /// `M x_j` of each mode, one row of N per mode (the projection weights).
    weights: Vec<f64>,
}

impl ModalBasis {
    /// The basis of `modes` (every mode or a window of them) of `lin`, linearised about `state`.
    pub fn new(lin: &Linearized, modes: &Modes, state: &[f64]) -> Result<Self, StudyError> {
        let nb = lin.mass.len();
        if state.len() != nb {
            return Err(StudyError::new(format!(
                "expected a state of {nb} displacements, got {}",
                state.len()
            )));
        }
        let mut weights = Vec::with_capacity(nb * modes.shapes.len());
        for x in &modes.shapes {
            weights.extend(x.iter().zip(&lin.mass).map(|(xi, m)| xi * m));
        }
        Ok(Self {
            state: state.to_vec(),
            lin: lin.clone(),
            index: modes.index.clone(),
            omega2: modes.omega2.clone(),
            weights,
        })
    }

    /// Number of beads.
    pub fn beads(&self) -> usize {
        self.state.len()
    }

    /// Number of modes projected on.
    pub fn modes(&self) -> usize {
        self.omega2.len()
    }

    /// Checks that a state has one displacement and one velocity per bead (`what` names it in
    /// the error, e.g. the file and frame).
    pub fn check_state(&self, u: &[f64], v: &[f64], what: &str) -> Result<(), StudyError> {
        let nb = self.beads();
        if u.len() != nb || v.len() != nb {
            return Err(StudyError::new(format!(
                "{what}: {} displacements and {} velocities, but the chain linearised has {nb} beads",
                u.len(),
                v.len()
            )));
        }
        Ok(())
    }

    /// The energies `E_j` of the state `(u, v)` into `e` (one per mode; no allocation).
    /// `u`, `v` must have [`Self::beads`] values ([`Self::check_state`]) and `e`
    /// [`Self::modes`].
    pub fn energies_into(&self, u: &[f64], v: &[f64], e: &mut [f64]) {
        let nb = self.beads();
        debug_assert!(u.len() == nb && v.len() == nb && e.len() == self.modes());
        for (j, ej) in e.iter_mut().enumerate() {
            let w = &self.weights[j * nb..(j + 1) * nb];
            let (mut q, mut qd) = (0.0, 0.0);
            for i in 0..nb {
                q += w[i] * (u[i] - self.state[i]);
                qd += w[i] * v[i];
            }
            *ej = 0.5 * (qd * qd + self.omega2[j] * q * q);
        }
    }

    /// The harmonic energy `½ vᵀ M v + ½ (u − u*)ᵀ K (u − u*)` of the state (eq. H of the
    /// module docs), from the stiffnesses directly (not through the modes).
    pub fn harmonic_energy(&self, u: &[f64], v: &[f64]) -> f64 {
        let l = &self.lin;
        let nb = self.beads();
        let w = |i: usize| u[i] - self.state[i];
        let kin: f64 = l.mass.iter().zip(v).map(|(m, x)| m * x * x).sum();
        let mut pot = 0.0;
        for (c, k) in l.stiffness.iter().enumerate() {
            let d = w(c) - w(c + 1);
            pot += k * d * d;
        }
        pot += l.ends[0].stiffness() * w(0) * w(0) + l.ends[1].stiffness() * w(nb - 1) * w(nb - 1);
        0.5 * (kin + pot)
    }
}
