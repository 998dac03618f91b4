//! The force-only kernel of [`Chain::accel`] (paper eq. 7), in two passes so that the compiler
//! can vectorise the contact forces.
//!
//! The one-pass loop `acc[c] −= F_c; acc[c+1] += F_c` carries a dependence from one contact to
//! the next through `acc` and branches per contact on its exponent, so it runs one contact at a
//! time (one scalar `sqrt` for `n = 2.5`). Here:
//!
//! 1. **Forces.** `F_c = n a δ₊^{n−1}` (eq. 6) into `acc[c]`, run by run of contacts with the
//!    same exponent. A run (of at least [`MIN_RUN`]) whose exponent is a common half-integer
//!    (2, 2.5, 3, 3.5, 4; see [`super::pow_nm2`]) is a branch-free loop over `δ₊ = max(δ, 0)`, which vectorises (packed
//!    `sqrt` and multiplications; on x86-64 with AVX2 the kernel is compiled for AVX2 as well).
//!    Other exponents, and short runs (alternating exponents), go one contact at a time through
//!    [`contact_force`] (`powf` per closed contact), as before.
//! 2. **Accelerations.** `m_i a_i = (W_i + F_{i−1}) − F_i`, in place from the right end.
//!
//! Every operation and its order is the one-pass loop's (`((n·a)·δ^{n−2})·δ`, then
//! `(W_i + F_{i−1}) − F_i`, walls, `/ m_i`), and `sqrt`, `×` and `+` are correctly rounded in
//! every instruction set, so the accelerations are bit-identical to it (`tests.rs` holds the
//! two equal on every exponent class, with and without precompression and field).

use super::{contact_force, Chain};

/// Is `n` one of the half-integer exponents with a branch-free force loop (n = 2, 2.5, … 4, i.e.
/// `2(n − 2)` an integer in 0 … 4, as in [`super::pow_nm2`])?
#[inline(always)]
fn is_fast_class(n: f64) -> bool {
    let k = 2.0 * (n - 2.0);
    (0.0..=4.0).contains(&k) && k == k.trunc()
}

/// Shortest run of equal exponents given to the branch-free loop.
const MIN_RUN: usize = 4;

/// Contact forces `F_c = (n a) δ₊^{n−2} δ₊` of one run of contacts sharing the exponent class
/// `K = 2(n − 2)` (0 … 4), `δ_c = pre_c + u_c − u_{c+1}`, into `f`. Branch-free: vectorises.
#[inline(always)]
fn run_fast<const K: u8, const PRE: bool>(
    n: f64,
    a: &[f64],
    pre: &[f64],
    u: &[f64],
    f: &mut [f64],
) {
    for (c, fc) in f.iter_mut().enumerate() {
        let mut d = u[c] - u[c + 1];
        if PRE {
            d += pre[c];
        }
        let d = if d > 0.0 { d } else { 0.0 };
        let p = match K {
            0 => 1.0,
            1 => d.sqrt(),
            2 => d,
            3 => d * d.sqrt(),
            _ => d * d,
        };
        *fc = n * a[c] * p * d;
    }
}

/// [`run_fast`] for the class of `n` (for which [`is_fast_class`] holds).
#[inline(always)]
fn run_class<const PRE: bool>(n: f64, a: &[f64], pre: &[f64], u: &[f64], f: &mut [f64]) {
    let k = 2.0 * (n - 2.0);
    if k == 0.0 {
        run_fast::<0, PRE>(n, a, pre, u, f)
    } else if k == 1.0 {
        run_fast::<1, PRE>(n, a, pre, u, f)
    } else if k == 2.0 {
        run_fast::<2, PRE>(n, a, pre, u, f)
    } else if k == 3.0 {
        run_fast::<3, PRE>(n, a, pre, u, f)
    } else {
        run_fast::<4, PRE>(n, a, pre, u, f)
    }
}

impl Chain {
    /// The two-pass force kernel (module docs); `PRE`, `FIELD` as in the one-pass kernel.
    #[inline(always)]
    pub(super) fn accel_two_pass<const PRE: bool, const FIELD: bool>(
        &self,
        lo: usize,
        u: &[f64],
        acc: &mut [f64],
    ) {
        let m = u.len();
        debug_assert_eq!(acc.len(), m);
        let n = &self.exponent[lo..lo + m - 1];
        let a = &self.prefactor[lo..lo + m - 1];
        let pre: &[f64] = match &self.precompression {
            Some(p) if PRE => &p[lo..lo + m - 1],
            _ => &[],
        };
        // pass 1: forces into acc[0 .. m−1]; runs of one fast exponent class go branch-free
        let mut c = 0;
        while c < m - 1 {
            let nc = n[c];
            // a run shorter than MIN_RUN (alternating exponents) is cheaper one by one
            if !is_fast_class(nc)
                || c + MIN_RUN > m - 1
                || n[c + 1..c + MIN_RUN].iter().any(|&x| x != nc)
            {
                let mut d = u[c] - u[c + 1];
                if PRE {
                    d += pre[c];
                }
                acc[c] = contact_force(nc, a[c], d);
                c += 1;
                continue;
            }
            let end = c + n[c..].iter().take_while(|&&x| x == nc).count();
            let pr = if PRE { &pre[c..end] } else { &[][..] };
            run_class::<PRE>(nc, &a[c..end], pr, &u[c..=end], &mut acc[c..end]);
            c = end;
        }
        // pass 2: m_i a_i = (W_i + F_{i−1}) − F_i, from the right end (F_{i−1} still unread)
        let w = |i: usize| match &self.field {
            Some(w) if FIELD => w[lo + i],
            _ => 0.0,
        };
        if m > 1 {
            acc[m - 1] = w(m - 1) + acc[m - 2];
            for i in (1..m - 1).rev() {
                acc[i] = (w(i) + acc[i - 1]) - acc[i];
            }
            acc[0] = w(0) - acc[0];
        } else {
            acc[0] = w(0);
        }
        self.wall_forces(lo, u, acc);
        for (ai, mi) in acc.iter_mut().zip(&self.mass[lo..lo + m]) {
            *ai /= mi;
        }
    }

    /// [`Self::accel_two_pass`] for the declared effects, compiled for AVX2.
    ///
    /// # Safety
    /// The processor must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn accel_avx2(&self, lo: usize, u: &[f64], acc: &mut [f64]) {
        self.accel_dispatch(lo, u, acc)
    }

    /// [`Self::accel_two_pass`] monomorphised on the declared effects.
    #[inline(always)]
    pub(super) fn accel_dispatch(&self, lo: usize, u: &[f64], acc: &mut [f64]) {
        match (self.precompression.is_some(), self.field.is_some()) {
            (false, false) => self.accel_two_pass::<false, false>(lo, u, acc),
            (true, false) => self.accel_two_pass::<true, false>(lo, u, acc),
            (false, true) => self.accel_two_pass::<false, true>(lo, u, acc),
            (true, true) => self.accel_two_pass::<true, true>(lo, u, acc),
        }
    }
}
