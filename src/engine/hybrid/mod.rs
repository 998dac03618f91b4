//! The event-driven hybrid engine.
//!
//! Beads that touch nothing fly analytically ([`free`]); maximal runs of beads joined by closed
//! contacts ("clusters", [`cluster`]) are integrated each on its own with the implicit (or
//! explicit) integrator of the dense engine, in a co-moving frame, with their own step sizes. Gap
//! closings and openings are discrete events in one priority queue. The physics is the paper's
//! eq. 7 exactly: inside a cluster the `(·)₊` of eq. 6 is integrated as is, so a contact that
//! opens and closes within one cluster step is still exact; events only decide *which beads are
//! integrated together*.
//!
//! ## Scheduling (why no event is missed or taken out of order)
//! The queue holds one entry per cluster, keyed by the cluster's current time (lagging cluster
//! first), one entry per predicted free–free or free–wall closing, the next output frame, and
//! per soft wall a crossing of `θ` found on the step of the cluster holding its end bead, until
//! the clock reaches it and it is logged ([`walllog`]).
//! When a cluster steps over `[t₀, t₁]` it looks for its boundary gaps closing over the part of
//! the step where the neighbour's trajectory is known (a free bead: always; a cluster: up to that
//! cluster's current time). Because clusters step lagging-first, the neighbour's last step always
//! covers `t₀`, and what one side cannot check yet the other side checks when it steps. Without a
//! field and hard contacts a boundary gap is convex in time, so its end values decide
//! ([`detect`]); otherwise it is sampled on the continuous output. A found
//! closing *parks* the cluster at the closing time; it is merged when the queue reaches that time,
//! when every other cluster's last step covers it. Explicit steps are shortened to end on
//! predicted openings (a lone bead's soft-wall contact too); an opening a step still reaches past
//! is located on the continuous output too and the cluster's step is redone to land on it
//! ([`opening`]). Explicit steps also end just past a closing with a free bead predicted from
//! the continuous output continued past its step, where the state is read without a redone step
//! ([`closing`]).
//!
//! ## Thresholds (hysteresis), documented rule
//! Let `θ = ε · L` (L: the run's characteristic length, see [`crate::model::Chain::scales`]) with
//! `ε = max(atol, rtol^p)`, `p = max(1, 1/(n_min − 1))` (`n_min`: the smallest exponent of the
//! chain). A gap *closes* when the overlap exceeds `θ`; a contact inside a cluster *opens* (the
//! cluster is split there) when its overlap falls below `θ` **and** the beads separate (`δ̇ < 0`).
//! `θ` must lie above the integration's own resolution of overlaps, which inside a wave is set by
//! `rtol` (relative error weights `rtol·|w|`), not by `atol`: with `θ = atol·L` and `rtol ≫ atol`
//! the decisions behind a solitary wave were taken on tolerance-level noise, so the number of
//! events depended on the method (hybrid DOP853, 1000-bead striker, rtol 1e-8: 1484 closings
//! instead of 998). The force neglected between a split pair is at most `n a θ^{n−1}`, i.e. at
//! most `ε^{n−1} ≤ rtol` of the characteristic force `n a L^{n−1}` (hence `p`); this removes the
//! super-exponentially small tails behind a solitary wave from the cluster, which is what keeps
//! the cost proportional to the beads actually in contact. Touching beads at rest (`δ = 0`,
//! `δ̇ = 0`) are never merged or split. Simultaneous events are processed in the order (time,
//! class, lowest bead index), which is deterministic.
//!
//! **Damped contacts** lower `θ` where their damping would dissipate more than `ε` of the
//! run's energy scale `E` below it ([`threshold()`]): a contact closing at the velocity scale `V`
//! dissipates `A·V·n a θ^{n−1}` (viscoelastic, `F_d = A F_el'(δ) δ̇`) or `c·V·θ` (linear
//! dashpot) before it is integrated, so `θ ≤ (εE / (A V n a))^{1/(n−1)}`, resp. `εE/(cV)`
//! (soft walls alike, with their own law).
//! Ordinary damping leaves `θ` as it is; an overdamped contact (3 beads, `A = 1e25`: the pair
//! sticks within `δ ≈ 1e-17`) closes at its onset, as in the dense engine, instead of 1e-8 deep,
//! where its damping force would be `1e20` (test `hybrid_overdamped_contact_is_integrated_like_dense`).

mod closing;
pub mod cluster;
mod context;
mod create;
pub mod detect;
mod eventlog;
mod exact;
pub mod free;
mod hard;
mod kick;
mod kinks;
mod opening;
mod process;
pub mod queue;
mod release;
mod rest;
pub mod saved;
mod state;
mod stepping;
mod stick;
mod threshold;
mod walllog;

pub use stepping::HybridEngine;
pub use threshold::{contact_threshold, threshold};

use super::{EngineError, RunConfig};
use crate::engine::events::EventCounts;
use crate::integrate::Stats;
use crate::scene::Scene;
use cluster::{Cluster, ClusterId, Clusters};
use context::{Context, Workspace};
use free::Free;
use queue::{prio, Queue};
pub use queue::{Key, Prio};
use saved::HybridData;

/// Owner of a free bead.
const FREE: ClusterId = ClusterId::FREE;

/// The hybrid engine: what it derives from the scene (rebuilt, never saved), its plain data
/// ([`HybridData`], saved as it is), its live clusters and event queue (saved as data by
/// [`Hybrid::save`], rebuilt by [`Hybrid::restore`]), and scratch.
pub struct Hybrid<'a> {
    /// What the run is: the chain, the configuration and what derives from them.
    ctx: Context<'a>,
    // ---- state
    /// Plain data (the checkpoint stores it as it is).
    st: HybridData,
    clusters: Clusters,
    queue: Queue,
    /// The last frame (at the run's end time) has been emitted (reset by every advance).
    finished: bool,
    /// Where advances pause ([`super::PauseAt`]).
    pause: super::PauseAt,
    /// Events logged so far that need no [`super::Stop::Event`] any more (returned, or logged
    /// while events were not paused at): the log's total count minus the ones still to return.
    reported: u64,
    /// Scratch, rebuilt at will ([`Workspace::new`]).
    ws: Workspace,
}

/// The peak overlaps at `t = 0`: each soft contact's and soft wall's overlap where it is
/// closed (positive), else 0. A contact that starts closed and only opens reaches its largest
/// overlap at the start, which no step's maximum covers ([`Hybrid::update_peaks`] takes each
/// step's interior and end).
fn initial_peaks(chain: &crate::model::Chain, u0: &[f64]) -> Vec<f64> {
    let n = chain.len();
    let mut peak = vec![0.0; n + 1];
    for c in 0..n.saturating_sub(1) {
        if chain.hard_restitution(c).is_none() {
            let pre = chain.precompression.as_ref().map_or(0.0, |p| p[c]);
            peak[c] = (pre + u0[c] - u0[c + 1]).max(0.0);
        }
    }
    let soft = |w: &Option<crate::model::Wall>| {
        w.as_ref()
            .filter(|w| w.restitution.is_none())
            .map(|w| w.precompression)
    };
    if let (Some(p), Some(&u)) = (soft(&chain.left_wall), u0.first()) {
        peak[n - 1] = (p - u).max(0.0);
    }
    if let (Some(p), Some(&u)) = (soft(&chain.right_wall), u0.last()) {
        peak[n] = (p + u).max(0.0);
    }
    peak
}

impl<'a> Hybrid<'a> {
    fn new(scene: &'a Scene, cfg: &'a RunConfig) -> Self {
        let chain = &scene.chain;
        let n = chain.len();
        let scales = chain.scales(&scene.u0, &scene.v0);
        let tol = cfg.tolerances(scales, Default::default());
        let g = match &chain.field {
            Some(w) => w.iter().zip(&chain.mass).map(|(w, m)| w / m).collect(),
            None => vec![0.0; n],
        };
        Self {
            ctx: Context {
                chain,
                cfg,
                tol,
                theta: threshold(chain, cfg.rtol, cfg.atol, &scales),
                n,
                g,
                fall: chain.free_fall(),
            },
            st: HybridData {
                t: 0.0,
                owner: vec![FREE; n],
                free: vec![Free::default(); n],
                version: vec![0; n],
                spare_slots: Vec::new(),
                peak: initial_peaks(chain, &scene.u0),
                stats: Stats::default(),
                events: Vec::new(),
                counts: EventCounts::default(),
                largest: 0,
                steps_total: 0,
                late_merges: 0,
                slow_closings: 0,
                shallow_closings: 0,
                implicit_steps: 0,
                exact_pairs: [0; 2],
                last_hard: vec![f64::NEG_INFINITY; n + 1],
                pinned: [false; 2],
                stuck: vec![false; n.saturating_sub(1)],
                next_frame: 0,
                dissipated: 0.0,
                wall_in: [false; 2],
            },
            clusters: Clusters::default(),
            queue: Queue::default(),
            finished: false,
            pause: super::PauseAt::default(),
            reported: 0,
            ws: Workspace::new(n),
        }
    }

    /// Contact threshold `θ`.
    pub fn theta(&self) -> f64 {
        self.ctx.theta
    }

    /// Closing threshold of contact `c`: `θ` for a soft contact, 0 for a hard one.
    fn theta_c(&self, c: usize) -> f64 {
        if self.ctx.chain.hard_restitution(c).is_some() {
            0.0
        } else {
            self.ctx.theta
        }
    }

    /// Threshold for detecting the closing of contact `c` from `t0` on. For a hard contact that
    /// starts the window overlapping by rounding right after a collision (δ₀ > 0 while not
    /// approaching), the threshold is δ₀: the next collision needs the overlap to grow again.
    ///
    /// A bead reaching an exact pair from a gap closes at its onset (overlap 0), as two free
    /// beads that may take the exact path do ([`Self::schedule_free_pair`]): a third body whose
    /// collision with the pair is shallower than `θ` would otherwise fly into it.
    fn closing_offset(&self, c: usize, t0: f64) -> f64 {
        if self.ctx.chain.hard_restitution(c).is_none() {
            let owners = [self.st.owner[c], self.st.owner[c + 1]];
            let pair = (owners.iter()).any(|&s| {
                s != FREE
                    && (self.clusters.get(s)).is_some_and(|cl| cl.integ.exact_pair().is_some())
            });
            if pair {
                let (ua, va) = self.pos(c, t0);
                let (ub, vb) = self.pos(c + 1, t0);
                let gap = self.pre(c) + ua - ub <= 0.0;
                if gap && !self.tolerance_level(va - vb, &[c, c + 1]) {
                    return 0.0;
                }
            }
            return self.ctx.theta;
        }
        let (ua, va) = self.pos(c, t0);
        let (ub, vb) = self.pos(c + 1, t0);
        let d0 = self.pre(c) + ua - ub;
        if d0 > 0.0 && va - vb <= 0.0 {
            d0
        } else {
            0.0
        }
    }

    /// Restitution of the wall at `side` when it is hard.
    fn hard_wall(&self, side: u8) -> Option<f64> {
        let w = if side == 0 {
            &self.ctx.chain.left_wall
        } else {
            &self.ctx.chain.right_wall
        };
        w.as_ref().and_then(|w| w.restitution)
    }

    fn pre(&self, c: usize) -> f64 {
        self.ctx.chain.precompression.as_ref().map_or(0.0, |p| p[c])
    }

    /// Displacement and velocity of bead `i` at `t` (valid where its owner's output is).
    fn pos(&self, i: usize, t: f64) -> (f64, f64) {
        match self.st.owner[i] {
            FREE => self.st.free[i].at(t),
            s => {
                let c = &self.clusters[s];
                (c.u_at(t, i), c.v_at(t, i))
            }
        }
    }

    /// Latest time up to which bead `i`'s trajectory is known.
    fn known_until(&self, i: usize) -> f64 {
        match self.st.owner[i] {
            FREE => f64::INFINITY,
            s => self
                .clusters
                .get(s)
                .map_or(f64::NEG_INFINITY, |c| c.data.t_now),
        }
    }

    /// Is the contact "closed or closing" in state (δ, δ̇, δ̈)?
    fn closing(&self, d: f64, dd: f64, ddd: f64) -> bool {
        d > self.ctx.theta || (d >= 0.0 && (dd > 0.0 || (dd == 0.0 && ddd > 0.0)))
    }

    /// Wall overlaps (δ, δ̇, δ̈) of the end bead at `side` (0 left, 1 right) for state (u, v).
    fn wall_state(&self, side: u8, u: f64, v: f64, i: usize) -> Option<(f64, f64, f64)> {
        if self.hard_wall(side).is_some() {
            return None;
        }
        if side == 0 {
            let w = self.ctx.chain.left_wall.as_ref()?;
            Some((w.precompression - u, -v, -self.ctx.g[i]))
        } else {
            let w = self.ctx.chain.right_wall.as_ref()?;
            Some((w.precompression + u, v, self.ctx.g[i]))
        }
    }

    /// Starts at `t0` from states `u0`, `v0` of every bead (free beads and clusters from the
    /// contacts that are closed or closing); the next frame is `self.st.next_frame`.
    fn init(&mut self, t0: f64, u0: &[f64], v0: &[f64]) {
        let n = self.ctx.n;
        self.st.wall_in = [
            self.wall_closed_at(0, u0[0]),
            self.wall_closed_at(1, u0[n - 1]),
        ];
        let mut lo = 0;
        while lo < n {
            let mut hi = lo + 1;
            while hi < n {
                let c = hi - 1;
                let d = self.pre(c) + u0[c] - u0[c + 1];
                if self.ctx.chain.hard_restitution(c).is_some()
                    || !self.closing(d, v0[c] - v0[c + 1], self.ctx.g[c] - self.ctx.g[c + 1])
                {
                    break;
                }
                hi += 1;
            }
            if hi - lo == 1 && !self.wall_holds(lo, u0[lo], v0[lo]) {
                self.st.free[lo] = Free {
                    t0,
                    u0: u0[lo],
                    v0: v0[lo],
                    g: self.ctx.g[lo],
                };
            } else {
                self.pin_resting_ends(lo, hi, &u0[lo..hi], &v0[lo..hi]);
                self.make_cluster(lo, hi, t0, (&u0[lo..hi], &v0[lo..hi]), None, false);
            }
            lo = hi;
        }
        for c in 0..n.saturating_sub(1) {
            self.schedule_free_pair(c);
        }
        self.schedule_wall(0);
        self.schedule_wall(1);
        let tf = self.ctx.cfg.frame_time(self.st.next_frame);
        self.queue.push(Key::Frame, prio(tf, 0, 0, Key::Frame));
    }

    /// Does a wall hold single bead `i` (contact closed or closing)?
    fn wall_holds(&self, i: usize, u: f64, v: f64) -> bool {
        let mut holds = false;
        if i == 0 {
            if let Some((d, dd, ddd)) = self.wall_state(0, u, v, i) {
                holds |= self.closing(d, dd, ddd);
            }
        }
        if i + 1 == self.ctx.n {
            if let Some((d, dd, ddd)) = self.wall_state(1, u, v, i) {
                holds |= self.closing(d, dd, ddd);
            }
        }
        holds
    }

    /// One step of a cluster, then event detection on its continuous output.
    /// First closing of a cluster's boundary gap `g` over `[t0, tb]`: from the end values alone
    /// where the gap is convex in time (no field, no hard contacts: [`detect`] module docs),
    /// else by sampling.
    pub(super) fn boundary_crossing(
        &self,
        g: impl Fn(f64) -> f64,
        t0: f64,
        tb: f64,
    ) -> Option<f64> {
        if self.ctx.chain.field.is_none() && !self.ctx.chain.has_hard() {
            detect::first_crossing_convex(g, t0, tb)
        } else {
            detect::first_crossing(g, t0, tb)
        }
    }

    /// First closing of `cl`'s boundary gaps over its step `[t0, t1]`, as `(t, contact)`, over
    /// the part of the step where the neighbour's trajectory is known (module docs).
    fn first_boundary_closing(&self, cl: &Cluster, t0: f64, t1: f64) -> Option<(f64, usize)> {
        let (lo, hi) = (cl.data.lo, cl.data.hi);
        let mut earliest: Option<(f64, usize)> = None;
        if lo > 0 {
            let c = lo - 1;
            let tb = t1.min(self.known_until(c));
            let pre = self.pre(c);
            let theta = self.closing_offset(c, t0);
            let g = |t: f64| pre + self.pos(c, t).0 - cl.u_at(t, lo) - theta;
            if let Some(t) = self.boundary_crossing(g, t0, tb) {
                earliest = Some((t, c));
            }
        }
        if hi < self.ctx.n {
            let c = hi - 1;
            let tb = t1.min(self.known_until(hi));
            let pre = self.pre(c);
            let theta = self.closing_offset(c, t0);
            let g = |t: f64| pre + cl.u_at(t, c) - self.pos(hi, t).0 - theta;
            if let Some(t) = self.boundary_crossing(g, t0, tb) {
                if earliest.is_none_or(|(te, _)| t < te) {
                    earliest = Some((t, c));
                }
            }
        }
        earliest
    }

    fn step_cluster(&mut self, slot: ClusterId) -> Result<(), EngineError> {
        let (lo, t0, t1) = self.take_step(slot)?;
        self.count_step()?;
        // Boundary closings over the known part of the step.
        let cl = &self.clusters[slot];
        let earliest = self.first_boundary_closing(cl, t0, t1);
        // Hard walls: the cluster holding an end bead watches the wall gap itself.
        let wall_hit = self.hard_wall_hit(cl, t0, t1);
        let release = self.first_release(cl, t0, t1);
        if let Some((tw, side)) = wall_hit {
            let released_first = release.is_some_and(|(tr, _)| tr <= tw);
            if earliest.is_none_or(|(te, _)| tw < te) && !released_first {
                self.update_peaks(slot, tw);
                self.watch_walls(slot, tw);
                let cl = &mut self.clusters[slot];
                cl.data.pending = Some(cluster::Pending::HardWall { side, t: tw });
                cl.data.t_now = tw;
                self.queue
                    .push(Key::Cluster(slot), prio(tw, 1, lo, Key::Cluster(slot)));
                return Ok(());
            }
        }
        let landing = self.first_landing(cl, t0, t1);
        if let Some((tr, hold)) = release {
            if earliest.is_none_or(|(te, _)| tr < te) && landing.is_none_or(|to| tr <= to) {
                self.defer_release(slot, tr, hold);
                return Ok(());
            }
        }
        if let Some(to) = landing {
            if earliest.is_none_or(|(te, _)| to < te) {
                self.defer_open(slot, to);
                return Ok(());
            }
        }
        let split = earliest.is_none() && self.needs_split(cl);
        let tb = earliest.map_or(t1, |(t, _)| t);
        self.update_peaks(slot, tb);
        self.watch_walls(slot, tb);
        let cl = &mut self.clusters[slot];
        if let Some((t, c)) = earliest {
            cl.data.pending = Some(cluster::Pending::Close {
                contact: c,
                t,
                ver: (self.st.version[c], self.st.version[c + 1]),
            });
            cl.data.t_now = t;
            self.queue
                .push(Key::Cluster(slot), prio(t, 1, c, Key::Cluster(slot)));
        } else if split {
            cl.data.pending = Some(cluster::Pending::Split);
            self.queue
                .push(Key::Cluster(slot), prio(t1, 1, lo, Key::Cluster(slot)));
        } else {
            self.queue
                .push(Key::Cluster(slot), prio(t1, 2, lo, Key::Cluster(slot)));
        }
        Ok(())
    }

    /// One step of the cluster in `slot` from its clock, bounded by the predicted openings and
    /// closings (and marked rough at a kink): `(first bead, t0, t1)`.
    fn take_step(&mut self, slot: ClusterId) -> Result<(usize, f64, f64), EngineError> {
        let until = self.ctx.cfg.until;
        let chain = self.ctx.chain;
        let (bound, rough) = {
            let cl = &self.clusters[slot];
            let bound = self.opening_bound(cl, until);
            let bound = self.closing_bound(cl, bound);
            let h = cl.integ.step_size().min(bound - cl.integ.t());
            (bound, self.rough_step(cl, h))
        };
        let (lo, t0, t1) = {
            let cl = &mut self.clusters[slot];
            let sys = cluster::ClusterSys {
                chain: self.ctx.fall.1.as_ref().unwrap_or(chain),
                lo: cl.data.lo,
                mass: &cl.data.mass,
                pinned: cl.data.pinned,
                rigid: cl.rigid.then(|| &self.st.stuck[cl.data.lo..cl.data.hi - 1]),
            };
            let t0 = cl.data.t_now;
            cl.integ.set_rough(rough);
            let t1 = cl.integ.step(&sys, bound);
            cl.integ.set_rough(crate::integrate::Rough::Smooth);
            let t1 = t1?;
            cl.data.t_now = t1;
            (cl.data.lo, t0, t1)
        };
        Ok((lo, t0, t1))
    }

    /// Energy dissipated by damped contacts up to `t`: the ended integrations plus every live
    /// cluster's integral up to `t` (which its last step covers, as for frames).
    fn dissipated_at(&self, t: f64) -> f64 {
        let mut e = self.st.dissipated;
        if self.ctx.chain.is_dissipative() {
            let diss = &mut *self.ws.diss.borrow_mut();
            for cl in self.clusters.iter() {
                let sys = cl.sys(
                    self.ctx.fall.1.as_ref().unwrap_or(self.ctx.chain),
                    &self.st.stuck,
                );
                let t = t.min(cl.integ.t());
                e += crate::integrate::dissipated_at(&*cl.integ, &sys, t, diss);
            }
        }
        e
    }

    /// Does any contact of the cluster open at its current state (see module docs)?
    fn needs_split(&self, cl: &Cluster) -> bool {
        let z = cl.integ.state();
        let m = cl.m();
        for k in 0..m - 1 {
            let c = cl.data.lo + k;
            let d = self.pre(c) + z[k] - z[k + 1];
            let dd = z[m + k] - z[m + k + 1];
            if d < self.ctx.theta && dd < 0.0 && !self.st.stuck[c] {
                return true;
            }
        }
        if cl.rigid && self.tension(cl).is_some() {
            return true;
        }
        if m == 1 {
            let (u, v) = (
                cl.frame_at(cl.data.t_now) + z[0],
                cl.frame_vel(cl.data.t_now) + z[1],
            );
            return !self.wall_holds(cl.data.lo, u, v);
        }
        self.release_pin(cl).is_some()
    }
}
