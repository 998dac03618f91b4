//! Band structure of a periodic chain (issue 35, part 3b).
//!
//! A unit cell of `p` beads (masses `m_0 … m_{p−1}`) and `p` contacts (stiffness `k_j` joins
//! bead `j` to bead `j+1`, `k_{p−1}` joins the last bead to the next cell's bead 0) repeated
//! without end. Bloch waves `u_{j,l} = U_j e^{i(q l − ω t)}` (cell `l`, wavenumber `q` per cell,
//! `−π ≤ q ≤ π`) solve the `p × p` Hermitian problem `H(q) V = ω² V`,
//!
//! ```text
//! H_jj += (k_{j−1} + k_j) / m_j,
//! H_{j,j+1} −= k_j / √(m_j m_{j+1})            (j < p−1),
//! H_{p−1,0} −= k_{p−1} e^{iq} / √(m_{p−1} m_0),  H_{0,p−1} = conj(H_{p−1,0}),
//! ```
//!
//! (for `p = 1`: `ω² = (2k/m)(1 − cos q) = 4 (k/m) sin²(q/2)`). `H = A + iB` is solved as the
//! real symmetric `[[A, −B], [B, A]]`, whose eigenvalues are those of `H`, each twice. Its
//! characteristic polynomial depends on `q` only through `cos q`, so every band is monotone on
//! `[0, π]` and its edges are its values at `q = 0` and `q = π` ([`Bands::edges`]).

use super::modes::Linearized;
use super::StudyError;

/// A unit cell: `p` masses and `p` contact stiffnesses (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct Cell {
    /// Masses `m_0 … m_{p−1}`.
    pub mass: Vec<f64>,
    /// Stiffnesses `k_0 … k_{p−1}` (`k_{p−1}` to the next cell).
    pub stiffness: Vec<f64>,
}

/// The unit cell of beads `start..start+p` of a linearised chain, with `p` given or the
/// smallest period of the masses and stiffnesses (relative tolerance 1e-12) over the chain's
/// contacts `start..`.
pub fn cell_of(lin: &Linearized, period: Option<usize>, start: usize) -> Result<Cell, StudyError> {
    let nc = lin.stiffness.len();
    if start >= nc {
        return Err(StudyError::new(format!(
            "the cell's first bead {start} (start) is past the last contact: the chain has {nc} contacts, 0..={}",
            nc.saturating_sub(1)
        )));
    }
    let p = match period {
        Some(0) => return Err(StudyError::new("the cell needs at least 1 bead, got 0")),
        Some(p) => p,
        None => (1..=nc.saturating_sub(start) / 2)
            .find(|&p| is_period(lin, start, p))
            .ok_or_else(|| {
                StudyError::new(format!(
                    "no period found in the {} contacts from bead {start} on (masses and stiffnesses differ): give the cell size (--cell)",
                    nc.saturating_sub(start)
                ))
            })?,
    };
    if start.checked_add(p).is_none_or(|end| end > nc) {
        return Err(StudyError::new(format!(
            "a cell of {p} beads from bead {start} needs {} contacts; the chain has {nc}",
            start.saturating_add(p)
        )));
    }
    Ok(Cell {
        mass: lin.mass[start..start + p].to_vec(),
        stiffness: lin.stiffness[start..start + p].to_vec(),
    })
}

/// Are the masses and contact stiffnesses from `start` on periodic with period `p`?
fn is_period(lin: &Linearized, start: usize, p: usize) -> bool {
    let same = |x: f64, y: f64| (x - y).abs() <= 1e-12 * x.abs().max(y.abs());
    let nc = lin.stiffness.len();
    (start..nc - p).all(|c| same(lin.stiffness[c], lin.stiffness[c + p]))
        && (start..nc - p).all(|i| same(lin.mass[i], lin.mass[i + p]))
}

/// The Bloch frequencies `ω(q)` of `cell` (p values, increasing).
pub fn bloch_frequencies(cell: &Cell, q: f64) -> Vec<f64> {
    let p = cell.mass.len();
    let (m, k) = (&cell.mass, &cell.stiffness);
    // H = A + iB as the real symmetric [[A, −B], [B, A]].
    let mut h = faer::Mat::<f64>::zeros(2 * p, 2 * p);
    let mut add = |i: usize, j: usize, re: f64, im: f64| {
        h[(i, j)] += re;
        h[(i + p, j + p)] += re;
        h[(i, j + p)] -= im;
        h[(i + p, j)] += im;
    };
    for j in 0..p {
        let prev = if j == 0 { p - 1 } else { j - 1 };
        add(j, j, (k[prev] + k[j]) / m[j], 0.0);
    }
    for j in 0..p {
        let next = (j + 1) % p;
        let c = k[j] / (m[j] * m[next]).sqrt();
        // H[next][j] −= c·phase, H[j][next] −= c·conj(phase); phase e^{iq} across the cell edge.
        let (re, im) = if j == p - 1 {
            (q.cos(), q.sin())
        } else {
            (1.0, 0.0)
        };
        add(next, j, -c * re, -c * im);
        add(j, next, -c * re, c * im);
    }
    let ev = h
        .self_adjoint_eigenvalues(faer::Side::Lower)
        .expect("the eigenvalues of a small symmetric matrix");
    ev.iter().step_by(2).map(|l| l.max(0.0).sqrt()).collect()
}

/// A band structure sampled on `q ∈ [0, π]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Bands {
    /// Wavenumbers per cell, `points` values from 0 to π.
    pub q: Vec<f64>,
    /// `omega[b][s]`: band `b` at `q[s]`.
    pub omega: Vec<Vec<f64>>,
    /// `(low, high)` of each band (its values at `q = 0` and `q = π`).
    pub edges: Vec<(f64, f64)>,
}

impl Bands {
    /// The gaps `(top of band b, bottom of band b+1)` where positive.
    pub fn gaps(&self) -> Vec<(f64, f64)> {
        self.edges
            .windows(2)
            .filter(|w| w[1].0 > w[0].1)
            .map(|w| (w[0].1, w[1].0))
            .collect()
    }
}

/// Most wavenumbers a band structure samples (`plot dispersion --points`, Python's `points=`).
pub const MAX_POINTS: usize = 100_000;

/// The band structure of `cell` at `points ≥ 2` wavenumbers from 0 to π.
pub fn bands(cell: &Cell, points: usize) -> Bands {
    let points = points.max(2);
    let p = cell.mass.len();
    let q: Vec<f64> = (0..points)
        .map(|s| std::f64::consts::PI * s as f64 / (points - 1) as f64)
        .collect();
    let mut omega = vec![Vec::with_capacity(points); p];
    for &qs in &q {
        for (b, w) in bloch_frequencies(cell, qs).into_iter().enumerate() {
            omega[b].push(w);
        }
    }
    let at0 = bloch_frequencies(cell, 0.0);
    let atpi = bloch_frequencies(cell, std::f64::consts::PI);
    let edges = (0..p)
        .map(|b| (at0[b].min(atpi[b]), at0[b].max(atpi[b])))
        .collect();
    Bands { q, omega, edges }
}
