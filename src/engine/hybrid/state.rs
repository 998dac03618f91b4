//! Saving and restoring the hybrid engine's state (checkpoints).

use super::cluster::Cluster;
use super::{prio, Hybrid, Key};
use crate::engine::checkpoint::{ClusterState, HybridState, QueueEntry};
use crate::engine::dense::make_integrator;
use std::cmp::Reverse;

impl Hybrid<'_> {
    /// Everything needed to continue bit-identically.
    pub(super) fn save(&self) -> HybridState {
        let clusters = self
            .clusters
            .iter()
            .map(|c| {
                c.as_ref().map(|c| ClusterState {
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
            t: self.clock,
            owner: self.owner.clone(),
            free: self.free.clone(),
            version: self.version.clone(),
            clusters,
            spare_slots: self.spare_slots.clone(),
            queue,
            peak: self.peak.clone(),
            stats: self.stats.clone(),
            events: self.events.clone(),
            counts: self.counts,
            largest: self.largest as u64,
            steps_total: self.steps_total,
            late_merges: self.late_merges,
            implicit_steps: self.implicit_steps,
            last_hard: self.last_hard.clone(),
            pinned: self.pinned,
            stuck: self.stuck.clone(),
            next_frame: self.next_frame,
            dissipated: self.dissipated,
        }
    }

    /// Restores a saved state; predictions that depend on the end time (free-flight closings
    /// and the next frame) are recomputed, so `until` may have been extended.
    pub(super) fn restore(&mut self, s: &HybridState) -> Result<(), String> {
        s.check(self.n)?;
        self.clock = s.t;
        self.owner.clone_from(&s.owner);
        self.free.clone_from(&s.free);
        self.version.clone_from(&s.version);
        self.clusters = s
            .clusters
            .iter()
            .enumerate()
            .map(|(k, c)| {
                let Some(c) = c else { return Ok(None) };
                let m = (c.hi - c.lo) as usize;
                let tol = self.cluster_tol(c.frame.1);
                let mut integ = make_integrator(self.cfg, m, tol);
                integ
                    .load(&c.integ)
                    .map_err(|e| format!("cluster slot {k} (beads {}..{}): {e}", c.lo, c.hi))?;
                Ok(Some(Cluster {
                    lo: c.lo as usize,
                    hi: c.hi as usize,
                    frame_u: c.frame.0,
                    frame_v: c.frame.1,
                    frame_t: c.frame.2,
                    integ,
                    t_now: c.t_now,
                    pending: c.pending,
                    mass: c.mass.clone(),
                    pinned: c.pinned,
                    rigid: s.stuck[c.lo as usize..c.hi as usize - 1].contains(&true),
                }))
            })
            .collect::<Result<_, String>>()?;
        self.spare_slots.clone_from(&s.spare_slots);
        self.queue.clear();
        for e in &s.queue {
            let key = match e.kind {
                0 => Key::Frame,
                1 => Key::Cluster(e.index as u32),
                2 => Key::FreeFree(e.index as u32),
                _ => Key::Wall(e.index as u8),
            };
            self.queue.push(
                key,
                Reverse((ordered_float::OrderedFloat(e.t), e.class, e.tie, key.id())),
            );
        }
        self.peak.clone_from(&s.peak);
        self.stats = s.stats.clone();
        self.events.clone_from(&s.events);
        self.counts = s.counts;
        self.largest = s.largest as usize;
        self.steps_total = s.steps_total;
        self.late_merges = s.late_merges;
        self.implicit_steps = s.implicit_steps;
        self.last_hard.clone_from(&s.last_hard);
        self.pinned = s.pinned;
        self.stuck.clone_from(&s.stuck);
        self.next_frame = s.next_frame;
        self.dissipated = s.dissipated;
        for c in 0..self.n.saturating_sub(1) {
            self.schedule_free_pair(c);
        }
        self.schedule_wall(0);
        self.schedule_wall(1);
        let tf = self.cfg.frame_time(self.next_frame);
        self.queue.push(Key::Frame, prio(tf, 0, 0, Key::Frame));
        Ok(())
    }
}
