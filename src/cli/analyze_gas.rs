//! The gas part of `beadchain analyze`: the collision rate (always) and, for a gas (a scene with
//! walls and gaps) or with `--gas`, the kinetic temperature per frame and the velocity
//! distribution at the first and the last frame. The formulas are
//! [`beadchain::analysis::gas`]'s; every number is in the snapshot's computer units, with SI
//! beside them for a physical scene (rate `R/β` per second, temperature `T·m0/β²` in J,
//! velocities `v/β` in m/s; paper eq. 10), as the rest of `analyze` prints them.

use beadchain::analysis::gas::{
    collision_rate, collisions_per_frame, kinetic_temperature, velocity_stats, CollisionRate,
    VelocityStats,
};
use beadchain::model::Chain;
use beadchain::scene::{Engine, UnitScales};
use beadchain::snapshot::{Frame, Snapshot};
use std::fmt::Write as _;

/// One frame's gas numbers.
pub struct GasFrame {
    /// Frame time.
    pub t: f64,
    /// Kinetic temperature.
    pub temperature: f64,
    /// Bead–bead collisions since the previous frame (`(t_prev, t]`); `None` when the run logged
    /// no events (the dense engine), not 0.
    pub collisions: Option<u64>,
}

/// What `analyze` reports about collisions and, for a gas, temperatures.
pub struct GasReport {
    /// The collision count and rate over the frames' span.
    pub collisions: CollisionRate,
    /// Per frame (only when the gas part is shown).
    pub frames: Vec<GasFrame>,
    /// Velocity distribution at the first and the last frame (only when shown).
    pub velocity: Option<(VelocityStats, VelocityStats)>,
    /// The scene's SI scales (physical scenes).
    pub units: Option<UnitScales>,
}

/// Whether a chain is a gas: walls and at least one initial gap (negative precompression).
pub fn is_gas(chain: &Chain) -> bool {
    let walls = chain.left_wall.is_some() || chain.right_wall.is_some();
    let gaps = chain
        .precompression
        .as_ref()
        .is_some_and(|d| d.iter().any(|&x| x < 0.0));
    walls && gaps
}

/// The report of a snapshot's frames and event log; `gas`: include the temperatures and the
/// velocity distribution.
pub fn report(snap: &Snapshot, frames: &[Frame], gas: bool) -> GasReport {
    let header = snap.header();
    let chain = &header.scene.chain;
    let n = chain.len();
    let logged = header.engine == Engine::Hybrid;
    let span = match (frames.first(), frames.last()) {
        (Some(a), Some(b)) => (a.t, b.t),
        _ => (0.0, 0.0),
    };
    let collisions = collision_rate(snap.events(), span, n, logged);
    let (mut per_frame, mut velocity) = (Vec::new(), None);
    if gas {
        let times: Vec<f64> = frames.iter().map(|f| f.t).collect();
        let counts = collisions_per_frame(snap.events(), &times);
        per_frame = frames
            .iter()
            .zip(counts)
            .map(|(f, c)| GasFrame {
                t: f.t,
                temperature: kinetic_temperature(&chain.mass, &f.v),
                collisions: logged.then_some(c),
            })
            .collect();
        if let (Some(a), Some(b)) = (frames.first(), frames.last()) {
            velocity = Some((velocity_stats(&a.v), velocity_stats(&b.v)));
        }
    }
    GasReport {
        collisions,
        frames: per_frame,
        velocity,
        units: header.scene.units,
    }
}

/// The collision line(s) and, when shown, the gas summary (and with `table` the per-frame
/// temperatures).
pub fn text(r: &GasReport, table: bool) -> String {
    let mut o = String::new();
    let c = &r.collisions;
    let (t0, t1) = c.span;
    match (c.logged, c.rate, c.per_bead) {
        (false, _, _) => {
            let _ = writeln!(
                o,
                "collisions: not computed (the dense engine logs no events; run with the hybrid engine)"
            );
        }
        (true, Some(rate), Some(per_bead)) => {
            let si = |x: f64| {
                r.units.map_or(String::new(), |u| {
                    format!(" (SI: {:.6e} per s)", x / u.time)
                })
            };
            let (si_rate, si_bead) = (si(rate), si(per_bead));
            let _ = writeln!(
                o,
                "collisions (close and hard_collision events between beads, t = {t0} to {t1}): {}, rate {rate:.6e} per unit time{si_rate}, {per_bead:.6e} per bead per unit time{si_bead}; wall collisions (wall_close): {}",
                c.pair, c.wall
            );
        }
        (true, _, _) => {
            let _ = writeln!(
                o,
                "collisions: {} between beads, {} with walls; rate not computed (the frames span no time)",
                c.pair, c.wall
            );
        }
    }
    if let Some((first, last)) = &r.velocity {
        gas_summary(&mut o, r, first, last);
        if table {
            frames_table(&mut o, r);
        } else {
            o.push_str("(per-frame kinetic temperature and collisions: --frames)\n");
        }
    }
    o
}

fn gas_summary(o: &mut String, r: &GasReport, first: &VelocityStats, last: &VelocityStats) {
    let (Some(a), Some(b)) = (r.frames.first(), r.frames.last()) else {
        return;
    };
    let (lo, hi) = r.frames.iter().fold((f64::INFINITY, 0.0f64), |(l, h), f| {
        (l.min(f.temperature), h.max(f.temperature))
    });
    let joule = |e: f64| r.units.map(|u| e * u.mass / (u.time * u.time));
    let si = |e: f64| joule(e).map_or(String::new(), |j| format!(" ({j:.6e} J)"));
    let _ = writeln!(
        o,
        "kinetic temperature T_kin = (1/N) sum_i m_i (v_i - v_cm)^2 (an energy, k_B = 1; computer units{}): first frame (t = {}) {:.6e}{}, last frame (t = {}) {:.6e}{}, range {:.6e}{} to {:.6e}{}",
        if r.units.is_some() { ", J in SI" } else { "" },
        a.t,
        a.temperature,
        si(a.temperature),
        b.t,
        b.temperature,
        si(b.temperature),
        lo,
        si(lo),
        hi,
        si(hi)
    );
    let _ = writeln!(
        o,
        "velocity distribution (every bead once; computer units; histogram: beads in bins with edges mean + k std, k = -3..3):"
    );
    for (what, t, s) in [("first", a.t, first), ("last", b.t, last)] {
        let kurt = s
            .excess_kurtosis
            .map_or("not computed (std 0)".into(), |k| format!("{k:.4}"));
        let hist: Vec<String> = s.histogram.iter().map(u64::to_string).collect();
        // v/β in m/s beside a physical scene's velocities, as the module docs promise
        let ms = |v: f64| {
            r.units
                .map_or(String::new(), |u| format!(" ({:.6e} m/s)", v / u.time))
        };
        let _ = writeln!(
            o,
            "  {what} frame (t = {t}): mean {:.6e}{}, std {:.6e}{}, excess kurtosis {kurt}, histogram [{}]",
            s.mean,
            ms(s.mean),
            s.std,
            ms(s.std),
            hist.join(", ")
        );
    }
}

fn frames_table(o: &mut String, r: &GasReport) {
    let _ = writeln!(
        o,
        "kinetic temperature and collisions per frame (collisions in (t_prev, t], rate = collisions / (t - t_prev)):"
    );
    let _ = writeln!(
        o,
        "{:>14} {:>14} {:>10} {:>14}",
        "t", "T_kin", "collisions", "rate"
    );
    let mut prev: Option<f64> = None;
    for f in &r.frames {
        let rate = match (prev, f.collisions) {
            (Some(p), Some(c)) if f.t > p => format!("{:.6e}", c as f64 / (f.t - p)),
            _ => "-".into(),
        };
        let count = f.collisions.map_or("-".into(), |c| c.to_string());
        let _ = writeln!(
            o,
            "{:>14.6e} {:>14.6e} {:>10} {:>14}",
            f.t, f.temperature, count, rate
        );
        prev = Some(f.t);
    }
}

fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:e}")
    } else {
        "null".into()
    }
}

fn opt(x: Option<f64>) -> String {
    x.map_or("null".into(), num)
}

fn velocity_json(s: &VelocityStats) -> String {
    let hist: Vec<String> = s.histogram.iter().map(u64::to_string).collect();
    format!(
        "{{\"mean\": {}, \"std\": {}, \"excess_kurtosis\": {}, \"histogram\": [{}]}}",
        num(s.mean),
        num(s.std),
        opt(s.excess_kurtosis),
        hist.join(", ")
    )
}

/// The JSON members (each starting with `,\n  `) of the report.
pub fn json(r: &GasReport) -> String {
    let c = &r.collisions;
    // counts of a run that logged no events are unknown (null), not 0
    let count = |x: u64| {
        if c.logged {
            x.to_string()
        } else {
            "null".into()
        }
    };
    let mut o = format!(
        ",\n  \"collisions\": {{\"logged\": {}, \"pair\": {}, \"wall\": {}, \"t_first\": {}, \"t_last\": {}, \"rate\": {}, \"rate_per_bead\": {}}}",
        c.logged,
        count(c.pair),
        count(c.wall),
        num(c.span.0),
        num(c.span.1),
        opt(c.rate),
        opt(c.per_bead)
    );
    if let Some((first, last)) = &r.velocity {
        o.push_str(",\n  \"gas\": {\"temperature\": [");
        for (i, f) in r.frames.iter().enumerate() {
            let _ = write!(
                o,
                "{}\n    {{\"t\": {}, \"T_kin\": {}, \"collisions\": {}}}",
                if i > 0 { "," } else { "" },
                num(f.t),
                num(f.temperature),
                f.collisions.map_or("null".into(), |c| c.to_string())
            );
        }
        let _ = write!(
            o,
            "\n  ], \"velocity_first\": {}, \"velocity_last\": {}}}",
            velocity_json(first),
            velocity_json(last)
        );
    }
    o
}
