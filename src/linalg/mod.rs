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
//! - [`faer_lu::FaerLu`]: faer's sparse LU with the symbolic analysis done once per pattern.
//!
//! [`SolverKind::Auto`] picks the faster one per size (see `benches/linear_solvers.rs` and the
//! numbers in docs/benchmarks.md).

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
    /// Prepares for systems of size `m` (symbolic analysis, buffers): by [`new_solver`], and
    /// again by a renewed integrator for its new size (the same size included); the solver
    /// then factorizes and solves as a new one of size `m` does, bit for bit.
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
    /// The faster one for the system size (measured; see docs/benchmarks.md).
    #[default]
    Auto,
    /// The direct tridiagonal sweep.
    Direct,
    /// faer sparse LU.
    Faer,
}

impl crate::names::Named for SolverKind {
    const WHAT: &'static str = "solver";
    const ALL: &'static [Self] = &[SolverKind::Auto, SolverKind::Direct, SolverKind::Faer];
    fn name(self) -> &'static str {
        match self {
            SolverKind::Auto => "auto",
            SolverKind::Direct => "direct",
            SolverKind::Faer => "faer",
        }
    }
}
crate::display_and_from_str!(SolverKind);

/// Scalars both solvers support (`f64`, `Complex64`): what [`new_solver`] needs.
pub trait SolverScalar: Scalar + faer::traits::ComplexField {}

impl<T: Scalar + faer::traits::ComplexField> SolverScalar for T {}

/// Resolves [`SolverKind::Auto`] for systems of size `m`.
///
/// The direct sweep wins at every measured size, so `Auto` is always [`SolverKind::Direct`].
/// Median time of one `factorize` + one `solve_in_place` (`benches/linear_solvers.rs`, criterion
/// `--warm-up-time 0.5 --measurement-time 1`, release build, shared 2-core machine, Radau
/// systems with `h = 0.3`, real `μ ≈ 3.64`, complex `μ ≈ 2.68 + 3.05i`):
///
/// | m       | real direct | real faer | ratio | complex direct | complex faer | ratio |
/// |---------|-------------|-----------|-------|----------------|--------------|-------|
/// | 2       | 11.2 ns     | 176 ns    | 15.6  | 17.9 ns        | 195 ns       | 10.9  |
/// | 4       | 20.9 ns     | 323 ns    | 15.4  | 44.3 ns        | 351 ns       | 7.9   |
/// | 8       | 50.4 ns     | 562 ns    | 11.2  | 123 ns         | 643 ns       | 5.2   |
/// | 32      | 348 ns      | 1.95 µs   | 5.6   | 680 ns         | 2.33 µs      | 3.4   |
/// | 128     | 1.76 µs     | 7.50 µs   | 4.3   | 2.92 µs        | 9.37 µs      | 3.2   |
/// | 1024    | 15.0 µs     | 61.2 µs   | 4.1   | 23.9 µs        | 76.8 µs      | 3.2   |
/// | 10000   | 148 µs      | 586 µs    | 4.0   | 234 µs         | 750 µs       | 3.2   |
/// | 100000  | 1.48 ms     | 6.10 ms   | 4.1   | 2.38 ms        | 8.11 ms      | 3.4   |
///
/// Both scale linearly; faer's constant is 3–4× larger for large `m` (pivot search,
/// permutations, CSC indirection), so no crossover exists. `Faer` stays selectable explicitly
/// (e.g. as a cross-check).
pub fn resolve_auto(m: usize) -> SolverKind {
    let _ = m;
    SolverKind::Direct
}

/// The kind of solver [`new_solver`] builds for `kind` at size `m` (`Auto` resolved by
/// [`resolve_auto`]).
pub fn resolve(kind: SolverKind, m: usize) -> SolverKind {
    match kind {
        SolverKind::Auto => resolve_auto(m),
        k => k,
    }
}

/// A boxed solver of the requested kind (`Auto` resolved by [`resolve_auto`]) with
/// [`TridiagSolver::pattern`] already called for size `m`.
pub fn new_solver<T: SolverScalar>(kind: SolverKind, m: usize) -> Box<dyn TridiagSolver<T>> {
    let kind = resolve(kind, m);
    let mut solver: Box<dyn TridiagSolver<T>> = match kind {
        SolverKind::Faer => Box::new(faer_lu::FaerLu::<T>::new()),
        SolverKind::Direct | SolverKind::Auto => Box::new(direct::DirectSweep::<T>::new()),
    };
    solver.pattern(m);
    solver
}

/// `A x` for the symmetric tridiagonal `A` of diagonal `d` and off-diagonal `e` (the solvers'
/// unit tests check residuals with it).
#[cfg(test)]
pub(crate) fn tridiag_matvec<T: Scalar>(d: &[T], e: &[T], x: &[T]) -> Vec<T> {
    let m = d.len();
    (0..m)
        .map(|i| {
            let mut s = d[i] * x[i];
            if i > 0 {
                s = s + e[i - 1] * x[i - 1];
            }
            if i + 1 < m {
                s = s + e[i] * x[i + 1];
            }
            s
        })
        .collect()
}
