//! The dense engine: the whole chain integrated as one ODE system `ż = F(z)` (paper appendix,
//! eq. A.3) with Radau IIA or DOP853, no events. Frames come from the integrator's continuous
//! output at the requested times.

use super::checkpoint::{DenseState, EngineState};
use super::{EngineError, Observer, RunConfig, RunOutcome};
use crate::integrate::auto::Auto;
use crate::integrate::dop853::Dop853;
use crate::integrate::radau5::Radau5;
use crate::integrate::verlet::Verlet;
use crate::integrate::{dissipated_at, ChainRange, Integrator, Method, System, Tolerances};
use crate::scene::Scene;
use std::time::Instant;

/// Builds the integrator for `m` beads.
pub fn make_integrator(cfg: &RunConfig, m: usize, tol: Tolerances) -> Box<dyn Integrator> {
    match cfg.method {
        Method::Radau5 => Box::new(Radau5::new(m, tol, cfg.solver)),
        Method::Dop853 => Box::new(Dop853::new(m, tol)),
        // Fixed step `rtol · L/V` (see `integrate::verlet`).
        Method::Verlet => Box::new(Verlet::new(m, tol)),
        Method::Auto => Box::new(Auto::new(m, tol, cfg.solver, false)),
    }
}

/// Runs the whole chain to `cfg.until`, from the start or from a checkpointed state.
pub fn run_from(
    scene: &Scene,
    cfg: &RunConfig,
    from: Option<&DenseState>,
    obs: &mut dyn Observer,
) -> Result<RunOutcome, EngineError> {
    let chain = &scene.chain;
    let n = chain.len();
    let sys = ChainRange::whole(chain);
    let tol = Tolerances {
        rtol: cfg.rtol,
        atol: cfg.atol,
        scales: chain.scales(&scene.u0, &scene.v0),
        v_frame: 0.0,
    };
    let start = Instant::now();
    let mut integ = make_integrator(cfg, n, tol);
    let mut next = 1u64;
    let mut last_frame_t = 0.0;
    match from {
        None => {
            integ.reset(&sys, 0.0, &scene.u0, &scene.v0);
            if chain.is_dissipative() {
                obs.dissipated(0.0, 0.0)?;
            }
            obs.frame(0.0, &scene.u0, &scene.v0)?;
        }
        Some(d) => {
            integ.load(&d.integ);
            next = d.next_frame;
            last_frame_t = d.last_frame_t;
        }
    }
    let mut buf = vec![0.0; 2 * n];
    while integ.t() < cfg.until {
        super::poll(obs, integ.t(), || {
            EngineState::Dense(DenseState {
                integ: integ.save(),
                next_frame: next,
                last_frame_t,
            })
        })?;
        integ.step(&sys as &dyn System, cfg.until)?;
        if let Some(max) = cfg.max_steps {
            if integ.stats().steps >= max {
                return Err(crate::integrate::IntegrationError::Budget(max).into());
            }
        }
        loop {
            let tf = cfg.frame_time(next);
            if tf > integ.t() || last_frame_t >= cfg.until {
                break;
            }
            integ.dense(tf, &mut buf);
            if chain.is_dissipative() {
                obs.dissipated(tf, dissipated_at(&*integ, &sys, tf))?;
            }
            obs.frame(tf, &buf[..n], &buf[n..])?;
            last_frame_t = tf;
            next += 1;
        }
    }
    let z = integ.state();
    let (u, v) = (z[..n].to_vec(), z[n..].to_vec());
    Ok(RunOutcome {
        stats: integ.stats().clone(),
        t_end: integ.t(),
        wall_seconds: start.elapsed().as_secs_f64(),
        energy_initial: chain.energy(&scene.u0, &scene.v0),
        energy_final: chain.energy(&u, &v),
        energy_scale: chain
            .energy_scale(&scene.u0, &scene.v0)
            .max(chain.energy_scale(&u, &v)),
        momentum_initial: chain.momentum(&scene.v0),
        momentum_final: chain.momentum(&v),
        events_by_kind: Vec::new(),
        largest_cluster: n as u64,
        late_merges: 0,
        implicit_steps: integ.implicit_steps(),
        dissipated: integ.dissipated().1,
        u,
        v,
    })
}
