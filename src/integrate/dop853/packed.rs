//! The stage sums of [`Dop853`] on a packed copy of its stages.
//!
//! Every DOP853 step forms `Σ_j c_j K_j` over its stages `K_j` about 150 times (HNW I, Sec.
//! II.5, eq. 5.18 for `y_s = z + h Σ_j a_sj K_j`; the 5th/3rd-order estimates; the continuous
//! output's `d` rows, Sec. II.6). Stored stage after stage (`K_j` contiguous), each sum is one
//! loop over the components per nonzero `c_j`, which loads and stores the partial sum every
//! time; on the hybrid engine's small clusters (state length 8–20) the loop's set-up outweighs
//! its arithmetic (`valgrind --tool=callgrind`: about 14 000 instructions per step of a 6-bead
//! cluster outside its right-hand sides).
//!
//! Here, for states of up to [`PACKED_MAX_LEN`] numbers, the stages are also kept **packed** by
//! groups of 4 components, the 16 stages of a group side by side: component `i = 4g + l` of
//! stage `j` at `((16g + j)·4 + l)`. A sum runs group by group with the partial sums of its 4
//! components in registers, over the nonzero coefficients of a row written out at compile time
//! ([`Row`]: the zero `a_sj` are never visited, and each term is a load, a multiplication and
//! an addition of 4 lanes). Each component is summed in the same order as the plain loop
//! ([`stage_sum`]: `0.0 + c_first K_first`, then `+ c_j K_j` in increasing `j`), so every result
//! is bit-identical to it (`tests.rs` holds them equal). Longer states use the plain loops,
//! which vectorise 4-wide there ([`use_packed`]). Measured in docs/engines.md (2026-11-26).
//!
//! [`Dop853`]: super::Dop853

use super::coefficients::{
    A1, A10, A11, A12, A13, A14, A15, A2, A3, A4, A5, A6, A7, A8, A9, D, E3, E5,
};

/// Components per group.
const LANES: usize = 4;
/// Stages per group (all of DOP853's: 12 main, the FSAL stage, 3 dense-output stages).
const STAGES: usize = super::N_STAGES;
/// Values per group.
const GROUP: usize = LANES * STAGES;

/// Length of the packed stages of a state of length `n`.
pub(super) fn packed_len(n: usize) -> usize {
    if use_packed(n) {
        n.div_ceil(LANES) * GROUP
    } else {
        0
    }
}

/// Copies stage `s` (`ks`, the state's length) into the packed stages `kp`.
#[inline(always)]
pub(super) fn pack(kp: &mut [f64], s: usize, ks: &[f64]) {
    if !use_packed(ks.len()) {
        return;
    }
    let mut chunks = ks.chunks_exact(LANES);
    for (g, c) in (&mut chunks).enumerate() {
        let at = g * GROUP + s * LANES;
        for (d, x) in kp[at..at + LANES].iter_mut().zip(c) {
            *d = *x;
        }
    }
    let rest = chunks.remainder();
    if !rest.is_empty() {
        let at = (ks.len() / LANES) * GROUP + s * LANES;
        kp[at..at + rest.len()].copy_from_slice(rest);
    }
}

/// A row of coefficients `c_j` over the stages, summed over one group of packed stages.
pub(super) trait Row {
    /// Stages where `c_j ≠ 0` (checked against the coefficient arrays by the tests).
    #[cfg(test)]
    const NONZERO: &'static [usize];
    /// `Σ_j c_j K_j` for the 4 components of the group `kg`, started as `0.0 + c_first K_first`.
    fn sum(kg: &[f64; GROUP]) -> [f64; LANES];
}

/// Stage `j` of a group.
#[inline(always)]
fn lanes(kg: &[f64; GROUP], j: usize) -> &[f64; LANES] {
    kg[j * LANES..(j + 1) * LANES]
        .try_into()
        .expect("a stage of a group")
}

/// `acc + c·k`, lane by lane: on x86-64 as packed SSE2 operations (two lanes each; the AVX2
/// build of the step may join them), whose products and sums are the scalar ones, correctly
/// rounded (LLVM left the plain form scalar).
#[inline(always)]
fn mul_add(acc: [f64; LANES], c: f64, k: &[f64; LANES]) -> [f64; LANES] {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_add_pd, _mm_loadu_pd, _mm_mul_pd, _mm_set1_pd, _mm_storeu_pd};
        let mut out = [0.0; LANES];
        // SAFETY: SSE2 is part of every x86-64 processor; the loads and stores read and write
        // two lanes inside arrays of four.
        unsafe {
            let cv = _mm_set1_pd(c);
            for h in [0, 2] {
                let a = _mm_loadu_pd(acc.as_ptr().add(h));
                let x = _mm_loadu_pd(k.as_ptr().add(h));
                _mm_storeu_pd(out.as_mut_ptr().add(h), _mm_add_pd(a, _mm_mul_pd(cv, x)));
            }
        }
        out
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        [
            acc[0] + c * k[0],
            acc[1] + c * k[1],
            acc[2] + c * k[2],
            acc[3] + c * k[3],
        ]
    }
}

/// A [`Row`] named `$name` for the coefficient array `$c` whose nonzero entries are at stages
/// `$j0, $j…` (integer literals, so that every coefficient and offset is a constant).
macro_rules! row {
    ($name:ident, $c:expr; $j0:literal $(, $j:literal)*) => {
        pub(super) struct $name;
        impl Row for $name {
            #[cfg(test)]
            const NONZERO: &'static [usize] = &[$j0 $(, $j)*];
            #[inline(always)]
            fn sum(kg: &[f64; GROUP]) -> [f64; LANES] {
                #[allow(unused_mut)]
                let mut acc = mul_add([0.0; LANES], $c[$j0], lanes(kg, $j0));
                $(
                    acc = mul_add(acc, $c[$j], lanes(kg, $j));
                )*
                acc
            }
        }
    };
}

row!(RowA1, A1; 0);
row!(RowA2, A2; 0, 1);
row!(RowA3, A3; 0, 2);
row!(RowA4, A4; 0, 2, 3);
row!(RowA5, A5; 0, 3, 4);
row!(RowA6, A6; 0, 3, 4, 5);
row!(RowA7, A7; 0, 3, 4, 5, 6);
row!(RowA8, A8; 0, 3, 4, 5, 6, 7);
row!(RowA9, A9; 0, 3, 4, 5, 6, 7, 8);
row!(RowA10, A10; 0, 3, 4, 5, 6, 7, 8, 9);
row!(RowA11, A11; 0, 3, 4, 5, 6, 7, 8, 9, 10);
row!(RowA12, A12; 0, 5, 6, 7, 8, 9, 10, 11);
row!(RowA13, A13; 0, 6, 7, 8, 9, 10, 11, 12);
row!(RowA14, A14; 0, 5, 6, 7, 10, 11, 12, 13);
row!(RowA15, A15; 0, 5, 6, 7, 8, 12, 13, 14);
row!(RowD0, D[0]; 0, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
row!(RowD1, D[1]; 0, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
row!(RowD2, D[2]; 0, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
row!(RowD3, D[3]; 0, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
row!(RowE5, E5; 0, 5, 6, 7, 8, 9, 10, 11);
row!(RowE3, E3; 0, 5, 6, 7, 8, 9, 10, 11);

/// Group `g` of the packed stages.
#[inline(always)]
fn group(kp: &[f64], g: usize) -> &[f64; GROUP] {
    kp[g * GROUP..(g + 1) * GROUP]
        .try_into()
        .expect("a whole group")
}

/// Does a state of length `n` use the packed stages? Up to [`PACKED_MAX_LEN`]: on longer states
/// the stage-after-stage loops are long enough for their set-up not to matter, and vectorise
/// 4-wide where the packed sums run 2-wide (`valgrind --tool=callgrind`, dense DOP853 on a
/// striker chain at rtol 1e-8 to t = 400, stage-after-stage / packed instructions: 6 beads
/// 3.28 / 2.72 M, 10 beads 5.44 / 4.62 M, 16 beads 8.32 / 8.06 M, 24 beads 11.2 / 11.5 M, 64
/// beads 38.4 / 46.3 M; the whole-chain interface, 150 beads, took 34 % more with packed sums).
#[inline(always)]
pub(super) fn use_packed(n: usize) -> bool {
    n <= PACKED_MAX_LEN
}

/// Longest state (2 × beads) summed on the packed stages: clusters of up to 20 beads.
pub(super) const PACKED_MAX_LEN: usize = 40;

/// `out = Σ_j c_j K_j` over the stages `K_j` stored one after the other in `k` with `c_j ≠ 0`,
/// started as `0.0 + c_first K_first` (the bits of zero-filling first, without a `memset`).
#[inline(always)]
pub(super) fn stage_sum(out: &mut [f64], c: &[f64], k: &[f64]) {
    let n = out.len();
    let mut first = true;
    for (j, &cj) in c.iter().enumerate() {
        if cj != 0.0 {
            let kj = &k[j * n..(j + 1) * n];
            if first {
                for (o, ki) in out.iter_mut().zip(kj) {
                    *o = 0.0 + cj * ki;
                }
                first = false;
            } else {
                for (o, ki) in out.iter_mut().zip(kj) {
                    *o += cj * ki;
                }
            }
        }
    }
    if first {
        out.fill(0.0);
    }
}

/// `y = z + h Σ_j a_j K_j` over the stages stored one after the other in `k`, and the velocity
/// half of `y` copied into `ku` while it is written (no `memcpy` call per stage).
#[inline(always)]
pub(super) fn combine_plain(
    y: &mut [f64],
    ku: &mut [f64],
    z: &[f64],
    h: f64,
    a: &[f64],
    k: &[f64],
) {
    let m = z.len() / 2;
    stage_sum(y, a, k);
    let (yu, yv) = y.split_at_mut(m);
    for (yi, zi) in yu.iter_mut().zip(&z[..m]) {
        *yi = zi + h * *yi;
    }
    for ((yi, zi), kui) in yv.iter_mut().zip(&z[m..]).zip(ku.iter_mut()) {
        *yi = zi + h * *yi;
        *kui = *yi;
    }
}

/// `x = Σ_j c_j K_j` (row `R`) into `out` (the state's length), times `h` (`x_i·h`: the
/// continuous output's rows), from the packed stages `kp`.
#[inline(always)]
pub(super) fn sum_times<R: Row>(out: &mut [f64], kp: &[f64], h: f64) {
    let mut chunks = out.chunks_exact_mut(LANES);
    let mut g = 0;
    for o in &mut chunks {
        let acc = R::sum(group(kp, g));
        for l in 0..LANES {
            o[l] = acc[l] * h;
        }
        g += 1;
    }
    let rest = chunks.into_remainder();
    if !rest.is_empty() {
        let acc = R::sum(group(kp, g));
        for (o, x) in rest.iter_mut().zip(acc) {
            *o = x * h;
        }
    }
}

/// `y = z + h Σ_j a_j K_j` (row `R` of the Runge–Kutta matrix) from the packed stages `kp`, and
/// the velocity half of `y` copied into `ku` (the displacement half of the stage `y` starts,
/// `K = (v, f(u))`).
#[inline(always)]
pub(super) fn combine<R: Row>(y: &mut [f64], ku: &mut [f64], z: &[f64], h: f64, kp: &[f64]) {
    let n = z.len();
    let (y, z) = (&mut y[..n], &z[..n]);
    let full = n / LANES;
    for g in 0..full {
        let acc = R::sum(group(kp, g));
        let yg: &mut [f64; LANES] = (&mut y[g * LANES..(g + 1) * LANES])
            .try_into()
            .expect("a group");
        let zg: &[f64; LANES] = z[g * LANES..(g + 1) * LANES].try_into().expect("a group");
        for l in 0..LANES {
            yg[l] = zg[l] + h * acc[l];
        }
    }
    if full * LANES < n {
        let acc = R::sum(group(kp, full));
        for i in full * LANES..n {
            y[i] = z[i] + h * acc[i - full * LANES];
        }
    }
    ku.copy_from_slice(&y[n / 2..]);
}

/// The continuous output's rows `f_{3+r} = h Σ_j d_rj K_j` (r = 0…3, each the state's length
/// `n`, one after the other in `f`), from the packed stages.
#[inline(always)]
pub(super) fn dense_rows(f: &mut [f64], kp: &[f64], h: f64) {
    let n = f.len() / 4;
    let (f0, rest) = f.split_at_mut(n);
    let (f1, rest) = rest.split_at_mut(n);
    let (f2, f3) = rest.split_at_mut(n);
    sum_times::<RowD0>(f0, kp, h);
    sum_times::<RowD1>(f1, kp, h);
    sum_times::<RowD2>(f2, kp, h);
    sum_times::<RowD3>(&mut f3[..n], kp, h);
}

/// The 5th- and 3rd-order error estimates `e5 = Σ_j E5_j K_j`, `e3 = Σ_j E3_j K_j` from the
/// packed stages. Both weights are nonzero on the same stages, so each sum is the bits of one
/// loop over both.
#[inline(always)]
pub(super) fn error_sums(e5: &mut [f64], e3: &mut [f64], kp: &[f64]) {
    for (g, (o5, o3)) in e5.chunks_mut(LANES).zip(e3.chunks_mut(LANES)).enumerate() {
        let kg = group(kp, g);
        let (a5, a3) = (RowE5::sum(kg), RowE3::sum(kg));
        for ((o, x), (r, y)) in o5.iter_mut().zip(a5).zip(o3.iter_mut().zip(a3)) {
            *o = x;
            *r = y;
        }
    }
}
