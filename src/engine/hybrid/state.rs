//! Saving and restoring the hybrid engine's state (checkpoints).

use super::cluster::{Cluster, Clusters};
use super::{prio, Hybrid, Key};
use crate::engine::checkpoint::{ClusterState, HybridState, QueueEntry, StateError};
use crate::integrate::rest::Rest;
use crate::integrate::{new_integrator, Integrator, MethodState};
use std::cmp::Reverse;

impl Hybrid<'_> {
    /// Everything needed to continue bit-identically.
    pub(super) fn save(&self) -> HybridState {
        let clusters = self
            .clusters
            .iter_slots()
            .map(|c| {
                c.map(|c| ClusterState {
                    lo: c.lo as u64,
                    hi: c.hi as u64,
                    frame: (c.frame_u, c.frame_v, c.frame_t),
                    t_now: c.t_now,
                    pending: c.pending,
                    mass: c.mass.clone(),
                    pinned: c.pinned,
                    integ: c.integ.save(),
                })
            })
            .collect();
        let mut queue: Vec<QueueEntry> = self
            .queue
            .iter()
            .map(|(k, Reverse((t, class, tie, _)))| {
                let (kind, index) = match *k {
                    Key::Frame => (0, 0),
                    Key::Cluster(s) => (1, s as u64),
                    Key::FreeFree(c) => (2, c as u64),
                    Key::Wall(w) => (3, w as u64),
                    Key::WallLog(w) => (4, w as u64),
                };
                QueueEntry {
                    kind,
                    index,
                    t: t.0,
                    class: *class,
                    tie: *tie,
                }
            })
            .collect();
        // the heap's internal order is not part of the state: store in priority order
        queue.sort_by(|a, b| {
            (a.t, a.class, a.tie, a.kind, a.index)
                .partial_cmp(&(b.t, b.class, b.tie, b.kind, b.index))
                .unwrap_or(std::cmp::Ordering::Equal)
        });
        HybridState {
            data: self.st.clone(),
            clusters,
            queue,
        }
    }

    /// Restores a saved state; predictions that depend on the end time (free-flight closings
    /// and the next frame) are recomputed, so `until` may have been extended.
    pub(super) fn restore(&mut self, s: &HybridState) -> Result<(), StateError> {
        s.check(self.ctx.n)?;
        self.st.clone_from(&s.data);
        let slots = s
            .clusters
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let Some(c) = c else { return Ok(None) };
                let m = (c.hi - c.lo) as usize;
                let tol = self.cluster_tol(c.lo as usize, c.hi as usize, c.frame.1, c.frame.2);
                let exact = matches!(c.integ.method, MethodState::Exact(_));
                let rest = matches!(c.integ.method, MethodState::Rest(_));
                let mut integ: Box<dyn Integrator> = match (exact, m) {
                    _ if rest => Box::new(Rest::new(m)),
                    (true, 2) => {
                        let law =
                            (self.exact_law(c.lo as usize)).ok_or(StateError::IneligiblePair(k))?;
                        self.exact_pair(law, false)
                    }
                    (true, 1) => {
                        let law = (self.exact_wall_law(c.lo as usize))
                            .ok_or(StateError::IneligibleWall(k))?;
                        self.exact_pair(law, false)
                    }
                    _ => new_integrator(self.ctx.cfg.method, self.ctx.cfg.solver, m, tol),
                };
                integ
                    .load(&c.integ)
                    .map_err(|error| StateError::Integrator {
                        slot: k,
                        beads: (c.lo, c.hi),
                        error,
                    })?;
                Ok(Some(Cluster {
                    lo: c.lo as usize,
                    hi: c.hi as usize,
                    frame_u: c.frame.0,
                    frame_v: c.frame.1,
                    frame_t: c.frame.2,
                    frame_g: self.ctx.fall.0,
                    integ,
                    t_now: c.t_now,
                    pending: c.pending,
                    mass: c.mass.clone(),
                    pinned: c.pinned,
                    rigid: s.data.stuck[c.lo as usize..c.hi as usize - 1].contains(&true),
                }))
            })
            .collect::<Result<_, StateError>>()?;
        self.clusters = Clusters::from_slots(slots);
        self.queue.clear();
        for e in &s.queue {
            let key = match e.kind {
                0 => Key::Frame,
                1 => Key::Cluster(e.index as u32),
                2 => Key::FreeFree(e.index as u32),
                3 => Key::Wall(e.index as u8),
                _ => Key::WallLog(e.index as u8),
            };
            self.queue.push(
                key,
                Reverse((ordered_float::OrderedFloat(e.t), e.class, e.tie, key.id())),
            );
        }
        for c in 0..self.ctx.n.saturating_sub(1) {
            self.schedule_free_pair(c);
        }
        self.schedule_wall(0);
        self.schedule_wall(1);
        let tf = self.ctx.cfg.frame_time(self.st.next_frame);
        self.queue.push(Key::Frame, prio(tf, 0, 0, Key::Frame));
        Ok(())
    }
}
