//! Discrete breathers: time-periodic solutions of the full nonlinear chain (issue 35, part 4).
//!
//! The equation of motion (paper eq. 7) `M ü = F(u)` is integrated by the dense engine (DOP853,
//! `rtol` 1e-12 by default): the period map `P_T(u, v) = (u(T), v(T))`. A breather of
//! frequency `ω = 2π/T` is a fixed point `P_T(x) = x`.
//!
//! **Half-period shooting.** The chain is time-reversible, so a breather that starts from rest,
//! `v(0) = 0`, and is at rest again at `T/2` is periodic: `u(T/2 + s) = u(T/2 − s)` and
//! `u(−s) = u(s)` give `u(T) = u(0)`, `v(T) = 0`. The unknowns are the displacements `u(0)`
//! (N) and the period `T`; the equations are `v(T/2) = 0` (N) and one constraint ([`Constraint`]):
//! the period fixed (continuation in frequency) or one bead's displacement fixed (the amplitude,
//! at the start near a band edge). Starting from rest removes the time-shift degeneracy. Newton's
//! method uses a Jacobian by central differences of the half-period map (2N + 2 runs).
//!
//! **Seed and continuation.** The linear mode `x_k` of frequency `ω_k` about the static
//! equilibrium `u*` ([`crate::studies::modes`]) seeds `u = u* + A x_k / x_{k,b}` (bead `b` the
//! mode's largest displacement) with `T = 2π/ω_k`; at small `A` the solution's frequency tends
//! to `ω_k` (the breather bifurcates from the mode). From there the frequency is stepped to the
//! target with a secant predictor ([`continue_to`]).
//!
//! **Floquet multipliers.** The monodromy matrix `∂P_T/∂(u, v)` (2N × 2N) by central
//! differences (4N runs) and its eigenvalues ([`super::floquet`]). For the conservative (Hamiltonian)
//! chain they come in reciprocal pairs `λ, 1/λ` (and conjugates) and include a pair at 1 (the
//! time shift and the energy / frequency direction, a Jordan block: the two computed values
//! split by about the square root of the differences' error, their mean and product stay at 1).
//! The breather is linearly stable when every multiplier lies on the unit circle.

use crate::engine::{self, Recorder, RunConfig};
use crate::integrate::{default_atol, Method};
use crate::scene::{Engine as EngineKind, Scene};
use crate::studies::equilibrium::equilibrium;
use crate::studies::modes::{linearize, solve};
use faer::linalg::solvers::Solve;
use std::f64::consts::PI;
use std::fmt;

/// A breather computation that failed (Newton did not converge, a run failed, …).
#[derive(Debug, Clone, PartialEq)]
pub struct BreatherError(pub String);

impl fmt::Display for BreatherError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BreatherError {}

fn err(msg: impl Into<String>) -> BreatherError {
    BreatherError(msg.into())
}

/// The extra equation of the half-period shooting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Constraint {
    /// The period is fixed at this value (continuation in frequency).
    Period(f64),
    /// Bead `bead` starts at displacement `value` (the amplitude is fixed, the period free).
    Displacement {
        /// The bead.
        bead: usize,
        /// Its displacement `u_b(0)`.
        value: f64,
    },
}

/// A periodic solution from rest: `u(0)`, `v(0) = 0`, period `T`.
#[derive(Clone, Debug, PartialEq)]
pub struct Breather {
    /// Displacements at `t = 0` (N).
    pub u: Vec<f64>,
    /// Period `T`.
    pub period: f64,
    /// `max_i |v_i(T/2)|` at convergence (the shooting residual).
    pub half_residual: f64,
    /// Newton iterations.
    pub iterations: usize,
}

impl Breather {
    /// Angular frequency `2π/T`.
    pub fn frequency(&self) -> f64 {
        2.0 * PI / self.period
    }
}

/// The shooting machinery: the scene (its initial state replaced at each run) and the dense
/// engine's configuration.
pub struct Shooter {
    scene: Scene,
    cfg: RunConfig,
    /// The static equilibrium `u*` the breather oscillates about.
    pub u_eq: Vec<f64>,
    /// Engine runs so far.
    pub runs: std::cell::Cell<u64>,
}

impl Shooter {
    /// The shooter for `scene` with the dense engine, DOP853 at `rtol` (atol `rtol/10⁴`).
    pub fn new(scene: &Scene, rtol: f64) -> Result<Self, BreatherError> {
        if scene.chain.has_hard() || scene.chain.damping.is_some() {
            return Err(err(format!(
                "{}: breathers need a conservative chain of soft contacts (no [hard], no damping)",
                scene.name
            )));
        }
        let eq = equilibrium(&scene.chain, &scene.u0, None)
            .map_err(|e| err(format!("{}: static equilibrium: {e}", scene.name)))?;
        let lin =
            linearize(&scene.chain, &eq.u).map_err(|e| err(format!("{}: {e}", scene.name)))?;
        let m = solve(&lin, None).map_err(|e| err(format!("{}: {e}", scene.name)))?;
        let top = m.omega2.iter().fold(0.0f64, |t, x| t.max(x.abs()));
        if m.omega2.iter().any(|x| *x <= 1e-12 * top) {
            return Err(err(format!(
                "{}: the chain has a zero mode at its equilibrium (a free end or an open contact): no isolated breathers; hold both ends with walls",
                scene.name
            )));
        }
        let mut cfg = RunConfig::from_scene(scene);
        cfg.engine = EngineKind::Dense;
        cfg.method = Method::Dop853;
        cfg.rtol = rtol;
        cfg.atol = default_atol(rtol);
        cfg.every = None;
        cfg.max_steps = None;
        Ok(Self {
            scene: scene.clone(),
            cfg,
            u_eq: eq.u,
            runs: std::cell::Cell::new(0),
        })
    }

    /// Bead masses.
    pub fn masses(&self) -> &[f64] {
        &self.scene.chain.mass
    }

    /// The chain's accelerations at displacements `u` (paper eq. 7; fields and walls
    /// included).
    pub fn accel(&self, u: &[f64]) -> Vec<f64> {
        let mut acc = vec![0.0; u.len()];
        self.scene.chain.accel(0, u, &mut acc);
        acc
    }

    /// Number of beads.
    pub fn len(&self) -> usize {
        self.u_eq.len()
    }

    /// Whether the chain has no beads (never: scenes have at least one).
    pub fn is_empty(&self) -> bool {
        self.u_eq.is_empty()
    }

    /// The state after time `t` from `(u, v)`.
    pub fn flow(
        &self,
        u: &[f64],
        v: &[f64],
        t: f64,
    ) -> Result<(Vec<f64>, Vec<f64>), BreatherError> {
        let mut s = self.scene.clone();
        s.u0 = u.to_vec();
        s.v0 = v.to_vec();
        let mut cfg = self.cfg.clone();
        cfg.until = t;
        let mut rec = Recorder::default();
        let out = engine::run(&s, &cfg, &mut rec)
            .map_err(|e| err(format!("{}: engine run to t = {t}: {e}", self.scene.name)))?;
        self.runs.set(self.runs.get() + 1);
        let last = rec
            .t
            .len()
            .checked_sub(1)
            .ok_or_else(|| err("the run recorded no frame"))?;
        if (rec.t[last] - t).abs() > 1e-12 * t.max(1.0)
            || (out.t_end - t).abs() > 1e-12 * t.max(1.0)
        {
            return Err(err(format!(
                "the run ended at {} instead of {t}",
                out.t_end
            )));
        }
        Ok((rec.u[last].clone(), rec.v[last].clone()))
    }

    /// The residuals of the half-period shooting at `(u, T)`: `v(T/2)` (N) and the constraint.
    fn residual(&self, u: &[f64], period: f64, c: Constraint) -> Result<Vec<f64>, BreatherError> {
        let zero = vec![0.0; u.len()];
        let (_, mut r) = self.flow(u, &zero, 0.5 * period)?;
        r.push(match c {
            Constraint::Period(t) => period - t,
            Constraint::Displacement { bead, value } => u[bead] - value,
        });
        Ok(r)
    }

    /// The amplitude `max_i |u_i − u*_i|` of displacements `u`.
    pub fn amplitude(&self, u: &[f64]) -> f64 {
        u.iter()
            .zip(&self.u_eq)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
    }

    /// Newton's method on the half-period shooting from `(u, T)` until `max |v(T/2)| ≤ tol`.
    pub fn newton(
        &self,
        u: &[f64],
        period: f64,
        c: Constraint,
        tol: f64,
    ) -> Result<Breather, BreatherError> {
        let nb = self.len();
        let mut x: Vec<f64> = u.iter().copied().chain([period]).collect();
        let mut r = self.residual(&x[..nb], x[nb], c)?;
        for it in 0..=12 {
            let res = r[..nb].iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if res <= tol && r[nb].abs() <= 1e-14 * period {
                return Ok(Breather {
                    u: x[..nb].to_vec(),
                    period: x[nb],
                    half_residual: res,
                    iterations: it,
                });
            }
            if it == 12 {
                break;
            }
            let jac = self.jacobian(&x, c)?;
            let rhs = faer::Mat::<f64>::from_fn(nb + 1, 1, |i, _| -r[i]);
            let dx = jac.partial_piv_lu().solve(&rhs);
            for i in 0..=nb {
                x[i] += dx[(i, 0)];
            }
            if !x.iter().all(|v| v.is_finite()) || x[nb] <= 0.0 {
                return Err(err(
                    "Newton's step left the admissible states (period <= 0)",
                ));
            }
            r = self.residual(&x[..nb], x[nb], c)?;
        }
        Err(err(format!(
            "{}: Newton's method did not converge in 12 iterations at T = {:.9} (residual {:.3e} > {tol:.1e})",
            self.scene.name,
            x[nb],
            r[..nb].iter().fold(0.0f64, |m, v| m.max(v.abs()))
        )))
    }

    /// Jacobian of the residual by central differences (steps `1e-6` times the amplitude, at
    /// least `1e-9`, and `1e-7 T`).
    fn jacobian(&self, x: &[f64], c: Constraint) -> Result<faer::Mat<f64>, BreatherError> {
        let nb = self.len();
        let h_u = (1e-6 * self.amplitude(&x[..nb])).max(1e-9);
        let mut jac = faer::Mat::<f64>::zeros(nb + 1, nb + 1);
        for j in 0..=nb {
            let h = if j < nb { h_u } else { 1e-7 * x[nb] };
            let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
            xp[j] += h;
            xm[j] -= h;
            let rp = self.residual(&xp[..nb], xp[nb], c)?;
            let rm = self.residual(&xm[..nb], xm[nb], c)?;
            for i in 0..=nb {
                jac[(i, j)] = (rp[i] - rm[i]) / (2.0 * h);
            }
        }
        Ok(jac)
    }

    /// The linear mode `k` about `u*`: its frequency and shape (`xᵀ M x = 1`).
    pub fn mode(&self, k: usize) -> Result<(f64, Vec<f64>), BreatherError> {
        let lin = linearize(&self.scene.chain, &self.u_eq).map_err(|e| err(e.to_string()))?;
        let m = solve(&lin, None).map_err(|e| err(e.to_string()))?;
        if k >= m.omega.len() {
            return Err(err(format!(
                "mode {k}: the chain has {} modes (0..{})",
                m.omega.len(),
                m.omega.len() - 1
            )));
        }
        Ok((m.omega[k], m.shapes[k].clone()))
    }

    /// The breather bifurcating from mode `k` at amplitude `amp` on the mode's largest bead
    /// (the period free).
    pub fn from_mode(&self, k: usize, amp: f64, tol: f64) -> Result<Breather, BreatherError> {
        let (w, x) = self.mode(k)?;
        if w <= 0.0 {
            return Err(err(format!(
                "mode {k} has zero frequency: no breather from it"
            )));
        }
        // Newton's residual is a velocity (max |v(T/2)|): a tolerance that is not small against
        // the seed's own velocities, about ω·amp, accepts the linear mode as it is (no
        // frequency shift, and the continuation's predictor divides by that shift)
        if tol > SEED_TOL_FRACTION * w * amp {
            return Err(err(format!(
                "Newton's tolerance {tol:.1e} is not small against the seed's velocities (omega·amplitude = {:.3e}; at most {SEED_TOL_FRACTION:.0e} of it): lower --tol (tol=) or raise --seed-amplitude (seed_amplitude=) to the scene's scale",
                w * amp
            )));
        }
        let b = (0..x.len())
            .max_by(|&i, &j| x[i].abs().total_cmp(&x[j].abs()))
            .unwrap_or(0);
        let u: Vec<f64> = (0..x.len())
            .map(|i| self.u_eq[i] + amp * x[i] / x[b])
            .collect();
        let c = Constraint::Displacement {
            bead: b,
            value: self.u_eq[b] + amp,
        };
        self.newton(&u, 2.0 * PI / w, c, tol)
    }

    /// The total energy of displacements `u` at rest minus that of the equilibrium.
    pub fn energy_above_equilibrium(&self, u: &[f64]) -> f64 {
        let c = &self.scene.chain;
        c.potential_energy(u) - c.potential_energy(&self.u_eq)
    }

    /// The full period map's residual `max(|u(T) − u(0)|, |v(T) − v(0)|)` (max-norm).
    pub fn period_residual(&self, b: &Breather) -> Result<f64, BreatherError> {
        let zero = vec![0.0; b.u.len()];
        let (u, v) = self.flow(&b.u, &zero, b.period)?;
        Ok(max_diff(&u, &b.u).max(max_diff(&v, &zero)))
    }

    /// The base scene with the breather as its initial state, run for `periods` periods by the
    /// dense engine at the shooter's tolerance, with `frames` frames per period.
    pub fn scene_of(&self, b: &Breather, periods: f64, frames: u32) -> Scene {
        let mut s = self.scene.clone();
        s.name = format!("{}_breather", self.scene.name);
        s.description = format!(
            "Discrete breather of {}: omega = {:.12}, period T = {:.12}, amplitude {:.6e}, from rest (beadchain breather)",
            self.scene.name,
            b.frequency(),
            b.period,
            self.amplitude(&b.u)
        );
        s.u0 = b.u.clone();
        s.v0 = vec![0.0; b.u.len()];
        s.run.until = periods * b.period;
        s.run.every = Some(b.period / f64::from(frames.max(1)));
        s.run.engine = Some(EngineKind::Dense);
        s.run.method = Some(Method::Dop853);
        s.run.rtol = Some(self.cfg.rtol);
        s.run.atol = Some(self.cfg.atol);
        s
    }
}

/// `max_i |a_i − b_i|`.
pub fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// Continues `start` in frequency to `target` in steps of at most `step`, each at a fixed
/// period. The predictor is a secant in `s = √|ω − ω_edge|` through the last two solutions,
/// the first of them the equilibrium (`s = 0`, `u = u*`) at the frequency `edge` the branch
/// bifurcates from: near the edge the amplitude grows as `√|ω − ω_edge|`, so a secant in `ω`
/// would start at the trivial solution. A step whose Newton iteration fails is halved (down to
/// `step/1024`), a step that succeeds lets the next grow by 1.5 (up to `step`). Every solution
/// on the way, `start` first.
///
/// A step that converges onto the equilibrium (the trivial solution, periodic with every
/// period: amplitude below [`COLLAPSE_FRACTION`] of `start`'s or velocity scale below
/// [`COLLAPSE_TOL_FACTOR`] `tol`) is an error saying on which side of `edge` the branch lies:
/// the continuation was asked for a frequency the branch does not reach.
pub fn continue_to(
    sh: &Shooter,
    start: Breather,
    edge: f64,
    target: f64,
    step: f64,
    tol: f64,
) -> Result<Vec<Breather>, BreatherError> {
    let sq = |w: f64| (w - edge).abs().sqrt();
    let dir = (target - start.frequency()).signum();
    let seed = Seed {
        amplitude: sh.amplitude(&start.u),
        frequency: start.frequency(),
        edge,
    };
    let mut h = step.abs();
    // (s, u) of the point before the last.
    let mut prev = (0.0, sh.u_eq.clone());
    let mut path = vec![start];
    loop {
        let last = &path[path.len() - 1];
        let w_last = last.frequency();
        if (target - w_last) * dir <= 0.0 {
            return Ok(path);
        }
        let w = if (target - w_last).abs() <= h {
            target
        } else {
            w_last + dir * h
        };
        let s_last = sq(w_last);
        let f = (sq(w) - s_last) / (s_last - prev.0);
        // a shift at round-off (1e-12 of the frequency) is none: its square root would scale
        // the predictor's step by up to 1e6
        if !f.is_finite() || (w_last - edge).abs() <= 1e-12 * edge.abs() {
            let why = if sh.scene.chain.exponent.iter().all(|&n| n == 2.0) {
                "every contact is linear (n = 2): no amplitude changes the frequency"
            } else {
                "raise the seed amplitude or lower Newton's tolerance"
            };
            return Err(err(format!(
                "continuation stopped at omega = {w_last:.6}: the branch has no frequency shift there (omega - omega_mode = {:.3e}), so it cannot be followed; {why}",
                w_last - edge
            )));
        }
        let guess: Vec<f64> = (0..last.u.len())
            .map(|i| last.u[i] + f * (last.u[i] - prev.1[i]))
            .collect();
        let t = 2.0 * PI / w;
        match sh.newton(&guess, t, Constraint::Period(t), tol) {
            Ok(b) => {
                seed.check_not_collapsed(sh, &b, target, tol)?;
                prev = (s_last, last.u.clone());
                path.push(b);
                h = (1.5 * h).min(step.abs());
            }
            Err(e) if h < step.abs() / 1024.0 => {
                let why = if seed.heads_away(dir) {
                    format!("; {}", seed.side())
                } else {
                    String::new()
                };
                return Err(err(format!(
                    "continuation stopped at omega = {w:.6}: {e}{why}"
                )));
            }
            Err(_) => h /= 2.0,
        }
    }
}

/// Largest Newton tolerance of a seed, as a fraction of its velocity scale `ω·amplitude`
/// ([`Shooter::from_mode`]).
pub const SEED_TOL_FRACTION: f64 = 1e-6;

/// A solution whose amplitude is below this fraction of the seed's has collapsed onto the
/// equilibrium (a fixed point of every period map), whatever Newton's residual says.
pub const COLLAPSE_FRACTION: f64 = 1e-6;

/// A solution whose velocity scale `ω A` is below this many times Newton's tolerance is the
/// equilibrium as far as the shooting can tell (a state of amplitude `A` that is no breather
/// has `max |v(T/2)| ~ ω A`, so Newton stops on any such state once `ω A ≲ tol`).
pub const COLLAPSE_TOL_FACTOR: f64 = 1e3;

/// The branch's start, to recognise a continuation that collapsed onto the equilibrium.
struct Seed {
    /// `max |u − u*|` of the seed.
    amplitude: f64,
    /// Its frequency (shifted from `edge` by the nonlinearity, `∝ A²`).
    frequency: f64,
    /// The linear mode's frequency the branch bifurcates from.
    edge: f64,
}

impl Seed {
    /// Errors when `b` is the equilibrium to the shooting's resolution (amplitude below
    /// [`COLLAPSE_FRACTION`] of the seed's, or `ω A` below [`COLLAPSE_TOL_FACTOR`] `tol`): the
    /// branch does not reach `b`'s frequency from the mode.
    fn check_not_collapsed(
        &self,
        sh: &Shooter,
        b: &Breather,
        target: f64,
        tol: f64,
    ) -> Result<(), BreatherError> {
        let amp = sh.amplitude(&b.u);
        if amp >= COLLAPSE_FRACTION * self.amplitude
            && amp * b.frequency() > COLLAPSE_TOL_FACTOR * tol
        {
            return Ok(());
        }
        Err(err(format!(
            "{}: the continuation to omega = {target} collapsed to the equilibrium at omega = {:.6} (amplitude {amp:.1e}, seed {:.1e}): {}",
            sh.scene.name,
            b.frequency(),
            self.amplitude,
            self.side()
        )))
    }

    /// Where the branch lies, from the seed's frequency shift. A soft branch (frequency falling
    /// with amplitude) is what precompressed Hertzian chains (n > 2) have at the edges of their
    /// optical bands: a power-law contact expanded about its static overlap `Δ`,
    /// `F(Δ + x) − F(Δ) = k (x + α x² + β x³)` with `α = (p−1)/(2Δ)`, `β = (p−1)(p−2)/(6Δ²)`
    /// (`p = n − 1`), shifts an oscillator's frequency by `(3β/8 − 5α²/12) A² ω =
    /// −(p−1)(2p+1) A² ω/(48Δ²)` (Landau & Lifshitz, Mechanics §28), negative for `n > 2`. In a
    /// finite chain the shift of a mode inside a band may take either sign (resonances with
    /// other modes; `docs/studies.md`), so the message states the measured one.
    fn side(&self) -> String {
        if self.frequency < self.edge {
            format!(
                "the branch from the linear mode at omega {:.6} exists only below it (its frequency falls as its amplitude grows: a soft nonlinearity, as at the band edges of precompressed Hertzian chains, n > 2, whose breathers bifurcate from the lower edge of an optical band into the gap below it, none above the top band)",
                self.edge
            )
        } else {
            format!(
                "the branch from the linear mode at omega {:.6} exists only above it (its frequency rises with its amplitude: a hard nonlinearity for this mode)",
                self.edge
            )
        }
    }

    /// Whether stepping in direction `dir` (±1) from the seed crosses the mode's frequency to
    /// the side where the branch does not exist.
    fn heads_away(&self, dir: f64) -> bool {
        (self.edge - self.frequency) * dir > 0.0
    }
}
