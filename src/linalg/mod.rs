//! Linear solvers for the banded Newton systems.
//!
//! The implicit integrators (Radau IIA, see [`crate::integrate::radau5`]) reduce their Newton
//! matrix `(c I − J)` for the first-order system `z = (u, v)` (paper appendix, eq. A.3) to an
//! `m × m` **symmetric tridiagonal** system in the bead coordinates,
//!
//! ```text
//! (μ² M + h² L(k)) x_u = M (h² r_v + μ h r_u),    x_v = (μ/h) x_u − r_u,
//! ```
//!
//! where `M` is the diagonal mass matrix, `L(k)` the Laplacian weighted by the contact
//! stiffnesses `k_c = dF_c/dδ ≥ 0` (walls add to the end diagonals), and `μ` is one eigenvalue of
//! the Radau matrix: real for one system, complex for the other. For complex `μ` the matrix is
//! complex *symmetric* (not Hermitian) with a positive definite imaginary part, for which
//! elimination without pivoting is stable; for real `μ` it is symmetric positive definite.
//!
//! Two implementations sit behind [`TridiagSolver`], with the lifecycle split as
//! pattern (once per size) / factorize (per Jacobian or step size) / solve (per Newton iteration):
//! - [`direct::DirectSweep`]: an `LDLᵀ` sweep (Thomas algorithm), `O(m)`, no allocation after
//!   `pattern`;
//! - `faer_lu::FaerLu`: faer's sparse LU with the symbolic analysis done once per pattern.
//!
//! [`SolverKind::Auto`] picks the faster one per size (see `benches/linear_solvers.rs` and the
//! numbers in README).

pub mod direct;
pub mod faer_lu;

use num_complex::Complex64;
use serde::{Deserialize, Serialize};

/// Scalars the tridiagonal solvers work with: `f64` and `Complex64`.
pub trait Scalar:
    Copy
    + Send
    + Sync
    + std::fmt::Debug
    + PartialEq
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
    + std::ops::Neg<Output = Self>
    + 'static
{
    /// Additive identity.
    fn zero() -> Self;
    /// True when the value is finite and nonzero (usable as a pivot).
    fn is_usable_pivot(self) -> bool;
    /// Embeds a real number.
    fn from_real(x: f64) -> Self;
}

impl Scalar for f64 {
    fn zero() -> Self {
        0.0
    }
    fn is_usable_pivot(self) -> bool {
        self != 0.0 && self.is_finite()
    }
    fn from_real(x: f64) -> Self {
        x
    }
}

impl Scalar for Complex64 {
    fn zero() -> Self {
        Complex64::new(0.0, 0.0)
    }
    fn is_usable_pivot(self) -> bool {
        (self.re != 0.0 || self.im != 0.0) && self.re.is_finite() && self.im.is_finite()
    }
    fn from_real(x: f64) -> Self {
        Complex64::new(x, 0.0)
    }
}

/// The factorization met a zero or non-finite pivot.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[error("singular or non-finite Newton matrix (pivot {row})")]
pub struct SingularMatrix {
    /// Row at which elimination failed.
    pub row: usize,
}

/// A solver for symmetric tridiagonal systems `A x = b`, `A = tridiag(e, d, e)`.
pub trait TridiagSolver<T: Scalar>: Send {
    /// Prepares for systems of size `m` (symbolic analysis, buffers). Called once per size.
    fn pattern(&mut self, m: usize);
    /// Numeric factorization of `A` with diagonal `d` (length `m`) and off-diagonal `e`
    /// (length `m − 1`).
    fn factorize(&mut self, d: &[T], e: &[T]) -> Result<(), SingularMatrix>;
    /// Solves `A x = b` in place (`b` becomes `x`). Requires a successful `factorize`.
    fn solve_in_place(&mut self, b: &mut [T]);
}

/// Which linear solver the implicit integrator uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum SolverKind {
    /// The faster one for the system size (measured; see README).
    #[default]
    Auto,
    /// The direct tridiagonal sweep.
    Direct,
    /// faer sparse LU.
    Faer,
}

/// Scalars both solvers support (`f64`, `Complex64`): what [`new_solver`] needs.
pub trait SolverScalar: Scalar + faer::traits::ComplexField {}

impl<T: Scalar + faer::traits::ComplexField> SolverScalar for T {}

/// Resolves [`SolverKind::Auto`] for systems of size `m`.
///
/// AUTO_DOC_PLACEHOLDER
pub fn resolve_auto(m: usize) -> SolverKind {
    let _ = m;
    SolverKind::Direct
}

/// A boxed solver of the requested kind (`Auto` resolved by [`resolve_auto`]) with
/// [`TridiagSolver::pattern`] already called for size `m`.
pub fn new_solver<T: SolverScalar>(kind: SolverKind, m: usize) -> Box<dyn TridiagSolver<T>> {
    let kind = match kind {
        SolverKind::Auto => resolve_auto(m),
        k => k,
    };
    let mut solver: Box<dyn TridiagSolver<T>> = match kind {
        SolverKind::Faer => Box::new(faer_lu::FaerLu::<T>::new()),
        SolverKind::Direct | SolverKind::Auto => Box::new(direct::DirectSweep::<T>::new()),
    };
    solver.pattern(m);
    solver
}
