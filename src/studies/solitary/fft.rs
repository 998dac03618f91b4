//! A small in-place radix-2 complex FFT (Cooley–Tukey, decimation in time) for the periodic
//! grids of the solitary-wave profile. Lengths are powers of two; the forward transform is
//! `X_j = Σ_k x_k e^{−2πi jk/N}`, the inverse has `e^{+2πi jk/N}` and divides by `N`.

use num_complex::Complex64;

/// In-place FFT of `x` (`x.len()` a power of two); `inverse` selects the sign and the `1/N`.
pub fn fft(x: &mut [Complex64], inverse: bool) {
    let n = x.len();
    assert!(n.is_power_of_two(), "FFT length {n} is not a power of two");
    let bits = n.trailing_zeros();
    for i in 0..n {
        let j = if bits == 0 {
            0
        } else {
            i.reverse_bits() >> (usize::BITS - bits)
        };
        if j > i {
            x.swap(i, j);
        }
    }
    let sign = if inverse { 1.0 } else { -1.0 };
    let mut len = 2;
    while len <= n {
        let half = len / 2;
        // Twiddles computed directly (not by repeated multiplication) to keep round-off at ε.
        let tw: Vec<Complex64> = (0..half)
            .map(|k| {
                Complex64::from_polar(
                    1.0,
                    sign * 2.0 * std::f64::consts::PI * k as f64 / len as f64,
                )
            })
            .collect();
        for start in (0..n).step_by(len) {
            for k in 0..half {
                let a = x[start + k];
                let b = x[start + k + half] * tw[k];
                x[start + k] = a + b;
                x[start + k + half] = a - b;
            }
        }
        len *= 2;
    }
    if inverse {
        let s = 1.0 / n as f64;
        for z in x.iter_mut() {
            *z *= s;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against the O(N²) DFT on a seeded pseudo-random vector: absolute 1e-12 on entries of
    /// order 1..N (relative ~1e-14).
    #[test]
    fn matches_direct_dft_and_inverts() {
        let n = 64;
        let mut s = 12345_u64;
        let x: Vec<Complex64> = (0..n)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let a = (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let b = (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                Complex64::new(a, b)
            })
            .collect();
        let mut y = x.clone();
        fft(&mut y, false);
        for j in 0..n {
            let d: Complex64 = (0..n)
                .map(|k| {
                    x[k] * Complex64::from_polar(
                        1.0,
                        -2.0 * std::f64::consts::PI * (j * k) as f64 / n as f64,
                    )
                })
                .sum();
            assert!((d - y[j]).norm() < 1e-12, "bin {j}: {d} vs {}", y[j]);
        }
        fft(&mut y, true);
        for k in 0..n {
            assert!((y[k] - x[k]).norm() < 1e-14, "entry {k}");
        }
    }
}
