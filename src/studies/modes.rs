//! Linear modes of a chain about a state `u*` (issue 35, part 3a).
//!
//! Linearising the equation of motion (paper eq. 7) about `u*` gives `M ü = −K (u − u*)` with
//! the symmetric tridiagonal stiffness matrix
//!
//! ```text
//! K_ii = k_{i−1,i} + k_{i,i+1} (+ k_L for i = 0, + k_R for i = N−1),   K_{i,i+1} = −k_{i,i+1},
//! k = dF/dδ = n (n−1) a δ^{n−2}  for δ > 0,   k = 0 for δ ≤ 0 (open contact: sonic vacuum),
//! ```
//!
//! where `δ` is the contact's overlap at `u*` (eq. 6) and `k_L`, `k_R` are the soft walls'
//! stiffnesses from their own law (a wall is a fixed body: the end is held by a spring). A chain
//! end without a wall is free. The modes `u = x cos ωt` solve `K x = ω² M x`, i.e. the symmetric
//! tridiagonal problem `A y = ω² y` with `A = M^{−1/2} K M^{−1/2}` and `y = M^{1/2} x`, solved
//! with faer's self-adjoint eigensolver ([`solve`]). [`sturm_count`] and
//! [`bisection_eigenvalues`] are an independent solver of the same problem (Sturm sequences of
//! the `LDLᵀ` pivots), used to count modes in a window and in the tests.
//!
//! The participation ratio of a mode with displacements `x` is
//! `P = (Σ x_i²)² / (N Σ x_i⁴)`: about 2/3 for an extended (sine) mode, `1/N` for a mode on one
//! bead (localisation in disordered chains).

use super::StudyError;
use crate::model::{contact_force_stiffness, Chain, Wall};

/// The boundary condition at one chain end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum End {
    /// No wall: a free end.
    Free,
    /// A soft wall: the end bead is held by a spring of this stiffness (0 when the wall's
    /// contact is open at the state: then the end is free).
    Wall {
        /// `n (n−1) a δ^{n−2}` of the wall contact.
        stiffness: f64,
    },
    /// A hard wall (unilateral, rigid): no linear stiffness; the end is treated as free.
    HardWall,
}

impl End {
    /// The wall stiffness added to the end bead's diagonal (0 for a free or hard end).
    pub fn stiffness(&self) -> f64 {
        match self {
            End::Wall { stiffness } => *stiffness,
            _ => 0.0,
        }
    }

    /// "fixed (soft wall, k = …)", "free", … for the output.
    pub fn describe(&self) -> String {
        match self {
            End::Free => "free (no wall)".to_string(),
            End::Wall { stiffness } if *stiffness > 0.0 => {
                format!("fixed through the soft wall's stiffness k = {stiffness:.6e}")
            }
            End::Wall { .. } => "free (the wall's contact is open: zero stiffness)".to_string(),
            End::HardWall => "free (hard wall: unilateral, no linear stiffness)".to_string(),
        }
    }
}

/// The chain linearised about a state: masses, contact stiffnesses and end conditions.
#[derive(Clone, Debug, PartialEq)]
pub struct Linearized {
    /// Bead masses `m_i` (N).
    pub mass: Vec<f64>,
    /// Contact overlaps `δ` at the state (N−1).
    pub overlap: Vec<f64>,
    /// Contact stiffnesses `k = n (n−1) a δ^{n−2}`, 0 for `δ ≤ 0` (N−1).
    pub stiffness: Vec<f64>,
    /// Left and right end conditions.
    pub ends: [End; 2],
}

/// The wall's end condition at overlap `delta`.
fn wall_end(w: Option<&Wall>, delta: impl Fn(&Wall) -> f64) -> End {
    match w {
        None => End::Free,
        Some(w) if w.restitution.is_some() => End::HardWall,
        Some(w) => End::Wall {
            stiffness: contact_force_stiffness(w.exponent, w.prefactor, delta(w)).1,
        },
    }
}

/// Linearises `chain` about displacements `u` (N values).
pub fn linearize(chain: &Chain, u: &[f64]) -> Result<Linearized, StudyError> {
    let nb = chain.len();
    if u.len() != nb {
        return Err(StudyError::new(format!(
            "expected {nb} displacements, got {}",
            u.len()
        )));
    }
    let mut overlap = Vec::with_capacity(nb - 1);
    let mut stiffness = Vec::with_capacity(nb - 1);
    for c in 0..nb - 1 {
        let d = chain.overlap(c, u[c], u[c + 1]);
        if chain.hard_restitution(c).is_some() && d >= 0.0 {
            return Err(StudyError::new(format!(
                "contact {c} (beads {c}-{}) is a closed hard contact: rigid, it has no linear stiffness",
                c + 1
            )));
        }
        overlap.push(d);
        let (n, a) = (chain.exponent[c], chain.prefactor[c]);
        stiffness.push(contact_force_stiffness(n, a, d).1);
    }
    let ends = [
        wall_end(chain.left_wall.as_ref(), |w| w.precompression - u[0]),
        wall_end(chain.right_wall.as_ref(), |w| w.precompression + u[nb - 1]),
    ];
    Ok(Linearized {
        mass: chain.mass.clone(),
        overlap,
        stiffness,
        ends,
    })
}

impl Linearized {
    /// Contacts with zero stiffness (open or just touching: sonic vacuum).
    pub fn open_contacts(&self) -> Vec<usize> {
        (0..self.stiffness.len())
            .filter(|&c| self.stiffness[c] == 0.0)
            .collect()
    }

    /// Diagonal (N) and off-diagonal (N−1) of `A = M^{−1/2} K M^{−1/2}`.
    pub fn tridiagonal(&self) -> (Vec<f64>, Vec<f64>) {
        let nb = self.mass.len();
        let mut d = vec![0.0; nb];
        let mut e = vec![0.0; nb - 1];
        for (c, &k) in self.stiffness.iter().enumerate() {
            d[c] += k;
            d[c + 1] += k;
            e[c] = -k / (self.mass[c] * self.mass[c + 1]).sqrt();
        }
        d[0] += self.ends[0].stiffness();
        d[nb - 1] += self.ends[1].stiffness();
        for (di, m) in d.iter_mut().zip(&self.mass) {
            *di /= m;
        }
        (d, e)
    }
}

/// Modes of a linearised chain, in increasing frequency.
#[derive(Clone, Debug, PartialEq)]
pub struct Modes {
    /// Index of each mode among all N modes (0 = lowest).
    pub index: Vec<usize>,
    /// Eigenvalues `ω²` (round-off may leave a zero mode slightly negative).
    pub omega2: Vec<f64>,
    /// Angular frequencies `ω = √max(ω², 0)`.
    pub omega: Vec<f64>,
    /// Mode shapes: displacements `x` (N each), `xᵀ M x = 1`, largest `|x_i|` positive.
    pub shapes: Vec<Vec<f64>>,
    /// Participation ratio `(Σ x_i²)² / (N Σ x_i⁴)` of each mode.
    pub participation: Vec<f64>,
    /// The largest `|ω²|` of all N modes, inside a window or not: the scale of "zero modes"
    /// (a window must not change which modes count as zero).
    pub omega2_max: f64,
}

/// Participation ratio `(Σ x_i²)² / (N Σ x_i⁴)` of displacements `x`.
pub fn participation_ratio(x: &[f64]) -> f64 {
    let s2: f64 = x.iter().map(|v| v * v).sum();
    let s4: f64 = x.iter().map(|v| v.powi(4)).sum();
    s2 * s2 / (x.len() as f64 * s4)
}

/// Every mode, or those with `ω` in the window `[lo, hi]`, by faer's dense self-adjoint
/// eigensolver on `A` (O(N³): a few seconds at N = 2000).
pub fn solve(lin: &Linearized, window: Option<(f64, f64)>) -> Result<Modes, StudyError> {
    let (d, e) = lin.tridiagonal();
    let nb = d.len();
    let mut a = faer::Mat::<f64>::zeros(nb, nb);
    for i in 0..nb {
        a[(i, i)] = d[i];
        if i + 1 < nb {
            a[(i + 1, i)] = e[i];
            a[(i, i + 1)] = e[i];
        }
    }
    let evd = a
        .self_adjoint_eigen(faer::Side::Lower)
        .map_err(|err| StudyError::new(format!("eigensolver failed: {err:?}")))?;
    let s = evd.S().column_vector();
    let vecs = evd.U();
    let mut modes = Modes {
        index: Vec::new(),
        omega2: Vec::new(),
        omega: Vec::new(),
        shapes: Vec::new(),
        participation: Vec::new(),
        omega2_max: (0..nb).fold(0.0f64, |t, j| t.max(s[j].abs())),
    };
    for j in 0..nb {
        let w2 = s[j];
        let w = w2.max(0.0).sqrt();
        if let Some((lo, hi)) = window {
            if w < lo || w > hi {
                continue;
            }
        }
        let mut x: Vec<f64> = (0..nb).map(|i| vecs[(i, j)] / lin.mass[i].sqrt()).collect();
        let big = x
            .iter()
            .fold(0.0f64, |b, v| if v.abs() > b.abs() { *v } else { b });
        if big < 0.0 {
            x.iter_mut().for_each(|v| *v = -*v);
        }
        modes.index.push(j);
        modes.omega2.push(w2);
        modes.omega.push(w);
        modes.participation.push(participation_ratio(&x));
        modes.shapes.push(x);
    }
    Ok(modes)
}

/// Number of eigenvalues of the symmetric tridiagonal matrix (diagonal `d`, off-diagonal `e`)
/// below `lambda`: the negative pivots of `T − λ I = L D Lᵀ` (Sylvester's law of inertia).
pub fn sturm_count(d: &[f64], e: &[f64], lambda: f64) -> usize {
    let scale = d
        .iter()
        .chain(e)
        .fold(f64::MIN_POSITIVE, |s, x| s.max(x.abs()));
    let tiny = f64::EPSILON * scale;
    let mut count = 0;
    let mut q = 1.0;
    for i in 0..d.len() {
        let off = if i == 0 { 0.0 } else { e[i - 1] * e[i - 1] / q };
        q = d[i] - lambda - off;
        if q == 0.0 {
            q = -tiny;
        }
        if q < 0.0 {
            count += 1;
        }
    }
    count
}

/// Every eigenvalue of the symmetric tridiagonal matrix by bisection on [`sturm_count`]
/// (increasing; each to a few ulps of the spectral radius). O(N²·60): for tests and
/// small chains.
pub fn bisection_eigenvalues(d: &[f64], e: &[f64]) -> Vec<f64> {
    let n = d.len();
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for i in 0..n {
        let r = if i > 0 { e[i - 1].abs() } else { 0.0 } + if i + 1 < n { e[i].abs() } else { 0.0 };
        lo = lo.min(d[i] - r);
        hi = hi.max(d[i] + r);
    }
    let span = hi - lo;
    (0..n)
        .map(|j| {
            // Smallest λ with more than j eigenvalues below: the (j+1)-th eigenvalue.
            let (mut a, mut b) = (lo - span * 1e-3 - 1e-300, hi + span * 1e-3 + 1e-300);
            for _ in 0..200 {
                let mid = 0.5 * (a + b);
                if mid <= a || mid >= b {
                    break;
                }
                if sturm_count(d, e, mid) > j {
                    b = mid;
                } else {
                    a = mid;
                }
            }
            0.5 * (a + b)
        })
        .collect()
}

/// Most bins of a density-of-states histogram (`beadchain modes --bins`, Python's `bins=`).
pub const MAX_BINS: usize = 1_000_000;

/// `bins` when it is a histogram's bin count (1 to [`MAX_BINS`]), else the one-line reason.
pub fn check_bins(bins: usize) -> Result<usize, StudyError> {
    if (1..=MAX_BINS).contains(&bins) {
        Ok(bins)
    } else {
        Err(StudyError::new(format!(
            "bins = {bins}: expected 1 to {MAX_BINS} bins"
        )))
    }
}

/// Density of states: `bins` equal bins of `ω` from 0 to the largest frequency (0 to 1
/// where none is above 0); returns the
/// `bins + 1` edges and the number of modes in each bin.
pub fn density_of_states(omega: &[f64], bins: usize) -> (Vec<f64>, Vec<f64>) {
    let bins = bins.max(1);
    let top = omega.iter().fold(0.0f64, |m, w| m.max(*w));
    let top = if top > 0.0 { top } else { 1.0 };
    let edges: Vec<f64> = (0..=bins).map(|b| top * b as f64 / bins as f64).collect();
    let mut counts = vec![0.0; bins];
    for w in omega {
        let b = ((w / top) * bins as f64).floor() as usize;
        counts[b.min(bins - 1)] += 1.0;
    }
    (edges, counts)
}
