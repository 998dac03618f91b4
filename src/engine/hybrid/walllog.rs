//! Soft-wall events of end beads that are part of a cluster.
//!
//! A soft wall's contact with the end bead is closed while its overlap `δ_w` (paper eq. 6 with
//! the wall's own law) exceeds the threshold `θ` of the bead–bead contacts ([`super`] module
//! docs), open below it. A lone bead's wall contact is an event of the engine itself: a free bead
//! reaching the wall makes a one-bead cluster ([`Hybrid::process_wall_close`]), and that cluster
//! splits when the wall no longer holds the bead. But the end bead of a cluster of several beads
//! keeps its wall force in the cluster's right-hand side, and its wall contact opens and closes
//! inside the cluster's steps without changing which beads are integrated together. Those
//! crossings used to go unlogged, so a log's `wall_close` and `wall_open` need not pair up (two
//! beads in a box of soft walls 2 units out, t = 1000, rtol 1e-6: 176 closings against 178
//! openings).
//!
//! So every accepted step of a cluster that holds a soft wall looks for the first crossing of
//! `θ` by that wall's overlap in the direction the log expects next ([`HybridData::wall_in`]:
//! closed or open), over the part of the step the cluster keeps (up to where it is parked), on
//! the continuous output with the same sampling + Illinois search as gap closings
//! ([`super::detect::first_crossing`]). A crossing found is logged only when the queue reaches
//! it (a [`Key::WallLog`] entry): the log never runs ahead of the engine's clock, which an
//! advance paused at events reports ([`crate::engine::Stop::Event`]). When the cluster is
//! removed first (merged or split at an earlier time), the entry goes with it and the cluster
//! that takes the bead over searches again from there. A crossing is taken only in the right
//! direction: a window that starts on the far side of `θ` while moving back (right after a
//! closing, where `δ_w = θ` to rounding) measures the crossing from its starting overlap, as
//! hard contacts do ([`Hybrid::closing_offset`]).
//!
//! [`HybridData::wall_in`]: crate::engine::hybrid::saved::HybridData::wall_in

use super::cluster::Cluster;
use super::{prio, Hybrid, Key, FREE};
use crate::engine::events::EventKind;

impl Hybrid<'_> {
    /// The end bead at `side` (0 left, 1 right).
    pub(super) fn end_bead(&self, side: u8) -> usize {
        if side == 0 {
            0
        } else {
            self.ctx.n - 1
        }
    }

    /// Sides of the soft walls whose end bead `cl` holds.
    pub(super) fn soft_walls_of(&self, cl: &Cluster) -> impl Iterator<Item = u8> + '_ {
        let (lo, hi) = (cl.data.lo, cl.data.hi);
        [0u8, 1].into_iter().filter(move |&side| {
            let held = if side == 0 { lo == 0 } else { hi == self.ctx.n };
            held && self.soft_wall(side).is_some()
        })
    }

    /// The overlap of the soft wall at `side` with its end bead is `pre + s·u`: `(pre, s)`, or
    /// `None` where there is no soft wall.
    pub(super) fn wall_frame(&self, side: u8) -> Option<(f64, f64)> {
        let s = if side == 0 { -1.0 } else { 1.0 };
        self.soft_wall(side).map(|w| (w.precompression, s))
    }

    /// Is the soft wall at `side` closed on bead state `u` (overlap above `θ`)?
    pub(super) fn wall_closed_at(&self, side: u8, u: f64) -> bool {
        self.wall_frame(side)
            .is_some_and(|(pre, s)| pre + s * u > self.ctx.theta)
    }

    /// After an accepted step of the cluster in `slot`, kept up to `tb` (its end, or where it is
    /// parked): schedules the first crossing of `θ` by each soft wall it holds (module docs).
    pub(super) fn watch_walls(&mut self, slot: u32, tb: f64) {
        let cl = &self.clusters[slot];
        let ta = cl.integ.t_prev();
        let tb = tb.min(cl.integ.t());
        let mut found = [None; 2];
        for side in self.soft_walls_of(cl) {
            found[side as usize] = Some(self.next_wall_crossing(cl, side, ta, tb));
        }
        for side in [0u8, 1] {
            let key = Key::WallLog(side);
            match found[side as usize] {
                None => {} // not this cluster's wall
                Some(Some(t)) => {
                    let i = self.end_bead(side);
                    self.queue.push(key, prio(t, 1, i, key));
                }
                Some(None) => {
                    self.queue.remove(&key);
                }
            }
        }
    }

    /// First time in `[ta, tb]` where the overlap of the soft wall at `side` with `cl`'s end
    /// bead crosses `θ` in the direction the log expects next (module docs).
    fn next_wall_crossing(&self, cl: &Cluster, side: u8, ta: f64, tb: f64) -> Option<f64> {
        let (pre, s) = self.wall_frame(side)?;
        let i = self.end_bead(side);
        let delta = |t: f64| pre + s * cl.u_at(t, i);
        let (d0, dd0) = (delta(ta), s * cl.v_at(ta, i));
        // Sign +1: looking for δ rising above the threshold (closing), −1: falling below it.
        let dir = if self.st.wall_in[side as usize] {
            -1.0
        } else {
            1.0
        };
        // starting beyond θ while moving back: the crossing is measured from the start
        let back = dir * (d0 - self.ctx.theta) > 0.0 && dir * dd0 <= 0.0;
        // an exact wall contact leaves θ at the profile's time (super::exact)
        let leaving = (dir < 0.0 && !back)
            .then(|| {
                cl.integ
                    .exact_pair()
                    .and_then(|p| p.leaving(self.ctx.theta))
            })
            .flatten();
        if let Some(t) = leaving {
            return (ta < t && t <= tb).then_some(t);
        }
        let thr = if back { d0 } else { self.ctx.theta };
        super::detect::first_crossing(|t| dir * (delta(t) - thr), ta, tb)
    }

    /// The end bead `i` of the removed cluster `cl` becomes free at `t`: a soft wall the log
    /// still has closed (a lone bead leaving its wall, split by the step-end rule; or a crossing
    /// at the split's own time) is logged open at the downward crossing of `θ` located on `cl`'s
    /// last step (`t` if none is found), so a free end bead always has its walls open.
    pub(super) fn leave_soft_walls(&mut self, cl: &Cluster, i: usize, t: f64) {
        for side in [0u8, 1] {
            let closed = self.st.wall_in[side as usize] && self.soft_wall(side).is_some();
            if self.end_bead(side) != i || !closed {
                continue;
            }
            let t_open = self
                .next_wall_crossing(cl, side, cl.integ.t_prev(), t)
                .unwrap_or(t);
            let k = self.ctx.n - 1 + side as usize;
            let rel = cl.v_at(t_open, i);
            self.log(t_open, i, EventKind::WallOpen, rel, self.st.peak[k]);
            self.st.peak[k] = 0.0;
            self.st.wall_in[side as usize] = false;
        }
    }

    /// The queue reached a scheduled soft-wall crossing at `t` (module docs): logs it, and
    /// schedules the next crossing in the rest of the step that found it.
    pub(super) fn process_wall_log(&mut self, side: u8, t: f64) {
        let i = self.end_bead(side);
        let slot = self.st.owner[i];
        if slot == FREE {
            return;
        }
        let cl = &self.clusters[slot];
        let rel = cl.v_at(t, i);
        let tb = cl.data.t_now.min(cl.integ.t());
        let k = self.ctx.n - 1 + side as usize;
        if self.st.wall_in[side as usize] {
            self.log(t, i, EventKind::WallOpen, rel, self.st.peak[k]);
            self.st.peak[k] = 0.0;
        } else {
            // the peak of the closed phase: from the closing on (the step's earlier part, open,
            // may have raised it)
            let (pre, s) = self.wall_frame(side).expect("soft wall");
            let d = |x: f64| pre + s * cl.u_at(x, i);
            let dd = |x: f64| s * cl.v_at(x, i);
            self.st.peak[k] = super::detect::step_max(d, dd, t, tb.max(t));
            self.log(t, i, EventKind::WallClose, rel, 0.0);
        }
        self.st.wall_in[side as usize] ^= true;
        let cl = &self.clusters[slot];
        if let Some(next) = self.next_wall_crossing(cl, side, t, tb) {
            let key = Key::WallLog(side);
            self.queue.push(key, prio(next, 1, i, key));
        }
    }
}
