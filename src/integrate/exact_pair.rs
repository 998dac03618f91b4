//! The exact two-body contact: an [`Integrator`] for a cluster of two beads joined by one
//! conservative power-law contact and touched by nothing else, in closed form.
//!
//! Relative to their centre of mass (which moves as `U + V τ + ½ A τ²` under a field that
//! accelerates both beads alike) the two beads follow the universal profile of their exponent
//! ([`Profile`], energy integral `½ μ δ̇² + a δⁿ = ½ μ w₀²`, `μ = m₀m₁/(m₀+m₁)`): the contact
//! starts at `t_s` (`δ = 0`, `δ̇ = w₀`), peaks at `δ_max = (μ w₀²/2a)^{1/n}` at
//! `t_p = t_s + τ_h δ_max/w₀` and ends at `t_e = t_s + 2 τ_h δ_max/w₀` with `δ̇ = −w₀`: the
//! collision is elastic. Outside `[t_s, t_e]` the beads fly on the asymptotes. The state at any
//! time (frames, the hand-over to an integrator when a third body arrives) is the profile's,
//! to round-off, and one [`Integrator::step`] covers the whole contact, whatever the tolerance.
//!
//! **Entering from free flight.** A contact closes in the hybrid engine when its overlap
//! exceeds the threshold `θ` (module docs of `engine::hybrid`), so the free-flight state handed
//! over has flown `δ/w` past the true contact time without the contact's force. Built with
//! `from_flight`, the first [`Integrator::reset`] reads that state as the incoming asymptote,
//! `t_s = t − δ/w`, `w₀ = w` (free flight is exact before contact), and the profile replaces it:
//! the result is the exact collision, independent of `θ`. Every other reset (a redone step, a
//! cluster piece, the start of a run) reads its state as a point of the trajectory.
//!
//! Its [`Integrator::step`] ends exactly at `t_e` with `δ = 0` (the second displacement is
//! rounded from the first, so the engine's `Δ + w₀ − w₁` is exactly zero) and the engine splits
//! the pair there.
//!
//! **One bead against a soft wall** ([`PairLaw::wall`]) is the same contact with the wall as a
//! body of infinite mass: `μ = m₀`, the overlap is `δ = Δ_w + s·u` (`s = −1` at the left wall,
//! `+1` at the right one, `Δ_w` the wall's precompression), and the bead's state is
//! `u = s·(δ − Δ_w)`, `v = s·δ̇` (so `δ = 0` exactly at the end). No field: a wall does not
//! fall with the bead.

use super::{IntegrationError, Integrator, IntegratorState, LoadError, MethodState, Stats, System};
use crate::model::profile::Profile;
use serde::{Deserialize, Serialize};
use std::cell::Cell;
use std::sync::Arc;

/// The contact: masses, law and precompression (`δ = Δ + w₀ − w₁`), and the common acceleration
/// of the two beads in the integrated frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct PairLaw {
    /// Masses of the left and right bead.
    pub mass: [f64; 2],
    /// Exponent `n > 1`.
    pub n: f64,
    /// Prefactor `a > 0`.
    pub a: f64,
    /// Precompression `Δ` of the contact.
    pub pre: f64,
    /// Acceleration of both beads by the field (equal for both: the eligibility rule).
    pub accel: f64,
    /// `Some(s)`: one bead (`mass[0]`; `mass[1]` unused) against a soft wall whose overlap is
    /// `pre + s·u` (`s = −1` left wall, `+1` right wall; module docs); `accel` must be 0.
    pub wall: Option<f64>,
}

impl PairLaw {
    /// Reduced mass `μ` of the contact (the bead's mass against a wall).
    fn reduced_mass(&self) -> f64 {
        let [m0, m1] = self.mass;
        if self.wall.is_some() {
            m0
        } else {
            m0 * m1 / (m0 + m1)
        }
    }

    /// Number of beads integrated: 1 against a wall, else 2.
    pub fn beads(&self) -> usize {
        if self.wall.is_some() {
            1
        } else {
            2
        }
    }
}

/// The trajectory: everything an exact pair needs to continue (checkpoints).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PairState {
    /// Current time and start of the last step.
    pub t: f64,
    /// Start of the last step.
    pub t_prev: f64,
    /// Contact start `t_s` and end `t_e`.
    pub t_s: f64,
    /// Contact end.
    pub t_e: f64,
    /// Impact speed `w₀ ≥ 0`.
    pub w0: f64,
    /// Peak overlap `δ_max`.
    pub d_max: f64,
    /// Centre of mass at `t_r`: position and velocity.
    pub cm: (f64, f64),
    /// Reference time of the centre of mass.
    pub t_r: f64,
    /// Whether the next reset reads its state as the free-flight asymptote (module docs).
    pub from_flight: bool,
}

/// The exact two-body contact as an integrator (module docs).
pub struct ExactPair {
    law: PairLaw,
    profile: Arc<Profile>,
    s: PairState,
    /// `u₀, u₁, v₀, v₁` at `s.t` (`u₀, v₀` against a wall, then two unused zeros).
    z: [f64; 4],
    /// Zero: an exact pair takes no integration steps (the engine counts the pairs).
    stats: Stats,
    /// The last state evaluated inside a step (frames read four components at one time).
    memo: Cell<(f64, [f64; 4])>,
}

impl ExactPair {
    /// An exact pair for `law` with its exponent's `profile`; `from_flight`: the first reset
    /// reads a free-flight state (module docs).
    pub fn new(law: PairLaw, profile: Arc<Profile>, from_flight: bool) -> Self {
        debug_assert_eq!(profile.exponent(), law.n);
        ExactPair {
            law,
            profile,
            s: PairState {
                from_flight,
                ..PairState::default()
            },
            z: [0.0; 4],
            stats: Stats::default(),
            memo: Cell::new((f64::NAN, [0.0; 4])),
        }
    }

    /// Makes this pair the one `new(law, profile, from_flight)` builds, keeping its allocation.
    pub fn renew(&mut self, law: PairLaw, profile: Arc<Profile>, from_flight: bool) {
        *self = ExactPair::new(law, profile, from_flight);
    }

    /// Time scale `δ_max/w₀` of the profile.
    fn scale(&self) -> f64 {
        self.s.d_max / self.s.w0
    }

    /// Contact end time `t_e`.
    pub fn end_time(&self) -> f64 {
        self.s.t_e
    }

    /// Peak overlap `δ_max` of the contact.
    pub fn peak(&self) -> f64 {
        self.s.d_max
    }

    /// The impact speed `w₀`.
    pub fn impact_speed(&self) -> f64 {
        self.s.w0
    }

    /// The contact law.
    pub fn law(&self) -> PairLaw {
        self.law
    }

    /// Largest overlap over `[ta, tb]`: `δ_max` where the peak lies inside, else the larger end.
    pub fn peak_over(&self, ta: f64, tb: f64) -> f64 {
        let tp = self.s.t_s + self.profile.tau_half() * self.scale();
        if self.s.w0 > 0.0 && ta <= tp && tp <= tb {
            self.s.d_max
        } else {
            self.relative(ta).0.max(self.relative(tb).0)
        }
    }

    /// The time on the way out at which the overlap falls to `level ∈ (0, δ_max)` (the logged
    /// opening time of the engine's threshold); the contact's end where `level ≥ δ_max` (a
    /// contact whose peak stays below the threshold opens where it ends); `None` for
    /// `level ≤ 0` or a pair that does not collide.
    pub fn leaving(&self, level: f64) -> Option<f64> {
        if !(self.s.w0 > 0.0 && level > 0.0) {
            return None;
        }
        if level >= self.s.d_max {
            return Some(self.s.t_e);
        }
        Some(self.s.t_e - self.profile.tau_of(level / self.s.d_max) * self.scale())
    }

    /// Overlap `δ` and its rate `δ̇` at `t` (module docs).
    fn relative(&self, t: f64) -> (f64, f64) {
        let s = &self.s;
        if s.w0 <= 0.0 {
            return (0.0, 0.0);
        }
        if t <= s.t_s {
            return (s.w0 * (t - s.t_s), s.w0);
        }
        if t >= s.t_e {
            return (-s.w0 * (t - s.t_e), -s.w0);
        }
        let k = self.scale();
        let tau_h = self.profile.tau_half();
        let tp = s.t_s + tau_h * k;
        let (x, sp, sign) = if t <= tp {
            let (x, sp) = self.profile.at((t - s.t_s) / k, (tp - t) / k);
            (x, sp, 1.0)
        } else {
            let (x, sp) = self.profile.at((s.t_e - t) / k, (t - tp) / k);
            (x, sp, -1.0)
        };
        (s.d_max * x, sign * s.w0 * sp)
    }

    /// The state `u₀, u₁, v₀, v₁` at `t` (`δ = 0` exactly at and after the end, module docs);
    /// `u₀, v₀, 0, 0` against a wall.
    fn eval(&self, t: f64) -> [f64; 4] {
        if let Some(s) = self.law.wall {
            let (d, dd) = self.relative(t);
            return [s * (d - self.law.pre), s * dd, 0.0, 0.0];
        }
        let [m0, m1] = self.law.mass;
        let mt = m0 + m1;
        let tau = t - self.s.t_r;
        let a = self.law.accel;
        let c = self.s.cm.0 + self.s.cm.1 * tau + 0.5 * a * tau * tau;
        let cv = self.s.cm.1 + a * tau;
        let (d, dd) = self.relative(t);
        let r = d - self.law.pre;
        let u0 = c + m1 / mt * r;
        let u1 = if d == 0.0 {
            self.law.pre + u0
        } else {
            c - m0 / mt * r
        };
        [u0, u1, cv + m1 / mt * dd, cv - m0 / mt * dd]
    }

    /// The state at `t`, through the memo.
    fn at(&self, t: f64) -> [f64; 4] {
        if t == self.s.t {
            return self.z;
        }
        let (tm, z) = self.memo.get();
        if tm == t {
            return z;
        }
        let z = self.eval(t);
        self.memo.set((t, z));
        z
    }

    /// Sets the trajectory through state `(u, v)` at `t` (module docs).
    fn start(&mut self, t: f64, u: &[f64], v: &[f64]) {
        let [m0, m1] = self.law.mass;
        let mt = m0 + m1;
        let mu = self.law.reduced_mass();
        let (n, a) = (self.law.n, self.law.a);
        let (d, w) = match self.law.wall {
            Some(s) => (self.law.pre + s * u[0], s * v[0]),
            None => (self.law.pre + u[0] - u[1], v[0] - v[1]),
        };
        let s = &mut self.s;
        s.cm = match self.law.wall {
            Some(_) => (0.0, 0.0),
            None => ((m0 * u[0] + m1 * u[1]) / mt, (m0 * v[0] + m1 * v[1]) / mt),
        };
        s.t_r = t;
        let flight = std::mem::take(&mut s.from_flight) && w > 0.0;
        let (w0, through) = if flight || d <= 0.0 {
            (w.abs(), None)
        } else {
            let e = 0.5 * w * w + a / mu * d.powf(n);
            ((2.0 * e).sqrt(), Some(d))
        };
        s.w0 = w0;
        if !(w0 > 0.0 && w0.is_finite()) {
            // touching at rest: nothing happens
            (s.w0, s.d_max, s.t_s, s.t_e) = (0.0, 0.0, t, t);
            return;
        }
        s.d_max = (mu * w0 * w0 / (2.0 * a)).powf(1.0 / n);
        let k = s.d_max / w0;
        let tc = 2.0 * self.profile.tau_half() * k;
        match through {
            None if w > 0.0 => s.t_s = t - d / w0,
            None => s.t_s = t + d / w0 - tc,
            Some(d) => {
                let tau = if (w.abs() / w0) <= std::f64::consts::FRAC_1_SQRT_2 {
                    self.profile.tau_of_speed(w.abs() / w0)
                } else {
                    self.profile.tau_of((d / s.d_max).min(1.0))
                };
                s.t_s = if w >= 0.0 {
                    t - tau * k
                } else {
                    t - (tc - tau * k)
                };
            }
        }
        s.t_e = s.t_s + tc;
    }
}

impl Integrator for ExactPair {
    fn reset(&mut self, _sys: &dyn System, t: f64, u: &[f64], v: &[f64]) {
        self.start(t, u, v);
        self.s.t = t;
        self.s.t_prev = t;
        self.memo.set((f64::NAN, [0.0; 4]));
        self.z = self.eval(t);
    }

    fn set_step_size(&mut self, _h: f64) {}

    /// Time to the contact's end (the whole rest of the contact is one step); infinite once it
    /// has ended.
    fn step_size(&self) -> f64 {
        if self.s.t_e > self.s.t {
            self.s.t_e - self.s.t
        } else {
            f64::INFINITY
        }
    }

    fn step(&mut self, _sys: &dyn System, t_bound: f64) -> Result<f64, IntegrationError> {
        let t = if self.s.t_e > self.s.t {
            self.s.t_e.min(t_bound)
        } else {
            t_bound
        };
        self.s.t_prev = self.s.t;
        self.s.t = t;
        self.z = self.eval(t);
        Ok(t)
    }

    fn t(&self) -> f64 {
        self.s.t
    }

    fn t_prev(&self) -> f64 {
        self.s.t_prev
    }

    fn state(&self) -> &[f64] {
        &self.z[..2 * self.law.beads()]
    }

    fn dense(&self, t: f64, z: &mut [f64]) {
        let k = 2 * self.law.beads();
        z[..k].copy_from_slice(&self.at(t)[..k]);
    }

    fn dense_at(&self, t: f64, j: usize) -> f64 {
        self.at(t)[j]
    }

    fn stats(&self) -> &Stats {
        &self.stats
    }

    fn exact_pair(&self) -> Option<&ExactPair> {
        Some(self)
    }

    fn exact_pair_mut(&mut self) -> Option<&mut ExactPair> {
        Some(self)
    }

    fn save(&self) -> IntegratorState {
        IntegratorState {
            t: self.s.t,
            t_prev: self.s.t_prev,
            stats: self.stats.clone(),
            dissipated: (0.0, 0.0),
            auto: None,
            method: MethodState::Exact(self.s),
        }
    }

    fn load(&mut self, s: &IntegratorState) -> Result<(), LoadError> {
        let MethodState::Exact(p) = s.method else {
            return Err(LoadError::wrong_method(&s.method, super::EXACT_NAME));
        };
        self.s = p;
        self.stats = s.stats.clone();
        self.memo.set((f64::NAN, [0.0; 4]));
        self.z = self.eval(self.s.t);
        Ok(())
    }
}
