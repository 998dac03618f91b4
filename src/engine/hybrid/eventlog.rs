//! The hybrid engine's event log: what is recorded at each event, and how it leaves the engine.
//!
//! **Streaming.** Events go into a small buffer that is handed to the observer
//! ([`crate::engine::Observer::events`]) when it holds [`crate::engine::EVENT_BLOCK`] events and
//! before every frame; the engine keeps only counts by kind. A run's memory therefore does not
//! grow with the number of events. A checkpoint stores the buffer (the events not yet handed
//! over), so a resumed run hands over the same blocks at the same points as an uninterrupted one.
//!
//! **Times.** A closing is logged at the located crossing of the threshold `θ` (see the
//! [parent module](super)). An opening — of a contact between beads or of a lone bead from its
//! soft wall — is acted on at the end of the cluster step in which it happened, but logged at the
//! moment the overlap crossed `θ` downwards, located on the step's continuous output with the
//! same sampling + Illinois search as closings ([`super::detect::first_crossing`]). The
//! soft-wall contact of an end bead inside a cluster of several beads changes no cluster; its
//! crossings of `θ` are logged when the queue reaches them ([`super::walllog`]), so on each wall
//! `wall_close` and `wall_open` alternate.
//!
//! **Slow closings.** A closing whose relative speed is within
//! [`crate::engine::SLOW_CLOSING_FACTOR`] of the closing beads' absolute velocity tolerance
//! `atol·V` is counted ([`crate::engine::RunOutcome::slow_closings`]): whether it happens is
//! decided at the tolerance level. Under a loose `--atol` the beads a solitary wave
//! leaves behind, whose true separation speeds are super-exponentially small, re-collide with
//! their own velocity errors (1000-bead striker, rtol 3e-5, atol 3e-7: 1668 closings instead
//! of 998, the 670 extra ones at 4e-7 … 1e-5 where the wave's own closings are at ~1e-4; 632 of
//! them are counted); the count lets `run` say so instead of returning those collisions
//! silently.
//!
//! **Shallow collisions.** A contact closes when its overlap reaches `θ` and opens when it falls
//! below `θ`: the force below `θ` is not applied, which is `(θ/δ_max)ⁿ` of a collision's
//! energy, and a collision whose peak overlap is below `θ` is not seen at all (the beads fly
//! through each other up to `θ` and are then merged, past their true peak) or is cut at once.
//! Exact two-body contacts close at their onset and do not depend on `θ`; the integrated ones
//! whose two-body peak estimate is below `θ·rtol^{−1/n}` (more than `rtol` lost; free beads
//! closing, a free bead onto a soft wall, an exact pair handed over) at a speed that matters
//! at the tolerance are counted ([`crate::engine::RunOutcome::shallow_closings`]) and `run`
//! says so. None on the presets at rtol 1e-8 and 1e-10; their number grows as `rtol` loosens
//! (`θ ∝ rtol`, module docs of [`super`]).
//!
//! **Peak overlaps.** The largest overlap a contact (or a soft wall contact) reaches while
//! closed is taken from the continuous output of every accepted cluster step: the overlap
//! `δ(t)` has an interior maximum on the step `[t₀, t₁]` exactly when `δ̇ = v_i − v_{i+1}` goes
//! from positive to negative; that root of `δ̇` (also in the continuous output) is refined by
//! Illinois iterations ([`super::detect::step_max`]) and `δ` is evaluated there. Only contacts
//! whose `δ̇` changes sign within the step are refined; the others contribute `δ(t₁)`. At a
//! maximum `δ̇ = 0`, so an error ε in the located time changes the peak only by `O(ε²)`: the
//! peak is as accurate as the continuous output itself. For a two-body collision with the
//! power law `a δⁿ` (paper eq. 6) it equals the energy bound `a δ_maxⁿ = ½ μ w²`.

use super::cluster::ClusterId;
use super::detect::{step_max, step_max_from};
use super::Hybrid;
use crate::engine::events::{EventKind, EventRecord};
use crate::engine::{EngineError, Observer};
use crate::model::Wall;

impl Hybrid<'_> {
    /// The soft wall at `side` (0 left, 1 right), if there is one.
    pub(super) fn soft_wall(&self, side: u8) -> Option<&Wall> {
        let w = if side == 0 {
            self.ctx.chain.left_wall.as_ref()
        } else {
            self.ctx.chain.right_wall.as_ref()
        };
        w.filter(|w| w.restitution.is_none())
    }

    /// Raises the peak overlaps of the cluster's contacts (and of a soft wall it holds) to their
    /// maxima over its last step, up to `tb` (the step end, or an earlier time it is parked at).
    pub(super) fn update_peaks(&mut self, slot: ClusterId, tb: f64) {
        let chain = self.ctx.chain;
        let cl = &self.clusters[slot];
        let ta = cl.integ.t_prev();
        let tb = tb.min(cl.integ.t()).max(ta);
        let m = cl.m();
        // Where the step's end states are arrays, the end-point values step_max reads are taken
        // from them (the same numbers), and the continuous output is read only to refine an
        // interior maximum.
        let ends = if tb == cl.integ.t() {
            cl.integ.end_states()
        } else {
            None
        };
        for k in 0..m - 1 {
            let c = cl.data.lo + k;
            let pre = chain.precompression.as_ref().map_or(0.0, |p| p[c]);
            let d = |t: f64| pre + cl.w_at(t, c) - cl.w_at(t, c + 1);
            let dd = |t: f64| cl.integ.dense_at(t, m + k) - cl.integ.dense_at(t, m + k + 1);
            let p = match (ends, cl.integ.exact_pair()) {
                (_, Some(pair)) => pair.peak_over(ta, tb),
                (Some((z0, z1)), None) => {
                    let end = pre + z1[k] - z1[k + 1];
                    let (sa, sb) = (z0[m + k] - z0[m + k + 1], z1[m + k] - z1[m + k + 1]);
                    step_max_from(end, sa, sb, d, dd, ta, tb)
                }
                (None, None) => step_max(d, dd, ta, tb),
            };
            self.ws.peak_before[c] = self.st.peak[c];
            if p > self.st.peak[c] {
                self.st.peak[c] = p;
            }
        }
        for side in [0u8, 1] {
            let i = if side == 0 { 0 } else { self.ctx.n - 1 };
            if i < cl.data.lo || i >= cl.data.hi {
                continue;
            }
            let w = if side == 0 {
                chain.left_wall.as_ref()
            } else {
                chain.right_wall.as_ref()
            };
            let Some(w) = w.filter(|w| w.restitution.is_none()) else {
                continue;
            };
            let s = if side == 0 { -1.0 } else { 1.0 };
            let d = |t: f64| w.precompression + s * cl.u_at(t, i);
            let dd = |t: f64| s * cl.v_at(t, i);
            // a cluster that holds a wall and is exact is a lone bead's exact wall contact
            let p = match cl.integ.exact_pair() {
                Some(pair) => pair.peak_over(ta, tb),
                None => step_max(d, dd, ta, tb),
            };
            let k = self.ctx.n - 1 + side as usize;
            if p > self.st.peak[k] {
                self.st.peak[k] = p;
            }
        }
    }

    /// Appends an event to the buffer and counts it.
    pub(super) fn log(&mut self, t: f64, contact: usize, kind: EventKind, rel: f64, peak: f64) {
        self.st.counts.add(kind);
        self.st.events.push(EventRecord {
            t,
            contact: contact as u64,
            kind,
            rel_velocity: rel,
            peak_overlap: peak,
        });
    }

    /// Counts a closing at relative speed `rel` of the beads `beads` in
    /// [`crate::engine::hybrid::saved::HybridData::slow_closings`] when it is below
    /// [`crate::engine::SLOW_CLOSING_FACTOR`] times their absolute velocity tolerance `atol·V_i`
    /// (the larger of the beads').
    pub(super) fn count_slow_closing(&mut self, rel: f64, beads: &[usize]) {
        if self.tolerance_level(rel, beads) {
            self.st.slow_closings += 1;
        }
    }

    /// Is the relative speed `rel` of beads `beads` at the tolerance level: below
    /// [`crate::engine::SLOW_CLOSING_FACTOR`] times their absolute velocity tolerance `atol·V_i`
    /// (the larger of the beads')?
    pub(super) fn tolerance_level(&self, rel: f64, beads: &[usize]) -> bool {
        let tol = &self.ctx.tol;
        let vtol = beads
            .iter()
            .map(|&i| tol.atol * tol.scales.bead_velocity(self.ctx.chain.mass[i]))
            .fold(0.0, f64::max);
        rel.abs() < crate::engine::SLOW_CLOSING_FACTOR * vtol
    }

    /// Counts a collision of beads `beads` through the law `(n, a)` closing at speed `w`
    /// (reduced mass `mu`, the bead's mass at a wall) under a relative static load `load`
    /// (force) in [`crate::engine::hybrid::saved::HybridData::shallow_closings`] when it is
    /// shallow ([`Self::shallow`]) by its two-body peak overlap
    /// `max((μw²/2a)^{1/n}, (load/(n a))^{1/(n−1)})`.
    pub(super) fn count_shallow(
        &mut self,
        (mu, w, load): (f64, f64, f64),
        (n, a): (f64, f64),
        beads: &[usize],
    ) {
        let kinetic = (mu * w * w / (2.0 * a)).powf(1.0 / n);
        let resting = if n > 1.0 {
            (load.abs() / (n * a)).powf(1.0 / (n - 1.0))
        } else {
            0.0
        };
        if self.shallow(kinetic.max(resting), n, w, beads) {
            self.st.shallow_closings += 1;
        }
    }

    /// Is a collision (exponent `n`) of beads `beads` at speed `w` whose peak overlap is `peak`
    /// shallow: its peak below `θ·rtol^{−1/n}`, where the force neglected below the threshold
    /// `θ` is more than `rtol` of its energy and impulse (`(θ/δ_max)ⁿ`; a peak below `θ` is
    /// missed entirely), while its speed matters at the tolerance (`w ≥ rtol·V_i`, the beads'
    /// velocity scale)?
    pub(super) fn shallow(&self, peak: f64, n: f64, w: f64, beads: &[usize]) -> bool {
        let tol = &self.ctx.tol;
        let vtol = (beads.iter())
            .map(|&i| tol.rtol * tol.scales.bead_velocity(self.ctx.chain.mass[i]))
            .fold(0.0, f64::max);
        peak * tol.rtol.powf(1.0 / n) < self.ctx.theta && w.abs() >= vtol
    }

    /// Hands the buffered events to the observer and empties the buffer (keeping its capacity).
    pub(super) fn flush_events(&mut self, obs: &mut dyn Observer) -> Result<(), EngineError> {
        if !self.st.events.is_empty() {
            obs.events(&self.st.events)?;
            self.st.events.clear();
        }
        Ok(())
    }
}
