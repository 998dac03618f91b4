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
//! instead of taken at the step end.
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
use crate::model::Chain;

/// Smallest located opening time after the step start, as a fraction of the step.
const MIN_FRACTION: f64 = 1e-3;

/// Overlap, as a fraction of `θ`, at which an aimed retry should end ([`retry_fraction`]):
/// the located opening's own `θ/2`.
const RETRY_TARGET: f64 = 0.5;

/// A step that ends with a separating contact's overlap in `[LATE·θ, θ/2)` is split at its end
/// rather than redone to land on `θ/2`: an aimed retry ends there when its prediction ran a
/// little long, and splitting later (at a smaller overlap) neglects less of the contact force
/// than splitting at `θ/2` does.
const LATE: f64 = 0.4;

/// The aimed retry of a rejected explicit step that opened a contact.
///
/// A DOP853 step across an opening (`δ > 0` at its start, `δ ≤ 0` at its end) integrates
/// across the kink of `δ₊^{n−1}`; its error estimate then measures the kink and the step is
/// rejected, and the error-based retry (at least a fifth of the step) usually straddles the
/// kink again: on `disorder_2.5_0.04` 85 % of all rejections were such steps. Instead the
/// retry ends where the contact's overlap reaches `RETRY_TARGET·θ` (or half its starting
/// overlap, when smaller), located on the cubic Hermite interpolant of `δ` through the
/// rejected step's end values and slopes `δ̇` (both exact derivatives of the states), earliest
/// over the contacts that opened. The retry is an ordinary step: it is accepted only by the
/// error test, so accuracy is untouched; only the size of the next trial changes. `None` when
/// no contact opened, or when the located time is closer to the start than `MIN_FRACTION`
/// (the error-based retry is then kept). `z = (w, ẇ)` of the cluster's beads `lo..lo+m`.
pub(super) fn retry_fraction(
    chain: &Chain,
    lo: usize,
    theta: f64,
    (z0, z1): (&[f64], &[f64]),
    h: f64,
) -> Option<f64> {
    let m = z0.len() / 2;
    let mut first: Option<f64> = None;
    for k in 0..m.saturating_sub(1) {
        let c = lo + k;
        let pre = chain.precompression.as_ref().map_or(0.0, |p| p[c]);
        let (d0, d1) = (pre + z0[k] - z0[k + 1], pre + z1[k] - z1[k + 1]);
        if d0 <= 0.0 || d1 > 0.0 || chain.hard_restitution(c).is_some() {
            continue;
        }
        let (s0, s1) = (
            h * (z0[m + k] - z0[m + k + 1]),
            h * (z1[m + k] - z1[m + k + 1]),
        );
        let target = (RETRY_TARGET * theta).min(0.5 * d0);
        let g = |x: f64| target - hermite(d0, s0, d1, s1, x);
        if let Some(x) = super::detect::first_crossing(g, 0.0, first.unwrap_or(1.0)) {
            if x < MIN_FRACTION {
                return None;
            }
            first = Some(x);
        }
    }
    first
}

/// The cubic Hermite interpolant on `[0, 1]` with values `p0`, `p1` and slopes `s0`, `s1`.
fn hermite(p0: f64, s0: f64, p1: f64, s1: f64, x: f64) -> f64 {
    let (x2, x3) = (x * x, x * x * x);
    (2.0 * x3 - 3.0 * x2 + 1.0) * p0
        + (x3 - 2.0 * x2 + x) * s0
        + (3.0 * x2 - 2.0 * x3) * p1
        + (x3 - x2) * s1
}

impl Hybrid<'_> {
    /// Earliest located opening time `t* ∈ (t0, t1)` of a contact of `cl` over its last step
    /// `[t0, t1]` (see module docs), or `None` when no contact opens strictly inside the step.
    pub(super) fn first_opening(&self, cl: &Cluster, t0: f64, t1: f64) -> Option<f64> {
        if cl.m() < 2 || cl.pinned[0] || cl.pinned[1] || t1 <= t0 {
            return None;
        }
        let z = cl.integ.state();
        let m = cl.m();
        let theta = self.theta;
        let mut first: Option<f64> = None;
        for k in 0..m - 1 {
            let c = cl.lo + k;
            let pre = self.pre(c);
            if pre + z[k] - z[k + 1] >= LATE * theta || z[m + k] - z[m + k + 1] >= 0.0 {
                continue; // still above θ, ends late (LATE), or not separating
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

    /// Records a located opening at `t` in the step just taken: the cluster waits in the queue
    /// until `t` ([`Self::open_at`]); until then its continuous output is the step's, valid
    /// over the whole of `[t0, t]`.
    pub(super) fn defer_open(&mut self, slot: u32, t: f64) {
        self.update_peaks(slot, t);
        let cl = self.clusters[slot as usize].as_mut().expect("live cluster");
        cl.pending = Some(Pending::Open { t });
        cl.t_now = t;
        let lo = cl.lo;
        self.queue
            .push(Key::Cluster(slot), prio(t, 1, lo, Key::Cluster(slot)));
    }

    /// Lands the cluster in `slot` on the located opening time `t` and splits it there if the
    /// split rule holds in the landed state (module docs), or continues it from `t` otherwise.
    pub(super) fn open_at(&mut self, slot: u32, t: f64) -> Result<(), EngineError> {
        self.settle_at(slot, t)?;
        let cl = self.clusters[slot as usize].as_ref().expect("live cluster");
        let (lo, split) = (cl.lo, self.needs_split(cl));
        let cl = self.clusters[slot as usize].as_mut().expect("live cluster");
        let class = if split {
            cl.pending = Some(Pending::Split);
            1
        } else {
            2
        };
        self.queue
            .push(Key::Cluster(slot), prio(t, class, lo, Key::Cluster(slot)));
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two beads (n = 2.5, a = 1, m = 1): one contact.
    fn pair() -> Chain {
        Chain {
            mass: vec![1.0, 1.0],
            exponent: vec![2.5],
            prefactor: vec![1.0],
            precompression: None,
            field: None,
            left_wall: None,
            right_wall: None,
            hard: None,
            damping: None,
        }
    }

    #[test]
    fn retry_fraction_ends_a_straddling_step_before_the_opening() {
        let (theta, h) = (1e-3, 0.1);
        // δ falls linearly from 0.01 to −0.01 over the step (δ̇ = −0.2 at both ends): the
        // Hermite cubic is that line, which reaches θ/2 at x = (0.01 − 5e-4)/0.02
        let z0 = [0.01, 0.0, -0.2, 0.0];
        let z1 = [-0.01, 0.0, -0.2, 0.0];
        let x = retry_fraction(&pair(), 0, theta, (&z0, &z1), h).expect("straddles");
        // abs tol 1e-12: Illinois refines the root to a few ulps
        assert!((x - (0.01 - 5e-4) / 0.02).abs() < 1e-12, "x = {x}");
        // a step that ends still touching, or starts open, is not targeted
        let inside = [0.001, 0.0, -0.2, 0.0];
        assert_eq!(retry_fraction(&pair(), 0, theta, (&z0, &inside), h), None);
        assert_eq!(retry_fraction(&pair(), 0, theta, (&z1, &z0), h), None);
    }
}
