//! `beadchain inspect`: the human-readable report of a snapshot (header fields with the
//! provenance block: version, build commit, date, command line, scene, engine settings; frames
//! and time span, the energy of paper eq. 1 plus kinetic energy at the first and last frame via
//! [`Chain::energy`], run statistics, warnings), and the check of every frame's checksum.

use super::Num;
use crate::model::Chain;
use crate::names::Named;
use crate::snapshot::{Frame, Snapshot, SnapshotError, FORMAT_VERSION, WALL_NOT_RECORDED};
use std::fmt::Write as _;

/// Reads every frame (verifying its section header, length, checksum and time): the frames
/// that fail, with the reason. One frame buffer is reused.
pub fn damaged_frames(snap: &Snapshot) -> Vec<(usize, String)> {
    let mut f = Frame::default();
    let prefix = format!("{}: ", snap.path().display());
    (0..snap.frame_count())
        .filter_map(|k| {
            let e = snap.read_frame_into(k, &mut f).err()?.to_string();
            Some((k, e.strip_prefix(&prefix).unwrap_or(&e).to_string()))
        })
        .collect()
}

/// Human-readable report: header fields, frame count and time span, total energy at the first
/// and last frame (with `chain`, normally `&snap.header().scene.chain`) and its relative
/// change, run statistics and warnings. Every frame's checksum is verified
/// ([`damaged_frames`]); damaged frames are listed and the file is not called complete.
pub fn inspect(snap: &Snapshot, chain: &Chain) -> String {
    inspect_with(snap, chain, &damaged_frames(snap))
}

/// [`inspect`] with the damaged frames already found.
pub fn inspect_with(snap: &Snapshot, chain: &Chain, damaged: &[(usize, String)]) -> String {
    let mut s = String::new();
    header_lines(&mut s, snap, damaged);
    let n = snap.frame_count();
    let _ = writeln!(s, "frames:      {n}");
    if n > 0 {
        let times = snap.frame_times();
        let _ = write!(s, "time span:   {} .. {}", Num(times[0]), Num(times[n - 1]));
        if let Some(u) = snap.header().scene.units {
            let _ = write!(
                s,
                " (SI: {:e} s .. {:e} s)",
                times[0] * u.time,
                times[n - 1] * u.time
            );
        }
        let _ = writeln!(s);
        energy_lines(&mut s, snap, chain);
    }
    let _ = writeln!(s, "events:      {}", snap.events().len());
    run_lines(&mut s, snap);
    for w in snap.warnings() {
        let _ = writeln!(s, "warning:     {w}");
    }
    for (k, e) in damaged {
        let _ = writeln!(s, "damaged:     frame {k}: {e}");
    }
    s
}

/// File, format and state, provenance (version, commit, date, command), scene, stored
/// selection, engine settings.
fn header_lines(s: &mut String, snap: &Snapshot, damaged: &[(usize, String)]) {
    let h = snap.header();
    let _ = writeln!(s, "file:        {}", snap.path().display());
    let state = match (snap.is_complete(), damaged.len()) {
        (true, 0) => "complete".to_string(),
        (false, 0) => "INCOMPLETE (no valid END/INDEX)".to_string(),
        (c, d) => format!(
            "{}DAMAGED: {d} of {} frames fail their checks",
            if c {
                ""
            } else {
                "INCOMPLETE (no valid END/INDEX), "
            },
            snap.frame_count()
        ),
    };
    let _ = writeln!(
        s,
        "format:      version {} (this build reads 1..={FORMAT_VERSION}), {state}",
        h.format_version,
    );
    let _ = writeln!(s, "written by:  beadchain {}", h.crate_version);
    let _ = writeln!(
        s,
        "commit:      {}",
        h.build_commit.as_deref().unwrap_or("not recorded")
    );
    let _ = writeln!(
        s,
        "created:     {}",
        h.created_at
            .as_deref()
            .unwrap_or(super::provenance::NO_DATE)
    );
    let _ = writeln!(s, "command:     {}", h.created_by);
    let _ = writeln!(s, "scene:       {} — {}", h.scene.name, h.scene.description);
    let _ = writeln!(s, "beads:       {}", h.n_beads);
    if !h.output.is_full() {
        let _ = writeln!(
            s,
            "stored:      {} (run --beads/--fields)",
            h.output.describe(h.n_beads)
        );
    }
    if let Some(k) = h.output.frames_max {
        let _ = writeln!(s, "frames max:  {k}");
    }
    let _ = writeln!(
        s,
        "engine:      {}, method {}, rtol {:e}, atol {:e}, seed {}",
        h.engine.name(),
        h.method.name(),
        h.rtol,
        h.atol,
        h.seed
    );
}

/// Why a frame's energy is not available.
#[derive(Debug, thiserror::Error)]
enum EnergyError {
    /// Partial frames, or an unreadable frame.
    #[error(transparent)]
    Snapshot(#[from] SnapshotError),
    /// The frame does not fit the chain.
    #[error("frame has {frame} beads but the chain has {chain}")]
    BeadCount {
        /// Beads in the frame.
        frame: usize,
        /// Beads in the chain.
        chain: usize,
    },
}

/// Energy of the first and last frame and its relative change (or why it is not available).
fn energy_lines(s: &mut String, snap: &Snapshot, chain: &Chain) {
    let n = snap.frame_count();
    let energy = |k: usize| -> Result<(f64, f64, Option<f64>), EnergyError> {
        snap.require_full("the energy needs every bead and both fields")?;
        let f = snap.frame(k)?;
        if f.u.len() != chain.len() {
            return Err(EnergyError::BeadCount {
                frame: f.u.len(),
                chain: chain.len(),
            });
        }
        let (e, scale) = (chain.energy(&f.u, &f.v), chain.energy_scale(&f.u, &f.v));
        Ok((e, scale, f.dissipated))
    };
    match (energy(0), energy(n - 1)) {
        (Ok((e0, s0, d0)), Ok((e1, s1, d1))) => {
            let _ = write!(
                s,
                "energy:      first frame {}, last frame {}",
                Num(e0),
                Num(e1)
            );
            if let Some(u) = snap.header().scene.units {
                let j = u.mass / (u.time * u.time);
                let _ = write!(s, " (SI: {:e} J, {:e} J)", e0 * j, e1 * j);
            }
            let _ = writeln!(s);
            // Relative to the gross energy (meaningful when E0 = 0, e.g. rest under a field).
            let rel = crate::model::relative_energy_change(e0, e1, s0.max(s1)).copysign(e1 - e0);
            let _ = writeln!(s, "energy change (relative): {rel:.3e}");
            if let (true, Some(d0), Some(d1)) = (chain.loses_energy(), d0, d1) {
                // E + E_d is conserved (format 4 frames store E_d): the balance error.
                let (b0, b1) = (e0 + d0, e1 + d1);
                let bal =
                    crate::model::relative_energy_change(b0, b1, s0.max(s1)).copysign(b1 - b0);
                let si = snap.header().scene.units.map_or(String::new(), |u| {
                    format!(" (SI: {:e} J)", (d1 - d0) * u.mass / (u.time * u.time))
                });
                let _ = writeln!(
                    s,
                    "dissipated:  {}{si} by the last frame (balance error {bal:.3e})",
                    Num(d1 - d0)
                );
                if let Some(note) = crate::engine::balance_note(bal.abs(), snap.header().rtol) {
                    let _ = writeln!(s, "warning:     {note}");
                }
            }
        }
        (Err(e), _) if !snap.header().output.is_full() => {
            let _ = writeln!(s, "energy:      not available: {e}");
        }
        (a, b) => {
            for (which, r) in [("first", a), ("last", b)] {
                if let Err(e) = r {
                    let _ = writeln!(s, "energy:      {which} frame unreadable: {e}");
                }
            }
        }
    }
}

/// The run summary (statistics, events by kind, notes), if the run finished.
fn run_lines(s: &mut String, snap: &Snapshot) {
    match snap.summary() {
        Some(r) => {
            let st = &r.stats;
            // a run without --timing stores 0 s and a note: say "not recorded" once, here
            let untimed = r.notes.iter().any(|n| n == WALL_NOT_RECORDED);
            let wall = if untimed {
                "wall time not recorded (see --timing)".to_string()
            } else {
                format!("wall {:.3} s", r.wall_seconds)
            };
            let _ = writeln!(
                s,
                "run:         t_end {}, {wall}, energy {} -> {}, momentum {} -> {}",
                Num(r.t_end),
                Num(r.energy_initial),
                Num(r.energy_final),
                Num(r.momentum_initial),
                Num(r.momentum_final)
            );
            let _ = writeln!(
                s,
                "steps:       {} accepted, {} rejected, {} rhs, {} jac, {} lu, {} newton ({} failed), {} bead-steps",
                st.steps,
                st.rejected,
                st.rhs_evals,
                st.jac_evals,
                st.factorizations,
                st.newton_iters,
                st.newton_failures,
                st.bead_steps
            );
            if !r.events_by_kind.is_empty() {
                let kinds: Vec<String> = r
                    .events_by_kind
                    .iter()
                    .map(|(k, c)| format!("{k} {c}"))
                    .collect();
                let _ = writeln!(s, "events by kind: {}", kinds.join(", "));
            }
            let _ = writeln!(s, "largest cluster: {}", r.largest_cluster);
            for note in r.notes.iter().filter(|n| *n != WALL_NOT_RECORDED) {
                let _ = writeln!(s, "note:        {note}");
            }
        }
        None => {
            let _ = writeln!(s, "run:         no statistics (run did not finish)");
        }
    }
}
