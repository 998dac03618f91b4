//! The hybrid engine's context and workspace, apart from its state (module docs of
//! [`super`]; docs/architecture.md): what the run is, and the scratch it may drop.

use super::stick;
use crate::engine::RunConfig;
use crate::integrate::Tolerances;
use crate::model::Chain;

/// The context of a hybrid run: the scene's chain, the run configuration and what derives
/// from them (rapier's habit: the pipeline's inputs apart from the state it advances). Fixed
/// while the run advances; only a change of state from outside
/// ([`super::Engine::set_velocities`]) derives the tolerances' scales and `theta` again.
pub(super) struct Context<'a> {
    pub(super) chain: &'a Chain,
    pub(super) cfg: &'a RunConfig,
    pub(super) tol: Tolerances,
    pub(super) theta: f64,
    pub(super) n: usize,
    /// Field acceleration per bead, `W_i / m_i`.
    pub(super) g: Vec<f64>,
    /// The chain's free fall ([`Chain::free_fall`]): the clusters' frames fall at `fall.0` and
    /// they integrate `fall.1` (the chain less the field's common part), or `chain` if `None`.
    pub(super) fall: (f64, Option<Chain>),
}

/// Scratch of a hybrid run: buffers every step or event overwrites before reading, and the
/// removed clusters' allocations kept for reuse. Dropping it and building a new one changes no
/// number (a checkpoint does not store it).
pub(super) struct Workspace {
    /// Scratch of [`Hybrid::form_group`].
    pub(super) pools: Vec<stick::Pool>,
    pub(super) bu: Vec<f64>,
    pub(super) bv: Vec<f64>,
    pub(super) bz: Vec<f64>,
    /// Scratch of [`Hybrid::settle_at`]: the state at the landing time (`2N`).
    pub(super) bzt: Vec<f64>,
    /// Scratch of the bead states at a merge or split (`N` each).
    pub(super) eu: Vec<f64>,
    pub(super) ev: Vec<f64>,
    /// Scratch of a cluster's accelerations at a hard collision ([`Hybrid::accel_of`]).
    pub(super) acc: Vec<f64>,
    /// Scratch of [`crate::integrate::dissipated_at`] (`3N`): a damped merge, a settle, and
    /// every frame of a damped scene read the dissipated energy inside a step. A cell, as
    /// frames read it through `&self` ([`Hybrid::dissipated_at`]).
    pub(super) diss: std::cell::RefCell<Vec<f64>>,
    /// Mass arrays of removed clusters, reused by the next clusters made.
    pub(super) spare_mass: Vec<Vec<f64>>,
    /// Integrators of removed clusters, renewed for the next clusters made
    /// ([`Integrator::renew`]): a gap event allocates nothing for them.
    pub(super) spare: Vec<Box<dyn crate::integrate::Integrator>>,
    /// Exact pairs of removed clusters, renewed for the next pairs made (no allocation per
    /// collision).
    pub(super) spare_pairs: Vec<Box<dyn crate::integrate::Integrator>>,
    /// Contact profiles of the exact pairs, by exponent (bits) ([`exact`]).
    pub(super) profiles:
        std::collections::HashMap<u64, std::sync::Arc<crate::model::profile::Profile>>,
    /// Each contact's peak overlap before its cluster's last step (`N + 1`; NaN where not
    /// known, e.g. after a resume): read only by a kick ([`super::kick`]).
    pub(super) peak_before: Vec<f64>,
    /// Scratch of the holds' margins ([`super::release`]); a cell, as the margins are
    /// evaluated inside the crossing search's closures.
    pub(super) hold: std::cell::RefCell<super::release::HoldScratch>,
}

impl Workspace {
    /// The scratch of an `n`-bead chain.
    pub(super) fn new(n: usize) -> Self {
        Self {
            pools: Vec::with_capacity(n + 2),
            bu: vec![0.0; n],
            bv: vec![0.0; n],
            bz: vec![0.0; 2 * n],
            bzt: vec![0.0; 2 * n],
            eu: vec![0.0; n],
            ev: vec![0.0; n],
            acc: Vec::with_capacity(n),
            diss: std::cell::RefCell::new(vec![0.0; 3 * n]),
            spare_mass: Vec::new(),
            spare: Vec::new(),
            spare_pairs: Vec::new(),
            profiles: Default::default(),
            peak_before: vec![f64::NAN; n + 1],
            hold: Default::default(),
        }
    }
}
