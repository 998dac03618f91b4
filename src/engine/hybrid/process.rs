//! Event processing of the hybrid engine: merging on gap closing, splitting on gap opening, and
//! the free-flight predictions that follow.

use super::cluster::{Cluster, ClusterId, ClusterSys};
use super::free::{first_upward_crossing, Free};
use super::{prio, Hybrid, Key, FREE};
use crate::engine::events::EventKind;
use crate::engine::EngineError;
use crate::integrate::{Rough, Tolerances};

/// Integrators of removed clusters kept for reuse ([`Hybrid::recycle`]).
const SPARE_INTEGRATORS: usize = 64;

impl Hybrid<'_> {
    /// The first step of the pieces of the cluster in `slot` when it splits: its step-size
    /// proposal, where it was stepping with an explicit method and its contact forces are C¹
    /// (every exponent ≥ 2); `None` (the method's starting-step estimate) otherwise. A piece moves
    /// on the time scale the cluster had (its contacts are the cluster's, less the one that
    /// opened), and Hairer's estimate from the state alone (HNW I, II.4) starts it 4–5× below
    /// that and spends two or three steps growing back, on every split (1000-bead striker, rtol
    /// 1e-8: 10 063 steps, 9 090 inheriting). Not inherited:
    /// - for merges: a contact that has just closed follows `δ ∝ τ` in the force `δ^{n−1}`,
    ///   which a step of the old cluster's size does not resolve (inherited there, disorder at
    ///   rtol 1e-8 rejected 344 000 steps instead of 222 000 and ran 8 % longer);
    /// - where an exponent is below 2 (the force's derivative is unbounded at `δ → 0`):
    ///   alternating 1.5/2.5 at rtol 1e-8 took 2477 steps instead of 1495 with DOP853, and
    ///   8979 instead of 7711 with Radau IIA (which first failed there, "step size too small",
    ///   from a controller defect since fixed: `radau_step_after_a_zero_error_step_is_not_zero`);
    /// - from Radau IIA: no measurable gain (interface, striker, periodic decay: < 1 % steps).
    pub(super) fn inherited_step(&self, slot: ClusterId) -> Option<f64> {
        let cl = self.clusters.get(slot)?;
        let smooth = self.ctx.chain.exponent[cl.data.lo..cl.data.hi - 1]
            .iter()
            .all(|&n| n >= 2.0);
        let h = cl.integ.step_size();
        (smooth && cl.integ.rate().is_some() && h.is_finite() && h > 0.0).then_some(h)
    }

    /// The tolerances of the cluster of beads `lo..hi` integrated in a frame moving at
    /// `frame_v`: relative velocity errors are measured on lab-frame velocities (see
    /// [`Tolerances::v_frame`]), so a bead the wave has left at rest is held to `atol·V`, not to
    /// `rtol·|frame_v|`. A cluster held by a wall is integrated in the lab frame, and its
    /// relative displacement errors are measured from the wall's zero-overlap position
    /// ([`Tolerances::u_origin`]): a bead that flew 2 length units to a soft wall was held to
    /// `2·rtol` in position, far more than its overlap's share, and a single bounce lost up to
    /// 300·rtol of the energy (`tests/regressions.rs`).
    pub(super) fn cluster_tol(
        &self,
        lo: usize,
        hi: usize,
        frame_v: f64,
        frame_t: f64,
    ) -> Tolerances {
        let u_origin = match (&self.ctx.chain.left_wall, &self.ctx.chain.right_wall) {
            (Some(w), _) if lo == 0 => w.precompression,
            (_, Some(w)) if hi == self.ctx.n => -w.precompression,
            _ => 0.0,
        };
        Tolerances {
            // relative to the chain's free fall at the frame's time (Chain::free_fall)
            v_frame: if self.ctx.fall.0 == 0.0 {
                frame_v
            } else {
                frame_v - self.ctx.fall.0 * frame_t
            },
            u_origin,
            ..self.ctx.tol
        }
    }

    /// Removes a cluster at time `t` (its counters go to the run totals, and the energy it
    /// dissipated up to `t`, not up to the end of its last step, to the run's books: a merge
    /// can read a cluster's state at `t` from the continuous output of a step that ends past
    /// `t`, and the merged cluster integrates the dissipation from `t` on).
    pub(super) fn remove_cluster(&mut self, slot: ClusterId, t: f64) -> Cluster {
        let cl = self.clusters.remove(slot);
        if self.ctx.chain.is_dissipative() {
            let sys = cl.sys(
                self.ctx.fall.1.as_ref().unwrap_or(self.ctx.chain),
                &self.st.stuck,
            );
            let t = t.min(cl.integ.t());
            let diss = self.ws.diss.get_mut();
            self.st.dissipated += crate::integrate::dissipated_at(&*cl.integ, &sys, t, diss);
        }
        self.queue.remove(&Key::Cluster(slot));
        // a wall crossing its step found goes with it (the next owner searches again)
        if cl.data.lo == 0 {
            self.queue.remove(&Key::WallLog(0));
        }
        if cl.data.hi == self.ctx.n {
            self.queue.remove(&Key::WallLog(1));
        }
        self.st.stats.add(cl.integ.stats());
        self.st.implicit_steps += cl.integ.implicit_steps();
        self.st.spare_slots.push(slot);
        cl
    }

    /// Keeps the integrator and mass array of a removed cluster for the next cluster made (at most
    /// [`SPARE_INTEGRATORS`] are kept).
    pub(super) fn recycle(&mut self, cl: Cluster) {
        if cl.integ.exact_pair().is_some() {
            if self.ws.spare_pairs.len() < SPARE_INTEGRATORS {
                self.ws.spare_pairs.push(cl.integ);
            }
            self.ws.spare_mass.push(cl.data.mass);
            return;
        }
        if self.ws.spare.len() < SPARE_INTEGRATORS && !cl.integ.at_rest() {
            self.ws.spare.push(cl.integ);
            self.ws.spare_mass.push(cl.data.mass);
        }
    }

    /// Makes bead `i` free with state (u, v) at `t`.
    pub(super) fn set_free(&mut self, i: usize, t: f64, u: f64, v: f64) {
        self.st.owner[i] = FREE;
        self.st.version[i] += 1;
        self.st.free[i] = Free {
            t0: t,
            u0: u,
            v0: v,
            g: self.ctx.g[i],
        };
    }

    /// (Re)computes the predicted closing of contact `c` if both its beads are free.
    pub(super) fn schedule_free_pair(&mut self, c: usize) {
        let key = Key::FreeFree(c as u32);
        if self.st.owner[c] != FREE || self.st.owner[c + 1] != FREE {
            self.queue.remove(&key);
            return;
        }
        let (fa, fb) = (self.st.free[c], self.st.free[c + 1]);
        let tr = fa.t0.max(fb.t0);
        let (ua, va) = fa.at(tr);
        let (ub, vb) = fb.at(tr);
        // An exact pair closes at its onset (overlap 0), whatever its peak: a collision whose
        // peak overlap is below θ would otherwise fly through without the force. Not beads
        // that overlap already (let go at θ on their way out of a contact), nor beads that
        // approach at a tolerance-level speed (touching beads a wave left behind): they close
        // at θ, as before (a closing at 0 would join them at rounding-level speeds).
        let d = self.pre(c) + ua - ub;
        let soft = self.ctx.chain.hard_restitution(c).is_none();
        let exact = soft
            && d <= 0.0
            && !self.tolerance_level(va - vb, &[c, c + 1])
            && self.exact_law(c).is_some();
        let theta = if exact { 0.0 } else { self.theta_c(c) };
        let mut a = d - theta;
        if theta == 0.0 && va - vb <= 0.0 {
            // overlapping by rounding after a collision, not approaching: wait for the gap to
            // close again from touching
            a = a.min(0.0);
        }
        match first_upward_crossing(a, va - vb, fa.g - fb.g) {
            Some(s) if tr + s <= self.ctx.cfg.until => {
                self.queue.push(key, prio(tr + s, 1, c, key));
            }
            _ => {
                self.queue.remove(&key);
            }
        }
    }

    /// (Re)computes the predicted closing of a free end bead onto the wall at `side`.
    pub(super) fn schedule_wall(&mut self, side: u8) {
        let key = Key::Wall(side);
        let i = if side == 0 { 0 } else { self.ctx.n - 1 };
        if self.st.owner[i] != FREE {
            self.queue.remove(&key);
            return;
        }
        let f = self.st.free[i];
        let (d, dd, ddd, theta) = match (self.hard_wall(side), side) {
            (Some(_), 0) => {
                let w = self.ctx.chain.left_wall.as_ref().expect("wall");
                (w.precompression - f.u0, -f.v0, -f.g, 0.0)
            }
            (Some(_), _) => {
                let w = self.ctx.chain.right_wall.as_ref().expect("wall");
                (w.precompression + f.u0, f.v0, f.g, 0.0)
            }
            (None, _) => {
                let Some((d, dd, ddd)) = self.wall_state(side, f.u0, f.v0, i) else {
                    return;
                };
                // an exact wall contact from a gap closes at its onset (as an exact pair does)
                let exact =
                    d <= 0.0 && !self.tolerance_level(dd, &[i]) && self.exact_wall_law(i).is_some();
                (d, dd, ddd, if exact { 0.0 } else { self.ctx.theta })
            }
        };
        let mut a = d - theta;
        if theta == 0.0 && dd <= 0.0 {
            a = a.min(0.0); // hard wall: rounding overlap after a bounce is not a new collision
        }
        match first_upward_crossing(a, dd, ddd) {
            Some(s) if f.t0 + s <= self.ctx.cfg.until => {
                self.queue.push(key, prio(f.t0 + s, 1, i, key));
            }
            _ => {
                self.queue.remove(&key);
            }
        }
    }

    /// A bead that just became free at `t` next to a cluster that is already ahead in time:
    /// that cluster will not re-examine the part of its last step after `t`, so the gap is
    /// checked here over `[t, t_now]` (the cluster's output covers it), and a closing found
    /// there parks the cluster at it.
    pub(super) fn check_new_free(&mut self, i: usize, t: f64) {
        let mut found: Option<(ClusterId, usize, f64)> = None;
        if i > 0 && self.st.owner[i - 1] != FREE {
            let theta = self.closing_offset(i - 1, t);
            let s = self.st.owner[i - 1];
            let a = &self.clusters[s];
            if a.data.t_now > t {
                let c = i - 1;
                let pre = self.pre(c);
                let f = self.st.free[i];
                let g = |x: f64| pre + a.u_at(x, c) - f.at(x).0 - theta;
                if let Some(tc) = self.boundary_crossing(g, t, a.data.t_now) {
                    found = Some((s, c, tc));
                }
            }
        }
        if i + 1 < self.ctx.n && self.st.owner[i + 1] != FREE {
            let theta = self.closing_offset(i, t);
            let s = self.st.owner[i + 1];
            let a = &self.clusters[s];
            if a.data.t_now > t {
                let c = i;
                let pre = self.pre(c);
                let f = self.st.free[i];
                let g = |x: f64| pre + f.at(x).0 - a.u_at(x, i + 1) - theta;
                if let Some(tc) = self.boundary_crossing(g, t, a.data.t_now) {
                    if found.is_none_or(|(_, _, te)| tc < te) {
                        found = Some((s, c, tc));
                    }
                }
            }
        }
        if let Some((s, c, tc)) = found {
            let ver = (self.st.version[c], self.st.version[c + 1]);
            let a = &mut self.clusters[s];
            a.data.pending = Some(super::cluster::Pending::Close {
                contact: c,
                t: tc,
                ver,
            });
            a.data.t_now = tc;
            self.queue
                .push(Key::Cluster(s), prio(tc, 1, c, Key::Cluster(s)));
        }
    }

    /// Removes the free-flight predictions that involve beads `lo..hi`.
    pub(super) fn drop_predictions(&mut self, lo: usize, hi: usize) {
        for c in lo.saturating_sub(1)..hi.min(self.ctx.n - 1) {
            self.queue.remove(&Key::FreeFree(c as u32));
        }
        if lo == 0 {
            self.queue.remove(&Key::Wall(0));
        }
        if hi == self.ctx.n {
            self.queue.remove(&Key::Wall(1));
        }
    }

    /// Brings a cluster's integrator exactly to `t ∈ [t_prev, t]` by redoing its last step to
    /// land on `t`, so that the state at an event is a full-accuracy step result rather than
    /// the (lower-order) continuous output.
    pub(super) fn settle_at(&mut self, slot: ClusterId, t: f64) -> Result<(), EngineError> {
        let chain = self.ctx.chain;
        let cl = &mut self.clusters[slot];
        cl.data.t_now = t;
        if cl.integ.t() <= t {
            return Ok(());
        }
        let t0 = cl.integ.t_prev();
        // a redone step starts at a kink, or ends on the one it lands on (kinks module)
        let rough = {
            let cl = &self.clusters[slot];
            let kink = self.rough_at(cl, t0, t - t0) || self.rough_at(cl, t, t - t0);
            if kink {
                Rough::Kink
            } else {
                Rough::Smooth
            }
        };
        let cl = &mut self.clusters[slot];
        let m = cl.m();
        let z = &mut self.ws.bz[..2 * m];
        let sys = ClusterSys {
            chain: self.ctx.fall.1.as_ref().unwrap_or(chain),
            lo: cl.data.lo,
            mass: &cl.data.mass,
            pinned: cl.data.pinned,
            rigid: cl.rigid.then(|| &self.st.stuck[cl.data.lo..cl.data.hi - 1]),
        };
        if t - t0 <= 64.0 * f64::EPSILON * t.abs().max(f64::MIN_POSITIVE) {
            // A few ulps after the step start: too short to integrate (the stage times would
            // coincide); the continuous output is exact to rounding there.
            cl.integ.dense(t, z);
            let diss = self.ws.diss.get_mut();
            self.st.dissipated += crate::integrate::dissipated_at(&*cl.integ, &sys, t, diss);
            cl.integ.reset(&sys, t, &z[..m], &z[m..]);
            return Ok(());
        }
        // the accepted step's own state at `t`, for a redo that cannot reach it (below)
        let zt = &mut self.ws.bzt[..2 * m];
        cl.integ.dense(t, zt);
        cl.integ.dense(t0, z);
        let d_t0 = cl.integ.dissipated().0;
        cl.integ.restart(&sys, t0, &z[..m], &z[m..], t - t0);
        cl.integ.set_rough(rough);
        while cl.integ.t() < t {
            match cl.integ.step(&sys, t) {
                Ok(_) => {}
                Err(crate::integrate::IntegrationError::StepTooSmall { .. }) => {
                    // A force that jumps (a dashpot wall's touch) a rounding-scale distance
                    // before `t`: the redo's steps shrink to rounding before it, and the
                    // accepted step's continuous output is the state there (the energy
                    // dissipated over that rounding-scale rest of the step is left out).
                    self.st.dissipated += d_t0 + cl.integ.dissipated().1;
                    cl.integ.reset(&sys, t, &zt[..m], &zt[m..]);
                    cl.integ.set_rough(Rough::Smooth);
                    return Ok(());
                }
                Err(e) => {
                    cl.integ.set_rough(Rough::Smooth);
                    return Err(e.into());
                }
            }
        }
        self.st.dissipated += d_t0;
        cl.integ.set_rough(Rough::Smooth);
        Ok(())
    }

    /// Merges everything on both sides of contact `c` into one cluster at `t`.
    pub(super) fn merge_at(&mut self, c: usize, t: f64) -> Result<(), EngineError> {
        for side in [self.st.owner[c], self.st.owner[c + 1]] {
            // a closing the step landed just past reads the state from the continuous output
            if side != FREE && !self.output_suffices(side, t) {
                self.settle_at(side, t)?;
            }
        }
        let flight = self.st.owner[c] == FREE && self.st.owner[c + 1] == FREE;
        // a free bead joins with its whole rigid group
        let lo = match self.st.owner[c] {
            FREE => self.group_of(c).lo,
            s => self.clusters[s].data.lo,
        };
        let hi = match self.st.owner[c + 1] {
            FREE => self.group_of(c + 1).hi,
            s => self.clusters[s].data.hi,
        };
        // the merged beads' states, in scratch taken out for the call (no allocation)
        let (mut u, mut v) = (
            std::mem::take(&mut self.ws.eu),
            std::mem::take(&mut self.ws.ev),
        );
        for i in lo..hi {
            let (a, b) = self.pos(i, t);
            u[i - lo] = a;
            v[i - lo] = b;
        }
        for side in [self.st.owner[c], self.st.owner[c + 1]] {
            if side != FREE && self.clusters.get(side).is_some() {
                let cl = self.remove_cluster(side, t);
                if let Some(pair) = cl.integ.exact_pair() {
                    self.st.exact_pairs[1] += 1;
                    let (lo, hi) = (cl.data.lo, cl.data.hi);
                    let beads = [lo, hi - 1];
                    let (peak, n, w) = (pair.peak(), pair.law().n, pair.impact_speed());
                    if self.shallow(peak, n, w, &beads[..hi - lo]) {
                        self.st.shallow_closings += 1;
                    }
                }
                self.recycle(cl);
            }
        }
        self.drop_predictions(lo, hi);
        let rel = v[c - lo] - v[c + 1 - lo];
        // A closing found late would start with an overlap well above θ: count them (a
        // diagnostic the tests hold at zero).
        let d = self.pre(c) + u[c - lo] - u[c + 1 - lo];
        if d > 1e3 * self.ctx.theta + 1e-12 * self.ctx.tol.scales.length {
            self.st.late_merges += 1;
        }
        self.st.peak[c] = 0.0;
        if !self.st.stuck[c] {
            self.log(t, c, EventKind::Close, rel, 0.0);
            self.count_slow_closing(rel, &[c, c + 1]);
        }
        self.make_cluster(lo, hi, t, (&u[..hi - lo], &v[..hi - lo]), None, flight);
        (self.ws.eu, self.ws.ev) = (u, v);
        if self.ctx.chain.hard_restitution(c).is_none() {
            let (m0, m1) = (self.ctx.chain.mass[c], self.ctx.chain.mass[c + 1]);
            let law = (self.ctx.chain.exponent[c], self.ctx.chain.prefactor[c]);
            let mu = m0 * m1 / (m0 + m1);
            let exact = self.clusters[self.st.owner[c]].integ.exact_pair().is_some();
            if flight && !exact && !self.st.stuck[c] {
                let load = mu * (self.ctx.g[c] - self.ctx.g[c + 1]);
                self.count_shallow((mu, rel, load), law, &[c, c + 1]);
            }
            self.cap_onset_step(self.st.owner[c], mu, law, rel);
        }
        Ok(())
    }

    /// A cluster reached the closing it found at `t` with the bead across contact `c`.
    pub(super) fn process_close(
        &mut self,
        slot: ClusterId,
        c: usize,
        t: f64,
        ver: (u64, u64),
    ) -> Result<(), EngineError> {
        if self.st.version[c] == ver.0 && self.st.version[c + 1] == ver.1 {
            if self.ctx.chain.hard_restitution(c).is_some() {
                return self.process_hard(c, t);
            }
            return self.merge_at(c, t);
        }
        // Stale (the neighbour changed since): continue the cluster from t.
        self.settle_at(slot, t)?;
        let lo = self.clusters[slot].data.lo;
        self.queue
            .push(Key::Cluster(slot), prio(t, 2, lo, Key::Cluster(slot)));
        Ok(())
    }

    /// Two free beads close contact `c` at `t`.
    pub(super) fn process_free_close(&mut self, c: usize, t: f64) -> Result<(), EngineError> {
        if self.ctx.chain.hard_restitution(c).is_some() {
            return self.process_hard(c, t);
        }
        self.merge_at(c, t)
    }

    /// A free end bead closes onto the wall at `side` at `t`.
    pub(super) fn process_wall_close(&mut self, side: u8, t: f64) {
        let i = if side == 0 { 0 } else { self.ctx.n - 1 };
        let (u, v) = self.pos(i, t);
        self.drop_predictions(i, i + 1);
        self.st.peak[self.ctx.n - 1 + side as usize] = 0.0;
        self.log(t, i, EventKind::WallClose, v, 0.0);
        self.st.wall_in[side as usize] = true;
        self.count_slow_closing(v, &[i]);
        self.make_cluster(i, i + 1, t, (&[u], &[v]), None, true);
        if let Some(w) = self.soft_wall(side) {
            let law = (w.exponent, w.prefactor);
            let speed = if side == 0 { -v } else { v };
            let m = self.ctx.chain.mass[i];
            if self.clusters[self.st.owner[i]].integ.exact_pair().is_none() {
                self.count_shallow((m, speed, m * self.ctx.g[i]), law, &[i]);
            }
            self.cap_onset_step(self.st.owner[i], m, law, speed);
        }
    }

    /// Splits a cluster at every contact that opened (and frees a lone bead leaving a wall).
    pub(super) fn process_split(&mut self, slot: ClusterId) {
        let (lo, hi, t) = {
            let cl = &self.clusters[slot];
            (cl.data.lo, cl.data.hi, cl.data.t_now)
        };
        self.release_and_unstick(slot, t);
        let h = self.inherited_step(slot);
        let cl = self.remove_cluster(slot, t);
        let m = hi - lo;
        let z = cl.integ.state();
        let fu = cl.frame_at(t);
        let (mut u, mut v) = (
            std::mem::take(&mut self.ws.eu),
            std::mem::take(&mut self.ws.ev),
        );
        for k in 0..m {
            u[k] = fu + z[k];
            v[k] = cl.frame_vel(t) + z[m + k];
        }
        let mut start = lo;
        for i in lo..hi {
            let last = i + 1 == hi;
            let opens = !last && {
                let k = i - lo;
                let d = self.pre(i) + z[k] - z[k + 1];
                if self.ctx.chain.hard_restitution(i).is_some() {
                    !self.st.stuck[i]
                } else {
                    d < self.ctx.theta && z[m + k] - z[m + k + 1] < 0.0
                }
            };
            if opens {
                // The split happens at the step end (the dynamics inside the cluster were exact
                // up to there); the logged time is the crossing located on the step's output,
                // a resting hard contact's the split's own (its overlap stays 0 while it rests:
                // a crossing of θ on the output would be anywhere in the step).
                let t_open = if self.ctx.chain.hard_restitution(i).is_some() {
                    t
                } else {
                    cl.opening_time(i, self.pre(i), self.ctx.theta, (cl.integ.t_prev(), t))
                };
                let rel = cl.v_at(t_open, i) - cl.v_at(t_open, i + 1);
                self.log(t_open, i, EventKind::Open, rel, self.st.peak[i]);
                self.st.peak[i] = 0.0;
            }
            if opens || last {
                let (a, b) = (start - lo, i + 1 - lo);
                if i + 1 - start == 1 && !self.wall_holds(start, u[a], v[a]) {
                    self.leave_soft_walls(&cl, start, t);
                    self.set_free(start, t, u[a], v[a]);
                } else if i > start && (start..i).all(|k| self.st.stuck[k]) {
                    self.free_rigid_piece(start, i + 1, t, &u[a..b], &v[a..b]);
                } else {
                    let h = h.map(|h| self.piece_step(&cl, start, i + 1, h));
                    self.make_cluster(start, i + 1, t, (&u[a..b], &v[a..b]), h, false);
                }
                start = i + 1;
            }
        }
        self.recycle(cl);
        (self.ws.eu, self.ws.ev) = (u, v);
        self.reschedule_after_split(lo, hi, t);
    }

    /// After the split of beads `lo..hi` at `t`: the free-flight closings and wall contacts of
    /// the pieces and their neighbours are predicted again, and an end bead left alone against
    /// the hard wall that holds it is held again.
    fn reschedule_after_split(&mut self, lo: usize, hi: usize, t: f64) {
        for c in lo.saturating_sub(1)..hi.min(self.ctx.n - 1) {
            self.schedule_free_pair(c);
        }
        for i in lo..hi {
            if self.st.owner[i] == FREE {
                self.check_new_free(i, t);
            }
        }
        if lo == 0 {
            self.schedule_wall(0);
        }
        if hi == self.ctx.n {
            self.schedule_wall(1);
        }
        // an end bead left alone against the hard wall that holds it stays held, as a group
        for (side, i) in [(0, 0), (1, self.ctx.n - 1)] {
            if self.st.pinned[side] && self.st.owner[i] == FREE && (lo..hi).contains(&i) {
                self.regroup(i, t);
            }
        }
    }
}
