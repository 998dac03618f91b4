//! Hard contacts and hard walls: instantaneous collisions (the `n → ∞` limit of the power law).
//!
//! A hard contact never joins a cluster. When its gap closes (threshold 0) the two beads
//! exchange the impulse of a collision with restitution `e`:
//! `v_a' = v_cm − s·m_b/M`, `v_b' = v_cm + s·m_a/M`, with separating speed `s = e·w` for the
//! approach speed `w` (momentum exact; kinetic energy loses `(1 − e²)` of the relative part).
//!
//! **Simultaneous collisions** are resolved sequentially in the queue order (time, then lowest
//! bead index): a Newton's cradle of equal beads with `e = 1` passes the striker's velocity to
//! the last bead exactly.
//!
//! **Inelastic collapse** (infinitely many collisions in finite time, e.g. `e < 1` under a
//! field, or a sequence at one instant) is prevented by the minimum-collision-interval ("TC")
//! model of Luding & McNamara (Granular Matter 1, 1998): a collision of a contact less than
//! `t_c` after its previous one is elastic, and the separating speed is at least `|δ̈|·t_c` (the
//! relative acceleration pushing the pair together), so collisions of one contact are at least
//! about `2 t_c` apart.

use super::{Hybrid, FREE};
use crate::engine::EngineError;
use crate::snapshot::EventKind;

impl Hybrid<'_> {
    /// Acceleration of bead `i` at the current event time (its owner settled there).
    fn accel_of(&self, i: usize) -> f64 {
        match self.owner[i] {
            FREE => self.g[i],
            s => {
                let cl = self.clusters[s as usize].as_ref().expect("live cluster");
                let m = cl.m();
                let z = cl.integ.state();
                let mut acc = vec![0.0; m];
                // real masses: the force a pinned bead feels
                self.chain.accel(cl.lo, &z[..m], &mut acc);
                acc[i - cl.lo]
            }
        }
    }

    /// Replaces bead `i`'s velocity at `t` (its owner settled at `t`): a free bead restarts its
    /// flight, a cluster restarts from its state with the new velocity.
    fn replace_velocity(&mut self, i: usize, t: f64, u: f64, v: f64) {
        match self.owner[i] {
            FREE => self.set_free(i, t, u, v),
            s => {
                let cl = self.remove_cluster(s);
                let (lo, hi) = (cl.lo, cl.hi);
                let mut us: Vec<f64> = (lo..hi).map(|k| cl.u_at(t, k)).collect();
                let mut vs: Vec<f64> = (lo..hi).map(|k| cl.v_at(t, k)).collect();
                us[i - lo] = u;
                vs[i - lo] = v;
                self.make_cluster(lo, hi, t, &us, &vs);
            }
        }
    }

    /// The TC-model interval `t_c`.
    fn collapse_interval(&self) -> f64 {
        self.chain
            .hard
            .as_ref()
            .map_or(1e-9 * self.cfg.until, |h| h.collapse_interval)
    }

    /// Effective restitution and separating-speed floor for collision slot `k` at `t`.
    fn tc_model(&mut self, k: usize, t: f64, e0: f64, push: f64) -> (f64, f64) {
        let tc = self.collapse_interval();
        let e = if t - self.last_hard[k] < tc { 1.0 } else { e0 };
        self.last_hard[k] = t;
        (e, push.max(0.0) * tc)
    }

    /// A hard contact `c` closes at `t`.
    pub(super) fn process_hard(&mut self, c: usize, t: f64) -> Result<(), EngineError> {
        let e0 = self.chain.hard_restitution(c).unwrap_or(1.0);
        for side in [self.owner[c], self.owner[c + 1]] {
            if side != FREE {
                self.settle_at(side, t)?;
            }
        }
        let (ua, va) = self.pos(c, t);
        let (ub, vb) = self.pos(c + 1, t);
        let w = va - vb;
        let push = self.accel_of(c) - self.accel_of(c + 1);
        let (e, floor) = self.tc_model(c, t, e0, push);
        let (ma, mb) = (self.chain.mass[c], self.chain.mass[c + 1]);
        let mt = ma + mb;
        let vcm = (ma * va + mb * vb) / mt;
        let sep = (e * w.max(0.0)).max(floor);
        self.log(t, c, EventKind::HardCollision, w, 0.0);
        self.replace_velocity(c, t, ua, vcm - sep * mb / mt);
        self.replace_velocity(c + 1, t, ub, vcm + sep * ma / mt);
        self.after_velocity_change(c, c + 2, t);
        Ok(())
    }

    /// The end bead at `side` reaches its hard wall at `t`.
    pub(super) fn process_hard_wall(&mut self, side: u8, t: f64) -> Result<(), EngineError> {
        let i = if side == 0 { 0 } else { self.n - 1 };
        let e0 = self.hard_wall(side).unwrap_or(1.0);
        if self.owner[i] != FREE {
            self.settle_at(self.owner[i], t)?;
        }
        let (u, v) = self.pos(i, t);
        let (w, push) = if side == 0 {
            (-v, -self.accel_of(i))
        } else {
            (v, self.accel_of(i))
        };
        let k = self.n - 1 + side as usize;
        let chatter = t - self.last_hard[k] < self.collapse_interval();
        let (e, floor) = self.tc_model(k, t, e0, push);
        self.log(t, i, EventKind::HardCollision, w, 0.0);
        if self.owner[i] != FREE && push > 0.0 && (chatter || w <= floor) {
            // Pressed into the wall by its cluster at (almost) no speed: the rigid-wall limit
            // is a bead held at the wall (pinned) until the net force pulls it away.
            self.pinned[side as usize] = true;
            self.replace_velocity(i, t, u, 0.0);
        } else {
            let sep = (e * w.max(0.0)).max(floor);
            self.replace_velocity(i, t, u, if side == 0 { sep } else { -sep });
        }
        self.after_velocity_change(i, i + 1, t);
        Ok(())
    }

    /// Re-predicts everything around beads `lo..hi` whose motion just changed at `t`.
    fn after_velocity_change(&mut self, lo: usize, hi: usize, t: f64) {
        self.drop_predictions(lo, hi);
        for c in lo.saturating_sub(1)..hi.min(self.n - 1) {
            self.schedule_free_pair(c);
        }
        if lo == 0 {
            self.schedule_wall(0);
        }
        if hi == self.n {
            self.schedule_wall(1);
        }
        for i in lo..hi {
            if self.owner[i] == FREE {
                self.check_new_free(i, t);
            }
        }
    }
}
