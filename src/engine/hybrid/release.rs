//! What holds a rigid body inside a cluster, and where it lets go ([`super::stick`] module
//! docs): a hard wall pinning an end bead (released when the net force on the bead, contacts +
//! field, points away from the wall) and a resting contact inside a rigid run (opened when it
//! would carry tension: contact `c` of a run `a..=b` with acceleration `A` carries
//! `F_c = Σ_{i=a..c} m_i (a_i − A)`, paper eq. 7 with `ü_i = A`).
//!
//! Each hold has a **margin**, a continuous function of the cluster's state that is positive
//! where the hold lets go: the end run's acceleration away from its wall, the tension of the
//! contact. At a step's end a positive margin splits the cluster there ([`Hybrid::needs_split`]);
//! within a step, a margin that changes sign is located on the continuous output like an
//! opening ([`Hybrid::first_release`]) and the step redone to end on it, where the hold is let go
//! ([`Hybrid::release_at`]). Before, the hold was let go at the end of the step that crossed:
//! a column under gravity pressed against a hard ceiling left it 0.07 … 0.002 time units late at
//! rtol 1e-8 … 1e-12 (pulled by the wall meanwhile), and a resting contact that was tensile
//! from its collision on held until the step's end.

use super::cluster::{Cluster, ClusterId, Hold, Pending};
use super::queue::{prio, Key};
use super::Hybrid;
use crate::engine::events::EventKind;
use crate::engine::EngineError;

/// A hold with its margin (positive: it lets go) and the margin it must exceed.
type Margin = (Hold, f64, f64);

/// Scratch of the margins' evaluations (in the workspace, so a step of a cluster with holds
/// allocates nothing): a state, its accelerations, the margins at a time and at the step's ends.
#[derive(Default)]
pub(super) struct HoldScratch {
    z: Vec<f64>,
    acc: Vec<f64>,
    out: Vec<Margin>,
    start: Vec<Margin>,
    end: Vec<Margin>,
}

impl Hybrid<'_> {
    /// The holds of `cl` and their margins at the local state `(u, v)` (as the integrator holds
    /// it), into `out`: the pinned walls (left, then right; let go where the margin is above 0),
    /// then the resting contacts of each rigid run (let go above `1e-12` of the run's force
    /// scale), in the order they are examined. `acc` is scratch (`m` long).
    fn margins(
        &self,
        cl: &Cluster,
        (u, v): (&[f64], &[f64]),
        acc: &mut [f64],
        out: &mut Vec<Margin>,
    ) {
        out.clear();
        let (lo, m) = (cl.data.lo, cl.m());
        self.ctx.chain.accel_v(lo, u, v, acc);
        let mass = &self.ctx.chain.mass[lo..cl.data.hi];
        let stuck = &self.st.stuck[lo..cl.data.hi - 1];
        // the acceleration of the rigid run `a..=b` (a lone bead's own), as `rigid_accel`
        let run = |a: usize, b: usize| {
            if b == a {
                return acc[a];
            }
            let (p, mt) = (a..=b).fold((0.0, 0.0), |(p, mt), i| {
                (p + mass[i] * acc[i], mt + mass[i])
            });
            p / mt
        };
        if cl.data.pinned[0] {
            let b = (0..m - 1).find(|&k| !stuck[k]).unwrap_or(m - 1);
            out.push((Hold::Wall(0), run(0, b), 0.0));
        }
        if cl.data.pinned[1] {
            let a = (0..m - 1).rev().find(|&k| !stuck[k]).map_or(0, |k| k + 1);
            out.push((Hold::Wall(1), -run(a, m - 1), 0.0));
        }
        if cl.rigid {
            self.contact_margins(cl, acc, out);
        }
    }

    /// The resting contacts' margins of the rigid runs of `cl` (accelerations `acc`; module
    /// docs): a run held by the left wall is summed from its free right end, one held by the
    /// right wall has `A = 0`.
    fn contact_margins(&self, cl: &Cluster, acc: &[f64], out: &mut Vec<Margin>) {
        let (lo, m) = (cl.data.lo, cl.m());
        let mass = &self.ctx.chain.mass[lo..cl.data.hi];
        let stuck = &self.st.stuck[lo..cl.data.hi - 1];
        let f = |i: usize| mass[i] * acc[i];
        let mut a = 0;
        while a < m {
            let mut b = a;
            while b + 1 < m && stuck[b] {
                b += 1;
            }
            let scale: f64 = (a..=b).map(|i| f(i).abs()).sum();
            let tol = 1e-12 * scale;
            if a == 0 && cl.data.pinned[0] {
                let mut s = 0.0;
                for c in (a..b).rev() {
                    s += f(c + 1);
                    out.push((Hold::Contact(lo + c), s, tol));
                }
            } else {
                let held_right = b == m - 1 && cl.data.pinned[1];
                let mean = if held_right {
                    0.0
                } else {
                    (a..=b).map(f).sum::<f64>() / mass[a..=b].iter().sum::<f64>()
                };
                let mut p = 0.0;
                for c in a..b {
                    p += f(c) - mass[c] * mean;
                    out.push((Hold::Contact(lo + c), -p, tol));
                }
            }
            a = b + 1;
        }
    }

    /// The holds of `cl` at its current state, into the workspace's `out`.
    fn margins_now(&self, cl: &Cluster, s: &mut HoldScratch) {
        let (m, z) = (cl.m(), cl.integ.state());
        s.acc.resize(m, 0.0);
        self.margins(cl, (&z[..m], &z[m..]), &mut s.acc, &mut s.out);
    }

    /// The holds of `cl` on its last step's continuous output at `t`, into `s.out`.
    fn margins_at(&self, cl: &Cluster, t: f64, s: &mut HoldScratch) {
        let m = cl.m();
        s.z.resize(2 * m, 0.0);
        s.acc.resize(m, 0.0);
        for k in 0..2 * m {
            s.z[k] = cl.integ.dense_at(t, k);
        }
        let (u, v) = s.z.split_at(m);
        self.margins(cl, (u, v), &mut s.acc, &mut s.out);
    }

    /// A resting contact inside `cl` that would be tensile at its current state (global
    /// contact index; module docs).
    pub(super) fn tension(&self, cl: &Cluster) -> Option<usize> {
        let s = &mut *self.ws.hold.borrow_mut();
        self.margins_now(cl, s);
        s.out.iter().find_map(|&(h, g, tol)| match h {
            Hold::Contact(c) if g > tol => Some(c),
            _ => None,
        })
    }

    /// A pinned end bead whose net force (contacts + field, real mass) points away from its
    /// wall at the current state: returns the side.
    pub(super) fn release_pin(&self, cl: &Cluster) -> Option<u8> {
        if !cl.data.pinned[0] && !cl.data.pinned[1] {
            return None;
        }
        let s = &mut *self.ws.hold.borrow_mut();
        self.margins_now(cl, s);
        s.out.iter().find_map(|&(h, g, tol)| match h {
            Hold::Wall(side) if g > tol => Some(side),
            _ => None,
        })
    }

    /// Earliest time `t_r ∈ (t0, t1)` where a hold of `cl` lets go within its last step
    /// `[t0, t1]` (a margin below its bound at `t0` and above at `t1`, located on the continuous
    /// output), and that hold. `None` for clusters without holds, and for crossings within
    /// `1e-3` of the step after its start or at its end (let go there by the step end's check).
    pub(super) fn first_release(&self, cl: &Cluster, t0: f64, t1: f64) -> Option<(f64, Hold)> {
        let pinned = cl.data.pinned[0] || cl.data.pinned[1];
        if !(pinned || cl.rigid) || cl.m() < 2 || t1 <= t0 {
            return None;
        }
        // the margins at the step's ends, then each crossing located on the continuous output
        // (the workspace's scratch: no allocation per step)
        let n = {
            let s = &mut *self.ws.hold.borrow_mut();
            self.margins_at(cl, t0, s);
            std::mem::swap(&mut s.out, &mut s.start);
            self.margins_at(cl, t1, s);
            std::mem::swap(&mut s.out, &mut s.end);
            s.start.len().min(s.end.len())
        };
        let mut first: Option<(f64, Hold)> = None;
        for k in 0..n {
            let ((hold, g1, tol1), (_, g0, tol0)) = {
                let s = self.ws.hold.borrow();
                (s.end[k], s.start[k])
            };
            if g0 > tol0 || g1 <= tol1 {
                continue;
            }
            let g = |t: f64| {
                let s = &mut *self.ws.hold.borrow_mut();
                self.margins_at(cl, t, s);
                s.out.get(k).map_or(-1.0, |&(_, g, tol)| g - tol)
            };
            let bound = first.map_or(t1, |(t, _)| t);
            let Some(t) = super::detect::first_crossing(g, t0, bound) else {
                continue;
            };
            if t - t0 > 1e-3 * (t1 - t0) && t < bound {
                first = Some((t, hold));
            }
        }
        first
    }

    /// The step of cluster `slot` crossed where `hold` lets go, at `t`: the cluster lands there
    /// when the queue reaches `t` ([`Self::release_at`]).
    pub(super) fn defer_release(&mut self, slot: ClusterId, t: f64, hold: Hold) {
        self.update_peaks(slot, t);
        self.watch_walls(slot, t);
        let cl = &mut self.clusters[slot];
        cl.data.pending = Some(Pending::Release { t, hold });
        cl.data.t_now = t;
        let lo = cl.data.lo;
        self.queue
            .push(Key::Cluster(slot), prio(t, 1, lo, Key::Cluster(slot)));
    }

    /// Cluster `slot`, at `t`, splits where a hold lets go, when the queue reaches it.
    pub(super) fn release_now(&mut self, slot: ClusterId, t: f64) {
        let cl = &mut self.clusters[slot];
        cl.data.pending = Some(Pending::Split);
        let lo = cl.data.lo;
        self.queue
            .push(Key::Cluster(slot), prio(t, 1, lo, Key::Cluster(slot)));
    }

    /// Lands cluster `slot` on `t`, lets `hold` go there (its margin is 0 to rounding in the
    /// landed state, so it is let go whatever the sign the redone step leaves) and splits.
    pub(super) fn release_at(
        &mut self,
        slot: ClusterId,
        t: f64,
        hold: Hold,
    ) -> Result<(), EngineError> {
        self.settle_at(slot, t)?;
        match hold {
            Hold::Wall(side) => {
                // the cluster's own flag too: the split's step-end check must not let it go (and
                // log it) a second time
                self.st.pinned[side as usize] = false;
                self.clusters[slot].data.pinned[side as usize] = false;
                let i = if side == 0 { 0 } else { self.ctx.n - 1 };
                self.log(t, i, EventKind::WallOpen, 0.0, 0.0);
            }
            Hold::Contact(c) => self.st.stuck[c] = false,
        }
        self.process_split(slot);
        Ok(())
    }
}
