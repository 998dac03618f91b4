//! Resting (sticking) hard contacts: rigid groups of free beads.
//!
//! A hard contact (or hard wall) whose collision is plastic (`e = 0`), or whose separating
//! speed `e·w` would be at most `p⁺·t_c` (`p` the relative acceleration pressing the pair
//! together, `t_c` the collapse interval), or that collides again within `t_c` of its previous
//! collision with `e < 1` (inelastic collapse), becomes a **resting contact**: the two sides
//! are joined and move as one rigid body ("group") instead of colliding infinitely often. This
//! is the resting-contact treatment of rigid-body codes, and the limit the TC model of Luding
//! & McNamara (Granular Matter 1, 1998) approximates by chatter.
//!
//! A group is a maximal run of **free** beads joined by stuck hard contacts, plus the walls it
//! is pinned to (then it is held at rest: infinite mass). It moves with one velocity `V` and
//! one acceleration `A = Σ W_i / Σ m_i` (the beads' free flights share `v₀` and `g`, so the gaps
//! inside stay constant and never close again). The contact force inside a group from the
//! field is constant between events: contact `c` carries `F_c = Σ_{i ≤ c} (W_i − m_i A)` (paper
//! eq. 7 with `ü_i = A`). A contact that would carry a tensile force opens. Finding the groups
//! that are consistent (no tension inside, neighbouring groups not accelerating into each other)
//! is the one-dimensional complementarity problem solved exactly by pool-adjacent-violators:
//! the accelerations `W_i/m_i` (weights `m_i`, a pinned wall = acceleration 0 with infinite
//! weight) are pooled until they are non-decreasing from left to right (a left neighbour
//! accelerating at least as fast as its right neighbour stays joined).
//!
//! Collisions between groups use the two-body formula with the groups' masses (momentum exact
//! to rounding).
//!
//! **Inside a cluster.** A group that closes a soft contact joins the cluster whole, and a
//! sticking collision with a bead in a cluster joins the two bodies into one cluster. There the
//! beads joined by resting contacts form a *rigid run*: each gets the run's mean acceleration
//! `Σ m_i a_i / Σ m_i` (internal contact forces cancel; [`super::cluster::rigid_accel`]), so
//! they keep their common velocity. At each step end the force the run's contacts carry is
//! checked ([`Hybrid::tension`]; within a step it is located: [`super::release`]); a resting
//! contact that would be tensile opens, and the
//! cluster splits there. A piece of a split made only of rigid beads becomes a free group again.
//! A cluster's boundary contacts are never stuck ([`Hybrid::unstick_around`]).

use super::cluster::ClusterId;
use super::free::Free;
use super::Hybrid;
use crate::engine::events::EventKind;

/// A rigid group of free beads `lo..hi`, held at rest by the walls in `held`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Group {
    /// First bead.
    pub lo: usize,
    /// One past the last bead.
    pub hi: usize,
    /// Pinned to the left / right wall.
    pub held: [bool; 2],
}

/// One pool of the pool-adjacent-violators pass: beads `lo..hi`, field force, mass, walls.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Pool {
    lo: usize,
    hi: usize,
    force: f64,
    mass: f64,
    wall: [bool; 2],
}

impl Pool {
    /// The pool's acceleration: 0 when held by a wall.
    fn accel(&self) -> f64 {
        if self.wall[0] || self.wall[1] {
            0.0
        } else {
            self.force / self.mass
        }
    }
}

/// Velocities after a collision of bodies of masses `ma`, `mb` (`∞`: held by a wall) at
/// velocities `va`, `vb` with separating speed `sep`: `v_a' = v_cm − sep·m_b/M`,
/// `v_b' = v_cm + sep·m_a/M` (momentum conserved to rounding).
pub(super) fn collide(ma: f64, va: f64, mb: f64, vb: f64, sep: f64) -> (f64, f64) {
    match (ma.is_infinite(), mb.is_infinite()) {
        (true, true) => (va, vb),
        (true, false) => (va, va + sep),
        (false, true) => (vb - sep, vb),
        (false, false) => {
            let mt = ma + mb;
            let vcm = (ma * va + mb * vb) / mt;
            (vcm - sep * mb / mt, vcm + sep * ma / mt)
        }
    }
}

impl Hybrid<'_> {
    /// The rigid group of bead `i`: the beads joined to it by resting contacts (free beads, or
    /// a run inside its cluster: a cluster's boundary contacts are never stuck).
    pub(super) fn group_of(&self, i: usize) -> Group {
        let mut lo = i;
        while lo > 0 && self.st.stuck[lo - 1] {
            lo -= 1;
        }
        let mut hi = i + 1;
        while hi < self.ctx.n && self.st.stuck[hi - 1] {
            hi += 1;
        }
        Group {
            lo,
            hi,
            held: [
                lo == 0 && self.st.pinned[0],
                hi == self.ctx.n && self.st.pinned[1],
            ],
        }
    }

    /// Mass of a group (`∞` when held by a wall).
    pub(super) fn group_mass(&self, g: &Group) -> f64 {
        if g.held[0] || g.held[1] {
            f64::INFINITY
        } else {
            self.ctx.chain.mass[g.lo..g.hi].iter().sum()
        }
    }

    /// Gives every bead of group `g` the velocity `v` at `t` (same accelerations).
    pub(super) fn set_group_velocity(&mut self, g: &Group, t: f64, v: f64) {
        for i in g.lo..g.hi {
            let f = self.st.free[i];
            self.st.free[i] = Free {
                t0: t,
                u0: f.at(t).0,
                v0: v,
                g: f.g,
            };
            self.st.version[i] += 1;
        }
    }

    /// Re-forms the free beads `lo..hi` (joined by stuck contacts; held by the walls in `held`)
    /// at `t` with common velocity `v`: pools them (module docs), sets each pool's free flight,
    /// unsticks the contacts between pools and releases walls no pool holds.
    pub(super) fn form_group(&mut self, lo: usize, hi: usize, held: [bool; 2], t: f64, v: f64) {
        let mut pools = std::mem::take(&mut self.ws.pools);
        pools.clear();
        let push = |pools: &mut Vec<Pool>, p: Pool| {
            pools.push(p);
            while pools.len() >= 2 {
                let (a, b) = (pools[pools.len() - 2], pools[pools.len() - 1]);
                if a.accel() < b.accel() {
                    break;
                }
                pools.pop();
                let top = pools.last_mut().expect("two pools");
                top.hi = b.hi;
                top.force += b.force;
                top.mass += b.mass;
                top.wall = [a.wall[0] || b.wall[0], a.wall[1] || b.wall[1]];
            }
        };
        if held[0] {
            let wall = Pool {
                lo,
                hi: lo,
                wall: [true, false],
                ..Pool::default()
            };
            push(&mut pools, wall);
        }
        for i in lo..hi {
            let m = self.ctx.chain.mass[i];
            let bead = Pool {
                lo: i,
                hi: i + 1,
                force: self.ctx.g[i] * m,
                mass: m,
                wall: [false, false],
            };
            push(&mut pools, bead);
        }
        if held[1] {
            let wall = Pool {
                lo: hi,
                hi,
                wall: [false, true],
                ..Pool::default()
            };
            push(&mut pools, wall);
        }
        if lo == 0 {
            self.st.pinned[0] = pools.first().is_some_and(|p| p.wall[0] && p.hi > p.lo);
        }
        if hi == self.ctx.n {
            self.st.pinned[1] = pools.last().is_some_and(|p| p.wall[1] && p.hi > p.lo);
        }
        for p in &pools {
            let held = p.wall[0] || p.wall[1];
            let (vp, a) = if held { (0.0, 0.0) } else { (v, p.accel()) };
            for i in p.lo..p.hi {
                let u = self.st.free[i].at(t).0;
                self.st.free[i] = Free {
                    t0: t,
                    u0: u,
                    v0: vp,
                    g: a,
                };
                self.st.version[i] += 1;
                if i + 1 < p.hi {
                    self.st.stuck[i] = true;
                }
            }
            if p.hi > p.lo && p.hi < hi {
                self.st.stuck[p.hi - 1] = false;
            }
        }
        self.ws.pools = pools;
    }

    /// Beads `lo..hi` are joining a cluster at `t`: the stuck contacts at its boundary open, and
    /// the free groups next to it are re-formed without those beads.
    pub(super) fn unstick_around(&mut self, lo: usize, hi: usize, t: f64) {
        if lo > 0 && self.st.stuck[lo - 1] {
            self.st.stuck[lo - 1] = false;
            self.regroup(lo - 1, t);
        }
        if hi < self.ctx.n && self.st.stuck[hi - 1] {
            self.st.stuck[hi - 1] = false;
            self.regroup(hi, t);
        }
    }

    /// Re-forms the group of free bead `i` at `t` with its current velocity, and re-predicts its
    /// closings.
    pub(super) fn regroup(&mut self, i: usize, t: f64) {
        let g = self.group_of(i);
        let v = self.st.free[i].at(t).1;
        self.form_group(g.lo, g.hi, g.held, t, v);
        self.after_velocity_change(g.lo, g.hi, t);
    }

    /// A piece of a split cluster made only of beads joined by resting contacts becomes a free
    /// rigid group (states `u`, `v` at `t`; common velocity: the mass-weighted mean).
    pub(super) fn free_rigid_piece(&mut self, lo: usize, hi: usize, t: f64, u: &[f64], v: &[f64]) {
        let mass = &self.ctx.chain.mass[lo..hi];
        let p: f64 = mass.iter().zip(v).map(|(m, x)| m * x).sum();
        let vm = p / mass.iter().sum::<f64>();
        for i in lo..hi {
            self.set_free(i, t, u[i - lo], vm);
        }
        let held = [
            lo == 0 && self.st.pinned[0],
            hi == self.ctx.n && self.st.pinned[1],
        ];
        self.form_group(lo, hi, held, t, vm);
    }

    /// Before a split of cluster `slot` at `t`: releases a pin whose net force points away from
    /// its wall, and opens a resting contact that would carry tension.
    pub(super) fn release_and_unstick(&mut self, slot: ClusterId, t: f64) {
        let cl = &self.clusters[slot];
        let (side, tense) = (
            self.release_pin(cl),
            cl.rigid.then(|| self.tension(cl)).flatten(),
        );
        if let Some(side) = side {
            self.st.pinned[side as usize] = false;
            let i = if side == 0 { 0 } else { self.ctx.n - 1 };
            self.log(t, i, EventKind::WallOpen, 0.0, 0.0);
        }
        if let Some(c) = tense {
            self.st.stuck[c] = false;
        }
    }
}
