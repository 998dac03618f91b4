//! Warnings for implausible values of a physical scene (issue 32, item 6): plain keys are in
//! computer units, so `striker = 0.11` meant as m/s runs at 0.11/β ≈ 121 000 m/s and
//! `--until 1e-3` meant as seconds runs 0.9 ns. These are warnings, not errors (such values
//! can be meant); each is one line naming the key, giving the value in SI and the `_si` key or
//! `--until-si` to use. Checks (physical scenes only, i.e. `Scene::units` set):
//!
//! - an initial overlap (displacements and precompression; lengths are metres) larger than the
//!   radius of either bead of the contact (needs the [`BeadMaterial`]);
//! - an initial velocity faster than the bead material's bar sound speed `sqrt(Y/ρ)` (needs the
//!   material);
//! - an approaching contact whose head-on collision would reach a peak overlap larger than a
//!   bead radius: with reduced mass `μ`, relative speed `w`, exponent `n`, prefactor `a`, the
//!   two-body collision reaches `δ_max = (μ w²/(2a))^{1/n}` (needs the material);
//! - a run shorter than one contact time of the fastest initial collision,
//!   `t_c = (2 δ_max / w) · √π Γ(1+1/n) / Γ(1/2+1/n)` (the integral `∫₀¹ dx/√(1−xⁿ)`; `π δ_max/w`
//!   for `n = 2`).
//!
//! Scenes shown in computer units (`[units] system = "computer"`) keep the scales but not the
//! material: only the last check applies to them.

use super::Scene;
use crate::model::collision::collision;

/// The SI material of each bead of a physical scene (radius in m, Young's modulus in Pa,
/// density in kg/m³), as parsed from `[units]`.
#[derive(Clone, Debug, PartialEq)]
pub struct BeadMaterial {
    /// Radius per bead, m.
    pub radius: Vec<f64>,
    /// Young's modulus per bead, Pa.
    pub young: Vec<f64>,
    /// Density per bead, kg/m³.
    pub density: Vec<f64>,
}

/// The scene key an initial velocity of `bead` (of `nb`) most likely came from, and its SI twin.
fn velocity_key(bead: usize, v: f64, nb: usize) -> (&'static str, &'static str) {
    match bead {
        0 if v > 0.0 => ("[initial].striker", "striker_si"),
        b if b + 1 == nb && v < 0.0 => ("[initial].striker_right", "striker_right_si"),
        _ => ("[initial].velocity", "velocity_si"),
    }
}

/// The warnings of a physical scene run until `until` (computer units; `until_key` names where
/// it came from: `[run].until`, `[run].until_si` or a command-line option; a key ending in `si`
/// was given in seconds, so its warning gives no advice on units); none for a dimensionless
/// scene.
pub fn warnings(
    scene: &Scene,
    material: Option<&BeadMaterial>,
    until: f64,
    until_key: &str,
) -> Vec<String> {
    let Some(sc) = scene.units else {
        return Vec::new();
    };
    let (c, u0, v0, name) = (&scene.chain, &scene.u0, &scene.v0, &scene.name);
    let nb = c.len();
    let mut out = Vec::new();
    if let Some(m) = material {
        let radius = |k: usize| m.radius[k].min(m.radius[k + 1]);
        if let Some(k) = (0..nb - 1).find(|&k| c.overlap(k, u0[k], u0[k + 1]) > radius(k)) {
            out.push(format!(
                "{name}: [initial].displacement: contact {k} (beads {k}–{}) starts overlapping by {:.4e} m, more than the bead radius {:.4e} m (lengths are metres; [chain].precompression counts too)",
                k + 1,
                c.overlap(k, u0[k], u0[k + 1]),
                radius(k)
            ));
        }
        let sound = |i: usize| (m.young[i] / m.density[i]).sqrt();
        if let Some(i) = (0..nb).find(|&i| v0[i].abs() / sc.time > sound(i)) {
            let (key, si) = velocity_key(i, v0[i], nb);
            out.push(format!(
                "{name}: {key}: bead {i} moves at {:.4e} m/s ({} computer units), faster than the sound speed sqrt(Y/ρ) = {:.4e} m/s of its material: plain velocities are computer units; for m/s write `{si} = {}`",
                v0[i].abs() / sc.time,
                v0[i],
                sound(i),
                v0[i].abs()
            ));
        }
    }
    let mut fastest: Option<(usize, f64)> = None;
    for k in 0..nb - 1 {
        let w = v0[k] - v0[k + 1];
        if c.hard_restitution(k).is_some() || w <= 0.0 || w.is_nan() {
            continue;
        }
        if fastest.is_none_or(|(_, f)| w > f) {
            fastest = Some((k, w));
        }
        let mu = c.mass[k] * c.mass[k + 1] / (c.mass[k] + c.mass[k + 1]);
        let (d, _) = collision(mu, w, c.exponent[k], c.prefactor[k]);
        let r = material.map(|m| m.radius[k].min(m.radius[k + 1]));
        if let Some(r) = r.filter(|r| d > *r) {
            let i = if v0[k] > 0.0 { k } else { k + 1 };
            let (key, si) = velocity_key(i, v0[i], nb);
            out.push(format!(
                "{name}: {key}: bead {i} at {:.4e} m/s ({} computer units) would press contact {k} by {:.4e} m, more than the bead radius {r:.4e} m: plain velocities are computer units; for m/s write `{si} = {}`",
                v0[i].abs() / sc.time,
                v0[i],
                d,
                v0[i].abs()
            ));
            break;
        }
    }
    if let Some((k, w)) = fastest {
        let mu = c.mass[k] * c.mass[k + 1] / (c.mass[k] + c.mass[k + 1]);
        let (_, tc) = collision(mu, w, c.exponent[k], c.prefactor[k]);
        let (until_s, tc_s) = (until * sc.time, tc * sc.time);
        if until < tc && until_key.ends_with("si") {
            out.push(format!(
                "{name}: {until_key}: {until_s:.4e} s is shorter than one contact time of the fastest initial collision ({tc_s:.4e} s, contact {k})"
            ));
        } else if until < tc {
            out.push(format!(
                "{name}: {until_key}: {until} ({until_s:.4e} s) is shorter than one contact time of the fastest initial collision ({tc:.4e} = {tc_s:.4e} s, contact {k}): plain times are computer units; for seconds use `until_si` or `--until-si`"
            ));
        }
    }
    out
}
