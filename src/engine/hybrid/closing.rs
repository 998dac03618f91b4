//! Steps that land on predicted gap closings.
//!
//! A cluster's boundary gap closes when the free bead across it meets the cluster's edge bead
//! (`g(t) = Δ + u_left(t) − u_right(t) − θ` crosses zero, [`super::detect`]). Found after the
//! fact, a closing costs two steps: the step that reaches past it, whose work beyond the
//! closing is lost, and the step redone to land on it ([`Hybrid::settle_at`]), so that the
//! merged cluster starts from a full-accuracy state rather than from the continuous output.
//!
//! So the closing is predicted before the step ([`Hybrid::closing_bound`]): the edge bead's
//! trajectory is the cluster's continuous output of its last step (DOP853's degree-7
//! polynomial, HNW I, II.6) continued past its end, the free bead's is its exact flight, and
//! their first crossing within [`HORIZON`] last steps bounds the next step. The step is aimed
//! [`PAST`] of the lead time beyond the predicted crossing, so that the closing falls inside the
//! step just before its end, where the continuous output matches the step's end in value and
//! slope and its error is quadratic in the distance from the end: a closing located within
//! [`NEAR_END`] of the step's end takes its state from the continuous output, without a redone
//! step ([`Hybrid::output_suffices`]). On the 1000-bead striker the continued polynomial puts
//! the closing within 0.02–0.16 % of its lead time (rtol 1e-4 … 1e-8); a Taylor cubic of the
//! edge bead (position, velocity, acceleration, jerk) was 15 % late, as the wave front's edge
//! bead accelerates ever faster. A poor prediction costs what a closing costs without it: a
//! closing found earlier in the step is landed on by a redone step as before.
//!
//! **The first step after a closing** is capped at the onset of the new contact's force
//! ([`Hybrid::cap_onset_step`]): a contact closing at speed `w` has `δ ≈ wτ`, so its force
//! `n a (wτ)^{n−1}` is not a polynomial in the step time (for non-integer `n`), and Hairer's
//! starting-step estimate (HNW I, II.4), which sees only the state and one Euler step, where the
//! force is still `≈ 0`, proposes steps far beyond what its onset allows; the error estimate then
//! accepts some of them with errors above the tolerance. The velocity change that the force makes
//! over a step `h` is `≈ a w^{n−1} hⁿ/μ`; holding [`ONSET_SHARE`] of it to `rtol·w` gives
//! `h = (δ_max/w)·(2 rtol/ONSET_SHARE)^{1/n}`, with `δ_max = (μw²/2a)^{1/n}` the contact's
//! two-body peak overlap. Measured (right-hand sides and energy error against the binary
//! without the cap, one run each, `docs/benchmarks.md`): `disorder_2.5_0.04` at rtol 1e-6 / 1e-7 /
//! 1e-8 +2 % / −7 % / −9 % right-hand sides for a 10× / 30× / 40× smaller energy error;
//! `periodic_decay_2.5_2.555` at 1e-6 / 1e-7 +2 % / −2 % for 30× / 14×; `interface_3.0_2.5` at
//! 1e-4 +5 % for a 2.1× smaller final-velocity error, at 1e-6 −1 % for the same; the
//! 1000-bead striker unchanged; on a chain with gaps of 0.1 the first steps of merged 4-bead
//! clusters were rejected 7 times each (130 000 rejections, 110 000 with the cap). A share of
//! 1 (a cap 6× shorter at n = 2.5) halved those rejections but cost up to 28 % more work on the
//! interface at rtol 1e-4; 1e-3 is the binary without the cap. A step rejected there is now
//! retried by the onset's own order ([`crate::integrate::Rough::Onset`], set by
//! [`Hybrid::rough_step`]): once instead of five times (70 000 rejections on that chain).
//!
//! Only a free neighbour is predicted (a neighbouring cluster's output ends at its own time),
//! only for DOP853 clusters (Radau IIA's continuous output is its collocation polynomial, not
//! continued here), and not across hard contacts (their collisions are located and resolved
//! instantaneously, `super::hard`).

use super::cluster::Cluster;
use super::{Hybrid, FREE};

/// How far past the predicted closing a landing step ends, as a fraction of its lead time.
const PAST: f64 = 0.01;

/// Prediction horizon, in lengths of the cluster's last step.
const HORIZON: f64 = 2.0;

/// A closing located within this fraction of its step from the step's end takes the state from
/// the continuous output (module docs).
const NEAR_END: f64 = 0.02;

/// Share of the onset force's velocity change that the first step after a closing may err by
/// (module docs).
const ONSET_SHARE: f64 = 0.01;

/// Smallest landing step, as a fraction of the proposed step (as for openings).
const MIN_FRACTION: f64 = 1e-3;

impl Hybrid<'_> {
    /// Latest end (at most `until`) of the next step of `cl` that lands just past its first
    /// predicted boundary closing (module docs): where the crossing is predicted within the
    /// proposed step `h`, the step ends [`PAST`] of its lead time beyond it; within `2h`, half
    /// way there. A bound shorter than `MIN_FRACTION` of `h` is not imposed.
    pub(super) fn closing_bound(&self, cl: &Cluster, until: f64) -> f64 {
        let h = cl.integ.step_size();
        self.landing_end(cl, cl.data.lo, cl.data.hi, h, until)
            .map_or(until, |end| until.min(end))
    }

    /// The first step of the piece `lo..hi` of the cluster `parent` that splits at its current
    /// time: the inherited step `h` ([`Hybrid::inherited_step`]), shortened to land just past
    /// a closing of the piece's outer boundaries predicted from the parent's continuous output
    /// (a new piece has no step of its own to continue; on the striker the closing ahead of
    /// the wave often comes right after the split behind it).
    pub(super) fn piece_step(&self, parent: &Cluster, lo: usize, hi: usize, h: f64) -> f64 {
        let t = parent.integ.t();
        self.landing_end(parent, lo, hi, h, f64::INFINITY)
            .map_or(h, |end| end - t)
    }

    /// End of a step of proposal `h` from `out`'s current time `t` that lands on the first
    /// predicted closing of the outer boundaries of beads `lo..hi` (module docs), searched up to
    /// `until` and [`HORIZON`] steps of `out` ahead: `None` where `out` has no DOP853 step to
    /// continue, no closing is predicted within `2h`, or the landing would be shorter than
    /// `MIN_FRACTION` of `h`.
    fn landing_end(&self, out: &Cluster, lo: usize, hi: usize, h: f64, until: f64) -> Option<f64> {
        let (t, tp) = (out.integ.t(), out.integ.t_prev());
        if out.integ.rate().is_none() || tp >= t {
            return None;
        }
        let horizon = until.min(t + (2.0 * h).min(HORIZON * (t - tp)));
        let tau = self.closing_lead(out, lo, hi, horizon);
        let end = if tau < h {
            t + tau * (1.0 + PAST)
        } else if tau < 2.0 * h {
            t + 0.5 * tau
        } else {
            return None;
        };
        (end - t >= MIN_FRACTION * h && end > t).then_some(end)
    }

    /// Lead time from `out`'s current time to the first predicted closing of the outer
    /// boundaries of beads `lo..hi` (whose trajectories are `out`'s continuous output continued
    /// past its step) with free beads, up to `horizon`; infinity when none is predicted.
    fn closing_lead(&self, out: &Cluster, lo: usize, hi: usize, horizon: f64) -> f64 {
        let t = out.integ.t();
        let mut tau = f64::INFINITY;
        if lo > 0 && self.predictable(lo - 1, lo - 1) {
            let c = lo - 1;
            let (pre, theta) = (self.pre(c), self.ctx.theta);
            let g = |s: f64| pre + self.pos(c, s).0 - out.u_at(s, lo) - theta;
            if let Some(tc) = self.boundary_crossing(g, t, horizon) {
                tau = tau.min(tc - t);
            }
        }
        if hi < self.ctx.n && self.predictable(hi - 1, hi) {
            let c = hi - 1;
            let (pre, theta) = (self.pre(c), self.ctx.theta);
            let g = |s: f64| pre + out.u_at(s, c) - self.pos(hi, s).0 - theta;
            if let Some(tc) = self.boundary_crossing(g, t, horizon) {
                tau = tau.min(tc - t);
            }
        }
        tau
    }

    /// Is the closing of contact `c` with the free bead `i` predicted (module docs)?
    fn predictable(&self, c: usize, i: usize) -> bool {
        self.st.owner[i] == FREE && self.ctx.chain.hard_restitution(c).is_none()
    }

    /// Does the continuous output of the cluster in `slot` give its state at the closing time
    /// `t` (a DOP853 step ending within [`NEAR_END`] of its length after `t`), so that no step
    /// needs to be redone to land there (module docs)?
    pub(super) fn output_suffices(&self, slot: u32, t: f64) -> bool {
        let cl = &self.clusters[slot];
        let (t1, t0) = (cl.integ.t(), cl.integ.t_prev());
        cl.integ.rate().is_some() && t1 > t0 && t1 - t <= NEAR_END * (t1 - t0)
    }

    /// Caps the first step of the cluster in `slot`, just made by a closing at approach speed
    /// `w` of a contact with reduced mass `mu` and law `(n, a)`, at the onset of its force
    /// (module docs). A method whose proposal is already shorter, or that takes no steps (an
    /// exact pair), is not changed.
    pub(super) fn cap_onset_step(&mut self, slot: u32, mu: f64, (n, a): (f64, f64), w: f64) {
        if !(w > 0.0 && a > 0.0 && n > 1.0) {
            return;
        }
        let d_max = (mu * w * w / (2.0 * a)).powf(1.0 / n);
        let h = d_max / w * (2.0 * self.ctx.cfg.rtol / ONSET_SHARE).powf(1.0 / n);
        let cl = &mut self.clusters[slot];
        if h.is_finite() && h > 0.0 && cl.integ.step_size() > h {
            cl.integ.set_step_size(h);
        }
    }
}
