//! Reading scene files: TOML text → [`Scene`], with every key checked (unknown keys are errors)
//! and every message naming the file and key path. The key reference is in the `scene` module
//! docs; value forms and builders are in [`super::values`], physical units in [`super::units`].

use super::error::{one_line, SceneError};
use super::keys::{exclusive, forbid, get, kp, opt_num, opt_spec, opt_str, positive, table};
use super::units::{self, UnitScales};
use super::validate::validate_in;
use super::values::{check_keys, index, number, type_name, Ctx, Per, Spec};
use super::{Engine, RunSettings, Scene};
use crate::integrate::Method;
use crate::model::{Chain, Wall};
use std::path::Path;
use toml::{Table, Value};

/// Largest chain a scene may declare (guards against absurd allocations from typos).
pub const MAX_BEADS: usize = 10_000_000;

/// Default per-bead mass of dimensionless scenes.
pub const DEFAULT_MASS: f64 = 1.0;
/// Default contact exponent (Hertz spheres).
pub const DEFAULT_EXPONENT: f64 = 2.5;
/// Default contact prefactor of dimensionless scenes.
pub const DEFAULT_PREFACTOR: f64 = 1.0;

/// Parse scene text. `base_dir` resolves `{ file = ... }` CSVs; `origin` names the file in
/// messages (its stem is the default scene name). The result is validated.
pub fn parse_str(text: &str, base_dir: &Path, origin: &str) -> Result<Scene, SceneError> {
    let origin = one_line(origin);
    let root: Table = toml::from_str(text).map_err(|e| syntax_error(&origin, text, &e))?;
    let scene = build(&root, base_dir, &origin)?;
    validate_in(&scene, &origin)?;
    Ok(scene)
}

/// Convert a TOML error into a one-line error with 1-based line/column.
fn syntax_error(file: &str, text: &str, e: &toml::de::Error) -> SceneError {
    let (line, column) = match e.span() {
        Some(span) => {
            let mut end = span.start.min(text.len());
            while !text.is_char_boundary(end) {
                end -= 1;
            }
            let upto = &text[..end];
            let line = upto.matches('\n').count() + 1;
            let col = upto.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            (line, col)
        }
        None => (0, 0),
    };
    let mut message = one_line(&e.message().trim().replace('\n', "; "));
    if let Some(key) = super::error::key_at_line(text, line) {
        message = format!("{key}: {message}");
    }
    SceneError::Syntax {
        file: file.to_string(),
        line,
        column,
        message,
    }
}

/// The `[units]` material data of a physical scene, resolved.
struct Material {
    radius: Vec<f64>,
    young: Vec<f64>,
    poisson: Vec<f64>,
}

fn build(root: &Table, base_dir: &Path, origin: &str) -> Result<Scene, SceneError> {
    let pre = Ctx {
        file: origin,
        base_dir,
        seed: 0,
    };
    const TABLES: &[&str] = &[
        "scene", "chain", "initial", "run", "field", "walls", "units", "hard", "output",
    ];
    for (k, _) in root.iter() {
        if !TABLES.contains(&k.as_str()) {
            return Err(pre.err(
                &format!("[{}]", one_line(k)),
                format!(
                    "unknown table or key (expected one of: {})",
                    TABLES.join(", ")
                ),
            ));
        }
    }
    let scene_t = table(&pre, root, "scene", &["name", "description", "seed"])?;
    let seed = match get(scene_t, "seed") {
        Some(Value::Integer(i)) if *i >= 0 => *i as u64,
        Some(v) => {
            return Err(pre.err(
                "[scene].seed",
                format!("expected a non-negative integer, got {v}"),
            ))
        }
        None => 0,
    };
    let ctx = Ctx {
        file: origin,
        base_dir,
        seed,
    };
    let ctx = &ctx;
    let chain_t = table(
        ctx,
        root,
        "chain",
        &[
            "beads",
            "mass",
            "exponent",
            "prefactor",
            "precompression",
            "radius",
            "law",
            "damping",
            "damping_si",
            "restitution",
            "impact_speed",
            "impact_speed_si",
        ],
    )?;
    let units_t = table(
        ctx,
        root,
        "units",
        &[
            "system",
            "time_scale",
            "radius",
            "young",
            "poisson",
            "density",
            "m0",
            "n0",
            "mu",
            "wall_young",
            "wall_poisson",
        ],
    )?;
    let initial_t = table(
        ctx,
        root,
        "initial",
        &[
            "velocity",
            "displacement",
            "striker",
            "striker_right",
            "pulse",
            "velocity_si",
            "striker_si",
            "striker_right_si",
        ],
    )?;
    let run_t = table(
        ctx,
        root,
        "run",
        &[
            "until", "every", "until_si", "every_si", "rtol", "atol", "method", "engine",
        ],
    )?;
    let field_t = table(
        ctx,
        root,
        "field",
        &["force", "gravity", "force_si", "gravity_si"],
    )?;
    let walls_t = table(ctx, root, "walls", &["left", "right"])?;

    let physical = match opt_str(ctx, units_t, "units", "system")? {
        None | Some("dimensionless") => false,
        Some("physical") => true,
        Some(s) => {
            return Err(ctx.err(
                "[units].system",
                format!("expected \"dimensionless\" or \"physical\", got \"{s}\""),
            ))
        }
    };
    if physical {
        let why = "not allowed in a physical scene (masses and prefactors come from [units] radius, young, poisson, density)";
        forbid(ctx, chain_t, "chain", &["mass", "prefactor", "radius"], why)?;
    } else {
        let why = "only allowed in a physical scene ([units] system = \"physical\")";
        forbid(
            ctx,
            units_t,
            "units",
            &[
                "time_scale",
                "radius",
                "young",
                "poisson",
                "density",
                "m0",
                "n0",
                "mu",
                "wall_young",
                "wall_poisson",
            ],
            why,
        )?;
        forbid(
            ctx,
            initial_t,
            "initial",
            &["velocity_si", "striker_si", "striker_right_si"],
            why,
        )?;
        forbid(ctx, run_t, "run", &["until_si", "every_si"], why)?;
        forbid(ctx, field_t, "field", &["force_si", "gravity_si"], why)?;
    }

    // Parse every array spec (reads CSVs) before N is known.
    let mass_s = opt_spec(ctx, chain_t, "chain", "mass")?;
    let exp_s = opt_spec(ctx, chain_t, "chain", "exponent")?;
    let pref_s = opt_spec(ctx, chain_t, "chain", "prefactor")?;
    let pre_s = opt_spec(ctx, chain_t, "chain", "precompression")?;
    let rad_s = opt_spec(ctx, chain_t, "chain", "radius")?;
    let urad_s = opt_spec(ctx, units_t, "units", "radius")?;
    let young_s = opt_spec(ctx, units_t, "units", "young")?;
    let pois_s = opt_spec(ctx, units_t, "units", "poisson")?;
    let dens_s = opt_spec(ctx, units_t, "units", "density")?;
    exclusive(ctx, initial_t, "initial", "velocity", "velocity_si")?;
    exclusive(ctx, initial_t, "initial", "striker", "striker_si")?;
    exclusive(
        ctx,
        initial_t,
        "initial",
        "striker_right",
        "striker_right_si",
    )?;
    let vel_s = opt_spec(ctx, initial_t, "initial", "velocity")?;
    let vel_si_s = opt_spec(ctx, initial_t, "initial", "velocity_si")?;
    let disp_s = opt_spec(ctx, initial_t, "initial", "displacement")?;
    let force_s = opt_spec(ctx, field_t, "field", "force")?;
    let force_si_s = opt_spec(ctx, field_t, "field", "force_si")?;

    // Number of beads: [chain].beads, else the first explicit array.
    let n = match get(chain_t, "beads") {
        Some(v) => (index(ctx, "[chain].beads", v)?, "[chain].beads".to_string()),
        None => {
            let cands: [(&str, &Option<Spec>, usize); 12] = [
                ("[chain].mass", &mass_s, 0),
                ("[chain].radius", &rad_s, 0),
                ("[units].radius", &urad_s, 0),
                ("[units].density", &dens_s, 0),
                ("[chain].exponent", &exp_s, 1),
                ("[chain].prefactor", &pref_s, 1),
                ("[chain].precompression", &pre_s, 1),
                ("[initial].velocity", &vel_s, 0),
                ("[initial].velocity_si", &vel_si_s, 0),
                ("[initial].displacement", &disp_s, 0),
                ("[field].force", &force_s, 0),
                ("[field].force_si", &force_si_s, 0),
            ];
            cands
                .iter()
                .find_map(|(k, s, off)| {
                    s.as_ref()
                        .and_then(Spec::explicit_len)
                        .map(|l| (l + off, k.to_string()))
                })
                .ok_or_else(|| {
                    ctx.err(
                        "[chain].beads",
                        "missing (and no array or file gives the chain length)",
                    )
                })?
        }
    };
    let (nb, nkey) = n;
    if nb < 2 {
        return Err(ctx.err(&nkey, format!("a chain needs at least 2 beads, got {nb}")));
    }
    if nb > MAX_BEADS {
        return Err(ctx.err(
            &nkey,
            format!("{nb} beads is more than the limit of {MAX_BEADS}"),
        ));
    }
    let nc = nb - 1;
    let res =
        |s: &Option<Spec>, key: &str, per: Per, default: f64| -> Result<Vec<f64>, SceneError> {
            let len = if per == Per::Bead { nb } else { nc };
            match s {
                Some(s) => s.resolve(ctx, key, len, per, default),
                None => Ok(vec![default; len]),
            }
        };

    let exponent = res(&exp_s, "[chain].exponent", Per::Contact, DEFAULT_EXPONENT)?;
    let mut scales: Option<UnitScales> = None;
    let mut material: Option<Material> = None;
    let (mass, prefactor) = if physical {
        let need = |s: &Option<Spec>, k: &str| -> Result<(), SceneError> {
            if s.is_none() {
                return Err(ctx.err(&kp("units", k), "required in a physical scene"));
            }
            Ok(())
        };
        need(&urad_s, "radius")?;
        need(&young_s, "young")?;
        need(&pois_s, "poisson")?;
        need(&dens_s, "density")?;
        let radius = res(&urad_s, "[units].radius", Per::Bead, 0.0)?;
        let young = res(&young_s, "[units].young", Per::Bead, 0.0)?;
        let poisson = res(&pois_s, "[units].poisson", Per::Bead, 0.0)?;
        let density = res(&dens_s, "[units].density", Per::Bead, 0.0)?;
        positive(ctx, "[units].radius", Per::Bead, &radius)?;
        positive(ctx, "[units].young", Per::Bead, &young)?;
        positive(ctx, "[units].density", Per::Bead, &density)?;
        if let Some(i) = poisson.iter().position(|p| !(*p > -1.0 && *p <= 0.5)) {
            return Err(ctx.index_err(
                "[units].poisson",
                Per::Bead,
                i,
                format!("must be in (-1, 0.5], got {}", poisson[i]),
            ));
        }
        let mass_si: Vec<f64> = radius
            .iter()
            .zip(&density)
            .map(|(r, d)| units::sphere_mass(*r, *d))
            .collect();
        let pref_si: Vec<f64> = (0..nc)
            .map(|c| {
                let d = units::hertz_d(young[c], poisson[c], young[c + 1], poisson[c + 1]);
                units::hertz_prefactor(radius[c], radius[c + 1], d)
            })
            .collect();
        let sc = match opt_str(ctx, units_t, "units", "time_scale")? {
            None | Some("paper") => {
                let pos = |k: &str, x: Option<f64>| -> Result<Option<f64>, SceneError> {
                    match x {
                        Some(x) if x <= 0.0 => {
                            Err(ctx.err(&kp("units", k), format!("must be > 0, got {x}")))
                        }
                        _ => Ok(x),
                    }
                };
                let m0 = pos("m0", opt_num(ctx, units_t, "units", "m0")?)?.unwrap_or(mass_si[0]);
                let n0 =
                    pos("n0", opt_num(ctx, units_t, "units", "n0")?)?.unwrap_or(units::DEFAULT_N0);
                let mu = pos("mu", opt_num(ctx, units_t, "units", "mu")?)?
                    .unwrap_or_else(|| UnitScales::order_of_magnitude(pref_si[0]));
                if n0 <= 0.0 || n0.is_nan() {
                    return Err(ctx.err(
                        "[units].n0",
                        format!("typical exponent must be > 0, got {n0}"),
                    ));
                }
                UnitScales::paper(m0, mu, n0)
            }
            Some("si") => {
                forbid(
                    ctx,
                    units_t,
                    "units",
                    &["m0", "n0", "mu"],
                    "only used with time_scale = \"paper\"",
                )?;
                UnitScales::si()
            }
            Some(s) => {
                return Err(ctx.err(
                    "[units].time_scale",
                    format!("expected \"paper\" or \"si\", got \"{s}\""),
                ))
            }
        };
        scales = Some(sc);
        material = Some(Material {
            radius,
            young,
            poisson,
        });
        (
            mass_si.iter().map(|m| sc.mass(*m)).collect::<Vec<_>>(),
            pref_si.iter().map(|a| sc.prefactor(*a)).collect::<Vec<_>>(),
        )
    } else {
        let mut mass = res(&mass_s, "[chain].mass", Per::Bead, DEFAULT_MASS)?;
        let mut prefactor = res(
            &pref_s,
            "[chain].prefactor",
            Per::Contact,
            DEFAULT_PREFACTOR,
        )?;
        if rad_s.is_some() {
            let r = res(&rad_s, "[chain].radius", Per::Bead, 1.0)?;
            positive(ctx, "[chain].radius", Per::Bead, &r)?;
            for (m, ri) in mass.iter_mut().zip(&r) {
                *m *= ri.powi(3);
            }
            for (c, a) in prefactor.iter_mut().enumerate() {
                *a *= (2.0 * r[c] * r[c + 1] / (r[c] + r[c + 1])).sqrt();
            }
        }
        (mass, prefactor)
    };

    let precompression = match &pre_s {
        Some(s) => {
            let p = s.resolve(ctx, "[chain].precompression", nc, Per::Contact, 0.0)?;
            p.iter().any(|x| *x != 0.0).then_some(p)
        }
        None => None,
    };

    // Initial state.
    let u0 = res(&disp_s, "[initial].displacement", Per::Bead, 0.0)?;
    let mut v0 = match (&vel_s, &vel_si_s, scales) {
        (_, Some(s), Some(sc)) => s
            .resolve(ctx, "[initial].velocity_si", nb, Per::Bead, 0.0)?
            .into_iter()
            .map(|v| sc.velocity(v))
            .collect(),
        _ => res(&vel_s, "[initial].velocity", Per::Bead, 0.0)?,
    };
    if let Some(pv) = get(initial_t, "pulse") {
        let k = "[initial].pulse";
        let pt = pv.as_table().ok_or_else(|| {
            ctx.err(
                k,
                format!(
                    "expected a table {{ beads, velocity }}, got {}",
                    type_name(pv)
                ),
            )
        })?;
        let allowed: &[&str] = if physical {
            &["beads", "velocity", "velocity_si"]
        } else {
            &["beads", "velocity"]
        };
        check_keys(ctx, k, pt, allowed)?;
        let l = match pt.get("beads") {
            Some(b) => index(ctx, "[initial].pulse.beads", b)?,
            None => return Err(ctx.err("[initial].pulse.beads", "missing")),
        };
        if l == 0 || l > nb {
            return Err(ctx.err(
                "[initial].pulse.beads",
                format!("must be in 1..={nb}, got {l}"),
            ));
        }
        let v = match (pt.get("velocity"), pt.get("velocity_si"), scales) {
            (Some(_), Some(_), _) => {
                return Err(ctx.err(
                    "[initial].pulse.velocity_si",
                    "give either `velocity` or `velocity_si`, not both",
                ))
            }
            (Some(v), None, _) => number(ctx, "[initial].pulse.velocity", v)?,
            (None, Some(v), Some(sc)) => {
                sc.velocity(number(ctx, "[initial].pulse.velocity_si", v)?)
            }
            _ => return Err(ctx.err("[initial].pulse.velocity", "missing")),
        };
        v0[..l].fill(v);
    }
    let si_or = |plain: &str, si: &str| -> Result<Option<f64>, SceneError> {
        if let Some(x) = opt_num(ctx, initial_t, "initial", plain)? {
            return Ok(Some(x));
        }
        match (opt_num(ctx, initial_t, "initial", si)?, scales) {
            (Some(x), Some(sc)) => Ok(Some(sc.velocity(x))),
            _ => Ok(None),
        }
    };
    if let Some(v) = si_or("striker", "striker_si")? {
        v0[0] = v;
    }
    if let Some(v) = si_or("striker_right", "striker_right_si")? {
        v0[nb - 1] = -v;
    }

    // Field: W_i, positive = towards increasing u; gravity g pulls towards decreasing u.
    exclusive(ctx, field_t, "field", "force", "force_si")?;
    exclusive(ctx, field_t, "field", "gravity", "gravity_si")?;
    let mut w = vec![0.0; nb];
    if force_s.is_some() {
        w = res(&force_s, "[field].force", Per::Bead, 0.0)?;
    } else if let (Some(s), Some(sc)) = (&force_si_s, scales) {
        w = s
            .resolve(ctx, "[field].force_si", nb, Per::Bead, 0.0)?
            .into_iter()
            .map(|f| sc.force(f))
            .collect();
    }
    let g = match (
        opt_num(ctx, field_t, "field", "gravity")?,
        opt_num(ctx, field_t, "field", "gravity_si")?,
        scales,
    ) {
        (Some(g), _, _) => g,
        (None, Some(g), Some(sc)) => sc.acceleration(g),
        _ => 0.0,
    };
    if g != 0.0 {
        for (wi, m) in w.iter_mut().zip(&mass) {
            *wi -= m * g;
        }
    }
    let field = w.iter().any(|x| *x != 0.0).then_some(w);

    // Walls.
    let mut walls = [None, None];
    for (side, slot) in ["left", "right"].iter().zip(walls.iter_mut()) {
        let Some(v) = get(walls_t, side) else {
            continue;
        };
        let k = kp("walls", side);
        let wt = v.as_table().ok_or_else(|| {
            ctx.err(
                &k,
                format!(
                    "expected a table {{ exponent, prefactor, precompression }}, got {}",
                    type_name(v)
                ),
            )
        })?;
        let allowed: &[&str] = if physical {
            &[
                "exponent",
                "prefactor",
                "prefactor_si",
                "precompression",
                "hard",
                "restitution",
                "damping",
                "damping_si",
            ]
        } else {
            &[
                "exponent",
                "prefactor",
                "precompression",
                "hard",
                "restitution",
                "damping",
            ]
        };
        check_keys(ctx, &k, wt, allowed)?;
        let (bead, contact) = if *side == "left" {
            (0, 0)
        } else {
            (nb - 1, nc - 1)
        };
        let num = |key: &str| {
            wt.get(key)
                .map(|x| number(ctx, &format!("{k}.{key}"), x))
                .transpose()
        };
        let exponent_w = num("exponent")?.unwrap_or(exponent[contact]);
        if wt.contains_key("prefactor") && wt.contains_key("prefactor_si") {
            return Err(ctx.err(
                &format!("{k}.prefactor_si"),
                "give either `prefactor` or `prefactor_si`, not both",
            ));
        }
        let prefactor_w = match (num("prefactor")?, num("prefactor_si")?, scales, &material) {
            (Some(a), _, _, _) => a,
            (None, Some(a), Some(sc), _) => sc.prefactor(a),
            (None, None, Some(sc), Some(mat)) => {
                let yw = opt_num(ctx, units_t, "units", "wall_young")?.unwrap_or(mat.young[bead]);
                let sw =
                    opt_num(ctx, units_t, "units", "wall_poisson")?.unwrap_or(mat.poisson[bead]);
                let d = units::hertz_d(mat.young[bead], mat.poisson[bead], yw, sw);
                sc.prefactor(units::hertz_wall_prefactor(mat.radius[bead], d))
            }
            _ => prefactor[contact],
        };
        let precompression_w = num("precompression")?.unwrap_or(0.0);
        let restitution_w = super::hard::wall_restitution(ctx, &k, wt)?;
        *slot = Some(Wall {
            exponent: exponent_w,
            prefactor: prefactor_w,
            precompression: precompression_w,
            restitution: restitution_w,
        });
    }
    let damping = super::damping::parse(
        ctx,
        chain_t,
        walls_t,
        &walls,
        super::damping::ChainArrays {
            mass: &mass,
            exponent: &exponent,
            prefactor: &prefactor,
        },
        scales,
    )?;
    let [left_wall, right_wall] = walls;

    // Run settings.
    exclusive(ctx, run_t, "run", "until", "until_si")?;
    exclusive(ctx, run_t, "run", "every", "every_si")?;
    let time = |plain: &str, si: &str| -> Result<Option<f64>, SceneError> {
        match (
            opt_num(ctx, run_t, "run", plain)?,
            opt_num(ctx, run_t, "run", si)?,
            scales,
        ) {
            (Some(t), _, _) => Ok(Some(t)),
            (None, Some(t), Some(sc)) => Ok(Some(sc.time(t))),
            _ => Ok(None),
        }
    };
    let until = time("until", "until_si")?
        .ok_or_else(|| ctx.err("[run].until", "missing (end time of the run)"))?;
    let every = time("every", "every_si")?;
    let method = match opt_str(ctx, run_t, "run", "method")? {
        None => None,
        Some("radau5") => Some(Method::Radau5),
        Some("dop853") => Some(Method::Dop853),
        Some("verlet") => Some(Method::Verlet),
        Some("auto") => Some(Method::Auto),
        Some(s) => {
            return Err(ctx.err(
                "[run].method",
                format!("expected \"auto\", \"radau5\", \"dop853\" or \"verlet\", got \"{s}\""),
            ))
        }
    };
    let engine = match opt_str(ctx, run_t, "run", "engine")? {
        None => None,
        Some("dense") => Some(Engine::Dense),
        Some("hybrid") => Some(Engine::Hybrid),
        Some(s) => {
            return Err(ctx.err(
                "[run].engine",
                format!("expected \"dense\" or \"hybrid\", got \"{s}\""),
            ))
        }
    };
    let hard = super::hard::parse_hard(ctx, root, nc)?;
    let run = RunSettings {
        until,
        every,
        rtol: opt_num(ctx, run_t, "run", "rtol")?,
        atol: opt_num(ctx, run_t, "run", "atol")?,
        method,
        engine,
        output: super::output::parse_output(ctx, root, nb)?,
    };

    let stem = Path::new(origin)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| origin.to_string());
    let name = opt_str(ctx, scene_t, "scene", "name")?.map_or(stem, str::to_string);
    let mut description = opt_str(ctx, scene_t, "scene", "description")?
        .unwrap_or("")
        .to_string();
    if let Some(sc) = scales {
        if !description.is_empty() {
            description.push(' ');
        }
        description.push_str(&format!(
            "[physical units: time unit {:.6e} s, mass unit {:.6e} kg, mu {:e}, n0 {}; lengths in m]",
            sc.time, sc.mass, sc.mu, sc.n0
        ));
    }
    let mut scene = Scene {
        name,
        description,
        chain: Chain {
            mass,
            exponent,
            prefactor,
            precompression,
            field,
            left_wall,
            right_wall,
            hard,
            damping,
        },
        u0,
        v0,
        run,
        seed,
    };
    super::hard::default_collapse_interval(&mut scene);
    Ok(scene)
}
