//! Steps at the kinks of the contact forces: landing on a soft wall's kink inside a cluster, and
//! measuring the steps that start or end at a kink as rough.
//!
//! A contact force `n a δ₊^{n−1}` (paper eq. 6) has a kink at `δ = 0`: for `1 < n < 3` its
//! second time derivative is infinite there, and the trajectory is smooth on either side only.
//! An explicit Runge–Kutta step across it loses its order, and an error estimate built for smooth
//! solutions no longer measures the step (Hairer, Nørsett & Wanner, *Solving ODEs I*, Sec. II.6:
//! locate the discontinuity and restart there). The hybrid engine keeps bead–bead kinks out of
//! its steps by the contact threshold (a gap closes at `δ = θ`, opens by a step landed at `θ/2`;
//! [`super`] module docs). Two cases were left:
//!
//! 1. **A soft wall inside a cluster.** The end bead of a cluster of several beads keeps its wall
//!    force in the cluster's right-hand side, and the wall's overlap `δ_w` crossed zero inside a
//!    step. Now an accepted explicit step across it is redone to end on the crossing
//!    ([`first_landing`]: located on the continuous output like an opening, a sign change
//!    within `MIN_FRACTION` of the step start being the kink the step started on), and the
//!    cluster goes on from there. Implicit (Radau IIA) steps are not landed: their estimate
//!    sees the kink, and a landing on a linear dashpot's jump there stalled them.
//!    Two beads between soft walls (n_w = 2.84, rtol 1e-10): a step of `h = 0.064` across the
//!    right wall's kink was accepted and lost 8·10⁻⁸ of the energy; landed, 7·10⁻⁹.
//! 2. **Steps that start or end at a kink.** Landing leaves the kink at a step's end (an
//!    opening at `θ/2`, a wall's kink) or start (a merge at `θ`, the step after a wall's kink).
//!    DOP853's combined estimate `err = e5²/√(e5² + 0.01·e3²)` trusts the 8th-order solution to
//!    be `e5/(0.1·e3)` times better than the 5th-order one, which holds on smooth solutions only:
//!    a lone bead's step onto its wall opening (n_w = 3.01, rtol 1e-10) was accepted with
//!    `e5 = 229` and `e3 = 6·10⁵` tolerances (`err` 0.87) and lost 10⁻⁸ of the energy. Such a
//!    step is now measured as rough ([`Integrator::set_rough`]: `max(err, e5)`) where the kink
//!    matters at the tolerance ([`Hybrid::rough_step`], [`Hybrid::rough_at`]): a soft contact
//!    or wall at its kink where the step starts (`|δ| ≤ max(θ, MIN_FRACTION·|δ̇|·h)`) or carried
//!    to within `θ` of it by the step (the quadratic `δ + δ̇τ + δ̈τ²/2`), whose force over the
//!    step, `∫₀ʰ n a (|δ̇|τ)^{n−1} dτ = a |δ̇|^{n−1} hⁿ` at the rate `|δ̇|` it crosses with,
//!    changes a bead's velocity by more than its error weight. The kinks behind a solitary wave
//!    do not (the 1000-bead striker opens and closes its contacts at `|δ̇| ≈ 10⁻⁷`), so such
//!    scenes take the steps they took; colliding beads do.
//!
//! 3. **The clip of a damped force.** A dissipative law's force `F_el + F_d` is clipped at 0
//!    ([`crate::model::law`]: no tensile force), a kink of the force while the beads (or a bead
//!    and a soft wall) still overlap. An accepted explicit step across it is redone to end on
//!    it ([`first_landing`], located like a wall's kink). A linear dashpot collision (two
//!    beads, rtol 1e-12) crossed it in one step that DOP853 accepted and left its velocities
//!    9·10⁻¹⁰ off (942·rtol); landed, within a few rtol. A bead leaving a damped soft wall was
//!    84·rtol off at rtol 1e-12 (216·rtol for two beads) until walls' clips were landed on too.
//!
//! [`first_landing`]: Hybrid::first_landing
//! [`Integrator::set_rough`]: crate::integrate::Integrator::set_rough

use super::cluster::Cluster;
use super::Hybrid;
use crate::integrate::Rough;

/// Where a force has its kink.
#[derive(Clone, Copy)]
enum Kink {
    /// Soft contact `c` (between beads `c` and `c + 1`).
    Contact(usize),
    /// The soft wall at this side (0 left, 1 right).
    Wall(u8),
}

/// Smallest located wall kink after the step start, as a fraction of the step: one closer to
/// the start is the kink the step started on (landed there to rounding). Likewise a kink within
/// this fraction of a step's length (`MIN_FRACTION·|δ̇|·h` in overlap) of its start is one the
/// step starts on ([`Hybrid::rough_at`]).
const MIN_FRACTION: f64 = 1e-3;

impl Hybrid<'_> {
    /// Earliest time in `(t0, t1)` the last step of `cl` must be redone to end at: a located
    /// opening ([`Self::first_opening`]) or a soft wall's kink ([`Self::first_wall_kink`]).
    pub(super) fn first_landing(&self, cl: &Cluster, t0: f64, t1: f64) -> Option<f64> {
        [
            self.first_opening(cl, t0, t1),
            self.first_wall_kink(cl, t0, t1),
            self.first_clip(cl, t0, t1),
        ]
        .into_iter()
        .flatten()
        .reduce(f64::min)
    }

    /// Earliest time `t_k ∈ (t0, t1)` where the damped force of a contact or soft wall of `cl`
    /// that overlaps at both ends of its last step `[t0, t1]` crosses its clip at 0 (module
    /// docs, case 3): `F_el + F_d` changes sign between the step's ends. `None` for
    /// conservative chains, implicit steps (as [`Self::first_wall_kink`]) and crossings within
    /// `MIN_FRACTION` of the step after its start (the clip the step started on).
    fn first_clip(&self, cl: &Cluster, t0: f64, t1: f64) -> Option<f64> {
        let chain = self.ctx.chain;
        if !chain.is_dissipative() || t1 <= t0 || cl.integ.rate().is_none() {
            return None;
        }
        let mut first: Option<f64> = None;
        let mut seek = |force: &dyn Fn(f64) -> Option<f64>| {
            let (Some(f0), Some(f1)) = (force(t0), force(t1)) else {
                return; // not overlapping at an end: an opening or a closing, landed on as such
            };
            if (f0 > 0.0) == (f1 > 0.0) {
                return;
            }
            let dir = if f0 > 0.0 { -1.0 } else { 1.0 };
            let g = |t: f64| force(t).map_or(-1.0, |f| dir * f);
            if let Some(t) = super::detect::first_crossing(g, t0, first.unwrap_or(t1)) {
                if t - t0 > MIN_FRACTION * (t1 - t0) && t < t1 {
                    first = Some(t);
                }
            }
        };
        for c in cl.data.lo..cl.data.hi - 1 {
            if self.st.stuck[c] || chain.hard_restitution(c).is_some() {
                continue;
            }
            let pre = self.pre(c);
            seek(&|t: f64| {
                let delta = pre + cl.w_at(t, c) - cl.w_at(t, c + 1);
                chain.unclipped_force(c, delta, cl.v_at(t, c) - cl.v_at(t, c + 1))
            });
        }
        for side in self.soft_walls_of(cl) {
            let Some((pre, s)) = self.wall_frame(side) else {
                continue;
            };
            let i = self.end_bead(side);
            seek(&|t: f64| {
                chain.unclipped_wall_force(side, pre + s * cl.u_at(t, i), s * cl.v_at(t, i))
            });
        }
        first
    }

    /// Earliest time `t_k ∈ (t0, t1)` where the overlap of a soft wall that `cl` holds changes
    /// sign over its last step `[t0, t1]` (module docs, case 1). `None` where no wall overlap
    /// changes sign, or only within `MIN_FRACTION` of the step after its start, and for
    /// implicit steps (Radau IIA, which holds no `f(z)`): their error estimate sees the kink,
    /// and one landed on a wall force that jumps there (a linear dashpot's `c·δ̇_w`) made the
    /// next Radau IIA steps start on the jump and shrink to rounding (two beads in a damped
    /// box, rtol 1e-12: step size 2e-14 at t = 25.8; it integrated across before).
    fn first_wall_kink(&self, cl: &Cluster, t0: f64, t1: f64) -> Option<f64> {
        if t1 <= t0 || cl.integ.rate().is_none() {
            return None;
        }
        let mut first: Option<f64> = None;
        for side in self.soft_walls_of(cl) {
            let Some((pre, s)) = self.wall_frame(side) else {
                continue;
            };
            let i = self.end_bead(side);
            let delta = |t: f64| pre + s * cl.u_at(t, i);
            // the sign change sought: rising above 0 from an open start, falling below from a
            // closed one
            let dir = if delta(t0) > 0.0 { -1.0 } else { 1.0 };
            let g = |t: f64| dir * delta(t);
            let Some(t) = super::detect::first_crossing(g, t0, first.unwrap_or(t1)) else {
                continue;
            };
            if t - t0 > MIN_FRACTION * (t1 - t0) && t < t1 {
                first = Some(t);
            }
        }
        first
    }

    /// How the next step of `cl`, of length `h` from its integrator's time `t`, meets a kink
    /// (module docs, case 2): [`Rough::Onset`] of the smallest exponent among the soft
    /// contacts or walls at their kink at `t` that are closing (`δ̇ > 0`: a merge's new
    /// contact, whose force sets in over the step); [`Rough::Kink`] where one is at its kink
    /// otherwise ([`Self::rough_at`]), or the quadratic `δ + δ̇τ + δ̈τ²/2` (from the state and the
    /// `f(z)` the method holds) carries one from `δ > θ` to within `θ` of its kink within the
    /// step (a step bounded by a predicted opening), at the rate `|δ̇ + δ̈τ|` it arrives with;
    /// each only where the kink matters at the tolerance.
    pub(super) fn rough_step(&self, cl: &Cluster, h: f64) -> Rough {
        if h.is_nan() || h <= 0.0 {
            return Rough::Smooth;
        }
        let t = cl.integ.t();
        let (m, z) = (cl.m(), cl.integ.state());
        let f = cl.integ.rate();
        let theta = self.ctx.theta;
        // (δ, δ̇, δ̈) at t → the rate at the kink and whether the force sets in at the step
        // start, where the step starts or ends at one
        let at_kink = |d: f64, dd: f64, ddd: Option<f64>| -> Option<(f64, bool)> {
            if d.abs() <= theta.max(MIN_FRACTION * dd.abs() * h) {
                return Some((dd.abs(), dd > 0.0));
            }
            let ddd = ddd?;
            // cheap filter first: not closing in on θ within the step
            if d <= theta || dd >= 0.0 || (d + h * dd > theta && ddd >= 0.0) {
                return None;
            }
            let tau = super::opening::reaches(d - theta, dd, ddd);
            (tau <= h).then(|| ((dd + ddd * tau).abs(), false))
        };
        let mut rough = Rough::Smooth;
        for (kink, law, beads) in self.soft_kinks(cl) {
            let (d, dd, ddd) = match kink {
                Kink::Contact(c) => {
                    let k = c - cl.data.lo;
                    let ddd = f.map(|f| f[m + k] - f[m + k + 1]);
                    (self.pre(c) + z[k] - z[k + 1], z[m + k] - z[m + k + 1], ddd)
                }
                Kink::Wall(side) => {
                    let (pre, s) = self.wall_frame(side).expect("a soft wall");
                    let i = beads[0];
                    let ddd = f.map(|f| s * f[m + i - cl.data.lo]);
                    (pre + s * cl.u_at(t, i), s * cl.v_at(t, i), ddd)
                }
            };
            let Some((rate, onset)) = at_kink(d, dd, ddd) else {
                continue;
            };
            if !self.kink_matters(cl, t, rate, law, h, beads) {
                continue;
            }
            rough = match rough {
                Rough::Onset(n) if onset => Rough::Onset(n.min(law.0)),
                Rough::Onset(n) => Rough::Onset(n),
                _ if onset => Rough::Onset(law.0),
                _ => Rough::Kink,
            };
        }
        rough
    }

    /// Is a soft contact or wall of `cl` at its kink at `t` (the start of a step of length `h`,
    /// or the end of a redone one): `|δ| ≤ max(θ, MIN_FRACTION·|δ̇|·h)` (a merge at `θ`, an
    /// opening landed at `θ/2`, a wall's kink landed on to the redone step's error), with a
    /// force over `h` that matters ([`Self::kink_matters`] at the rate `|δ̇|`)?
    pub(super) fn rough_at(&self, cl: &Cluster, t: f64, h: f64) -> bool {
        if h.is_nan() || h <= 0.0 {
            return false;
        }
        let Some((z0, z1)) = cl.integ.end_states() else {
            return false; // no continuous output to read (and no rough steps: Radau IIA)
        };
        let (m, theta) = (cl.m(), self.ctx.theta);
        self.soft_kinks(cl).any(|(c, law, beads)| {
            let (d, dd) = match c {
                Kink::Contact(c) => {
                    // cheap filter: the overlap at neither end of the step near the kink, and
                    // not changing sign (a graze inside the step is not sought)
                    let (k, pre) = (c - cl.data.lo, self.pre(c));
                    let (d0, d1) = (pre + z0[k] - z0[k + 1], pre + z1[k] - z1[k + 1]);
                    let r = (z0[m + k] - z0[m + k + 1])
                        .abs()
                        .max((z1[m + k] - z1[m + k + 1]).abs());
                    let margin = theta.max(MIN_FRACTION * r * h);
                    if d0.min(d1) > margin || d0.max(d1) < -margin {
                        return false;
                    }
                    (
                        pre + cl.w_at(t, c) - cl.w_at(t, c + 1),
                        cl.v_at(t, c) - cl.v_at(t, c + 1),
                    )
                }
                Kink::Wall(side) => {
                    let (pre, s) = self.wall_frame(side).expect("a soft wall");
                    (pre + s * cl.u_at(t, beads[0]), s * cl.v_at(t, beads[0]))
                }
            };
            let near = d.abs() <= theta.max(MIN_FRACTION * dd.abs() * h);
            near && self.kink_matters(cl, t, dd.abs(), law, h, beads)
        })
    }

    /// The soft kinks of `cl`: its soft contacts that are not stuck and the soft walls it
    /// holds, each with its law `(n, a)` and its two beads (a wall's bead twice).
    fn soft_kinks<'s>(
        &'s self,
        cl: &'s Cluster,
    ) -> impl Iterator<Item = (Kink, (f64, f64), [usize; 2])> + 's {
        let contacts = (cl.data.lo..cl.data.hi - 1)
            .filter(|&c| !self.st.stuck[c] && self.ctx.chain.hard_restitution(c).is_none())
            .map(|c| {
                let law = (self.ctx.chain.exponent[c], self.ctx.chain.prefactor[c]);
                (Kink::Contact(c), law, [c, c + 1])
            });
        let walls = self.soft_walls_of(cl).filter_map(|side| {
            let w = self.soft_wall(side)?;
            let i = self.end_bead(side);
            Some((Kink::Wall(side), (w.exponent, w.prefactor), [i, i]))
        });
        contacts.chain(walls)
    }

    /// Does a kink crossed at `rate` by a contact of law `(n, a)` between `beads` matter over a
    /// step `h`: is the force `n a (rate·τ)^{n−1}` over it, `a·rate^{n−1}·hⁿ`, a velocity change
    /// of a bead above its error weight at `t`?
    fn kink_matters(
        &self,
        cl: &Cluster,
        t: f64,
        rate: f64,
        (n, a): (f64, f64),
        h: f64,
        beads: [usize; 2],
    ) -> bool {
        let impulse = a * h * (rate * h).powf(n - 1.0);
        let tol = &self.ctx.tol;
        beads.into_iter().any(|i| {
            let mi = self.ctx.chain.mass[i];
            // the velocity relative to the chain's free fall, as the cluster's weights take it
            let v = cl.v_at(t, i) - cl.frame_g * t;
            let weight = tol.atol * tol.scales.bead_velocity(mi) + tol.rtol * v.abs();
            impulse / mi > weight
        })
    }
}
