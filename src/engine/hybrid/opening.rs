//! Located contact openings inside a cluster.
//!
//! The contact force `n·a·δ₊^{n−1}` (paper eq. 6) is not smooth at `δ = 0`: for `n < 3` its
//! second derivative jumps there, for `n < 2` already its first. A Runge–Kutta step that
//! straddles an opening integrates across that kink, where its error estimate (which assumes a
//! smooth right-hand side, HNW I, II.4) no longer measures its error: the separating beads leave
//! with velocity errors far above the tolerance, and behind a solitary wave those errors are as
//! large as the true, super-exponentially small separation speeds, so the free beads re-collide
//! spuriously (hybrid DOP853 on a 20 000-bead striker chain: 12 close events per bead instead of
//! one, energy error 100× the dense engine's).
//!
//! So an opening is an event located on the continuous output like a closing: when a contact of
//! the cluster ends a step below the threshold `θ` while separating, the first time `t*` in the
//! step where its overlap falls to `θ/2` is found (sampling + Illinois, [`super::detect`]), the
//! step is redone to land exactly on `t*` ([`Hybrid::settle_at`]), and the cluster is split there.
//! The cluster therefore never integrates across `δ = 0`: every one of its steps sees a smooth
//! right-hand side. The split rule itself is unchanged (`δ < θ` and `δ̇ < 0`, module docs of
//! [`super`]) and is applied to the redone step's state at `t*`; only its time is located
//! instead of taken at the step end. A step that ends on the near side of the kink
//! (`0 ≤ δ < θ/2` at its end) never integrated across it, so it is split at its end without
//! a redone step.
//!
//! A lone bead against a soft wall has the same kink in its wall force: its wall contact's
//! opening is landed on and located the same way ([`Hybrid::first_wall_opening`]), and the
//! step-end rule (the wall no longer holds it) frees the bead. A wall contact of a bead that
//! also touches a neighbour is not an event (the cluster keeps the bead) and is integrated as is.
//!
//! Most openings are not located at all but **landed on** ([`Hybrid::opening_bound`]): before
//! each step a separating contact's overlap is extrapolated from the state and `f(z)`, and the
//! step is shortened to end where it reaches `θ/2`. Without that, the steps that reach past the
//! kink are rejected (often several times) before the located opening can act: DOP853 at rtol
//! 1e-6 on the disorder chain rejected 202 096 steps, 169 468 of them across an opening; with
//! the bound it rejects 65 000.
//!
//! The landing is **deferred** until the queue reaches `t*`, like a closing: redoing the step
//! may take several sub-steps, and then the continuous output covers only the last of them.
//! Landing at once (while the queue is still at the step start) left frames and neighbours'
//! event searches at earlier times reading the output outside its step, an extrapolation
//! (frame velocities of ±108 in a box scene whose beads move at 0.3, and a run whose energy
//! then grew ×10²² through spurious collisions). When the redone step disagrees with the continuous output
//! (the overlap is still above `θ` at `t*`, a difference at the tolerance level) the cluster
//! simply continues from `t*` with its integrator as it is: it is not rebuilt, so no loop of
//! fresh, short starting steps can form.

use super::cluster::{Cluster, Pending};
use super::{prio, Hybrid, Key};
use crate::engine::EngineError;

/// Smallest located opening time after the step start, as a fraction of the step.
const MIN_FRACTION: f64 = 1e-3;

/// Overlap a step shortened onto a predicted opening aims at, as a fraction of `θ`: the `θ/2` a
/// located opening splits at, half-way between the split threshold and the kink (a landing
/// anywhere in `[0, θ)` splits by the step-end rule).
const LANDING: f64 = 0.5;

impl Hybrid<'_> {
    /// Earliest located opening time `t* ∈ (t0, t1)` of a contact of `cl` over its last step
    /// `[t0, t1]` (see module docs), or `None` when no contact opens strictly inside the step.
    pub(super) fn first_opening(&self, cl: &Cluster, t0: f64, t1: f64) -> Option<f64> {
        if cl.data.pinned[0] || cl.data.pinned[1] || t1 <= t0 {
            return None;
        }
        if cl.m() == 1 {
            return self.first_wall_opening(cl, t0, t1);
        }
        let z = cl.integ.state();
        let m = cl.m();
        let theta = self.ctx.theta;
        let mut first: Option<f64> = None;
        for k in 0..m - 1 {
            let c = cl.data.lo + k;
            let pre = self.pre(c);
            let d1 = pre + z[k] - z[k + 1];
            if d1 >= theta || z[m + k] - z[m + k + 1] >= 0.0 {
                continue;
            }
            if d1 >= 0.0 {
                continue; // the step stopped short of the kink: the step-end rule splits at t1
            }
            let delta = |t: f64| pre + cl.w_at(t, c) - cl.w_at(t, c + 1);
            if delta(t0) < theta {
                continue; // already open at the step start: the step-end rule handles it
            }
            let g = |t: f64| 0.5 * theta - delta(t);
            let Some(t) = super::detect::first_crossing(g, t0, first.unwrap_or(t1)) else {
                continue;
            };
            // a crossing a sliver after the step start is left to the step-end rule: the step
            // redone to land there would be a few ulps long
            let sliver = t - t0 <= MIN_FRACTION * (t1 - t0);
            if !sliver && t < t1 && cl.v_at(t, c) - cl.v_at(t, c + 1) < 0.0 {
                first = Some(t);
            }
        }
        first
    }

    /// Latest end (at most `until`) of the next step of `cl` that does not carry a contact past
    /// its predicted opening (module docs). Where a separating contact's quadratic
    /// `δ + δ̇τ + δ̈τ²/2` (from the state and the `f(z)` the method holds, [`rate`]) reaches
    /// `θ/2` within the proposed step `h`, the step is shortened to end there (in two equal
    /// steps when it is reached within `2h`, so that no sliver of a step is left), and the
    /// step-end rule splits the cluster after a step on a smooth right-hand side. It is only a
    /// step bound: the prediction decides no event, and a poor one costs a step (an end above
    /// `θ` steps again; one past the kink is located as before). A bound shorter than
    /// `MIN_FRACTION` of the proposed step is not imposed. Methods that hold no `f(z)` (Radau
    /// IIA) are not bounded.
    ///
    /// [`rate`]: crate::integrate::Integrator::rate
    pub(super) fn opening_bound(&self, cl: &Cluster, until: f64) -> f64 {
        let m = cl.m();
        if cl.data.pinned[0] || cl.data.pinned[1] {
            return until;
        }
        let Some(f) = cl.integ.rate() else {
            return until;
        };
        let z = cl.integ.state();
        let h = cl.integ.step_size();
        let target = LANDING * self.ctx.theta;
        let mut tau = f64::INFINITY;
        for side in [0u8, 1] {
            if let Some((d, dd, ddd)) = self.wall_overlap(cl, side, f) {
                if d >= self.ctx.theta && dd < 0.0 {
                    tau = tau.min(reaches(d - target, dd, ddd));
                }
            }
        }
        for k in 0..m - 1 {
            let c = cl.data.lo + k;
            let d = self.pre(c) + z[k] - z[k + 1];
            let dd = z[m + k] - z[m + k + 1];
            // not separating, or (a cheap filter) not reaching θ within 2h on its own speed
            // while not accelerating apart
            let far = d + 2.0 * h * dd > self.ctx.theta && f[m + k] >= f[m + k + 1];
            if d < self.ctx.theta || dd >= 0.0 || far {
                continue;
            }
            if self.st.stuck[c] || self.ctx.chain.hard_restitution(c).is_some() {
                continue;
            }
            let ddd = f[m + k] - f[m + k + 1];
            tau = tau.min(reaches(d - target, dd, ddd));
        }
        let t = cl.integ.t();
        let end = if tau < h {
            t + tau
        } else if tau < 2.0 * h {
            t + 0.5 * tau
        } else {
            return until;
        };
        // A sliver of a step (or one that rounds to no step at all, which would make no
        // progress) is not imposed: that opening is left to the located-opening rule.
        if end - t < MIN_FRACTION * h || end <= t {
            return until;
        }
        until.min(end)
    }

    /// The overlap `(δ, δ̇, δ̈)` of a lone bead (`cl` of one bead) with the soft wall at `side`
    /// (0 left, 1 right) that it is the end bead for, from its state and the acceleration `f`
    /// holds (`f(z)`, [`rate`]); `None` where there is no such wall.
    ///
    /// [`rate`]: crate::integrate::Integrator::rate
    fn wall_overlap(&self, cl: &Cluster, side: u8, f: &[f64]) -> Option<(f64, f64, f64)> {
        let end = if side == 0 { 0 } else { self.ctx.n - 1 };
        if cl.m() != 1 || cl.data.lo != end {
            return None;
        }
        let w = self.soft_wall(side)?;
        let z = cl.integ.state();
        let (u, v) = (
            cl.frame_at(cl.integ.t()) + z[0],
            cl.frame_vel(cl.integ.t()) + z[1],
        );
        let s = if side == 0 { -1.0 } else { 1.0 };
        Some((w.precompression + s * u, s * v, s * f[1]))
    }

    /// [`Self::first_opening`] for a lone bead against a soft wall: the wall contact's force has
    /// the same kink at `δ = 0` as a bead–bead contact's (paper eq. 6), so a step that ends past
    /// it while the bead leaves is located and landed on the same way (the step-end rule, a
    /// wall that no longer holds the bead, then frees it).
    fn first_wall_opening(&self, cl: &Cluster, t0: f64, t1: f64) -> Option<f64> {
        let theta = self.ctx.theta;
        let mut first: Option<f64> = None;
        for side in [0u8, 1] {
            let end = if side == 0 { 0 } else { self.ctx.n - 1 };
            let Some(w) = self.soft_wall(side).filter(|_| cl.data.lo == end) else {
                continue;
            };
            let s = if side == 0 { -1.0 } else { 1.0 };
            let delta = |t: f64| w.precompression + s * cl.u_at(t, end);
            // past the kink at the step end, leaving, and above θ at the step start
            if delta(t1) >= 0.0 || s * cl.v_at(t1, end) >= 0.0 || delta(t0) < theta {
                continue;
            }
            let g = |t: f64| 0.5 * theta - delta(t);
            let Some(t) = super::detect::first_crossing(g, t0, first.unwrap_or(t1)) else {
                continue;
            };
            let sliver = t - t0 <= MIN_FRACTION * (t1 - t0);
            if !sliver && t < t1 && s * cl.v_at(t, end) < 0.0 {
                first = Some(t);
            }
        }
        first
    }

    /// Records a located opening at `t` in the step just taken: the cluster waits in the queue
    /// until `t` ([`Self::open_at`]); until then its continuous output is the step's, valid
    /// over the whole of `[t0, t]`.
    pub(super) fn defer_open(&mut self, slot: u32, t: f64) {
        self.update_peaks(slot, t);
        self.watch_walls(slot, t);
        let cl = &mut self.clusters[slot];
        cl.data.pending = Some(Pending::Open { t });
        cl.data.t_now = t;
        let lo = cl.data.lo;
        self.queue
            .push(Key::Cluster(slot), prio(t, 1, lo, Key::Cluster(slot)));
    }

    /// Lands the cluster in `slot` on the located opening time `t` and splits it there if the
    /// split rule holds in the landed state (module docs), or continues it from `t` otherwise.
    pub(super) fn open_at(&mut self, slot: u32, t: f64) -> Result<(), EngineError> {
        self.settle_at(slot, t)?;
        let cl = &self.clusters[slot];
        let (lo, split) = (cl.data.lo, self.needs_split(cl));
        let cl = &mut self.clusters[slot];
        let class = if split {
            cl.data.pending = Some(Pending::Split);
            1
        } else {
            2
        };
        self.queue
            .push(Key::Cluster(slot), prio(t, class, lo, Key::Cluster(slot)));
        Ok(())
    }
}

/// Time for an overlap `gap` above its target, moving as `gap + δ̇τ + δ̈τ²/2`, to reach the
/// target (its first root), or infinity where the quadratic never does.
pub(super) fn reaches(gap: f64, dd: f64, ddd: f64) -> f64 {
    let disc = dd * dd - 2.0 * ddd * gap;
    if disc >= 0.0 {
        2.0 * gap / (disc.sqrt() - dd)
    } else {
        f64::INFINITY
    }
}
