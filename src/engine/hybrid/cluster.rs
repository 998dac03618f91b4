//! A contact cluster: a maximal run of beads joined by closed contacts, integrated on its own.
//!
//! The cluster integrates its beads in a **co-moving frame**: `u_i(t) = U + V (t − t_f) + w_i(t)`,
//! with `U` the first bead's displacement and `V` the centre-of-mass velocity at creation. The
//! forces depend only on differences `w_i − w_{i+1}` (paper eq. 6), so the equations of motion
//! for `w` are those of `u` (eq. 7), while overlaps of 1e-12 stay representable even when the beads
//! have travelled far (relative form). A cluster that holds a chain end with a wall uses the
//! absolute frame (`U = V = 0`), because the wall force depends on the absolute position.
//!
//! A chain in a field without walls falls freely ([`Chain::free_fall`]): the frame falls with
//! it, `U + V τ + ½ g τ²` (`τ = t − t_f`), and the cluster integrates the chain less the field's
//! common part, so a uniform field leaves the integrated numbers those of the chain without one.

use crate::integrate::{Integrator, System};
use crate::model::Chain;

/// Mass factor of a bead pinned against a hard wall (effectively infinite: its acceleration is
/// also set to zero, the factor keeps the Newton matrices consistent with that).
pub const PIN_MASS_FACTOR: f64 = 1e100;

/// The system a cluster integrates: its beads of the chain, with pinned end beads held fixed.
pub struct ClusterSys<'a> {
    /// The chain.
    pub chain: &'a Chain,
    /// First bead.
    pub lo: usize,
    /// Masses used by the integrator (pinned beads scaled by [`PIN_MASS_FACTOR`]).
    pub mass: &'a [f64],
    /// First / last bead pinned against its hard wall.
    pub pinned: [bool; 2],
    /// Resting hard contacts inside the cluster (local contact `k` joins beads `k`, `k + 1`),
    /// when it has any: the beads they join move as one rigid body ([`super::stick`]).
    pub rigid: Option<&'a [bool]>,
}

impl System for ClusterSys<'_> {
    fn len(&self) -> usize {
        self.mass.len()
    }
    fn mass(&self) -> &[f64] {
        self.mass
    }
    fn accel(&self, u: &[f64], v: &[f64], acc: &mut [f64]) -> f64 {
        let p = self.chain.accel_v(self.lo, u, v, acc);
        self.pin(acc);
        p
    }
    fn accel_stiffness(
        &self,
        u: &[f64],
        v: &[f64],
        acc: &mut [f64],
        k: &mut [f64],
        kv: &mut [f64],
    ) -> f64 {
        let p = self.chain.accel_stiffness_v(self.lo, u, v, acc, k, kv);
        self.pin(acc);
        p
    }
    fn dissipative(&self) -> bool {
        self.chain.is_dissipative()
    }
}

impl ClusterSys<'_> {
    #[inline]
    fn pin(&self, acc: &mut [f64]) {
        if let Some(stuck) = self.rigid {
            rigid_accel(&self.chain.mass[self.lo..], stuck, self.pinned, acc);
        }
        if self.pinned[0] {
            acc[0] = 0.0;
        }
        if self.pinned[1] {
            let m = acc.len();
            acc[m - 1] = 0.0;
        }
    }
}

/// Gives every run of beads joined by resting contacts (`stuck[k]` joins `k`, `k + 1`) the
/// run's acceleration `Σ m_i a_i / Σ m_i` (internal contact forces cancel), 0 when the run
/// holds a pinned end bead.
pub fn rigid_accel(mass: &[f64], stuck: &[bool], pinned: [bool; 2], acc: &mut [f64]) {
    let m = acc.len();
    let mut a = 0;
    while a < m {
        let mut b = a;
        while b + 1 < m && stuck[b] {
            b += 1;
        }
        if b > a {
            let held = (a == 0 && pinned[0]) || (b == m - 1 && pinned[1]);
            let mean = if held {
                0.0
            } else {
                let (p, mt) = (a..=b).fold((0.0, 0.0), |(p, mt), i| {
                    (p + mass[i] * acc[i], mt + mass[i])
                });
                p / mt
            };
            acc[a..=b].fill(mean);
        }
        a = b + 1;
    }
}

/// Something that holds inside a cluster ([`super::release`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Hold {
    /// The hard wall at this side (0 left, 1 right) pins the cluster's end bead.
    Wall(u8),
    /// Resting contact `c` (global index) inside a rigid run.
    Contact(usize),
}

/// Something a cluster found in its last step and must act on when the queue reaches it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Pending {
    /// The gap of `contact` (to a bead outside the cluster) closes at `t`. `ver` are the
    /// versions of the two beads of the contact when it was found (stale if they changed).
    Close {
        /// Contact index (beads `contact`, `contact + 1`).
        contact: usize,
        /// Time of the closing.
        t: f64,
        /// Versions of beads `contact` and `contact + 1`.
        ver: (u64, u64),
    },
    /// Some contacts inside have opened (re-examined when processed).
    Split,
    /// The end bead reaches a hard wall (`side` 0 left, 1 right) at `t`.
    HardWall {
        /// Which wall.
        side: u8,
        /// Time of the collision.
        t: f64,
    },
    /// A contact inside opens at `t` (located on the continuous output,
    /// [`super::opening`]): the cluster lands there when the queue reaches `t`.
    Open {
        /// Located opening time.
        t: f64,
    },
    /// A hold inside lets go at `t` (located on the continuous output, [`super::release`]):
    /// the cluster lands there, lets it go and splits.
    Release {
        /// Located time.
        t: f64,
        /// What lets go.
        hold: Hold,
    },
}

/// A cluster's state as data: its beads, frame, clock, pending event, integrator masses and
/// pinned ends. A checkpoint stores it as it is, beside the integrator's own typed state
/// ([`super::saved::ClusterState`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ClusterData {
    /// First bead.
    pub lo: usize,
    /// One past the last bead.
    pub hi: usize,
    /// Frame displacement `U`.
    pub frame_u: f64,
    /// Frame velocity `V`.
    pub frame_v: f64,
    /// Frame reference time `t_f`.
    pub frame_t: f64,
    /// The cluster's current time: `integ.t()`, or the earlier time it is parked at.
    pub t_now: f64,
    /// What to do when the queue reaches the cluster.
    pub pending: Option<Pending>,
    /// Integrator masses (pinned beads scaled).
    pub mass: Vec<f64>,
    /// First / last bead pinned against its hard wall.
    pub pinned: [bool; 2],
}

/// One cluster of beads `lo..hi` with its integrator: its state as data ([`ClusterData`]), the
/// integrator holding the state `w`, `ẇ` (saved as its typed state), and what the run derives
/// (the frame's fall, whether it holds a resting contact).
pub struct Cluster {
    /// The cluster's state.
    pub data: ClusterData,
    /// The cluster's integrator (state `w`, `ẇ`).
    pub integ: Box<dyn Integrator>,
    /// Frame acceleration `g` (the chain's free fall, [`Chain::free_fall`]; 0 in general).
    pub frame_g: f64,
    /// Holds a resting hard contact (derived from the engine's `stuck` flags).
    pub rigid: bool,
}

impl Cluster {
    /// Number of beads.
    pub fn m(&self) -> usize {
        self.data.hi - self.data.lo
    }

    /// Frame displacement at `t`.
    #[inline]
    pub fn frame_at(&self, t: f64) -> f64 {
        let tau = t - self.data.frame_t;
        let u = self.data.frame_u + self.data.frame_v * tau;
        if self.frame_g == 0.0 {
            u
        } else {
            u + 0.5 * self.frame_g * tau * tau
        }
    }

    /// Frame velocity at `t`.
    #[inline]
    pub fn frame_vel(&self, t: f64) -> f64 {
        if self.frame_g == 0.0 {
            self.data.frame_v
        } else {
            self.data.frame_v + self.frame_g * (t - self.data.frame_t)
        }
    }

    /// Local displacement `w` of global bead `i` at `t` (continuous output).
    #[inline]
    pub fn w_at(&self, t: f64, i: usize) -> f64 {
        self.integ.dense_at(t, i - self.data.lo)
    }

    /// Global displacement of bead `i` at `t ∈ [t_prev, t_now]`.
    #[inline]
    pub fn u_at(&self, t: f64, i: usize) -> f64 {
        self.frame_at(t) + self.w_at(t, i)
    }

    /// Global velocity of bead `i` at `t`.
    #[inline]
    pub fn v_at(&self, t: f64, i: usize) -> f64 {
        self.frame_vel(t) + self.integ.dense_at(t, self.m() + i - self.data.lo)
    }

    /// When contact `c` (precompression `pre`) crossed the threshold `theta` downwards within
    /// `[ta, t]`: an exact pair's own leaving time, else the crossing located on the
    /// continuous output (`t` where none is found), as the event log records an opening.
    pub fn opening_time(&self, c: usize, pre: f64, theta: f64, (ta, t): (f64, f64)) -> f64 {
        let g = |x: f64| theta - (pre + self.w_at(x, c) - self.w_at(x, c + 1));
        match self.integ.exact_pair().and_then(|p| p.leaving(theta)) {
            Some(te) => te.clamp(ta, t),
            None => super::detect::first_crossing(g, ta, t).unwrap_or(t),
        }
    }

    /// The accelerations of the cluster's beads at its current state, with their real masses
    /// (the force a pinned bead feels), into `acc` (resized to the cluster's beads).
    pub fn accel_now(&self, chain: &Chain, acc: &mut Vec<f64>) {
        let m = self.m();
        let z = self.integ.state();
        acc.resize(m, 0.0);
        chain.accel_v(self.data.lo, &z[..m], &z[m..], acc);
    }

    /// The system this cluster integrates (`stuck`: the engine's flags, one per contact).
    pub fn sys<'a>(&'a self, chain: &'a Chain, stuck: &'a [bool]) -> ClusterSys<'a> {
        ClusterSys {
            chain,
            lo: self.data.lo,
            mass: &self.data.mass,
            pinned: self.data.pinned,
            rigid: self.rigid.then(|| &stuck[self.data.lo..self.data.hi - 1]),
        }
    }
}

/// A cluster's slot in [`Clusters`]: what the beads' owners, the event queue and checkpoints
/// name a cluster by (stored as its number, `serde(transparent)`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(transparent)]
pub struct ClusterId(u32);

impl ClusterId {
    /// The owner of a free bead: no cluster.
    pub const FREE: ClusterId = ClusterId(u32::MAX);

    /// The slot number.
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// The live clusters, each in a slot (rapier's island set): the slot numbers are what the
/// beads' owners, the event queue and checkpoints name a cluster by, and a removed cluster's
/// slot is reused by the next one made ([`super::HybridData`]'s spare slots). Indexing a slot
/// that holds no cluster is an engine defect, checked here once.
#[derive(Default)]
pub struct Clusters {
    slots: Vec<Option<Cluster>>,
}

impl Clusters {
    /// The clusters of a checkpoint, in their slots.
    pub fn from_slots(slots: Vec<Option<Cluster>>) -> Self {
        Self { slots }
    }

    /// Every slot's id, live or free.
    pub fn ids(&self) -> impl Iterator<Item = ClusterId> {
        (0..self.slots.len() as u32).map(ClusterId)
    }

    /// The cluster in `slot`, if it is live.
    pub fn get(&self, slot: ClusterId) -> Option<&Cluster> {
        self.slots.get(slot.index()).and_then(Option::as_ref)
    }

    /// The cluster in `slot`, if it is live.
    pub fn get_mut(&mut self, slot: ClusterId) -> Option<&mut Cluster> {
        self.slots.get_mut(slot.index()).and_then(Option::as_mut)
    }

    /// Puts `cl` in `slot` (a free one) or, without one, in a new slot; returns the slot.
    pub fn insert(&mut self, slot: Option<ClusterId>, cl: Cluster) -> ClusterId {
        match slot {
            Some(s) => {
                self.slots[s.index()] = Some(cl);
                s
            }
            None => {
                self.slots.push(Some(cl));
                ClusterId((self.slots.len() - 1) as u32)
            }
        }
    }

    /// Takes the cluster out of `slot`, leaving it free.
    pub fn remove(&mut self, slot: ClusterId) -> Cluster {
        self.slots[slot.index()].take().expect("live cluster")
    }

    /// Every slot, live (`Some`) or free.
    pub fn iter_slots(&self) -> impl Iterator<Item = Option<&Cluster>> {
        self.slots.iter().map(Option::as_ref)
    }

    /// The live clusters.
    pub fn iter(&self) -> impl Iterator<Item = &Cluster> {
        self.slots.iter().flatten()
    }

    /// The live clusters, mutably.
    pub fn iter_mut(&mut self) -> impl Iterator<Item = &mut Cluster> {
        self.slots.iter_mut().flatten()
    }
}

impl std::ops::Index<ClusterId> for Clusters {
    type Output = Cluster;
    fn index(&self, slot: ClusterId) -> &Cluster {
        self.get(slot).expect("live cluster")
    }
}

impl std::ops::IndexMut<ClusterId> for Clusters {
    fn index_mut(&mut self, slot: ClusterId) -> &mut Cluster {
        self.get_mut(slot).expect("live cluster")
    }
}
