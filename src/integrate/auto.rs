//! Per-cluster method choice ("auto"): the explicit DOP853 while the system is non-stiff, the
//! implicit Radau IIA when it is stiff, switched as the integration runs.
//!
//! ## Stiffness test
//! The linearised system `ẅ = −M⁻¹K w` (paper appendix, eq. A.3, `K` tridiagonal from the
//! contact stiffnesses `k_c = n a δ^{n−2}(n−1)` and the walls) has the eigenvalues `±iω`. Its
//! largest `ω² = λ_max(M^{-1/2} K M^{-1/2})` is bounded by Gershgorin's theorem:
//! `ω²_max ≤ max_i [(k_{i−1} + k_i)/m_i + k_{i−1}/√(m_{i−1}m_i) + k_i/√(m_i m_{i+1})]`, exact within
//! a factor 2 (for a uniform chain the bound is the band edge `4k/m` itself). DOP853 is stable
//! on the imaginary axis up to `hω ≈ 5.9` (its stability function, Hairer & Wanner II, IV.2,
//! evaluated numerically from the tableau: `|R(5.75i)| = 0.74`, `|R(6.0i)| = 1.08`); where its
//! step is limited by that boundary rather than by its error estimate, the system is stiff for
//! it and an implicit method takes far longer steps.
//!
//! ## Switching rule (deterministic, with hysteresis)
//! After every [`STRIDE`]-th accepted step (of size `h`) the bound `ρ = h·ω_max` is evaluated at
//! the new state (one stiffness evaluation, so the test costs about 1/(15·STRIDE) of DOP853's
//! right-hand sides):
//! - explicit: `ρ > RHO_STIFF` on [`STREAK`] consecutive tests → Radau IIA from the next step;
//! - implicit: `ρ' = h_next·ω_max < RHO_NONSTIFF` on [`STREAK`] consecutive tests (the explicit
//!   method would be stable with room to spare at the step Radau itself proposes) → DOP853.
//!
//! The switch happens at the start of the next step, so the continuous output of the last step
//! stays valid for the caller's event location. The new method starts from the current state
//! with the current step size. Everything the rule depends on (mode, streak, pending switch) is
//! part of the saved state, so a resumed run switches at the same steps: same bytes out.

use super::dop853::Dop853;
use super::radau5::Radau5;
use super::{
    IntegrationError, Integrator, IntegratorState, LoadError, Method, Stats, System, Tolerances,
};
use crate::linalg::SolverKind;
use crate::names::Named;
use serde::{Deserialize, Serialize};

/// `ρ` above which an explicit step counts as stability-limited.
pub const RHO_STIFF: f64 = 4.0;
/// `ρ` below which an implicit step would be comfortably stable for the explicit method.
pub const RHO_NONSTIFF: f64 = 1.5;
/// The stiffness test runs after every `STRIDE`-th accepted step.
pub const STRIDE: u32 = 4;
/// Consecutive tests that must agree before a switch (`STREAK · STRIDE` steps).
pub const STREAK: u32 = 4;

/// The switching state of an [`Auto`] integrator (saved in checkpoints).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AutoState {
    /// Radau IIA is the active method.
    pub implicit: bool,
    /// Consecutive stiffness tests voting for a switch.
    pub streak: u32,
    /// Accepted steps since the last stiffness test.
    pub since: u32,
    /// Switch at the start of the next step.
    pub pending: bool,
    /// Accepted steps taken by the implicit method so far.
    pub implicit_steps: u64,
    /// Energy dissipated in the phases before the current one (since the last reset).
    pub diss_base: f64,
}

/// DOP853 and Radau IIA behind one [`Integrator`], switched by the rule of the module docs.
///
/// Only DOP853 is built with the integrator: Radau IIA (some 40 arrays and two tridiagonal
/// solvers) is built at the first switch to it, and the stiffness-test scratch at the first
/// test. A hybrid run makes a new integrator for every cluster it forms (one per gap event), and
/// most clusters live a few explicit steps: building and dropping Radau IIA for each of them was
/// ~10 % of the instructions of a 1000-bead striker run (`valgrind --tool=callgrind`). Building
/// it later changes no number: [`Integrator::reset`] sets every array a step reads. A renewed
/// integrator ([`Integrator::renew`], the hybrid engine's reuse of a removed cluster's) keeps
/// the Radau IIA it built and renews it at its next switch to it, as it renews DOP853.
pub struct Auto {
    m: usize,
    tol: Tolerances,
    solver: SolverKind,
    dop: Dop853,
    /// Built at the first switch to the implicit method (or by `new`/`load` when implicit).
    radau: Option<Box<Radau5>>,
    /// `radau` was built or last renewed for another cluster (this integrator was renewed
    /// since): it is renewed for `m`, `tol` before it is used.
    radau_stale: bool,
    mode: AutoState,
    stats: Stats,
    /// Scratch, empty until the first stiffness test or switch: state copy at a switch (`2m`),
    /// accelerations (`m`), stiffnesses (`m + 1`), damping Jacobian (`m + 1`).
    scratch: Vec<f64>,
}

impl Auto {
    /// An `m`-bead integrator, starting explicit (or implicit when `implicit`).
    pub fn new(m: usize, tol: Tolerances, solver: SolverKind, implicit: bool) -> Self {
        let mut auto = Self {
            m,
            tol,
            solver,
            dop: Dop853::new(m, tol),
            radau: None,
            radau_stale: false,
            mode: AutoState {
                implicit,
                ..AutoState::default()
            },
            stats: Stats::default(),
            scratch: Vec::new(),
        };
        if implicit {
            auto.build_radau();
        }
        auto
    }

    /// Builds the implicit integrator if it does not exist yet, or renews the one kept from
    /// another cluster (the integrator `new` builds, in its allocations).
    fn build_radau(&mut self) -> &mut Radau5 {
        let (m, tol, solver) = (self.m, self.tol, self.solver);
        if std::mem::take(&mut self.radau_stale) {
            if let Some(r) = self.radau.as_mut() {
                r.renew(m, tol);
            }
        }
        self.radau
            .get_or_insert_with(|| Box::new(Radau5::new(m, tol, solver)))
    }

    /// The implicit integrator when it is the active one (else DOP853 is): lets the hot
    /// read-only calls (`dense_at`, `t`, …) reach the concrete type, a static call, instead of
    /// a second dynamic dispatch through [`Auto::active`].
    #[inline(always)]
    fn implicit_active(&self) -> Option<&Radau5> {
        match (&self.radau, self.mode.implicit) {
            (Some(r), true) => Some(r),
            _ => None,
        }
    }

    fn active(&self) -> &dyn Integrator {
        match self.implicit_active() {
            Some(r) => r,
            None => &self.dop,
        }
    }

    fn active_mut(&mut self) -> &mut dyn Integrator {
        match (&mut self.radau, self.mode.implicit) {
            (Some(r), true) => &mut **r,
            _ => &mut self.dop,
        }
    }

    /// Upper bound of the largest angular frequency at the current state (module docs).
    fn omega_max(&mut self, sys: &dyn System) -> f64 {
        let m = self.m;
        self.scratch.resize(5 * m + 2, 0.0);
        let (_, rest) = self.scratch.split_at_mut(2 * m);
        let (acc, rest) = rest.split_at_mut(m);
        let (k, kv) = rest.split_at_mut(m + 1);
        let z = match (&self.radau, self.mode.implicit) {
            (Some(r), true) => r.state(),
            _ => self.dop.state(),
        };
        sys.accel_stiffness(&z[..m], &z[m..], acc, k, kv);
        let mass = sys.mass();
        let w = gershgorin_sqrt(mass, k);
        if sys.dissipative() {
            // Damping moves the eigenvalues to λ = −γ ± sqrt(γ² − ω²): |λ| ≤ ω + g with g the
            // Gershgorin bound of M⁻¹ L(k_v).
            w + gershgorin_sqrt(mass, kv).powi(2)
        } else {
            w
        }
    }

    /// Applies a pending switch: the other method starts from the current state and step.
    fn switch(&mut self, sys: &dyn System) {
        let m = self.m;
        let (t, h) = (self.active().t(), self.active().step_size());
        let diss = self.active().dissipated().1;
        let mut zbuf = std::mem::take(&mut self.scratch);
        zbuf.resize(5 * m + 2, 0.0);
        zbuf[..2 * m].copy_from_slice(self.active().state());
        self.mode.diss_base += diss;
        self.mode.implicit = !self.mode.implicit;
        self.mode.streak = 0;
        self.mode.since = 0;
        self.mode.pending = false;
        if self.mode.implicit {
            self.build_radau();
        }
        let (u, v) = zbuf[..2 * m].split_at(m);
        let before = self.active().stats().clone();
        let next = self.active_mut();
        next.restart(sys, t, u, v, h);
        let now = next.stats().clone();
        add_diff(&mut self.stats, &now, &before);
        self.scratch = zbuf;
    }

    /// Votes after an accepted step (module docs).
    fn vote(&mut self, sys: &dyn System, h: f64) {
        let w = self.omega_max(sys);
        let agree = if self.mode.implicit {
            self.active().step_size() * w < RHO_NONSTIFF
        } else {
            h * w > RHO_STIFF
        };
        self.mode.streak = if agree { self.mode.streak + 1 } else { 0 };
        if self.mode.streak >= STREAK {
            self.mode.pending = true;
        }
    }

    /// (Re)starts the active method with `start` (a reset or restart), counting its work.
    fn start_active(&mut self, start: impl FnOnce(&mut dyn Integrator)) {
        let before = self.active().stats().clone();
        start(self.active_mut());
        self.mode.diss_base = 0.0;
        self.mode.pending = false;
        let now = self.active().stats().clone();
        add_diff(&mut self.stats, &now, &before);
    }

    /// Accepted steps taken by the implicit method.
    pub fn implicit_steps(&self) -> u64 {
        self.mode.implicit_steps
    }
}

/// `sqrt` of the Gershgorin bound of the spectral radius of `M^{-1/2} L(k) M^{-1/2}`.
fn gershgorin_sqrt(mass: &[f64], k: &[f64]) -> f64 {
    let m = mass.len();
    let mut w2: f64 = 0.0;
    for i in 0..m {
        let (kl, cl) = if i > 0 {
            (k[i - 1], k[i - 1] / (mass[i - 1] * mass[i]).sqrt())
        } else {
            (k[m - 1], 0.0)
        };
        let (kr, cr) = if i + 1 < m {
            (k[i], k[i] / (mass[i] * mass[i + 1]).sqrt())
        } else {
            (k[m], 0.0)
        };
        w2 = w2.max((kl + kr) / mass[i] + cl + cr);
    }
    w2.sqrt()
}

/// `acc += now − before`, field by field.
fn add_diff(acc: &mut Stats, now: &Stats, before: &Stats) {
    acc.steps += now.steps - before.steps;
    acc.rejected += now.rejected - before.rejected;
    acc.rhs_evals += now.rhs_evals - before.rhs_evals;
    acc.jac_evals += now.jac_evals - before.jac_evals;
    acc.factorizations += now.factorizations - before.factorizations;
    acc.newton_iters += now.newton_iters - before.newton_iters;
    acc.newton_failures += now.newton_failures - before.newton_failures;
    acc.bead_steps += now.bead_steps - before.bead_steps;
}

impl Integrator for Auto {
    fn reset(&mut self, sys: &dyn System, t: f64, u: &[f64], v: &[f64]) {
        self.start_active(|i| i.reset(sys, t, u, v));
    }

    fn set_step_size(&mut self, h: f64) {
        self.active_mut().set_step_size(h);
    }

    fn set_rough(&mut self, rough: super::Rough) {
        self.dop.set_rough(rough);
    }

    fn restart(&mut self, sys: &dyn System, t: f64, u: &[f64], v: &[f64], h: f64) {
        self.start_active(|i| i.restart(sys, t, u, v, h));
    }

    fn step_size(&self) -> f64 {
        self.active().step_size()
    }

    fn step(&mut self, sys: &dyn System, t_bound: f64) -> Result<f64, IntegrationError> {
        if self.mode.pending {
            self.switch(sys);
        }
        let before = self.active().stats().clone();
        let t0 = self.active().t();
        let r = self.active_mut().step(sys, t_bound);
        let now = self.active().stats().clone();
        add_diff(&mut self.stats, &now, &before);
        let t1 = r?;
        if t1 > t0 {
            if self.mode.implicit {
                self.mode.implicit_steps += 1;
            }
            self.mode.since += 1;
            if self.mode.since >= STRIDE {
                self.mode.since = 0;
                self.vote(sys, t1 - t0);
            }
        }
        Ok(t1)
    }

    fn t(&self) -> f64 {
        match self.implicit_active() {
            Some(r) => r.t(),
            None => self.dop.t(),
        }
    }

    fn t_prev(&self) -> f64 {
        match self.implicit_active() {
            Some(r) => r.t_prev(),
            None => self.dop.t_prev(),
        }
    }

    fn state(&self) -> &[f64] {
        self.active().state()
    }

    fn dense(&self, t: f64, z: &mut [f64]) {
        self.active().dense(t, z)
    }

    fn dense_at(&self, t: f64, j: usize) -> f64 {
        match self.implicit_active() {
            Some(r) => r.dense_at(t, j),
            None => self.dop.dense_at(t, j),
        }
    }

    /// DOP853 renewed, Radau IIA kept and renewed at the next switch to it (built there if
    /// there is none), the switching state, counters and scratch as [`Auto::new`] (explicit)
    /// sets them.
    fn renew(&mut self, m: usize, tol: Tolerances) -> bool {
        self.m = m;
        self.tol = tol;
        self.dop.renew(m, tol);
        self.radau_stale = self.radau.is_some();
        self.mode = AutoState::default();
        self.stats = Stats::default();
        self.scratch.clear();
        true
    }

    fn end_states(&self) -> Option<(&[f64], &[f64])> {
        match self.implicit_active() {
            Some(r) => r.end_states(),
            None => self.dop.end_states(),
        }
    }

    fn rate(&self) -> Option<&[f64]> {
        match self.implicit_active() {
            Some(_) => None,
            None => self.dop.rate(),
        }
    }

    fn stats(&self) -> &Stats {
        &self.stats
    }

    fn implicit_steps(&self) -> u64 {
        self.mode.implicit_steps
    }

    fn dissipated(&self) -> (f64, f64) {
        let (a, b) = self.active().dissipated();
        (self.mode.diss_base + a, self.mode.diss_base + b)
    }

    fn save(&self) -> IntegratorState {
        let mut s = self.active().save();
        s.stats = self.stats.clone();
        s.auto = Some(self.mode);
        s
    }

    fn load(&mut self, s: &IntegratorState) -> Result<(), LoadError> {
        let mode = s
            .auto
            .ok_or_else(|| LoadError::wrong_method(&s.method, Method::Auto.name()))?;
        let before = self.mode;
        self.mode = mode;
        if mode.implicit {
            self.build_radau();
        }
        if let Err(e) = self.active_mut().load(s) {
            self.mode = before;
            return Err(e);
        }
        self.stats = s.stats.clone();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::test_util::{striker, uniform_chain};
    use crate::integrate::ChainRange;

    /// The tolerances of these tests: `rtol`, `atol` on the chain's scales in the lab frame.
    fn tol_of(chain: &crate::model::Chain, u: &[f64], v: &[f64], atol: f64) -> Tolerances {
        Tolerances {
            rtol: 1e-8,
            atol,
            scales: chain.scales(u, v),
            v_frame: 0.0,
            u_origin: 0.0,
            dissipation: Default::default(),
        }
    }

    /// Radau IIA is built at the first switch to it, not with the integrator (a hybrid run
    /// makes one integrator per cluster; building Radau IIA for each was ~10 % of a 1000-bead
    /// striker run): explicit steps never build it, a switch does (here forced, as the
    /// stiffness vote would), and a state saved while implicit loads into a new integrator,
    /// which builds it and continues with the same steps.
    #[test]
    fn radau_is_built_at_the_first_switch_only() {
        let chain = uniform_chain(6);
        let (u, v) = striker(6, 1.0);
        let tol = tol_of(&chain, &u, &v, 1e-10);
        let sys = ChainRange::whole(&chain);
        let mut a = Auto::new(6, tol, SolverKind::Auto, false);
        a.reset(&sys, 0.0, &u, &v);
        for _ in 0..40 {
            a.step(&sys, 1e4).expect("steps");
        }
        assert!(a.radau.is_none() && !a.mode.implicit);
        // explicit: the step's end states are DOP853's arrays; implicit: none (the callers
        // then read the collocation polynomial through dense_at)
        assert_eq!(a.end_states().map(|(_, z)| z), Some(a.state()));
        a.mode.pending = true;
        a.step(&sys, 1e4).expect("steps");
        assert!(a.mode.implicit && a.radau.is_some());
        assert!(a.end_states().is_none());
        let mut resumed = Auto::new(6, tol, SolverKind::Auto, false);
        resumed.load(&a.save()).expect("loads");
        assert!(resumed.radau.is_some());
        let t = a.step(&sys, 1e4).expect("steps");
        assert_eq!(resumed.step(&sys, 1e4).expect("steps"), t);
        assert_eq!(resumed.state(), a.state(), "same step after the load");
    }

    /// The hybrid engine reuses the integrators of removed clusters ([`Integrator::renew`]):
    /// one renewed from a 6-bead integrator that ran explicit and implicit steps must, after
    /// `reset`, save the same state as a new 4-bead one (stale stages included: written as
    /// zeros before the first step) and take bit-identical steps.
    #[test]
    fn renewed_integrator_is_bit_identical_to_a_new_one() {
        let (chain6, chain4) = (uniform_chain(6), uniform_chain(4));
        let (u6, v6) = striker(6, 1.0);
        let (u4, v4) = striker(4, 0.7);
        let (sys6, sys4) = (ChainRange::whole(&chain6), ChainRange::whole(&chain4));
        let mut a = Auto::new(6, tol_of(&chain6, &u6, &v6, 1e-12), SolverKind::Auto, false);
        a.reset(&sys6, 0.0, &u6, &v6);
        for _ in 0..20 {
            a.step(&sys6, 1e4).expect("steps");
        }
        a.mode.pending = true;
        a.step(&sys6, 1e4).expect("steps");
        assert!(a.mode.implicit);
        let tol4 = tol_of(&chain4, &u4, &v4, 1e-12);
        assert!(a.renew(4, tol4));
        let mut b = Auto::new(4, tol4, SolverKind::Auto, false);
        a.reset(&sys4, 0.5, &u4, &v4);
        b.reset(&sys4, 0.5, &u4, &v4);
        assert_eq!(a.save(), b.save(), "before the first step");
        let bits = |x: &[f64]| x.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
        for _ in 0..30 {
            let t = a.step(&sys4, 1e4).expect("steps");
            assert_eq!(t.to_bits(), b.step(&sys4, 1e4).expect("steps").to_bits());
            assert_eq!(bits(a.state()), bits(b.state()));
        }
        assert_eq!(a.save(), b.save(), "after 30 steps");
        assert_eq!(a.stats(), b.stats());
    }

    /// A renewed integrator keeps the Radau IIA it built (the same allocation) and renews it at
    /// its next switch to the implicit method: the switch and the implicit steps after it are
    /// bit-identical to those of a new integrator, which builds its Radau IIA there.
    #[test]
    fn renewed_integrator_switches_with_its_kept_radau_bit_identically() {
        let (chain6, chain4) = (uniform_chain(6), uniform_chain(4));
        let (u6, v6) = striker(6, 1.0);
        let (u4, v4) = striker(4, 0.7);
        let (sys6, sys4) = (ChainRange::whole(&chain6), ChainRange::whole(&chain4));
        let mut a = Auto::new(6, tol_of(&chain6, &u6, &v6, 1e-12), SolverKind::Auto, true);
        a.reset(&sys6, 0.0, &u6, &v6);
        for _ in 0..20 {
            a.step(&sys6, 1e4).expect("steps");
        }
        let kept: *const Radau5 = &**a.radau.as_ref().expect("built");
        let tol4 = tol_of(&chain4, &u4, &v4, 1e-12);
        assert!(a.renew(4, tol4));
        assert!(
            a.radau.is_some() && a.radau_stale,
            "kept by renew, to be renewed"
        );
        let mut b = Auto::new(4, tol4, SolverKind::Auto, false);
        a.reset(&sys4, 0.5, &u4, &v4);
        b.reset(&sys4, 0.5, &u4, &v4);
        let bits = |x: &[f64]| x.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
        for k in 0..40 {
            if k == 10 {
                (a.mode.pending, b.mode.pending) = (true, true);
            }
            let t = a.step(&sys4, 1e4).expect("steps");
            assert_eq!(t.to_bits(), b.step(&sys4, 1e4).expect("steps").to_bits());
            assert_eq!(bits(a.state()), bits(b.state()));
        }
        let implicit = a.implicit_steps();
        assert!(
            implicit > 0 && implicit == b.implicit_steps(),
            "{implicit} implicit steps"
        );
        let now: *const Radau5 = &**a.radau.as_ref().expect("kept");
        assert_eq!(now, kept, "the kept Radau IIA, renewed, not a new one");
        assert_eq!(a.save(), b.save(), "after 40 steps");
        assert_eq!(a.stats(), b.stats());
    }

    /// A method's state is a typed variant ([`crate::integrate::MethodState`]): an exact
    /// pair's trajectory never loads into an integrator, nor an integrator's state into an
    /// exact pair; each refusal names both methods (the pair's state used to call itself
    /// "auto") and leaves the integrator unchanged.
    #[test]
    fn exact_pair_state_is_refused_by_its_own_name_not_as_auto() {
        use crate::integrate::exact_pair::{ExactPair, PairLaw};
        use crate::model::profile::Profile;
        use std::sync::Arc;
        let chain = uniform_chain(2);
        let (u, v) = striker(2, 1.0);
        let tol = tol_of(&chain, &u, &v, 1e-12);
        let sys = ChainRange::whole(&chain);
        let law = PairLaw {
            mass: [1.0, 1.0],
            n: 2.5,
            a: 0.4,
            pre: 0.0,
            accel: 0.0,
            wall: None,
        };
        let mut pair = ExactPair::new(law, Arc::new(Profile::new(2.5)), false);
        pair.reset(&sys, 0.0, &u, &v);
        let mut dop = Dop853::new(2, tol);
        dop.reset(&sys, 0.0, &u, &v);
        let mut auto = Auto::new(2, tol, SolverKind::Auto, false);
        auto.reset(&sys, 0.0, &u, &v);
        let (ps, ds, autos) = (pair.save(), dop.save(), auto.save());
        let e = dop.load(&ps).expect_err("a trajectory into DOP853");
        let m = "the state of a two-body (exact) integrator cannot continue as dop853";
        assert_eq!(e.to_string(), m);
        let e = pair
            .load(&ds)
            .expect_err("DOP853 arrays into an exact pair");
        let m = "the state of a dop853 integrator cannot continue as two-body (exact)";
        assert_eq!(e.to_string(), m);
        let e = auto.load(&ps).expect_err("a trajectory into auto");
        let m = "the state of a two-body (exact) integrator cannot continue as auto";
        assert_eq!(e.to_string(), m);
        assert_eq!((pair.save(), dop.save(), auto.save()), (ps, ds, autos));
    }
}
