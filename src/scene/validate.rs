//! Validation of a resolved [`Scene`]: hard errors (the run could not be meaningful) and
//! warnings (it can run, but the user should know). Implements the model constraints of the
//! paper's eq. 1 and 7: `n > 1` (with a warning below 2, where the force `n a δ^{n−1}` is not C¹
//! at contact), `a > 0`, `m > 0`, everything finite.

use super::error::SceneError;
use super::values::{Ctx, Per};
use super::{RunSettings, Scene};
use crate::model::Chain;
use std::path::Path;

/// How many indices a warning lists before summarising.
const LIST_MAX: usize = 5;

/// Validate a resolved scene; on success returns the warnings. Messages name the scene (its
/// `name`, control characters escaped), the key path and the bead/contact index.
pub fn validate(scene: &Scene) -> Result<Vec<String>, SceneError> {
    validate_in(scene, &super::error::one_line(&scene.name))
}

/// [`validate`] with messages naming `file`.
pub(crate) fn validate_in(scene: &Scene, file: &str) -> Result<Vec<String>, SceneError> {
    let ctx = Ctx {
        file,
        base_dir: Path::new("."),
        seed: scene.seed,
    };
    check_name(&ctx, &scene.name)?;
    check_lengths(&ctx, scene)?;
    check_values(&ctx, scene)?;
    super::hard::check_start(&ctx, scene)?;
    let mut warnings = Vec::new();
    check_walls(&ctx, scene, &mut warnings)?;
    check_run(&ctx, &scene.run)?;
    check_scales(&ctx, scene)?;
    super::damping::check_scale(&ctx, scene)?;
    warn_soft_contacts(file, &scene.chain, &mut warnings);
    let c = &scene.chain;
    let n = c.mass.len();
    let moving = scene.v0.iter().any(|v| *v != 0.0);
    let pressed = c.field.is_some()
        || (0..n - 1).any(|k| c.overlap(k, scene.u0[k], scene.u0[k + 1]) > 0.0)
        || c.left_wall
            .as_ref()
            .is_some_and(|w| w.precompression - scene.u0[0] > 0.0)
        || c.right_wall
            .as_ref()
            .is_some_and(|w| w.precompression + scene.u0[n - 1] > 0.0);
    if !moving && !pressed {
        warnings.push(format!(
            "{file}: [initial]: every bead at rest with no force: nothing will move"
        ));
    }
    let r = &scene.run;
    if let Some(e) = r.every {
        if e > r.until {
            warnings.push(format!(
                "{file}: [run].every: {e} > until {}: only the first and last frame",
                r.until
            ));
        }
    }
    Ok(warnings)
}

/// At least two beads, and every array as long as the chain (per bead) or one shorter (per
/// contact).
fn check_lengths(ctx: &Ctx, scene: &Scene) -> Result<(), SceneError> {
    let c = &scene.chain;
    let n = c.mass.len();
    if n < 2 {
        return Err(ctx.err(
            "[chain].beads",
            format!("a chain needs at least 2 beads, got {n}"),
        ));
    }
    let len = |key: &str, got: usize, want: usize, per: Per| {
        if got == want {
            Ok(())
        } else {
            Err(ctx.err(
                key,
                format!("expected {want} values (one per {}), got {got}", per.noun()),
            ))
        }
    };
    len("[chain].exponent", c.exponent.len(), n - 1, Per::Contact)?;
    len("[chain].prefactor", c.prefactor.len(), n - 1, Per::Contact)?;
    if let Some(p) = &c.precompression {
        len("[chain].precompression", p.len(), n - 1, Per::Contact)?;
    }
    if let Some(w) = &c.field {
        len("[field].force", w.len(), n, Per::Bead)?;
    }
    len("[initial].displacement", scene.u0.len(), n, Per::Bead)?;
    len("[initial].velocity", scene.v0.len(), n, Per::Bead)
}

/// Largest contact or wall exponent a scene may declare: exponents up to it keep the energy to
/// the tolerance (a 4-bead striker at rtol 1e-8: 1e-9 at n = 10⁴); far beyond, the force is a
/// step at `δ ≈ 1` that the engines do not resolve (n = 10¹⁷ gained 150 % of the energy, without
/// a word). A rigid contact is `[hard]`.
pub const MAX_EXPONENT: f64 = 1e4;

/// Every value finite; masses and prefactors > 0, exponents in `(1, MAX_EXPONENT]` (eq. 1).
fn check_values(ctx: &Ctx, scene: &Scene) -> Result<(), SceneError> {
    let c = &scene.chain;
    let check = |key: &str, per: Per, v: &[f64], ok: &dyn Fn(f64) -> bool, need: &str| match v
        .iter()
        .position(|x| !x.is_finite() || !ok(*x))
    {
        None => Ok(()),
        Some(i) if !v[i].is_finite() => {
            Err(ctx.index_err(key, per, i, format!("not a finite number ({})", v[i])))
        }
        Some(i) => Err(ctx.index_err(key, per, i, format!("{need}, got {}", v[i]))),
    };
    let any = |_: f64| true;
    check(
        "[chain].mass",
        Per::Bead,
        &c.mass,
        &|m| m > 0.0,
        "mass must be > 0",
    )?;
    check(
        "[chain].exponent",
        Per::Contact,
        &c.exponent,
        &|x| x > 1.0 && x <= MAX_EXPONENT,
        "exponent must be > 1 and at most 10000 (the range the engines are tested on; a rigid contact is [hard])",
    )?;
    check(
        "[chain].prefactor",
        Per::Contact,
        &c.prefactor,
        &|x| x > 0.0,
        "prefactor must be > 0",
    )?;
    if let Some(p) = &c.precompression {
        check("[chain].precompression", Per::Contact, p, &any, "")?;
    }
    if let Some(w) = &c.field {
        check("[field].force", Per::Bead, w, &any, "")?;
    }
    check("[initial].displacement", Per::Bead, &scene.u0, &any, "")?;
    check("[initial].velocity", Per::Bead, &scene.v0, &any, "")
}

/// Walls: finite, exponent > 1, prefactor > 0; a warning for an exponent below 2.
fn check_walls(ctx: &Ctx, scene: &Scene, warnings: &mut Vec<String>) -> Result<(), SceneError> {
    let c = &scene.chain;
    for (side, wall) in [("left", &c.left_wall), ("right", &c.right_wall)] {
        let Some(w) = wall else { continue };
        let k = format!("[walls].{side}");
        let finite = |name: &str, x: f64| {
            if x.is_finite() {
                Ok(())
            } else {
                Err(ctx.err(&format!("{k}.{name}"), format!("not a finite number ({x})")))
            }
        };
        finite("exponent", w.exponent)?;
        finite("prefactor", w.prefactor)?;
        finite("precompression", w.precompression)?;
        if w.exponent <= 1.0 || w.exponent > MAX_EXPONENT {
            return Err(ctx.err(
                &format!("{k}.exponent"),
                format!(
                    "exponent must be > 1 and at most 10000 (the range the engines are tested on; a rigid wall is hard = true), got {}",
                    w.exponent
                ),
            ));
        }
        if w.prefactor <= 0.0 {
            return Err(ctx.err(
                &format!("{k}.prefactor"),
                format!("prefactor must be > 0, got {}", w.prefactor),
            ));
        }
        if w.exponent < 2.0 {
            warnings.push(format!(
                "{}: {k}.exponent: {} < 2: wall force not C¹ at contact (steps shrink there)",
                ctx.file, w.exponent
            ));
        }
    }
    Ok(())
}

/// `[run]`: end time and interval finite and > 0, tolerances in (0, 1).
fn check_run(ctx: &Ctx, r: &RunSettings) -> Result<(), SceneError> {
    let pos = |key: &str, x: f64| {
        if x.is_finite() && x > 0.0 {
            Ok(())
        } else {
            Err(ctx.err(key, format!("must be a finite number > 0, got {x}")))
        }
    };
    pos("[run].until", r.until)?;
    if let Some(e) = r.every {
        pos("[run].every", e)?;
    }
    for (key, tol) in [("[run].rtol", r.rtol), ("[run].atol", r.atol)] {
        if let Some(t) = tol {
            if !(t > 0.0 && t < 1.0) {
                return Err(ctx.err(key, format!("must be in (0, 1), got {t}")));
            }
        }
    }
    Ok(())
}

/// A warning naming the contacts with an exponent below 2 (force not C¹ at contact).
fn warn_soft_contacts(file: &str, c: &Chain, warnings: &mut Vec<String>) {
    let n = c.mass.len();
    let soft: Vec<usize> = (0..n - 1).filter(|&k| c.exponent[k] < 2.0).collect();
    if !soft.is_empty() {
        let shown: Vec<String> = soft.iter().take(LIST_MAX).map(usize::to_string).collect();
        let more = if soft.len() > LIST_MAX {
            format!(" and {} more", soft.len() - LIST_MAX)
        } else {
            String::new()
        };
        warnings.push(format!(
            "{file}: [chain].exponent: contact {}{more}: exponent < 2 (e.g. {}): force not C¹ at contact (steps shrink there)",
            shown.join(", "),
            c.exponent[soft[0]]
        ));
    }
}

/// `[scene].name` names the default output `<name>.snap` in the working directory, so it must be
/// a plain file stem: not empty, not `.`/`..`, no `/`, `\`, NUL or other control character.
fn check_name(ctx: &Ctx, name: &str) -> Result<(), SceneError> {
    // a control character (a newline) would also split the one-line messages and the
    // exports' `# scene:` comment line that carry the name
    let bad = name.is_empty()
        || name == "."
        || name == ".."
        || name.contains(['/', '\\'])
        || name.chars().any(char::is_control);
    if bad {
        return Err(ctx.err(
            "[scene].name",
            format!(
                "{name:?} is not a plain file name (it names the output <name>.snap in the working directory: no /, \\, NUL or other control character, . or ..)"
            ),
        ));
    }
    Ok(())
}

/// Rejects initial states whose characteristic scales ([`crate::model::Chain::scales`], the unit
/// of every tolerance and of the energy error) under- or overflow f64: an energy of 0 although a
/// bead moves or a contact is compressed (e.g. a striker of 1e-300), a non-finite energy, or a
/// length `(E/a_c)^{1/n_c}` or velocity `sqrt(2E/m_i)` scale that is 0 or not finite.
fn check_scales(ctx: &Ctx, scene: &Scene) -> Result<(), SceneError> {
    use crate::model::contact_potential;
    let (c, u0, v0) = (&scene.chain, &scene.u0, &scene.v0);
    let (kv, ku) = ("[initial].velocity", "[initial].displacement");
    let pot = |k: usize| {
        contact_potential(
            c.exponent[k],
            c.prefactor[k],
            c.overlap(k, u0[k], u0[k + 1]),
        )
    };
    let ke = c.kinetic_energy(v0);
    let pe: f64 = (0..c.len() - 1).map(pot).sum();
    let e = ke + pe;
    if !e.is_finite() {
        let key = if ke.is_finite() { ku } else { kv };
        return Err(ctx.err(key, format!("the initial energy overflows f64 (kinetic {ke:e}, contact {pe:e}): rescale the scene")));
    }
    if e == 0.0 {
        if let Some(i) = v0.iter().position(|v| *v != 0.0) {
            let msg = format!(
                "the kinetic energy ½mv² = {:e} underflows f64 (v = {:e}): rescale the scene",
                0.5 * c.mass[i] * v0[i] * v0[i],
                v0[i]
            );
            return Err(ctx.index_err(kv, Per::Bead, i, msg));
        }
        if let Some(k) = (0..c.len() - 1).find(|&k| c.overlap(k, u0[k], u0[k + 1]) > 0.0) {
            let d = c.overlap(k, u0[k], u0[k + 1]);
            let msg = format!("the contact energy a·δⁿ of the overlap δ = {d:e} underflows f64: rescale the scene");
            return Err(ctx.index_err(ku, Per::Contact, k, msg));
        }
        return Ok(());
    }
    for k in 0..c.len() - 1 {
        let l = (e / c.prefactor[k]).powf(1.0 / c.exponent[k]);
        if !(l > 0.0 && l.is_finite()) {
            let msg = format!("the length scale (E/a)^(1/n) = {l:e} (E = {e:e}) is outside the f64 range: rescale the scene");
            return Err(ctx.index_err("[chain].prefactor", Per::Contact, k, msg));
        }
    }
    for (i, m) in c.mass.iter().enumerate() {
        let v = (2.0 * e / m).sqrt();
        if !(v > 0.0 && v.is_finite()) {
            let msg = format!("the velocity scale sqrt(2E/m) = {v:e} (E = {e:e}) is outside the f64 range: rescale the scene");
            return Err(ctx.index_err("[chain].mass", Per::Bead, i, msg));
        }
    }
    Ok(())
}
