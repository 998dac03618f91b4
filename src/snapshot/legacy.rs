//! Headers of format versions 1 and 2, frozen: the `Chain` they stored had no `damping` field
//! (added in version 3). [`decode_header`] reads a HEADER payload of any supported version into
//! today's [`Header`] (a version-1/2 chain is conservative: `damping = None`).

use super::{decode_exact, Header};
use crate::integrate::Method;
use crate::model::{Chain, HardContacts, Wall};
use crate::scene::{Engine, RunSettings, Scene};
use serde::Deserialize;

/// `Chain` as versions 1 and 2 stored it.
#[derive(Deserialize)]
struct ChainV2 {
    mass: Vec<f64>,
    exponent: Vec<f64>,
    prefactor: Vec<f64>,
    precompression: Option<Vec<f64>>,
    field: Option<Vec<f64>>,
    left_wall: Option<Wall>,
    right_wall: Option<Wall>,
    hard: Option<HardContacts>,
}

/// `Scene` as versions 1 and 2 stored it.
#[derive(Deserialize)]
struct SceneV2 {
    name: String,
    description: String,
    chain: ChainV2,
    u0: Vec<f64>,
    v0: Vec<f64>,
    run: RunSettings,
    seed: u64,
}

/// `Header` as versions 1 and 2 stored it.
#[derive(Deserialize)]
struct HeaderV2 {
    format_version: u32,
    crate_version: String,
    scene: SceneV2,
    engine: Engine,
    method: Method,
    rtol: f64,
    atol: f64,
    seed: u64,
    n_beads: u64,
    created_by: String,
}

/// Decodes the HEADER payload of a file of format `version`.
pub(crate) fn decode_header(version: u32, payload: &[u8]) -> Result<Header, String> {
    if version >= 3 {
        return decode_exact(payload);
    }
    let h: HeaderV2 = decode_exact(payload)?;
    let c = h.scene.chain;
    Ok(Header {
        format_version: h.format_version,
        crate_version: h.crate_version,
        scene: Scene {
            name: h.scene.name,
            description: h.scene.description,
            chain: Chain {
                mass: c.mass,
                exponent: c.exponent,
                prefactor: c.prefactor,
                precompression: c.precompression,
                field: c.field,
                left_wall: c.left_wall,
                right_wall: c.right_wall,
                hard: c.hard,
                damping: None,
            },
            u0: h.scene.u0,
            v0: h.scene.v0,
            run: h.scene.run,
            seed: h.scene.seed,
        },
        engine: h.engine,
        method: h.method,
        rtol: h.rtol,
        atol: h.atol,
        seed: h.seed,
        n_beads: h.n_beads,
        created_by: h.created_by,
    })
}
