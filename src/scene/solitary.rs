//! `[initial].solitary`: exact solitary waves of the discrete chain as initial condition
//! ([`crate::studies::solitary`]: the travelling wave of `m c² R'' = Δ₂ F(R)`, scaled profile
//! solved by Petviashvili's iteration).
//!
//! ```toml
//! solitary = { at = 50, velocity = 1.0 }                       # peak bead velocity v_m, moving right
//! solitary = { at = 50, energy = 2.0, direction = "left" }     # or its energy E = κ(n) m v_m²
//! solitary = [{ at = 30, velocity = 1.0 }, { at = 70, velocity = 1.0, direction = "left" }]
//! ```
//!
//! Physical scenes also accept `velocity_si` (m/s, converted by `v β`) and `energy_si` (J,
//! converted by `E β² / m0`, paper eq. 11, [`UnitScales`]). Bead `at` gets the peak velocity; beads ahead
//! of the wave stay at rest and unshifted, those behind are shifted by the wave's total
//! compression `Σ r`, so every contact carries exactly the wave's overlap. The waves add to the
//! `displacement`/`velocity`/`pulse`/`striker` state. Refused: a wave whose support (beads where
//! its velocity or overlap exceeds 1e-15 of the peak, plus one bead each side) leaves the chain,
//! meets another wave's, or is not uniform (mass, exponent, prefactor; the message names the bead
//! or contact where it changes); `n ≤ 2`; a precompression, field or hard contact on it.

use super::ctx::table_of;
use super::error::SceneError;
use super::keys::{forbid, PHYSICAL_ONLY};
use super::tables::{SolitaryKeys, Tables};
use super::units::UnitScales;
use super::values::{index, number, Ctx};
use super::Scene;
use crate::studies::solitary::{Direction, Placement, UnitProfile, Wave};
use toml::Value;

/// One `[initial].solitary` entry as written.
struct Spec {
    key: String,
    at: usize,
    amount: Amount,
    direction: Direction,
}

enum Amount {
    PeakVelocity(f64),
    Energy(f64),
}

/// Adds the scene's solitary waves to `scene.u0`, `scene.v0` (the chain is fully built).
pub(super) fn apply(
    ctx: &Ctx,
    t: &Tables,
    physical: bool,
    scales: Option<UnitScales>,
    scene: &mut Scene,
) -> Result<(), SceneError> {
    let Some(value) = &t.initial.solitary else {
        return Ok(());
    };
    let entries: Vec<(String, &Value)> = match value {
        Value::Array(a) => a
            .iter()
            .enumerate()
            .map(|(i, v)| (format!("[initial].solitary[{i}]"), v))
            .collect(),
        v => vec![("[initial].solitary".to_string(), v)],
    };
    let mut profiles: Vec<UnitProfile> = Vec::new();
    let mut placed: Vec<(String, Placement)> = Vec::new();
    for (key, v) in entries {
        let spec = parse_entry(ctx, &key, v, physical, scales)?;
        let nb = scene.chain.mass.len();
        if spec.at >= nb {
            return Err(ctx.err(
                &format!("{key}.at"),
                format!(
                    "bead {} is outside the chain (beads 0..={})",
                    spec.at,
                    nb - 1
                ),
            ));
        }
        let wave = wave_at(ctx, &spec, scene, &mut profiles)?;
        let p = wave
            .place(spec.at, spec.direction, nb)
            .map_err(|m| ctx.err(&format!("{key}.at"), m.to_string()))?;
        check_uniform(ctx, &spec, &p, scene)?;
        if let Some((other, _)) = placed.iter().find(|(_, q)| {
            q.beads().start() <= p.beads().end() && p.beads().start() <= q.beads().end()
        }) {
            return Err(ctx.err(
                &key,
                format!(
                    "its support (beads {}..={}) overlaps the wave of {other}",
                    p.beads().start(),
                    p.beads().end()
                ),
            ));
        }
        p.add_to(&mut scene.u0, &mut scene.v0);
        placed.push((key, p));
    }
    Ok(())
}

/// The wave of one entry for the chain's local `n`, `a`, `m` at bead `at` (profiles are
/// computed once per exponent).
fn wave_at(
    ctx: &Ctx,
    spec: &Spec,
    scene: &Scene,
    profiles: &mut Vec<UnitProfile>,
) -> Result<Wave, SceneError> {
    let ch = &scene.chain;
    let c = spec.at.min(ch.exponent.len() - 1);
    let n = ch.exponent[c];
    if n <= 2.0 {
        return Err(ctx.err(
            &format!("{}.at", spec.key),
            format!("contact {c} has exponent n = {n}: solitary waves need n > 2"),
        ));
    }
    let profile = match profiles.iter().find(|p| p.exponent == n) {
        Some(p) => p.clone(),
        None => {
            let p = UnitProfile::compute(n).map_err(|m| ctx.err(&spec.key, m.to_string()))?;
            profiles.push(p.clone());
            p
        }
    };
    let (m, a) = (ch.mass[spec.at], ch.prefactor[c]);
    match spec.amount {
        Amount::PeakVelocity(v) => Wave::with_peak_velocity(profile, m, a, v),
        Amount::Energy(e) => Wave::with_energy(profile, m, a, e),
    }
    .map_err(|msg| ctx.err(&spec.key, msg.to_string()))
}

/// Equal within 1e-12 (relative): physical scenes compute each contact's prefactor on its own.
fn same(x: f64, y: f64) -> bool {
    (x - y).abs() <= 1e-12 * x.abs().max(y.abs())
}

/// The indices of `range` ordered by distance from `centre` (nearest first), so the first
/// mismatch found is where the chain changes.
fn outward(range: std::ops::RangeInclusive<usize>, centre: usize) -> Vec<usize> {
    let mut v: Vec<usize> = range.collect();
    v.sort_by_key(|i| (i.abs_diff(centre), *i));
    v
}

/// Refuses a chain that is not uniform (or precompressed, in a field, hard) over the support.
fn check_uniform(ctx: &Ctx, spec: &Spec, p: &Placement, scene: &Scene) -> Result<(), SceneError> {
    let ch = &scene.chain;
    let key = format!("{}.at", spec.key);
    let c0 = spec.at.min(ch.exponent.len() - 1);
    let span = format!(
        "the chain is not uniform over the wave's support (beads {}..={})",
        p.beads().start(),
        p.beads().end()
    );
    for b in outward(p.beads(), spec.at) {
        if !same(ch.mass[b], ch.mass[spec.at]) {
            return Err(ctx.err(
                &key,
                format!(
                    "{span}: bead {b} has mass {} (bead {} has {})",
                    ch.mass[b], spec.at, ch.mass[spec.at]
                ),
            ));
        }
        if let Some(f) = ch.field.as_ref().filter(|f| f[b] != 0.0) {
            return Err(ctx.err(
                &key,
                format!("bead {b} feels the external force {}: solitary waves need no field over their support", f[b]),
            ));
        }
    }
    for c in outward(p.contacts(), spec.at) {
        for (what, arr) in [("exponent", &ch.exponent), ("prefactor", &ch.prefactor)] {
            if !same(arr[c], arr[c0]) {
                return Err(ctx.err(
                    &key,
                    format!(
                        "{span}: contact {c} (beads {c}-{}) has {what} {} (contact {c0} has {})",
                        c + 1,
                        arr[c],
                        arr[c0]
                    ),
                ));
            }
        }
        if let Some(d) = ch.precompression.as_ref().filter(|d| d[c] != 0.0) {
            return Err(ctx.err(
                &key,
                format!("contact {c} has precompression {}: only the sonic vacuum (precompression 0) is supported over the wave's support", d[c]),
            ));
        }
        if ch.hard.as_ref().is_some_and(|h| h.restitution[c].is_some()) {
            return Err(ctx.err(
                &key,
                format!("contact {c} is hard: solitary waves need power-law contacts over their support"),
            ));
        }
    }
    Ok(())
}

/// One entry `{ at, velocity | velocity_si | energy | energy_si, direction }`.
fn parse_entry(
    ctx: &Ctx,
    key: &str,
    v: &Value,
    physical: bool,
    scales: Option<UnitScales>,
) -> Result<Spec, SceneError> {
    let shape = "a table { at, velocity | energy, direction } or an array of them";
    let t: SolitaryKeys = table_of(ctx, key, Some(v), shape)?.unwrap_or_default();
    if !physical {
        let si = [("velocity_si", &t.velocity_si), ("energy_si", &t.energy_si)];
        forbid(ctx, key, &si, PHYSICAL_ONLY)?;
    }
    let at = match &t.at {
        Some(b) => index(ctx, &format!("{key}.at"), b)?,
        None => return Err(ctx.err(&format!("{key}.at"), "missing (the wave's centre bead)")),
    };
    let amount = amount(ctx, key, &t, scales)?;
    let direction = match &t.direction {
        None => Direction::Right,
        Some(Value::String(s)) if s == "right" => Direction::Right,
        Some(Value::String(s)) if s == "left" => Direction::Left,
        Some(d) => {
            return Err(ctx.err(
                &format!("{key}.direction"),
                format!("expected \"right\" or \"left\", got {d}"),
            ))
        }
    };
    Ok(Spec {
        key: key.to_string(),
        at,
        amount,
        direction,
    })
}

/// Exactly one of `velocity`, `velocity_si` (m/s, `v β`), `energy`, `energy_si` (J,
/// `E β² / m0`), as written `> 0`; in computer units.
fn amount(
    ctx: &Ctx,
    key: &str,
    t: &SolitaryKeys,
    scales: Option<UnitScales>,
) -> Result<Amount, SceneError> {
    let amounts = [
        ("velocity", &t.velocity),
        ("velocity_si", &t.velocity_si),
        ("energy", &t.energy),
        ("energy_si", &t.energy_si),
    ];
    let given: Vec<(&str, &Value)> = (amounts.into_iter())
        .filter_map(|(k, v)| v.as_ref().map(|v| (k, v)))
        .collect();
    let names: Vec<&str> = given.iter().map(|(k, _)| *k).collect();
    // The amount as written, > 0 (the message names the key and the value given).
    let num = |(k, v): (&str, &Value)| match number(ctx, &format!("{key}.{k}"), v)? {
        x if x > 0.0 => Ok(x),
        x => Err(ctx.err(&format!("{key}.{k}"), format!("must be > 0, got {x}"))),
    };
    let si =
        |k: &str| scales.ok_or_else(|| ctx.err(&format!("{key}.{k}"), "needs a physical scene"));
    Ok(match given.as_slice() {
        [g @ ("velocity", _)] => Amount::PeakVelocity(num(*g)?),
        [g @ ("velocity_si", _)] => Amount::PeakVelocity(si(g.0)?.velocity(num(*g)?)),
        [g @ ("energy", _)] => Amount::Energy(num(*g)?),
        [g] => Amount::Energy(si(g.0)?.energy(num(*g)?)),
        [] => {
            return Err(ctx.err(
                &format!("{key}.velocity"),
                "missing: give the peak velocity `velocity` (or `velocity_si`) or the `energy` (or `energy_si`)",
            ))
        }
        _ => {
            return Err(ctx.err(
                &format!("{key}.{}", names[1]),
                format!("give only one of {}", names.join(", ")),
            ))
        }
    })
}
