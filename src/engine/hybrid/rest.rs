//! Clusters at rest ([`crate::integrate::rest`]): a new cluster whose beads are all at rest in
//! its frame and whose net forces balance to round-off is not integrated.
//!
//! The test, per bead `i` of the cluster (paper eq. 7 with `u̇ = 0`): `|m_i a_i| ≤ 16 ε R_i`,
//! where `a_i` is the acceleration the cluster's system computes (contacts, soft walls,
//! field; pinned beads 0) and `R_i` bounds the round-off of that sum: the magnitudes of the
//! forces on the bead (`F_c` of its contacts and soft wall, `|W_i|` of the field) plus, for
//! each of its contacts, the stiffness times the magnitude of the displacements that make its
//! overlap (`K_c (|Δ_c| + |u_i| + |u_j|)`: the overlap's own rounding). A state that passes
//! is an equilibrium as far as the chain's floating-point forces can tell; the exact motion
//! from it is an oscillation at that round-off. Resting hard contacts (a rigid run) are
//! excluded: their constraint forces are not in `a_i`.
//!
//! At the start of a run (and after `set_velocities`) an end bead of a new cluster that rests on
//! its **hard** wall (touching it, at rest, pressed into it by its cluster) is pinned there at
//! once ([`super::stick`]), as the collision at zero speed that would follow pins it; so a column
//! on a hard wall is at rest from the start too, instead of being integrated until that
//! collision and left with the other beads at round-off speeds.

use super::cluster::ClusterSys;
use super::Hybrid;
use crate::integrate::System;
use crate::model::contact_force_stiffness;

/// Multiple of the machine epsilon in the round-off bound `R_i` (module docs).
const REST_ULPS: f64 = 16.0;

impl Hybrid<'_> {
    /// Pins the end beads of the new cluster of beads `lo..hi` (initial state `u`, `v`) that
    /// rest on their hard walls (module docs).
    pub(super) fn pin_resting_ends(&mut self, lo: usize, hi: usize, u: &[f64], v: &[f64]) {
        for side in [0u8, 1] {
            let (k, s, held) = if side == 0 {
                (0, -1.0, lo == 0)
            } else {
                (hi - 1 - lo, 1.0, hi == self.ctx.n)
            };
            let wall = if side == 0 {
                &self.ctx.chain.left_wall
            } else {
                &self.ctx.chain.right_wall
            };
            let Some(w) = wall.as_ref().filter(|w| w.restitution.is_some()) else {
                continue;
            };
            // touching (overlap `Δ_w + s·u`, zero at rest on the wall) and at rest
            if !held || v[k] != 0.0 || w.precompression + s * u[k] < 0.0 {
                continue;
            }
            let mut acc = vec![0.0; hi - lo];
            self.ctx.chain.accel_v(lo, u, v, &mut acc);
            if s * acc[k] > 0.0 {
                self.st.pinned[side as usize] = true;
            }
        }
    }

    /// Whether the new cluster of beads `lo..hi`, with frame state `(ws.bu, ws.bv)[..m]` and
    /// integrator masses `mass`, is at rest (module docs).
    pub(super) fn at_rest(&self, lo: usize, mass: &[f64], pinned: [bool; 2], rigid: bool) -> bool {
        let m = mass.len();
        let (u, v) = (&self.ws.bu[..m], &self.ws.bv[..m]);
        if rigid || v.iter().any(|&v| v != 0.0) {
            return false;
        }
        let chain = self.ctx.fall.1.as_ref().unwrap_or(self.ctx.chain);
        let sys = ClusterSys {
            chain,
            lo,
            mass,
            pinned,
            rigid: None,
        };
        let mut acc = vec![0.0; m];
        sys.accel(u, v, &mut acc);
        let mut bound: Vec<f64> = (0..m)
            .map(|i| chain.field.as_ref().map_or(0.0, |w| w[lo + i].abs()))
            .collect();
        for k in 0..m.saturating_sub(1) {
            let c = lo + k;
            let pre = chain.precompression.as_ref().map_or(0.0, |d| d[c]);
            let delta = chain.overlap(c, u[k], u[k + 1]);
            let (f, stiff) = contact_force_stiffness(chain.exponent[c], chain.prefactor[c], delta);
            let r = f.abs() + stiff.abs() * (pre.abs() + u[k].abs() + u[k + 1].abs());
            bound[k] += r;
            bound[k + 1] += r;
        }
        for side in [0u8, 1] {
            let i = if side == 0 { 0 } else { m - 1 };
            let held = if side == 0 {
                lo == 0
            } else {
                lo + m == self.ctx.n
            };
            if let (true, Some((pre, s))) = (held, self.wall_frame(side)) {
                let w = self.soft_wall(side).expect("a wall frame is a soft wall's");
                let (f, stiff) = contact_force_stiffness(w.exponent, w.prefactor, pre + s * u[i]);
                bound[i] += f.abs() + stiff.abs() * (pre.abs() + u[i].abs());
            }
        }
        (0..m).all(|i| {
            let m_i = self.ctx.chain.mass[lo + i];
            (m_i * acc[i]).abs() <= REST_ULPS * f64::EPSILON * bound[i]
        })
    }
}
