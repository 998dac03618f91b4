//! Time integrators for second-order bead systems `ü = f(u)` written as the first-order system
//! `z = (u, v)`, `ż = (v, f(u))` (paper appendix, eqs. A.2–A.3).
//!
//! - [`radau5`]: Radau IIA order 5, implicit and stiffly stable, with error control and the
//!   collocation polynomial as continuous output (Hairer & Wanner, *Solving ODEs II*, IV.8). Its
//!   Newton matrices reduce to tridiagonal systems in bead coordinates ([`crate::linalg`]).
//! - [`dop853`]: Dormand–Prince 8(5,3), explicit, with its 7th-order dense output (Hairer,
//!   Nørsett & Wanner, *Solving ODEs I*, II.10), an independent check from another family.
//!
//! - [`verlet`]: fixed-step velocity Verlet, the symplectic second-order DEM baseline without
//!   error control (its step is `rtol · L/V`).
//!
//! All integrate any contiguous range of beads (a [`System`]), so the dense engine (whole chain)
//! and the hybrid engine (one contact cluster) share them. Both hold only scratch buffers sized
//! at construction: a step allocates nothing.
//!
//! ## Tolerances
//! The error of component `z_j` is weighed by `sc_j = atol·S_j + rtol·|z_j|`, where `S_j` is the
//! characteristic length `L` (for `u`) or the bead's own velocity scale
//! `V_i = sqrt(2E/max(m_i, m_E))` (for `v_i`; `m_E` = lightest bead holding energy initially) of
//! the run ([`crate::model::Scales`], [`crate::model::Chain::scales`]). So `atol` is *relative to
//! the physical scales*: the same `rtol`/`atol` work whether displacements are 1 or 1e-7. The
//! velocity scale is per bead so that a very light bead neither loosens the other beads'
//! tolerance (a single `V = sqrt(2E/m_min)` did: with masses 1 and 1e-8 every bead's velocity
//! was controlled only to `1e4·atol·v0`) nor is held to a meaningless one, while a heavy bead,
//! which cannot move faster than `sqrt(2E/m_i)`, is held to that. For equal masses `V_i = V`
//! exactly. Errors are measured in the max norm over components, so
//! the meaning of a tolerance does not depend on how many beads are integrated together.
//!
//! The default `atol` is `rtol · DEFAULT_ATOL_RATIO` (= `rtol/10⁴`), at least `ATOL_FLOOR`
//! (`1e-15`, see [`default_atol`]), so that the error keeps falling with `rtol` over
//! `1e-3 … 1e-13`: a fixed `atol` stalled the error at tight `rtol` and, at loose `rtol`, held
//! the displacements to a far tighter tolerance than the velocities. The ratio `10⁻⁴` (it was
//! `10⁻²`) holds the beads a wave leaves behind, whose velocities fall geometrically with the
//! distance behind it, to velocities a hundred times smaller: with `rtol/100`, DOP853 left them
//! with errors of `~atol·V` that reordered their relative velocities, and on a 100-bead striker
//! chain to `t = 10⁵` they re-collided 1445 times at relative speeds of `1e-11 … 3e-10` (99 with
//! `rtol/10⁴`); on the 1000-bead striker to wave exit the velocity error at `rtol = 1e-8` fell
//! from 5.4e-8 to 7.5e-10 (energy error 1.1e-7 to 1.5e-9) for 18 % more time, a better
//! work–precision trade at every `rtol` from `1e-6` to `1e-10`. The floor keeps the absolute
//! weights above rounding. It was `1e-14` until the error of the default method was found to
//! stall there: on the 1000-bead striker to wave exit 7.3e-12 at `rtol = 1e-10`, 9.5e-12 at
//! `1e-11` and 1.3e-12 at `1e-12`; with `1e-15` 2.3e-12 at `1e-11` (+26 % time) and 9.3e-13 at
//! `1e-12` (`tests/convergence.rs`). `1e-16` stops hybrid Radau IIA at `rtol = 1e-12` on a box of
//! linear-dashpot contacts (`validation/repro/radau_dashpot_box_atol1e-16.toml`).

pub mod auto;
pub mod dop853;
pub mod exact_pair;
pub mod radau5;
pub mod rest;
mod state;
pub mod verlet;

/// How the next steps of an integrator meet a kink of the right-hand side
/// ([`Integrator::set_rough`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Rough {
    /// No kink: the method's own error estimate.
    #[default]
    Smooth,
    /// The steps end at, or are carried to, a kink: measured by an estimate that does not
    /// assume a smooth solution.
    Kink,
    /// The steps start at the kink of a contact `V = a δⁿ` that has just closed (this `n`):
    /// measured as [`Rough::Kink`], and their error grows like `hⁿ`, as the velocity change
    /// `a w^{n−1} hⁿ/μ` of the onset force does (a closing at speed `w`), not like the
    /// smooth `h⁸` of DOP853's estimator, so a rejected one is shrunk by `err^{−1/n}` (for
    /// `n` below the method's error order; a smoother onset errs like the method and is
    /// retried like a smooth step).
    Onset(f64),
}

impl Rough {
    /// `self` where it is an [`Rough::Onset`] rougher than a method whose error estimate has
    /// order `order` (`n < order`), else [`Rough::Smooth`] (for the retry factor only).
    pub fn filter_onset(self, order: f64) -> Rough {
        match self {
            Rough::Onset(n) if n < order => self,
            _ => Rough::Smooth,
        }
    }
}

pub use state::{check_lengths, IntegratorState, LoadError, MethodState, EXACT_NAME};

use crate::linalg::SolverKind;
use crate::model::{Chain, Scales};
use crate::names::Named;
use serde::{Deserialize, Serialize};

/// Default relative tolerance.
pub const DEFAULT_RTOL: f64 = 1e-8;
/// Default absolute tolerance at the default `rtol` (relative to the run's characteristic
/// scales, see module docs); in general the default is [`default_atol`]`(rtol)`.
pub const DEFAULT_ATOL: f64 = 1e-12;
/// Default `atol / rtol` when only `rtol` is given.
pub const DEFAULT_ATOL_RATIO: f64 = 1e-4;
/// Smallest default `atol` (near rounding of the scaled state).
pub const ATOL_FLOOR: f64 = 1e-15;

/// The default absolute tolerance for a relative tolerance `rtol`: `rtol · DEFAULT_ATOL_RATIO`,
/// at least [`ATOL_FLOOR`] and below `rtol` (so `default_atol(DEFAULT_RTOL) == DEFAULT_ATOL`).
pub fn default_atol(rtol: f64) -> f64 {
    (rtol * DEFAULT_ATOL_RATIO).max(ATOL_FLOOR.min(rtol))
}

/// A second-order system of `m` beads: `ü = f(u, u̇)`, with a contact structure giving
/// tridiagonal Jacobian blocks `∂f/∂u`, `∂f/∂u̇`.
pub trait System {
    /// Number of beads `m`.
    fn len(&self) -> usize;
    /// True for an empty system.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Bead masses, length `m`.
    fn mass(&self) -> &[f64];
    /// Accelerations `f(u, v)`; returns the power dissipated by the contacts (0 for a
    /// conservative system, which ignores `v`).
    fn accel(&self, u: &[f64], v: &[f64], acc: &mut [f64]) -> f64;
    /// Accelerations and contact Jacobians: `k[c]` (c < m−1) is `∂F/∂δ` of the contact between
    /// local beads `c` and `c+1`, `k[m−1]`/`k[m]` the left/right wall (0 when none), and
    /// `kv` the same for `∂F/∂δ̇` (left untouched by a conservative system). Both have length
    /// `m + 1`. Returns the dissipated power.
    fn accel_stiffness(
        &self,
        u: &[f64],
        v: &[f64],
        acc: &mut [f64],
        k: &mut [f64],
        kv: &mut [f64],
    ) -> f64;
    /// Whether forces depend on velocities (damping): the implicit method then includes the
    /// `∂F/∂δ̇` block, and the integrators accumulate the dissipated energy.
    fn dissipative(&self) -> bool {
        false
    }
}

/// Beads `lo..lo+m` of a chain, as a [`System`].
#[derive(Clone, Copy, Debug)]
pub struct ChainRange<'a> {
    /// The chain.
    pub chain: &'a Chain,
    /// First bead of the range.
    pub lo: usize,
    /// Number of beads.
    pub m: usize,
}

impl<'a> ChainRange<'a> {
    /// The whole chain.
    pub fn whole(chain: &'a Chain) -> Self {
        Self {
            chain,
            lo: 0,
            m: chain.len(),
        }
    }
}

impl System for ChainRange<'_> {
    fn len(&self) -> usize {
        self.m
    }
    fn mass(&self) -> &[f64] {
        &self.chain.mass[self.lo..self.lo + self.m]
    }
    fn accel(&self, u: &[f64], v: &[f64], acc: &mut [f64]) -> f64 {
        self.chain.accel_v(self.lo, u, v, acc)
    }
    fn accel_stiffness(
        &self,
        u: &[f64],
        v: &[f64],
        acc: &mut [f64],
        k: &mut [f64],
        kv: &mut [f64],
    ) -> f64 {
        self.chain.accel_stiffness_v(self.lo, u, v, acc, k, kv)
    }
    fn dissipative(&self) -> bool {
        self.chain.is_dissipative()
    }
}

/// Integration method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum Method {
    /// Radau IIA order 5 (implicit).
    Radau5,
    /// Dormand–Prince 8(5,3) (explicit).
    Dop853,
    /// Fixed-step velocity Verlet (symplectic, order 2; the DEM baseline). Its step is
    /// `rtol · L/V` (see [`verlet`]).
    Verlet,
    /// DOP853 while non-stiff, Radau IIA while stiff, chosen per cluster as it runs
    /// (see [`auto`]). The default.
    #[default]
    Auto,
}

impl Named for Method {
    const WHAT: &'static str = "method";
    const ALL: &'static [Self] = &[Method::Auto, Method::Radau5, Method::Dop853, Method::Verlet];
    fn name(self) -> &'static str {
        match self {
            Method::Radau5 => "radau5",
            Method::Dop853 => "dop853",
            Method::Verlet => "verlet",
            Method::Auto => "auto",
        }
    }
    fn help(self) -> &'static str {
        match self {
            Method::Radau5 => "Radau IIA order 5 (implicit)",
            Method::Dop853 => "Dormand-Prince 8(5,3) (explicit)",
            Method::Verlet => "Fixed-step velocity Verlet; its step is rtol·L/V",
            Method::Auto => "DOP853 while non-stiff, Radau IIA while stiff, per cluster",
        }
    }
}
crate::display_and_from_str!(Method);

/// Builds the integrator of `method` for `m` beads (`solver`: the implicit methods' linear
/// solver).
pub fn new_integrator(
    method: Method,
    solver: SolverKind,
    m: usize,
    tol: Tolerances,
) -> Box<dyn Integrator> {
    match method {
        Method::Radau5 => Box::new(radau5::Radau5::new(m, tol, solver)),
        Method::Dop853 => Box::new(dop853::Dop853::new(m, tol)),
        // Fixed step `rtol · L/V` (see `integrate::verlet`).
        Method::Verlet => Box::new(verlet::Verlet::new(m, tol)),
        Method::Auto => Box::new(auto::Auto::new(m, tol, solver, false)),
    }
}

/// Relative and absolute tolerances, plus the scales that make `atol` unit-free.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Tolerances {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance, in units of the characteristic scales.
    pub atol: f64,
    /// Characteristic scales of the run.
    pub scales: Scales,
    /// Velocity of the frame the integrated velocities are measured in (a hybrid cluster's
    /// co-moving frame; 0 otherwise): the relative part of a velocity weight is taken on the
    /// velocity in the lab frame, `rtol·|v + v_frame|`.
    pub v_frame: f64,
    /// Displacement at which the relative part of a displacement weight vanishes,
    /// `rtol·|u − u_origin|`: 0 for a co-moving cluster (its displacements are measured from its
    /// centre of mass) and the whole chain; for a hybrid cluster held in the lab frame by a
    /// wall, the wall's zero-overlap position, so that the error allowed in a bead's position
    /// is relative to its distance from the wall that its force depends on, not to how far it
    /// travelled to get there.
    pub u_origin: f64,
    /// What the relative part of the dissipated energy's error weight is taken on in DOP853
    /// ([`Tolerances::weight_e`]; Radau IIA's estimate is always relative to `E_d` since the
    /// reset).
    pub dissipation: DissipationWeight,
}

/// What the relative part of the error weight of the dissipated energy `E_d` (the extra state
/// of dissipative systems) is relative to.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum DissipationWeight {
    /// `|E_d|` since the integrator's last reset: a hybrid cluster, restarted at every gap
    /// event, so `E_d` is what its current contacts dissipated.
    #[default]
    SinceReset,
    /// The step's own increment `|ΔE_d|`: an integration that is never restarted (the dense
    /// engine), where `E_d` since the start grows to a fraction of `E_0` and an error weight
    /// `rtol·E_d` would let every step across a contact's onset or release err by that much
    /// (40 damped beads, rtol 1e-10: balance error 1.9e-7, 1931·rtol; now 1.3e-12).
    Step,
}

impl Tolerances {
    /// Error weight of a displacement component.
    #[inline(always)]
    pub fn weight_u(&self, u_old: f64, u_new: f64) -> f64 {
        self.atol * self.scales.length
            + self.rtol
                * (u_old - self.u_origin)
                    .abs()
                    .max((u_new - self.u_origin).abs())
    }
    /// Error weight of a velocity component of a bead whose velocity scale is `vs` (from
    /// [`Tolerances::velocity_scales`]).
    #[inline(always)]
    pub fn weight_v(&self, vs: f64, v_old: f64, v_new: f64) -> f64 {
        self.atol * vs
            + self.rtol
                * (v_old + self.v_frame)
                    .abs()
                    .max((v_new + self.v_frame).abs())
    }
    /// Error weight of the dissipated energy (the extra state `E_d` of dissipative systems)
    /// over a step from `d_old` to `d_new`: `atol·E + rtol·|E_d|` (or `rtol·|ΔE_d|`, see
    /// [`DissipationWeight`]), with `E` the run's energy scale (1 when it has none).
    #[inline]
    pub fn weight_e(&self, d_old: f64, d_new: f64) -> f64 {
        let e = if self.scales.energy > 0.0 {
            self.scales.energy
        } else {
            1.0
        };
        let rel = match self.dissipation {
            DissipationWeight::SinceReset => d_old.abs().max(d_new.abs()),
            DissipationWeight::Step => (d_new - d_old).abs(),
        };
        self.atol * e + self.rtol * rel
    }
    /// Per-bead velocity scales `V_i` of beads with masses `mass` into `out` (see
    /// [`Scales::bead_velocity`]). No allocation; the integrators call it once per step.
    #[inline]
    pub fn velocity_scales(&self, mass: &[f64], out: &mut [f64]) {
        for (o, &mi) in out.iter_mut().zip(mass) {
            *o = self.scales.bead_velocity(mi);
        }
    }
}

/// Counters of an integration (summed over clusters by the hybrid engine).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps (error test or Newton failure).
    pub rejected: u64,
    /// Right-hand side evaluations (one per bead range).
    pub rhs_evals: u64,
    /// Jacobian (stiffness) evaluations.
    pub jac_evals: u64,
    /// Numeric factorizations (a real + complex pair counts as one).
    pub factorizations: u64,
    /// Newton iterations.
    pub newton_iters: u64,
    /// Newton failures (non-convergence leading to a step cut).
    pub newton_failures: u64,
    /// Σ over accepted steps of the number of beads integrated ("active bead-steps").
    pub bead_steps: u64,
}

impl Stats {
    /// Adds another set of counters into this one.
    pub fn add(&mut self, o: &Stats) {
        self.steps += o.steps;
        self.rejected += o.rejected;
        self.rhs_evals += o.rhs_evals;
        self.jac_evals += o.jac_evals;
        self.factorizations += o.factorizations;
        self.newton_iters += o.newton_iters;
        self.newton_failures += o.newton_failures;
        self.bead_steps += o.bead_steps;
    }
}

/// Why an integration failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum IntegrationError {
    /// The step size fell below what the floating-point time can resolve.
    #[error(
        "step size {h:e} too small at t = {t} (stiffness, a singularity, or tolerances too tight)"
    )]
    StepTooSmall {
        /// Time reached.
        t: f64,
        /// Step size attempted.
        h: f64,
    },
    /// The state became non-finite.
    #[error("non-finite state at t = {t}")]
    NonFinite {
        /// Time reached.
        t: f64,
    },
    /// The step budget was exhausted.
    #[error("step budget of {0} steps exhausted")]
    Budget(u64),
}

/// Panics unless `sys`, `u` and `v` all have the `m` beads an integrator was built for.
pub(crate) fn assert_sizes(m: usize, sys: &dyn System, u: &[f64], v: &[f64]) {
    assert_eq!(sys.len(), m, "system size differs from the integrator's");
    assert_eq!(
        u.len(),
        m,
        "displacement length differs from the integrator's"
    );
    assert_eq!(v.len(), m, "velocity length differs from the integrator's");
}

/// An adaptive one-step integrator with continuous output over the last accepted step.
pub trait Integrator: Send {
    /// Starts (or restarts) from state `(u, v)` at time `t`.
    fn reset(&mut self, sys: &dyn System, t: f64, u: &[f64], v: &[f64]);
    /// Overrides the next step-size proposal (e.g. to land on a known time in one step).
    fn set_step_size(&mut self, h: f64);
    /// Whether the next steps start or end at a kink of the right-hand side (a contact force
    /// `n a δ₊^{n−1}` at `δ = 0`), where the solution is not smooth: a method whose error
    /// estimate assumes a smooth solution then measures them by one that does not
    /// ([`dop853`]: its 5th-order estimate too), and shrinks a rejected step that starts at
    /// the onset of a force by the order the error has there ([`Rough::Onset`]). Not part of
    /// the saved state: the caller sets it before the steps and resets it to
    /// [`Rough::Smooth`] after. Default: ignored.
    fn set_rough(&mut self, _rough: Rough) {}
    /// [`Integrator::reset`] then [`Integrator::set_step_size`]`(h)`, for a restart whose first
    /// step is known (the hybrid engine redoing a step to land on an event, a method switch):
    /// a method whose `reset` estimates a starting step skips that estimate (DOP853: one
    /// right-hand side). The states and steps are those of `reset` + `set_step_size`.
    fn restart(&mut self, sys: &dyn System, t: f64, u: &[f64], v: &[f64], h: f64) {
        self.reset(sys, t, u, v);
        self.set_step_size(h);
    }
    /// The next step-size proposal.
    fn step_size(&self) -> f64;
    /// Advances one accepted step, never past `t_bound`. Returns the new time.
    fn step(&mut self, sys: &dyn System, t_bound: f64) -> Result<f64, IntegrationError>;
    /// Current time.
    fn t(&self) -> f64;
    /// Time at the start of the last accepted step.
    fn t_prev(&self) -> f64;
    /// Current state (u then v, length `2m`).
    fn state(&self) -> &[f64];
    /// Evaluates the continuous output of the last step at `t ∈ [t_prev, t]` into `z` (`2m`).
    fn dense(&self, t: f64, z: &mut [f64]);
    /// Continuous output of one component `j` (`0..2m`) at `t ∈ [t_prev, t]` (no allocation).
    fn dense_at(&self, t: f64, j: usize) -> f64;
    /// The states at `t_prev` and at `t` as arrays, when [`Integrator::dense_at`] returns exactly
    /// their components at those two times (DOP853); `None` otherwise. A fast path for callers
    /// that read a whole step's end points (the peak overlaps of the event log).
    fn end_states(&self) -> Option<(&[f64], &[f64])> {
        None
    }
    /// `f(z)` at the current time (velocities, then accelerations; `2m`) where the method holds
    /// it without extra work (DOP853: its first stage, FSAL); `None` otherwise.
    fn rate(&self) -> Option<&[f64]> {
        None
    }
    /// Counters so far.
    fn stats(&self) -> &Stats;
    /// Accepted steps taken by an implicit method so far (all of them for Radau IIA, none for
    /// the explicit methods, those of its implicit phases for [`auto::Auto`]).
    fn implicit_steps(&self) -> u64 {
        0
    }
    /// Energy dissipated by the contacts since the last [`Integrator::reset`], at `t_prev` and
    /// at `t`: the integral of the dissipated power computed with the method's own quadrature on
    /// its stages (equivalent to integrating `Ė_d = P(u, v)` as one more state component).
    /// `(0, 0)` for a conservative system.
    fn dissipated(&self) -> (f64, f64) {
        (0.0, 0.0)
    }
    /// Makes this integrator the one its kind's `new(m, tol)` builds (same method, solver and
    /// settings), keeping its allocations; returns `false`, changing nothing, where the kind
    /// cannot (the caller then builds a new one). After the next [`Integrator::reset`] every
    /// number it produces is the new integrator's.
    fn renew(&mut self, _m: usize, _tol: Tolerances) -> bool {
        false
    }
    /// The exact two-body contact, where this integrator is one ([`exact_pair`]): its peak
    /// and opening times are known in closed form. `None` for the integrating methods.
    fn exact_pair(&self) -> Option<&exact_pair::ExactPair> {
        None
    }
    /// [`Integrator::exact_pair`], mutable (an engine reusing a removed pair's allocation).
    fn exact_pair_mut(&mut self) -> Option<&mut exact_pair::ExactPair> {
        None
    }
    /// Whether this is the integrator of a cluster at rest ([`rest`]), which an engine does
    /// not reuse for another cluster.
    fn at_rest(&self) -> bool {
        false
    }
    /// The state needed to continue exactly (see [`IntegratorState`]).
    fn save(&self) -> IntegratorState;
    /// Restores a state saved by the same method for the same number of beads; any other
    /// state is an error ([`LoadError`]) and leaves the integrator unchanged.
    fn load(&mut self, s: &IntegratorState) -> Result<(), LoadError>;
}

/// Gauss–Legendre nodes (on `[0, 1]`) and weights of order 8, for [`dissipated_at`].
const GL4: [(f64, f64); 4] = [
    (0.069_431_844_202_973_71, 0.173_927_422_568_726_93),
    (0.330_009_478_207_571_87, 0.326_072_577_431_273_07),
    (0.669_990_521_792_428_1, 0.326_072_577_431_273_07),
    (0.930_568_155_797_026_3, 0.173_927_422_568_726_93),
];

/// Energy dissipated since the last reset at `t ∈ [t_prev, t]` of the last step: the value at
/// the step's ends exactly, inside it the value at `t_prev` plus the 4-point Gauss–Legendre
/// quadrature of the power along the continuous output. `scratch` holds the state and
/// accelerations at the nodes: grown to `3m` where shorter, so a caller that keeps it (the
/// engines' workspaces, sized for the whole chain) allocates nothing.
pub fn dissipated_at(
    integ: &dyn Integrator,
    sys: &dyn System,
    t: f64,
    scratch: &mut Vec<f64>,
) -> f64 {
    let (d0, d1) = integ.dissipated();
    let (t0, t1) = (integ.t_prev(), integ.t());
    if !sys.dissipative() || t >= t1 {
        return d1;
    }
    if t <= t0 {
        return d0;
    }
    let m = sys.len();
    if scratch.len() < 3 * m {
        scratch.resize(3 * m, 0.0);
    }
    // both written before they are read: `dense` sets all `2m` components, `accel` all `m`
    let (z, acc) = scratch.split_at_mut(2 * m);
    let acc = &mut acc[..m];
    let h = t - t0;
    let mut sum = 0.0;
    for (x, w) in GL4 {
        integ.dense(t0 + x * h, z);
        sum += w * sys.accel(&z[..m], &z[m..], acc);
    }
    d0 + h * sum
}

/// The max-norm of `err` weighted componentwise (u-part then v-part of length `m` each);
/// `vs` holds the `m` per-bead velocity scales ([`Tolerances::velocity_scales`]).
#[inline]
pub fn weighted_max_norm(
    err: &[f64],
    z_old: &[f64],
    z_new: &[f64],
    tol: &Tolerances,
    vs: &[f64],
) -> f64 {
    let m = err.len() / 2;
    let mut n: f64 = 0.0;
    for j in 0..m {
        n = n.max((err[j] / tol.weight_u(z_old[j], z_new[j])).abs());
    }
    for j in m..2 * m {
        n = n.max((err[j] / tol.weight_v(vs[j - m], z_old[j], z_new[j])).abs());
    }
    // f64::max ignores NaN: make a non-finite error count as a failed test.
    if err.iter().all(|x| x.is_finite()) {
        n
    } else {
        f64::INFINITY
    }
}

#[cfg(test)]
#[path = "renew_tests.rs"]
mod renew_tests;

/// Shared helpers of the integrators' unit tests.
#[cfg(test)]
pub(crate) mod test_util {
    use crate::model::Chain;

    /// `N` unit-mass beads, Hertz-like contacts `n = 2.5`, `a = 0.4`, no walls.
    pub fn uniform_chain(beads: usize) -> Chain {
        Chain {
            mass: vec![1.0; beads],
            exponent: vec![2.5; beads - 1],
            prefactor: vec![0.4; beads - 1],
            ..Chain::default()
        }
    }

    /// Striker initial condition (paper eq. 8): bead 0 moves at `v0`, all else at rest.
    pub fn striker(beads: usize, v0: f64) -> (Vec<f64>, Vec<f64>) {
        let mut v = vec![0.0; beads];
        v[0] = v0;
        (vec![0.0; beads], v)
    }
}
