//! Energies and momentum of a chain state: kinetic `½ Σ m_i v_i²`, the contact potential of
//! the paper's eq. 1 (`V = a δⁿ` per contact and soft wall), the field potential `−Σ W_i u_i`,
//! and the gross energy scale that energy errors are relative to.

use super::{contact_potential, Chain, Wall};

impl Chain {
    /// Potential energy stored in the contacts (and walls) of the whole chain, plus the field
    /// potential `−Σ W_i u_i`.
    pub fn potential_energy(&self, u: &[f64]) -> f64 {
        let mut e = 0.0;
        for c in 0..self.len() - 1 {
            e += contact_potential(
                self.exponent[c],
                self.prefactor[c],
                self.overlap(c, u[c], u[c + 1]),
            );
        }
        // two additions, in this order: the energies' bits are those of every earlier build
        let (left, right) = self.wall_energies(u);
        e += left;
        e += right;
        if let Some(f) = &self.field {
            e -= f.iter().zip(u).map(|(w, x)| w * x).sum::<f64>();
        }
        e
    }

    /// The potential energies of the soft left and right walls' contacts (0 without one).
    pub fn wall_energies(&self, u: &[f64]) -> (f64, f64) {
        let energy = |w: &Option<Wall>, overlap: &dyn Fn(f64) -> f64| match w {
            Some(w) if w.restitution.is_none() => {
                contact_potential(w.exponent, w.prefactor, overlap(w.precompression))
            }
            _ => 0.0,
        };
        let last = u[self.len() - 1];
        (
            energy(&self.left_wall, &|p| p - u[0]),
            energy(&self.right_wall, &|p| p + last),
        )
    }

    /// The field's potential energy `−Σ W_i u_i` of the beads `lo..hi` (0 without a field).
    pub fn field_energy(&self, u: &[f64], lo: usize, hi: usize) -> f64 {
        self.field.as_ref().map_or(0.0, |f| {
            -f[lo..hi]
                .iter()
                .zip(&u[lo..hi])
                .map(|(w, x)| w * x)
                .sum::<f64>()
        })
    }

    /// Kinetic energy `½ Σ m_i v_i²`.
    pub fn kinetic_energy(&self, v: &[f64]) -> f64 {
        0.5 * self.mass.iter().zip(v).map(|(m, x)| m * x * x).sum::<f64>()
    }

    /// Total energy (kinetic + contact + wall + field potential).
    pub fn energy(&self, u: &[f64], v: &[f64]) -> f64 {
        self.kinetic_energy(v) + self.potential_energy(u)
    }

    /// Gross energy `KE + contact/wall PE + |Σ W_i u_i|`: every part counted positive, so it is
    /// a meaningful scale for energy errors even when the total energy is 0 (a chain at rest
    /// under a field: the field potential and the contact/kinetic energies cancel).
    pub fn energy_scale(&self, u: &[f64], v: &[f64]) -> f64 {
        let field = self
            .field
            .as_ref()
            .map_or(0.0, |f| f.iter().zip(u).map(|(w, x)| w * x).sum::<f64>());
        // potential_energy() subtracts the field part: add it back, then count it positive.
        self.kinetic_energy(v) + (self.potential_energy(u) + field) + field.abs()
    }

    /// Total momentum `Σ m_i v_i`.
    pub fn momentum(&self, v: &[f64]) -> f64 {
        self.mass.iter().zip(v).map(|(m, x)| m * x).sum()
    }
}
