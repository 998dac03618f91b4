//! Gas observables of a run: the collision rate from the event log, the kinetic temperature per
//! frame and a coarse velocity distribution (issue 33, `beadchain analyze`). Pure functions of
//! the masses, the frames and the event log; every quantity is in the snapshot's (computer)
//! units.
//!
//! - **Collision rate**: `R = C / (t_last − t_first)`, with `C` the number of bead–bead
//!   collisions in the event log between the first and the last frame (`t_first ≤ t ≤ t_last`):
//!   one `close` event (a gap closes, a soft contact starts) or one `hard_collision` event per
//!   collision. Wall collisions (`wall_close`) are counted apart. Per bead: `R / N`. Per frame
//!   interval `(t_{k−1}, t_k]`: its own count over its length. The dense engine logs no events,
//!   so its runs have no rate ([`CollisionRate::logged`]).
//! - **Kinetic temperature** (one dimension, `k_B = 1`): `T_kin = (1/N) Σ_i m_i (v_i − v̄)²`,
//!   `v̄ = Σ m_i v_i / Σ m_i` the centre-of-mass velocity, so `T_kin` is twice the kinetic energy
//!   per bead in the centre-of-mass frame: an energy (computer units; `E·m0/β²` in J for a
//!   physical scene, paper eq. 10).
//! - **Velocity distribution** of one frame, every bead counted once (not mass-weighted): mean
//!   `μ`, standard deviation `σ = sqrt(mean((v − μ)²))`, excess kurtosis
//!   `mean((v − μ)⁴)/σ⁴ − 3` (0 for a Gaussian, −1.2 for a uniform distribution) and the counts
//!   in the 8 bins with edges `μ + kσ`, `k = −3 … 3` (the outer bins open-ended).

use crate::engine::events::{EventKind, EventRecord};

/// Bins of [`VelocityStats::histogram`]: edges at `μ + kσ` for `k = −3 … 3`, open outer bins.
pub const HISTOGRAM_BINS: usize = 8;

/// Collisions counted in an event log over the span of the frames.
#[derive(Clone, Debug, PartialEq)]
pub struct CollisionRate {
    /// Whether the run logged events at all (the hybrid engine does, the dense one does not).
    pub logged: bool,
    /// Bead–bead collisions (`close` and `hard_collision` events) in `[t_first, t_last]`.
    pub pair: u64,
    /// Wall collisions (`wall_close` events) in `[t_first, t_last]`.
    pub wall: u64,
    /// `t_first` and `t_last`.
    pub span: (f64, f64),
    /// `pair / (t_last − t_first)`; `None` when the span is empty or nothing is logged.
    pub rate: Option<f64>,
    /// `rate / N`.
    pub per_bead: Option<f64>,
}

/// Whether an event is a bead–bead collision.
pub fn is_pair_collision(kind: EventKind) -> bool {
    matches!(kind, EventKind::Close | EventKind::HardCollision)
}

/// Counts the collisions of `events` between `t_first` and `t_last` (`n` beads, `logged`:
/// whether the engine logs events).
pub fn collision_rate(
    events: &[EventRecord],
    (t_first, t_last): (f64, f64),
    n: usize,
    logged: bool,
) -> CollisionRate {
    let inside = |e: &&EventRecord| e.t >= t_first && e.t <= t_last;
    let pair = events
        .iter()
        .filter(inside)
        .filter(|e| is_pair_collision(e.kind))
        .count() as u64;
    let wall = events
        .iter()
        .filter(inside)
        .filter(|e| e.kind == EventKind::WallClose)
        .count() as u64;
    let span = t_last - t_first;
    let rate = (logged && span > 0.0).then(|| pair as f64 / span);
    CollisionRate {
        logged,
        pair,
        wall,
        span: (t_first, t_last),
        rate,
        per_bead: rate.map(|r| r / n as f64),
    }
}

/// Bead–bead collisions in each frame interval `(t_{k−1}, t_k]` (the first entry, for the first
/// frame, counts those at `t ≤ t_0`). `times` must be increasing.
pub fn collisions_per_frame(events: &[EventRecord], times: &[f64]) -> Vec<u64> {
    let mut counts = vec![0u64; times.len()];
    for e in events.iter().filter(|e| is_pair_collision(e.kind)) {
        // First frame at or after the event: the interval it falls in.
        let k = times.partition_point(|&t| t < e.t);
        if let Some(c) = counts.get_mut(k) {
            *c += 1;
        }
    }
    counts
}

/// The kinetic temperature `T_kin = (1/N) Σ m_i (v_i − v̄)²` (module docs).
pub fn kinetic_temperature(mass: &[f64], v: &[f64]) -> f64 {
    let m_total: f64 = mass.iter().sum();
    let p: f64 = mass.iter().zip(v).map(|(m, x)| m * x).sum();
    let vbar = p / m_total;
    let s: f64 = mass
        .iter()
        .zip(v)
        .map(|(m, x)| m * (x - vbar) * (x - vbar))
        .sum();
    s / v.len() as f64
}

/// A frame's velocity distribution (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct VelocityStats {
    /// Mean velocity (every bead counted once).
    pub mean: f64,
    /// Standard deviation (population, `1/N`).
    pub std: f64,
    /// Excess kurtosis; `None` when `σ = 0`.
    pub excess_kurtosis: Option<f64>,
    /// Beads per bin, edges `μ + kσ`, `k = −3 … 3` (all in one bin when `σ = 0`).
    pub histogram: [u64; HISTOGRAM_BINS],
}

/// The velocity distribution of one frame.
pub fn velocity_stats(v: &[f64]) -> VelocityStats {
    let n = v.len() as f64;
    let mean = v.iter().sum::<f64>() / n;
    let m2 = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n;
    let m4 = v.iter().map(|x| (x - mean).powi(4)).sum::<f64>() / n;
    let std = m2.sqrt();
    let mut histogram = [0u64; HISTOGRAM_BINS];
    for x in v {
        let bin = if std > 0.0 {
            let z = ((x - mean) / std).floor() + 4.0;
            z.clamp(0.0, (HISTOGRAM_BINS - 1) as f64) as usize
        } else {
            HISTOGRAM_BINS / 2
        };
        histogram[bin] += 1;
    }
    VelocityStats {
        mean,
        std,
        excess_kurtosis: (m2 > 0.0).then(|| m4 / (m2 * m2) - 3.0),
        histogram,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(t: f64, kind: EventKind) -> EventRecord {
        EventRecord {
            t,
            contact: 0,
            kind,
            rel_velocity: 1.0,
            peak_overlap: 0.0,
        }
    }

    #[test]
    fn counts_collisions_by_kind_and_interval() {
        let log = [
            ev(0.5, EventKind::Close),
            ev(0.7, EventKind::Open),
            ev(1.0, EventKind::HardCollision),
            ev(1.5, EventKind::WallClose),
            ev(2.5, EventKind::Close),
        ];
        let r = collision_rate(&log, (0.0, 2.0), 4, true);
        assert_eq!((r.pair, r.wall), (2, 1));
        assert_eq!(r.rate, Some(1.0));
        assert_eq!(r.per_bead, Some(0.25));
        assert_eq!(
            collisions_per_frame(&log, &[0.0, 1.0, 2.0, 3.0]),
            [0, 2, 0, 1]
        );
        assert_eq!(collision_rate(&[], (0.0, 2.0), 4, false).rate, None);
    }

    #[test]
    fn temperature_and_distribution_exact() {
        // v̄ = (1·1 + 3·(−1))/4 = −0.5; T = (1·1.5² + 3·0.5²)/2 = 1.5
        assert_eq!(kinetic_temperature(&[1.0, 3.0], &[1.0, -1.0]), 1.5);
        let s = velocity_stats(&[-1.0, 1.0, -1.0, 1.0]);
        assert_eq!((s.mean, s.std, s.excess_kurtosis), (0.0, 1.0, Some(-2.0)));
        // z = −1 falls in [μ − σ, μ) (bin 3), z = +1 in [μ + σ, μ + 2σ) (bin 5)
        assert_eq!(s.histogram, [0, 0, 0, 2, 0, 2, 0, 0]);
        assert_eq!(velocity_stats(&[2.0; 3]).histogram[4], 3);
    }
}
