//! Dormand–Prince 8(5,3) ("DOP853"): explicit Runge–Kutta of order 8 with a combined 5th/3rd
//! order error estimator and a 7th-order continuous (dense) output.
//!
//! Reference: E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I*,
//! 2nd ed., Sec. II.10 (and Hairer's Fortran `dop853.f`). Coefficients and algorithm are
//! transcribed from SciPy's `scipy/integrate/_ivp/dop853_coefficients.py` and class `DOP853` of
//! `scipy/integrate/_ivp/rk.py` (`rk_step`, `_step_impl`, `_estimate_error_norm`,
//! `_dense_output_impl`, `Dop853DenseOutput`); the starting step follows SciPy's
//! `select_initial_step` (`_ivp/common.py`), i.e. the algorithm of HNW I, II.4, p. 169.
//!
//! It integrates the first-order form of the equation of motion (paper eq. 7, appendix eqs.
//! A.2–A.3): `z = (u, v)`, `ż = (v, f(u))`, one [`System::accel`] call per stage.
//!
//! Departures from SciPy, all for the tolerance conventions of [`crate::integrate`]:
//! - Error norms are **max norms** over components with weights
//!   [`Tolerances::weight_u`]/[`Tolerances::weight_v`] instead of RMS norms. The combined estimator
//!   is `err = |h|·e5² / sqrt(e5² + 0.01·e3²)` with `e5`, `e3` the weighted max norms of the 5th
//!   and 3rd order estimates. A non-finite error (or new state) counts as a rejection.
//! - The initial-step heuristic (Hairer's, as in SciPy, for error-estimator order 7) is made
//!   dimensionless with the time scale `T = L/V` of [`Tolerances::scales`]: its absolute
//!   constants (`1e-6`, `1e-5`, `1e-15`) are read in units of `T`. With [`crate::model::Chain::scales`]
//!   the whole algorithm is then invariant under the similarity `v → λv`, `u → λ^{2/n}u`.
//! - Step control: safety 0.9, factors in `[0.2, 10]`, exponent −1/8, no increase after a
//!   rejection within the same step (as in SciPy). After an accepted step shortened to land on
//!   `t_bound` (an event time of the caller) the next proposal is at least the interrupted one
//!   (as OrdinaryDiffEq.jl does at `tstops`; SciPy would restart from the short step, whose
//!   error estimate is mostly rounding noise when it is very short).
//! - A step marked rough ([`Integrator::set_rough`]: at a kink of the right-hand side, where
//!   the combined estimate's smoothness assumption fails) needs `e5 ≤ 1` too (hybrid `kinks`).
//!   A rejected step that starts at the onset of a contact force `a δ₊ⁿ` ([`Rough::Onset`])
//!   with `n < 8` shrinks by `0.9·err^{−1/n}` (factors down to 0.01): its error grows like `hⁿ`
//!   (measured on a chain with gaps of 0.1, n = 2.5: `err` 75, 15, 4.9, 2.3, 1.4 at `h` 3.6,
//!   1.9, 1.2, 0.90, 0.73·10⁻³), so the smooth exponent `−1/8` took five rejections where
//!   this takes one.
//! - The three extra dense-output stages are evaluated eagerly after every accepted step (15
//!   right-hand sides per accepted step, 12 per rejected one), because [`Integrator::dense`]
//!   has no access to the system. Making them lazy would pay little in the hybrid engine: it
//!   reads the continuous output inside 87–100 % of accepted steps (closing predictions;
//!   measured on `granular_gas`, disorder, periodic decay, the interface, the striker and gaps
//!   of 0.1), so it would save at most 3 of 15 right-hand sides on the other 0–13 %.
//! - The stage sums run on a copy of the stages packed by groups of 4 components, over each
//!   row's nonzero coefficients written out at compile time ([`packed`]): the same bits as the
//!   plain loop, in fewer instructions on small clusters.

mod coefficients;
mod packed;
mod stages;
mod start;
mod state;

pub use state::Dop853State;

use super::{
    IntegrationError, Integrator, IntegratorState, LoadError, Rough, Stats, System, Tolerances,
};

/// Multiplier of the asymptotically optimal step.
const SAFETY: f64 = 0.9;
/// Smallest step-size factor after a rejection.
const MIN_FACTOR: f64 = 0.2;
/// Smallest step-size factor after a rejected step at a force's onset ([`Rough::Onset`]), whose
/// error's order is known: the first step after a closing is typically `err ≈ 10²` from the
/// tolerance, a factor `0.15` at `n = 2.5`.
const MIN_ONSET_FACTOR: f64 = 0.01;
/// Largest step-size factor after an acceptance.
const MAX_FACTOR: f64 = 10.0;
/// Step-size exponent `−1/(q+1)` for the error-estimator order `q = 7`.
const ERROR_EXPONENT: f64 = -1.0 / 8.0;
/// Main stages (0..12) plus the FSAL stage 12.
const N_MAIN: usize = 13;
/// All stages including the 3 extra dense-output stages.
const N_STAGES: usize = 16;
/// Number of coefficient vectors of the continuous output (degree 7).
const N_DENSE: usize = 7;

/// The DOP853 integrator for an `m`-bead [`System`]; all scratch is allocated by [`Dop853::new`].
#[derive(Clone, Debug)]
pub struct Dop853 {
    m: usize,
    tol: Tolerances,
    /// Per-bead velocity scales of the system being integrated (refreshed every step).
    vs: Vec<f64>,
    t: f64,
    t_prev: f64,
    /// The method's state as data: the proposed step (> 0), the states at `t` and `t_prev`
    /// (`2m` each), the stage derivatives (`N_STAGES × 2m`, stage 0 is `f(t, z)`) and the
    /// continuous-output coefficients of the last accepted step (`N_DENSE × 2m`); saved as it
    /// is, but for the stages a new integrator has not written and the power at `z`, which the
    /// step keeps in `pw[0]` ([`Dop853::save_state`]).
    st: Dop853State,
    /// Stage state / candidate new state.
    y: Vec<f64>,
    /// Scratch: 5th and 3rd order error estimates.
    e5: Vec<f64>,
    e3: Vec<f64>,
    /// Dissipated power at the main stages (stage 0 = at `z`; 0 for conservative systems).
    pw: [f64; N_MAIN],
    /// Energy dissipated since the reset, at `t_prev` and at `t`.
    diss: (f64, f64),
    /// The system is dissipative: `E_d` is an error-controlled component (set every step).
    damped: bool,
    /// Steps at a kink ([`Integrator::set_rough`]; set around steps, never saved).
    rough: Rough,
    stats: Stats,
    /// The stages packed by groups of 4 components for the stage sums of small states
    /// ([`packed`]; empty for longer ones).
    kp: Vec<f64>,
}

/// Distance from `|t|` to the next larger float.
#[inline]
fn ulp(t: f64) -> f64 {
    let a = t.abs();
    if a.is_finite() {
        f64::from_bits(a.to_bits() + 1) - a
    } else {
        f64::INFINITY
    }
}

/// `z = (u, v)` → `k = (v, f(u, v))`; returns the dissipated power at `z`.
#[inline(always)]
fn rhs(sys: &dyn System, stats: &mut Stats, z: &[f64], k: &mut [f64]) -> f64 {
    let m = z.len() / 2;
    k[..m].copy_from_slice(&z[m..]);
    stats.rhs_evals += 1;
    sys.accel(&z[..m], &z[m..], &mut k[m..])
}

/// [`rhs`] for a stage whose displacement half `k[..m]` [`packed::combine`] has already written.
#[inline(always)]
fn rhs_of_combined(sys: &dyn System, stats: &mut Stats, z: &[f64], k: &mut [f64]) -> f64 {
    let m = z.len() / 2;
    stats.rhs_evals += 1;
    sys.accel(&z[..m], &z[m..], &mut k[m..])
}

impl Dop853 {
    /// An integrator for `m` beads (state length `2m`) with tolerances `tol`. Call
    /// [`Integrator::reset`] before stepping.
    pub fn new(m: usize, tol: Tolerances) -> Self {
        let n = 2 * m;
        Self {
            m,
            tol,
            vs: vec![0.0; m],
            t: 0.0,
            t_prev: 0.0,
            st: Dop853State {
                h: 0.0,
                z: vec![0.0; n],
                z_old: vec![0.0; n],
                k: vec![0.0; N_STAGES * n],
                f: vec![0.0; N_DENSE * n],
                p0: 0.0,
            },
            y: vec![0.0; n],
            kp: vec![0.0; packed::packed_len(n)],
            e5: vec![0.0; n],
            e3: vec![0.0; n],
            pw: [0.0; N_MAIN],
            diss: (0.0, 0.0),
            damped: false,
            rough: Rough::Smooth,
            stats: Stats::default(),
        }
    }

    /// Number of beads the integrator was built for.
    pub fn len(&self) -> usize {
        self.m
    }

    /// True when built for zero beads.
    pub fn is_empty(&self) -> bool {
        self.m == 0
    }

    /// The tolerances in use.
    pub fn tolerances(&self) -> &Tolerances {
        &self.tol
    }

    /// Size proposed for the next step.
    pub fn step_size(&self) -> f64 {
        self.st.h
    }

    /// Weight of component `i` (u-part `i < m`, v-part otherwise) between two states.
    #[inline(always)]
    fn weight(&self, i: usize, a: f64, b: f64) -> f64 {
        if i < self.m {
            self.tol.weight_u(a, b)
        } else {
            self.tol.weight_v(self.vs[i - self.m], a, b)
        }
    }

    /// The part of [`Integrator::reset`] that sets the state: `z`, `f(z)` (stage 0), the
    /// continuous output (zero), the dissipation and the velocity scales.
    ///
    /// # Panics
    /// If `sys.len()`, `u.len()` or `v.len()` differs from the `m` given to [`Dop853::new`].
    fn start(&mut self, sys: &dyn System, t: f64, u: &[f64], v: &[f64]) {
        let m = self.m;
        super::assert_sizes(m, sys, u, v);
        self.t = t;
        self.t_prev = t;
        self.st.z[..m].copy_from_slice(u);
        self.st.z[m..].copy_from_slice(v);
        self.st.z_old.copy_from_slice(&self.st.z);
        self.st.f.fill(0.0);
        let (k0, _) = self.st.k.split_at_mut(2 * m);
        self.pw[0] = rhs(sys, &mut self.stats, &self.st.z, k0);
        packed::pack(&mut self.kp, 0, k0);
        self.diss = (0.0, 0.0);
        self.tol.velocity_scales(sys.mass(), &mut self.vs);
    }

    /// [`Integrator::step`] compiled for AVX2.
    ///
    /// # Safety
    /// The processor must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn step_avx2(
        &mut self,
        sys: &dyn System,
        t_bound: f64,
    ) -> Result<f64, IntegrationError> {
        self.step_any(sys, t_bound)
    }

    /// [`Self::step_impl`] for the state's length: on packed stages or not (inlined into the
    /// baseline and AVX2 versions of [`Integrator::step`]).
    #[inline(always)]
    fn step_any(&mut self, sys: &dyn System, t_bound: f64) -> Result<f64, IntegrationError> {
        if packed::use_packed(2 * self.m) {
            self.step_impl::<true>(sys, t_bound)
        } else {
            self.step_impl::<false>(sys, t_bound)
        }
    }

    /// The body of [`Integrator::step`] (inlined into its baseline and AVX2 versions).
    #[inline(always)]
    /// `P`: the stage sums run on the packed stages ([`packed::use_packed`]), decided once per
    /// step so that the code for long states is the plain loops alone.
    fn step_impl<const P: bool>(
        &mut self,
        sys: &dyn System,
        t_bound: f64,
    ) -> Result<f64, IntegrationError> {
        debug_assert_eq!(sys.len(), self.m);
        self.tol.velocity_scales(sys.mass(), &mut self.vs);
        self.damped = sys.dissipative();
        let t = self.t;
        if !t.is_finite() || !self.st.z.iter().all(|x| x.is_finite()) {
            return Err(IntegrationError::NonFinite { t });
        }
        if t_bound.is_nan() || t_bound <= t {
            return Ok(t);
        }
        let min_step = 10.0 * ulp(t);
        let mut h_abs = if self.st.h.is_finite() {
            self.st.h.max(min_step)
        } else {
            min_step
        };
        let mut rejected = false;
        let mut last_nonfinite = false;
        loop {
            if h_abs < min_step {
                self.st.h = h_abs;
                return Err(if last_nonfinite {
                    IntegrationError::NonFinite { t }
                } else {
                    IntegrationError::StepTooSmall { t, h: h_abs }
                });
            }
            let clipped = t + h_abs > t_bound;
            let t_new = if clipped { t_bound } else { t + h_abs };
            let h = t_new - t;
            self.main_stages::<P>(sys, h);
            let err = self.error_norm::<P>(h);
            if err < 1.0 {
                // Optimal next step from this step's error (uncapped).
                let h_opt = if err == 0.0 {
                    f64::INFINITY
                } else {
                    h * SAFETY * err.powf(ERROR_EXPONENT)
                };
                let mut h_next = (h * MAX_FACTOR).min(h_opt);
                if rejected {
                    h_next = h_next.min(h);
                } else if clipped {
                    // Shortened to land on t_bound: resume with the proposal it interrupted (the
                    // error of a much shorter step is rounding noise, a poor predictor).
                    h_next = h_next.max(h_abs);
                }
                self.st.h = h_next;
                std::mem::swap(&mut self.st.z_old, &mut self.st.z);
                std::mem::swap(&mut self.st.z, &mut self.y);
                self.t_prev = t;
                self.t = t_new;
                if sys.dissipative() {
                    self.diss = (self.diss.1, self.diss.1 + self.step_dissipation(h));
                    self.pw[0] = self.pw[N_MAIN - 1];
                }
                self.dense_coefficients::<P>(sys, h);
                self.stats.steps += 1;
                self.stats.bead_steps += self.m as u64;
                return Ok(t_new);
            }
            self.stats.rejected += 1;
            rejected = true;
            last_nonfinite = !err.is_finite();
            let factor = if last_nonfinite {
                MIN_FACTOR
            } else if let Rough::Onset(n) = self.rough.filter_onset(-1.0 / ERROR_EXPONENT) {
                // error ∝ hⁿ at a force's onset (`Rough::Onset`) rougher than the method
                MIN_ONSET_FACTOR.max(SAFETY * err.powf(-1.0 / n))
            } else {
                MIN_FACTOR.max(SAFETY * err.powf(ERROR_EXPONENT))
            };
            h_abs = h * factor;
        }
    }
}

impl Integrator for Dop853 {
    /// Starts from `(u, v)` at `t`: evaluates `f(z)` and Hairer's starting step (2 right-hand
    /// sides). Counters accumulate across resets.
    ///
    /// # Panics
    /// If `sys.len()`, `u.len()` or `v.len()` differs from the `m` given to [`Dop853::new`].
    fn reset(&mut self, sys: &dyn System, t: f64, u: &[f64], v: &[f64]) {
        self.start(sys, t, u, v);
        self.st.h = self.initial_step(sys);
    }

    /// As `reset`, without the starting-step estimate (its stage-1 and `y` scratch is
    /// overwritten by the first step before it is read, so the step is the same).
    fn restart(&mut self, sys: &dyn System, t: f64, u: &[f64], v: &[f64], h: f64) {
        self.start(sys, t, u, v);
        self.st.h = h;
    }

    /// One accepted step of at most `t_bound − t` (landing exactly on `t_bound` when shortened).
    /// Returns `t` unchanged, without stepping, when `t_bound ≤ t`.
    ///
    /// On x86-64 processors with AVX2 the same code runs compiled for AVX2 (twice the vector
    /// width for the stage sums): bit-identical results, since Rust never fuses or reorders
    /// floating-point operations (no fused multiply-add is enabled or formed).
    fn step(&mut self, sys: &dyn System, t_bound: f64) -> Result<f64, IntegrationError> {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: `step_avx2` requires AVX2, which the processor was just checked to have.
            return unsafe { self.step_avx2(sys, t_bound) };
        }
        self.step_any(sys, t_bound)
    }

    fn step_size(&self) -> f64 {
        self.st.h
    }

    fn set_step_size(&mut self, h: f64) {
        self.st.h = h;
    }

    fn set_rough(&mut self, rough: Rough) {
        self.rough = rough;
    }

    fn t(&self) -> f64 {
        self.t
    }

    fn t_prev(&self) -> f64 {
        self.t_prev
    }

    fn state(&self) -> &[f64] {
        &self.st.z
    }

    /// The 7th-order continuous output of the last accepted step (SciPy `Dop853DenseOutput`);
    /// exact copies of the endpoint states at `t_prev` and `t`.
    fn dense(&self, t: f64, z: &mut [f64]) {
        let n = 2 * self.m;
        debug_assert_eq!(z.len(), n);
        if t == self.t {
            z.copy_from_slice(&self.st.z);
            return;
        }
        if t == self.t_prev {
            z.copy_from_slice(&self.st.z_old);
            return;
        }
        let x = (t - self.t_prev) / (self.t - self.t_prev);
        let x1 = 1.0 - x;
        let f = &self.st.f;
        for (i, zi) in z.iter_mut().enumerate() {
            let mut p = f[5 * n + i] + x * f[6 * n + i];
            p = f[4 * n + i] + x1 * p;
            p = f[3 * n + i] + x * p;
            p = f[2 * n + i] + x1 * p;
            p = f[n + i] + x * p;
            p = f[i] + x1 * p;
            *zi = self.st.z_old[i] + x * p;
        }
    }

    fn dense_at(&self, t: f64, j: usize) -> f64 {
        let n = 2 * self.m;
        if t == self.t {
            return self.st.z[j];
        }
        if t == self.t_prev {
            return self.st.z_old[j];
        }
        let x = (t - self.t_prev) / (self.t - self.t_prev);
        let x1 = 1.0 - x;
        let f = &self.st.f;
        let mut p = f[5 * n + j] + x * f[6 * n + j];
        p = f[4 * n + j] + x1 * p;
        p = f[3 * n + j] + x * p;
        p = f[2 * n + j] + x1 * p;
        p = f[n + j] + x * p;
        p = f[j] + x1 * p;
        self.st.z_old[j] + x * p
    }

    fn end_states(&self) -> Option<(&[f64], &[f64])> {
        Some((&self.st.z_old, &self.st.z))
    }

    fn rate(&self) -> Option<&[f64]> {
        Some(&self.st.k[..2 * self.m])
    }

    /// Resizes the arrays in place. Their old contents are never read: [`Integrator::reset`]
    /// sets `z`, `z_old`, `f`, stage 0 and the velocity scales, and a step writes every stage
    /// and scratch entry before reading it; stages 2–15 saved before the first step are written
    /// as zeros ([`Integrator::save`]), as a new integrator holds them.
    fn renew(&mut self, m: usize, tol: Tolerances) -> bool {
        self.renew_arrays(m, tol)
    }

    fn stats(&self) -> &Stats {
        &self.stats
    }

    fn dissipated(&self) -> (f64, f64) {
        self.diss
    }

    fn save(&self) -> IntegratorState {
        self.save_state()
    }

    fn load(&mut self, s: &IntegratorState) -> Result<(), LoadError> {
        self.load_state(s)
    }
}

#[cfg(test)]
mod ode_tests;

#[cfg(test)]
mod tests;
