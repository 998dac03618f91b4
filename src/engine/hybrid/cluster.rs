//! A contact cluster: a maximal run of beads joined by closed contacts, integrated on its own.
//!
//! The cluster integrates its beads in a **co-moving frame**: `u_i(t) = U + V (t − t_f) + w_i(t)`,
//! with `U` the first bead's displacement and `V` the centre-of-mass velocity at creation. The
//! forces depend only on differences `w_i − w_{i+1}` (paper eq. 6), so the equations of motion
//! for `w` are those of `u` (eq. 7), while overlaps of 1e-12 stay representable even when the beads
//! have travelled far (relative form). A cluster that holds a chain end with a wall uses the
//! absolute frame (`U = V = 0`), because the wall force depends on the absolute position.

use crate::integrate::Integrator;

/// Something a cluster found in its last step and must act on when the queue reaches it.
#[derive(Clone, Copy, Debug, PartialEq)]
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
}

/// One cluster of beads `lo..hi` with its integrator.
pub struct Cluster {
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
    /// The cluster's integrator (state `w`, `ẇ`).
    pub integ: Box<dyn Integrator>,
    /// The cluster's current time: `integ.t()`, or the earlier time it is parked at.
    pub t_now: f64,
    /// What to do when the queue reaches the cluster.
    pub pending: Option<Pending>,
}

impl Cluster {
    /// Number of beads.
    pub fn m(&self) -> usize {
        self.hi - self.lo
    }

    /// Frame displacement at `t`.
    #[inline]
    pub fn frame_at(&self, t: f64) -> f64 {
        self.frame_u + self.frame_v * (t - self.frame_t)
    }

    /// Local displacement `w` of global bead `i` at `t` (continuous output).
    #[inline]
    pub fn w_at(&self, t: f64, i: usize) -> f64 {
        self.integ.dense_at(t, i - self.lo)
    }

    /// Global displacement of bead `i` at `t ∈ [t_prev, t_now]`.
    #[inline]
    pub fn u_at(&self, t: f64, i: usize) -> f64 {
        self.frame_at(t) + self.w_at(t, i)
    }

    /// Global velocity of bead `i` at `t`.
    #[inline]
    pub fn v_at(&self, t: f64, i: usize) -> f64 {
        self.frame_v + self.integ.dense_at(t, self.m() + i - self.lo)
    }

    /// Earliest time at which the continuous output is valid.
    pub fn t_valid_from(&self) -> f64 {
        self.integ.t_prev()
    }
}
