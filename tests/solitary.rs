//! Exact solitary waves as initial condition (`[initial].solitary`, issue 35 part 1): the wave
//! of the discrete chain travels unchanged, at constant speed, with no radiation; its speed
//! follows `c ∝ v_m^{(n−2)/n}`; `⟨K⟩/⟨E⟩ = n/(n+2)` (virial theorem); head-on collisions of
//! equal waves stay mirror-symmetric. Longer versions: `validation/solitary.sh`.

mod common;
use beadchain::engine::{Recorder, RunConfig};
use beadchain::integrate::Method;
use beadchain::linalg::SolverKind;
use beadchain::scene::{parse_str, Engine, Scene};
use beadchain::studies::solitary::{UnitProfile, Wave};
use std::path::Path;

/// A uniform dimensionless chain of `nb` beads with the given `[initial].solitary` value.
fn scene(nb: usize, n: f64, a: f64, solitary: &str) -> Scene {
    let text = format!(
        "[chain]\nbeads = {nb}\nexponent = {n}\nprefactor = {a}\n[initial]\nsolitary = {solitary}\n[run]\nuntil = 1.0\n"
    );
    parse_str(&text, Path::new("."), "test.toml").expect("scene parses")
}

/// Dense DOP853 run with frames every `every` up to `until`.
fn run(s: &Scene, until: f64, every: f64, rtol: f64) -> Recorder {
    let cfg = RunConfig {
        engine: Engine::Dense,
        method: Method::Dop853,
        rtol,
        atol: rtol * 1e-2,
        until,
        every: Some(every),
        solver: SolverKind::Auto,
        max_steps: Some(20_000_000),
    };
    common::run(s, &cfg).1
}

fn wave(n: f64, a: f64, v_m: f64) -> Wave {
    Wave::with_peak_velocity(UnitProfile::compute(n).unwrap(), 1.0, a, v_m).unwrap()
}

#[test]
fn probe() {
    let (n, a, v_m) = (2.5, 1.0, 1.0);
    let w = wave(n, a, v_m);
    let c = w.speed;
    let s = scene(80, n, a, "{ at = 15, velocity = 1.0 }");
    for rtol in [1e-10, 1e-12, 1e-13] {
        let t0 = std::time::Instant::now();
        let travel = 50.0;
        let rec = run(&s, travel / c, 0.25 / c, rtol);
        let mut err = 0.0_f64;
        for f in [0, 1, 2, 100, 200] {
            let k = (0..80)
                .max_by(|&i, &j| rec.v[f][i].total_cmp(&rec.v[f][j]))
                .unwrap();
            eprintln!(
                "t {} argmax {k} vmax {} pred {}",
                rec.t[f],
                rec.v[f][k],
                15.0 + c * rec.t[f]
            );
        }
        for (f, t) in rec.t.iter().enumerate() {
            for k in 0..80 {
                let x = k as f64 - 15.0 - c * t;
                err = err.max((rec.v[f][k] - w.velocity(x)).abs());
            }
        }
        eprintln!(
            "rtol {rtol:e}: max |v - exact| {err:e}  frames {} t {:?}",
            rec.t.len(),
            t0.elapsed()
        );
    }
}
#[test]
fn probe2() {
    let w = wave(2.5, 1.0, 1.0);
    let s = scene(40, 2.5, 1.0, "{ at = 15, velocity = 1.0 }");
    eprintln!("c {} lambda {}", w.speed, w.scale);
    for k in 5..26 {
        eprintln!(
            "{k} u {:e} v {:e} exact {:e} {:e}",
            s.u0[k],
            s.v0[k],
            w.velocity(k as f64 - 15.0),
            w.velocity(k as f64 - 15.0 + 0.3)
        );
    }
}
