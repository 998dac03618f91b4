//! The Newton systems of Radau IIA for bead chains, reduced to bead coordinates.
//!
//! With `z = (u, v)` and `ż = (v, f(u, v))`, the Jacobian is `J = [[0, I], [K_u, K_v]]` with
//! `M K_u = −L(k)` and `M K_v = −L(k_v)`, where `L(w)` is the weighted Laplacian of the contact
//! graph (`k = ∂F/∂δ`, `k_v = ∂F/∂δ̇` per contact; walls on the diagonal). Each system
//! `(c I − J) x = r` reduces to the `m × m` symmetric tridiagonal system
//!
//! ```text
//! (c² M + c L(k_v) + L(k)) x_u = M (r_v + c r_u) + L(k_v) r_u,      x_v = c x_u − r_u
//! ```
//!
//! (Hairer & Wanner, *Solving ODEs II*, IV.8, specialised to second-order systems; without
//! damping `k_v = 0` and the terms vanish), real for `c = μ_r/h` and complex for `c = μ_c/h`.

use crate::linalg::{Scalar, TridiagSolver};
use num_complex::Complex64;

/// `(L(w) x)_i`: the weighted Laplacian of the chain's contacts (`w[c]` for contact `c`,
/// `w[m−1]`/`w[m]` the left/right wall) applied to `x`, at bead `i`.
#[inline(always)]
fn laplacian_at<T: Scalar>(w: &[f64], x: &[T], i: usize) -> T {
    let m = x.len();
    let left = if i > 0 {
        (x[i] - x[i - 1]) * T::from_real(w[i - 1])
    } else {
        x[i] * T::from_real(w[m - 1])
    };
    let right = if i + 1 < m {
        (x[i] - x[i + 1]) * T::from_real(w[i])
    } else {
        x[i] * T::from_real(w[m])
    };
    left + right
}

/// Diagonal `d` and off-diagonal `e` of `c² M + c L(k_v) + L(k)` (`k_v = None`: no damping).
// The three kernels of every Newton iteration are `#[inline]`: they then inline into
// `Radau5::step` whichever of the release profile's codegen units the crate's partition puts
// them in (without the hint, unrelated changes elsewhere moved them out of line and the
// striker's Radau IIA run by +2.6 % instructions).
#[inline]
pub(super) fn newton_matrix<T: Scalar>(
    mass: &[f64],
    k: &[f64],
    kv: Option<&[f64]>,
    c: T,
    d: &mut [T],
    e: &mut [T],
) {
    let m = mass.len();
    let c2 = c * c;
    let lap = |w: &[f64], i: usize| -> f64 {
        let l = if i > 0 { w[i - 1] } else { w[m - 1] };
        let r = if i + 1 < m { w[i] } else { w[m] };
        l + r
    };
    for i in 0..m {
        d[i] = c2 * T::from_real(mass[i]) + T::from_real(lap(k, i));
        if let Some(kv) = kv {
            d[i] = d[i] + c * T::from_real(lap(kv, i));
        }
    }
    for i in 0..m.saturating_sub(1) {
        e[i] = T::from_real(-k[i]);
        if let Some(kv) = kv {
            e[i] = e[i] - c * T::from_real(kv[i]);
        }
    }
}

/// Solves `(c I − J) x = r` in place for real `c` (`r` has length `2m`).
#[inline]
pub(super) fn solve_real(
    real: &mut dyn TridiagSolver<f64>,
    mass: &[f64],
    kv: Option<&[f64]>,
    c: f64,
    r: &mut [f64],
) {
    let m = mass.len();
    let (ru, rv) = r.split_at_mut(m);
    // rhs = M (r_v + c r_u) [+ L(k_v) r_u], stored into rv temporarily.
    for i in 0..m {
        rv[i] = mass[i] * (rv[i] + c * ru[i]);
    }
    if let Some(kv) = kv {
        for i in 0..m {
            rv[i] += laplacian_at(kv, ru, i);
        }
    }
    real.solve_in_place(rv);
    // now rv = x_u; x_v = c x_u − r_u
    for i in 0..m {
        let xu = rv[i];
        let xv = c * xu - ru[i];
        ru[i] = xu;
        rv[i] = xv;
    }
}

/// Solves `(c I − J) x = r` for complex `c` and `r = re + i·im` (each length `2m`), in place;
/// `buf` (length `m`) is scratch.
#[inline]
pub(super) fn solve_complex(
    cplx: &mut dyn TridiagSolver<Complex64>,
    mass: &[f64],
    kv: Option<&[f64]>,
    c: Complex64,
    re: &mut [f64],
    im: &mut [f64],
    buf: &mut [Complex64],
) {
    let m = mass.len();
    for i in 0..m {
        let ru = Complex64::new(re[i], im[i]);
        let rv = Complex64::new(re[m + i], im[m + i]);
        buf[i] = (rv + c * ru) * mass[i];
    }
    if let Some(kv) = kv {
        // L(k_v) r_u with r_u read from re/im (buf already holds the rest).
        for i in 0..m {
            let at = |j: usize| Complex64::new(re[j], im[j]);
            let l = if i > 0 {
                (at(i) - at(i - 1)) * kv[i - 1]
            } else {
                at(i) * kv[m - 1]
            };
            let r = if i + 1 < m {
                (at(i) - at(i + 1)) * kv[i]
            } else {
                at(i) * kv[m]
            };
            buf[i] += l + r;
        }
    }
    cplx.solve_in_place(buf);
    for i in 0..m {
        let ru = Complex64::new(re[i], im[i]);
        let xu = buf[i];
        let xv = c * xu - ru;
        re[i] = xu.re;
        im[i] = xu.im;
        re[m + i] = xv.re;
        im[m + i] = xv.im;
    }
}
