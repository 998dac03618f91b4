//! The engine state as plain data (issue 12): a checkpoint is `serde` of the state, and loading
//! checks it. A state saved by one integrator never continues in another, and a state that does
//! not fit the chain is an error naming what is wrong, never a panic or a silently different run.

mod common;

use beadchain::engine::EngineState;
use beadchain::engine::{self, EngineError, RunConfig};
use beadchain::integrate::Method;
use beadchain::scene::{Engine as Kind, Scene};
use beadchain::snapshot::ckpt::{read_checkpoint, write_checkpoint, CheckpointFile};
use beadchain::snapshot::WriterMark;

fn state_of(kind: Kind, method: Method) -> (Scene, RunConfig, EngineState) {
    let sc = common::striker(30, 2.5, 1.0, 1.0, 30.0);
    let cfg = common::config(kind, method, 1e-8, 1e-12, 30.0);
    let mut g = common::Grab {
        at: 7.0,
        state: None,
    };
    engine::run(&sc, &cfg, &mut g).expect("runs");
    (sc, cfg, g.state.expect("a state after t = 7"))
}

/// The message of a refused checkpoint (the typed `StateError`, shown as a configuration error).
fn config_error(r: Result<Box<dyn engine::Engine + '_>, EngineError>) -> String {
    match r {
        Err(e @ EngineError::Checkpoint(_)) => {
            let m = e.to_string();
            m.strip_prefix("invalid run configuration: ")
                .unwrap_or(&m)
                .to_string()
        }
        Err(e) => panic!("expected a checkpoint that does not fit, got {e}"),
        Ok(_) => panic!("an inconsistent state was accepted"),
    }
}

/// Before the check, a DOP853 state loaded into Radau copied its 5 arrays into Radau's 9
/// (a length-1 array into a stage vector): a panic, or for equal lengths a wrong state.
#[test]
fn checkpoint_of_another_method_is_refused() {
    for kind in [Kind::Dense, Kind::Hybrid] {
        let (sc, mut cfg, st) = state_of(kind, Method::Dop853);
        cfg.method = Method::Radau5;
        let m = config_error(engine::restore(&sc, &cfg, &st));
        assert!(
            m.contains("the state of a dop853 integrator cannot continue as radau5"),
            "{kind:?}: {m}"
        );
        cfg.method = Method::Auto;
        let m = config_error(engine::restore(&sc, &cfg, &st));
        assert!(m.contains("cannot continue as auto"), "{kind:?}: {m}");
    }
}

#[test]
fn hybrid_state_for_another_chain_is_refused() {
    let (_, cfg, st) = state_of(Kind::Hybrid, Method::Auto);
    let other = common::striker(31, 2.5, 1.0, 1.0, 30.0);
    let m = config_error(engine::restore(&other, &cfg, &st));
    assert!(
        m.starts_with(
            "checkpoint: hybrid state `owner` holds 30 entries, a chain of 31 beads needs 31"
        ),
        "{m}"
    );
    let (sc, cfg, st) = state_of(Kind::Dense, Method::Radau5);
    let m = config_error(engine::restore(&other, &cfg, &st));
    assert!(m.contains("radau5 state arrays have lengths"), "{m}");
    assert!(engine::restore(&sc, &cfg, &st).is_ok());
}

/// A checkpoint file is `serde` of the state: written and read back it is the same value, and
/// the engine restored from it ends where the uninterrupted run ends, bit for bit.
#[test]
fn checkpoint_is_serde_of_the_state() {
    let d = tempfile::tempdir().unwrap();
    for (kind, method) in [(Kind::Dense, Method::Dop853), (Kind::Hybrid, Method::Auto)] {
        let (sc, cfg, st) = state_of(kind, method);
        let ck = CheckpointFile {
            scene: sc.clone(),
            config: cfg.clone(),
            timing: false,
            writer: WriterMark {
                path: d.path().join("x.snap"),
                temp: d.path().join(".x.snap.tmp"),
                len: 0,
                n_beads: 30,
                offsets: vec![],
                times: vec![],
                event_blocks: vec![],
                events_written: 0,
            },
            engine: st.clone(),
        };
        let p = d.path().join("x.ckpt");
        write_checkpoint(&p, &ck).unwrap();
        let back = read_checkpoint(&p).unwrap();
        assert_eq!(back, ck, "{kind:?}");
        let mut e = engine::restore(&back.scene, &back.config, &back.engine).unwrap();
        e.advance(cfg.until, &mut engine::Recorder::default())
            .unwrap();
        let whole = engine::run(&sc, &cfg, &mut engine::Recorder::default()).unwrap();
        let out = e.outcome();
        let bits = |x: &[f64]| x.iter().map(|y| y.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&out.u), bits(&whole.u), "{kind:?}");
        assert_eq!(bits(&out.v), bits(&whole.v), "{kind:?}");
    }
}
