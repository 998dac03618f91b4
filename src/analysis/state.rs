//! Steady state (paper appendix A) and fragmentation.
//!
//! **Steady state** (appendix A, the criterion below eq. A.5): every bead moves at constant
//! velocity and no faster than its right neighbour, relaxed to
//! `v_{i+1} − v_i > −10⁻⁵ · max_j |v_j|` for all `i`, and no contact overlaps (`δ ≤ 0`), so the
//! energy is purely kinetic and nothing will collide again. [`SteadyStateStop`] wraps an
//! [`Observer`] and stops the run at the first frame that satisfies it (an engine's `advance`
//! then returns `Stop::Requested`, see [`crate::engine::run_to_stop`]; `engine::run` reports
//! it as `EngineError::Interrupted(t)`; the wrapped observer has seen every frame up to it).
//!
//! **Fragmentation**: a contact is an open gap when its overlap is below `−gap_tol` (beads that
//! merely touch at rest are not a gap); fragments are the maximal runs of beads without an open
//! gap, each with its mass and centre-of-mass velocity.
//!
//! **Final fragments** (the run stop `run --stop-when-fragmented`): without a field and walls, no
//! pair can ever collide again when every contact is open or idle and the velocities do not
//! decrease along the chain. Contact `i` (overlap `δ_i`, [`Chain::overlap`]) must have
//! `δ_i < 0`, or `δ_i = 0` with `v_i = v_{i+1}` (touching, no force, not approaching), or `δ_i =
//! 0` with `v_i < v_{i+1}` (separating), and `v_i ≤ v_{i+1}` for every `i`. Free beads then fly
//! at constant velocity and every gap stays open or grows, exactly (no tolerance: a contact
//! approaching at `10⁻¹⁷` still closes, some day). The fragments are the maximal runs of beads
//! joined by touching contacts at equal velocity, each with its total mass and centre-of-mass
//! velocity ([`final_fragments`]).

use crate::engine::{self, Control, EngineError, EngineState, Observer, PauseAt, RunConfig};
use crate::engine::{RunOutcome, Stop};
use crate::model::Chain;
use crate::scene::Scene;

/// The appendix-A steady-state predicate (`rel` = 1e-5 in the paper).
pub fn is_steady_state(chain: &Chain, u: &[f64], v: &[f64], rel: f64) -> bool {
    let vmax = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let monotone = v.windows(2).all(|w| w[1] - w[0] > -rel * vmax);
    monotone && (0..v.len().saturating_sub(1)).all(|c| chain.overlap(c, u[c], u[c + 1]) <= 0.0)
}

/// Observer wrapper that stops the run at the first steady-state frame.
pub struct SteadyStateStop<'a> {
    /// The wrapped observer (sees every frame).
    pub inner: &'a mut dyn Observer,
    /// The chain (for overlaps).
    pub chain: &'a Chain,
    /// Relative tolerance of the monotonicity test (paper: 1e-5).
    pub rel: f64,
    /// Time of the first steady-state frame, once seen.
    pub reached: Option<f64>,
}

impl<'a> SteadyStateStop<'a> {
    /// Wraps `inner` with the paper's tolerance 1e-5.
    pub fn new(inner: &'a mut dyn Observer, chain: &'a Chain) -> Self {
        Self {
            inner,
            chain,
            rel: 1e-5,
            reached: None,
        }
    }
}

impl Observer for SteadyStateStop<'_> {
    fn dissipated(&mut self, t: f64, energy: f64) -> Result<(), EngineError> {
        self.inner.dissipated(t, energy)
    }
    fn events(&mut self, events: &[crate::engine::events::EventRecord]) -> Result<(), EngineError> {
        self.inner.events(events)
    }
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        self.inner.frame(t, u, v)?;
        if self.reached.is_none() && t > 0.0 && is_steady_state(self.chain, u, v, self.rel) {
            self.reached = Some(t);
        }
        Ok(())
    }
    fn control(&mut self, t: f64) -> Control {
        if self.reached.is_some() {
            Control::Stop
        } else {
            self.inner.control(t)
        }
    }
    fn checkpoint(&mut self, state: &EngineState) -> Result<(), EngineError> {
        if self.reached.is_some() {
            Ok(())
        } else {
            self.inner.checkpoint(state)
        }
    }
}

/// One fragment: beads `first..=last` moving together.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fragment {
    /// First bead.
    pub first: usize,
    /// Last bead.
    pub last: usize,
    /// Total mass.
    pub mass: f64,
    /// Centre-of-mass velocity.
    pub velocity: f64,
}

/// Fragmentation statistics of one state.
#[derive(Clone, Debug, PartialEq)]
pub struct Fragmentation {
    /// Number of open gaps (contacts with overlap `< −gap_tol`).
    pub gaps: usize,
    /// The fragments, left to right (`gaps + 1` of them).
    pub fragments: Vec<Fragment>,
}

/// Gaps and fragments of a state (`gap_tol ≥ 0`, in length units).
pub fn fragmentation(chain: &Chain, u: &[f64], v: &[f64], gap_tol: f64) -> Fragmentation {
    let n = v.len();
    let mut fragments = Vec::new();
    let mut first = 0;
    let close = |first: usize, last: usize| fragment(chain, v, first, last);
    for c in 0..n.saturating_sub(1) {
        if chain.overlap(c, u[c], u[c + 1]) < -gap_tol {
            fragments.push(close(first, c));
            first = c + 1;
        }
    }
    if n > 0 {
        fragments.push(close(first, n - 1));
    }
    Fragmentation {
        gaps: fragments.len().saturating_sub(1),
        fragments,
    }
}

/// The fragments of a state of a chain without field and walls in which no pair can ever
/// collide again (module docs); `None` when some contact overlaps or approaches. The caller
/// checks that the chain has no field and no walls (a field or a wall can always bring beads
/// back). Whether it has fragmented is tested first, so that a state that has not (every frame
/// but the last of the run stop) allocates nothing.
pub fn final_fragments(chain: &Chain, u: &[f64], v: &[f64]) -> Option<Vec<Fragment>> {
    if !fragmented_for_good(chain, u, v) {
        return None;
    }
    let n = v.len();
    let mut fragments = Vec::new();
    let mut first = 0;
    for c in 0..n.saturating_sub(1) {
        let delta = chain.overlap(c, u[c], u[c + 1]);
        let joined = delta == 0.0 && v[c] == v[c + 1];
        if !joined {
            fragments.push(fragment(chain, v, first, c));
            first = c + 1;
        }
    }
    if n > 0 {
        fragments.push(fragment(chain, v, first, n - 1));
    }
    Some(fragments)
}

/// The predicate of [`final_fragments`]: no contact overlaps (`δ > 0`) or approaches
/// (`v_i > v_{i+1}`).
fn fragmented_for_good(chain: &Chain, u: &[f64], v: &[f64]) -> bool {
    let blocked = |c: usize| chain.overlap(c, u[c], u[c + 1]) > 0.0 || v[c] > v[c + 1];
    !(0..v.len().saturating_sub(1)).any(blocked)
}

/// Where a run stopped because it fragmented ([`run_until_fragmented`]): the frame time and the
/// fragments.
#[derive(Clone, Debug, PartialEq)]
pub struct Fragmented {
    /// Time of the frame at which no pair can collide again.
    pub t: f64,
    /// The fragments, left to right.
    pub fragments: Vec<Fragment>,
}

/// Runs `scene` to `cfg.until` or to the first output frame at which it has fragmented for
/// good ([`final_fragments`] on the frame's state, exact at a frame: [`engine::Engine::state`]
/// right after a [`Stop::Frame`]); `run --stop-when-fragmented`. The caller checks that the
/// chain has no field and no walls. The engine is driven through its steppable API, pausing at
/// frames only ([`PauseAt`]: pausing changes no byte of the run), so a run that never fragments
/// hands `obs` what [`engine::run`] does.
pub fn run_until_fragmented(
    scene: &Scene,
    cfg: &RunConfig,
    obs: &mut dyn Observer,
) -> Result<(RunOutcome, Option<Fragmented>), EngineError> {
    let mut e = engine::start(scene, cfg)?;
    e.pause_at(PauseAt {
        frames: true,
        events: false,
    });
    // the state at each frame, in one allocation (hot loops allocation-free)
    let mut s = e.state();
    loop {
        match e.advance(cfg.until, obs)? {
            Stop::Reached { .. } => return Ok((e.outcome(), None)),
            Stop::Requested { t } => return Err(EngineError::Interrupted(t)),
            Stop::Frame { t } => {
                e.state_into(&mut s);
                if let Some(fragments) = final_fragments(&scene.chain, &s.u, &s.v) {
                    return Ok((e.outcome(), Some(Fragmented { t, fragments })));
                }
            }
            Stop::Event { .. } => {}
        }
    }
}

/// Beads `first..=last` as one fragment: total mass and centre-of-mass velocity.
fn fragment(chain: &Chain, v: &[f64], first: usize, last: usize) -> Fragment {
    let mass: f64 = chain.mass[first..=last].iter().sum();
    let p: f64 = (first..=last).map(|i| chain.mass[i] * v[i]).sum();
    Fragment {
        first,
        last,
        mass,
        velocity: p / mass,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::wave::tests::chain;
    use crate::engine::Recorder;

    #[test]
    fn steady_state_predicate() {
        let c = chain(4, 2.5);
        let apart = [0.0, 1.0, 2.0, 3.0]; // u increasing: every overlap negative
        assert!(is_steady_state(&c, &apart, &[-1.0, 0.0, 0.5, 1.0], 1e-5));
        // a decrease of 2e-5 * max|v| fails, 0.5e-5 passes
        assert!(!is_steady_state(
            &c,
            &apart,
            &[0.0, 1.0, 1.0 - 2e-5, 1.0],
            1e-5
        ));
        assert!(is_steady_state(
            &c,
            &apart,
            &[0.0, 1.0, 1.0 - 0.5e-5, 1.0],
            1e-5
        ));
        // monotone but overlapping contact 1
        let over = [0.0, 1.0, 0.9, 3.0];
        assert!(!is_steady_state(&c, &over, &[0.0, 0.1, 0.2, 0.3], 1e-5));
    }

    #[test]
    fn stop_wrapper_stops_at_first_steady_frame() {
        let c = chain(3, 2.5);
        let mut rec = Recorder::default();
        let mut s = SteadyStateStop::new(&mut rec, &c);
        let u = [0.0, 1.0, 2.0];
        s.frame(0.0, &u, &[0.0, 0.0, 0.0]).unwrap(); // t = 0 never counts
        assert_eq!(s.control(0.5), Control::Continue);
        s.frame(1.0, &u, &[1.0, 0.0, 0.0]).unwrap(); // not monotone
        assert_eq!(s.control(1.5), Control::Continue);
        s.frame(2.0, &u, &[0.0, 0.0, 1.0]).unwrap();
        assert_eq!(s.reached, Some(2.0));
        assert_eq!(s.control(2.5), Control::Stop);
        assert_eq!(rec.t, vec![0.0, 1.0, 2.0]);
    }

    #[test]
    fn fragments_exact() {
        let c = chain(5, 2.5);
        // overlaps: c0 = 0 (touching), c1 = -0.5 (gap), c2 = 0.1, c3 = -1e-9 (gap only if tol < 1e-9)
        let u = [0.0, 0.0, 0.5, 0.4, 0.4 + 1e-9];
        let v = [1.0, 3.0, -1.0, 0.0, 2.0];
        let f = fragmentation(&c, &u, &v, 0.0);
        assert_eq!(f.gaps, 2);
        let spans: Vec<_> = f.fragments.iter().map(|g| (g.first, g.last)).collect();
        assert_eq!(spans, vec![(0, 1), (2, 3), (4, 4)]);
        // velocities: (1+3)/2 = 2, (-1+0)/2 = -0.5, 2 (exact)
        let vel: Vec<_> = f.fragments.iter().map(|g| g.velocity).collect();
        assert_eq!(vel, vec![2.0, -0.5, 2.0]);
        assert_eq!(fragmentation(&c, &u, &v, 1e-6).gaps, 1);
    }

    #[test]
    fn final_fragments_exact() {
        let c = chain(5, 2.5);
        // contact 0 touching at equal velocity (joined), 1 open, 2 touching but separating,
        // 3 open: fragments 0..1, 2, 3, 4
        let u = [0.0, 0.0, 0.5, 0.5, 1.0];
        let v = [-1.0, -1.0, 0.0, 2.0, 2.0];
        let f = final_fragments(&c, &u, &v).expect("fragmented");
        let spans: Vec<_> = f.iter().map(|g| (g.first, g.last)).collect();
        assert_eq!(spans, vec![(0, 1), (2, 2), (3, 3), (4, 4)]);
        assert_eq!(f[0].mass, 2.0);
        assert_eq!(f[0].velocity, -1.0);
        // an approaching open contact, an overlapping one: not fragmented
        assert!(final_fragments(&c, &u, &[-1.0, -1.0, 0.0, 2.0, 1.0]).is_none());
        assert!(final_fragments(&c, &[0.0, 0.0, 0.5, 0.4, 1.0], &v).is_none());
    }
}
