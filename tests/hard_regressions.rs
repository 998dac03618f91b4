//! Regressions of hard contacts (issue 11, items 3, 4 and 12): plastic collisions conserve
//! momentum and turn into resting (sticking) contacts, beads may not start inside a hard
//! contact or hard wall, and inelastic-collapse scenes with the default collapse interval
//! finish with a bounded number of events.
//!
//! The run-away scenes are run under [`Budget`], an observer that stops the run after a fixed
//! number of engine events, so a regression fails (interrupted) instead of running forever.

mod common;
use beadchain::engine::events::EventKind;
use beadchain::engine::{Control, EngineError, Observer, Recorder, RunConfig, RunOutcome};
use beadchain::integrate::Method;
use beadchain::scene::{parse_str, Engine, Scene};
use common::config;
use std::path::Path;

/// Records frames and stops the run after `left` engine events (queue entries).
struct Budget {
    left: u64,
    rec: Recorder,
}

impl Observer for Budget {
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        self.rec.frame(t, u, v)
    }
    fn control(&mut self, _t: f64) -> Control {
        self.left = self.left.saturating_sub(1);
        Control::stop_if(self.left == 0)
    }
}

fn scene(text: &str) -> Scene {
    parse_str(text, Path::new("."), "s.toml").expect("scene parses")
}

fn cfg(s: &Scene) -> RunConfig {
    let mut c = config(Engine::Hybrid, Method::Radau5, 1e-10, 1e-12, s.run.until);
    c.every = s.run.every;
    c
}

/// Runs with an event budget; panics (with the time reached) when the budget runs out.
fn run_bounded(s: &Scene, events: u64) -> (RunOutcome, Recorder) {
    let c = cfg(s);
    let mut obs = Budget {
        left: events,
        rec: Recorder::default(),
    };
    match beadchain::engine::run(s, &c, &mut obs) {
        Ok(o) => (o, obs.rec),
        Err(e) => panic!("run did not finish within {events} engine events: {e}"),
    }
}

fn hard_events(o: &RunOutcome) -> u64 {
    o.events(EventKind::HardCollision)
}

/// Total energy of every frame never rises above the previous frame's by more than
/// `abs + rel·|E|` (abs and rel stated by the caller).
fn assert_energy_never_increases(s: &Scene, rec: &Recorder, abs: f64, rel: f64) {
    let mut prev = f64::INFINITY;
    for (k, (u, v)) in rec.u.iter().zip(&rec.v).enumerate() {
        let e = s.chain.energy(u, v);
        assert!(
            e <= prev + abs + rel * prev.abs().min(e.abs()),
            "frame {k} (t = {}): energy {e} after {prev}",
            rec.t[k]
        );
        prev = e;
    }
}

const PLASTIC_WALL: &str = "
[chain]
beads = 3
[initial]
displacement = [0.5, 0.5, 0.5]
velocity = [-1.0, -1.0, -1.0]
[hard]
contacts = \"all\"
restitution = 0.0
[walls]
left = { hard = true, restitution = 0.0 }
[run]
until = 2.0
every = 0.25
";

/// Three touching beads at v = −1 hitting a plastic wall, all contacts plastic: every bead
/// ends at rest against the wall (was (0.25, 0.25, 0.5): momentum −3 → +1), for the default
/// collapse interval and an explicit one.
#[test]
fn plastic_wall_brings_all_beads_to_rest() {
    for extra in ["", "collapse_interval = 1e-3\n"] {
        let text = PLASTIC_WALL.replace(
            "restitution = 0.0\n[walls]",
            &format!("restitution = 0.0\n{extra}[walls]"),
        );
        let s = scene(&text);
        let (o, rec) = run_bounded(&s, 10_000);
        // exact to rounding: abs 1e-15 (rel: the scale is 1)
        for (i, v) in o.v.iter().enumerate() {
            assert!(v.abs() <= 1e-15, "{extra}bead {i}: v = {v}");
        }
        // resting against the wall and each other: u = 0 to abs 1e-15
        for (i, u) in o.u.iter().enumerate() {
            assert!(u.abs() <= 1e-15, "{extra}bead {i}: u = {u}");
        }
        assert!(
            hard_events(&o) <= 10,
            "{extra}{} collisions",
            hard_events(&o)
        );
        assert_energy_never_increases(&s, &rec, 1e-15, 1e-15);
    }
}

/// A plastic Newton's cradle: one striker at v = 1 onto five touching beads at rest, all
/// contacts plastic. Every bead-bead collision conserves momentum and sticks, so all six move
/// together at 1/6 (was 0.125 × 4 and 0.25 × 2), for any collapse interval.
#[test]
fn plastic_newtons_cradle_moves_together() {
    for tc in [
        "",
        "collapse_interval = 1e-3\n",
        "collapse_interval = 10.0\n",
    ] {
        let text = format!(
            "[chain]\nbeads = 6\n[initial]\ndisplacement = [-1.0, 0.0, 0.0, 0.0, 0.0, 0.0]\n\
             striker = 1.0\n[hard]\ncontacts = \"all\"\nrestitution = 0.0\n{tc}[run]\nuntil = 5.0\n"
        );
        let s = scene(&text);
        let (o, _) = run_bounded(&s, 10_000);
        // abs 1e-15 + rel 1e-14 of 1/6
        for (i, v) in o.v.iter().enumerate() {
            assert!(
                (v - 1.0 / 6.0).abs() <= 1e-15 + 1e-14 / 6.0,
                "{tc}bead {i}: v = {v}"
            );
        }
        // momentum exactly 1 to rounding (abs 1e-15, rel 1e-15)
        assert!(
            (o.momentum_final - 1.0).abs() <= 2e-15,
            "{}",
            o.momentum_final
        );
        assert_eq!(hard_events(&o), 5, "{tc}one collision per contact");
    }
}

/// Bead-bead collisions of any restitution conserve momentum to rounding, also when they
/// stick (a random hard gas with e = 0.3 in a box of plastic walls is not, so no walls here).
#[test]
fn inelastic_hard_gas_conserves_momentum() {
    use rand::{Rng, SeedableRng};
    let n = 60;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    let mut s = common::striker(n, 2.5, 1.0, 0.0, 20.0);
    for i in 0..n {
        s.chain.mass[i] = 0.5 + rng.random::<f64>();
        s.v0[i] = rng.random::<f64>() * 2.0 - 1.0;
        s.u0[i] = 0.3 * rng.random::<f64>() + i as f64 * 0.31;
    }
    s.chain.hard = Some(beadchain::model::HardContacts {
        restitution: vec![Some(0.3); n - 1],
        collapse_interval: 1e-6,
    });
    let (o, _) = run_bounded(&s, 1_000_000);
    assert!(hard_events(&o) > 100, "{:?}", o.events_by_kind);
    // momentum: abs 1e-12 (rel to Σ m|v| ≈ 30: 3e-14)
    assert!(
        (o.momentum_final - o.momentum_initial).abs() < 1e-12,
        "{} → {}",
        o.momentum_initial,
        o.momentum_final
    );
    assert!(o.energy_final <= o.energy_initial, "energy gained");
}

/// Issue 12, scene 1: five hard beads (e = 0.5) falling onto a hard wall under gravity, with
/// the default collapse interval, ran practically forever (t = 0.059 of 30 in 20 s). Now the
/// stack comes to rest on the wall in a bounded number of collisions.
#[test]
fn falling_hard_stack_comes_to_rest() {
    let s = scene(&wall_e05(common::FALLING_STACK));
    let (o, rec) = run_bounded(&s, 200_000);
    assert!(hard_events(&o) < 5_000, "{} collisions", hard_events(&o));
    // at rest, stacked on the wall: u = 0, v = 0 (abs 1e-12)
    for i in 0..5 {
        assert!(
            o.u[i].abs() <= 1e-12 && o.v[i].abs() <= 1e-12,
            "bead {i}: {} {}",
            o.u[i],
            o.v[i]
        );
    }
    // energy never increases (abs 1e-12, rel 1e-12 of the total)
    assert_energy_never_increases(&s, &rec, 1e-12, 1e-12);
}

/// Issue 12, scene 2: a ball bouncing on a hard wall (e = 0.5) under gravity, a far soft
/// neighbour at rest without field. Inelastic collapse: it must stop bouncing after
/// about log(v₀ / (g t_c)) / log(1/e) bounces and rest on the wall.
#[test]
fn bouncing_ball_comes_to_rest() {
    let text = "
[chain]
beads = 2
[field]
force = [-1.0, 0.0]
[initial]
displacement = [1.0, 10.0]
[walls]
left = { hard = true, restitution = 0.5 }
[run]
until = 30.0
every = 1.0
";
    let s = scene(text);
    let (o, rec) = run_bounded(&s, 100_000);
    assert!(hard_events(&o) < 200, "{} bounces", hard_events(&o));
    assert!(
        o.u[0].abs() <= 1e-12 && o.v[0].abs() <= 1e-12,
        "{} {}",
        o.u[0],
        o.v[0]
    );
    assert_energy_never_increases(&s, &rec, 1e-12, 1e-12);
}

/// Issue 12, scene 3: a hard segment (contacts 8–11, e = 0.5) inside a soft chain struck at
/// v = 1 (reached t = 6.6 of 80 with 1.6 GB): finishes in a bounded number of events.
#[test]
fn hard_segment_in_soft_chain_finishes() {
    let text = "
[chain]
beads = 20
[initial]
striker = 1.0
[hard]
contacts = { from = 8, to = 11 }
restitution = 0.5
[run]
until = 80.0
every = 2.0
";
    let s = scene(text);
    let (o, rec) = run_bounded(&s, 2_000_000);
    assert!(hard_events(&o) < 100_000, "{:?}", o.events_by_kind);
    // momentum: abs 1e-9 (rel 1e-9 of the striker's 1)
    assert!(
        (o.momentum_final - 1.0).abs() < 1e-9,
        "{}",
        o.momentum_final
    );
    assert_energy_never_increases(&s, &rec, 1e-9, 1e-9);
}

/// Energy never increases in hard scenes with e ≤ 1: each restitution on a falling stack and
/// on a cradle with a field pressing it onto a wall.
#[test]
fn hard_scenes_never_gain_energy() {
    for e in ["0.0", "0.3", "0.9", "1.0"] {
        let text = wall_e05(common::FALLING_STACK)
            .replace("restitution = 0.5", &format!("restitution = {e}"));
        let s = scene(&text);
        let (_, rec) = run_bounded(&s, 500_000);
        // abs 1e-12, rel 1e-12 of the total
        assert_energy_never_increases(&s, &rec, 1e-12, 1e-12);
    }
}

/// Item 4: a hard contact that starts overlapping, or a bead that starts inside a hard wall,
/// is rejected with a one-line error naming the contact (the energy used to rise ×36).
#[test]
fn hard_overlap_at_start_is_rejected() {
    let base = "[chain]\nbeads = 4\n[initial]\ndisplacement = [0.0, 0.0, 0.0, 0.0]\n\
                [hard]\ncontacts = \"all\"\n[walls]\nleft = { hard = true }\n\
                right = { hard = true, precompression = -1.0 }\n[run]\nuntil = 1.0\n";
    for (disp, want) in [
        (
            "[0.0, 0.01, 0.0, 0.0]",
            "s.toml: [hard].contacts: contact 1 (beads 1–2) starts overlapping by 0.01",
        ),
        (
            "[-0.25, 0.0, 0.0, 0.0]",
            "s.toml: [walls].left: bead 0 starts inside the hard wall by 0.25",
        ),
        (
            "[0.0, 0.0, 0.0, 1.5]",
            "s.toml: [walls].right: bead 3 starts inside the hard wall by 0.5",
        ),
    ] {
        let text = base.replace("[0.0, 0.0, 0.0, 0.0]", disp);
        let err = parse_str(&text, Path::new("."), "s.toml")
            .expect_err("rejected")
            .to_string();
        assert_eq!(err, want);
    }
    // touching exactly is fine
    scene(base);
    // a soft contact may overlap (precompression)
    let soft = base.replace("contacts = \"all\"", "contacts = [0, 2]");
    scene(&soft.replace("[0.0, 0.0, 0.0, 0.0]", "[0.0, 0.01, 0.0, 0.0]"));
}

/// Item 4 through the binary: exit code 2, one line, nothing written.
#[test]
fn hard_overlap_at_start_cli_error() {
    let d = tempfile::tempdir().expect("tempdir");
    let text = "[chain]\nbeads = 3\n[initial]\ndisplacement = [0.0, 0.0, -0.5]\n\
                [hard]\ncontacts = [1]\n[run]\nuntil = 1.0\n";
    std::fs::write(d.path().join("s.toml"), text).expect("write");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_beadchain"))
        .args(["run", "s.toml", "--out", "o.bcs"])
        .current_dir(d.path())
        .output()
        .expect("start");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(
        err.trim_end(),
        "beadchain: error: s.toml: [hard].contacts: contact 1 (beads 1–2) starts overlapping by 0.5"
    );
    assert!(!d.path().join("o.bcs").exists());
}

/// Soft beads falling onto a hard wall (bead 0 in a soft cluster) chattered on the wall at the
/// TC interval: 337 928 wall collisions in 30 time units (measured at commit 21dda2a, before
/// the cluster's wall collisions used the sticking rule). Now the bead is held on the wall
/// once its collision sticks; also with a hard contact 0 (a rigid run held by the wall).
#[test]
fn soft_cluster_on_hard_wall_stops_chattering() {
    for contacts in ["[2, 5]", "[0, 2, 5]"] {
        let s = scene(&wall_e05(common::SOFT_ON_HARD_WALL).replace("[2, 5]", contacts));
        let (o, rec) = run_bounded(&s, 200_000);
        assert!(
            hard_events(&o) < 1_000,
            "{contacts}: {:?}",
            o.events_by_kind
        );
        assert!(o.u.iter().chain(&o.v).all(|x| x.is_finite()));
        // the soft contacts are integrated: energy to abs 1e-9, rel 1e-9 of the total per frame
        assert_energy_never_increases(&s, &rec, 1e-9, 1e-9);
    }
}

/// Records frames; checkpoints and stops at the `at`-th poll (encoded as on disk).
struct Stopper {
    polls: u64,
    at: u64,
    rec: Recorder,
    saved: Option<(beadchain::engine::EngineState, usize)>,
}

impl Observer for Stopper {
    fn frame(&mut self, t: f64, u: &[f64], v: &[f64]) -> Result<(), EngineError> {
        self.rec.frame(t, u, v)
    }
    fn control(&mut self, _t: f64) -> Control {
        self.polls += 1;
        Control::stop_if(self.polls == self.at)
    }
    fn checkpoint(&mut self, state: &beadchain::engine::EngineState) -> Result<(), EngineError> {
        let cfg = bincode::config::standard();
        let bytes = bincode::serde::encode_to_vec(state, cfg).expect("encodes");
        let (back, _) = bincode::serde::decode_from_slice(&bytes, cfg).expect("decodes");
        self.saved = Some((back, self.rec.t.len()));
        Ok(())
    }
}

fn bits(r: &Recorder) -> Vec<u64> {
    r.t.iter()
        .chain(r.u.iter().flatten())
        .chain(r.v.iter().flatten())
        .map(|x| x.to_bits())
        .collect()
}

/// Resting contacts are part of the checkpointed state: a run stopped anywhere and resumed
/// gives bit-identical frames and final state (free groups, rigid runs in clusters, pins).
#[test]
fn resting_contacts_resume_bit_identically() {
    let seg =
        "[chain]\nbeads = 20\n[initial]\nstriker = 1.0\n[hard]\ncontacts = { from = 8, to = 11 }\n\
               restitution = 0.5\n[run]\nuntil = 80.0\nevery = 2.0\n";
    let cases = [
        wall_e05(common::FALLING_STACK),
        wall_e05(common::SOFT_ON_HARD_WALL).replace("[2, 5]", "[0, 2, 5]"),
        seg.to_string(),
    ];
    for text in &cases {
        let s = scene(text);
        let c = cfg(&s);
        let mut full = Stopper {
            polls: 0,
            at: u64::MAX,
            rec: Recorder::default(),
            saved: None,
        };
        let reference = beadchain::engine::run(&s, &c, &mut full).expect("runs");
        for frac in [0.2, 0.6, 0.95] {
            let at = (full.polls as f64 * frac) as u64 + 1;
            let mut first = Stopper {
                polls: 0,
                at,
                rec: Recorder::default(),
                saved: None,
            };
            beadchain::engine::run(&s, &c, &mut first).expect_err("stopped");
            let (state, n) = first.saved.take().expect("checkpoint");
            let mut second = Recorder::default();
            let out = beadchain::engine::resume(&s, &c, &state, &mut second).expect("resumes");
            let mut joined = Recorder::default();
            for k in 0..n {
                joined
                    .frame(first.rec.t[k], &first.rec.u[k], &first.rec.v[k])
                    .expect("frame");
            }
            for k in 0..second.t.len() {
                joined
                    .frame(second.t[k], &second.u[k], &second.v[k])
                    .expect("frame");
            }
            assert_eq!(bits(&joined), bits(&full.rec), "at {frac}");
            assert_eq!(out.u, reference.u);
            assert_eq!(out.v, reference.v);
            assert_eq!(out.events_by_kind, reference.events_by_kind);
        }
    }
}

/// A scene of `tests/common` with its hard left wall's restitution 0.5 instead of 0.8.
fn wall_e05(text: &str) -> String {
    text.replace(
        "left = { hard = true, restitution = 0.8 }",
        "left = { hard = true, restitution = 0.5 }",
    )
}
