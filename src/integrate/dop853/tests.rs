//! Tests of [`Dop853`] on bead chains (accuracy against references, step bookkeeping,
//! continuous output, checkpoints).

use super::coefficients::{A, E3, E5};
use super::*;
use crate::integrate::test_util::{striker, uniform_chain};
use crate::integrate::{ChainRange, DEFAULT_ATOL};
use crate::model::Chain;

fn tolerances(chain: &Chain, u: &[f64], v: &[f64], rtol: f64, atol: f64) -> Tolerances {
    Tolerances {
        rtol,
        atol,
        scales: chain.scales(u, v),
        v_frame: 0.0,
        u_origin: 0.0,
        dissipation: Default::default(),
    }
}

/// Integrates the whole chain from `(u, v)` at 0 to exactly `t_end`.
fn run(chain: &Chain, u: &[f64], v: &[f64], tol: Tolerances, t_end: f64) -> Dop853 {
    let sys = ChainRange::whole(chain);
    let mut ig = Dop853::new(chain.len(), tol);
    ig.reset(&sys, 0.0, u, v);
    while ig.t() < t_end {
        ig.step(&sys, t_end).expect("integration failed");
    }
    assert_eq!(ig.t(), t_end, "must land exactly on t_bound");
    ig
}

fn rel_energy_error(chain: &Chain, ig: &Dop853, e0: f64) -> f64 {
    let m = chain.len();
    let z = ig.state();
    ((chain.energy(&z[..m], &z[m..]) - e0) / e0).abs()
}

#[test]
fn two_beads_exchange_velocities_and_conserve_energy() {
    let chain = uniform_chain(2);
    let (u, v) = striker(2, 1.0);
    let e0 = chain.energy(&u, &v);
    let ig = run(
        &chain,
        &u,
        &v,
        tolerances(&chain, &u, &v, 1e-11, 1e-13),
        20.0,
    );
    let z = ig.state();
    // Equal masses exchange velocities: abs 1e-8.
    assert!(z[2].abs() <= 1e-8, "striker velocity {}", z[2]);
    assert!((z[3] - 1.0).abs() <= 1e-8, "struck velocity {}", z[3]);
    let de = rel_energy_error(&chain, &ig, e0);
    assert!(de <= 1e-9, "relative energy error {de:e}");
    assert!(ig.stats().steps > 5);
}

#[test]
fn twenty_bead_chain_conserves_energy() {
    let chain = uniform_chain(20);
    let (u, v) = striker(20, 1.0);
    let e0 = chain.energy(&u, &v);
    let ig = run(
        &chain,
        &u,
        &v,
        tolerances(&chain, &u, &v, 1e-10, 1e-12),
        30.0,
    );
    let de = rel_energy_error(&chain, &ig, e0);
    assert!(de <= 1e-8, "relative energy error {de:e}");
    // Momentum is conserved by any Runge–Kutta method up to rounding: abs 1e-12.
    let p = chain.momentum(&ig.state()[20..]);
    assert!((p - 1.0).abs() <= 1e-12, "momentum {p}");
    assert_eq!(ig.stats().bead_steps, 20 * ig.stats().steps);
}

#[test]
fn dense_output_agrees_with_stepping_to_the_time() {
    let chain = uniform_chain(5);
    let sys = ChainRange::whole(&chain);
    let (u, v) = striker(5, 1.0);
    let tol = tolerances(&chain, &u, &v, 1e-9, 1e-11);
    let mut checked = 0;
    for &ts in &[2.37, 4.1, 7.77, 11.3] {
        let mut free = Dop853::new(5, tol);
        free.reset(&sys, 0.0, &u, &v);
        while free.t() < ts {
            free.step(&sys, f64::INFINITY).expect("step");
        }
        let mut zd = [0.0; 10];
        free.dense(ts, &mut zd);
        let exact = run(&chain, &u, &v, tol, ts);
        let ze = exact.state();
        let size = ze.iter().fold(0.0_f64, |a, x| a.max(x.abs()));
        for (a, b) in zd.iter().zip(ze) {
            // Relative 1e-6 of the state's max norm (abs floor 1e-6 × size).
            assert!((a - b).abs() <= 1e-6 * size, "t = {ts}: {a} vs {b}");
        }
        checked += 1;
    }
    assert_eq!(checked, 4);
}

#[test]
fn dense_output_reproduces_step_endpoints() {
    let chain = uniform_chain(3);
    let sys = ChainRange::whole(&chain);
    let (u, v) = striker(3, 1.0);
    let mut ig = Dop853::new(3, tolerances(&chain, &u, &v, 1e-8, DEFAULT_ATOL));
    ig.reset(&sys, 0.0, &u, &v);
    let mut z = [0.0; 6];
    ig.dense(0.0, &mut z);
    assert_eq!(&z[..], ig.state(), "before any step");
    for _ in 0..20 {
        let before = ig.state().to_vec();
        let t = ig.step(&sys, f64::INFINITY).expect("step");
        ig.dense(ig.t_prev(), &mut z);
        assert_eq!(&z[..], &before[..], "start of step");
        ig.dense(t, &mut z);
        assert_eq!(&z[..], ig.state(), "end of step");
        // Just inside the step the interpolant is continuous with slope f(z) (the FSAL
        // stage 0): z(t − δ) ≈ z(t) − δ·f, abs 1e-13 (the δ² term is ~1e-20).
        let dt = 1e-9 * (t - ig.t_prev());
        ig.dense(t - dt, &mut z);
        for ((a, b), f) in z.iter().zip(ig.state()).zip(&ig.st.k) {
            assert!((a - (b - dt * f)).abs() <= 1e-13, "{a} vs {b} − {dt:e}·{f}");
        }
    }
}

#[test]
fn end_states_are_what_dense_at_returns_at_the_step_ends() {
    // The event log reads the peak overlaps' end points from `end_states` instead of
    // `dense_at`: they must be the same numbers (bit for bit), after a reset and every step.
    let chain = uniform_chain(4);
    let sys = ChainRange::whole(&chain);
    let (u, v) = striker(4, 1.0);
    let mut ig = Dop853::new(4, tolerances(&chain, &u, &v, 1e-6, 1e-10));
    ig.reset(&sys, 0.0, &u, &v);
    for _ in 0..=15 {
        let (z0, z1) = ig
            .end_states()
            .expect("DOP853 has its end states as arrays");
        for j in 0..8 {
            assert_eq!(
                z0[j].to_bits(),
                ig.dense_at(ig.t_prev(), j).to_bits(),
                "t_prev, {j}"
            );
            assert_eq!(z1[j].to_bits(), ig.dense_at(ig.t(), j).to_bits(), "t, {j}");
        }
        ig.step(&sys, f64::INFINITY).expect("step");
    }
}

#[test]
fn error_decreases_with_tolerance() {
    let chain = uniform_chain(10);
    let (u, v) = striker(10, 1.0);
    let e0 = chain.energy(&u, &v);
    let loose = run(&chain, &u, &v, tolerances(&chain, &u, &v, 1e-6, 1e-8), 20.0);
    let tight = run(
        &chain,
        &u,
        &v,
        tolerances(&chain, &u, &v, 1e-10, 1e-12),
        20.0,
    );
    let (el, et) = (
        rel_energy_error(&chain, &loose, e0),
        rel_energy_error(&chain, &tight, e0),
    );
    assert!(
        el > et,
        "energy error at rtol 1e-6 ({el:e}) vs 1e-10 ({et:e})"
    );
    assert!(loose.stats().steps < tight.stats().steps);
}

#[test]
fn similarity_scaling_gives_same_steps() {
    let chain = uniform_chain(2);
    let count = |v0: f64| {
        let (u, v) = striker(2, v0);
        let tol = tolerances(&chain, &u, &v, 1e-8, DEFAULT_ATOL);
        // 20 characteristic times of the unit problem.
        let t_end = 20.0 * tol.scales.time() / chain.scales(&[0.0; 2], &[1.0, 0.0]).time();
        let ig = run(&chain, &u, &v, tol, t_end);
        // Velocities exchanged: relative 1e-6 of v0.
        assert!((ig.state()[3] - v0).abs() <= 1e-6 * v0, "v0 = {v0}");
        (ig.stats().steps, ig.stats().rejected)
    };
    let (s1, r1) = count(1.0);
    let (s2, r2) = count(1e-7);
    assert!(s1.abs_diff(s2) <= 2, "steps {s1} (v=1) vs {s2} (v=1e-7)");
    assert!(r1.abs_diff(r2) <= 2, "rejections {r1} vs {r2}");
}

/// [`Dop853::step`] runs its AVX2 build where the processor has AVX2; it must give the bits of
/// the baseline build (`step_any` inlined here, compiled without AVX2): the same operations in
/// the same order, no fused multiply-adds. Conservative and damped chains (the damped one also
/// integrates the dissipated energy). Without AVX2 both run the baseline code (printed).
#[test]
fn avx2_and_baseline_steps_are_bit_identical() {
    #[cfg(target_arch = "x86_64")]
    let avx2 = std::arch::is_x86_feature_detected!("avx2");
    #[cfg(not(target_arch = "x86_64"))]
    let avx2 = false;
    if !avx2 {
        eprintln!("no AVX2 on this processor: both calls run the baseline build");
    }
    // 20 beads run on the packed stages, 40 on the stage-after-stage loops (`packed.rs`)
    for (nb, chain) in [20, 40].into_iter().flat_map(|nb| {
        let plain = uniform_chain(nb);
        let mut damped = plain.clone();
        damped.damping = Some(crate::model::Damping {
            law: crate::model::DampingLaw::Viscoelastic,
            contact: vec![0.3; nb - 1],
            left_wall: 0.0,
            right_wall: 0.0,
        });
        [(nb, plain), (nb, damped)]
    }) {
        let (u, v) = striker(nb, 1.0);
        let tol = tolerances(&chain, &u, &v, 1e-8, 1e-12);
        let sys = ChainRange::whole(&chain);
        let (mut a, mut b) = (Dop853::new(nb, tol), Dop853::new(nb, tol));
        a.reset(&sys, 0.0, &u, &v);
        b.reset(&sys, 0.0, &u, &v);
        let bits = |x: &[f64]| x.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
        let (mut za, mut zb) = (vec![0.0; 2 * nb], vec![0.0; 2 * nb]);
        while a.t() < 30.0 {
            let ta = a.step(&sys, 30.0).expect("step");
            let tb = b.step_any(&sys, 30.0).expect("step");
            assert_eq!(ta.to_bits(), tb.to_bits());
            assert_eq!(bits(a.state()), bits(b.state()), "t = {ta}");
            let (da, db) = (a.dissipated(), b.dissipated());
            assert_eq!(
                (da.0.to_bits(), da.1.to_bits()),
                (db.0.to_bits(), db.1.to_bits())
            );
            let mid = 0.5 * (a.t_prev() + a.t());
            a.dense(mid, &mut za);
            b.dense(mid, &mut zb);
            assert_eq!(bits(&za), bits(&zb), "continuous output at t = {mid}");
        }
        assert!(a.stats().steps > 20, "{} steps", a.stats().steps);
        assert_eq!(a.stats(), b.stats());
        assert_eq!(chain.is_dissipative(), a.dissipated().1 > 0.0);
    }
}

/// The stage sums on the packed stages (`packed.rs`) and the stage-after-stage ones are bit for
/// bit those of the plain loop `0 + Σ_j c_j K_j` over the nonzero `c_j` in stage order (signed
/// zeros included), for every row
/// of the method's coefficients (main, dense-output and error rows) and state lengths with full
/// and partial groups of 4; each row's list of nonzero stages is that of its array.
#[test]
fn packed_stage_sums_are_bit_identical_to_the_plain_loop() {
    use super::coefficients::D;
    use super::packed::{self, *};
    fn check<R: Row>(c: &[f64]) {
        let nonzero: Vec<usize> = (0..c.len()).filter(|&j| c[j] != 0.0).collect();
        assert_eq!(R::NONZERO, &nonzero[..]);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        for m in [1, 2, 3, 4, 7] {
            let n = 2 * m;
            // stage values with zeros of both signs, tiny and large entries
            let k: Vec<f64> = (0..N_STAGES * n)
                .map(|i| match i % 7 {
                    0 => 0.0,
                    1 => -0.0,
                    2 => 1e-300 * (i as f64),
                    3 => -(i as f64).sqrt(),
                    _ => 1.0 / (i as f64 + 0.5),
                })
                .collect();
            // a larger, stale packed array, as a renewed integrator has
            let mut kp = vec![f64::NAN; packed::packed_len(n) + 64];
            for (s, ks) in k.chunks_exact(n).enumerate() {
                packed::pack(&mut kp, s, ks);
            }
            let mut naive = vec![0.0; n];
            for &j in &nonzero {
                for (x, kj) in naive.iter_mut().zip(&k[j * n..(j + 1) * n]) {
                    *x += c[j] * kj;
                }
            }
            let h = 0.3;
            let mut scaled = vec![f64::NAN; n];
            packed::sum_times::<R>(&mut scaled, &kp, h);
            let naive_h: Vec<f64> = naive.iter().map(|x| x * h).collect();
            assert_eq!(bits(&scaled), bits(&naive_h), "sum × h, m = {m}");
            let z: Vec<f64> = (0..n)
                .map(|i| if i % 2 == 0 { -0.0 } else { 0.25 * i as f64 })
                .collect();
            let naive_y: Vec<f64> = z.iter().zip(&naive).map(|(zi, yi)| zi + h * yi).collect();
            let (mut y, mut ku) = (vec![f64::NAN; n], vec![f64::NAN; m]);
            packed::combine::<R>(&mut y, &mut ku, &z, h, &kp);
            assert_eq!(bits(&y), bits(&naive_y), "combine, m = {m}");
            assert_eq!(bits(&ku), bits(&naive_y[m..]), "velocity half, m = {m}");
            // the stage-after-stage loop of the longer states gives the same bits
            let (mut y, mut ku) = (vec![f64::NAN; n], vec![f64::NAN; m]);
            packed::combine_plain(&mut y, &mut ku, &z, h, c, &k);
            assert_eq!(bits(&y), bits(&naive_y), "plain combine, m = {m}");
            assert_eq!(
                bits(&ku),
                bits(&naive_y[m..]),
                "plain velocity half, m = {m}"
            );
        }
    }
    check::<RowA1>(A[1]);
    check::<RowA2>(A[2]);
    check::<RowA3>(A[3]);
    check::<RowA4>(A[4]);
    check::<RowA5>(A[5]);
    check::<RowA6>(A[6]);
    check::<RowA7>(A[7]);
    check::<RowA8>(A[8]);
    check::<RowA9>(A[9]);
    check::<RowA10>(A[10]);
    check::<RowA11>(A[11]);
    check::<RowA12>(A[12]);
    check::<RowA13>(A[13]);
    check::<RowA14>(A[14]);
    check::<RowA15>(A[15]);
    check::<RowD0>(&D[0][..]);
    check::<RowD1>(&D[1][..]);
    check::<RowD2>(&D[2][..]);
    check::<RowD3>(&D[3][..]);
    check::<RowE5>(&E5[..]);
    check::<RowE3>(&E3[..]);
}

/// The error estimates are summed on the stages where either weight is nonzero, which are the
/// same for both: summing them apart gives the bits of the joint loop.
#[test]
fn error_weights_are_nonzero_on_the_same_stages() {
    for j in 0..E5.len() {
        assert_eq!(E5[j] != 0.0, E3[j] != 0.0, "stage {j}");
    }
}

/// The first step of two beads that touch at `t = 0` (`δ = 0`) and close at speed 1 (rtol
/// 1e-8, atol 1e-12), proposed at `h0` and marked `rough`.
fn first_onset_step(chain: &Chain, h0: f64, rough: Rough) -> Dop853 {
    let (u, v) = striker(2, 1.0);
    let sys = ChainRange::whole(chain);
    let mut ig = Dop853::new(2, tolerances(chain, &u, &v, 1e-8, 1e-12));
    ig.reset(&sys, 0.0, &u, &v);
    ig.set_step_size(h0);
    ig.set_rough(rough);
    ig.step(&sys, 10.0).expect("step");
    ig.set_rough(Rough::Smooth);
    ig
}

/// Regression (issue 33): a rejected step at the onset of a contact force shrank by the smooth
/// exponent `err^{−1/8}`, although its error grows like `hⁿ` there, and took five rejections
/// (each 12 right-hand sides) where one suffices: every closing of a chain with gaps of 0.1 paid
/// them. Two beads closing at `δ = 0` (n = 2.5), first step proposed at 0.01 (about 17× the
/// longest step the tolerance allows there): marked [`Rough::Onset`] it is rejected once;
/// marked [`Rough::Kink`] (the smooth exponent) at least three times. Either accepted step must
/// agree with a tight run to its tolerance (abs 1e-7 on velocities of order 1, rtol 1e-8).
#[test]
fn onset_step_shrinks_by_its_own_order_not_the_smooth_one() {
    let chain = uniform_chain(2);
    let onset = first_onset_step(&chain, 0.01, Rough::Onset(2.5));
    let kink = first_onset_step(&chain, 0.01, Rough::Kink);
    assert_eq!(
        onset.stats().rejected,
        1,
        "onset-aware shrink: one rejection"
    );
    let rej_kink = kink.stats().rejected;
    assert!(rej_kink >= 3, "smooth shrink: {rej_kink} rejections");
    let (u, v) = striker(2, 1.0);
    for ig in [onset, kink] {
        let t1 = ig.t();
        let tight = run(&chain, &u, &v, tolerances(&chain, &u, &v, 1e-13, 1e-15), t1);
        for (a, b) in ig.state()[2..].iter().zip(&tight.state()[2..]) {
            assert!((a - b).abs() <= 1e-7, "v {a} vs tight {b} at t = {t1}");
        }
    }
}

/// Regression (issue 33, the onset retry above): for `n ≥ 8` the onset `δ^{n−1}` is as smooth
/// as the method sees, its error grows like the estimator's `h⁸`, and a retry by `err^{−1/n}`
/// shrank less than the smooth one (n = 10: `err^{−1/10}`), taking more rejections than before.
/// It now retries as a smooth step: two beads at n = 10, a = 0.4, closing at speed 1, first step
/// proposed at 0.5: as many rejections and the same accepted step as with [`Rough::Kink`] (the
/// smooth factor), bit for bit.
#[test]
fn onset_retry_of_a_smooth_onset_is_the_smooth_one() {
    let mut chain = uniform_chain(2);
    chain.exponent = vec![10.0];
    let onset = first_onset_step(&chain, 0.5, Rough::Onset(10.0));
    let kink = first_onset_step(&chain, 0.5, Rough::Kink);
    assert!(
        kink.stats().rejected >= 1,
        "the test needs a rejected first step"
    );
    assert_eq!(
        (onset.t(), onset.stats().rejected),
        (kink.t(), kink.stats().rejected)
    );
}
