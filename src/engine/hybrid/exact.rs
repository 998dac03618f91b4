//! Exact two-body contacts ([`crate::integrate::exact_pair`]) in the hybrid engine.
//!
//! A cluster of two beads whose contact is a conservative power law (no damping, not hard, not
//! a resting contact), with no wall at either bead and a field that accelerates both alike (and
//! their neighbours alike too), is resolved in closed form instead of integrated: one step covers the whole contact, whatever
//! the tolerance, and the event log's peak overlap and opening time are the profile's. A third
//! body reaching the pair during the contact is found on the pair's exact continuous output
//! like any closing (the pair's edge beads have monotone velocities, so their boundary gaps stay
//! convex in time, [`super::detect`]), and the merge reads the pair's exact state at that moment:
//! the merged cluster is integrated from there ("hand-over").
//!
//! A **lone bead against a soft wall** takes the same path, the wall being a body of infinite
//! mass ([`PairLaw::wall`]): a conservative power-law wall (not hard, no damping in the scene),
//! no field on the bead (the wall does not fall with it) nor on its neighbour, and no second
//! wall the bead touches.
//!
//! A neighbour that the field accelerates otherwise than the pair (a `[field] force` on some
//! beads only) has a gap to the pair that is not convex in time: it could graze the pair
//! between the samples of the pair's one step and be missed (a 3-bead chain with a force on
//! bead 2 only: bead 0's final velocity 0 instead of −8.0652e-4, at any rtol). Such pairs are
//! integrated.
//! A neighbour reaching the bead during the contact is found on the exact output (the bead's
//! velocity is monotone while the wall pushes it) and handed over like a pair's third body.

use super::Hybrid;
use crate::integrate::exact_pair::{ExactPair, PairLaw};
use crate::integrate::Integrator;
use crate::model::profile::Profile;
use std::sync::Arc;

impl Hybrid<'_> {
    /// The law of contact `c` when the two beads `c`, `c + 1` alone may take the exact path
    /// (module docs); `None` otherwise.
    pub(super) fn exact_law(&self, c: usize) -> Option<PairLaw> {
        let chain = self.ctx.chain;
        let walls = (c == 0 && chain.left_wall.is_some())
            || (c + 2 == self.ctx.n && chain.right_wall.is_some());
        if walls
            || chain.hard_restitution(c).is_some()
            || chain.is_dissipative()
            || self.st.stuck[c]
        {
            return None;
        }
        let (n, a) = (chain.exponent[c], chain.prefactor[c]);
        if !(n > 1.0 && n.is_finite() && a > 0.0 && a.is_finite()) {
            return None;
        }
        // the field of the integrated chain (less the free fall), per unit mass
        let sys = self.ctx.fall.1.as_ref().unwrap_or(chain);
        let accel = |i: usize| sys.field.as_ref().map_or(0.0, |w| w[i] / sys.mass[i]);
        let g = accel(c);
        // the neighbours too: a third body that the field accelerates otherwise than the pair
        // can graze it between the samples of the pair's one step (its gap is not convex)
        let alike = [c.wrapping_sub(1), c, c + 1, c + 2]
            .into_iter()
            .filter(|&i| i < self.ctx.n)
            .all(|i| accel(i) == g);
        alike.then_some(PairLaw {
            mass: [chain.mass[c], chain.mass[c + 1]],
            n,
            a,
            pre: self.pre(c),
            accel: g,
            wall: None,
        })
    }

    /// The law of the soft wall that lone bead `i` touches when it may take the exact path
    /// (module docs); `None` otherwise.
    pub(super) fn exact_wall_law(&self, i: usize) -> Option<PairLaw> {
        let chain = self.ctx.chain;
        // the walls (soft or hard) at bead i: exactly one, and soft
        let left = i == 0 && chain.left_wall.is_some();
        let right = i + 1 == self.ctx.n && chain.right_wall.is_some();
        let side = match (left, right) {
            (true, false) => 0,
            (false, true) => 1,
            _ => return None,
        };
        let w = self.soft_wall(side)?;
        // no field on the bead nor on its neighbour (whose gap to the bead would not be convex:
        // a graze between the samples of the one step would be missed)
        let neighbour = if side == 0 { i + 1 } else { i.wrapping_sub(1) };
        let field = (chain.field.as_ref())
            .is_some_and(|f| f[i] != 0.0 || f.get(neighbour).is_some_and(|&x| x != 0.0));
        let (n, a) = (w.exponent, w.prefactor);
        if chain.is_dissipative()
            || field
            || !(n > 1.0 && n.is_finite() && a > 0.0 && a.is_finite())
        {
            return None;
        }
        let (pre, s) = self.wall_frame(side)?;
        Some(PairLaw {
            mass: [chain.mass[i], f64::INFINITY],
            n,
            a,
            pre,
            accel: 0.0,
            wall: Some(s),
        })
    }

    /// An exact pair for `law` (its exponent's profile computed once per run; a removed pair's
    /// allocation reused where there is one).
    pub(super) fn exact_pair(&mut self, law: PairLaw, from_flight: bool) -> Box<dyn Integrator> {
        let profile = self
            .ws
            .profiles
            .entry(law.n.to_bits())
            .or_insert_with(|| Arc::new(Profile::new(law.n)))
            .clone();
        match self.ws.spare_pairs.pop() {
            Some(mut pair) => {
                if let Some(p) = pair.exact_pair_mut() {
                    p.renew(law, profile, from_flight);
                }
                pair
            }
            None => Box::new(ExactPair::new(law, profile, from_flight)),
        }
    }
}
