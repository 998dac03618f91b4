//! The per-bead and per-contact array keys of a scene (every value form of [`super::values`],
//! CSV files included), read before the chain length is known, and the chain length itself:
//! `[chain].beads`, else the length of the first explicit array (a per-contact array of length
//! `L` gives `L + 1` beads).

use super::error::SceneError;
use super::keys::{exclusive, opt_spec};
use super::tables::Tables;
use super::values::{index, Ctx, Per, Spec};

/// Largest chain a scene may declare (guards against absurd allocations from typos).
pub const MAX_BEADS: usize = 10_000_000;

/// Default contact exponent (Hertz spheres).
pub const DEFAULT_EXPONENT: f64 = 2.5;

/// The array specs of a scene, unresolved (`None`: key absent).
pub(super) struct Specs {
    pub mass: Option<Spec>,
    pub exponent: Option<Spec>,
    pub prefactor: Option<Spec>,
    pub precompression: Option<Spec>,
    pub radius: Option<Spec>,
    pub units_radius: Option<Spec>,
    pub young: Option<Spec>,
    pub poisson: Option<Spec>,
    pub density: Option<Spec>,
    pub viscosity_shear: Option<Spec>,
    pub viscosity_bulk: Option<Spec>,
    pub velocity: Option<Spec>,
    pub velocity_si: Option<Spec>,
    pub displacement: Option<Spec>,
    pub force: Option<Spec>,
    pub force_si: Option<Spec>,
}

/// Parses every array spec (reads CSVs) before N is known; also refuses `[initial]` keys given
/// both plainly and with `_si`.
pub(super) fn read_specs(ctx: &Ctx, t: &Tables) -> Result<Specs, SceneError> {
    let (c, u, i, f) = (&t.chain, &t.units, &t.initial, &t.field);
    let mass = opt_spec(ctx, "[chain].mass", &c.mass)?;
    let exponent = opt_spec(ctx, "[chain].exponent", &c.exponent)?;
    let prefactor = opt_spec(ctx, "[chain].prefactor", &c.prefactor)?;
    let precompression = opt_spec(ctx, "[chain].precompression", &c.precompression)?;
    let radius = opt_spec(ctx, "[chain].radius", &c.radius)?;
    let units_radius = opt_spec(ctx, "[units].radius", &u.radius)?;
    let young = opt_spec(ctx, "[units].young", &u.young)?;
    let poisson = opt_spec(ctx, "[units].poisson", &u.poisson)?;
    let density = opt_spec(ctx, "[units].density", &u.density)?;
    let plain_si = [
        (("velocity", &i.velocity), ("velocity_si", &i.velocity_si)),
        (("striker", &i.striker), ("striker_si", &i.striker_si)),
        (
            ("striker_right", &i.striker_right),
            ("striker_right_si", &i.striker_right_si),
        ),
    ];
    for (plain, si) in plain_si {
        exclusive(ctx, "initial", plain, si)?;
    }
    Ok(Specs {
        mass,
        exponent,
        prefactor,
        precompression,
        radius,
        units_radius,
        young,
        poisson,
        density,
        viscosity_shear: opt_spec(ctx, "[units].viscosity_shear", &u.viscosity_shear)?,
        viscosity_bulk: opt_spec(ctx, "[units].viscosity_bulk", &u.viscosity_bulk)?,
        velocity: opt_spec(ctx, "[initial].velocity", &i.velocity)?,
        velocity_si: opt_spec(ctx, "[initial].velocity_si", &i.velocity_si)?,
        displacement: opt_spec(ctx, "[initial].displacement", &i.displacement)?,
        force: opt_spec(ctx, "[field].force", &f.force)?,
        force_si: opt_spec(ctx, "[field].force_si", &f.force_si)?,
    })
}

/// Number of beads `nb` and contacts `nc = nb − 1` of the chain.
#[derive(Clone, Copy)]
pub(super) struct Len {
    pub nb: usize,
    pub nc: usize,
}

impl Len {
    /// Resolves an optional spec to `len` values (`default` everywhere when absent), `len` being
    /// the bead or contact count.
    pub(super) fn resolve(
        self,
        ctx: &Ctx,
        s: &Option<Spec>,
        key: &str,
        per: Per,
        default: f64,
    ) -> Result<Vec<f64>, SceneError> {
        let len = if per == Per::Bead { self.nb } else { self.nc };
        match s {
            Some(s) => s.resolve(ctx, key, len, per, default),
            None => Ok(vec![default; len]),
        }
    }
}

/// The chain length a per-contact `[chain] damping` (`damping_si`) array or file gives, the
/// last candidate of [`chain_length`] (read here only when no other key gives it).
fn damping_length(ctx: &Ctx, t: &Tables) -> Result<Option<(usize, String)>, SceneError> {
    for (k, v) in [
        ("[chain].damping", &t.chain.damping),
        ("[chain].damping_si", &t.chain.damping_si),
    ] {
        if let Some(l) = opt_spec(ctx, k, v)?.as_ref().and_then(Spec::explicit_len) {
            return Ok(Some((l + 1, k.to_string())));
        }
    }
    Ok(None)
}

/// Number of beads: `[chain].beads`, else the first explicit array; at least 2, at most
/// [`MAX_BEADS`].
pub(super) fn chain_length(ctx: &Ctx, t: &Tables, s: &Specs) -> Result<Len, SceneError> {
    let (nb, nkey) = match &t.chain.beads {
        Some(v) => (index(ctx, "[chain].beads", v)?, "[chain].beads".to_string()),
        None => {
            let cands: [(&str, &Option<Spec>, usize); 16] = [
                ("[chain].mass", &s.mass, 0),
                ("[chain].radius", &s.radius, 0),
                ("[units].radius", &s.units_radius, 0),
                ("[units].density", &s.density, 0),
                ("[units].young", &s.young, 0),
                ("[units].poisson", &s.poisson, 0),
                ("[units].viscosity_shear", &s.viscosity_shear, 0),
                ("[units].viscosity_bulk", &s.viscosity_bulk, 0),
                ("[chain].exponent", &s.exponent, 1),
                ("[chain].prefactor", &s.prefactor, 1),
                ("[chain].precompression", &s.precompression, 1),
                ("[initial].velocity", &s.velocity, 0),
                ("[initial].velocity_si", &s.velocity_si, 0),
                ("[initial].displacement", &s.displacement, 0),
                ("[field].force", &s.force, 0),
                ("[field].force_si", &s.force_si, 0),
            ];
            cands
                .iter()
                .find_map(|(k, s, off)| {
                    s.as_ref()
                        .and_then(Spec::explicit_len)
                        .map(|l| (l + off, k.to_string()))
                })
                .map_or_else(|| damping_length(ctx, t), |found| Ok(Some(found)))?
                .ok_or_else(|| {
                    ctx.err(
                        "[chain].beads",
                        "missing (and no array or file gives the chain length)",
                    )
                })?
        }
    };
    if nb < 2 {
        return Err(ctx.err(&nkey, format!("a chain needs at least 2 beads, got {nb}")));
    }
    if nb > MAX_BEADS {
        return Err(ctx.err(
            &nkey,
            format!("{nb} beads is more than the limit of {MAX_BEADS}"),
        ));
    }
    Ok(Len { nb, nc: nb - 1 })
}
