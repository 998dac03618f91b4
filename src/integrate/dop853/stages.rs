//! The stages of a [`Dop853`] step (HNW I, Sec. II.5, Table 5.3 for the 8th-order tableau;
//! `Σ_j c_j K_j` on the packed stages for small states, [`super::packed`]), its error estimate
//! (the combined 5th/3rd-order estimator, module docs of [`super`]) and its continuous output's
//! coefficients (HNW I, Sec. II.6; SciPy `_dense_output_impl`).
//!
//! [`Dop853`]: super::Dop853

use super::coefficients::{A, D, E3, E5};
use super::packed::{
    self, Row, RowA1, RowA10, RowA11, RowA12, RowA13, RowA14, RowA15, RowA2, RowA3, RowA4, RowA5,
    RowA6, RowA7, RowA8, RowA9,
};
use super::{rhs_of_combined, Dop853, System, N_MAIN};

impl Dop853 {
    /// Stages 1–12 of a step of size `h` from `z`; leaves the new state in `y` and
    /// `f(y)` in stage 12.
    #[inline(always)]
    pub(super) fn main_stages<const P: bool>(&mut self, sys: &dyn System, h: f64) {
        let n = 2 * self.m;
        if !P {
            for (s, a) in A.iter().enumerate().take(N_MAIN).skip(1) {
                let (done, rest) = self.st.k.split_at_mut(s * n);
                let ks = &mut rest[..n];
                packed::combine_plain(&mut self.y, &mut ks[..n / 2], &self.st.z, h, a, done);
                self.pw[s] = rhs_of_combined(sys, &mut self.stats, &self.y, ks);
            }
            return;
        }
        self.packed_main_stages(sys, h);
    }

    /// [`Self::main_stages`] on the packed stages (small states, [`packed::use_packed`]).
    #[inline(always)]
    fn packed_main_stages(&mut self, sys: &dyn System, h: f64) {
        self.pw[1] = self.stage::<RowA1>(sys, h, 1, false);
        self.pw[2] = self.stage::<RowA2>(sys, h, 2, false);
        self.pw[3] = self.stage::<RowA3>(sys, h, 3, false);
        self.pw[4] = self.stage::<RowA4>(sys, h, 4, false);
        self.pw[5] = self.stage::<RowA5>(sys, h, 5, false);
        self.pw[6] = self.stage::<RowA6>(sys, h, 6, false);
        self.pw[7] = self.stage::<RowA7>(sys, h, 7, false);
        self.pw[8] = self.stage::<RowA8>(sys, h, 8, false);
        self.pw[9] = self.stage::<RowA9>(sys, h, 9, false);
        self.pw[10] = self.stage::<RowA10>(sys, h, 10, false);
        self.pw[11] = self.stage::<RowA11>(sys, h, 11, false);
        self.pw[12] = self.stage::<RowA12>(sys, h, 12, false);
    }

    /// Stage `s` (row `R` of `A`) on the packed stages: its state `y = z + h Σ_j a_j K_j` from
    /// `z`, or from `z_old` for the dense-output stages (`old`), and `K_s = f(y)`, stored and
    /// packed; returns the dissipated power at `y`.
    #[inline(always)]
    fn stage<R: Row>(&mut self, sys: &dyn System, h: f64, s: usize, old: bool) -> f64 {
        let n = 2 * self.m;
        let ks = &mut self.st.k[s * n..(s + 1) * n];
        let z = if old { &self.st.z_old } else { &self.st.z };
        packed::combine::<R>(&mut self.y, &mut ks[..n / 2], z, h, &self.kp);
        let p = rhs_of_combined(sys, &mut self.stats, &self.y, ks);
        packed::pack(&mut self.kp, s, ks);
        p
    }

    /// Energy dissipated over the step of size `h` just computed: the 8th-order weights (the
    /// last main row of `A`) applied to the stage powers, i.e. `Ė_d = P` integrated as one more
    /// component of the state.
    #[inline(always)]
    pub(super) fn step_dissipation(&self, h: f64) -> f64 {
        let b = &A[N_MAIN - 1];
        h * b.iter().zip(&self.pw).map(|(b, p)| b * p).sum::<f64>()
    }

    /// Weighted max-norm error of the step just computed by [`Self::main_stages`] (`INFINITY`
    /// when anything is non-finite).
    #[inline(always)]
    pub(super) fn error_norm<const P: bool>(&mut self, h: f64) -> f64 {
        let n = 2 * self.m;
        if P {
            packed::error_sums(&mut self.e5, &mut self.e3, &self.kp);
        } else {
            // started as `0.0 + c·K` at the first stage used (the bits of zero-filling first)
            let mut first = true;
            for j in 0..E5.len() {
                let kj = &self.st.k[j * n..(j + 1) * n];
                let (c5, c3) = (E5[j], E3[j]);
                if c5 != 0.0 || c3 != 0.0 {
                    let pairs = self.e5.iter_mut().zip(self.e3.iter_mut()).zip(kj);
                    if first {
                        for ((e5, e3), k) in pairs {
                            *e5 = 0.0 + c5 * k;
                            *e3 = 0.0 + c3 * k;
                        }
                        first = false;
                    } else {
                        for ((e5, e3), k) in pairs {
                            *e5 += c5 * k;
                            *e3 += c3 * k;
                        }
                    }
                }
            }
        }
        let (mut n5, mut n3) = (0.0_f64, 0.0_f64);
        let mut finite = true;
        for i in 0..n {
            let sc = self.weight(i, self.st.z[i], self.y[i]);
            let (r5, r3) = ((self.e5[i] / sc).abs(), (self.e3[i] / sc).abs());
            finite &= r5.is_finite() && r3.is_finite() && self.y[i].is_finite();
            n5 = n5.max(r5);
            n3 = n3.max(r3);
        }
        if self.damped {
            // The dissipated energy, integrated as one more component, is error-controlled
            // too: inside a step the clipped force can vanish while the power does not
            // (`P = −F_el δ̇`), which the state's error estimate cannot see.
            let (d5, d3) = self
                .pw
                .iter()
                .zip(E5.iter().zip(&E3))
                .fold((0.0, 0.0), |(a, b), (p, (e5, e3))| (a + e5 * p, b + e3 * p));
            let d_new = self.diss.1 + self.step_dissipation(h);
            let sc = self.tol.weight_e(self.diss.1, d_new);
            let (r5, r3) = ((d5 / sc).abs(), (d3 / sc).abs());
            finite &= r5.is_finite() && r3.is_finite();
            n5 = n5.max(r5);
            n3 = n3.max(r3);
        }
        // The FSAL stage becomes the next step's first stage: it must be finite too.
        finite &= self.st.k[12 * n..13 * n].iter().all(|x| x.is_finite());
        if !finite {
            return f64::INFINITY;
        }
        if n5 == 0.0 && n3 == 0.0 {
            return 0.0;
        }
        let (n5sq, n3sq) = (n5 * n5, n3 * n3);
        let err = h.abs() * n5sq / (n5sq + 0.01 * n3sq).sqrt();
        if self.rough != super::Rough::Smooth {
            // at a kink the 8th-order solution is no better than the 5th-order one
            err.max(h.abs() * n5)
        } else {
            err
        }
    }

    /// The 3 extra stages and the continuous-output coefficients of the step `z_old → z` of
    /// size `h` (SciPy `_dense_output_impl`), then the FSAL shift of stage 12 into stage 0.
    #[inline(always)]
    pub(super) fn dense_coefficients<const P: bool>(&mut self, sys: &dyn System, h: f64) {
        let n = 2 * self.m;
        let packed = P;
        if packed {
            self.packed_dense_stages(sys, h);
        } else {
            for (s, a) in A.iter().enumerate().skip(N_MAIN) {
                let (done, rest) = self.st.k.split_at_mut(s * n);
                let ks = &mut rest[..n];
                packed::combine_plain(&mut self.y, &mut ks[..n / 2], &self.st.z_old, h, a, done);
                rhs_of_combined(sys, &mut self.stats, &self.y, ks);
            }
        }
        let (f012, f3) = self.st.f.split_at_mut(3 * n);
        for i in 0..n {
            let dz = self.st.z[i] - self.st.z_old[i];
            let (k0, k12) = (self.st.k[i], self.st.k[12 * n + i]);
            f012[i] = dz;
            f012[n + i] = h * k0 - dz;
            f012[2 * n + i] = 2.0 * dz - h * (k12 + k0);
        }
        if packed {
            packed::dense_rows(f3, &self.kp, h);
        } else {
            for (r, drow) in D.iter().enumerate() {
                let fr = &mut f3[r * n..(r + 1) * n];
                packed::stage_sum(fr, drow, &self.st.k);
                for x in fr.iter_mut() {
                    *x *= h;
                }
            }
        }
        self.st.k.copy_within(12 * n..13 * n, 0);
        packed::pack(&mut self.kp, 0, &self.st.k[..n]);
    }

    /// The 3 extra stages of [`Self::dense_coefficients`] on the packed stages.
    #[inline(always)]
    fn packed_dense_stages(&mut self, sys: &dyn System, h: f64) {
        self.stage::<RowA13>(sys, h, 13, true);
        self.stage::<RowA14>(sys, h, 14, true);
        self.stage::<RowA15>(sys, h, 15, true);
    }
}
