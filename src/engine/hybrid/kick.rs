//! The event log across [`crate::engine::Engine::set_velocities`] (a "kick" at the clock `t`).
//!
//! Clusters step ahead of the clock: an opening is logged at its located crossing of `θ` when
//! the step it happened in ends, and a step's peak overlaps are taken when it is taken. A kick
//! ends every cluster at `t` and classifies the contacts again from the new state
//! ([`super::Hybrid`]'s `init`: closed or closing). Before, what lay between was lost: an
//! opening already crossed at `t` but not yet logged (`striker` kicked 1e-3 after contact 30
//! opened: that `open` was missing), contacts the new classification closed or opened without
//! a logged `close` or `open` (repeated kicks with unchanged velocities: 2 `close` and 80
//! `open` events where the plain run logs 98 and 99), and peak overlaps from the part of a
//! step after `t`, which the kick abandoned (a pair reversed before its peak logged the peak
//! it never reached, 0.574 where the largest overlap was 0.452). Now:
//! 1. [`Hybrid::settle_for_kick`]: each cluster's contacts that crossed `θ` downwards by `t` are
//!    logged as `open` at the crossing (as the step's end would have), and the peak overlaps of
//!    its contacts are the largest up to `t` (the peak before the cluster's last step, kept in
//!    the workspace, and the step's maximum over `[t_prev, t]`; a checkpoint does not keep it,
//!    so after a resume the step's whole maximum stays);
//! 2. [`Hybrid::log_reclassified`]: after the new start, each bead–bead contact whose state
//!    changed is logged at `t` (`close` with its new relative velocity, `open` with its peak).
//!
//! Soft walls' contacts are not settled this way.

use super::detect::step_max;
use super::Hybrid;
use crate::engine::events::EventKind;

impl Hybrid<'_> {
    /// Whether beads `c` and `c + 1` belong to one cluster.
    fn joined(&self, c: usize) -> bool {
        let (a, b) = (self.st.owner[c], self.st.owner[c + 1]);
        a == b && a != super::FREE
    }

    /// Logs the openings crossed by `t` and takes the peaks up to `t` (module docs, 1); returns
    /// which contacts are closed at `t`.
    pub(super) fn settle_for_kick(&mut self, t: f64) -> Vec<bool> {
        let n = self.ctx.n;
        let theta = self.ctx.theta;
        let mut closed = vec![false; n.saturating_sub(1)];
        let ids: Vec<_> = self.clusters.ids().collect();
        for slot in ids {
            let Some((lo, hi)) = self.clusters.get(slot).map(|cl| (cl.data.lo, cl.data.hi)) else {
                continue;
            };
            for c in lo..hi - 1 {
                if self.ctx.chain.hard_restitution(c).is_some() {
                    closed[c] = true;
                    continue;
                }
                let pre = self.pre(c);
                let cl = &self.clusters[slot];
                let ta = cl.integ.t_prev().min(t);
                let d = |x: f64| pre + cl.w_at(x, c) - cl.w_at(x, c + 1);
                let dd = |x: f64| cl.v_at(x, c) - cl.v_at(x, c + 1);
                let before = self.ws.peak_before[c];
                if before.is_finite() {
                    let p = match cl.integ.exact_pair() {
                        Some(pair) => pair.peak_over(ta, t),
                        None => step_max(d, dd, ta, t),
                    };
                    self.st.peak[c] = before.max(p);
                }
                if d(t) < theta && dd(t) < 0.0 {
                    let t_open = cl.opening_time(c, pre, theta, (ta, t));
                    let rel = dd(t_open);
                    self.log(t_open, c, EventKind::Open, rel, self.st.peak[c]);
                    self.st.peak[c] = 0.0;
                } else {
                    closed[c] = true;
                }
            }
        }
        closed
    }

    /// Logs at `t` the contacts whose state the new start changed (module docs, 2), from the
    /// states `(u, v)` at `t` and which contacts were closed before.
    pub(super) fn log_reclassified(&mut self, t: f64, closed: &[bool], u: &[f64], v: &[f64]) {
        for (c, &was) in closed.iter().enumerate() {
            if self.ctx.chain.hard_restitution(c).is_some() {
                continue;
            }
            let now = self.joined(c);
            let rel = v[c] - v[c + 1];
            if now && !was {
                self.log(t, c, EventKind::Close, rel, 0.0);
                self.st.peak[c] = (self.pre(c) + u[c] - u[c + 1]).max(0.0);
            } else if was && !now {
                self.log(t, c, EventKind::Open, rel, self.st.peak[c]);
                self.st.peak[c] = 0.0;
            }
        }
    }
}
