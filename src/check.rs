//! `beadchain check`: is the hybrid engine right on this scene, told apart from how sensitive
//! the scene itself is.
//!
//! A trajectory comparison alone cannot judge a chaotic scene (disorder, periodic decay, gases):
//! tolerance-level differences between two correct runs grow there until the final states
//! differ at order one. So the check measures the scene's own **sensitivity** first, by running
//! the reference engine twice, at `rtol` and at `rtol/100`: their deviation `S` is what
//! rtol-level differences become by the end time. The hybrid run (at `rtol`) is then judged by
//! - its deviation `D` from the reference at `rtol`: `D ≤ max(tol, 10·S)` (`tol` = `--tol`,
//!   default `1000·rtol`); in a scene with `S ≤ tol` this is the plain trajectory test;
//! - conserved quantities: the total energy (paper eq. 5; relative to the gross energy) when
//!   no contact dissipates, `ΔE_H ≤ max(10·ΔE_R, 1000·rtol)` with `ΔE_R` the reference's error
//!   at `rtol`; the momentum (eq. 7 conserves `Σ m_i v_i` without walls and fields) to
//!   `1000·rtol` of `Σ m_i |v_i(0)|` (of `M·max|v|` over the run where the chain starts at rest);
//! - an observable of the paper (eq. 13): the energy of the leading wave at the end time (the
//!   beads within 10 of the fastest one), against the reference at `rtol/100`:
//!   `|ΔE_lead,H| ≤ max(10·|ΔE_lead,R|, 1000·rtol)`, `R` the reference at `rtol`.
//!
//! A chain **at rest** at the end (every velocity of the reference at `rtol/100` below
//! `rtol·V`, `L` and `V` the run's length and velocity scales, e.g. a static equilibrium) has
//! no motion to be relative to: its deviations `D` and `S` are taken against `L` and `V`
//! (the hybrid engine holds an equilibrium exactly, the dense one moves it by round-off), and
//! it has no leading wave to locate, so that criterion is left out.
//!
//! Deviations are relative to the motion over the run (the largest `|u − u0|` and `|v|` in 256
//! frames of the reference at `rtol/100`, [`Amplitude`], and in the final states), not to the
//! final state alone, which can be back near the initial one (a breather run for whole periods).
//!
//! The scene is called **sensitive** when `S > tol`; the verdict says so, with the
//! amplification `S/rtol`. Where `10·S > tol` (the bound would widen), the hybrid engine is
//! run at `rtol/100` too; where its two runs differ by `S_h ≤ min(tol, S/10)` (the hybrid
//! engine finds the scene not sensitive, and itself 10 times steadier), `S` is the reference's
//! own error, not the scene's sensitivity (the dense engine's DOP853 steps across contact kinks
//! with an estimate that assumes a smooth solution: a 4-bead scene with gaps, walls and a
//! field was 3000·rtol off at rtol 1e-10, the hybrid engine 10·rtol, and the check widened its
//! bound to 9000·rtol), the report says so, the scene is not called sensitive, and the
//! trajectory test is `D ≤ max(tol, 10·S_h)` against the reference at `rtol/100`.
//!
//! The reference is the dense engine (same method), which shares no event code with the hybrid
//! one. A scene with hard contacts or hard walls has no dense counterpart: there the reference
//! is the hybrid engine itself with the other method family (Radau IIA for `auto`/`dop853`,
//! DOP853 for `radau5`), and the energy test applies only when every restitution is 1.

use crate::engine::{self, Amplitude, Deviation, EngineError, Recorder, RunConfig, RunOutcome};
use crate::integrate::Method;
use crate::names::Named;
use crate::progress::RunProgress;
use crate::scene::{Engine, Scene};

/// Half-width (beads) of the leading-wave window.
const LEAD_WINDOW: usize = 10;

/// One verdict line: what was compared, the measured value, the bound, and whether it held.
#[derive(Clone, Debug)]
pub struct Criterion {
    /// What is compared.
    pub what: String,
    /// Measured value.
    pub value: f64,
    /// Bound it must not exceed.
    pub bound: f64,
}

impl Criterion {
    /// Whether the value is within its bound.
    pub fn holds(&self) -> bool {
        self.value <= self.bound
    }
}

/// The outcome of a check.
#[derive(Clone, Debug)]
pub struct CheckReport {
    /// The reference run's description (engine and method).
    pub reference: String,
    /// Hybrid vs reference at `rtol` (at `rtol/100` where [`Self::hybrid_spread`] is set).
    pub deviation: Deviation,
    /// Reference at `rtol` vs reference at `rtol/100` (the scene's sensitivity).
    pub sensitivity: Deviation,
    /// `rtol` of the runs.
    pub rtol: f64,
    /// Whether the scene is sensitive (module docs).
    pub sensitive: bool,
    /// Where the reference at rtol and rtol/100 differ by more than `tol/10` and the hybrid
    /// engine at rtol and rtol/100 agree within `tol` and 10 times better: their deviation
    /// (module docs). The
    /// reference's own error, not the scene, made the difference, and the trajectory test is
    /// against the reference at rtol/100 (`deviation` is then hybrid vs that run).
    pub hybrid_spread: Option<f64>,
    /// Whether the chain is at rest (module docs): the deviations are then relative to the
    /// scene's scales `L`, `V`, and there is no leading-wave criterion.
    pub at_rest: bool,
    /// The criteria, in order.
    pub criteria: Vec<Criterion>,
    /// The hybrid run and the reference run at `rtol`.
    pub runs: (RunOutcome, RunOutcome),
}

impl CheckReport {
    /// Whether every criterion holds.
    pub fn passed(&self) -> bool {
        self.criteria.iter().all(Criterion::holds)
    }
}

/// One run to the end time; with `amp`, its frames sample the motion's amplitude (frames are
/// read from the continuous output: the steps and the final state are the same without them).
fn run(
    scene: &Scene,
    cfg: &RunConfig,
    bar: &RunProgress,
    (label, amp): (&str, Option<&mut Amplitude>),
) -> Result<RunOutcome, EngineError> {
    let mut cfg = cfg.clone();
    cfg.every = amp.as_ref().map(|_| Amplitude::every(cfg.until));
    let mut discard = Recorder::default();
    let obs: &mut dyn engine::Observer = match amp {
        Some(a) => a,
        None => &mut discard,
    };
    let out = engine::run(scene, &cfg, &mut bar.watch(obs, 0.0, cfg.until, label));
    bar.finish();
    out
}

/// Energy of the beads within [`LEAD_WINDOW`] of the fastest one (kinetic + their contacts).
pub fn leading_wave_energy(scene: &Scene, u: &[f64], v: &[f64]) -> f64 {
    let c = &scene.chain;
    let k = (0..v.len()).fold(0, |k, i| if v[i].abs() > v[k].abs() { i } else { k });
    let (lo, hi) = (
        k.saturating_sub(LEAD_WINDOW),
        (k + LEAD_WINDOW + 1).min(v.len()),
    );
    let ke: f64 = (lo..hi).map(|i| 0.5 * c.mass[i] * v[i] * v[i]).sum();
    let pe: f64 = (lo..hi - 1)
        .map(|i| {
            let d = c.overlap(i, u[i], u[i + 1]);
            crate::model::contact_potential(c.exponent[i], c.prefactor[i], d)
        })
        .sum();
    ke + pe
}

/// The momentum change of `o` relative to `Σ m_i |v_i(0)|`, or where the chain starts at rest
/// to `M·max|v|` over the run (`amp`): the scale was `f64::MIN_POSITIVE` there, and a change of
/// 2.6e-17 read 1.2e291. A chain at rest throughout gives the absolute change.
fn momentum_change(scene: &Scene, o: &RunOutcome, amp: &Amplitude) -> f64 {
    let m = &scene.chain.mass;
    let p0: f64 = m.iter().zip(&scene.v0).map(|(m, v)| m * v.abs()).sum();
    let scale = if p0 > 0.0 {
        p0
    } else {
        m.iter().sum::<f64>() * amp.velocity
    };
    let dp = (o.momentum_final - o.momentum_initial).abs();
    if scale > 0.0 {
        dp / scale
    } else {
        dp
    }
}

/// Runs the check of `scene` (module docs). `hybrid_scene` is the scene the hybrid engine runs
/// (the same scene, except in tests that perturb it on purpose).
pub fn check(
    hybrid_scene: &Scene,
    scene: &Scene,
    base: &RunConfig,
    tol: f64,
) -> Result<CheckReport, EngineError> {
    check_with_progress(hybrid_scene, scene, base, tol, &RunProgress::hidden())
}

/// [`check`] with a progress bar fed by each of its runs.
pub fn check_with_progress(
    hybrid_scene: &Scene,
    scene: &Scene,
    base: &RunConfig,
    tol: f64,
    bar: &RunProgress,
) -> Result<CheckReport, EngineError> {
    let (hyb, refc, tight) = configs(scene, base);
    let h = run(hybrid_scene, &hyb, bar, ("hybrid: ", None))?;
    let r = run(scene, &refc, bar, ("reference: ", None))?;
    let mut amp = Amplitude::new(&scene.u0, &scene.v0);
    let r2 = run(
        scene,
        &tight,
        bar,
        ("reference at rtol/100: ", Some(&mut amp)),
    )?;
    let rtol = base.rtol;
    let sc = scene.chain.scales(&scene.u0, &scene.v0);
    let at_rest = r2.v.iter().all(|v| v.abs() <= rtol * sc.velocity);
    let compare = |a: &RunOutcome, b: &RunOutcome| {
        let d = Deviation::between(scene, a, b);
        if at_rest {
            d.against_scales(sc.length, sc.velocity)
        } else {
            d.over_motion(&amp)
        }
    };
    let sensitivity = compare(&r, &r2);
    let s = sensitivity.rel_u.max(sensitivity.rel_v);
    // a reference whose own error would widen the bound (module docs): where the hybrid
    // engine at rtol and rtol/100 agree within tol and 10 times better, the trajectory test
    // is against r2
    let hybrid_spread = if 10.0 * s > tol {
        let mut tight_h = tight.clone();
        tight_h.engine = Engine::Hybrid;
        tight_h.method = base.method;
        let h2 = run(hybrid_scene, &tight_h, bar, ("hybrid at rtol/100: ", None))?;
        let d = compare(&h, &h2);
        Some(d.rel_u.max(d.rel_v)).filter(|&sh| sh <= tol && sh <= 0.1 * s)
    } else {
        None
    };
    let reference = format!("{} {}", refc.engine.name(), refc.method.name());
    let (deviation, against, bound) = match hybrid_spread {
        Some(sh) => (
            compare(&h, &r2),
            format!("{reference} at rtol/100"),
            tol.max(10.0 * sh),
        ),
        None => (compare(&h, &r), reference.clone(), tol.max(10.0 * s)),
    };
    let mut criteria = vec![Criterion {
        what: format!("trajectory: hybrid vs {against} (max of relative u, v)"),
        value: deviation.rel_u.max(deviation.rel_v),
        bound,
    }];
    criteria.extend(conserved(scene, (&h, &r), rtol, &amp));
    if !at_rest {
        criteria.extend(leading_wave(scene, [&h, &r, &r2], rtol));
    }
    Ok(CheckReport {
        reference,
        deviation,
        sensitivity,
        rtol,
        sensitive: s > tol && hybrid_spread.is_none(),
        hybrid_spread,
        at_rest,
        criteria,
        runs: (h, r),
    })
}

/// The hybrid run's configuration, the reference's (the dense engine, or for hard scenes the
/// hybrid engine with the other method family) and the reference's at `rtol/100`.
fn configs(scene: &Scene, base: &RunConfig) -> (RunConfig, RunConfig, RunConfig) {
    let mut hyb = base.clone();
    hyb.engine = Engine::Hybrid;
    let mut refc = base.clone();
    if scene.chain.has_hard() {
        refc.method = match base.method {
            Method::Radau5 => Method::Dop853,
            _ => Method::Radau5,
        };
    } else {
        refc.engine = Engine::Dense;
    }
    let mut tight = refc.clone();
    tight.rtol = base.rtol / 100.0;
    tight.atol = base.atol / 100.0;
    (hyb, refc, tight)
}

/// The conserved-quantity criteria (module docs): energy where no contact or wall loses it,
/// momentum without walls and fields.
fn conserved(
    scene: &Scene,
    (h, r): (&RunOutcome, &RunOutcome),
    rtol: f64,
    amp: &Amplitude,
) -> Vec<Criterion> {
    let mut criteria = Vec::new();
    let restitutions_one = scene
        .chain
        .hard
        .as_ref()
        .is_none_or(|hc| hc.restitution.iter().flatten().all(|&e| e == 1.0))
        && [&scene.chain.left_wall, &scene.chain.right_wall]
            .iter()
            .all(|w| {
                w.as_ref()
                    .is_none_or(|w| w.restitution.is_none_or(|e| e == 1.0))
            });
    if restitutions_one {
        criteria.push(Criterion {
            what: "energy error of the hybrid run".into(),
            value: h.relative_energy_error(),
            bound: (10.0 * r.relative_energy_error()).max(1000.0 * rtol),
        });
    }
    let c = &scene.chain;
    if c.left_wall.is_none() && c.right_wall.is_none() && c.field.is_none() {
        criteria.push(Criterion {
            what: "momentum change of the hybrid run (relative to Σ m|v₀|, or M·max|v| from rest)"
                .into(),
            value: momentum_change(scene, h, amp),
            bound: 1000.0 * rtol,
        });
    }
    criteria
}

/// The leading-wave criterion (module docs) of the hybrid run `h` against the reference at
/// `rtol/100`, `r2`, bounded by the reference at `rtol`, `r`.
fn leading_wave(scene: &Scene, [h, r, r2]: [&RunOutcome; 3], rtol: f64) -> Option<Criterion> {
    let lead = |o: &RunOutcome| leading_wave_energy(scene, &o.u, &o.v);
    let l2 = lead(r2);
    (l2 > 0.0).then(|| Criterion {
        what: "leading-wave energy at the end, hybrid vs tight reference (relative)".into(),
        value: (lead(h) - l2).abs() / l2,
        bound: (10.0 * (lead(r) - l2).abs() / l2).max(1000.0 * rtol),
    })
}
