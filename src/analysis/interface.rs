//! Interfaces and impurities: reflected/transmitted energy and peak-velocity ratios.
//!
//! - [`energy_split`]: at interface bead `k` (the paper's bead 50: contact `k−1` has `n₁`,
//!   contact `k` has `n₂`), the energy left of the interface, beads `0..k` and contacts
//!   `0..k−1`, and right of it, beads `k..N` and contacts `k..N−1`; the straddling contact `k−1`
//!   (beads `k−1`, `k`) counts half to each side; a soft wall's contact energy counts on its
//!   side, and a field's potential energy `−W_i u_i` on bead `i`'s, so the two sides sum to
//!   the chain's total energy (they left out walls and fields: on `dimer_dispersion` the two
//!   walls' 0.0094 of 0.19). Once the reflected and transmitted pulses have
//!   separated (no force across contact `k−1`, nothing crossing the interface any more) this is
//!   the paper's `E_refl` and `E_trans` (Sec. 3.2, Fig. 7), up to the small energy left in beads
//!   that rest near the interface.
//! - [`velocity_ratio`]: `|v_out/v_in|` of Sec. 5.1 / Fig. 18: `v_in` the largest forward
//!   velocity and `v_out` the largest backward velocity of the beads `lo..k−margin` over all
//!   frames (the striker region `< lo` is excluded: the striker itself moves faster than the
//!   solitary wave it makes).

use super::wave::range_energy;
use crate::model::{contact_potential, Chain};

/// Energy left and right of an interface bead.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergySplit {
    /// Energy of beads `0..k` (and their contacts; half of the straddling one).
    pub left: f64,
    /// Energy of beads `k..N` (and their contacts; half of the straddling one).
    pub right: f64,
}

impl EnergySplit {
    /// `left + right`: the chain's total energy ([`Chain::energy`], to rounding).
    pub fn total(&self) -> f64 {
        self.left + self.right
    }
}

/// Energy split at interface bead `k` (`1 ≤ k ≤ N−1`; other values are clamped).
pub fn energy_split(chain: &Chain, u: &[f64], v: &[f64], k: usize) -> EnergySplit {
    let n = v.len();
    let k = k.clamp(1, n.saturating_sub(1).max(1));
    let c = k - 1;
    let straddle = contact_potential(
        chain.exponent[c],
        chain.prefactor[c],
        chain.overlap(c, u[c], u[c + 1]),
    );
    let (left_wall, right_wall) = chain.wall_energies(u);
    EnergySplit {
        left: range_energy(chain, u, v, 0, k)
            + 0.5 * straddle
            + left_wall
            + chain.field_energy(u, 0, k),
        right: range_energy(chain, u, v, k, n)
            + 0.5 * straddle
            + right_wall
            + chain.field_energy(u, k, n),
    }
}

/// Incoming and reflected peak velocities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VelocityRatio {
    /// Largest forward velocity in the window (the incoming wave's peak).
    pub v_in: f64,
    /// Largest backward speed in the window (the reflected wave's peak, as a positive number).
    pub v_out: f64,
}

impl VelocityRatio {
    /// `|v_out / v_in|` (NaN when `v_in = 0`).
    pub fn ratio(&self) -> f64 {
        (self.v_out / self.v_in).abs()
    }
}

/// Peak velocities of the beads `lo..k−margin` over the given frames (velocity profiles).
pub fn velocity_ratio<'a, I>(frames: I, k: usize, lo: usize, margin: usize) -> VelocityRatio
where
    I: IntoIterator<Item = &'a [f64]>,
{
    let mut r = VelocityRatio {
        v_in: 0.0,
        v_out: 0.0,
    };
    for v in frames {
        let hi = k.saturating_sub(margin).min(v.len());
        for &x in v.get(lo..hi).unwrap_or(&[]) {
            r.v_in = r.v_in.max(x);
            r.v_out = r.v_out.max(-x);
        }
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::wave::tests::chain;

    #[test]
    fn split_exact() {
        let c = chain(4, 2.0);
        // contacts: c0 = 0 (open), c1 = 0.2 (straddles k = 2) -> 0.04, c2 = 0.1 -> 0.01
        let u = [0.0, 0.2, 0.0, -0.1];
        let v = [-1.0, 0.0, 2.0, 1.0];
        let s = energy_split(&c, &u, &v, 2);
        // left: 0.5 + 0.02; right: 2 + 0.5 + 0.01 + 0.02 (abs 1e-14)
        assert!((s.left - 0.52).abs() < 1e-14, "{s:?}");
        assert!((s.right - 2.53).abs() < 1e-14, "{s:?}");
        assert!((s.total() - c.energy(&u, &v)).abs() < 1e-14);
    }

    /// The defect: the split left out the walls' contact energy and the field's potential
    /// energy, so `left + right` was not the total that `analyze` calls it a fraction of.
    #[test]
    fn split_counts_walls_and_the_field_on_their_sides() {
        let mut c = chain(4, 2.0);
        let wall = |p: f64| crate::model::Wall {
            exponent: 2.0,
            prefactor: 1.0,
            precompression: p,
            restitution: None,
        };
        // left wall overlap 0.1 − u0 = 0.3 -> 0.09; right wall 0.05 + u3 = 0.15 -> 0.0225
        (c.left_wall, c.right_wall) = (Some(wall(0.1)), Some(wall(0.05)));
        c.field = Some(vec![-1.0, -2.0, -3.0, -4.0]);
        let u = [-0.2, 0.0, 0.0, 0.1];
        let v = [1.0, 0.0, 0.0, 0.0];
        let s = energy_split(&c, &u, &v, 2);
        // left: 0.5 kinetic + 0.09 wall + field −(−1)(−0.2) = −0.2 (contact 0 open: u0 − u1 < 0)
        // right: 0.0225 wall + field −(−4)(0.1) = 0.4 (abs 1e-14)
        assert!((s.left - (0.5 + 0.09 - 0.2)).abs() < 1e-14, "{s:?}");
        assert!((s.right - (0.0225 + 0.4)).abs() < 1e-14, "{s:?}");
        assert!((s.total() - c.energy(&u, &v)).abs() < 1e-14, "{s:?}");
    }

    #[test]
    fn ratio_from_frames() {
        let f1 = vec![5.0, 0.0, 1.0, 0.2, 0.0, 0.0]; // striker (excluded) and incoming peak 1.0
        let f2 = vec![0.0, -0.3, 0.0, 0.0, 0.0, 9.0]; // reflected -0.3; bead 5 is past k
        let r = velocity_ratio([f1.as_slice(), f2.as_slice()], 5, 1, 1);
        assert_eq!(r.v_in, 1.0);
        assert_eq!(r.v_out, 0.3);
        assert!((r.ratio() - 0.3).abs() < 1e-15);
        // empty window
        let r = velocity_ratio([f1.as_slice()], 1, 3, 0);
        assert_eq!((r.v_in, r.v_out), (0.0, 0.0));
    }
}
