//! Creating a cluster: its frame (centre of mass, or the lab frame at a wall, module docs of
//! [`super::cluster`]), its integrator masses (pinned beads held at rest), its integrator (an
//! exact pair, [`super::exact`], or the configured method, reusing removed ones), and its slot.

use super::cluster::{Cluster, ClusterData, ClusterSys, PIN_MASS_FACTOR};
use super::{prio, Hybrid, Key};
use crate::integrate::rest::Rest;
use crate::integrate::{new_integrator, Integrator};

impl Hybrid<'_> {
    /// Creates a cluster of beads `lo..hi` at time `t` from global states `u`, `v`. Its first
    /// step is `h` where given (the step size of the cluster it comes from, see
    /// [`Self::inherited_step`]), else the method's starting-step estimate. Two beads alone on
    /// a conservative contact, or one bead alone against a soft wall, take the exact path
    /// ([`super::exact`]); a cluster at rest whose forces balance to round-off is not
    /// integrated ([`super::rest`]); `from_flight`: the state is the free flight of two free beads (a
    /// free bead and its wall) that have just closed their contact.
    pub(super) fn make_cluster(
        &mut self,
        lo: usize,
        hi: usize,
        t: f64,
        (u, v): (&[f64], &[f64]),
        h: Option<f64>,
        from_flight: bool,
    ) {
        let m = hi - lo;
        let chain = self.ctx.chain;
        // a new cluster has taken no step: its contacts' peaks so far are their peaks before
        // its last step (read by a kick, `super::kick`)
        for c in lo..hi - 1 {
            self.ws.peak_before[c] = self.st.peak[c];
        }
        let absolute = (lo == 0 && chain.left_wall.is_some())
            || (hi == self.ctx.n && chain.right_wall.is_some());
        let (fu, fv) = self.frame_state(lo, hi, absolute, (u, v));
        let (mass, pinned) = self.cluster_masses(lo, hi);
        let tol = self.cluster_tol(lo, hi, fv, t);
        let rigid = self.st.stuck[lo..hi - 1].contains(&true);
        let exact = match (m, absolute) {
            (2, false) if !rigid => self.exact_law(lo),
            (1, true) if !pinned[0] && !pinned[1] => self.exact_wall_law(lo),
            _ => None,
        };
        let rest = exact.is_none() && self.at_rest(lo, &mass, pinned, rigid);
        let mut integ: Box<dyn Integrator> = match exact {
            Some(law) => {
                self.st.exact_pairs[0] += 1;
                self.exact_pair(law, from_flight)
            }
            None if rest => Box::new(Rest::new(m)),
            None => (self.ws.spare.pop())
                .and_then(|mut i| i.renew(m, tol).then_some(i))
                .unwrap_or_else(|| {
                    new_integrator(self.ctx.cfg.method, self.ctx.cfg.solver, m, tol)
                }),
        };
        let sys = ClusterSys {
            chain: self.ctx.fall.1.as_ref().unwrap_or(chain),
            lo,
            mass: &mass,
            pinned,
            rigid: rigid.then(|| &self.st.stuck[lo..hi - 1]),
        };
        match h {
            Some(h) => integ.restart(&sys, t, &self.ws.bu[..m], &self.ws.bv[..m], h),
            None => integ.reset(&sys, t, &self.ws.bu[..m], &self.ws.bv[..m]),
        }
        let data = ClusterData {
            lo,
            hi,
            frame_u: fu,
            frame_v: fv,
            frame_t: t,
            t_now: t,
            pending: None,
            mass,
            pinned,
        };
        let cl = Cluster {
            data,
            integ,
            // 0 with walls (the only clusters in the lab frame)
            frame_g: self.ctx.fall.0,
            rigid,
        };
        self.insert_cluster(cl, t);
    }

    /// The frame `(U, V)` of a new cluster of beads `lo..hi` from their states `u`, `v` (the
    /// lab frame where `absolute`, else the centre of mass: a frame that does not depend on
    /// which end is "first", so mirror images of a cluster are integrated with mirror-image
    /// numbers), and the beads' states in it, in `bu`, `bv`.
    fn frame_state(
        &mut self,
        lo: usize,
        hi: usize,
        absolute: bool,
        (u, v): (&[f64], &[f64]),
    ) -> (f64, f64) {
        let (fu, fv) = if absolute {
            (0.0, 0.0)
        } else {
            let mass = &self.ctx.chain.mass[lo..hi];
            let p: f64 = mass.iter().zip(v).map(|(m, x)| m * x).sum();
            let q: f64 = mass.iter().zip(u).map(|(m, x)| m * x).sum();
            let mt: f64 = mass.iter().sum();
            (q / mt, p / mt)
        };
        for i in 0..hi - lo {
            self.ws.bu[i] = u[i] - fu;
            self.ws.bv[i] = v[i] - fv;
        }
        (fu, fv)
    }

    /// The integrator masses of a new cluster of beads `lo..hi` (a reused allocation) and which
    /// end is pinned against its hard wall: a pinned bead, and the rigid run of resting contacts
    /// holding it, are held at rest (mass scaled by [`PIN_MASS_FACTOR`], velocity 0 in `bv`).
    fn cluster_masses(&mut self, lo: usize, hi: usize) -> (Vec<f64>, [bool; 2]) {
        let m = hi - lo;
        let mut mass = self.ws.spare_mass.pop().unwrap_or_default();
        mass.clear();
        mass.extend_from_slice(&self.ctx.chain.mass[lo..hi]);
        let pinned = [
            lo == 0 && self.st.pinned[0],
            hi == self.ctx.n && self.st.pinned[1],
        ];
        let stuck = &self.st.stuck[lo..hi - 1];
        let left_run = stuck.iter().take_while(|s| **s).count();
        let right_run = stuck.iter().rev().take_while(|s| **s).count();
        if pinned[0] {
            for k in 0..=left_run {
                mass[k] *= PIN_MASS_FACTOR;
                self.ws.bv[k] = 0.0;
            }
        }
        if pinned[1] {
            for k in m - 1 - right_run..m {
                mass[k] *= PIN_MASS_FACTOR;
                self.ws.bv[k] = 0.0;
            }
        }
        (mass, pinned)
    }

    /// Puts a new cluster in a free slot, gives it its beads and queues its first step at `t`.
    fn insert_cluster(&mut self, cl: Cluster, t: f64) {
        let (lo, hi) = (cl.data.lo, cl.data.hi);
        let slot = self.clusters.insert(self.st.spare_slots.pop(), cl);
        for i in lo..hi {
            self.st.owner[i] = slot;
            self.st.version[i] += 1;
        }
        self.st.largest = self.st.largest.max((hi - lo) as u64);
        self.queue
            .push(Key::Cluster(slot), prio(t, 2, lo, Key::Cluster(slot)));
        self.unstick_around(lo, hi, t);
    }
}
