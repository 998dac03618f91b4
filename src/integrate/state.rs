//! The state of an integrator as data (checkpoints): [`IntegratorState`] holds what every
//! method has and the method's own typed state ([`MethodState`], after diffsol's typed
//! per-method states); [`Integrator::load`] takes only the variant its method saved and checks
//! the array lengths against its own, else a [`LoadError`].
//!
//! [`Integrator::load`]: super::Integrator::load

use super::{auto, dop853, exact_pair, radau5, rest, verlet, Method, Stats};
use crate::names::Named;
use serde::{Deserialize, Serialize};

/// Everything an integrator needs to continue bit-identically (checkpoints): what every
/// method has (times, counters, dissipated energy, the switching state of [`auto::Auto`]) and
/// the method's own typed state ([`MethodState`]). Scratch buffers that every step recomputes
/// are not part of it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct IntegratorState {
    /// Current time.
    pub t: f64,
    /// Start of the last accepted step.
    pub t_prev: f64,
    /// Counters.
    pub stats: Stats,
    /// Energy dissipated since the last reset, at `t_prev` and at `t` ([`super::Integrator::dissipated`]).
    pub dissipated: (f64, f64),
    /// Switching state of the [`auto::Auto`] integrator (`None` for the others).
    pub auto: Option<auto::AutoState>,
    /// The state of the method (for [`auto::Auto`], the active one).
    pub method: MethodState,
}

/// The state of one method, typed: a state loads only into the method that saved it (the
/// variant is checked by `match`, the array lengths against the loading integrator's).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum MethodState {
    /// [`dop853::Dop853`].
    Dop853(dop853::Dop853State),
    /// [`radau5::Radau5`].
    Radau5(radau5::Radau5State),
    /// [`verlet::Verlet`].
    Verlet(verlet::VerletState),
    /// The trajectory of an [`exact_pair::ExactPair`].
    Exact(exact_pair::PairState),
    /// The state of a cluster at rest ([`rest::Rest`]).
    Rest(rest::RestState),
}

/// The name of the exact two-body contact ([`exact_pair::ExactPair`]) in messages.
pub const EXACT_NAME: &str = "two-body (exact)";

impl MethodState {
    /// The method's name as messages write it.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Dop853(_) => Method::Dop853.name(),
            Self::Radau5(_) => Method::Radau5.name(),
            Self::Verlet(_) => Method::Verlet.name(),
            Self::Exact(_) => EXACT_NAME,
            Self::Rest(_) => rest::REST_NAME,
        }
    }
}

/// Why [`super::Integrator::load`] refused a state (the integrator is left unchanged).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LoadError {
    /// The state was saved by another method.
    #[error("the state of a {saved} integrator cannot continue as {loading}")]
    WrongMethod {
        /// The method that saved the state.
        saved: &'static str,
        /// The method of the loading integrator.
        loading: &'static str,
    },
    /// The state's arrays do not fit the loading integrator's beads.
    #[error("{method} state arrays have lengths {got:?}, expected {expected:?}")]
    Lengths {
        /// The method.
        method: &'static str,
        /// The state's array lengths.
        got: Vec<usize>,
        /// The loading integrator's.
        expected: Vec<usize>,
    },
}

impl LoadError {
    /// The state `s` was not saved by `loading`.
    pub fn wrong_method(s: &MethodState, loading: &'static str) -> Self {
        Self::WrongMethod {
            saved: s.name(),
            loading,
        }
    }
}

/// The length check of [`super::Integrator::load`]: the state's arrays `got` have the lengths
/// `expected` (the loading integrator's own).
pub fn check_lengths(
    method: Method,
    got: &[&Vec<f64>],
    expected: &[usize],
) -> Result<(), LoadError> {
    let got: Vec<usize> = got.iter().map(|v| v.len()).collect();
    if got != expected {
        return Err(LoadError::Lengths {
            method: method.name(),
            got,
            expected: expected.to_vec(),
        });
    }
    Ok(())
}
