//! Bead-to-bead energy transfer in chains with random exponents (paper Sec. 5.2, Fig. 23).
//!
//! The paper measures the energy passed from bead `i − 1` to bead `i` by the ratio of their
//! largest kinetic energies `E^kin_i / E^kin_{i−1}`, `E^kin_i = max_t m v_i²/2` (the equation
//! above Fig. 23), and plots it against `n_right − n_left`, the exponents of bead `i`'s contacts
//! with its right (contact `i`) and left (contact `i − 1`) neighbours, for `n = n̄ + ε r`
//! (eq. 19) with `n̄ = 2.4` and `3.7`, `ε = 0.04`. On average the ratio is below 1 (energy
//! reflected) for `n_right < n_left` and above 1 for `n_right > n_left`.
//!
//! - [`transfer_samples`]: the ratio and `n_right − n_left` of every bead in a range, from the
//!   per-bead largest velocities of a run.
//! - [`bin_samples`], [`transfer_trend`]: binned means and the linear trend.
//! - [`transfer_run`]: one disordered chain (contacts `0..20` uniform, as in Fig. 19).

use super::paper::{physical_scene, time_per_bead, PaperError};
use super::periodic::run_observer;
use crate::analysis::fit::{least_squares, LinearFit};
use crate::analysis::window::WindowWatch;
use crate::analysis::AnalysisError;
use crate::model::Chain;
use crate::scene::Engine;

/// One bead's transfer ratio.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TransferSample {
    /// Bead `i`.
    pub bead: usize,
    /// `n_right − n_left` = exponent of contact `i` minus exponent of contact `i − 1`.
    pub dn: f64,
    /// `E^kin_i / E^kin_{i−1}` (largest kinetic energies over the run).
    pub ratio: f64,
}

/// Transfer samples of beads `from..to` (`from ≥ 1`, `to ≤ N − 1`) from the largest forward
/// velocity `vmax` of every bead; beads whose left neighbour never moved are skipped.
pub fn transfer_samples(
    chain: &Chain,
    vmax: &[f64],
    from: usize,
    to: usize,
) -> Vec<TransferSample> {
    let to = to
        .min(vmax.len().saturating_sub(1))
        .min(chain.exponent.len());
    (from.max(1)..to)
        .filter_map(|i| {
            let prev = chain.mass[i - 1] * vmax[i - 1] * vmax[i - 1];
            (prev > 0.0).then(|| TransferSample {
                bead: i,
                dn: chain.exponent[i] - chain.exponent[i - 1],
                ratio: chain.mass[i] * vmax[i] * vmax[i] / prev,
            })
        })
        .collect()
}

/// Statistics of one `dn` bin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BinStat {
    /// Bin centre.
    pub centre: f64,
    /// Samples in the bin.
    pub count: usize,
    /// Mean ratio.
    pub mean: f64,
    /// Sample standard deviation of the ratio (0 for one sample).
    pub sd: f64,
}

/// Mean and s.d. of the ratio in `bins` equal bins over `[lo, hi)` of `dn` (empty bins omitted).
pub fn bin_samples(samples: &[TransferSample], lo: f64, hi: f64, bins: usize) -> Vec<BinStat> {
    let w = (hi - lo) / bins.max(1) as f64;
    (0..bins)
        .filter_map(|b| {
            let (a, z) = (lo + b as f64 * w, lo + (b + 1) as f64 * w);
            let r: Vec<f64> = samples
                .iter()
                .filter(|s| s.dn >= a && s.dn < z)
                .map(|s| s.ratio)
                .collect();
            if r.is_empty() {
                return None;
            }
            let n = r.len() as f64;
            let mean = r.iter().sum::<f64>() / n;
            let sd = if r.len() > 1 {
                (r.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
            } else {
                0.0
            };
            Some(BinStat {
                centre: 0.5 * (a + z),
                count: r.len(),
                mean,
                sd,
            })
        })
        .collect()
}

/// Least-squares line `ratio = c0 + c1 · dn` (coefficients `[c1, c0]` with standard errors).
pub fn transfer_trend(samples: &[TransferSample]) -> Result<LinearFit, AnalysisError> {
    let rows: Vec<Vec<f64>> = samples.iter().map(|s| vec![s.dn, 1.0]).collect();
    let y: Vec<f64> = samples.iter().map(|s| s.ratio).collect();
    least_squares(&rows, &y)
}

/// One disordered chain `n = n̄ + ε r` from contact 20 (seed `seed`, `beads` beads), run until
/// the front reaches bead `beads − 10`: the samples of beads `22..beads − 20` and the wall time.
pub fn transfer_run(
    nbar: f64,
    eps: f64,
    seed: u64,
    beads: usize,
) -> Result<(Vec<TransferSample>, f64), PaperError> {
    let tb = time_per_bead(nbar)?;
    let ex = format!("{{ random = {{ mean = {nbar}, eps = {eps} }}, start = 20 }}");
    let sc = physical_scene(beads, &ex, seed, tb * beads as f64 * 4.0, tb / 5.0)?;
    let mut w = WindowWatch::new(sc.chain.clone(), &[], beads.saturating_sub(10));
    let secs = run_observer(&sc, Engine::Hybrid, 1e-8, &mut w)?;
    Ok((
        transfer_samples(&sc.chain, &w.vmax, 22, beads.saturating_sub(20)),
        secs,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::wave::tests::chain;

    #[test]
    fn samples_bins_and_trend() {
        let mut c = chain(6, 3.0);
        c.exponent = vec![3.0, 3.1, 2.9, 3.0, 3.0];
        let vmax = [2.0, 2.0, 1.0, 2.0, 0.0, 1.0];
        let s = transfer_samples(&c, &vmax, 1, 5);
        // bead 1: dn = 0.1, 4/4; bead 2: dn = −0.2, 1/4; bead 3: 0.1, 4/1; bead 4: 0, 0/4;
        // bead 5 is past the range; exact arithmetic up to rounding (abs 1e-12)
        let want = [(1, 0.1, 1.0), (2, -0.2, 0.25), (3, 0.1, 4.0), (4, 0.0, 0.0)];
        assert_eq!(s.len(), 4);
        for (x, (b, dn, r)) in s.iter().zip(want) {
            assert_eq!(x.bead, b);
            assert!(
                (x.dn - dn).abs() < 1e-12 && (x.ratio - r).abs() < 1e-12,
                "{x:?}"
            );
        }
        let bins = bin_samples(&s, -0.3, 0.3, 3);
        // bins [-0.3,-0.1): bead 2; [-0.1,0.1): bead 4; [0.1,0.3): beads 1, 3 (mean 2.5)
        assert_eq!(bins.len(), 3);
        assert_eq!(bins[2].count, 2);
        assert!((bins[2].mean - 2.5).abs() < 1e-12);
        let f = transfer_trend(&s).unwrap();
        assert!(f.coef[0] > 0.0, "{f:?}");
    }
}
