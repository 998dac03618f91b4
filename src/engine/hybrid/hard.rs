//! Hard contacts and hard walls: instantaneous collisions (the `n → ∞` limit of the power law).
//!
//! A hard contact never joins a cluster. When its gap closes (threshold 0) the bodies on its
//! two sides exchange the impulse of a collision with restitution `e`:
//! `v_a' = v_cm − s·m_b/M`, `v_b' = v_cm + s·m_a/M`, with separating speed `s = e·w` for the
//! approach speed `w` (momentum conserved to rounding; kinetic energy loses `(1 − e²)` of the
//! relative part). A body is a free bead's rigid group ([`super::stick`], infinite mass when a
//! wall holds it), or a bead alone when it is in a (soft) cluster.
//!
//! **Simultaneous collisions** are resolved sequentially in the queue order (time, then lowest
//! bead index): a Newton's cradle of equal beads with `e = 1` passes the striker's velocity to
//! the last bead exactly; with `e = 0` every collision sticks and all beads leave together.
//!
//! **Inelastic collapse** (infinitely many collisions in finite time, e.g. `e < 1` under a
//! field, or a sequence at one instant) is prevented with the collapse interval `t_c` of the
//! minimum-collision-interval ("TC") model of Luding & McNamara (Granular Matter 1, 1998):
//! - a collision **sticks** (the contact becomes a resting contact) when it is plastic, when
//!   the separating speed `e·w` is at most `p⁺·t_c` (`p`: the relative acceleration pressing
//!   the pair together, so the next collision would come within `2 t_c`), or when `e < 1` and
//!   the contact collided less than `t_c` before (collapse). Free bodies join one rigid group
//!   ([`super::stick`]); with a bead in a cluster the two bodies join one cluster, where beads
//!   joined by resting contacts move as one rigid run ([`super::cluster::rigid_accel`]) until a
//!   resting contact would carry tension. A cluster's end bead pressed into a hard wall is held
//!   there (pinned) when its collision sticks, until the net force on it points away from the
//!   wall. Sticking only loses energy.
//! - a collision with a bead in a cluster that does not stick is elastic within `t_c` of the
//!   previous one of the same contact and separates at least at `p⁺·t_c` (the TC model), so
//!   its collisions are at least about `2 t_c` apart.
//!
//! **Energy.** A collision changes the relative velocity from the approach speed `w` to the
//! separating speed `−s` with momentum conserved, so the kinetic energy drops by
//! `ΔE = ½ μ (w² − s²)` with the reduced mass `μ = m_a m_b / (m_a + m_b)` of the two bodies
//! (`μ = m` of the moving body against a wall or a body a wall holds): `½ μ (1 − e²) w²` for a
//! plain collision, `½ μ w²` when it sticks, and `ΔE < 0` when the TC floor `p⁺·t_c` raises
//! `s` above `e·w`. Every collision adds its `ΔE` to the dissipated energy `E_d` that frames
//! carry ([`crate::engine::Observer::dissipated`]; a scene with hard contacts or walls reports
//! it, [`crate::model::Chain::loses_energy`]), so `E_kin + E_pot + E_d` is conserved as in a
//! damped scene.
//!
//! **Event log.** A collision between beads is logged as `hard_collision` (the contact index);
//! a bounce off a hard wall as `wall_close` with the bead index and the bead's velocity, as a
//! soft wall's contact is (no `wall_open` follows a bounce, which lasts no time; a collision
//! that sticks holds the bead at the wall, and its release is a `wall_open`). It was logged as `hard_collision` with the bead
//! index, which `analyze` counted as a collision between beads and which a reader could not
//! tell from the contact between beads 0 and 1.

use super::stick::collide;
use super::{Hybrid, FREE};
use crate::engine::events::EventKind;
use crate::engine::EngineError;

/// Kinetic energy a collision of bodies of masses `ma`, `mb` (`∞`: held by a wall) loses when
/// their approach speed `w` becomes the separating speed `sep`: `½ μ (w² − sep²)` (module docs;
/// 0 when both are held, which never move).
fn collision_loss(ma: f64, mb: f64, w: f64, sep: f64) -> f64 {
    let mu = match (ma.is_infinite(), mb.is_infinite()) {
        (true, true) => return 0.0,
        (true, false) => mb,
        (false, true) => ma,
        (false, false) => ma * mb / (ma + mb),
    };
    0.5 * mu * (w * w - sep * sep)
}

impl Hybrid<'_> {
    /// Acceleration of bead `i` at the current event time (its owner settled there).
    fn accel_of(&mut self, i: usize) -> f64 {
        match self.st.owner[i] {
            FREE => self.st.free[i].g,
            s => {
                let cl = &self.clusters[s];
                cl.accel_now(self.ctx.chain, &mut self.ws.acc);
                self.ws.acc[i - cl.data.lo]
            }
        }
    }

    /// Gives beads `a..b` of one cluster the velocity `v` at `t` (the cluster settled at `t`):
    /// the cluster restarts from its state with the new velocities (its beads' states in
    /// scratch taken out for the call: no allocation).
    fn replace_velocity(&mut self, a: usize, b: usize, t: f64, v: f64) {
        let cl = self.remove_cluster(self.st.owner[a], t);
        let (lo, hi) = (cl.data.lo, cl.data.hi);
        let (mut us, mut vs) = (
            std::mem::take(&mut self.ws.eu),
            std::mem::take(&mut self.ws.ev),
        );
        for k in lo..hi {
            us[k - lo] = cl.u_at(t, k);
            vs[k - lo] = cl.v_at(t, k);
        }
        vs[a - lo..b - lo].fill(v);
        self.recycle(cl);
        self.make_cluster(lo, hi, t, (&us[..hi - lo], &vs[..hi - lo]), None, false);
        (self.ws.eu, self.ws.ev) = (us, vs);
    }

    /// The TC-model interval `t_c`.
    fn collapse_interval(&self) -> f64 {
        self.ctx
            .chain
            .hard
            .as_ref()
            .map_or(self.ctx.tol.scales.collapse_interval(), |h| {
                h.collapse_interval
            })
    }

    /// Effective restitution and separating-speed floor for collision slot `k` at `t`.
    fn tc_model(&mut self, k: usize, t: f64, e0: f64, push: f64) -> (f64, f64) {
        let tc = self.collapse_interval();
        let e = if t - self.st.last_hard[k] < tc {
            1.0
        } else {
            e0
        };
        self.st.last_hard[k] = t;
        (e, push.max(0.0) * tc)
    }

    /// Does a collision of slot `k` at `t` (restitution `e0`, approach speed `w`, relative
    /// acceleration `push` pressing it together) stick, i.e. become a resting contact
    /// ([`super::stick`])? Plastic, or a separating speed below what the push undoes within
    /// `t_c`, or inelastic and again within `t_c` of the previous collision (collapse).
    fn sticks(&self, k: usize, t: f64, e0: f64, w: f64, push: f64) -> bool {
        let tc = self.collapse_interval();
        e0 == 0.0
            || e0 * w.max(0.0) <= push.max(0.0) * tc
            || (e0 < 1.0 && t - self.st.last_hard[k] < tc)
    }

    /// Gives the body of bead `i` (its rigid group: free beads, or a run inside a cluster
    /// joined by resting contacts) the velocity `v` at `t`; nothing when a wall holds it.
    fn set_velocity(&mut self, i: usize, t: f64, v: f64) {
        let g = self.group_of(i);
        if g.held[0] || g.held[1] {
            return;
        }
        if self.st.owner[i] == FREE {
            self.set_group_velocity(&g, t, v);
        } else {
            self.replace_velocity(g.lo, g.hi, t, v);
        }
    }

    /// A hard contact `c` closes at `t`.
    pub(super) fn process_hard(&mut self, c: usize, t: f64) -> Result<(), EngineError> {
        let e0 = self.ctx.chain.hard_restitution(c).unwrap_or(1.0);
        for side in [self.st.owner[c], self.st.owner[c + 1]] {
            if side != FREE {
                self.settle_at(side, t)?;
            }
        }
        if self.st.owner[c] == FREE && self.st.owner[c + 1] == FREE {
            self.collide_free(c, t, e0);
            return Ok(());
        }
        let (va, vb) = (self.pos(c, t).1, self.pos(c + 1, t).1);
        let w = va - vb;
        let push = self.accel_of(c) - self.accel_of(c + 1);
        let (ga, gb) = (self.group_of(c), self.group_of(c + 1));
        let (ma, mb) = (self.group_mass(&ga), self.group_mass(&gb));
        self.log(t, c, EventKind::HardCollision, w, 0.0);
        if self.sticks(c, t, e0, w, push) {
            // a resting contact: the two bodies join one cluster and move as one there
            self.st.last_hard[c] = t;
            self.st.dissipated += collision_loss(ma, mb, w, 0.0);
            let v = collide(ma, va, mb, vb, 0.0).0;
            self.set_velocity(c, t, v);
            self.set_velocity(c + 1, t, v);
            self.st.stuck[c] = true;
            self.merge_at(c, t)?;
            // a resting contact already tensile lets go at once ([`super::release`])
            let slot = self.st.owner[c];
            if slot != FREE && self.tension(&self.clusters[slot]).is_some() {
                self.release_now(slot, t);
            }
            return Ok(());
        }
        let (e, floor) = self.tc_model(c, t, e0, push);
        let sep = (e * w.max(0.0)).max(floor);
        self.st.dissipated += collision_loss(ma, mb, w, sep);
        let (va2, vb2) = collide(ma, va, mb, vb, sep);
        self.set_velocity(c, t, va2);
        self.set_velocity(c + 1, t, vb2);
        self.after_velocity_change(ga.lo, gb.hi, t);
        Ok(())
    }

    /// Hard contact `c` between two free groups closes at `t`: a two-body collision of the
    /// groups, or they stick and form one group ([`super::stick`]).
    fn collide_free(&mut self, c: usize, t: f64, e0: f64) {
        let (ga, gb) = (self.group_of(c), self.group_of(c + 1));
        let (fa, fb) = (self.st.free[c], self.st.free[c + 1]);
        let (va, vb) = (fa.at(t).1, fb.at(t).1);
        let w = va - vb;
        let stick = self.sticks(c, t, e0, w, fa.g - fb.g);
        self.st.last_hard[c] = t;
        self.log(t, c, EventKind::HardCollision, w, 0.0);
        let (ma, mb) = (self.group_mass(&ga), self.group_mass(&gb));
        let sep = if stick { 0.0 } else { e0 * w.max(0.0) };
        self.st.dissipated += collision_loss(ma, mb, w, sep);
        if stick {
            let v = collide(ma, va, mb, vb, 0.0).0;
            self.st.stuck[c] = true;
            self.form_group(ga.lo, gb.hi, [ga.held[0], gb.held[1]], t, v);
        } else {
            let (va2, vb2) = collide(ma, va, mb, vb, sep);
            if ma.is_finite() {
                self.set_group_velocity(&ga, t, va2);
            }
            if mb.is_finite() {
                self.set_group_velocity(&gb, t, vb2);
            }
        }
        self.after_velocity_change(ga.lo, gb.hi, t);
    }

    /// The end bead at `side` reaches its hard wall at `t`.
    pub(super) fn process_hard_wall(&mut self, side: u8, t: f64) -> Result<(), EngineError> {
        let i = if side == 0 { 0 } else { self.ctx.n - 1 };
        let e0 = self.hard_wall(side).unwrap_or(1.0);
        if self.st.owner[i] == FREE {
            self.wall_free(side, i, t, e0);
            return Ok(());
        }
        self.settle_at(self.st.owner[i], t)?;
        let v = self.pos(i, t).1;
        let g = self.group_of(i);
        let (w, push) = if side == 0 {
            (-v, -self.accel_of(i))
        } else {
            (v, self.accel_of(i))
        };
        let k = self.ctx.n - 1 + side as usize;
        let stick = push > 0.0 && self.sticks(k, t, e0, w, push);
        let (e, floor) = self.tc_model(k, t, e0, push);
        self.log(t, i, EventKind::WallClose, v, 0.0);
        let sep = if stick {
            0.0
        } else {
            (e * w.max(0.0)).max(floor)
        };
        // every bead of the run gets the new velocity (`replace_velocity`): its real mass
        let mass: f64 = self.ctx.chain.mass[g.lo..g.hi].iter().sum();
        self.st.dissipated += collision_loss(mass, f64::INFINITY, w, sep);
        if stick {
            // Pressed into the wall by its cluster, and the collision sticks: the rigid-wall
            // limit is a bead held at the wall (pinned) until the net force pulls it away.
            self.st.pinned[side as usize] = true;
            self.replace_velocity(g.lo, g.hi, t, 0.0);
        } else {
            self.replace_velocity(g.lo, g.hi, t, if side == 0 { sep } else { -sep });
        }
        self.after_velocity_change(g.lo, g.hi, t);
        Ok(())
    }

    /// The free group of end bead `i` reaches the hard wall at `side` at `t`: it bounces, or
    /// it sticks and is held at rest by the wall ([`super::stick`]).
    fn wall_free(&mut self, side: u8, i: usize, t: f64, e0: f64) {
        let g = self.group_of(i);
        let f = self.st.free[i];
        let v = f.at(t).1;
        let (w, push) = if side == 0 { (-v, -f.g) } else { (v, f.g) };
        let k = self.ctx.n - 1 + side as usize;
        let stick = self.sticks(k, t, e0, w, push);
        self.st.last_hard[k] = t;
        self.log(t, i, EventKind::WallClose, v, 0.0);
        let sep = if stick { 0.0 } else { e0 * w.max(0.0) };
        // a group a wall already holds is at rest and stays so (infinite mass: no loss)
        self.st.dissipated += collision_loss(self.group_mass(&g), f64::INFINITY, w, sep);
        if stick {
            let mut held = g.held;
            held[side as usize] = true;
            self.form_group(g.lo, g.hi, held, t, 0.0);
        } else if !g.held[0] && !g.held[1] {
            self.set_group_velocity(&g, t, if side == 0 { sep } else { -sep });
        }
        self.after_velocity_change(g.lo, g.hi, t);
    }

    /// Re-predicts everything around beads `lo..hi` whose motion just changed at `t`.
    pub(super) fn after_velocity_change(&mut self, lo: usize, hi: usize, t: f64) {
        self.drop_predictions(lo, hi);
        for c in lo.saturating_sub(1)..hi.min(self.ctx.n - 1) {
            self.schedule_free_pair(c);
        }
        if lo == 0 {
            self.schedule_wall(0);
        }
        if hi == self.ctx.n {
            self.schedule_wall(1);
        }
        for i in lo..hi {
            if self.st.owner[i] == FREE {
                self.check_new_free(i, t);
            }
        }
    }
}

impl Hybrid<'_> {
    /// A speed of bead `i` at the rounding of its velocity scale: a bead let go by its wall
    /// (`super::release`) lies inside it by rounding and may move in by as little; that is no
    /// approach, so its wall gap is measured from where it starts (a Radau IIA run re-held such
    /// a bead by a zero-speed hit at once and let it go a step later).
    fn rounding_speed(&self, i: usize) -> f64 {
        16.0 * f64::EPSILON * self.ctx.tol.scales.bead_velocity(self.ctx.chain.mass[i])
    }

    /// First collision over `[t0, t1]` of `cl`'s end bead with a hard wall it holds (not pinned
    /// there): the crossing of the wall gap on the continuous output, as `(t, side)`. A bead that
    /// starts the window overlapping by rounding right after a bounce (moving away, or in at
    /// [`Self::rounding_speed`]) is measured from that overlap.
    pub(super) fn hard_wall_hit(
        &self,
        cl: &super::cluster::Cluster,
        t0: f64,
        t1: f64,
    ) -> Option<(f64, u8)> {
        let (lo, hi) = (cl.data.lo, cl.data.hi);
        let mut wall_hit: Option<(f64, u8)> = None;
        if lo == 0 && self.hard_wall(0).is_some() && !self.st.pinned[0] {
            let pre = self
                .ctx
                .chain
                .left_wall
                .as_ref()
                .map_or(0.0, |w| w.precompression);
            let d0 = pre - cl.u_at(t0, 0);
            let off = if d0 > 0.0 && cl.v_at(t0, 0) >= -self.rounding_speed(0) {
                d0
            } else {
                0.0
            };
            if let Some(t) = super::detect::first_crossing(|t| pre - cl.u_at(t, 0) - off, t0, t1) {
                wall_hit = Some((t, 0));
            }
        }
        if hi == self.ctx.n && self.hard_wall(1).is_some() && !self.st.pinned[1] {
            let pre = self
                .ctx
                .chain
                .right_wall
                .as_ref()
                .map_or(0.0, |w| w.precompression);
            let last = self.ctx.n - 1;
            let d0 = pre + cl.u_at(t0, last);
            let off = if d0 > 0.0 && cl.v_at(t0, last) <= self.rounding_speed(last) {
                d0
            } else {
                0.0
            };
            if let Some(t) = super::detect::first_crossing(|t| pre + cl.u_at(t, last) - off, t0, t1)
            {
                if wall_hit.is_none_or(|(te, _)| t < te) {
                    wall_hit = Some((t, 1));
                }
            }
        }
        wall_hit
    }
}
