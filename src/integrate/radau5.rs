//! Radau IIA of order 5 with step-size control and collocation (dense) output.
//!
//! Reference: E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II*, 2nd ed.,
//! Sec. IV.8 (RADAU5): simplified Newton iteration on the transformed stage system (one real
//! eigenvalue `γ = 1/μ_r` and a complex pair), the embedded error estimate filtered by
//! `(μ_r/h I − J)⁻¹`, Gustafsson's predictive step control, and the collocation polynomial as
//! continuous output. The constants follow SciPy's `Radau` (same algorithm).
//!
//! Specialisation to bead chains (paper appendix, eq. A.3): `z = (u, v)`, `ż = (v, f(u))`, so
//! `J = [[0, I], [K, 0]]` with `K = −M⁻¹ L(k)` tridiagonal. Each Newton system `(c I − J) x = r`
//! reduces to the `m × m` symmetric tridiagonal system
//! `(c² M + L(k)) x_u = M (r_v + c r_u)`, `x_v = c x_u − r_u` (see [`crate::linalg`]),
//! real for `c = μ_r/h` and complex for `c = μ_c/h`. The Jacobian (the contact stiffnesses `k`)
//! comes for free with the force evaluation at the start of every step (same `powf`), so it is
//! always current and both systems are refactorised per step attempt, in `O(m)`.

use super::{IntegrationError, Integrator, IntegratorState, LoadError, Stats, System, Tolerances};
use crate::linalg::{new_solver, SolverKind, TridiagSolver};
use num_complex::Complex64;

mod linear;
mod newton;
mod state;
mod step;

pub use state::Radau5State;

const S6: f64 = 2.449_489_742_783_178; // sqrt(6)
/// Collocation nodes.
const C: [f64; 3] = [(4.0 - S6) / 10.0, (4.0 + S6) / 10.0, 1.0];
/// Error-estimate weights (divided by 3 as in SciPy).
const E: [f64; 3] = [
    (-13.0 - 7.0 * S6) / 3.0,
    (-13.0 + 7.0 * S6) / 3.0,
    -1.0 / 3.0,
];
/// Real eigenvalue of the inverse Radau matrix: 3 + 3^(2/3) − 3^(1/3).
const MU_REAL: f64 = 3.637_834_252_744_496;
/// Complex eigenvalue: 3 + (3^(1/3) − 3^(2/3))/2 − i (3^(5/6) + 3^(7/6))/2.
const MU_COMPLEX: (f64, f64) = (2.681_082_873_627_752, -3.050_430_199_247_411);
#[allow(clippy::excessive_precision)] // SciPy/Hairer constants as published
const T: [[f64; 3]; 3] = [
    [
        0.094_438_762_488_975_24,
        -0.141_255_295_020_954_21,
        0.030_029_194_105_147_42,
    ],
    [
        0.250_213_122_965_333_32,
        0.204_129_352_293_799_94,
        -0.382_942_112_757_261_92,
    ],
    [1.0, 1.0, 0.0],
];
#[allow(clippy::excessive_precision)]
const TI: [[f64; 3]; 3] = [
    [
        4.178_718_591_551_904_28,
        0.327_682_820_761_062_37,
        0.523_376_445_499_449_51,
    ],
    [
        -4.178_718_591_551_904_28,
        -0.327_682_820_761_062_37,
        0.476_623_554_500_550_44,
    ],
    [
        0.502_872_634_945_786_82,
        -2.571_926_949_855_605_22,
        0.596_039_204_828_224_92,
    ],
];
/// Collocation interpolant coefficients.
const P: [[f64; 3]; 3] = [
    [
        13.0 / 3.0 + 7.0 * S6 / 3.0,
        -23.0 / 3.0 - 22.0 * S6 / 3.0,
        10.0 / 3.0 + 5.0 * S6,
    ],
    [
        13.0 / 3.0 - 7.0 * S6 / 3.0,
        -23.0 / 3.0 + 22.0 * S6 / 3.0,
        10.0 / 3.0 - 5.0 * S6,
    ],
    [1.0 / 3.0, -8.0 / 3.0, 10.0 / 3.0],
];
/// The Radau IIA matrix (its last row holds the quadrature weights).
const RADAU_A: [[f64; 3]; 3] = [
    [
        (88.0 - 7.0 * S6) / 360.0,
        (296.0 - 169.0 * S6) / 1800.0,
        (-2.0 + 3.0 * S6) / 225.0,
    ],
    [
        (296.0 + 169.0 * S6) / 1800.0,
        (88.0 + 7.0 * S6) / 360.0,
        (-2.0 - 3.0 * S6) / 225.0,
    ],
    [(16.0 - S6) / 36.0, (16.0 + S6) / 36.0, 1.0 / 9.0],
];
const NEWTON_MAXITER: usize = 6;
/// A Newton increment below this fraction of the Newton tolerance counts as converged.
const NEGLIGIBLE_NEWTON: f64 = 1e-3;
/// A Newton increment component within this many ulps of the state component it moves is
/// rounding noise ([`Radau5::newton`]).
const ROUNDING_NEWTON: f64 = 64.0;
/// A step that would leave less than this fraction of itself before `t_bound` is stretched to
/// land on it (no sliver steps of a few ulps, whose stage times would coincide).
const STRETCH: f64 = 1e-3;
const MIN_FACTOR: f64 = 0.2;
const MAX_FACTOR: f64 = 10.0;

/// Radau IIA (order 5) integrator for a [`System`] of `m` beads. Holds only scratch buffers.
pub struct Radau5 {
    m: usize,
    tol: Tolerances,
    /// Per-bead velocity scales of the system being integrated (refreshed every step).
    vs: Vec<f64>,
    newton_tol: f64,
    /// The linear solver asked for (`Auto` resolved per size by [`crate::linalg::resolve`]).
    solver: SolverKind,
    real: Box<dyn TridiagSolver<f64>>,
    cplx: Box<dyn TridiagSolver<Complex64>>,
    t: f64,
    t_old: f64,
    /// The method's state as data, saved as it is ([`Radau5State`]): the step size and the
    /// controller's memory, the states at `t` and `t_old`, `F(z)`, the stiffnesses and damping
    /// Jacobian at `z` (`m + 1`: contacts, then left/right wall), the dissipated power at `z`,
    /// and the dense-output coefficients of the last accepted step (valid when `have_sol`).
    st: Radau5State,
    /// Energy dissipated since the reset, at `t_old` and at `t`.
    diss: (f64, f64),
    /// Dissipated power at the three stages of the step being tried.
    ps: [f64; 3],
    zs: [Vec<f64>; 3],
    w: [Vec<f64>; 3],
    fs: [Vec<f64>; 3],
    // scratch
    dw: [Vec<f64>; 3],
    ytmp: Vec<f64>,
    /// Scratch for the stage states of [`Self::stage_dissipation`] (`ytmp` holds the new state).
    ytmp_d: Vec<f64>,
    acc: Vec<f64>,
    ktmp: Vec<f64>,
    kvtmp: Vec<f64>,
    d_r: Vec<f64>,
    e_r: Vec<f64>,
    d_c: Vec<Complex64>,
    e_c: Vec<Complex64>,
    rhs_c: Vec<Complex64>,
    err: Vec<f64>,
    inv_w: Vec<f64>,
    stats: Stats,
}

impl Radau5 {
    /// A solver for systems of `m` beads with the given tolerances and linear solver.
    pub fn new(m: usize, tol: Tolerances, kind: SolverKind) -> Self {
        let n = 2 * m;
        let v = || vec![0.0; n];
        Self {
            m,
            tol,
            vs: vec![0.0; m],
            newton_tol: newton_tol(tol.rtol),
            solver: kind,
            real: new_solver::<f64>(kind, m),
            cplx: new_solver::<Complex64>(kind, m),
            t: 0.0,
            t_old: 0.0,
            st: Radau5State {
                h: 0.0,
                h_old: None,
                err_old: None,
                have_sol: false,
                z: v(),
                z_old: v(),
                f: v(),
                k: vec![0.0; m + 1],
                q: [v(), v(), v()],
                kv: vec![0.0; m + 1],
                p0: 0.0,
            },
            diss: (0.0, 0.0),
            ps: [0.0; 3],
            zs: [v(), v(), v()],
            w: [v(), v(), v()],
            fs: [v(), v(), v()],
            dw: [v(), v(), v()],
            ytmp: v(),
            ytmp_d: v(),
            acc: vec![0.0; m],
            ktmp: vec![0.0; m + 1],
            kvtmp: vec![0.0; m + 1],
            d_r: vec![0.0; m],
            e_r: vec![0.0; m.saturating_sub(1)],
            d_c: vec![Complex64::new(0.0, 0.0); m],
            e_c: vec![Complex64::new(0.0, 0.0); m.saturating_sub(1)],
            rhs_c: vec![Complex64::new(0.0, 0.0); m],
            err: v(),
            inv_w: v(),
            stats: Stats::default(),
        }
    }

    /// The tolerances in use.
    pub fn tolerances(&self) -> &Tolerances {
        &self.tol
    }

    /// Current step-size proposal.
    pub fn step_size(&self) -> f64 {
        self.st.h
    }

    /// `F(y)` into `out` (u-part = v, v-part = f(u)); counts one RHS evaluation.
    fn rhs(sys: &dyn System, m: usize, y: &[f64], out: &mut [f64], stats: &mut Stats) {
        let (ou, ov) = out.split_at_mut(m);
        ou.copy_from_slice(&y[m..]);
        sys.accel(&y[..m], &y[m..], ov);
        stats.rhs_evals += 1;
    }

    fn weights_norm(&self, x: &[f64], y_a: &[f64], y_b: &[f64]) -> f64 {
        super::weighted_max_norm(x, y_a, y_b, &self.tol, &self.vs)
    }

    /// Factorises `(c² M + c L(k_v) + L(k))` for `c = μ_r/h` and `c = μ_c/h`
    /// ([`linear::newton_matrix`]).
    fn factorize(&mut self, sys: &dyn System, h: f64) -> bool {
        let mass = sys.mass();
        let kv = sys.dissipative().then_some(&self.st.kv[..]);
        let cr = MU_REAL / h;
        let cc = Complex64::new(MU_COMPLEX.0, MU_COMPLEX.1) / h;
        linear::newton_matrix(mass, &self.st.k, kv, cr, &mut self.d_r, &mut self.e_r);
        linear::newton_matrix(mass, &self.st.k, kv, cc, &mut self.d_c, &mut self.e_c);
        self.stats.factorizations += 1;
        self.real.factorize(&self.d_r, &self.e_r).is_ok()
            && self.cplx.factorize(&self.d_c, &self.e_c).is_ok()
    }

    /// The damping block for the Newton solves (`None` for a conservative system).
    fn kv_of<'a>(sys: &dyn System, kv: &'a [f64]) -> Option<&'a [f64]> {
        sys.dissipative().then_some(kv)
    }

    /// Initial step (Hairer's algorithm, error-estimator order 3), scale-free via the
    /// characteristic time of the tolerances' scales.
    fn initial_step(&mut self, sys: &dyn System) -> f64 {
        let tau = self.tol.scales.time();
        let d0 = self.weights_norm(&self.st.z, &self.st.z, &self.st.z);
        let d1 = self.weights_norm(&self.st.f, &self.st.z, &self.st.z);
        let h0 = if d0 < 1e-5 || d1 < 1e-5 {
            1e-6 * tau
        } else {
            0.01 * d0 / d1
        };
        for j in 0..2 * self.m {
            self.ytmp[j] = self.st.z[j] + h0 * self.st.f[j];
        }
        let mut f1 = std::mem::take(&mut self.err);
        Self::rhs(sys, self.m, &self.ytmp, &mut f1, &mut self.stats);
        for j in 0..2 * self.m {
            f1[j] -= self.st.f[j];
        }
        let d2 = self.weights_norm(&f1, &self.st.z, &self.st.z) / h0;
        self.err = f1;
        let h1 = if d1 <= 1e-15 && d2 <= 1e-15 {
            (1e-6 * tau).max(h0 * 1e-3)
        } else {
            (0.01 / d1.max(d2)).powf(1.0 / 4.0)
        };
        (100.0 * h0).min(h1)
    }

    /// Advances to `t_bound` (a few ulps away) by one explicit Euler step; the continuous output
    /// over it is the straight line.
    fn micro_step(&mut self, sys: &dyn System, t_bound: f64) {
        let m = self.m;
        let dt = t_bound - self.t;
        self.st.z_old.copy_from_slice(&self.st.z);
        for j in 0..2 * m {
            self.st.q[0][j] = dt * self.st.f[j];
            self.st.q[1][j] = 0.0;
            self.st.q[2][j] = 0.0;
            self.st.z[j] += self.st.q[0][j];
        }
        self.t_old = self.t;
        self.t = t_bound;
        self.st.have_sol = true;
        self.st.f[..m].copy_from_slice(&self.st.z[m..]);
        let (u, v) = self.st.z.split_at(m);
        self.diss = (self.diss.1, self.diss.1 + dt * self.st.p0);
        self.st.p0 = sys.accel_stiffness(u, v, &mut self.acc, &mut self.st.k, &mut self.st.kv);
        self.st.f[m..].copy_from_slice(&self.acc);
        self.stats.rhs_evals += 1;
        self.stats.jac_evals += 1;
        self.stats.steps += 1;
        self.stats.bead_steps += m as u64;
    }

    /// Takes the accepted step `t → t_new` of size `h_abs` with error `err_norm` (and
    /// dissipated energy `d_step`), and proposes `h_abs · factor` next; a step clipped to land
    /// on the bound keeps at least the proposal it replaced (`keep`).
    fn accept(
        &mut self,
        sys: &dyn System,
        (t, t_new): (f64, f64),
        (h_abs, factor): (f64, f64),
        (err_norm, d_step): (f64, f64),
        keep: Option<f64>,
    ) -> Result<f64, IntegrationError> {
        if sys.dissipative() {
            self.diss = (self.diss.1, self.diss.1 + d_step);
        }
        self.advance(sys, t, t_new);
        self.st.h_old = Some(h_abs);
        self.st.err_old = Some(err_norm);
        self.st.h = h_abs * factor;
        if let Some(h_request) = keep {
            // A step clipped to land on t_bound says nothing against the proposal it replaced.
            self.st.h = self.st.h.max(h_request);
        }
        if !self.st.z.iter().all(|x| x.is_finite()) {
            return Err(IntegrationError::NonFinite { t: self.t });
        }
        Ok(self.t)
    }
}

/// The Newton iteration's tolerance at relative tolerance `rtol`.
fn newton_tol(rtol: f64) -> f64 {
    (10.0 * f64::EPSILON / rtol).max(0.03_f64.min(rtol.sqrt()))
}

/// Smallest previous error the predictive controller extrapolates from (Hairer's RADAU5 stores
/// `ERRACC = max(1e-2, err)`): below it the previous error says nothing about the trend, and
/// one of zero (a step in free flight, integrated exactly) made the next step zero.
const MIN_ERR_OLD: f64 = 1e-2;

/// Step-size factor from the error `err` of a step of size `h` and, when known, the previous
/// accepted step's size and error (Gustafsson's predictive controller, HNW II, IV.8, as in
/// SciPy's `Radau` with RADAU5's floor [`MIN_ERR_OLD`] on the previous error).
fn predict_factor(h: f64, h_old: Option<f64>, err: f64, err_old: Option<f64>) -> f64 {
    if err == 0.0 {
        return MAX_FACTOR;
    }
    let multiplier = match (h_old, err_old) {
        (Some(ho), Some(eo)) => h / ho * (eo.max(MIN_ERR_OLD) / err).powf(0.25),
        _ => 1.0,
    };
    multiplier.min(1.0) * err.powf(-0.25)
}

impl Integrator for Radau5 {
    fn reset(&mut self, sys: &dyn System, t: f64, u: &[f64], v: &[f64]) {
        let m = self.m;
        debug_assert_eq!(sys.len(), m);
        self.t = t;
        self.t_old = t;
        self.st.z[..m].copy_from_slice(u);
        self.st.z[m..].copy_from_slice(v);
        self.st.z_old.copy_from_slice(&self.st.z);
        self.st.f[..m].copy_from_slice(v);
        self.st.p0 =
            sys.accel_stiffness(u, v, &mut self.st.f[m..], &mut self.st.k, &mut self.st.kv);
        self.diss = (0.0, 0.0);
        self.stats.rhs_evals += 1;
        self.stats.jac_evals += 1;
        self.st.have_sol = false;
        self.st.h_old = None;
        self.st.err_old = None;
        self.tol.velocity_scales(sys.mass(), &mut self.vs);
        self.st.h = self.initial_step(sys);
        for qi in self.st.q.iter_mut() {
            qi.fill(0.0);
        }
    }

    fn step_size(&self) -> f64 {
        self.st.h
    }

    fn set_step_size(&mut self, h: f64) {
        self.st.h = h;
        self.st.h_old = None;
        self.st.err_old = None;
    }

    fn step(&mut self, sys: &dyn System, t_bound: f64) -> Result<f64, IntegrationError> {
        self.tol.velocity_scales(sys.mass(), &mut self.vs);
        let t = self.t;
        let min_step = 10.0 * (next_up(t.abs()) - t.abs());
        if t_bound > t && t_bound - t <= min_step {
            // Only a few ulps to go: the Radau stages would coincide. Advance by an explicit
            // Euler step (error O(Δt²), far below rounding of the state at this Δt).
            self.micro_step(sys, t_bound);
            return Ok(self.t);
        }
        let mut h_abs = self.st.h.max(min_step);
        let h_request = h_abs;
        let mut h_abs_old = self.st.h_old;
        let mut err_old = self.st.err_old;
        let mut rejected = false;
        loop {
            if h_abs < min_step || !h_abs.is_finite() {
                return Err(IntegrationError::StepTooSmall { t, h: h_abs });
            }
            let mut t_new = t + h_abs;
            if t_new >= t_bound || t_bound - t_new <= STRETCH * h_abs {
                t_new = t_bound;
            }
            let h = t_new - t;
            if h <= 0.0 {
                return Err(IntegrationError::StepTooSmall { t, h });
            }
            h_abs = h;
            self.predict_stages(h);
            if !self.factorize(sys, h) {
                self.stats.rejected += 1;
                h_abs *= 0.5;
                continue;
            }
            let (converged, n_iter, _rate) = self.newton(sys, h);
            if !converged {
                self.stats.newton_failures += 1;
                self.stats.rejected += 1;
                h_abs *= 0.5;
                rejected = true;
                continue;
            }
            let (err_norm, d_step) = self.error_estimate(sys, h, rejected);
            let safety =
                0.9 * (2 * NEWTON_MAXITER + 1) as f64 / (2 * NEWTON_MAXITER + n_iter) as f64;
            if err_norm.is_nan() || err_norm > 1.0 {
                let factor = if err_norm.is_finite() {
                    predict_factor(h_abs, h_abs_old, err_norm, err_old)
                } else {
                    MIN_FACTOR
                };
                h_abs *= MIN_FACTOR.max(safety * factor);
                self.stats.rejected += 1;
                rejected = true;
                // the two-step predictor needs consistent history after a rejection
                h_abs_old = None;
                err_old = None;
                continue;
            }
            // accepted
            let factor = predict_factor(h_abs, h_abs_old, err_norm, err_old);
            // bounded below as well, as RADAU5's `FACL`: an accepted step never cuts the next
            // one by more than a rejected step would
            let mut factor = MAX_FACTOR.min(safety * factor).max(MIN_FACTOR);
            if rejected {
                factor = factor.min(1.0);
            }
            let clipped = t_new == t_bound && !rejected;
            return self.accept(
                sys,
                (t, t_new),
                (h_abs, factor),
                (err_norm, d_step),
                clipped.then_some(h_request),
            );
        }
    }

    fn t(&self) -> f64 {
        self.t
    }

    fn t_prev(&self) -> f64 {
        self.t_old
    }

    fn state(&self) -> &[f64] {
        &self.st.z
    }

    fn dense(&self, t: f64, z: &mut [f64]) {
        if !self.st.have_sol || self.t == self.t_old {
            z.copy_from_slice(&self.st.z);
            return;
        }
        if t == self.t {
            z.copy_from_slice(&self.st.z);
            return;
        }
        let x = (t - self.t_old) / (self.t - self.t_old);
        let (x1, x2, x3) = (x, x * x, x * x * x);
        for (j, zj) in z.iter_mut().enumerate() {
            *zj = self.st.z_old[j]
                + self.st.q[0][j] * x1
                + self.st.q[1][j] * x2
                + self.st.q[2][j] * x3;
        }
    }

    fn dense_at(&self, t: f64, j: usize) -> f64 {
        if !self.st.have_sol || self.t == self.t_old || t == self.t {
            return self.st.z[j];
        }
        let x = (t - self.t_old) / (self.t - self.t_old);
        self.st.z_old[j] + x * (self.st.q[0][j] + x * (self.st.q[1][j] + x * self.st.q[2][j]))
    }

    fn stats(&self) -> &Stats {
        &self.stats
    }

    fn implicit_steps(&self) -> u64 {
        self.stats.steps
    }

    fn dissipated(&self) -> (f64, f64) {
        self.diss
    }

    /// Every array resized in place and zeroed, every other field as [`Radau5::new`] sets it,
    /// the linear solvers prepared for the new size ([`TridiagSolver::pattern`]).
    fn renew(&mut self, m: usize, tol: Tolerances) -> bool {
        self.renew_arrays(m, tol);
        true
    }

    fn save(&self) -> IntegratorState {
        self.save_state()
    }

    fn load(&mut self, s: &IntegratorState) -> Result<(), LoadError> {
        self.load_state(s)
    }
}

/// Smallest float greater than `x ≥ 0`.
fn next_up(x: f64) -> f64 {
    if x.is_nan() || x == f64::INFINITY {
        return x;
    }
    f64::from_bits(x.to_bits() + 1)
}
