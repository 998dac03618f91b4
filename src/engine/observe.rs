//! Observers: what watches a run. An engine hands every frame, the dissipated energy, blocks
//! of its event log and checkpoints to one [`Observer`], and asks it between steps whether to
//! go on ([`Observer::control`]). Several observers watch one run as an [`Observers`] list,
//! which is itself an observer (argmin's observer list); [`Recorder`] keeps everything in memory.

use super::checkpoint::Control;
use super::EngineState;
use super::{events, EngineError};

/// Watches a run.
pub trait Observer {
    /// A frame at output time `t`.
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError>;
    /// The energy dissipated from `t = 0` up to the frame at `t` (by damped contacts and in
    /// hard collisions); called right before [`Observer::frame`], for scenes that lose energy
    /// only ([`crate::model::Chain::loses_energy`]). The default drops it.
    fn dissipated(&mut self, _t: f64, _energy: f64) -> Result<(), EngineError> {
        Ok(())
    }
    /// A block of the event log, in processing order (hybrid engine). Blocks are handed over
    /// when the engine's buffer holds [`super::EVENT_BLOCK`] events and before every frame; the
    /// engine keeps no other copy. The default drops them.
    fn events(&mut self, _events: &[events::EventRecord]) -> Result<(), EngineError> {
        Ok(())
    }
    /// Asked between steps (engine clock `t`): continue, checkpoint, or checkpoint and stop.
    fn control(&mut self, _t: f64) -> Control {
        Control::Continue
    }
    /// A checkpoint of the engine state (after [`Control::Checkpoint`] or [`Control::Stop`]).
    fn checkpoint(&mut self, _state: &EngineState) -> Result<(), EngineError> {
        Ok(())
    }
}

/// Asks the observer and acts (checkpoint when asked); `Ok(true)` when it asked to stop.
pub(crate) fn poll_stop(
    obs: &mut dyn Observer,
    t: f64,
    save: impl FnOnce() -> EngineState,
) -> Result<bool, EngineError> {
    match obs.control(t) {
        Control::Continue => Ok(false),
        Control::Checkpoint => obs.checkpoint(&save()).map(|_| false),
        Control::Stop => obs.checkpoint(&save()).map(|_| true),
    }
}

/// Several observers as one, in order: frames, dissipated energy, event blocks and checkpoints
/// go to each member; [`Observer::control`] asks every member and returns the strongest request
/// (stop over checkpoint over continue). The first error ends the call.
#[derive(Default)]
pub struct Observers<'a>(pub Vec<&'a mut dyn Observer>);

impl Observer for Observers<'_> {
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        self.0.iter_mut().try_for_each(|o| o.frame(t, u, v))
    }

    fn dissipated(&mut self, t: f64, energy: f64) -> Result<(), EngineError> {
        self.0.iter_mut().try_for_each(|o| o.dissipated(t, energy))
    }

    fn events(&mut self, events: &[events::EventRecord]) -> Result<(), EngineError> {
        self.0.iter_mut().try_for_each(|o| o.events(events))
    }

    fn control(&mut self, t: f64) -> Control {
        let rank = |c: Control| match c {
            Control::Continue => 0,
            Control::Checkpoint => 1,
            Control::Stop => 2,
        };
        self.0
            .iter_mut()
            .map(|o| o.control(t))
            .max_by_key(|&c| rank(c))
            .unwrap_or(Control::Continue)
    }

    fn checkpoint(&mut self, state: &EngineState) -> Result<(), EngineError> {
        self.0.iter_mut().try_for_each(|o| o.checkpoint(state))
    }
}

/// Frames [`Amplitude`] samples a run at (every `until / AMPLITUDE_FRAMES`).
pub const AMPLITUDE_FRAMES: f64 = 256.0;

/// The amplitude of a run's motion: the largest `|u_i − u_i(0)|` and `|v_i|` over its initial
/// state and frames (run it with [`Amplitude::every`]), the scale a final-state error is
/// relative to ([`super::Deviation::over_motion`]). The final state alone is no scale: a
/// breather run for whole periods ends where it started, and its errors relative to that read
/// 1e10× too large (`beadchain check dimer_gap_breather`).
#[derive(Clone, Debug)]
pub struct Amplitude {
    u0: Vec<f64>,
    /// Largest `|u_i(t) − u_i(0)|`.
    pub length: f64,
    /// Largest `|v_i(t)|`.
    pub velocity: f64,
}

impl Amplitude {
    /// Before a run from `(u0, v0)`.
    pub fn new(u0: &[f64], v0: &[f64]) -> Self {
        Self {
            u0: u0.to_vec(),
            length: 0.0,
            velocity: v0.iter().fold(0.0f64, |m, x| m.max(x.abs())),
        }
    }

    /// The output interval of a run to `until` sampled for its amplitude.
    pub fn every(until: f64) -> f64 {
        until / AMPLITUDE_FRAMES
    }
}

impl Observer for Amplitude {
    fn frame(&mut self, _t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        let du = u
            .iter()
            .zip(&self.u0)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        self.length = self.length.max(du);
        self.velocity = v.iter().fold(self.velocity, |m, x| m.max(x.abs()));
        Ok(())
    }
}

/// Collects frames and the event log in memory (tests, small runs).
#[derive(Default, Debug, Clone)]
pub struct Recorder {
    /// Frame times.
    pub t: Vec<f64>,
    /// Displacements per frame.
    pub u: Vec<Vec<f64>>,
    /// Velocities per frame.
    pub v: Vec<Vec<f64>>,
    /// The event log (hybrid engine), in processing order.
    pub events: Vec<events::EventRecord>,
    /// Energy dissipated up to each frame (scenes that lose energy; empty otherwise).
    pub dissipated: Vec<f64>,
}

impl Observer for Recorder {
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        self.t.push(t);
        self.u.push(u.to_vec());
        self.v.push(v.to_vec());
        Ok(())
    }

    fn events(&mut self, events: &[events::EventRecord]) -> Result<(), EngineError> {
        self.events.extend_from_slice(events);
        Ok(())
    }

    fn dissipated(&mut self, _t: f64, energy: f64) -> Result<(), EngineError> {
        self.dissipated.push(energy);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::engine::events::{EventKind, EventRecord};

    /// Counts every call and answers `control` with a fixed request.
    struct Counting {
        calls: [usize; 5],
        answer: Control,
    }

    impl Observer for Counting {
        fn frame(&mut self, _: f64, _: &[f64], _: &[f64]) -> Result<(), EngineError> {
            self.calls[0] += 1;
            Ok(())
        }
        fn dissipated(&mut self, _: f64, _: f64) -> Result<(), EngineError> {
            self.calls[1] += 1;
            Ok(())
        }
        fn events(&mut self, e: &[EventRecord]) -> Result<(), EngineError> {
            self.calls[2] += e.len();
            Ok(())
        }
        fn control(&mut self, _: f64) -> Control {
            self.calls[3] += 1;
            self.answer
        }
        fn checkpoint(&mut self, _: &EngineState) -> Result<(), EngineError> {
            self.calls[4] += 1;
            Ok(())
        }
    }

    /// Regression (issue 34): the appendix study's two-observer wrapper forwarded frames only,
    /// dropping events, the dissipated energy, control requests and checkpoints of its members.
    #[test]
    fn observer_list_forwards_every_call_to_every_member() {
        let mut a = Counting {
            calls: [0; 5],
            answer: Control::Continue,
        };
        let mut b = Counting {
            calls: [0; 5],
            answer: Control::Checkpoint,
        };
        let ev = EventRecord {
            t: 1.0,
            contact: 0,
            kind: EventKind::Close,
            rel_velocity: 0.5,
            peak_overlap: 0.0,
        };
        let mut list = Observers(vec![&mut a, &mut b]);
        list.frame(0.0, &[0.0], &[1.0]).unwrap();
        list.dissipated(0.0, 0.0).unwrap();
        list.events(&[ev.clone(), ev]).unwrap();
        assert_eq!(
            list.control(0.0),
            Control::Checkpoint,
            "the stronger request wins"
        );
        let scene = crate::scene::preset("striker").unwrap();
        let cfg = crate::engine::RunConfig::from_scene(&scene);
        let state = crate::engine::start(&scene, &cfg).unwrap().save();
        list.checkpoint(&state).unwrap();
        assert_eq!(a.calls, [1, 1, 2, 1, 1]);
        assert_eq!(b.calls, [1, 1, 2, 1, 1]);
    }

    #[test]
    fn an_empty_list_continues() {
        assert_eq!(Observers::default().control(3.0), Control::Continue);
    }
}
