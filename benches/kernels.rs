//! Kernel benchmarks (criterion): force/Jacobian evaluation (the two-pass force kernel against
//! the one-pass loop it replaced), one Radau step per cluster size,
//! event-queue operations, free-flight gap prediction, and the cost of declared effects
//! (precompression, field) against the same chain without them.
//! Run: `cargo bench --bench kernels -- --warm-up-time 1 --measurement-time 2`.

use beadchain::engine::hybrid::free::first_upward_crossing;
use beadchain::integrate::radau5::Radau5;
use beadchain::integrate::{ChainRange, Integrator, Tolerances};
use beadchain::linalg::SolverKind;
use beadchain::model::{Chain, Scales};
use criterion::{black_box, criterion_group, criterion_main, BenchmarkId, Criterion};
use ordered_float::OrderedFloat;
use priority_queue::PriorityQueue;
use std::cmp::Reverse;

fn chain(n: usize, exp: f64, pre: bool, field: bool) -> Chain {
    Chain {
        mass: vec![1.0; n],
        exponent: vec![exp; n - 1],
        prefactor: vec![1.0; n - 1],
        precompression: pre.then(|| vec![0.0; n - 1]),
        field: field.then(|| vec![0.0; n]),
        left_wall: None,
        right_wall: None,
        hard: None,
        damping: None,
    }
}

/// A compressed state: every contact closed with overlap between 0.05 and 0.15.
fn compressed(n: usize) -> (Vec<f64>, Vec<f64>) {
    let u: Vec<f64> = (0..n)
        .map(|i| -0.1 * i as f64 + 0.05 * (i % 3) as f64)
        .collect();
    let v: Vec<f64> = (0..n).map(|i| 0.3 * ((i % 5) as f64 - 2.0)).collect();
    (u, v)
}

fn forces(c: &mut Criterion) {
    let mut g = c.benchmark_group("force_jacobian");
    for &exp in &[2.5, 2.7] {
        for &n in &[4usize, 16, 1000] {
            let ch = chain(n, exp, false, false);
            let (u, _) = compressed(n);
            let mut acc = vec![0.0; n];
            let mut k = vec![0.0; n + 1];
            g.bench_with_input(BenchmarkId::new(format!("accel_n{exp}"), n), &n, |b, _| {
                b.iter(|| ch.accel(0, black_box(&u), &mut acc))
            });
            g.bench_with_input(
                BenchmarkId::new(format!("accel_one_pass_n{exp}"), n),
                &n,
                |b, _| b.iter(|| ch.accel_one_pass(0, black_box(&u), &mut acc)),
            );
            g.bench_with_input(
                BenchmarkId::new(format!("accel_stiffness_n{exp}"), n),
                &n,
                |b, _| b.iter(|| ch.accel_stiffness(0, black_box(&u), &mut acc, &mut k)),
            );
        }
    }
    g.finish();
}

fn effects(c: &mut Criterion) {
    let mut g = c.benchmark_group("declared_effects");
    let n = 1000;
    let (u, _) = compressed(n);
    let mut acc = vec![0.0; n];
    for (name, pre, field) in [
        ("none", false, false),
        ("precompression", true, false),
        ("field", false, true),
        ("both", true, true),
    ] {
        let ch = chain(n, 2.5, pre, field);
        g.bench_function(name, |b| b.iter(|| ch.accel(0, black_box(&u), &mut acc)));
    }
    g.finish();
}

fn radau_step(c: &mut Criterion) {
    let mut g = c.benchmark_group("radau5_step_per_cluster_size");
    for &m in &[2usize, 4, 8, 16, 64] {
        let ch = chain(m, 2.5, false, false);
        let sys = ChainRange::whole(&ch);
        let (u, v) = compressed(m);
        let tol = Tolerances {
            rtol: 1e-8,
            atol: 1e-10,
            scales: Scales {
                length: 0.1,
                velocity: 1.0,
                energy: 0.0,
                mass: 0.0,
            },
            v_frame: 0.0,
            u_origin: 0.0,
            dissipation: Default::default(),
        };
        let mut r = Radau5::new(m, tol, SolverKind::Auto);
        r.reset(&sys, 0.0, &u, &v);
        r.step(&sys, f64::INFINITY).expect("step");
        let saved = r.save();
        g.bench_with_input(BenchmarkId::from_parameter(m), &m, |b, _| {
            b.iter(|| {
                r.load(&saved).expect("same integrator");
                r.step(&sys, f64::INFINITY).expect("step")
            })
        });
    }
    g.finish();
}

type Prio = Reverse<(OrderedFloat<f64>, u8, u64, u64)>;

fn event_queue(c: &mut Criterion) {
    let mut g = c.benchmark_group("event_queue");
    let n = 10_000u32;
    let times: Vec<f64> = (0..n)
        .map(|i| ((i as f64) * 0.618_033_988_7).fract())
        .collect();
    g.bench_function("push_10k_then_pop_all", |b| {
        b.iter(|| {
            let mut q: PriorityQueue<u32, Prio> = PriorityQueue::with_capacity(n as usize);
            for (i, t) in times.iter().enumerate() {
                q.push(i as u32, Reverse((OrderedFloat(*t), 2, i as u64, i as u64)));
            }
            let mut s = 0.0;
            while let Some((_, Reverse((t, ..)))) = q.pop() {
                s += t.0;
            }
            s
        })
    });
    let mut q: PriorityQueue<u32, Prio> = PriorityQueue::with_capacity(n as usize);
    for (i, t) in times.iter().enumerate() {
        q.push(i as u32, Reverse((OrderedFloat(*t), 2, i as u64, i as u64)));
    }
    let mut k = 0u32;
    g.bench_function("reprioritize_one_of_10k", |b| {
        b.iter(|| {
            k = (k + 7919) % n;
            let t = times[k as usize] + 1.0;
            q.push(k, Reverse((OrderedFloat(t), 2, k as u64, k as u64)));
        })
    });
    g.finish();
}

fn free_flight(c: &mut Criterion) {
    c.bench_function("free_flight_gap_prediction", |b| {
        b.iter(|| first_upward_crossing(black_box(-0.3), black_box(0.7), black_box(-0.2)))
    });
}

criterion_group!(
    benches,
    forces,
    effects,
    radau_step,
    event_queue,
    free_flight
);
criterion_main!(benches);
