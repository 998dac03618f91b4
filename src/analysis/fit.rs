//! Least-squares fits.
//!
//! - [`fit_exponential`]: `E(x) = a e^{−γx}` (paper Sec. 5.2, the fit below Fig. 21) by linear
//!   regression of `ln E` on `x` (log-linear least squares, equal weights in `ln E`), with the
//!   standard errors of `γ` and `ln a` from the residual variance `s² = SSR/(n−2)`:
//!   `se(γ) = s/√Sxx`, `se(ln a) = s·√(1/n + x̄²/Sxx)`. (The paper does not say whether it fitted
//!   `E` or `ln E`; the log-linear fit is the standard choice for a decay spanning decades.)
//! - [`least_squares`]: ordinary multilinear least squares `y ≈ X β` with standard errors from
//!   `s²·(XᵀX)⁻¹`, used for the Table 2 fit `log γ = α log ε + B̃ n̄ + C̃` (eq. 21).

use super::AnalysisError;

/// Result of [`fit_exponential`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExpFit {
    /// Prefactor `a`.
    pub a: f64,
    /// Decay rate `γ` (per unit of `x`).
    pub gamma: f64,
    /// Standard error of `γ` (0 for an exact fit or two points).
    pub gamma_stderr: f64,
    /// Standard error of `ln a`.
    pub ln_a_stderr: f64,
    /// Coefficient of determination of the log-linear fit.
    pub r2: f64,
    /// Number of points used.
    pub n: usize,
}

/// Fits `E(x) = a e^{−γx}`; every `e` must be positive and finite.
pub fn fit_exponential(x: &[f64], e: &[f64]) -> Result<ExpFit, AnalysisError> {
    if x.len() != e.len() {
        return Err(AnalysisError::Length(format!(
            "{} x values, {} energies",
            x.len(),
            e.len()
        )));
    }
    let n = x.len();
    if n < 2 {
        return Err(AnalysisError::TooFewPoints { need: 2, got: n });
    }
    let mut y = Vec::with_capacity(n);
    for (i, &ei) in e.iter().enumerate() {
        if !(ei > 0.0 && ei.is_finite()) {
            return Err(AnalysisError::NotPositive {
                what: "energy",
                index: i,
                value: ei,
            });
        }
        y.push(ei.ln());
    }
    let nf = n as f64;
    let xm = x.iter().sum::<f64>() / nf;
    let ym = y.iter().sum::<f64>() / nf;
    let sxx: f64 = x.iter().map(|xi| (xi - xm).powi(2)).sum();
    if sxx <= 0.0 || !sxx.is_finite() {
        return Err(AnalysisError::Singular);
    }
    let sxy: f64 = x.iter().zip(&y).map(|(xi, yi)| (xi - xm) * (yi - ym)).sum();
    let slope = sxy / sxx;
    let icpt = ym - slope * xm;
    let ssr: f64 = x
        .iter()
        .zip(&y)
        .map(|(xi, yi)| (yi - icpt - slope * xi).powi(2))
        .sum();
    let syy: f64 = y.iter().map(|yi| (yi - ym).powi(2)).sum();
    let s2 = if n > 2 { ssr / (nf - 2.0) } else { 0.0 };
    Ok(ExpFit {
        a: icpt.exp(),
        gamma: -slope,
        gamma_stderr: (s2 / sxx).sqrt(),
        ln_a_stderr: (s2 * (1.0 / nf + xm * xm / sxx)).sqrt(),
        r2: if syy > 0.0 { 1.0 - ssr / syy } else { 1.0 },
        n,
    })
}

/// Result of [`least_squares`].
#[derive(Clone, Debug, PartialEq)]
pub struct LinearFit {
    /// Coefficients `β` (one per column of `X`).
    pub coef: Vec<f64>,
    /// Their standard errors `√(s² (XᵀX)⁻¹_jj)`, `s² = SSR/(n − p)`.
    pub stderr: Vec<f64>,
    /// Residual standard deviation `s`.
    pub residual_sd: f64,
}

/// Ordinary least squares `y ≈ X β` (rows of `X` given as slices of equal length `p`), via the
/// normal equations solved by Gauss–Jordan elimination with partial pivoting (`p` is small).
pub fn least_squares(rows: &[Vec<f64>], y: &[f64]) -> Result<LinearFit, AnalysisError> {
    let n = rows.len();
    if n != y.len() {
        return Err(AnalysisError::Length(format!(
            "{n} rows, {} values",
            y.len()
        )));
    }
    let p = rows.first().map_or(0, |r| r.len());
    if p == 0 || n < p {
        return Err(AnalysisError::TooFewPoints {
            need: p.max(1),
            got: n,
        });
    }
    if rows.iter().any(|r| r.len() != p) {
        return Err(AnalysisError::Length("rows of unequal length".into()));
    }
    // augmented [XᵀX | Xᵀy | I]
    let w = 2 * p + 1;
    let mut m = vec![0.0; p * w];
    for (r, &yi) in rows.iter().zip(y) {
        for j in 0..p {
            for k in 0..p {
                m[j * w + k] += r[j] * r[k];
            }
            m[j * w + p] += r[j] * yi;
        }
    }
    for j in 0..p {
        m[j * w + p + 1 + j] = 1.0;
    }
    let scale = (0..p).map(|j| m[j * w + j].abs()).fold(0.0, f64::max);
    for col in 0..p {
        let piv = (col..p)
            .max_by(|&a, &b| m[a * w + col].abs().total_cmp(&m[b * w + col].abs()))
            .unwrap_or(col);
        if m[piv * w + col].abs() <= 1e-13 * scale {
            return Err(AnalysisError::Singular);
        }
        if piv != col {
            for k in 0..w {
                m.swap(piv * w + k, col * w + k);
            }
        }
        let d = m[col * w + col];
        for k in 0..w {
            m[col * w + k] /= d;
        }
        for r in 0..p {
            if r != col {
                let f = m[r * w + col];
                if f != 0.0 {
                    for k in 0..w {
                        m[r * w + k] -= f * m[col * w + k];
                    }
                }
            }
        }
    }
    let coef: Vec<f64> = (0..p).map(|j| m[j * w + p]).collect();
    let ssr: f64 = rows
        .iter()
        .zip(y)
        .map(|(r, yi)| (yi - r.iter().zip(&coef).map(|(a, b)| a * b).sum::<f64>()).powi(2))
        .sum();
    let s2 = if n > p { ssr / (n - p) as f64 } else { 0.0 };
    let stderr = (0..p).map(|j| (s2 * m[j * w + p + 1 + j]).sqrt()).collect();
    Ok(LinearFit {
        coef,
        stderr,
        residual_sd: s2.sqrt(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_exponential() {
        let x: Vec<f64> = (0..20).map(|i| i as f64 * 3.0).collect();
        let e: Vec<f64> = x.iter().map(|x| 2.5 * (-0.02 * x).exp()).collect();
        let f = fit_exponential(&x, &e).unwrap();
        // exact data: rel 1e-12 on gamma and a, stderr ~ 0 (abs 1e-12)
        assert!((f.gamma - 0.02).abs() < 1e-12 * 0.02 + 1e-15, "{f:?}");
        assert!((f.a - 2.5).abs() < 1e-12 * 2.5);
        assert!(f.gamma_stderr < 1e-12);
        assert!((f.r2 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn stderr_known_case() {
        // ln E = -x + r with residuals r = (+d, -d, -d, +d) at x = 0,1,2,3: slope unaffected
        // (residuals orthogonal to 1 and x), SSR = 4d², s² = 2d², Sxx = 5, se = d·sqrt(2/5).
        let d = 0.1;
        let x = [0.0, 1.0, 2.0, 3.0];
        let r = [d, -d, -d, d];
        let e: Vec<f64> = x
            .iter()
            .zip(&r)
            .map(|(x, r): (&f64, &f64)| (-x + r).exp())
            .collect();
        let f = fit_exponential(&x, &e).unwrap();
        // abs tol 1e-12 (exact arithmetic up to rounding)
        assert!((f.gamma - 1.0).abs() < 1e-12, "{f:?}");
        assert!(
            (f.gamma_stderr - d * (0.4f64).sqrt()).abs() < 1e-12,
            "{f:?}"
        );
    }

    #[test]
    fn fit_errors() {
        assert!(matches!(
            fit_exponential(&[1.0], &[1.0]),
            Err(AnalysisError::TooFewPoints { .. })
        ));
        assert!(matches!(
            fit_exponential(&[1.0, 2.0], &[1.0, 0.0]),
            Err(AnalysisError::NotPositive { index: 1, .. })
        ));
        assert!(matches!(
            fit_exponential(&[1.0, 1.0], &[1.0, 2.0]),
            Err(AnalysisError::Singular)
        ));
        assert!(matches!(
            fit_exponential(&[1.0, 2.0], &[1.0]),
            Err(AnalysisError::Length(_))
        ));
    }

    #[test]
    fn multilinear_recovers_plane() {
        // y = 2.085 a - 3.511 b + 10.945 on a 4x3 grid: exact recovery (abs 1e-10)
        let mut rows = Vec::new();
        let mut y = Vec::new();
        for a in [-6.0, -5.0, -4.0, -3.2] {
            for b in [2.4, 3.0, 3.7] {
                rows.push(vec![a, b, 1.0]);
                y.push(2.085 * a - 3.511 * b + 10.945);
            }
        }
        let f = least_squares(&rows, &y).unwrap();
        for (c, want) in f.coef.iter().zip([2.085, -3.511, 10.945]) {
            assert!((c - want).abs() < 1e-10, "{f:?}");
        }
        assert!(f.stderr.iter().all(|s| *s < 1e-6));
        // a collinear design is singular
        let rows = vec![vec![1.0, 2.0], vec![2.0, 4.0], vec![3.0, 6.0]];
        assert!(matches!(
            least_squares(&rows, &[1.0, 2.0, 3.0]),
            Err(AnalysisError::Singular)
        ));
    }

    #[test]
    fn multilinear_stderr_matches_simple_regression() {
        // a straight line through noisy points: the multilinear stderr of the slope equals the
        // simple-regression formula used by fit_exponential (rel 1e-10)
        let x = [0.0, 1.0, 2.0, 3.0, 4.0];
        let y = [0.1, -0.9, -2.2, -2.9, -4.1];
        let rows: Vec<Vec<f64>> = x.iter().map(|&x| vec![x, 1.0]).collect();
        let f = least_squares(&rows, &y).unwrap();
        let e: Vec<f64> = y.iter().map(|y: &f64| y.exp()).collect();
        let g = fit_exponential(&x, &e).unwrap();
        assert!((f.coef[0] + g.gamma).abs() < 1e-10);
        assert!((f.stderr[0] - g.gamma_stderr).abs() < 1e-10 * g.gamma_stderr);
    }
}
