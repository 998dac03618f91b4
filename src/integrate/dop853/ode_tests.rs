//! Tests of [`Dop853`] on small ODEs with known behaviour (coefficients, accuracy against an
//! exact solution, step-size bookkeeping, failure modes); the chain tests are in the parent.

use super::coefficients::{A, C, E3, E5};
use super::Dop853;
use crate::integrate::{IntegrationError, Integrator, System, Tolerances};
use crate::model::Scales;

/// `ü = −u` (one unit-mass bead on a linear spring): exact solution known.
struct Oscillator;
impl System for Oscillator {
    fn len(&self) -> usize {
        1
    }
    fn mass(&self) -> &[f64] {
        &[1.0]
    }
    fn accel(&self, u: &[f64], _v: &[f64], acc: &mut [f64]) -> f64 {
        acc[0] = -u[0];
        0.0
    }
    fn accel_stiffness(
        &self,
        u: &[f64],
        _v: &[f64],
        acc: &mut [f64],
        k: &mut [f64],
        _kv: &mut [f64],
    ) -> f64 {
        acc[0] = -u[0];
        k.fill(0.0);
        0.0
    }
}

/// `ü = 2u³`, `u(0) = v(0) = 1`: `u = 1/(1 − t)` blows up at `t = 1`; the force is NaN
/// beyond `u = 1e6` when `nan_above` is set.
struct Blowup {
    nan_above: bool,
}
impl System for Blowup {
    fn len(&self) -> usize {
        1
    }
    fn mass(&self) -> &[f64] {
        &[1.0]
    }
    fn accel(&self, u: &[f64], _v: &[f64], acc: &mut [f64]) -> f64 {
        acc[0] = if self.nan_above && u[0] > 1e6 {
            f64::NAN
        } else {
            2.0 * u[0].powi(3)
        };
        0.0
    }
    fn accel_stiffness(
        &self,
        u: &[f64],
        v: &[f64],
        acc: &mut [f64],
        k: &mut [f64],
        _kv: &mut [f64],
    ) -> f64 {
        self.accel(u, v, acc);
        k.fill(0.0);
        0.0
    }
}

fn unit_tol(rtol: f64, atol: f64) -> Tolerances {
    Tolerances {
        rtol,
        atol,
        scales: Scales {
            length: 1.0,
            velocity: 1.0,
            energy: 0.0,
            mass: 0.0,
        },
        v_frame: 0.0,
        u_origin: 0.0,
        dissipation: Default::default(),
    }
}

#[test]
fn tableau_is_consistent() {
    // Row sums of A equal the nodes; b, b̂₅, b̂₃ each sum to 1 (abs 1e-14, coefficients O(50)).
    for (s, row) in A.iter().enumerate().skip(1) {
        let sum: f64 = row.iter().sum();
        assert!(
            (sum - C[s]).abs() <= 1e-14,
            "row {s}: {sum} vs c = {}",
            C[s]
        );
    }
    assert!((A[12].iter().sum::<f64>() - 1.0).abs() <= 1e-14);
    assert!(E5.iter().sum::<f64>().abs() <= 1e-14, "sum E5");
    assert!(E3.iter().sum::<f64>().abs() <= 1e-14, "sum E3");
}

#[test]
fn oscillator_matches_exact_solution_and_dense_output() {
    let sys = Oscillator;
    let mut ig = Dop853::new(1, unit_tol(1e-10, 1e-12));
    ig.reset(&sys, 0.0, &[1.0], &[0.0]);
    let mut z = [0.0; 2];
    let mut worst_dense: f64 = 0.0;
    while ig.t() < 10.0 {
        ig.step(&sys, 10.0).expect("step");
        for q in 1..8 {
            let t = ig.t_prev() + (ig.t() - ig.t_prev()) * q as f64 / 8.0;
            ig.dense(t, &mut z);
            worst_dense = worst_dense.max((z[0] - t.cos()).abs().max((z[1] + t.sin()).abs()));
        }
    }
    let z = ig.state();
    // Global error at t = 10 after ~10 steps per unit time: abs 1e-8 (rtol 1e-10).
    assert!((z[0] - 10f64.cos()).abs() <= 1e-8, "u = {}", z[0]);
    assert!((z[1] + 10f64.sin()).abs() <= 1e-8, "v = {}", z[1]);
    // The 7th-order interpolant is as accurate as the steps: abs 1e-8.
    assert!(worst_dense <= 1e-8, "dense error {worst_dense:e}");
    let st = ig.stats();
    assert_eq!(
        st.rhs_evals,
        2 + 12 * (st.steps + st.rejected) + 3 * st.steps
    );
    assert_eq!(st.bead_steps, st.steps);
}

#[test]
fn landing_on_t_bound_does_not_shrink_the_next_step() {
    let sys = Oscillator;
    let mut ig = Dop853::new(1, unit_tol(1e-8, 1e-10));
    ig.reset(&sys, 0.0, &[1.0], &[0.0]);
    ig.step(&sys, f64::INFINITY).expect("step");
    let proposal = ig.step_size();
    // A tiny step to an event time just ahead, then the free step size is kept.
    let t_event = ig.t() + 1e-6 * proposal;
    assert_eq!(ig.step(&sys, t_event), Ok(t_event));
    assert!(
        ig.step_size() >= proposal,
        "{} < {proposal}",
        ig.step_size()
    );
}

#[test]
fn blowup_reports_step_too_small() {
    let sys = Blowup { nan_above: false };
    let mut ig = Dop853::new(1, unit_tol(1e-8, 1e-10));
    ig.reset(&sys, 0.0, &[1.0], &[1.0]);
    let res = (0..100_000).find_map(|_| ig.step(&sys, 2.0).err());
    match res {
        // The numerical blow-up time differs from 1 by the global error: abs 1e-6.
        Some(IntegrationError::StepTooSmall { t, .. }) => {
            assert!((t - 1.0).abs() <= 1e-6, "t = {t}")
        }
        other => panic!("expected StepTooSmall, got {other:?}"),
    }
}

#[test]
fn nan_force_and_nan_state_report_non_finite() {
    let sys = Blowup { nan_above: true };
    let mut ig = Dop853::new(1, unit_tol(1e-8, 1e-10));
    ig.reset(&sys, 0.0, &[1.0], &[1.0]);
    let res = (0..100_000).find_map(|_| ig.step(&sys, 2.0).err());
    assert!(
        matches!(res, Some(IntegrationError::NonFinite { .. })),
        "got {res:?}"
    );
    assert!(
        ig.state().iter().all(|x| x.is_finite()),
        "state kept finite"
    );

    let osc = Oscillator;
    let mut ig = Dop853::new(1, unit_tol(1e-8, 1e-10));
    ig.reset(&osc, 0.0, &[f64::NAN], &[0.0]);
    assert_eq!(
        ig.step(&osc, 1.0),
        Err(IntegrationError::NonFinite { t: 0.0 })
    );
}
