//! A renewed integrator ([`Integrator::renew`]: the hybrid engine's reuse of a removed
//! cluster's integrator) is the integrator `new` builds: after the same `reset` it saves the
//! same state, takes the same steps bit for bit, and ends with the same state and counters,
//! whether it shrinks or grows, ran conservative or damped steps before, and (Radau IIA) with
//! either linear solver.

use super::radau5::Radau5;
use super::test_util::{striker, uniform_chain};
use super::verlet::Verlet;
use super::{ChainRange, Integrator, Tolerances};
use crate::linalg::SolverKind;
use crate::model::{Chain, Damping, DampingLaw};

/// Builds a method's integrator for `m` beads.
type Make = dyn Fn(usize, Tolerances) -> Box<dyn Integrator>;

/// The tolerances of these tests: `rtol`, `atol = rtol/10⁴` on the chain's scales.
fn tol_of(chain: &Chain, u: &[f64], v: &[f64], rtol: f64) -> Tolerances {
    Tolerances {
        rtol,
        atol: rtol * 1e-4,
        scales: chain.scales(u, v),
        v_frame: 0.0,
        u_origin: 0.0,
        dissipation: Default::default(),
    }
}

/// `beads` beads as [`uniform_chain`], with viscoelastic contacts where `damped`.
fn chain(beads: usize, damped: bool) -> Chain {
    let mut c = uniform_chain(beads);
    if damped {
        c.damping = Some(Damping {
            law: DampingLaw::Viscoelastic,
            contact: vec![0.3; beads - 1],
            left_wall: 0.0,
            right_wall: 0.0,
        });
    }
    c
}

/// Runs an integrator of `make` on `from` beads, renews it for `to` beads and checks it
/// against a new one (module docs).
fn check(make: &Make, (from, to): (usize, usize), damped: bool, rtol: f64) {
    let bits = |x: &[f64]| x.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
    let (c0, c1) = (chain(from, damped), chain(to, damped));
    let ((u0, v0), (u1, v1)) = (striker(from, 1.0), striker(to, 0.7));
    let (s0, s1) = (ChainRange::whole(&c0), ChainRange::whole(&c1));
    let mut a = make(from, tol_of(&c0, &u0, &v0, rtol));
    a.reset(&s0, 0.0, &u0, &v0);
    for _ in 0..25 {
        a.step(&s0, 1e4).expect("steps");
    }
    let tol = tol_of(&c1, &u1, &v1, rtol);
    assert!(a.renew(to, tol), "renews");
    let mut b = make(to, tol);
    a.reset(&s1, 0.5, &u1, &v1);
    b.reset(&s1, 0.5, &u1, &v1);
    assert_eq!(
        a.save(),
        b.save(),
        "{from} → {to} beads: before the first step"
    );
    for _ in 0..40 {
        let t = a.step(&s1, 1e4).expect("steps");
        assert_eq!(t.to_bits(), b.step(&s1, 1e4).expect("steps").to_bits());
        assert_eq!(bits(a.state()), bits(b.state()), "{from} → {to} beads");
    }
    assert_eq!(a.save(), b.save(), "{from} → {to} beads: after 40 steps");
    assert_eq!(a.stats(), b.stats());
    assert_eq!(a.dissipated(), b.dissipated());
}

#[test]
fn renewed_radau5_is_bit_identical_to_a_new_one() {
    for solver in [SolverKind::Direct, SolverKind::Faer, SolverKind::Auto] {
        let make = move |m, tol| Box::new(Radau5::new(m, tol, solver)) as Box<dyn Integrator>;
        for damped in [false, true] {
            check(&make, (6, 4), damped, 1e-8);
            check(&make, (3, 7), damped, 1e-8);
            check(&make, (5, 5), damped, 1e-8);
        }
    }
}

#[test]
fn renewed_verlet_is_bit_identical_to_a_new_one() {
    let make = |m, tol| Box::new(Verlet::new(m, tol)) as Box<dyn Integrator>;
    check(&make, (6, 4), false, 1e-2);
    check(&make, (3, 7), false, 1e-2);
}
