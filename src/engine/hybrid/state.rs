//! Saving and restoring the hybrid engine's state (checkpoints).

use super::cluster::{Cluster, Clusters};
use super::saved::{ClusterState, HybridState};
use super::{prio, Hybrid, Key, Prio};
use crate::engine::checkpoint::StateError;
use crate::integrate::rest::Rest;
use crate::integrate::{new_integrator, Integrator, MethodState};

impl Hybrid<'_> {
    /// Everything needed to continue bit-identically.
    pub(super) fn save(&self) -> HybridState {
        let clusters = self
            .clusters
            .iter_slots()
            .map(|c| {
                c.map(|c| ClusterState {
                    data: c.data.clone(),
                    integ: c.integ.save(),
                })
            })
            .collect();
        let mut queue: Vec<(Key, Prio)> = self.queue.iter().map(|(k, p)| (*k, *p)).collect();
        // the heap's internal order is not part of the state: store in priority order (every
        // priority is unique)
        queue.sort_unstable_by_key(|(_, p)| p.0);
        HybridState {
            data: self.st.clone(),
            clusters,
            queue,
        }
    }

    /// Restores a saved state; predictions that depend on the end time (free-flight closings
    /// and the next frame) are recomputed, so `until` may have been extended (or set to the
    /// checkpoint's time: when the frame at it was written already, the run is finished).
    pub(super) fn restore(&mut self, s: &HybridState) -> Result<(), StateError> {
        s.check(self.ctx.n)?;
        self.st.clone_from(&s.data);
        let slots = (s.clusters.iter().enumerate())
            .map(|(k, c)| c.as_ref().map(|c| self.restore_cluster(k, c)).transpose())
            .collect::<Result<_, StateError>>()?;
        self.clusters = Clusters::from_slots(slots);
        self.queue.clear();
        for &(key, p) in &s.queue {
            self.queue.push(key, p);
        }
        for c in 0..self.ctx.n.saturating_sub(1) {
            self.schedule_free_pair(c);
        }
        self.schedule_wall(0);
        self.schedule_wall(1);
        let cfg = self.ctx.cfg;
        if self.st.next_frame > 0 && cfg.frame_time(self.st.next_frame - 1) >= cfg.until {
            // the last frame (at `until`) was written before the checkpoint: a resume whose
            // `--until` is the checkpoint's frame time writes no frame twice (the dense engine's
            // `last_frame_t >= until`)
            self.finished = true;
            return Ok(());
        }
        let tf = cfg.frame_time(self.st.next_frame);
        self.queue.push(Key::Frame, prio(tf, 0, 0, Key::Frame));
        Ok(())
    }

    /// The live cluster of saved slot `k`: its data as saved, an integrator of the method that
    /// saved it (an exact pair or wall contact only where this run takes the exact path there)
    /// loaded with its typed state, and what the run derives (frame fall, resting contacts).
    fn restore_cluster(&mut self, k: usize, c: &ClusterState) -> Result<Cluster, StateError> {
        let d = &c.data;
        let m = d.hi - d.lo;
        let mut integ: Box<dyn Integrator> = match (&c.integ.method, m) {
            (MethodState::Rest(_), _) => Box::new(Rest::new(m)),
            (MethodState::Exact(_), 2) => {
                let law = (self.exact_law(d.lo)).ok_or(StateError::IneligiblePair(k))?;
                self.exact_pair(law, false)
            }
            (MethodState::Exact(_), 1) => {
                let law = (self.exact_wall_law(d.lo)).ok_or(StateError::IneligibleWall(k))?;
                self.exact_pair(law, false)
            }
            _ => {
                let tol = self.cluster_tol(d.lo, d.hi, d.frame_v, d.frame_t);
                new_integrator(self.ctx.cfg.method, self.ctx.cfg.solver, m, tol)
            }
        };
        integ
            .load(&c.integ)
            .map_err(|error| StateError::Integrator {
                slot: k,
                beads: (d.lo as u64, d.hi as u64),
                error,
            })?;
        Ok(Cluster {
            data: d.clone(),
            integ,
            frame_g: self.ctx.fall.0,
            rigid: self.st.stuck[d.lo..d.hi - 1].contains(&true),
        })
    }
}
