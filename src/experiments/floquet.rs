//! Floquet multipliers of a breather ([`super::breather`]): the eigenvalues of the monodromy
//! matrix `M = ∂P_T/∂(u, v)` of the period map, by central differences (4N engine runs).
//!
//! For the conservative chain `M` is symplectic: `det M = 1`, the multipliers come in reciprocal
//! pairs `λ, 1/λ` (with their conjugates), and `M ẋ(0) = ẋ(0)` for the flow direction
//! `ẋ(0) = (v(0), M⁻¹F(u(0)))` (the time shift). The time shift and the energy direction make a
//! pair at 1 (a 2 × 2 Jordan block: a perturbation `ε` of `M` splits it by `~√ε`, while the
//! pair's mean and product move by `O(ε)`). The breather is linearly stable when every
//! multiplier has `|λ| ≤ 1 + tol` (on the unit circle).

use super::breather::{max_diff, Breather, BreatherError, Shooter};

/// The monodromy matrix and its multipliers.
#[derive(Clone, Debug)]
pub struct Floquet {
    /// The 2N × 2N monodromy matrix, row-major over the state `(u, v)`.
    pub monodromy: Vec<Vec<f64>>,
    /// Multipliers `(re, im)`, sorted by decreasing modulus.
    pub multipliers: Vec<(f64, f64)>,
    /// Indices (into `multipliers`) of the two multipliers nearest 1: the time-shift pair.
    pub unit_pair: [usize; 2],
    /// `max |M ẋ(0) − ẋ(0)| / max |ẋ(0)|`: the flow direction (time shift) is the right
    /// eigenvector at 1.
    pub flow_residual: f64,
    /// `max |∇Hᵀ M − ∇Hᵀ| / max |∇H|` at `x(0)`: the energy's gradient is the left eigenvector
    /// at 1 (`H(P_T(x)) = H(x)` differentiated at the fixed point; `∇H = (−m a, m v)`, `v = 0`).
    pub energy_residual: f64,
}

impl Floquet {
    /// The largest modulus of the multipliers other than the pair at 1.
    pub fn max_modulus(&self) -> f64 {
        (0..self.multipliers.len())
            .filter(|k| !self.unit_pair.contains(k))
            .map(|k| modulus(self.multipliers[k]))
            .fold(0.0, f64::max)
    }

    /// Linearly stable: every multiplier but the pair at 1 within `tol` of the unit circle.
    pub fn stable(&self, tol: f64) -> bool {
        self.max_modulus() <= 1.0 + tol
    }

    /// `max_k min_j |λ_k λ_j − 1|`: how far the multipliers are from reciprocal pairs (each
    /// `λ_k` with its partner `1/λ_k` among the others).
    pub fn reciprocity_error(&self) -> f64 {
        let m = &self.multipliers;
        (0..m.len())
            .map(|k| {
                (0..m.len())
                    .filter(|&j| j != k)
                    .map(|j| {
                        let p = mul(m[k], m[j]);
                        modulus((p.0 - 1.0, p.1))
                    })
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    }

    /// The pair at 1: `|mean − 1|` and `|product − 1|` of its two multipliers.
    pub fn unit_pair_error(&self) -> (f64, f64) {
        let (a, b) = (
            self.multipliers[self.unit_pair[0]],
            self.multipliers[self.unit_pair[1]],
        );
        let mean = ((a.0 + b.0) / 2.0 - 1.0, (a.1 + b.1) / 2.0);
        let p = mul(a, b);
        (modulus(mean), modulus((p.0 - 1.0, p.1)))
    }
}

fn modulus(z: (f64, f64)) -> f64 {
    z.0.hypot(z.1)
}

fn mul(a: (f64, f64), b: (f64, f64)) -> (f64, f64) {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}

/// The period map of the full state `x = (u, v)`.
fn period_map(sh: &Shooter, x: &[f64], t: f64) -> Result<Vec<f64>, BreatherError> {
    let nb = sh.len();
    let (u, v) = sh.flow(&x[..nb], &x[nb..], t)?;
    Ok(u.into_iter().chain(v).collect())
}

/// The Floquet multipliers of breather `b`: the monodromy by central differences (steps
/// `h` times the amplitude for displacements, `h ω` times it for velocities).
pub fn floquet(sh: &Shooter, b: &Breather, h: f64) -> Result<Floquet, BreatherError> {
    let nb = sh.len();
    let x0: Vec<f64> = b.u.iter().copied().chain(vec![0.0; nb]).collect();
    let amp = sh.amplitude(&b.u).max(1e-12);
    let mut mono = vec![vec![0.0; 2 * nb]; 2 * nb];
    for j in 0..2 * nb {
        let hj = if j < nb {
            h * amp
        } else {
            h * amp * b.frequency()
        };
        let (mut xp, mut xm) = (x0.clone(), x0.clone());
        xp[j] += hj;
        xm[j] -= hj;
        let (fp, fm) = (
            period_map(sh, &xp, b.period)?,
            period_map(sh, &xm, b.period)?,
        );
        for i in 0..2 * nb {
            mono[i][j] = (fp[i] - fm[i]) / (2.0 * hj);
        }
    }
    let m = faer::Mat::<f64>::from_fn(2 * nb, 2 * nb, |i, j| mono[i][j]);
    let ev = m
        .eigenvalues()
        .map_err(|e| BreatherError(format!("monodromy eigenvalues: {e:?}")))?;
    let mut mult: Vec<(f64, f64)> = ev.iter().map(|z| (z.re, z.im)).collect();
    mult.sort_by(|a, b| modulus(*b).total_cmp(&modulus(*a)));
    let mut by_dist: Vec<usize> = (0..mult.len()).collect();
    by_dist.sort_by(|&i, &j| {
        modulus((mult[i].0 - 1.0, mult[i].1)).total_cmp(&modulus((mult[j].0 - 1.0, mult[j].1)))
    });
    let (flow_residual, energy_residual) = unit_vector_residuals(sh, b, &mono);
    Ok(Floquet {
        monodromy: mono,
        multipliers: mult,
        unit_pair: [by_dist[0], by_dist[1]],
        flow_residual,
        energy_residual,
    })
}

/// The residuals of the pair at 1's two vectors: `max |M ẋ − ẋ| / max |ẋ|` (right, the time
/// shift) and `max |∇Hᵀ M − ∇Hᵀ| / max |∇H|` (left, the energy), at `x(0) = (u, 0)`:
/// `ẋ = (0, a)`, `∇H = (−m a, 0)`, with the chain's accelerations `a(u)` (paper eq. 7).
fn unit_vector_residuals(sh: &Shooter, b: &Breather, mono: &[Vec<f64>]) -> (f64, f64) {
    let nb = sh.len();
    let zero = vec![0.0; nb];
    let acc = sh.accel(&b.u);
    let xdot: Vec<f64> = zero.iter().chain(&acc).copied().collect();
    let mx: Vec<f64> = mono
        .iter()
        .map(|row| row.iter().zip(&xdot).map(|(a, b)| a * b).sum())
        .collect();
    let grad: Vec<f64> = (acc.iter().zip(sh.masses()).map(|(a, m)| -m * a))
        .chain(zero.iter().copied())
        .collect();
    let gm: Vec<f64> = (0..2 * nb)
        .map(|j| grad.iter().zip(mono).map(|(g, row)| g * row[j]).sum())
        .collect();
    let max_abs = |x: &[f64]| x.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    (
        max_diff(&mx, &xdot) / max_abs(&xdot),
        max_diff(&gm, &grad) / max_abs(&grad),
    )
}
